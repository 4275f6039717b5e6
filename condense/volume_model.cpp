#include "condense/volume_model.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "common/error.hpp"
#include "condense/abaqus_mesh.hpp"
#include "condense/block_assembly.hpp"
#include "condense/gmsh_mesh.hpp"
#include "condense/node_selector.hpp"
#include "condense/solid_element.hpp"

namespace nvh::condense {

namespace {

/// A connection point far from its surface is almost always a typing or unit error (mm for m, a wrong
/// sign): the point must lie within the surface's size - the diagonal of its nodes' bounding box, or
/// interface.max_distance if given - of the nearest node of its surface. A bore's centre lies one radius
/// from its surface, well within its diameter.
void check_reach(const FeModel& model, const NamedPoint& p, const std::vector<int>& surface,
                 const std::string& key) {
  const Eigen::Vector3d at(p.at[0], p.at[1], p.at[2]);
  Eigen::Vector3d lo = model.nodes[surface[0]], hi = lo;
  double nearest = std::numeric_limits<double>::infinity();
  for (int n : surface) {
    lo = lo.cwiseMin(model.nodes[n]);
    hi = hi.cwiseMax(model.nodes[n]);
    nearest = std::min(nearest, (model.nodes[n] - at).norm());
  }
  const double limit = p.max_distance > 0.0 ? p.max_distance : (hi - lo).norm();
  if (nearest > limit) {
    std::ostringstream m;
    m.precision(6);
    m << "the connection point of interface \"" << p.name << "\" at [" << at.transpose() << "] lies "
      << nearest << " m from the nearest node of its " << key << ", farther than "
      << (p.max_distance > 0.0 ? "max_distance (" : "the size of the surface (") << limit
      << " m); check the point's coordinates and units (m), or set max_distance if the lever is intended";
    throw Error(m.str(), p.where, p.path + ".at");
  }
}

/// Rigid couplings (RBE2): the coupling node of interface i (node first_coupling + i, all 6 DOF
/// active) becomes the master of the mesh nodes of its surface, u_s = u_m + theta_m x r. The coupling
/// adds no mass of its own; its rotations get inertia through the slaves, so a surface needs at least
/// three nodes that are not on one line.
std::vector<std::vector<int>> add_couplings(FeModel& model, const Mesh& mesh, const std::vector<bool>& used,
                                            const std::vector<bool>& on_surface,
                                            const std::vector<NamedPoint>& interfaces, int first_coupling) {
  std::vector<std::vector<int>> surfaces;
  std::vector<int> coupled_by(model.nodes.size(), -1);
  for (std::size_t i = 0; i < interfaces.size(); ++i) {
    const NamedPoint& p = interfaces[i];
    const int master = first_coupling + static_cast<int>(i);
    NodeSelector selector{p.surface, p.box,  p.cylinder,
                          p.where,   p.path, "the coupling of interface \"" + p.name + "\""};
    const std::vector<int> surface = select_nodes(mesh, p.cylinder ? on_surface : used, selector);
    check_reach(model, p, surface, selector.key());
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
                  p.where, p.path + "." + selector.key());
    }
    surfaces.push_back(surface);
    for (int n : surface) {
      if (coupled_by[n] >= 0) {
        throw Error("mesh node " + std::to_string(mesh.node_ids[n]) + " is coupled to two interfaces (\"" +
                        interfaces[coupled_by[n]].name + "\" and \"" + p.name + "\")",
                    p.where, p.path);
      }
      coupled_by[n] = static_cast<int>(i);
      if (!p.distributing) model.master_of[n] = master;  // RBE2: the surface follows the point rigidly
    }
    for (int d = 0; d < 6; ++d) model.inactive_dof[6 * master + d] = false;
    model.coupling_nodes.push_back(master);
  }
  return surfaces;
}

