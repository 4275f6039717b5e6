// The superelement file's writer and reader (common/superelement.hpp); the layout is docs/hdf5-format.md.
#include "common/superelement.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "common/error.hpp"
#include "common/hdf5.hpp"

namespace nvh {
namespace {

/// A 6 x n shape per point, stored as one (count, 6, n) dataset.
std::vector<double> stack_shapes(const PointSet& points, int n) {
  std::vector<double> flat;
  flat.reserve(points.shapes.size() * 6 * n);
  for (const Eigen::MatrixXd& s : points.shapes)
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < n; ++c) flat.push_back(s(r, c));
  return flat;
}

void write_points(h5::Group& g, const PointSet& points, int n, const std::string& what) {
  const hsize_t count = points.names.size();
  g.write("name", points.names);
  Eigen::MatrixXd position = points.position;
  if (position.rows() == 0) position.resize(0, 3);
  g.write("position", position);
  g.set_attribute("units", "m", "position");
  g.write("shape", stack_shapes(points, n), {count, 6, static_cast<hsize_t>(n)});
  g.set_attribute("units", "m (ux uy uz) and rad (rx ry rz) per unit coordinate", "shape");
  g.set_attribute("description",
                  "motion of each " + what +
                      " point per unit of each coordinate: "
                      "(point, [ux uy uz rx ry rz], coordinate)",
                  "shape");
}

PointSet read_points(const h5::Group& g, int n, const std::string& where) {
  PointSet p;
  p.names = g.read_strings("name");
  const hsize_t count = p.names.size();
  p.position = g.read_matrix("position", count, 3);
  std::vector<hsize_t> dims;
  const std::vector<double> flat = g.read_array("shape", dims);
  if (dims.size() != 3 || dims[0] != count || dims[1] != 6 || dims[2] != static_cast<hsize_t>(n)) {
    throw Error(where + ":" + g.path() + "/shape: expected shape (" + std::to_string(count) + ", 6, " +
                std::to_string(n) + ")");
  }
  for (hsize_t i = 0; i < count; ++i) {
    Eigen::MatrixXd s(6, n);
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < n; ++c) s(r, c) = flat[(i * 6 + r) * n + c];
    p.shapes.push_back(s);
  }
  return p;
}

// Numbers a corrupted (or hand-edited) file may hold that no shape check sees: what solve would turn into
// NaN states or a singular mass matrix many steps later. Errors name the file and the dataset.
void require_finite(const Eigen::Ref<const Eigen::MatrixXd>& values, const std::string& where) {
  for (Eigen::Index c = 0; c < values.cols(); ++c)
    for (Eigen::Index r = 0; r < values.rows(); ++r)
      if (!std::isfinite(values(r, c))) {
        throw Error(where + ": entry (" + std::to_string(r) + ", " + std::to_string(c) + ") is " +
                    std::to_string(values(r, c)) + "; expected finite numbers (a corrupted file?)");
      }
}

void require_ascending_frequencies(const Eigen::VectorXd& f, const std::string& where) {
  require_finite(f, where);
  for (Eigen::Index i = 0; i < f.size(); ++i) {
    if (f[i] < 0.0 || (i > 0 && f[i] < f[i - 1])) {
      throw Error(where + ": frequency " + std::to_string(i) + " is " + std::to_string(f[i]) +
                  " Hz; expected non-negative frequencies in ascending order (a corrupted file?)");
    }
  }
}

