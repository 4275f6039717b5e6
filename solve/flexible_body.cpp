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
#include "solve/element_registry.hpp"
#include "solve/flexible_rotor_body.hpp"

#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "common/superelement.hpp"

namespace nvh::solve {
namespace {

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

/// D(theta, z) = d(T(theta) z)/dtheta (3 x 3), T = angular_rate_matrix. With a = |theta|,
///   T z = z + c1 theta x z + c2 theta x (theta x z),   c1 = (1 - cos a)/a^2,  c2 = (a - sin a)/a^3,
///   D = -c1 z~ + c2 ((theta.z) 1 + theta z^T - 2 z theta^T) + (g1 theta x z + g2 theta x (theta x z))
///   theta^T,
/// g_i = (dc_i/da)/a (series below a = 0.05, where the closed forms lose digits to cancellation).
/// d(T(theta)^T y)/dtheta = -D(-theta, y) (T(theta)^T = T(-theta): c1, c2 are even in a).
Mat3 rate_derivative(const Vec3& theta, const Vec3& z) {
  const double a = theta.norm(), a2 = a * a;
  double c1, c2, g1, g2;
  if (a < 1e-4) {  // as angular_rate_matrix
    c1 = 0.5 - a2 / 24;
    c2 = 1.0 / 6 - a2 / 120;
  } else {
    c1 = (1 - std::cos(a)) / a2;
    c2 = (a - std::sin(a)) / (a2 * a);
  }
  if (a < 0.05) {
    g1 = -1.0 / 12 + a2 / 180 - a2 * a2 / 6720;
    g2 = -1.0 / 60 + a2 / 1260 - a2 * a2 / 60480;
  } else {
    g1 = (a * std::sin(a) - 2 * (1 - std::cos(a))) / (a2 * a2);
    g2 = (a * (1 - std::cos(a)) - 3 * (a - std::sin(a))) / (a2 * a2 * a);
  }
  const Vec3 tz = theta.cross(z), ttz = theta.cross(tz);
  return -c1 * skew(z) +
         c2 * (theta.dot(z) * Mat3::Identity() + theta * z.transpose() - 2 * z * theta.transpose()) +
         (g1 * tz + g2 * ttz) * theta.transpose();
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
FlexibleData load_flexible_data(const std::filesystem::path& file, int modes, const std::vector<int>& numbers) {
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
  if (!numbers.empty()) {  // the chosen coordinates (1-based), as the file orders them
    Eigen::MatrixXd chosen(x.rows(), static_cast<Eigen::Index>(numbers.size()));
    Eigen::VectorXd chosen_hz(static_cast<Eigen::Index>(numbers.size()));
    for (std::size_t k = 0; k < numbers.size(); ++k) {
      const int j = numbers[k] - 1;
      if (j < 0 || j >= available)
        throw Error(where + ": mode number " + std::to_string(numbers[k]) + " asked for, the superelement has " +
                    std::to_string(available) + " elastic coordinates");
      if (k > 0 && numbers[k] <= numbers[k - 1])
        throw Error(where + ": mode numbers must be distinct and ascending, got " +
                    std::to_string(numbers[k - 1]) + " before " + std::to_string(numbers[k]));
      chosen.col(static_cast<Eigen::Index>(k)) = x.col(j);
      chosen_hz[static_cast<Eigen::Index>(k)] = j < hz.size() ? hz[j] : 0.0;
    }
    x = chosen;
    hz = chosen_hz;
  }
  const int n = static_cast<int>(x.cols());

  FlexibleData d;
  d.file = file;
  d.coordinates_in_file = available;
  d.static_correction = se.static_correction;
  d.rigid_body_modes = se.rigid_body_modes_removed + se.rigid_body_modes_contained;
  d.mode_numbers = numbers;
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
  for (const Eigen::MatrixXd& k : se.geometric_stiffness) d.geometric.push_back(x.transpose() * k * x);
  d.reference_spin = se.reference_spin;
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
std::string FlexibleBody::state_meaning(int r) const {
  const auto mode = [&](const char* what, int k) {
    std::ostringstream s;
    s << what << " " << k + 1;
    if (k < data_.frequency_hz.size()) {
      s.precision(2);
      s << ", " << std::fixed << data_.frequency_hz[k] / 1000.0 << " kHz";
    }
    return s.str();
  };
  if (r < 7) return frame_position_meaning(r);
  if (r < 7 + n_) return mode("modal coordinate", r - 7);
  if (r < 13 + n_) return frame_velocity_meaning(r - 7 - n_);
  if (r < 13 + 2 * n_) return mode("modal velocity", r - 13 - n_);
  return {};
}

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
  position_cols_.resize(n_, 9);
  for (int c = 0; c < 9; ++c) position_cols_.col(c) = data_.position[c];
  ws_s_eta_.resize(n_, 9);
  ws_s_rate_.resize(n_, 9);
  ws_s_acc_.resize(n_, 9);
  ws_p_.resize(n_, 9);
  ws_dpsi_.resize(n_, 9);
  ws_3n_.resize(3, n_);
  ws_n_.resize(n_);
  ws_geo_.resize(n_, 6);
}

std::array<double, 6> FlexibleBody::spin_coefficients(const Vec3& omega) const {
  std::array<double, 6> c = spin_products(omega);
  const std::array<double, 6> ref = spin_products(data_.reference_spin);
  for (int p = 0; p < 6; ++p) c[p] -= ref[p];
  return c;
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

// Psi(eta) and P_ab(eta) (top of this file). The linear parts by one product with the packed I_tilde columns:
// Psi_kl = I_kl + (I_tilde^T eta)_kl + (I_tilde^T eta)_lk [+ eta . S_kl eta];  P_ab = I_tilde_ab [+ S_ba eta]
// (S_ab^T = S_ba), the bracketed terms with full coupling only (ws_s_eta_ holds S_kl eta).
const Eigen::MatrixXd& FlexibleBody::inertia_terms(const Eigen::Ref<const Eigen::VectorXd>& eta,
                                                   Mat3& psi) const {
  const bool full = coupling_ == Coupling::kFull;
  Eigen::Matrix<double, 9, 1> te;  // I_tilde_kl . eta
  te.noalias() = position_cols_.transpose() * eta;
  if (full)
    for (int c = 0; c < 9; ++c) ws_s_eta_.col(c).noalias() = data_.quadratic[c] * eta;
  psi = data_.second_moment;
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) {
      psi(k, l) += te[3 * k + l] + te[3 * l + k];
      if (full) psi(k, l) += eta.dot(ws_s_eta_.col(3 * k + l));
    }
  if (!full) return position_cols_;
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l)
      ws_p_.col(3 * k + l) = position_cols_.col(3 * k + l) + ws_s_eta_.col(3 * l + k);
  return ws_p_;
}

void FlexibleBody::mass_matrix(std::span<const double> q, Eigen::Ref<Eigen::MatrixXd> m) const {
  const Mat3 a = rotation_matrix(vec4(q, 3));
  const auto eta = tail(q, 7, n_);
  Mat3 psi;
  const Eigen::MatrixXd& p = inertia_terms(eta, psi);
  const Vec3 mc = data_.first_moment + data_.translational * eta;
  m.topLeftCorner<3, 3>() = data_.mass * Mat3::Identity();
  m.block<3, 3>(0, 3) = -a * skew(mc);
  m.block(0, 6, 3, n_).noalias() = a * data_.translational;
  m.block<3, 3>(3, 3) = psi.trace() * Mat3::Identity() - psi;  // J(eta)
  // int rho s~ S dV: row i = P_jk - P_kj, (i, j, k) cyclic
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    m.block(3 + i, 6, 1, n_) = (p.col(3 * j + k) - p.col(3 * k + j)).transpose();
  }
  m.bottomRightCorner(n_, n_) = data_.modal_mass;
  // symmetric: the lower blocks are the transposes
  m.block<3, 3>(3, 0) = m.block<3, 3>(0, 3).transpose();
  m.block(6, 0, n_, 3) = m.block(0, 6, 3, n_).transpose();
  m.block(6, 3, n_, 3) = m.block(3, 6, 3, n_).transpose();
}

// R = M(eta) w' + h(eta, w) - Q_g + [0; 0; K eta + D eta'] by blocks, without forming M. Gravity acts as an
// acceleration of the frame: Q_g = M [g; 0; 0], so with y = a_r - g and w' = [a_r, a_w, eta''] (as in
// inertia_jacobian below, which differentiates these rows):
//   R_r   = m y + A (a_w x mc + S_bar eta'' + omega x (omega x mc) + 2 omega x S_bar eta')
//   R_om  = mc x (A^T y) + J a_w + (int rho s~ S) eta'' + omega x J omega + 2 (tr(G) omega - G omega)
//   R_eta = S_bar^T A^T y + sum_ab C_ab P_ab + M_r eta'' + K eta + D eta' [+ 2 sum_ab omega~_ab S_ab eta']
// with C = omega~^2 + a_w~^T: (omega~ omega~)_ab P_ab is h_eta's first term (omega~^2 is symmetric) and
// (int rho s~ S)^T a_w = sum_ab (a_w~)_ba P_ab; the bracket with full coupling only.
void FlexibleBody::inertia_residual(std::span<const double> q, std::span<const double> w,
                                    std::span<const double> wdot, const Vec3& gravity,
                                    std::span<double> rows) const {
  const Mat3 a = rotation_matrix(vec4(q, 3));
  const auto eta = tail(q, 7, n_);
  const auto rate = tail(w, 6, n_);
  const auto acc = tail(wdot, 6, n_);
  const Vec3 omega = vec3(w, 3), a_r = vec3(wdot, 0), a_w = vec3(wdot, 3);
  const bool full = coupling_ == Coupling::kFull;
  const auto& sb = data_.translational;
  Mat3 psi;
  const Eigen::MatrixXd& p = inertia_terms(eta, psi);
  const Mat3 j = psi.trace() * Mat3::Identity() - psi;
  const Vec3 mc = data_.first_moment + sb * eta, ub = sb * rate, ua = sb * acc;
  const Vec3 y = a_r - gravity, yb = a.transpose() * y;
  const Mat3 om = skew(omega), om2 = om * om;

  // P_ab . eta' (G_ab = P_ba . eta') and P_ab . eta'' ((int rho s~ S) eta'', row i = (P_jk - P_kj) . eta'').
  Eigen::Matrix<double, 9, 1> pr, pa;
  pr.noalias() = p.transpose() * rate;
  pa.noalias() = p.transpose() * acc;
  Mat3 g;
  Vec3 rot_acc;
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) g(i, k) = pr[3 * k + i];
    const int jj = (i + 1) % 3, kk = (i + 2) % 3;
    rot_acc[i] = pa[3 * jj + kk] - pa[3 * kk + jj];
  }

  Eigen::Map<Eigen::VectorXd> r(rows.data(), 6 + n_);
  r.head<3>() =
      data_.mass * y + a * (a_w.cross(mc) + ua + omega.cross(omega.cross(mc)) + 2 * omega.cross(ub));
  r.segment<3>(3) =
      mc.cross(yb) + j * a_w + rot_acc + omega.cross(j * omega) + 2 * (g.trace() * omega - g * omega);

  const Mat3 c = om2 + skew(a_w).transpose();
  Eigen::Matrix<double, 9, 1> cv;  // C_ab at 3a+b
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) cv[3 * i + k] = c(i, k);
  auto re = r.tail(n_);
  re.noalias() = sb.transpose() * yb;
  re.noalias() += p * cv;
  re.noalias() += data_.modal_mass * acc;
  re.noalias() += data_.stiffness * eta;
  re.noalias() += data_.damping * rate;
  if (!data_.geometric.empty()) {
    const std::array<double, 6> c = spin_coefficients(omega);
    for (int k = 0; k < 6; ++k)
      if (c[k] != 0.0) re.noalias() += c[k] * (data_.geometric[k] * eta);
  }
  if (full)
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k)
        if (om(i, k) != 0.0) re.noalias() += (2 * om(i, k)) * (data_.quadratic[3 * i + k] * rate);
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