/// Distributing couplings (RBE3): the point moves as the least-squares rigid fit of its surface,
///   [u_p; theta_p] = A u_s,  A = (G^T G)^-1 G^T,  G_i = [I, -[r_i]x],  r_i = x_i - x_p
/// (equal weights), and adds no stiffness. The point's DOF stay independent coordinates (the interface
/// DOF of Craig-Bampton). Elimination form: six surface DOF u_d, chosen by column-pivoted QR of A among
/// the unsupported ones, become dependent: u_d = A_d^-1 (u_p - A_o u_o); T^T K T then couples every
/// node of the surface with every other. Multiplier form: all DOF stay free and the six rows
/// [u_p; theta_p] - A u_s = 0 are kept as constraints (model.constraint_rows), K stays sparse.
void add_distributing_constraints(FeModel& model, const std::vector<NamedPoint>& interfaces,
                                  const std::vector<std::vector<int>>& surfaces, bool multiplier) {
  for (std::size_t i = 0; i < interfaces.size(); ++i) {
    if (!interfaces[i].distributing) continue;
    const int point = model.coupling_nodes[i];
    const std::vector<int>& surface = surfaces[i];
    const int m = static_cast<int>(surface.size());
    Eigen::MatrixXd G(3 * m, 6);
    std::vector<int> dofs(3 * m);
    for (int j = 0; j < m; ++j) {
      const Eigen::Vector3d r = model.nodes[surface[j]] - model.nodes[point];
      Eigen::Matrix3d rx;
      rx << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
      G.block<3, 3>(3 * j, 0).setIdentity();
      G.block<3, 3>(3 * j, 3) = -rx;
      for (int a = 0; a < 3; ++a) dofs[3 * j + a] = 6 * surface[j] + a;
    }
    const Eigen::MatrixXd A = (G.transpose() * G).ldlt().solve(G.transpose());  // 6 x 3m
    // Candidates for the dependent DOF: the unsupported ones.
    std::vector<int> candidates;
    for (int k = 0; k < 3 * m; ++k)
      if (!model.supported_dof[dofs[k]]) candidates.push_back(k);
    const auto held = [&] {
      return Error("the distributing coupling of interface \"" + interfaces[i].name +
                       "\" cannot carry all six DOF: its surface is held by supports",
                   interfaces[i].where, interfaces[i].path);
    };
    if (candidates.size() < 6) throw held();
    Eigen::MatrixXd Ac(6, candidates.size());
    for (std::size_t k = 0; k < candidates.size(); ++k) Ac.col(k) = A.col(candidates[k]);
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Ac);
    if (qr.rank() < 6) throw held();
    if (multiplier) {
      for (int k = 0; k < 6; ++k) {
        ConstraintRow row;
        row.terms.emplace_back(6 * point + k, 1.0);
        for (int o = 0; o < 3 * m; ++o) row.terms.emplace_back(dofs[o], -A(k, o));
        model.constraint_rows.push_back(std::move(row));
      }
      continue;
    }
    std::vector<int> dependent;
    for (int k = 0; k < 6; ++k) dependent.push_back(candidates[qr.colsPermutation().indices()(k)]);
    Eigen::Matrix<double, 6, 6> Ad;
    for (int k = 0; k < 6; ++k) Ad.col(k) = A.col(dependent[k]);
    const Eigen::Matrix<double, 6, 6> Ad_inv = Ad.inverse();
    std::vector<bool> is_dependent(3 * m, false);
    for (int k : dependent) is_dependent[k] = true;
    for (int k = 0; k < 6; ++k) {
      LinearConstraint c;
      c.dof = dofs[dependent[k]];
      for (int j = 0; j < 6; ++j) c.terms.emplace_back(6 * point + j, Ad_inv(k, j));
      const Eigen::RowVectorXd minus = -Ad_inv.row(k) * A;
      for (int o = 0; o < 3 * m; ++o)
        if (!is_dependent[o]) c.terms.emplace_back(dofs[o], minus(o));
      model.constraints.push_back(std::move(c));
    }
  }
}

/// The form of the distributing couplings (see DistributingForm): kAuto resolved to the multiplier form
/// where it applies - a Craig-Bampton or Guyan reduction without band, preload or geometric stiffening,
/// whose interior the supports and the rigid couplings' points (boundary DOF) restrain, so that K_ii is
/// positive definite without the constraints (the range-space solves of constrained_factor.hpp need it).
/// nvh::Error at volume.rbe3_form if "multiplier" is asked for where it does not apply.
bool multiplier_form(const Component& c, const FeModel& model, DistributingForm form) {
  bool any = false;
  for (const NamedPoint& p : c.interfaces) any = any || p.distributing;
  if (!any || form == DistributingForm::kElimination) return false;
  const ReductionSettings& r = c.reduction;
  std::string why;
  if (r.method == ReductionMethod::kModal)
    why = "the modal reduction";
  else if (r.band_hz > 0.0)
    why = "the error estimate (reduction.band)";
  else if (r.geometric_stiffening)
    why = "geometric stiffening";
  else if (!c.preloads.empty())
    why = "preloads";
  if (why.empty()) {
    // Rigid-body motions that no support and no rigid coupling's point holds leave K_ii singular.
    std::vector<int> held;
    for (int d = 0; d < model.all_dofs(); ++d)
      if (model.supported_dof[d]) held.push_back(d);
    for (std::size_t i = 0; i < c.interfaces.size(); ++i)
      if (!c.interfaces[i].distributing)
        for (int d = 0; d < 6; ++d) held.push_back(6 * model.coupling_nodes[i] + d);
    Eigen::Index rank = 0;
    if (!held.empty()) {
      const Eigen::MatrixXd field = model.rigid_body_field();
      Eigen::MatrixXd rows(static_cast<Eigen::Index>(held.size()), 6);
      for (std::size_t k = 0; k < held.size(); ++k)
        rows.row(static_cast<Eigen::Index>(k)) = field.row(held[k]);
      Eigen::JacobiSVD<Eigen::MatrixXd> svd(rows);
      svd.setThreshold(1e-9);
      rank = svd.rank();
    }
    if (rank < 6)
      why =
          "a component whose interior only the distributing couplings restrain (no support or rigid coupling "
          "holds all its rigid-body motion)";
  }
  if (why.empty()) return true;
  if (form == DistributingForm::kMultiplier)
    throw Error("rbe3_form = \"multiplier\" does not work with " + why + "; use \"elimination\" or \"auto\"",
                c.volume.where, "volume.rbe3_form");
  return false;
}