void validate(const SuperelementFile& se, const std::string& file) {
  const int n = se.size();
  require_ascending_frequencies(se.frequency_hz, file + ":/modes/frequency_hz");
  require_ascending_frequencies(se.fixed_interface_hz, file + ":/modes/fixed_interface_hz");
  if (static_cast<int>(se.coordinates.size()) != n) {
    throw Error(file + ":/reduced/coordinates: " + std::to_string(se.coordinates.size()) + " names for " +
                std::to_string(n) + " coordinates");
  }
  require_finite(se.mass, file + ":/reduced/mass");
  require_finite(se.stiffness, file + ":/reduced/stiffness");
  require_finite(se.damping, file + ":/reduced/damping");
  // The mass matrix: symmetric and positive definite up to round-off (a product basis^T M basis).
  const double scale = se.mass.cwiseAbs().maxCoeff();
  if (n > 0 && !(scale > 0.0))
    throw Error(file + ":/reduced/mass: all zero; expected a positive definite matrix");
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < i; ++j)
      if (std::abs(se.mass(i, j) - se.mass(j, i)) > 1e-8 * scale) {
        throw Error(file + ":/reduced/mass: not symmetric (entries (" + std::to_string(i) + ", " +
                    std::to_string(j) + ") and (" + std::to_string(j) + ", " + std::to_string(i) +
                    ") differ); a corrupted file?");
      }
  if (n > 0) {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(se.mass, Eigen::EigenvaluesOnly);
    if (eigen.info() != Eigen::Success || !(eigen.eigenvalues()[0] > 1e-12 * scale)) {
      throw Error(file + ":/reduced/mass: not positive definite (smallest eigenvalue " +
                  std::to_string(eigen.eigenvalues()[0]) + "); a corrupted file?");
    }
  }
  for (const auto* points : {&se.interfaces, &se.observers}) {
    const std::string group = points == &se.interfaces ? ":/interface" : ":/observe";
    require_finite(points->position, file + group + "/position");
    for (const Eigen::MatrixXd& shape : points->shapes) require_finite(shape, file + group + "/shape");
  }
  require_finite(se.observers.normals, file + ":/observe/normal");
  if (se.surface) {
    require_finite(se.surface->position, file + ":/surface/position");
    require_finite(se.surface->normal, file + ":/surface/normal");
    require_finite(se.surface->area, file + ":/surface/area");
    require_finite(Eigen::Map<const Eigen::VectorXd>(se.surface->shape.data(),
                                                     static_cast<Eigen::Index>(se.surface->shape.size())),
                   file + ":/surface/shape");
    const auto nodes = static_cast<std::int64_t>(se.surface->labels.size());
    for (const auto& triangle : se.surface->triangles)
      for (const int node : triangle)
        if (node < 0 || node >= nodes) {
          throw Error(file + ":/surface/triangles: node index " + std::to_string(node) + " outside 0.." +
                      std::to_string(nodes - 1));
        }
  }
  if (!(se.inertia.mass > 0.0) || !std::isfinite(se.inertia.mass)) {
    throw Error(file + ":/invariants/mass: " + std::to_string(se.inertia.mass) +
                " kg; expected a positive mass");
  }
  require_finite(se.inertia.center_of_mass, file + ":/invariants/center_of_mass");
  require_finite(se.inertia.inertia, file + ":/invariants/inertia");
  require_finite(se.inertia.inertia_origin, file + ":/invariants/inertia_origin");
  require_finite(se.inertia.second_moment, file + ":/invariants/second_moment");
  require_finite(se.invariants.translational, file + ":/invariants/translational_coupling");
  require_finite(se.invariants.rotational, file + ":/invariants/rotational_coupling");
  for (const Eigen::VectorXd& v : se.invariants.position)
    require_finite(v, file + ":/invariants/position_coupling");
  for (const Eigen::MatrixXd& m : se.invariants.quadratic) require_finite(m, file + ":/invariants/quadratic");
  if (se.rigid_body_modes_removed < 0 || se.rigid_body_modes_contained < 0 ||
      se.rigid_body_modes_contained > n) {
    throw Error(file + ":/modes: rigid_body_modes_removed / _contained out of range (a corrupted file?)");
  }
}

}  // namespace