// The rate of marker_motion's velocity (A' = A omega~, s' = Phi eta'):
// a = v' + A (omega' x s + omega x (omega x s) + 2 omega x Phi eta' + Phi eta'').
Vec3 FlexibleBody::marker_acceleration(int marker, std::span<const double> q, std::span<const double> w,
                                       std::span<const double> wdot) const {
  const auto& pt = data_.points[point_of(marker)];
  const Vec3 s = pt.position + pt.translation * tail(q, 7, n_);
  const Vec3 omega = vec3(w, 3), elastic_rate = pt.translation * tail(w, 6, n_);
  const Vec3 relative = vec3(wdot, 3).cross(s) + omega.cross(omega.cross(s)) + 2 * omega.cross(elastic_rate) +
                        pt.translation * tail(wdot, 6, n_);
  return vec3(wdot, 0) + rotation_matrix(vec4(q, 3)) * relative;
}

// [Jv w; Jw w] = marker_motion's velocity and angular velocity (both written as A (...)), without forming Jv,
// Jw.
void FlexibleBody::marker_twist(int marker, std::span<const double> q, std::span<const double> w,
                                Vec3& velocity, Vec3& angular_velocity) const {
  const auto& pt = data_.points[point_of(marker)];
  const Mat3 a = rotation_matrix(vec4(q, 3));
  const auto eta = tail(q, 7, n_);
  const auto eta_rate = tail(w, 6, n_);
  const Vec3 s = pt.position + pt.translation * eta;
  const Vec3 omega = vec3(w, 3);
  velocity = vec3(w, 0) + a * (omega.cross(s) + pt.translation * eta_rate);
  angular_velocity = a * (omega + angular_rate_matrix(pt.rotation * eta) * (pt.rotation * eta_rate));
}