/// Supports: a box takes every node inside (mesh nodes and interface points, see apply_supports); a node
/// set takes mesh nodes, a cylinder nodes of the outer surface. Nodes that follow a rigid coupling are
/// held through its point.
void apply_volume_supports(FeModel& model, const Mesh& mesh, const std::vector<bool>& used,
                           const std::vector<bool>& on_surface, const Component& c) {
  std::vector<Support> boxes;
  for (const Support& s : c.supports)
    if (s.box) boxes.push_back(s);
  apply_supports(model, boxes, c.point_tolerance);
  for (const Support& s : c.supports) {
    if (s.box) continue;
    const NodeSelector selector{s.surface, std::nullopt, s.cylinder,
                                s.where,   s.path,       "the support " + s.path};
    int held = 0;
    for (int n : select_nodes(mesh, s.cylinder ? on_surface : used, selector)) {
      if (model.master_of[n] != n) continue;
      ++held;
      for (int d = 0; d < 6; ++d)
        if (s.dofs[d]) model.supported_dof[6 * n + d] = true;
    }
    if (held == 0) {
      throw Error("every node the support takes follows a rigid coupling; hold the interface's point instead",
                  s.where, s.path + "." + selector.key());
    }
  }
}

/// The material of each element (indices into mesh.elements): its region's ([[volume.region]]), or the
/// component's default. nvh::Error at the region's group key for a group the mesh does not hold (the
/// message lists its element sets) and for an element that is in two regions.
std::vector<const Material*> element_materials(const Component& c, const Mesh& mesh) {
  std::vector<const Material*> materials(mesh.elements.size(), &c.materials.at(c.volume.material));
  std::vector<int> region_of(mesh.elements.size(), -1);
  for (std::size_t r = 0; r < c.volume.regions.size(); ++r) {
    const MaterialRegion& region = c.volume.regions[r];
    const auto set = mesh.element_sets.find(region.group);
    if (set == mesh.element_sets.end()) {
      std::string sets;
      for (const auto& [name, members] : mesh.element_sets) sets += (sets.empty() ? "" : ", ") + name;
      throw Error("the element set \"" + region.group + "\" is not in the mesh " + mesh.file +
                      (sets.empty() ? " (it has no *ELSET or 3D physical group)"
                                    : " (its element sets: " + sets + ")"),
                  region.where, region.path + ".group");
    }
    for (int e : set->second) {
      if (region_of[e] >= 0) {
        throw Error("element " + std::to_string(mesh.elements[e].id) + " is in two regions: \"" +
                        c.volume.regions[region_of[e]].group + "\" (" + c.volume.regions[region_of[e]].path +
                        ") and \"" + region.group + "\"; an element takes one material",
                    region.where, region.path + ".group");
      }
      region_of[e] = static_cast<int>(r);
      materials[e] = &c.materials.at(region.material);
    }
  }
  return materials;
}

double shear_wave_speed(const Material& m) {
  return std::sqrt(m.shear_modulus() / m.rho);
}

double mesh_size(const Component& c) {
  const VolumeGeometry& v = c.volume;
  if (v.elements_per_wavelength <= 0.0) return v.size;
  // The shortest wavelength of interest is the shear wavelength c_s / fmax, c_s = sqrt(G / rho). With a
  // band and no fmax, fmax is taken as 3 x band, the middle of the usual Craig-Bampton cut-offs.
  const double fmax = c.reduction.fmax_hz > 0.0 ? c.reduction.fmax_hz : 3.0 * c.reduction.band_hz;
  if (fmax <= 0.0) {
    throw Error("elements_per_wavelength needs reduction.fmax or reduction.band (the size follows the "
                "frequency range)",
                v.where, "volume.elements_per_wavelength");
  }
  // With regions, the slowest of the materials sets the size (the mesh is not known yet).
  double c_s = shear_wave_speed(c.materials.at(v.material));
  for (const MaterialRegion& r : v.regions) c_s = std::min(c_s, shear_wave_speed(c.materials.at(r.material)));
  return c_s / fmax / v.elements_per_wavelength;
}

}  // namespace

