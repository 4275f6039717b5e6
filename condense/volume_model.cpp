#include "condense/volume_model.hpp"

#include <Eigen/SVD>
#include <map>

#include "common/error.hpp"
#include "condense/abaqus_mesh.hpp"
#include "condense/solid_element.hpp"

namespace nvh::condense {

namespace {

/// Rigid couplings (RBE2): the coupling node of interface i (node first_coupling + i, all 6 DOF
/// active) becomes the master of the mesh nodes of its surface, u_s = u_m + theta_m x r. The coupling
/// adds no mass of its own; its rotations get inertia through the slaves, so a surface needs at least
/// three nodes that are not on one line.
void add_couplings(FeModel& model, const Mesh& mesh, const std::vector<bool>& used,
                   const std::vector<NamedPoint>& interfaces, int first_coupling) {
  std::vector<int> coupled_by(model.nodes.size(), -1);
  for (std::size_t i = 0; i < interfaces.size(); ++i) {
    const NamedPoint& p = interfaces[i];
    const int master = first_coupling + static_cast<int>(i);
    std::vector<int> surface;
    if (!p.surface.empty()) {
      const auto it = mesh.node_sets.find(p.surface);
      if (it == mesh.node_sets.end()) {
        std::string sets;
        for (const auto& [name, nodes] : mesh.node_sets) sets += (sets.empty() ? "" : ", ") + name;
        throw Error("the node set \"" + p.surface + "\" is not in the mesh " + mesh.file +
                        (sets.empty() ? " (it has no *NSET)" : " (its node sets: " + sets + ")"),
                    p.where, p.path + ".surface");
      }
      for (int n : it->second)
        if (used[n]) surface.push_back(n);
    } else {
      const auto& b = *p.box;
      for (int n = 0; n < first_coupling; ++n) {
        const Eigen::Vector3d& x = model.nodes[n];
        bool inside = used[n];
        for (int k = 0; k < 3; ++k) inside = inside && x(k) >= b[k] - 1e-6 && x(k) <= b[3 + k] + 1e-6;
        if (inside) surface.push_back(n);
      }
    }
    // At least three nodes not on one line, or the coupling's rotations would have no stiffness.
    Eigen::MatrixXd centred(3, surface.size());
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int n : surface) mean += model.nodes[n] / static_cast<double>(surface.size());
    for (std::size_t j = 0; j < surface.size(); ++j) centred.col(j) = model.nodes[surface[j]] - mean;
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(centred);
    const double scale = surface.empty() ? 0.0 : svd.singularValues()(0);
    if (surface.size() < 3 || svd.singularValues().size() < 2 || svd.singularValues()(1) <= 1e-9 * scale) {
      throw Error("the coupling of interface \"" + p.name + "\" holds " + std::to_string(surface.size()) +
                      " mesh nodes; it needs at least three that are not on one line",
                  p.where, p.path + (p.surface.empty() ? ".box" : ".surface"));
    }
    for (int n : surface) {
      if (coupled_by[n] >= 0) {
        throw Error("mesh node " + std::to_string(mesh.node_ids[n]) + " is coupled to two interfaces (\"" +
                        interfaces[coupled_by[n]].name + "\" and \"" + p.name + "\")",
                    p.where, p.path);
      }
      coupled_by[n] = static_cast<int>(i);
      model.master_of[n] = master;
    }
    for (int d = 0; d < 6; ++d) model.inactive_dof[6 * master + d] = false;
    model.coupling_nodes.push_back(master);
  }
}

}  // namespace

