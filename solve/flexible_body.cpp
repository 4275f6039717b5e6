// Flexible bodies in a floating frame of reference (see flexible_body.hpp for coordinates and equations).
//
// Notation: S(x) is the superelement's displacement field (3 x n), s = x + S eta the deformed position of a
// material point in the body frame, u' = S eta' its elastic velocity, A = A(p) body -> global. The inertia
// invariants (condense, docs/hdf5-format.md; Shabana 2005, eq. 5.99-5.110):
//   m, m c = int rho x, I_kl = int rho x_k x_l, S_bar = int rho S, I_tilde_kl = int rho x_k S_l,
//   S_kl = int rho S_k^T S_l (S_k: row k of S).
// The deformation-dependent integrals follow:
//   Psi(eta)  = int rho s s^T   : Psi_kl = I_kl + I_tilde_kl.eta + I_tilde_lk.eta + eta^T S_kl eta
//   P_ab(eta) = int rho s_a S_b : P_ab  = I_tilde_ab + S_ab^T eta                               (n)
//   J(eta)    = tr(Psi) 1 - Psi  (inertia about the frame origin),   (int rho s~ S)_k = eps_kab P_ab.
// The material point's acceleration a = r'' + A (omega' x s + omega x (omega x s) + 2 omega x u' + S eta'')
// projected by J_P^T gives M w' + h with (Shabana 2005, eq. 5.115 and 5.125, here in body-axis omega):
//   M = [ m 1        -A (m c + S_bar eta)~   A S_bar ]      h_r   = A (omega x (omega x (m c + S_bar eta))
//       [ sym        J(eta)                  int rho s~ S ]          + 2 omega x S_bar eta')
//       [ sym        sym                     M_r     ]      h_om  = omega x J omega + 2 (tr(G) omega - G
//       omega),
//                                                                   G_ab = int rho u'_a s_b = P_ba . eta'
//   h_eta_j = sum_ab (omega~ omega~)_ab P_ba,j + 2 sum_ab omega~_ab (S_ab eta')_j.
// Gravity: Q_g = [m g; (m c + S_bar eta) x A^T g; S_bar^T A^T g].
#include "solve/flexible_body.hpp"

#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "common/superelement.hpp"

