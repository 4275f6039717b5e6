#include "condense/volume_model.hpp"

#include <map>

#include "common/error.hpp"
#include "condense/abaqus_mesh.hpp"
#include "condense/solid_element.hpp"

namespace nvh::condense {

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

  apply_supports(model, c.supports, c.point_tolerance);
  build_transform(model);
  return model;
}

}  // namespace nvh::condense