Mesh load_volume_mesh(const Component& c) {
  // An Abaqus/CalculiX mesh is read as it is; anything else goes through gmsh (a .msh is read, a
  // geometry is meshed with second-order tetrahedra by default).
  std::vector<std::string> skipped;
  const bool inp = c.volume.mesh.extension() == ".inp" || c.volume.mesh.extension() == ".INP";
  // The size first, on its own: when mesh_size threw inside the braced request (after its path member was
  // built), ASan reported a stack-use-after-scope in the unwinding of the half-built temporary.
  Mesh mesh;
  if (inp) {
    mesh = read_abaqus_mesh(c.volume.mesh, &skipped);
  } else {
    GmshRequest request;
    request.geometry = c.volume.mesh;
    request.order = c.volume.order;
    request.size = mesh_size(c);
    request.threads = 1;
    mesh = mesh_with_gmsh(request);
  }
  if (mesh.elements.empty()) {
    throw Error(
        "the mesh " + c.volume.mesh.string() + " holds no solid elements (C3D4, C3D10, C3D8 or C3D20)",
        c.volume.where, "volume.mesh");
  }
  return mesh;
}

FeModel build_volume_model(const Component& c, DistributingForm form) {
  return build_volume_model(c, load_volume_mesh(c), form);
}

FeModel build_volume_model(const Component& c, const Mesh& mesh, DistributingForm form) {
  // Each element's own material (its region's or the default): stiffness, mass and the position and
  // component masses all follow from it, element by element.
  const std::vector<const Material*> materials = element_materials(c, mesh);

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
  // Assembly in place (block_assembly.hpp): the stiffness couples all translation components; the mass
  // is the scalar m_ij = int rho N_i N_j dV alone (the nodal mass is m (x) I_3 on the translations, and
  // the mass invariants follow from m and the nodal shapes: invariants.hpp).
  const NodeGraph graph = node_graph(mesh_nodes, mesh.elements);
  std::array<std::array<bool, 3>, 3> all{};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) all[a][b] = true;
  BlockAssembler kt(graph, n_nodes, all);
  NodeAssembler mt(graph, n_nodes);
  for (std::size_t k = 0; k < mesh.elements.size(); ++k) {
    const MeshElement& e = mesh.elements[k];
    const SolidType type = parse_solid_type(e.type);
    const IsotropicMaterial material{materials[k]->E, materials[k]->nu, materials[k]->rho};
    const int n = static_cast<int>(e.nodes.size());
    Eigen::Matrix<double, 3, Eigen::Dynamic> x(3, n);
    for (int i = 0; i < n; ++i) x.col(i) = model.nodes[e.nodes[i]];
    SolidElementMatrices m;
    try {
      m = solid_element(
          type, x, material,
          c.volume.mass_like_calculix ? MassQuadrature::kStiffnessRule : MassQuadrature::kExact);
    } catch (const Error& err) {
      throw Error("element " + std::to_string(e.id) + " (" + e.type + "): " + err.message(),
                  SourceLocation{mesh.file, e.line, 0}, "");
    }
    ++types[e.type];
    if (c.reduction.geometric_stiffening || !c.preloads.empty()) {
      model.solid_elements.push_back(e);
      model.solid_materials.push_back(material);
    }
    for (int i = 0; i < n; ++i) {
      const int ni = e.nodes[i];
      for (int a = 0; a < 3; ++a) model.inactive_dof[6 * ni + a] = false;
      for (int j = 0; j < n; ++j) {
        const int nj = e.nodes[j];
        const int p = graph.position(nj, ni);  // row node ni among column node nj's neighbours
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) kt.add(p, a, nj, b, m.stiffness(3 * i + a, 3 * j + b));
        mt.add(p, nj, m.scalar_mass(i, j));
      }
    }
    ++model.element_count;
  }
  std::string kinds;
  for (const auto& [name, count] : types) kinds += (kinds.empty() ? "" : " + ") + name;
  model.element_kind = kinds + " elements";
  kt.take(model.stiffness_all);
  mt.take(model.scalar_mass);

  model.surface = extract_surface(mesh);
  std::vector<bool> on_surface(mesh_nodes, false);
  for (int n : model.surface.nodes) on_surface[n] = true;
  const std::vector<std::vector<int>> surfaces =
      add_couplings(model, mesh, used, on_surface, c.interfaces, mesh_nodes);
  apply_volume_supports(model, mesh, used, on_surface, c);
  add_distributing_constraints(model, c.interfaces, surfaces, multiplier_form(c, model, form));
  model.labels = mesh.node_ids;
  build_transform(model);
  return model;
}

}  // namespace nvh::condense