// Jv = [1, -A s~, A Phi_t],  Jw = [0, A, A T(theta) Phi_r].
void FlexibleBody::marker_jacobian(int marker, std::span<const double> q, Eigen::Ref<Mat3X> jv,
                                   Eigen::Ref<Mat3X> jw) const {
  const auto& pt = data_.points[point_of(marker)];
  const Mat3 a = rotation_matrix(vec4(q, 3));
  const auto eta = tail(q, 7, n_);
  const Vec3 s = pt.position + pt.translation * eta;
  jv.leftCols<3>() = Mat3::Identity();
  jv.block<3, 3>(0, 3) = -a * skew(s);
  jv.rightCols(n_).noalias() = a * pt.translation;
  jw.leftCols<3>().setZero();
  jw.block<3, 3>(0, 3) = a;
  const Mat3 ar = a * angular_rate_matrix(pt.rotation * eta);
  jw.rightCols(n_).noalias() = ar * pt.rotation;
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
// (Called by every residual, for the energy balance: no heap allocation, D eta' into the workspace.)
double FlexibleBody::dissipated_power(std::span<const double>, std::span<const double> w) const {
  const auto rate = tail(w, 6, n_);
  ws_n_.noalias() = data_.damping * rate;
  return rate.dot(ws_n_);
}

double FlexibleBody::strain_energy(std::span<const double> q) const {
  const auto eta = tail(q, 7, n_);
  ws_n_.noalias() = data_.stiffness * eta;
  return 0.5 * eta.dot(ws_n_);
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

// ---------------------------------------------------------------- derivatives (analytic Jacobian, body.hpp)
// Notation as above; for a marker on point P: u0, Phi_t, Phi_r (3 x n), s = u0 + Phi_t eta, theta_P =
// Phi_r eta, T = T(theta_P) (angular_rate_matrix), D(theta, z) = d(T(theta) z)/dtheta (rate_derivative).
// Theta = d(theta)/dp (rotation_sensitivity): a vector x = A x0 fixed in the body changes by dx = -x~ Theta
// dp, and d(A^T y)/dp = A^T y~ Theta for a fixed global y.

// Q += Jv^T F + Jw^T T with Jv = [1, -A s~, A Phi_t], Jw = [0, A, A T Phi_r] (marker_jacobian):
//   Q = [F;  s x (A^T F) + A^T T;  Phi_t^T A^T F + Phi_r^T T^T A^T T]   (Shabana 2005, eq. 5.127-5.130).
void FlexibleBody::add_wrench(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                              std::span<double> generalized) const {
  const auto& pt = data_.points[point_of(marker)];
  const Mat3 at = rotation_matrix(vec4(q, 3)).transpose();
  const auto eta = tail(q, 7, n_);
  const Vec3 s = pt.position + pt.translation * eta;
  const Vec3 fb = at * force, tb = at * torque;
  const Vec3 tr = angular_rate_matrix(pt.rotation * eta).transpose() * tb;
  Eigen::Map<Eigen::VectorXd> g(generalized.data(), 6 + n_);
  g.head<3>() += force;
  g.segment<3>(3) += s.cross(fb) + tb;
  g.tail(n_).noalias() += pt.translation.transpose() * fb;
  g.tail(n_).noalias() += pt.rotation.transpose() * tr;
}

// The marker's motion (marker_motion): p_P = r + A s, axes A exp(theta_P~) axes0,
// v_P = v + A b with b = omega x s + Phi_t eta', omega_P = A c with c = omega + T Phi_r eta'. By q = [r, p,
// eta]:
//   dp_P     = [1,  -(A s)~ Theta,  A Phi_t]
//   dtheta_m = [0,   Theta,         A T Phi_r]          (d exp(theta~) = (T dtheta)~ exp(theta~))
//   dv_P     = [0,  -(A b)~ Theta,  A omega~ Phi_t]
//   domega_P = [0,  -(A c)~ Theta,  A D(theta_P, Phi_r eta') Phi_r]
void FlexibleBody::marker_sensitivity(int marker, std::span<const double> q, std::span<const double> w,
                                      Eigen::Ref<Eigen::MatrixXd> out) const {
  const auto& pt = data_.points[point_of(marker)];
  const Vec4 p = vec4(q, 3);
  const Mat3 a = rotation_matrix(p);
  const Mat34 theta = rotation_sensitivity(p);
  const auto eta = tail(q, 7, n_);
  const auto rate = tail(w, 6, n_);
  const Vec3 omega = vec3(w, 3);
  const Vec3 s = pt.position + pt.translation * eta;
  const Vec3 th = pt.rotation * eta, z = pt.rotation * rate;
  const Mat3 t = angular_rate_matrix(th);
  const Vec3 b = omega.cross(s) + pt.translation * rate;
  const Vec3 c = omega + t * z;
  out.setZero();
  out.block<3, 3>(0, 0) = Mat3::Identity();
  out.block<3, 4>(0, 3) = -skew(a * s) * theta;
  out.block(0, 7, 3, n_).noalias() = a * pt.translation;
  out.block<3, 4>(3, 3) = theta;
  const Mat3 at_ = a * t;
  out.block(3, 7, 3, n_).noalias() = at_ * pt.rotation;
  out.block<3, 4>(6, 3) = -skew(a * b) * theta;
  const Mat3 aom = a * skew(omega);
  out.block(6, 7, 3, n_).noalias() = aom * pt.translation;
  out.block<3, 4>(9, 3) = -skew(a * c) * theta;
  const Mat3 ad = a * rate_derivative(th, z);
  out.block(9, 7, 3, n_).noalias() = ad * pt.rotation;
}

// d/dq of Q above at fixed F, T (fb = A^T F, tb = A^T T):
//   rows omega: d/dp = s~ A^T F~ Theta + A^T T~ Theta,   d/deta = -fb~ Phi_t
//   rows eta:   d/dp = Phi_t^T A^T F~ Theta + Phi_r^T T^T A^T T~ Theta,
//               d/deta = Phi_r^T (-D(-theta_P, tb)) Phi_r          (d(T^T tb)/dtheta, rate_derivative)
void FlexibleBody::add_wrench_derivative(int marker, std::span<const double> q, const Vec3& force,
                                         const Vec3& torque, Eigen::Ref<Eigen::MatrixXd> out) const {
  const auto& pt = data_.points[point_of(marker)];
  const Vec4 p = vec4(q, 3);
  const Mat3 at = rotation_matrix(p).transpose();
  const Mat34 theta = rotation_sensitivity(p);
  const auto eta = tail(q, 7, n_);
  const Vec3 s = pt.position + pt.translation * eta;
  const Vec3 th = pt.rotation * eta;
  const Mat3 t = angular_rate_matrix(th);
  const Vec3 fb = at * force, tb = at * torque;
  const Mat34 fp = at * skew(force) * theta, tp = at * skew(torque) * theta;
  out.block<3, 4>(3, 3) += skew(s) * fp + tp;
  const Mat3 fbx = skew(fb);
  out.block(3, 7, 3, n_).noalias() -= fbx * pt.translation;
  const Mat34 ttp = t.transpose() * tp;
  out.block(6, 3, n_, 4).noalias() += pt.translation.transpose() * fp;
  out.block(6, 3, n_, 4).noalias() += pt.rotation.transpose() * ttp;
  const Mat3 e = -rate_derivative(-th, tb);
  ws_3n_.noalias() = e * pt.rotation;
  out.block(6, 7, n_, n_).noalias() += pt.rotation.transpose() * ws_3n_;
}

// Rows r' - v, p' - 1/2 L(p)^T omega + beta (p.p - 1) p, eta' - eta_rate (as RigidBody::kinematic_jacobian).
void FlexibleBody::kinematic_jacobian(std::span<const double> q, std::span<const double> w_eff,
                                      Eigen::Ref<Eigen::MatrixXd> d_q,
                                      Eigen::Ref<Eigen::MatrixXd> d_w) const {
  floating_frame_kinematic_jacobian(vec4(q, 3), vec3(w_eff, 3), kNormalizationRate, d_q, d_w);
  d_w.block(7, 6, n_, n_).diagonal().setConstant(-1.0);
}

// The inertial rows R = M(eta) w' + h(eta, w) - Q_g + [0; 0; K eta + D eta'] (top of this file), with
// w' = [a_r, a_w, eta''], mc = m c + S_bar eta, y = a_r - g and, written out by blocks,
//   R_r   = m (a_r - g) + A (a_w x mc + S_bar eta'' + omega x (omega x mc) + 2 omega x S_bar eta')
//   R_om  = mc x (A^T y) + J a_w + (int rho s~ S) eta'' + omega x J omega + 2 (tr(G) omega - G omega)
//   R_eta = S_bar^T A^T y + (int rho s~ S)^T a_w + M_r eta'' + h_eta + K eta + D eta'
// (Shabana 2005, eq. 5.115-5.125). The eta-dependence enters through mc, Psi and P:
//   dPsi_kl/deta = I_tilde_kl + I_tilde_lk + (S_kl + S_lk) eta,   dP_ab/deta = S_ab^T = S_ba,
//   d(P_ab . x)/deta = (S_ab x)^T,   (int rho s~ S)^T a_w = sum_ab (a_w~)_ba P_ab,
// the terms in S_kl only with full coupling. Derivatives:
//   dR_r/dp    = -(A x_r)~ Theta  (x_r = the bracket),      dR_r/deta = A (a_w~ + omega~^2) S_bar
//   dR_om/dp   = mc~ A^T y~ Theta,   dR_om/deta = -(A^T y)~ S_bar + dJ(a_w) + omega~ dJ(omega)
//                + d((int rho s~ S) eta'')/deta + 2 d(tr(G) omega - G omega)/deta,
//                dJ(u)_i = u_i sum_k dPsi_kk - sum_l u_l dPsi_il,  dG_ab/deta = (S_ba eta')^T
//   dR_eta/dp  = S_bar^T A^T y~ Theta,   dR_eta/deta = K + sum_ab (omega~^2 + a_w~)_ab S_ab
//   dR_r/domega  = A ((omega.mc) 1 + omega mc^T - 2 mc omega^T - 2 (S_bar eta')~),  dR_r/deta' = 2 A omega~
//   S_bar dR_om/domega = omega~ J - (J omega)~ + 2 (tr(G) 1 - G),   dR_om/deta'_i-row = 2 (omega_i sum_k P_kk
//   - sum_b
//                  omega_b P_bi)^T
//   dR_eta/domega_c = sum_b omega_b P_bc + sum_a omega_a P_ca - 2 omega_c sum_a P_aa + 2 (S_kj - S_jk) eta'
//                  ((c, j, k) cyclic; the last term with full coupling),
//   dR_eta/deta' = D + 2 sum_ab omega~_ab S_ab (full coupling).
void FlexibleBody::inertia_jacobian(std::span<const double> q, std::span<const double> w,
                                    std::span<const double> wdot, const Vec3& gravity,
                                    Eigen::Ref<Eigen::MatrixXd> d_q, Eigen::Ref<Eigen::MatrixXd> d_w) const {
  const Vec4 p = vec4(q, 3);
  const Mat3 a = rotation_matrix(p);
  const Mat34 theta = rotation_sensitivity(p);
  const auto eta = tail(q, 7, n_);
  const auto rate = tail(w, 6, n_);
  const auto acc = tail(wdot, 6, n_);
  const Vec3 omega = vec3(w, 3), a_r = vec3(wdot, 0), a_w = vec3(wdot, 3);
  const bool full = coupling_ == Coupling::kFull;
  const auto& sb = data_.translational;
  const Vec3 mc = data_.first_moment + sb * eta;
  const Vec3 ub = sb * rate, ua = sb * acc;
  const Mat3 om = skew(omega), om2 = om * om;

  // Psi and P_ab(eta) (with full coupling also S_ab eta: inertia_terms), S_ab eta', S_ab eta'', dPsi_kl/deta.
  Mat3 psi;
  const Eigen::MatrixXd& pab = inertia_terms(eta, psi);
  if (full)
    for (int c = 0; c < 9; ++c) {
      ws_s_rate_.col(c).noalias() = data_.quadratic[c] * rate;
      ws_s_acc_.col(c).noalias() = data_.quadratic[c] * acc;
    }
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) {
      const int kl = 3 * k + l, lk = 3 * l + k;
      ws_dpsi_.col(kl) = position_cols_.col(kl) + position_cols_.col(lk);
      if (full) ws_dpsi_.col(kl) += ws_s_eta_.col(kl) + ws_s_eta_.col(lk);
    }
  const Mat3 j = psi.trace() * Mat3::Identity() - psi;
  Mat3 g;  // G_ab = P_ba . eta'
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) g(i, k) = pab.col(3 * k + i).dot(rate);

  d_q.setZero();
  d_w.setZero();
  const Vec3 y = a_r - gravity, yb = a.transpose() * y;
  const Mat34 yp = a.transpose() * skew(y) * theta;  // d(A^T y)/dp

  // rows r
  const Vec3 xr = a_w.cross(mc) + ua + om2 * mc + 2 * omega.cross(ub);
  d_q.block<3, 4>(0, 3) = -skew(a * xr) * theta;
  const Mat3 a_aw = a * (skew(a_w) + om2);
  d_q.block(0, 7, 3, n_).noalias() = a_aw * sb;
  d_w.block<3, 3>(0, 3) = a * (omega.dot(mc) * Mat3::Identity() + omega * mc.transpose() -
                               2 * mc * omega.transpose() - 2 * skew(ub));
  const Mat3 a_om2 = 2 * a * om;
  d_w.block(0, 6, 3, n_).noalias() = a_om2 * sb;

  // rows omega
  d_q.block<3, 4>(3, 3) = skew(mc) * yp;
  {
    // dJ(a_w) + omega~ dJ(omega) = wj dPsi^T (3 x 9 coefficients of the columns dPsi_kl)
    Eigen::Matrix<double, 3, 9> wj = Eigen::Matrix<double, 3, 9>::Zero();
    const Vec3 omo = om * omega;  // zero, kept for the form
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) {
        wj(i, 4 * k) += a_w[i] + omo[i];
        wj(i, 3 * i + k) -= a_w[k];
        for (int l = 0; l < 3; ++l) wj(i, 3 * k + l) -= om(i, k) * omega[l];
      }
    const Mat3 ybx = -skew(yb);
    ws_3n_.noalias() = ybx * sb;
    ws_3n_.noalias() += wj * ws_dpsi_.transpose();
    if (full) {
      // d((int rho s~ S) eta'')/deta: row i = (S_jk - S_kj) eta'' ((i, j, k) cyclic);
      // 2 d(tr(G) omega - G omega)/deta: row i = 2 (omega_i sum_k S_kk eta' - sum_b omega_b S_bi eta')
      Eigen::Matrix<double, 3, 9> wa = Eigen::Matrix<double, 3, 9>::Zero(), wr = wa;
      for (int i = 0; i < 3; ++i) {
        const int jj = (i + 1) % 3, kk = (i + 2) % 3;
        wa(i, 3 * jj + kk) += 1;
        wa(i, 3 * kk + jj) -= 1;
        for (int k = 0; k < 3; ++k) {
          wr(i, 4 * k) += 2 * omega[i];
          wr(i, 3 * k + i) -= 2 * omega[k];
        }
      }
      ws_3n_.noalias() += wa * ws_s_acc_.transpose();
      ws_3n_.noalias() += wr * ws_s_rate_.transpose();
    }
    d_q.block(3, 7, 3, n_) = ws_3n_;
    // d/deta': row i = 2 (omega_i sum_k P_kk - sum_b omega_b P_bi)^T
    Eigen::Matrix<double, 3, 9> wp = Eigen::Matrix<double, 3, 9>::Zero();
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) {
        wp(i, 4 * k) += 2 * omega[i];
        wp(i, 3 * k + i) -= 2 * omega[k];
      }
    d_w.block(3, 6, 3, n_).noalias() = wp * pab.transpose();
  }
  d_w.block<3, 3>(3, 3) = om * j - skew(j * omega) + 2 * (g.trace() * Mat3::Identity() - g);

  // rows eta
  d_q.block(6, 3, n_, 4).noalias() = sb.transpose() * yp;
  d_q.block(6, 7, n_, n_) = data_.stiffness;
  d_w.block(6, 6, n_, n_) = data_.damping;
  if (!data_.geometric.empty()) {
    // K(omega) eta: d/deta = K_G(omega) - K_G(omega_ref); d/domega_c = sum_p d(omega_a omega_b)/domega_c K_p
    // eta.
    const std::array<double, 6> c = spin_coefficients(omega);
    for (int k = 0; k < 6; ++k) {
      if (c[k] != 0.0) d_q.block(6, 7, n_, n_) += c[k] * data_.geometric[k];
      ws_geo_.col(k).noalias() = data_.geometric[k] * eta;
    }
  }
  if (full) {
    const Mat3 ce = om2 + skew(a_w);
    for (int c = 0; c < 9; ++c) {
      d_q.block(6, 7, n_, n_) += ce(c / 3, c % 3) * data_.quadratic[c];
      if (om(c / 3, c % 3) != 0.0) d_w.block(6, 6, n_, n_) += 2 * om(c / 3, c % 3) * data_.quadratic[c];
    }
  }
  {
    // d/domega, column c: sum_b omega_b P_bc + sum_a omega_a P_ca - 2 omega_c sum_a P_aa (+ full: 2 (S_kj -
    // S_jk) eta')
    Eigen::Matrix<double, 9, 3> xw = Eigen::Matrix<double, 9, 3>::Zero();
    for (int c = 0; c < 3; ++c)
      for (int b = 0; b < 3; ++b) {
        xw(3 * b + c, c) += omega[b];
        xw(3 * c + b, c) += omega[b];
        xw(4 * b, c) -= 2 * omega[c];
      }
    d_w.block(6, 3, n_, 3).noalias() = pab * xw;
    if (full) {
      Eigen::Matrix<double, 9, 3> xs = Eigen::Matrix<double, 9, 3>::Zero();
      for (int c = 0; c < 3; ++c) {
        const int jj = (c + 1) % 3, kk = (c + 2) % 3;
        xs(3 * kk + jj, c) += 2;
        xs(3 * jj + kk, c) -= 2;
      }
      d_w.block(6, 3, n_, 3).noalias() += ws_s_rate_ * xs;
    }
    if (!data_.geometric.empty()) {
      for (int k = 0; k < 6; ++k) {
        const int a = kSpinProducts[k][0], b = kSpinProducts[k][1];
        d_w.block(6, 3 + a, n_, 1) += omega[b] * ws_geo_.col(k);
        d_w.block(6, 3 + b, n_, 1) += omega[a] * ws_geo_.col(k);
      }
    }
  }
}

