#include "condense/condense.hpp"

#include <algorithm>
#include <limits>
#include <memory>
#include <set>
#include <sstream>

#include "condense/abaqus_mesh.hpp"
#include "condense/beam_model.hpp"
#include "condense/geometric_stiffness.hpp"
#include "condense/p_multigrid.hpp"
#include "condense/reduction.hpp"
#include "condense/volume_model.hpp"

namespace nvh::condense {
namespace {

const char* kDofNames[6] = {"x", "y", "z", "rx", "ry", "rz"};
constexpr double kPi = 3.14159265358979323846;

/// Node index of each named point; error located at the point's entry if it is not on the model.
std::vector<int> locate(const FeModel& model, const std::vector<NamedPoint>& points, double tolerance,
                        const std::string& what) {
  std::vector<int> nodes;
  for (const NamedPoint& p : points) {
    const int n = model.find_node(p.at, tolerance);
    if (n < 0) {
      std::ostringstream at;
      at << "[" << p.at[0] << ", " << p.at[1] << ", " << p.at[2] << "]";
      std::ostringstream tol;
      tol << tolerance;
      throw Error("the " + what + " point \"" + p.name + "\" at " + at.str() +
                      " is not on the model: put it on a station or element node of the beam, or at the end "
                      "of a [[beam.rigid]] link (tolerance " +
                      tol.str() + " m)",
                  p.where, p.path + ".at");
    }
    nodes.push_back(n);
  }
  return nodes;
}

PointSet point_set(const FeModel& model, const std::vector<NamedPoint>& points, const std::vector<int>& nodes,
                   const Eigen::MatrixXd& shapes) {
  PointSet set;
  set.position.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) {
    set.names.push_back(points[i].name);
    set.position.row(i) = model.nodes[nodes[i]].transpose();
    set.shapes.push_back(shapes.middleRows(6 * nodes[i], 6));
  }
  return set;
}

/// Boundary DOF of Craig-Bampton and Guyan: the free DOF of each interface node (its master's for the
/// end of a rigid link), each once, in the order of the file; named "<interface>.<dof>".
void collect_boundary(const FeModel& model, const std::vector<NamedPoint>& interfaces,
                      const std::vector<int>& nodes, std::vector<int>& dofs,
                      std::vector<std::string>& names) {
  const std::vector<int> free_of_dof = model.free_index();
  std::set<int> taken;
  for (std::size_t i = 0; i < interfaces.size(); ++i) {
    const int master = model.master_of[nodes[i]];
    for (int d = 0; d < 6; ++d) {
      const int f = free_of_dof[6 * master + d];
      if (f < 0 || !taken.insert(f).second) continue;
      dofs.push_back(f);
      names.push_back(interfaces[i].name + "." + kDofNames[d]);
    }
  }
}

}  // namespace

void apply_options(Component& component, const CondenseOptions& options) {
  ReductionSettings& r = component.reduction;
  const SourceLocation command_line{"command line", 0, 0};
  if (options.fmax_hz) {
    r.fmax_hz = *options.fmax_hz;
    r.modes = 0;
    r.where = command_line;
    r.where_key = "--fmax";
  }
  if (options.modes) {
    r.modes = *options.modes;
    r.fmax_hz = 0.0;
    r.where = command_line;
    r.where_key = "--modes";
  }
  if (options.method) r.method = *options.method;
  if (options.band_hz) {
    r.band_hz = *options.band_hz;
    r.band_where = command_line;
  }
  default_residual_modes(r);
  check_reduction(component);
}

void check_reduction(const Component& component) {
  const ReductionSettings& r = component.reduction;
  if (r.method != ReductionMethod::kGuyan && r.fmax_hz <= 0.0 && r.modes <= 0 && r.band_hz <= 0.0) {
    throw Error("the " + to_string(r.method) +
                    " reduction needs band (Hz: the cut-off chosen to meet frf_tolerance), fmax (Hz) or "
                    "modes (a count) in [reduction], or --band / --fmax / --modes on the command line",
                r.where, "reduction");
  }
  if (r.residual_modes && r.method != ReductionMethod::kModal) {
    throw Error("residual_modes = true works with method = \"modal\" only (" + to_string(r.method) +
                    " keeps the interface DOF, whose constraint modes already carry static loads there)",
                r.where, "reduction.residual_modes");
  }
}