void write_superelement(const std::filesystem::path& path, const SuperelementFile& se,
                        const Provenance& provenance, const SuperelementExtra& extra) {
  const int n = se.size();
  const hsize_t hn = static_cast<hsize_t>(n);
  h5::File file = h5::File::create(path);
  h5::Group root = file.root();
  root.set_attribute("format", kSuperelementFormat);
  root.set_attribute("format_version", kSuperelementFormatVersion);
  root.set_attribute("units", "SI");
  root.set_attribute("component", se.name);
  root.set_attribute("kind", se.kind);
  root.set_attribute("method", se.method);
  root.set_attribute("orthonormalized", se.orthonormalized ? 1 : 0);
  root.set_attribute("coordinates", static_cast<std::int64_t>(n));
  write_provenance(root, provenance);

  h5::Group modes = root.create_group("modes");
  modes.write("frequency_hz", se.frequency_hz);
  modes.set_attribute("units", "Hz", "frequency_hz");
  modes.set_attribute("description",
                      "elastic eigenfrequencies of the reduced system (K_r, M_r), ascending; for an "
                      "orthonormalized or modal basis, the frequency of each coordinate",
                      "frequency_hz");
  modes.set_attribute("rigid_body_modes_removed", se.rigid_body_modes_removed);
  modes.set_attribute("rigid_body_modes_contained", se.rigid_body_modes_contained);
  if (se.fixed_interface_hz.size() > 0) {
    modes.write("fixed_interface_hz", se.fixed_interface_hz);
    modes.set_attribute("units", "Hz", "fixed_interface_hz");
    modes.set_attribute("description",
                        "Craig-Bampton: eigenfrequencies of the model with all interface DOF "
                        "held, for the retained fixed-interface modes",
                        "fixed_interface_hz");
  }

  h5::Group reduced = root.create_group("reduced");
  reduced.write("mass", se.mass);
  reduced.write("stiffness", se.stiffness);
  reduced.write("damping", se.damping);
  reduced.write("coordinates", se.coordinates);
  // Generalized units: they follow the coordinates (see docs/hdf5-format.md).
  reduced.set_attribute("units",
                        "generalized: basis^T M basis (1 for mass-normalized modes; kg, kg m^2 for "
                        "interface translations, rotations)",
                        "mass");
  reduced.set_attribute("units",
                        "generalized: basis^T K basis (1/s^2 for mass-normalized modes; N/m, N m/rad "
                        "for interface DOF)",
                        "stiffness");
  reduced.set_attribute("units", "generalized, as stiffness times s", "damping");
  reduced.set_attribute("damping_ratio", se.damping_ratio, "damping");
  reduced.set_attribute("description", "what each coordinate q_j is", "coordinates");
  reduced.set_attribute("static_correction", static_cast<std::int64_t>(se.static_correction));
  if (!se.geometric_stiffness.empty()) {
    h5::Group g = reduced.create_group("geometric_stiffness");
    for (std::size_t p = 0; p < kSpinProducts.size(); ++p) {
      g.write(kSpinProductNames[p], se.geometric_stiffness[p]);
      g.set_attribute("units", "generalized stiffness per (rad/s)^2", kSpinProductNames[p]);
    }
    g.set_attribute(
        "description",
        "centrifugal geometric stiffness K_ab per product omega_a omega_b of the spin's components "
        "(component axes, about the origin): K(omega) = stiffness + sum (omega_a omega_b - "
        "reference_spin_a reference_spin_b) K_ab; reference_spin (rad/s, component axes): the "
        "spin at which stiffness was reduced");
    g.set_attribute("reference_spin",
                    std::vector<double>{se.reference_spin(0), se.reference_spin(1), se.reference_spin(2)});
  }

  h5::Group interface = root.create_group("interface");
  write_points(interface, se.interfaces, n, "interface");
  h5::Group observe = root.create_group("observe");
  write_points(observe, se.observers, n, "observation");
  if (se.observers.normals.rows() > 0) {
    observe.write("normal", se.observers.normals);
    observe.set_attribute("description", "outward unit normal of the surface at each observation point",
                          "normal");
  }
  if (se.surface) {
    const SurfaceExport& s = *se.surface;
    h5::Group surface = root.create_group("surface");
    const hsize_t count = s.labels.size();
    surface.write("node", std::span<const std::int64_t>(s.labels));
    surface.set_attribute("description", "mesh node label of each surface node", "node");
    surface.write("position", s.position);
    surface.set_attribute("units", "m", "position");
    surface.write("normal", s.normal);
    surface.set_attribute("description", "outward unit normal (area-weighted over the adjacent triangles)",
                          "normal");
    surface.write("area", s.area);
    surface.set_attribute("units", "m^2", "area");
    surface.set_attribute("description", "area each node represents (a third of its adjacent triangles)",
                          "area");
    std::vector<std::int64_t> triangles;
    for (const auto& t : s.triangles) triangles.insert(triangles.end(), t.begin(), t.end());
    surface.write("triangles", std::span<const std::int64_t>(triangles));
    surface.set_attribute("description",
                          "flat sub-triangles, 3 consecutive 0-based indices into the surface nodes "
                          "(read as shape (triangles, 3))",
                          "triangles");
    surface.write("shape", s.shape, {count, 3, static_cast<hsize_t>(n)});
    surface.set_attribute("units", "m per unit coordinate", "shape");
  }

  h5::Group inv = root.create_group("invariants");
  inv.set_attribute("formulation", "Shabana, Dynamics of Multibody Systems, 3rd ed., 2005, sec. 5.5");
  inv.write("mass", se.inertia.mass);
  inv.set_attribute("units", "kg", "mass");
  inv.write("center_of_mass", Eigen::VectorXd(se.inertia.center_of_mass));
  inv.set_attribute("units", "m", "center_of_mass");
  inv.write("inertia", Eigen::MatrixXd(se.inertia.inertia));
  inv.set_attribute("units", "kg m^2", "inertia");
  inv.set_attribute("description", "inertia tensor about the centre of mass, component axes", "inertia");
  inv.write("inertia_origin", Eigen::MatrixXd(se.inertia.inertia_origin));
  inv.set_attribute("units", "kg m^2", "inertia_origin");
  inv.write("second_moment", Eigen::MatrixXd(se.inertia.second_moment));
  inv.set_attribute("units", "kg m^2", "second_moment");
  inv.set_attribute("description", "I_kl = int rho x_k x_l dV about the component origin", "second_moment");
  inv.write("translational_coupling", se.invariants.translational);
  inv.set_attribute("description", "S_bar = int rho S dV (3 x n)", "translational_coupling");
  inv.set_attribute("units", "kg m per unit coordinate", "translational_coupling");
  inv.write("rotational_coupling", se.invariants.rotational);
  inv.set_attribute("description", "int rho x~ S dV about the component origin (3 x n)",
                    "rotational_coupling");
  inv.set_attribute("units", "kg m^2 per unit coordinate", "rotational_coupling");
  std::vector<double> position, quadratic;
  for (int kl = 0; kl < 9; ++kl) {
    for (int i = 0; i < n; ++i) position.push_back(se.invariants.position[kl](i));
  }
  for (int kl = 0; kl < 9; ++kl) {
    const Eigen::MatrixXd& s = se.invariants.quadratic[kl];
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) quadratic.push_back(s(i, j));
  }
  inv.write("position_coupling", position, {3, 3, hn});
  inv.set_attribute("description", "I_tilde[k][l] = int rho x_k S_l dV (3, 3, n)", "position_coupling");
  inv.write("quadratic", quadratic, {3, 3, hn, hn});
  inv.set_attribute("description", "S[k][l] = int rho S_k^T S_l dV (3, 3, n, n)", "quadratic");
  inv.set_attribute("units", "kg m^2 per unit coordinate", "position_coupling");
  inv.set_attribute("units", "kg m^2 per unit coordinate squared", "quadratic");

  // The producing tool's own record (condense: /model), not part of the contract.
  if (extra) extra(root);
  file.commit();
}