// ---------------------------------------------------------------- the scene's [[body]] table
std::unique_ptr<Body> make_flexible_body(const input::Table& t, const std::string& name,
                                         const InitialState& init, const std::filesystem::path& base,
                                         std::vector<std::filesystem::path>& inputs) {
  const std::filesystem::path file = base / t.string("superelement");
  inputs.push_back(file);
  const int modes =
      static_cast<int>(t.optional_integer("modes", input::Range::closed(1, 100000)).value_or(0));
  std::vector<int> numbers;  // `mode_numbers`: exactly these coordinates (Adams/Flex' enabled modes)
  if (t.has("mode_numbers")) {
    if (t.has("modes")) t.fail("mode_numbers", "give either `modes` (the lowest N) or `mode_numbers`, not both");
    for (const std::int64_t k : t.integers("mode_numbers", input::Range::closed(1, 100000)))
      numbers.push_back(static_cast<int>(k));
    if (numbers.empty()) t.fail("mode_numbers", "expected at least one mode number (1-based)");
  }
  const Coupling coupling = t.optional_choice("coupling", {"full", "linear"}).value_or("full") == "full"
                                ? Coupling::kFull
                                : Coupling::kLinear;
  FlexibleData data;
  try {
    data = load_flexible_data(file, modes, numbers);
  } catch (const Error& e) {
    const std::string what = e.what();
    const bool too_many = modes > 0 && what.find("modes asked for") != std::string::npos;
    const bool bad_number = what.find("mode number") != std::string::npos;
    t.fail(too_many ? "modes" : bad_number ? "mode_numbers" : "superelement",
           "cannot use superelement '" + file.string() + "': " + what);
  }
  // The centrifugal geometric stiffness: on when the file carries it, unless switched off.
  if (const auto stiffening = t.optional_boolean("geometric_stiffening")) {
    if (*stiffening && data.geometric.empty()) {
      t.fail("geometric_stiffening", "the superelement '" + file.string() +
                                         "' has no /reduced/geometric_stiffness: condense the component with "
                                         "[reduction] geometric_stiffening = true");
    }
    if (!*stiffening) data.geometric.clear();  // the stiffness stays that of the file's reference spin
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
  if (!t.has("axis")) {
    if (t.has("speed")) t.fail("speed", "only a flexible body on a fixed axis (`axis`) takes an initial `speed`");
    return std::make_unique<FlexibleBody>(name, std::move(data), coupling, init, eta0, eta_rate0,
                                          std::move(user_points));
  }
  // On a fixed axis through the frame's origin (flexible_rotor_body.hpp): one coordinate for the frame.
  for (const char* key : {"velocity", "angular_velocity"})
    if (t.has(key))
      t.fail(key,
             "a flexible body on a fixed axis turns about it only: give its initial rate as `speed` (rad/s "
             "about the axis, right-handed)");
  const auto a = t.vec3("axis", input::Range::magnitude(bounds::kLength));
  const Vec3 axis(a[0], a[1], a[2]);
  if (axis.norm() < 1e-12) t.fail("axis", "the axis must not be zero");
  const double speed = t.number_or("speed", 0.0, input::Range::magnitude(bounds::kAngularSpeed));
  if (const std::string problem = fixed_axis_basis_problem(data, file.string()); !problem.empty())
    t.fail("superelement", "cannot turn on a fixed axis: " + problem);
  InitialState at_rest = init;
  at_rest.velocity.setZero();
  at_rest.angular_velocity.setZero();
  return std::make_unique<FlexibleRotorBody>(
      FlexibleBody(name, std::move(data), coupling, at_rest, eta0, eta_rate0, std::move(user_points)), axis,
      speed);
}

}  // namespace nvh::solve