namespace nvh::solve {
namespace {

using Mat3X = Eigen::Matrix<double, 3, Eigen::Dynamic>;
Eigen::Map<const Vec3> vec3(std::span<const double> s, int at) {
  return Eigen::Map<const Vec3>(s.data() + at);
}
Eigen::Map<const Vec4> vec4(std::span<const double> s, int at) {
  return Eigen::Map<const Vec4>(s.data() + at);
}
Eigen::Map<const Eigen::VectorXd> tail(std::span<const double> s, int from, int n) {
  return Eigen::Map<const Eigen::VectorXd>(s.data() + from, n);
}

/// exp(theta~): the rotation by the vector theta (Rodrigues).
Mat3 rotation_of(const Vec3& theta) {
  const double a = theta.norm();
  if (a < 1e-12) return Mat3::Identity() + skew(theta);
  return Eigen::AngleAxisd(a, theta / a).toRotationMatrix();
}

/// T(theta) with d/dt exp(theta~) = (T theta')~ exp(theta~): the angular velocity of a rotation vector
/// (the left Jacobian of SO(3)): T = 1 + (1 - cos a)/a^2 theta~ + (a - sin a)/a^3 theta~^2, a = |theta|.
Mat3 angular_rate_matrix(const Vec3& theta) {
  const double a = theta.norm();
  const Mat3 t = skew(theta);
  const double c1 = a < 1e-4 ? 0.5 - a * a / 24 : (1 - std::cos(a)) / (a * a);
  const double c2 = a < 1e-4 ? 1.0 / 6 - a * a / 120 : (a - std::sin(a)) / (a * a * a);
  return Mat3::Identity() + c1 * t + c2 * t * t;
}

FlexibleData::Point read_point(const PointSet& set, std::size_t k) {
  FlexibleData::Point p;
  p.name = set.names[k];
  p.position = set.position.row(static_cast<int>(k)).transpose();
  p.translation = set.shapes[k].topRows(3);
  p.rotation = set.shapes[k].bottomRows(3);
  return p;
}

}  // namespace

// ---------------------------------------------------------------- the superelement
FlexibleData load_flexible_data(const std::filesystem::path& file, int modes) {
  const SuperelementFile se = read_superelement(file);
  const std::string where = file.string();
  const int n_all = se.size();
  if (se.inertia.mass <= 0)
    throw Error(where + ": /invariants/mass must be > 0, got " + std::to_string(se.inertia.mass));

  // The elastic basis X (n_all x n_e): identity for orthonormal files (modal, or orthonormalized
  // Craig-Bampton/Guyan); for raw Craig-Bampton/Guyan the elastic modes of (K_r, M_r), the rigid-body
  // modes they contain dropped (the floating frame carries the rigid motion; the elastic modes are
  // mass-orthogonal to it, which makes the frame a Tisserand/mean-axis frame to first order).
  Eigen::MatrixXd x = Eigen::MatrixXd::Identity(n_all, n_all);
  Eigen::VectorXd hz = se.frequency_hz;
  if (!se.orthonormalized) {
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(se.stiffness, se.mass);
    if (eig.info() != Eigen::Success)
      throw Error(where + ": the reduced mass matrix is not positive definite");
    const int rigid = se.rigid_body_modes_contained;
    const Eigen::VectorXd lambda = eig.eigenvalues();
    if (rigid > 0 && rigid < n_all && std::abs(lambda[rigid - 1]) > 1e-6 * lambda[rigid])
      throw Error(where + ": the file says it contains " + std::to_string(rigid) +
                  " rigid-body modes, but (K_r, M_r) has only " + std::to_string(rigid - 1) +
                  " eigenvalues near zero");
    x = eig.eigenvectors().rightCols(n_all - rigid);
    hz = lambda.tail(n_all - rigid).cwiseMax(0.0).cwiseSqrt() / (2 * 3.14159265358979323846);
  }
  const int available = static_cast<int>(x.cols());
  if (available == 0) throw Error(where + ": the superelement has no elastic coordinates");
  if (modes > available)
    throw Error(where + ": " + std::to_string(modes) + " modes asked for, the superelement has " +
                std::to_string(available) + " elastic coordinates");
  if (modes > 0) x = x.leftCols(modes).eval();
  const int n = static_cast<int>(x.cols());

  FlexibleData d;
  d.file = file;
  d.mass = se.inertia.mass;
  d.first_moment = se.inertia.mass * se.inertia.center_of_mass;
  d.second_moment = se.inertia.second_moment;
  d.modal_mass = x.transpose() * se.mass * x;
  d.stiffness = x.transpose() * se.stiffness * x;
  d.damping = x.transpose() * se.damping * x;
  d.translational = se.invariants.translational * x;
  for (int k = 0; k < 9; ++k) {
    d.position[k] = x.transpose() * se.invariants.position[k];
    d.quadratic[k] = x.transpose() * se.invariants.quadratic[k] * x;
  }
  d.frequency_hz = hz.head(std::min<int>(n, static_cast<int>(hz.size())));
  for (const auto* set : {&se.interfaces, &se.observers})
    for (std::size_t k = 0; k < set->names.size(); ++k) {
      FlexibleData::Point p = read_point(*set, k);
      p.translation = p.translation * x;
      p.rotation = p.rotation * x;
      d.points.push_back(std::move(p));
    }
  return d;
}

// ---------------------------------------------------------------- the body
FlexibleBody::FlexibleBody(std::string name, FlexibleData data, Coupling coupling, InitialState init,
                           Eigen::VectorXd eta0, Eigen::VectorXd eta_rate0,
                           std::vector<int> point_of_user_marker)
    : Body(std::move(name)),
      data_(std::move(data)),
      coupling_(coupling),
      init_(init),
      eta0_(std::move(eta0)),
      eta_rate0_(std::move(eta_rate0)),
      n_(data_.size()),
      user_points_(std::move(point_of_user_marker)) {
  if (eta0_.size() == 0) eta0_ = Eigen::VectorXd::Zero(n_);
  if (eta_rate0_.size() == 0) eta_rate0_ = Eigen::VectorXd::Zero(n_);
  for (std::size_t k = 0; k < data_.points.size(); ++k) {
    MarkerDefinition m;
    m.name = data_.points[k].name;
    m.position = data_.points[k].position;
    m.node = static_cast<int>(k);
    add_marker(std::move(m));
  }
  builtin_markers_ = static_cast<int>(data_.points.size());
}

Eigen::VectorXd FlexibleBody::initial_positions() const {
  Eigen::VectorXd q(7 + n_);
  q << init_.position, euler_parameters(init_.orientation), eta0_;
  return q;
}
Eigen::VectorXd FlexibleBody::initial_velocities() const {
  Eigen::VectorXd w(6 + n_);
  w << init_.velocity, init_.orientation.transpose() * init_.angular_velocity, eta_rate0_;
  return w;
}

void FlexibleBody::kinematic_residual(std::span<const double> q, std::span<const double> qdot,
                                      std::span<const double> w_eff, std::span<const double>,
                                      std::span<double> rows, std::span<double>) const {
  frame_kinematic_residual(q, qdot, w_eff, kNormalizationRate, rows);  // as RigidBody (body.hpp)
  Eigen::Map<Eigen::VectorXd>(rows.data() + 7, n_) = tail(qdot, 7, n_) - tail(w_eff, 6, n_);
}

Eigen::VectorXd FlexibleBody::position_rates(std::span<const double> q, std::span<const double> w) const {
  Eigen::VectorXd qd(7 + n_);
  qd << vec3(w, 0), 0.5 * l_matrix(vec4(q, 3)).transpose() * vec3(w, 3), tail(w, 6, n_);
  return qd;
}

FlexibleBody::Inertia FlexibleBody::inertia_terms(const Eigen::Ref<const Eigen::VectorXd>& eta) const {
  Inertia in;
  const bool full = coupling_ == Coupling::kFull;
  in.psi = data_.second_moment;
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) {
      in.psi(k, l) += data_.position[3 * k + l].dot(eta) + data_.position[3 * l + k].dot(eta);
      if (full) in.psi(k, l) += eta.dot(data_.quadratic[3 * k + l] * eta);
      in.p[3 * k + l] = data_.position[3 * k + l];
      if (full) in.p[3 * k + l] += data_.quadratic[3 * k + l].transpose() * eta;
    }
  return in;
}