int count_rigid_body_modes(const FeModel& model) {
  return static_cast<int>(model.unsupported_rigid_motions().cols());
}

Superelement condense_component(const Component& c, EigenBackend backend, const Logger& log,
                                StageTimer* timer, const EigenProgress& progress) {
  CondenseRun run;
  run.timer = timer;
  run.progress = progress;
  return condense_component(c, backend, log, run);
}

std::vector<std::pair<std::string, double>> stage_report(const StageTimer& timer, const Superelement& se) {
  std::vector<std::pair<std::string, double>> stages;
  for (const StageTimer::Stage& stage : timer.stages()) {
    if (stage.name != "reduce") {
      stages.emplace_back(stage.name, stage.seconds);
      continue;
    }
    stages.emplace_back("order", se.order_seconds);
    stages.emplace_back("factor", se.factor_seconds);
    stages.emplace_back("eigen-solve", se.eigen_seconds);
    stages.emplace_back(
        "reduce", std::max(0.0, stage.seconds - se.order_seconds - se.factor_seconds - se.eigen_seconds));
  }
  return stages;
}

Superelement condense_component(const Component& c, EigenBackend backend, const Logger& log,
                                const CondenseRun& run) {
  StageTimer* timer = run.timer;
  const bool volume = c.kind == "volume";
  if (backend == EigenBackend::kLobpcg) {
    // The iterative eigen-solve (lobpcg.hpp) replaces the factor of K for solids; everything else factorizes
    // anyway.
    if (!volume)
      throw Error(
          "the lobpcg eigensolver is for volume components (second-order tetrahedra); beam models "
          "solve with block-lanczos (the default) in a fraction of a second");
    // Distributing couplings in multiplier form solve through a factor of K_ii (constrained_factor.hpp).
    if (c.volume.rbe3_form == DistributingForm::kMultiplier)
      throw Error(
          "rbe3_form = \"multiplier\" solves through a factor of the interior stiffness; the lobpcg "
          "eigensolver "
          "forms none: use \"elimination\" or \"auto\"",
          c.volume.where, "volume.rbe3_form");
  }
  Mesh mesh;
  if (volume) {
    mesh = load_volume_mesh(c);
    log.info("mesh: " + std::to_string(mesh.nodes.size()) + " nodes, " +
             std::to_string(mesh.elements.size()) + " elements from " + c.volume.mesh.filename().string());
    if (timer) timer->lap("mesh");
  }
  const DistributingForm rbe3_form =
      backend == EigenBackend::kLobpcg ? DistributingForm::kElimination : c.volume.rbe3_form;
  FeModel model = volume ? build_volume_model(c, mesh, rbe3_form) : build_beam_model(c);
  // A volume's interfaces are its coupling nodes; a beam's must lie on nodes of the beam.
  const std::vector<int> interface_nodes =
      volume ? model.coupling_nodes : locate(model, c.interfaces, c.point_tolerance, "interface");
  // Observation points of a solid snap to the nearest node (a beam's must lie on a node).
  std::vector<int> observer_nodes;
  Eigen::MatrixXd observer_normals;
  if (volume) {
    // The nearest node of the outer surface, and its outward normal (normal velocity later).
    observer_normals.resize(static_cast<Eigen::Index>(c.observers.size()), 3);
    for (std::size_t i = 0; i < c.observers.size(); ++i) {
      const Vec3& at = c.observers[i].at;
      const int best = nearest_surface_node(model.surface, model.nodes, Eigen::Vector3d(at[0], at[1], at[2]));
      observer_nodes.push_back(model.surface.nodes[best]);
      observer_normals.row(static_cast<Eigen::Index>(i)) = model.surface.normals.row(best);
    }
  } else {
    observer_nodes = locate(model, c.observers, c.point_tolerance, "observation");
  }
  const int rigid_body_modes = count_rigid_body_modes(model);
  // The free-DOF matrices; what the reduction does not need is freed before it runs (its factorization
  // sets the peak memory): the nodal stiffness, and the mesh unless it is exported. A modal reduction
  // reads one triangle only and hands both matrices over to the eigen-solve (see ReductionInput).
  const auto stored =
      c.reduction.method == ReductionMethod::kModal ? FeModel::Triangles::kLower : FeModel::Triangles::kBoth;
  ReductionInput in;
  in.lower_triangles = stored == FeModel::Triangles::kLower;
  {
    SparseMatrix K = model.stiffness(stored);
    in.stiffness.swap(K);  // Eigen 3.4's SparseMatrix has no move assignment: swap, not copy
  }
  release(model.stiffness_all);
  {
    SparseMatrix M = model.mass(stored);
    in.mass.swap(M);
  }
  if (backend == EigenBackend::kLobpcg)
    in.coarse_space = std::make_shared<const CoarseSpace>(tet10_vertex_space(mesh, model));
  if (!run.mesh_export) mesh = Mesh();
  log.info("model: " + std::to_string(model.nodes.size()) + " nodes, " + std::to_string(model.element_count) +
           " " + model.element_kind + ", " + std::to_string(model.free_dofs()) + " free DOF");
  if (timer) timer->lap("assemble");

  // The centrifugal geometric stiffness per product of the spin (geometric_stiffness.hpp), from the
  // free-DOF K and M; reduced at speed, the modes are those of K + K_G(spin).
  std::array<SparseMatrix, 6> spin_stiffness;
  const Eigen::Vector3d spin(c.reduction.spin[0], c.reduction.spin[1], c.reduction.spin[2]);
  if (c.reduction.geometric_stiffening) {
    spin_stiffness = centrifugal_geometric_stiffness(model, in.stiffness, in.mass, in.lower_triangles,
                                                     rigid_body_modes, run.ordering);
    if (spin.norm() > 0.0) {
      const std::array<double, 6> w = spin_products(spin);
      SparseMatrix kg = w[0] * spin_stiffness[0];
      for (int p = 1; p < 6; ++p) kg += w[p] * spin_stiffness[p];
      if (in.lower_triangles) kg = SparseMatrix(kg.triangularView<Eigen::Lower>());
      in.stiffness += kg;
      log.info("reduce at spin " + std::to_string(spin.norm() * 30.0 / kPi) +
               " rpm: stiffness K + K_G(omega)");
    }
    if (timer) timer->lap("prestress");
  }

  // A static preload stiffens (or softens) the part for good: K + K_G(u_preload) (geometric_stiffness.hpp).
  if (!c.preloads.empty()) {
    Eigen::VectorXd load = Eigen::VectorXd::Zero(model.all_dofs());
    for (const Preload& p : c.preloads) {
      const auto named = [&](const std::vector<NamedPoint>& points, const std::vector<int>& nodes) {
        for (std::size_t k = 0; k < points.size(); ++k)
          if (points[k].name == p.point) return nodes[k];
        return -1;
      };
      int node = named(c.interfaces, interface_nodes);
      if (node < 0) node = named(c.observers, observer_nodes);
      const bool moment = p.moment[0] != 0.0 || p.moment[1] != 0.0 || p.moment[2] != 0.0;
      if (moment && model.inactive_dof[6 * node + 3])
        throw Error("preload at \"" + p.point +
                        "\": a moment needs a node with rotations (a beam node or a volume's "
                        "interface), not a solid's surface node",
                    p.where, p.path + ".moment");
      for (int a = 0; a < 3; ++a) {
        load(6 * node + a) += p.force[a];
        load(6 * node + 3 + a) += p.moment[a];
      }
    }
    SparseMatrix kg = preload_geometric_stiffness(model, in.stiffness, in.mass, in.lower_triangles,
                                                  rigid_body_modes, run.ordering, load);
    if (in.lower_triangles) kg = SparseMatrix(kg.triangularView<Eigen::Lower>());
    in.stiffness += kg;
    log.info("preload: " + std::to_string(c.preloads.size()) + " load(s); stiffness K + K_G(preload)");
    if (timer) timer->lap("preload");
  }

  in.settings = c.reduction;
  in.backend = backend;
  in.progress = run.progress;
  in.ordering = run.ordering;
  in.rigid_body_modes = rigid_body_modes;
  {
    // The error estimate scales rotations by the model's size: half the diagonal of its bounding box.
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (const Eigen::Vector3d& x : model.nodes) {
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
    in.length_scale = model.nodes.empty() ? 1.0 : std::max(0.5 * (hi - lo).norm(), 1e-9);
  }
  collect_boundary(model, c.interfaces, interface_nodes, in.boundary_dofs, in.boundary_names);
  if (!c.reduction.residual_vectors.empty()) {
    // Unit forces along the surface normal at the named observation points (component.hpp)
    if (!volume)
      throw Error(
          "residual_vectors need a volume's observation points (the load is along the surface normal)",
          c.reduction.residual_where, "reduction.residual_vectors");
    const std::vector<int> free_of = model.free_index();
    std::vector<int> chosen;
    for (const std::string& want : c.reduction.residual_vectors) {
      const bool prefix = !want.empty() && want.back() == '*';
      const std::string stem = prefix ? want.substr(0, want.size() - 1) : want;
      bool found = false;
      for (std::size_t i = 0; i < c.observers.size(); ++i) {
        const std::string& name = c.observers[i].name;
        if (prefix ? name.rfind(stem, 0) == 0 : name == want) {
          found = true;
          if (std::find(chosen.begin(), chosen.end(), static_cast<int>(i)) == chosen.end())
            chosen.push_back(static_cast<int>(i));
        }
      }
      if (!found)
        throw Error("residual_vectors: no observation point " +
                        (prefix ? "starts with \"" + stem + "\"" : "is named \"" + want + "\""),
                    c.reduction.residual_where, "reduction.residual_vectors");
    }
    in.residual_loads = Eigen::MatrixXd::Zero(model.free_dofs(), static_cast<Eigen::Index>(chosen.size()));
    const double patch = c.reduction.residual_patch;
    for (std::size_t k = 0; k < chosen.size(); ++k) {
      const int i = chosen[k], node = observer_nodes[i];
      // the patch: the free surface nodes within `patch` of the point's node (at least the node itself)
      std::vector<std::pair<int, Eigen::Vector3d>> loaded;
      for (std::size_t s = 0; s < model.surface.nodes.size(); ++s) {
        const int m = model.surface.nodes[s];
        const bool free = free_of[6 * m] >= 0 && free_of[6 * m + 1] >= 0 && free_of[6 * m + 2] >= 0;
        if (m == node || (patch > 0 && free && (model.nodes[m] - model.nodes[node]).norm() <= patch))
          loaded.emplace_back(m, model.surface.normals.row(static_cast<Eigen::Index>(s)).transpose());
      }
      for (const auto& [m, normal] : loaded)
        for (int a = 0; a < 3; ++a) {
          const int f = free_of[6 * m + a];
          if (f < 0)
            throw Error("residual_vectors: observation point \"" + c.observers[i].name +
                            "\" is on a held or coupled node",
                        c.reduction.residual_where, "reduction.residual_vectors");
          in.residual_loads(f, static_cast<Eigen::Index>(k)) +=
              normal(a) / static_cast<double>(loaded.size());
        }
      in.residual_load_names.push_back(c.observers[i].name);
    }
  }
  in.constraints = model.constraint_matrix;
  if (in.constraints.rows() > 0) {
    log.info("distributing couplings: " + std::to_string(in.constraints.rows() / 6) +
             " in multiplier form (" + std::to_string(in.constraints.rows()) +
             " constraints C u = 0 beside a sparse K)");
  }

  log.info("reduce: " + to_string(c.reduction.method) + " on " + std::to_string(model.free_dofs()) +
           " DOF (" + std::to_string(in.boundary_dofs.size()) + " interface DOF, " +
           std::to_string(in.rigid_body_modes) + " rigid-body modes, eigen-solver " + to_string(backend) +
           ")");
  const ReducedModel r = reduce(in, log);
  release(in.stiffness);
  release(in.mass);
  if (timer) timer->lap("reduce");

  const Eigen::MatrixXd shapes = model.transform * r.basis;  // 6N x n nodal shapes
  Superelement se;
  se.name = c.name;
  se.kind = c.kind;
  se.method = to_string(c.reduction.method);
  se.orthonormalized = c.reduction.method == ReductionMethod::kModal || c.reduction.orthonormalize;
  se.damping_ratio = c.reduction.damping_ratio;
  se.rigid_body_modes_removed = r.rigid_body_modes_removed;
  se.rigid_body_modes_contained = r.rigid_body_modes_contained;
  se.frequency_hz = r.frequency_hz;
  se.fixed_interface_hz = r.fixed_interface_hz;
  se.coordinates = r.coordinates;
  se.static_correction = r.static_correction;
  se.mass = r.mass;
  se.stiffness = r.stiffness;
  se.damping = r.damping;
  if (c.reduction.geometric_stiffening) {
    se.reference_spin = spin;
    for (int p = 0; p < 6; ++p) {
      Eigen::MatrixXd kr = r.basis.transpose() * (spin_stiffness[p] * r.basis);
      se.geometric_stiffness.push_back(0.5 * (kr + kr.transpose()));
    }
  }
  se.interfaces = point_set(model, c.interfaces, interface_nodes, shapes);
  se.observers = point_set(model, c.observers, observer_nodes, shapes);
  se.observers.normals = observer_normals;
  if (c.export_surface) {
    SurfaceExport s;
    const std::size_t count = model.surface.nodes.size();
    s.position.resize(static_cast<Eigen::Index>(count), 3);
    s.normal = model.surface.normals;
    s.area = model.surface.areas;
    s.triangles = model.surface.triangles;
    s.shape.reserve(count * 3 * shapes.cols());
    for (std::size_t i = 0; i < count; ++i) {
      const int node = model.surface.nodes[i];
      s.labels.push_back(model.labels[node]);
      s.position.row(static_cast<Eigen::Index>(i)) = model.nodes[node].transpose();
      for (int a = 0; a < 3; ++a)
        for (Eigen::Index j = 0; j < shapes.cols(); ++j) s.shape.push_back(shapes(6 * node + a, j));
    }
    se.surface = std::move(s);
  }
  se.inertia = rigid_body_inertia(model);
  se.invariants = modal_invariants(model, shapes);
  se.node_count = static_cast<int>(model.nodes.size());
  se.element_count = model.element_count;
  se.dof_count = model.all_dofs();
  se.free_dof_count = model.free_dofs();
  se.max_residual = r.max_residual;
  se.factor_ordering = r.factor.ordering;
  se.matrix_nonzeros = r.factor.matrix_nonzeros;
  se.factor_nonzeros = r.factor.factor_nonzeros;
  se.factor_flops = r.factor.flops;
  se.factorizations = r.factor.factorizations;
  se.order_seconds = r.factor.order_seconds;
  se.factor_seconds = r.factor.factor_seconds;
  se.eigen_seconds = r.eigen_seconds;
  se.eigen_solves = r.eigen_solves;
  se.eigensolver = to_string(r.backend);  // lobpcg may have handed the fixed-interface modes to the factor
  se.reduction_error.estimate = r.frf_error;
  se.reduction_error.tolerance = c.reduction.frf_tolerance;
  se.reduction_error.cutoff_hz = r.cutoff_hz;
  se.reduction_error.passes = r.cutoff_passes;
  if (run.mesh_export && volume) {
    *run.mesh_export =
        make_mesh_export(mesh, shapes, se.coordinates,
                         se.orthonormalized || se.method == "modal" ? se.frequency_hz : Eigen::VectorXd());
  }
  if (timer) timer->lap("invariants");
  return se;
}

}  // namespace nvh::condense