FeModel build_volume_model(const Component& c) {
  std::vector<std::string> skipped;
  const Mesh mesh = read_abaqus_mesh(c.volume.mesh, &skipped);
  if (mesh.elements.empty()) {
    throw Error("the mesh " + c.volume.mesh.string() +
                    " holds no solid elements (C3D4, C3D10, C3D8 or C3D20)",
                c.volume.where, "volume.mesh");
  }
  const Material& mat = c.materials.at(c.volume.material);
  const IsotropicMaterial material{mat.E, mat.nu, mat.rho};

  FeModel model;
  model.nodes = mesh.nodes;
  const int mesh_nodes = static_cast<int>(model.nodes.size());
  std::vector<bool> used(mesh_nodes, false);
  for (const MeshElement& e : mesh.elements)
    for (int n : e.nodes) used[n] = true;
  // One coupling node per interface, after the mesh nodes (see add_couplings).
  for (const NamedPoint& p : c.interfaces) model.nodes.emplace_back(p.at[0], p.at[1], p.at[2]);
  const int n_nodes = static_cast<int>(model.nodes.size());
  const int n_all = model.all_dofs();
  model.master_of.resize(n_nodes);
  for (int n = 0; n < n_nodes; ++n) model.master_of[n] = n;

  // Solid nodes move by translations only; nodes no element uses are not part of the model at all.
  model.inactive_dof.assign(n_all, true);
  std::map<std::string, int> types;
  std::vector<Eigen::Triplet<double>> kt, mt;
  std::array<std::array<std::vector<Eigen::Triplet<double>>, 3>, 3> ct;
  model.position_moment_all = Eigen::MatrixXd::Zero(n_all, 9);
  for (const MeshElement& e : mesh.elements) {
    const SolidType type = parse_solid_type(e.type);
    const int n = static_cast<int>(e.nodes.size());
    Eigen::Matrix<double, 3, Eigen::Dynamic> x(3, n);
    for (int i = 0; i < n; ++i) x.col(i) = model.nodes[e.nodes[i]];
    SolidElementMatrices m;
    try {
      m = solid_element(type, x, material,
                        c.volume.mass_like_calculix ? MassQuadrature::kStiffnessRule : MassQuadrature::kExact);
    } catch (const Error& err) {
      throw Error("element " + std::to_string(e.id) + " (" + e.type + "): " + err.message(),
                  SourceLocation{mesh.file, e.line, 0}, "");
    }
    ++types[e.type];
    for (int i = 0; i < n; ++i) {
      const int ni = e.nodes[i];
      for (int a = 0; a < 3; ++a) model.inactive_dof[6 * ni + a] = false;
      for (int j = 0; j < n; ++j) {
        const int nj = e.nodes[j];
        const double mij = m.scalar_mass(i, j);
        for (int a = 0; a < 3; ++a) {
          for (int b = 0; b < 3; ++b) {
            const double kij = m.stiffness(3 * i + a, 3 * j + b);
            if (kij != 0.0) kt.emplace_back(6 * ni + a, 6 * nj + b, kij);
            // int rho N_a^T N_b dV: displacement component a at node i times component b at node j.
            if (mij != 0.0) ct[a][b].emplace_back(6 * ni + a, 6 * nj + b, mij);
          }
          if (mij != 0.0) mt.emplace_back(6 * ni + a, 6 * nj + a, mij);
        }
        // int rho x_k u_A dV = sum_j m_ij x_k(j) u_A(i): the position is interpolated like u.
        for (int k = 0; k < 3; ++k)
          for (int a = 0; a < 3; ++a) model.position_moment_all(6 * ni + a, 3 * k + a) += mij * model.nodes[nj](k);
      }
    }
    ++model.element_count;
  }
  std::string kinds;
  for (const auto& [name, count] : types) kinds += (kinds.empty() ? "" : " + ") + name;
  model.element_kind = kinds + " elements";

  auto assemble = [n_all](const std::vector<Eigen::Triplet<double>>& t) {
    SparseMatrix a(n_all, n_all);
    a.setFromTriplets(t.begin(), t.end());
    return a;
  };
  model.stiffness_all = assemble(kt);
  model.mass_all = assemble(mt);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) model.component_mass_all[a][b] = assemble(ct[a][b]);

  add_couplings(model, mesh, used, c.interfaces, mesh_nodes);
  apply_supports(model, c.supports, c.point_tolerance);
  build_transform(model);
  return model;
}

}  // namespace nvh::condense