Mat3X FlexibleBody::Inertia::rotational() const {
  Mat3X r(3, p[0].size());
  r.row(0) = (p[3 * 1 + 2] - p[3 * 2 + 1]).transpose();
  r.row(1) = (p[3 * 2 + 0] - p[3 * 0 + 2]).transpose();
  r.row(2) = (p[3 * 0 + 1] - p[3 * 1 + 0]).transpose();
  return r;
}

Eigen::MatrixXd FlexibleBody::mass_matrix(std::span<const double> q) const {
  const Mat3 a = rotation_matrix(vec4(q, 3));
  const auto eta = tail(q, 7, n_);
  const Inertia in = inertia_terms(eta);
  const Vec3 mc = data_.first_moment + data_.translational * eta;
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(6 + n_, 6 + n_);
  m.topLeftCorner<3, 3>() = data_.mass * Mat3::Identity();
  m.block<3, 3>(0, 3) = -a * skew(mc);
  m.block(0, 6, 3, n_) = a * data_.translational;
  m.block<3, 3>(3, 3) = in.inertia();
  m.block(3, 6, 3, n_) = in.rotational();
  m.bottomRightCorner(n_, n_) = data_.modal_mass;
  // symmetric: the lower blocks are the transposes
  m.block<3, 3>(3, 0) = m.block<3, 3>(0, 3).transpose();
  m.block(6, 0, n_, 3) = m.block(0, 6, 3, n_).transpose();
  m.block(6, 3, n_, 3) = m.block(3, 6, 3, n_).transpose();
  return m;
}