SuperelementFile read_superelement(const std::filesystem::path& path) {
  h5::File file = h5::File::open_read(path);
  const h5::Group& root = file.root();
  const std::string where = path.string();
  if (!root.has_attribute("format") || root.string_attribute("format") != kSuperelementFormat) {
    throw Error(where + ": not a superelement file (root attribute format = \"superelement\" missing)");
  }
  const std::string version = root.string_attribute("format_version");
  if (version.substr(0, 2) != "1.") {
    throw Error(where + ": superelement format_version " + version + " is not supported (expected 1.x)");
  }
  SuperelementFile se;
  se.name = root.string_attribute("component");
  se.kind = root.string_attribute("kind");
  se.method = root.string_attribute("method");
  se.orthonormalized = root.int_attribute("orthonormalized") != 0;
  const h5::Group modes = root.open_group("modes");
  se.frequency_hz = modes.read_vector("frequency_hz");
  se.rigid_body_modes_removed = static_cast<int>(modes.int_attribute("rigid_body_modes_removed"));
  se.rigid_body_modes_contained = static_cast<int>(modes.int_attribute("rigid_body_modes_contained"));
  if (modes.exists("fixed_interface_hz")) se.fixed_interface_hz = modes.read_vector("fixed_interface_hz");
  const h5::Group reduced = root.open_group("reduced");
  se.mass = reduced.read_matrix("mass");
  const int n = static_cast<int>(se.mass.rows());
  const hsize_t hn = static_cast<hsize_t>(n);
  se.stiffness = reduced.read_matrix("stiffness", hn, hn);
  se.damping = reduced.read_matrix("damping", hn, hn);
  se.damping_ratio = reduced.double_attribute("damping_ratio", "damping");
  se.coordinates = reduced.read_strings("coordinates");
  se.static_correction = reduced.has_attribute("static_correction")
                             ? static_cast<int>(reduced.int_attribute("static_correction"))
                             : 0;
  if (reduced.exists("geometric_stiffness")) {
    const h5::Group g = reduced.open_group("geometric_stiffness");
    for (const char* name : kSpinProductNames) {
      se.geometric_stiffness.push_back(g.read_matrix(name, hn, hn));
      require_finite(se.geometric_stiffness.back(), where + ":/reduced/geometric_stiffness/" + name);
    }
    const std::vector<double> w = g.doubles_attribute("reference_spin");
    if (w.size() != 3) {
      throw Error(where +
                  ":/reduced/geometric_stiffness: attribute reference_spin: expected 3 values (rad/s)");
    }
    se.reference_spin = Eigen::Vector3d(w[0], w[1], w[2]);
  }
  se.interfaces = read_points(root.open_group("interface"), n, where);
  se.observers = read_points(root.open_group("observe"), n, where);
  if (root.exists("observe/normal")) {
    se.observers.normals = root.open_group("observe").read_matrix("normal", se.observers.names.size(), 3);
  }
  if (root.exists("surface")) {
    const h5::Group g = root.open_group("surface");
    SurfaceExport s;
    s.labels = g.read_ints("node");
    const hsize_t count = s.labels.size();
    s.position = g.read_matrix("position", count, 3);
    s.normal = g.read_matrix("normal", count, 3);
    s.area = g.read_vector("area", count);
    const std::vector<std::int64_t> t = g.read_ints("triangles");
    if (t.size() % 3 != 0) throw Error(where + ":/surface/triangles: expected a multiple of 3 indices");
    for (std::size_t i = 0; i < t.size(); i += 3) {
      s.triangles.push_back({static_cast<int>(t[i]), static_cast<int>(t[i + 1]), static_cast<int>(t[i + 2])});
    }
    std::vector<hsize_t> dims;
    s.shape = g.read_array("shape", dims);
    if (dims != std::vector<hsize_t>{count, 3, hn}) {
      throw Error(where + ":/surface/shape: expected shape (" + std::to_string(count) + ", 3, " +
                  std::to_string(n) + ")");
    }
    se.surface = std::move(s);
  }
  const h5::Group inv = root.open_group("invariants");
  se.inertia.mass = inv.read_double("mass");
  se.inertia.center_of_mass = inv.read_vector("center_of_mass", 3);
  se.inertia.inertia = inv.read_matrix("inertia", 3, 3);
  se.inertia.inertia_origin = inv.read_matrix("inertia_origin", 3, 3);
  se.inertia.second_moment = inv.read_matrix("second_moment", 3, 3);
  se.invariants.translational = inv.read_matrix("translational_coupling", 3, hn);
  se.invariants.rotational = inv.read_matrix("rotational_coupling", 3, hn);
  std::vector<hsize_t> dims;
  const std::vector<double> position = inv.read_array("position_coupling", dims);
  if (dims != std::vector<hsize_t>{3, 3, hn}) {
    throw Error(where + ":/invariants/position_coupling: expected shape (3, 3, " + std::to_string(n) + ")");
  }
  const std::vector<double> quadratic = inv.read_array("quadratic", dims);
  if (dims != std::vector<hsize_t>{3, 3, hn, hn}) {
    throw Error(where + ":/invariants/quadratic: expected shape (3, 3, " + std::to_string(n) + ", " +
                std::to_string(n) + ")");
  }
  for (int kl = 0; kl < 9; ++kl) {
    se.invariants.position.push_back(Eigen::Map<const Eigen::VectorXd>(position.data() + kl * n, n));
    Eigen::MatrixXd s(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) s(i, j) = quadratic[(static_cast<std::size_t>(kl) * n + i) * n + j];
    se.invariants.quadratic.push_back(s);
  }
  validate(se, where);
  return se;
}

}  // namespace nvh