void FlexibleBody::inertia_residual(std::span<const double> q, std::span<const double> w,
                                    std::span<const double> wdot, const Vec3& gravity,
                                    std::span<double> rows) const {
  const Mat3 a = rotation_matrix(vec4(q, 3));
  const auto eta = tail(q, 7, n_);
  const Vec3 omega = vec3(w, 3);
  const auto eta_rate = tail(w, 6, n_);
  const bool full = coupling_ == Coupling::kFull;
  const Inertia in = inertia_terms(eta);
  const Vec3 mc = data_.first_moment + data_.translational * eta;
  const Mat3 om = skew(omega), om2 = om * om;

  // Quadratic velocity vector h (see the top of this file).
  Eigen::VectorXd h(6 + n_);
  h.head<3>() = a * (omega.cross(omega.cross(mc)) + 2 * omega.cross(data_.translational * eta_rate));
  Mat3 g;  // G_ab = P_ba . eta'
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) g(i, j) = in.p[3 * j + i].dot(eta_rate);
  h.segment<3>(3) = omega.cross(in.inertia() * omega) + 2 * (g.trace() * omega - g * omega);
  Eigen::VectorXd he = Eigen::VectorXd::Zero(n_);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      he += om2(i, j) * in.p[3 * j + i];
      if (full && om(i, j) != 0.0) he += 2 * om(i, j) * (data_.quadratic[3 * i + j] * eta_rate);
    }
  h.tail(n_) = he;

  // Gravity and the elastic forces.
  const Vec3 g_body = a.transpose() * gravity;
  Eigen::VectorXd rhs(6 + n_);
  rhs << data_.mass * gravity, mc.cross(g_body),
      data_.translational.transpose() * g_body - data_.stiffness * eta - data_.damping * eta_rate;

  Eigen::Map<Eigen::VectorXd>(rows.data(), 6 + n_) = mass_matrix(q) * tail(wdot, 0, 6 + n_) + h - rhs;
}

int FlexibleBody::point_of(int marker) const {
  const auto& m = markers()[marker];
  if (m.node >= 0) return m.node;
  const int k = marker - builtin_markers_;
  if (k < 0 || k >= static_cast<int>(user_points_.size()))
    throw Error("flexible body '" + name() + "': marker '" + m.name +
                "' is not attached to a superelement point");
  return user_points_[k];
}

// A marker on point P: position r + A (u0 + Phi_t eta), axes A exp((Phi_r eta)~) axes0, angular velocity
// A (omega + T(theta) Phi_r eta'), theta = Phi_r eta (T: angular_rate_matrix; T = 1 for small rotations).
MarkerMotion FlexibleBody::marker_motion(int marker, std::span<const double> q,
                                         std::span<const double> w) const {
  const auto& pt = data_.points[point_of(marker)];
  const Mat3 a = rotation_matrix(vec4(q, 3));
  const auto eta = tail(q, 7, n_);
  const auto eta_rate = tail(w, 6, n_);
  const Vec3 s = pt.position + pt.translation * eta;
  const Vec3 theta = pt.rotation * eta;
  const Vec3 omega = vec3(w, 3);
  MarkerMotion mm;
  mm.position = vec3(q, 0) + a * s;
  mm.axes = a * rotation_of(theta) * markers()[marker].axes;
  mm.velocity = vec3(w, 0) + a * (omega.cross(s) + pt.translation * eta_rate);
  mm.angular_velocity = a * (omega + angular_rate_matrix(theta) * (pt.rotation * eta_rate));
  return mm;
}

// Jv = [1, -A s~, A Phi_t],  Jw = [0, A, A T(theta) Phi_r].
MarkerJacobian FlexibleBody::marker_jacobian(int marker, std::span<const double> q) const {
  const auto& pt = data_.points[point_of(marker)];
  const Mat3 a = rotation_matrix(vec4(q, 3));
  const auto eta = tail(q, 7, n_);
  const Vec3 s = pt.position + pt.translation * eta;
  MarkerJacobian j{Mat3X::Zero(3, 6 + n_), Mat3X::Zero(3, 6 + n_)};
  j.jv.leftCols<3>() = Mat3::Identity();
  j.jv.block<3, 3>(0, 3) = -a * skew(s);
  j.jv.rightCols(n_) = a * pt.translation;
  j.jw.block<3, 3>(0, 3) = a;
  j.jw.rightCols(n_) = a * angular_rate_matrix(pt.rotation * eta) * pt.rotation;
  return j;
}

Vec3 FlexibleBody::reference_position(std::span<const double> q) const {
  return vec3(q, 0);
}
Mat3 FlexibleBody::rotation(std::span<const double> q) const {
  return rotation_matrix(vec4(q, 3));
}

double FlexibleBody::kinetic_energy(std::span<const double> q, std::span<const double> w) const {
  const auto wv = tail(w, 0, 6 + n_);
  return 0.5 * wv.dot(mass_matrix(q) * wv);
}

double FlexibleBody::potential_energy(std::span<const double> q, const Vec3& gravity) const {
  return -data_.mass * gravity.dot(center_of_mass(q)) + strain_energy(q);
}
double FlexibleBody::dissipated_power(std::span<const double>, std::span<const double> w) const {
  const Eigen::Map<const Eigen::VectorXd> rate(w.data() + 6, n_);
  return rate.dot(data_.damping * rate);
}

double FlexibleBody::strain_energy(std::span<const double> q) const {
  const auto eta = tail(q, 7, n_);
  return 0.5 * eta.dot(data_.stiffness * eta);
}

Vec3 FlexibleBody::center_of_mass(std::span<const double> q) const {
  const auto eta = tail(q, 7, n_);
  return vec3(q, 0) +
         rotation_matrix(vec4(q, 3)) * (data_.first_moment + data_.translational * eta) / data_.mass;
}

// The generalized momentum M w holds the linear momentum (rows 0-2) and, in body axes, the angular momentum
// about the frame origin (rows 3-5: int rho s~ A^T v_P = A^T int rho (A s) x v_P).
void FlexibleBody::momentum(std::span<const double> q, std::span<const double> w, Vec3& linear,
                            Vec3& angular) const {
  const Eigen::VectorXd pm = mass_matrix(q) * tail(w, 0, 6 + n_);
  linear = pm.head<3>();
  angular = vec3(q, 0).cross(linear) + rotation_matrix(vec4(q, 3)) * pm.segment<3>(3);
}

// ---------------------------------------------------------------- the scene's [[body]] table
std::unique_ptr<Body> make_flexible_body(const input::Table& t, const std::string& name,
                                         const InitialState& init, const std::filesystem::path& base,
                                         std::vector<std::filesystem::path>& inputs) {
  const std::filesystem::path file = base / t.string("superelement");
  inputs.push_back(file);
  const int modes = static_cast<int>(t.optional_integer("modes", input::Range::at_least(1)).value_or(0));
  const Coupling coupling = t.optional_choice("coupling", {"full", "linear"}).value_or("full") == "full"
                                ? Coupling::kFull
                                : Coupling::kLinear;
  FlexibleData data;
  try {
    data = load_flexible_data(file, modes);
  } catch (const Error& e) {
    const std::string what = e.what();
    const bool too_many = modes > 0 && what.find("modes asked for") != std::string::npos;
    t.fail(too_many ? "modes" : "superelement", "cannot use superelement '" + file.string() + "': " + what);
  }
  const int n = data.size();
  auto modal = [&](const char* key) {
    if (!t.has(key)) return Eigen::VectorXd(Eigen::VectorXd::Zero(n));
    const auto v = t.numbers(key);
    if (static_cast<int>(v.size()) != n)
      t.fail(key, "expected " + std::to_string(n) + " numbers (one per modal coordinate in use), got " +
                      std::to_string(v.size()));
    return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(v.data(), n));
  };
  const Eigen::VectorXd eta0 = modal("modal_coordinates"), eta_rate0 = modal("modal_velocities");

  // [[body.marker]] tables: each sits on a superelement point, named by 'point' or found at 'at'.
  std::vector<int> user_points;
  std::string names;
  for (const auto& p : data.points) names += (names.empty() ? "" : ", ") + p.name;
  for (const auto& m : t.table_array("marker")) {
    int found = -1;
    if (const auto point = m.optional_string("point")) {
      if (m.has("at")) m.fail("at", "give either 'point' (a superelement point) or 'at', not both");
      for (std::size_t k = 0; k < data.points.size(); ++k)
        if (data.points[k].name == *point) found = static_cast<int>(k);
      if (found < 0) {
        std::vector<std::string> candidates;
        for (const auto& p : data.points) candidates.push_back(p.name);
        const std::string near = input::closest(*point, candidates);
        m.fail("point", "the superelement has no point '" + *point + "'" +
                            (near.empty() ? "" : " (did you mean '" + near + "'?)") +
                            "; its points: " + names);
      }
    } else {
      const auto at = m.optional_vec3("at").value_or(std::array<double, 3>{0, 0, 0});
      const Vec3 x(at[0], at[1], at[2]);
      for (std::size_t k = 0; k < data.points.size(); ++k)
        if ((data.points[k].position - x).norm() <= 1e-6) found = static_cast<int>(k);
      if (found < 0)
        m.fail(
            m.has("at") ? "at" : "point",
            "a marker on a flexible body sits on a superelement point: give point = \"NAME\" or 'at' within "
            "1e-6 m of one; its points: " +
                names);
    }
    user_points.push_back(found);
  }
  return std::make_unique<FlexibleBody>(name, std::move(data), coupling, init, eta0, eta_rate0,
                                        std::move(user_points));
}

}  // namespace nvh::solve
