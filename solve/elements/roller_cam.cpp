// A roller follower on a cam: the roller's centre (marker i, on the follower) against the cam's pitch curve
// (marker j, on the camshaft: origin on the cam's axis, z_j the axis, x_j the zero of the lift's cam angle;
// solve/cam/cam_profile.hpp). Works for any follower kinematics - a translating lifter, a pivoting roller
// lever - because the contact is found on the profile at every evaluation, not assumed on a line.
//
// Geometry (cam frame, c = A_j^T (p_i - p_j) projected on the x-y plane): the foot P(psi*) of c on the pitch
// curve (Newton on (P(psi) - c) . P'(psi) = 0 from psi = atan2(c_y, c_x)), the outward normal n there, the
// signed gap g = n . (c - P) (> 0: roller lifted off the cam), the approach delta = -g. The pitch curve is
// the cam surface offset by the roller radius, so g is the gap between roller and cam surface. Normal force
// (Hertz line contact of the roller, width L, on the cam, solve/elements/hertz_line.hpp):
//   fn = F(delta) (1 + alpha delta'),  F = Palmgren's law scaled by E* (or a linear `stiffness` k delta),
//   alpha = 3 (1 - e) / (2 v_ref)  (Hunt & Crossley, J. Appl. Mech. 42, 1975, eq. 5), never pulling,
// acting on the roller along n through its centre and on the cam at the contact point p_i - Rr n: the force
// passes through the roller's centre, so the follower gets no torque from it (the roller turns freely, unless
// its friction below is switched on), and the cam's reaction gives the camshaft's drive torque. Channels:
// normal force, Hertz pressure p0 = sqrt(fn E* / (pi L R)) with 1/R = 1/Rr + 1/R_cam (the cam surface's
// radius of curvature at the contact, concave negative), its half-width, the cam angle of the contact point,
// the gap, a separation flag, the torque on the cam about z_j.
//
// Jacobian (force_element.hpp's columns): with r = p_i - p_j, dc = dr + r~ dtheta_j (the relative position as
// the cam sees it, in global axes), the distance field's gradient n and Hessian H = t t^T / (R_p + g) (R_p
// the pitch curve's radius of curvature at the foot, t its tangent):
//   d delta = -n^T dc,   dn = H dc - n~ dtheta_j,
//   delta' = -n . vr,  vr = v_i - v_j - omega_j x r,  dvr = dv_i - dv_j + r~ domega_j - omega_j~ dr,
//   d delta' = -vr^T dn - n^T dvr,   dfn = F' (1 + alpha delta') d delta + F alpha d delta',   dF = n dfn +
//   fn dn.
//
// Crowned roller (`crown_radius` Rc > 0): an elliptical point contact (solve/elements/hertz_point.hpp:
// Hertz's exact solution, Johnson 1985 section 4.2, eqs. 4.39-4.41, the ellipse's shape interpolated in the
// radius ratio from exact nodes) of the radii Rx (rolling plane, 1/Rx = 1/Rr + 1/R_cam) and Ry = Rc (the
// roller's axial plane; the cam is straight across): F = K(Rx) delta^1.5. K follows the cam's curvature at
// the foot: dK = K'(Rx) (Rx / R_cam)^2 R_p'(psi*) dpsi, the foot moving by dpsi = R_p / (R_p + g) t^T dc /
// |P'| (the foot condition's implicit derivative). The stored energy is K delta^2.5 / 2.5; its change with K
// (dK/dt delta^2.5 / 2.5, zero on circular arcs) is booked against the dissipated power so that the balance
// closes.
//
// Roller friction (t the tangent, z = n x t = z_j, the contact point x = p_i - Rr n; the cam surface speed
// relative to the roller's centre along t: s = t . (v_cam(x) - v_i) = -t . vr - Rr z . omega_j):
// - the roller's resistance moment M = c fn, c = mu_pin r_pin + f_r (a needle or plain pin's friction torque
//   mu_pin F r_pin: the simple bearing friction torque M = mu F d / 2 of A. Palmgren, Ball and Roller Bearing
//   Engineering, 3rd ed. 1959, with F ~ fn; plus a rolling-resistance arm f_r, the offset ahead of the centre
//   of the pressure's resultant, Johnson 1985 section 8.1: M = f_r fn),
//   opposing the roller's spin relative to the follower;
// - pure rolling (no `roller_inertia`): the spin is kinematic, Omega = -s / Rr; the roller (massless) needs
// the
//   traction ft = (M / Rr) tanh(v / v_eps) along t, v = s + Rr z . omega_i the rolling speed (the cam surface
//   against the follower's material point at x); F = fn n + ft t acts on the follower at x (the pin's moment
//   is the traction's about the centre); dissipated ft v;
// - slip (`roller_inertia` J > 0): the absolute spin Omega about z is a state, J Omega' = -Rr ft - M tanh(Rr
// w /
//   v_eps), w = Omega - z . omega_i the spin relative to the follower; the slip speed v = s + Rr Omega (the
//   cam's surface speed minus the roller's), ft = mu(v) fn (contact_law.hpp's regularized Coulomb with
//   Stribeck); the follower gets F at its centre and the pin's moment +M z, the cam -F at x; stored J Omega^2
//   / 2, dissipated ft v + M w.
// Jacobian of the friction: dt = -n t^T dc / (R_p + g) - t~ dtheta_j, dz = -z~ dtheta_j,
//   ds = -vr^T dt - t^T dvr - Rr (omega_j^T dz + z^T domega_j); pure rolling: dv = ds + Rr (omega_i^T dz +
//   z^T domega_i), dft = (c / Rr) (th dfn + fn (1 - th^2) dv / v_eps); slip: dv = ds + Rr dOmega, dw = dOmega
//   - omega_i^T dz - z^T domega_i, dft = mu' fn dv + mu dfn; dF = n dfn + fn dn + t dft + ft dt; the
//   follower's torque tau z (pure rolling tau = -Rr ft, slip tau = M): dT = z dtau + tau dz; the cam's torque
//   about p_j is
//   -(x - p_j) x F = jacobian_at_i's -T - r x F plus (Rr ft + tau) z.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "solve/cam/cam_profile.hpp"
#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"
#include "solve/elements/cam_contact_keys.hpp"
#include "solve/elements/contact_law.hpp"
#include "solve/elements/hertz_line.hpp"
#include "solve/elements/hertz_point.hpp"

namespace nvh::solve {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

struct Parameters {
  double width = 0;          // m, the roller's contact length
  double e_star = 0;         // Pa
  double stiffness = 0;      // N/m; > 0: a linear law instead of Palmgren's
  double restitution = 1.0;  // at the reference speed
  double reference_speed = 1.0;
  double crown_radius = 0;    // m; > 0: a crowned roller, elliptical point contact (hertz_point.hpp)
  double resistance_arm = 0;  // m: the roller's resistance moment M = resistance_arm fn (mu_pin r_pin + f_r)
  double roller_inertia = 0;  // kg m^2; > 0: the roller's spin is a state and the roller can slip
  contact::Parameters traction;  // the slip's friction; its regularization_speed also smooths M's sign
};

/// The roller against the pitch curve at one state.
struct Contact {
  Vec3 r;                   // p_i - p_j (m)
  Vec3 n;                   // outward normal of the pitch curve at the foot, global
  Vec3 t;                   // its tangent (d/dpsi direction), global unit
  Vec3 z;                   // n x t = z_j
  double gap = 0;           // m
  double rate = 0;          // delta' (m/s), > 0 closing
  Vec3 vr;                  // v_i - v_j - omega_j x r
  double psi = 0;           // the foot's polar angle in the cam frame (rad)
  double pitch_radius = 0;  // signed radius of curvature of the pitch curve at the foot (m)
  double pitch_radius_rate = 0;  // its derivative by psi (m/rad)
  double speed = 0;              // |P'(psi)| (m/rad)
  double surface = 0;            // s: the cam surface's speed relative to the roller's centre along t (m/s)
};

/// The roller's friction at one state (the header's symbols).
struct Friction {
  double ft = 0;      // traction on the roller along t (N)
  double v = 0;       // pure rolling: the rolling speed; slip: the slip speed (m/s)
  double w = 0;       // slip: the spin relative to the follower (rad/s)
  double moment = 0;  // slip: the pin's moment M tanh(Rr w / v_eps) on the follower about z (N m)
  double tau = 0;     // the follower's torque about z beyond the force at its centre (N m)
  double spin = 0;    // the roller's absolute spin about z (rad/s)
  double power = 0;   // dissipated (W)
};

class RollerCam final : public ForceElement {
 public:
  RollerCam(std::unique_ptr<cam::CamProfile> profile, Parameters p)
      : profile_(std::move(profile)),
        p_(p),
        law_(p.width, p.e_star),
        traction_(p.traction),
        rr_(profile_->roller_radius()) {
    if (crowned()) point_law_.emplace(p_.e_star);
  }
  std::string type() const override { return "roller-cam"; }
  int marker_count() const override { return 2; }
  bool crowned() const { return p_.crown_radius > 0; }
  bool slips() const { return p_.roller_inertia > 0; }
  bool has_friction() const { return slips() || p_.resistance_arm > 0; }
  void set_initial_spin(double spin) { initial_spin_ = spin; }
  double roller_radius() const { return rr_; }

  std::vector<StateDefinition> states() const override {
    if (!slips()) return {};
    return {{"roller_speed", "rad/s", true, initial_spin_}};
  }

  Contact contact(const ElementInput& in) const {
    const MarkerMotion& mi = in.markers[0];
    const MarkerMotion& mj = in.markers[1];
    Contact k;
    k.r = mi.position - mj.position;
    const Vec3 c = mj.axes.transpose() * k.r;
    const cam::PitchFoot foot = cam::pitch_foot(*profile_, c.x(), c.y());
    const cam::PitchPoint& pp = foot.point;
    k.psi = foot.psi;
    k.pitch_radius = pp.radius_of_curvature;
    k.pitch_radius_rate = pp.radius_derivative;
    const Vec3 n_cam(pp.nx, pp.ny, 0.0);
    const double tl = std::hypot(pp.dx, pp.dy);
    k.speed = tl;
    k.n = mj.axes * n_cam;
    k.t = mj.axes * Vec3(pp.dx / tl, pp.dy / tl, 0.0);
    k.z = mj.axes.col(2);
    k.gap = foot.gap;
    k.vr = mi.velocity - mj.velocity - mj.angular_velocity.cross(k.r);
    k.rate = -k.n.dot(k.vr);
    k.surface = -k.t.dot(k.vr) - rr_ * k.z.dot(mj.angular_velocity);
    return k;
  }

  /// The relative radius in the rolling plane, 1/Rx = 1/Rr + 1/R_cam (m).
  double rolling_radius(const Contact& k) const { return hertz::relative_radius(rr_, k.pitch_radius - rr_); }
  /// K of the crowned law (N/m^1.5) and dK/dpsi.
  double point_k(const Contact& k) const { return point_law_->stiffness(rolling_radius(k), p_.crown_radius); }
  double point_k_rate(const Contact& k) const {
    const double r_cam = k.pitch_radius - rr_;
    if (!std::isfinite(r_cam) || !std::isfinite(k.pitch_radius_rate)) return 0.0;  // a flank: Rx = Rr
    const double rx = rolling_radius(k);
    return point_law_->stiffness_derivative(rx, p_.crown_radius) * (rx * rx) / (r_cam * r_cam) *
           k.pitch_radius_rate;
  }
  /// dpsi = foot_factor t^T dc: the foot's motion along the pitch curve.
  static double foot_factor(const Contact& k) {
    if (!std::isfinite(k.pitch_radius)) return 1.0 / k.speed;
    const double denom = k.pitch_radius + k.gap;
    return std::abs(denom) > 1e-12 ? k.pitch_radius / (denom * k.speed) : 0.0;
  }

  double elastic(const Contact& k) const {
    const double delta = -k.gap;
    if (delta <= 0) return 0.0;
    if (p_.stiffness > 0) return p_.stiffness * delta;
    return crowned() ? point_k(k) * std::pow(delta, 1.5) : law_.force(delta);
  }
  double elastic_stiffness(const Contact& k) const {
    const double delta = -k.gap;
    if (delta <= 0) return 0.0;
    if (p_.stiffness > 0) return p_.stiffness;
    return crowned() ? 1.5 * point_k(k) * std::sqrt(delta) : law_.stiffness(delta);
  }
  double exponent() const {
    return p_.stiffness > 0 ? 1.0 : crowned() ? 1.5 : hertz::PalmgrenLine::kExponent;
  }
  double alpha() const { return 3.0 * (1.0 - p_.restitution) / (2.0 * p_.reference_speed); }
  double normal_force(const Contact& k) const {
    const double delta = -k.gap;
    if (delta <= 0) return 0.0;
    return std::max(0.0, elastic(k) * (1.0 + alpha() * k.rate));
  }

  Friction friction(const ElementInput& in, const Contact& k, double fn) const {
    Friction f;
    const double eps = p_.traction.regularization_speed;
    const double omega_i = k.z.dot(in.markers[0].angular_velocity);
    if (slips()) {
      f.spin = in.z[0];
      f.v = k.surface + rr_ * f.spin;
      f.w = f.spin - omega_i;
      if (fn > 0) {
        f.ft = traction_.mu(f.v) * fn;
        f.moment = p_.resistance_arm * fn * std::tanh(rr_ * f.w / eps);
      }
      f.tau = f.moment;
      f.power = f.ft * f.v + f.moment * f.w;
    } else {
      f.spin = -k.surface / rr_;  // pure rolling
      f.v = k.surface + rr_ * omega_i;
      if (fn > 0) f.ft = p_.resistance_arm / rr_ * fn * std::tanh(f.v / eps);
      f.tau = -rr_ * f.ft;
      f.power = f.ft * f.v;
    }
    return f;
  }

  void evaluate(const ElementInput& in, ElementOutput& out) const override {
    const Contact k = contact(in);
    const double fn = normal_force(k);
    const Friction f = friction(in, k, fn);
    if (slips()) out.state_residual[0] = p_.roller_inertia * in.zp[0] + rr_ * f.ft + f.moment;
    if (fn <= 0) return;
    const Vec3 force = fn * k.n + f.ft * k.t;
    apply_at_i(in, out, force, f.tau * k.z, in.markers[0].position);
    // The cam gets -F at the contact point only (the pin's moment stays between roller and follower).
    if (slips()) out.wrenches[1].torque += (rr_ * f.ft + f.tau) * k.z;
  }

  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override {
    const Contact k = contact(in);
    const double delta = -k.gap, fn = normal_force(k);
    const int state_row = 12, state_col = 24;
    if (slips()) jac.matrix(state_row, state_col) += jac.cj * p_.roller_inertia;
    if (fn <= 0) return true;  // no force around here
    constexpr int kCols = 25;  // the two markers' 24, then the roller's spin (used only when it is a state)
    using Rows = Eigen::Matrix<double, 3, kCols>;
    using Row = Eigen::Matrix<double, 1, kCols>;
    const MarkerMotion& mi = in.markers[0];
    const MarkerMotion& mj = in.markers[1];
    const Mat3 eye = Mat3::Identity(), rx = skew(k.r), wx = skew(mj.angular_velocity);
    Rows dc = Rows::Zero(), dvr = Rows::Zero(), dn = Rows::Zero(), dt = Rows::Zero(), dz = Rows::Zero();
    dc.block<3, 3>(0, 0) = eye;
    dc.block<3, 3>(0, 12) = -eye;
    dc.block<3, 3>(0, 15) = rx;
    // The distance field's Hessian; on a flank (R_p = inf) the normal does not turn with the foot.
    const double denom = k.pitch_radius + k.gap;
    const double turn = std::isfinite(denom) && std::abs(denom) > 1e-12 ? 1.0 / denom : 0.0;
    const Row tdc = k.t.transpose() * dc;
    dn = turn * k.t * tdc;
    dn.block<3, 3>(0, 15) -= skew(k.n);
    dt = -turn * k.n * tdc;
    dt.block<3, 3>(0, 15) -= skew(k.t);
    dz.block<3, 3>(0, 15) = -skew(k.z);
    dvr.block<3, 3>(0, 6) = eye;
    dvr.block<3, 3>(0, 18) = -eye;
    dvr.block<3, 3>(0, 21) = rx;
    dvr.block<3, 3>(0, 0) -= wx;
    dvr.block<3, 3>(0, 12) += wx;
    const Row ddelta = -k.n.transpose() * dc;
    const Row drate = -k.vr.transpose() * dn - k.n.transpose() * dvr;
    const double fe = elastic(k), a = alpha();
    Row dfn = elastic_stiffness(k) * (1.0 + a * k.rate) * ddelta + fe * a * drate;
    if (crowned() && p_.stiffness <= 0)
      dfn += point_k_rate(k) * std::pow(delta, 1.5) * (1.0 + a * k.rate) * foot_factor(k) * tdc;
    const Friction f = friction(in, k, fn);
    Row dft = Row::Zero(), dtau = Row::Zero();
    if (has_friction()) {
      const double eps = p_.traction.regularization_speed;
      Row ds = -k.vr.transpose() * dt - k.t.transpose() * dvr - rr_ * mj.angular_velocity.transpose() * dz;
      ds.segment<3>(21) -= rr_ * k.z.transpose();
      if (slips()) {
        Row dv = ds, dw = -mi.angular_velocity.transpose() * dz;
        dv[state_col] += rr_;
        dw[state_col] += 1.0;
        dw.segment<3>(9) -= k.z.transpose();
        dft = traction_.mu_derivative(f.v) * fn * dv + traction_.mu(f.v) * dfn;
        const double th = std::tanh(rr_ * f.w / eps);
        dtau = p_.resistance_arm * (th * dfn + fn * (1 - th * th) * rr_ / eps * dw);
      } else {
        Row dv = ds + rr_ * mi.angular_velocity.transpose() * dz;
        dv.segment<3>(9) += rr_ * k.z.transpose();
        const double th = std::tanh(f.v / eps);
        dft = p_.resistance_arm / rr_ * (th * dfn + fn * (1 - th * th) / eps * dv);
        dtau = -rr_ * dft;
      }
    }
    ElementRows dforce = zero_rows(jac), dtorque = zero_rows(jac);
    const int cols = slips() ? kCols : 24;
    dforce.leftCols(cols) = (k.n * dfn + fn * dn + k.t * dft + f.ft * dt).leftCols(cols);
    dtorque.leftCols(cols) = (k.z * dtau + f.tau * dz).leftCols(cols);
    jacobian_at_i(in, jac, dforce, dtorque, fn * k.n + f.ft * k.t);
    if (slips()) {
      const Row dkappa =
          rr_ * dft + dtau;  // the cam's torque's correction (rr ft + tau) z, and the state row
      jac.matrix.block(9, 0, 3, kCols) += k.z * dkappa + (rr_ * f.ft + f.tau) * dz;
      jac.matrix.block(state_row, 0, 1, kCols) += dkappa;
    }
    return true;
  }

  std::vector<Channel> channels() const override {
    std::vector<Channel> c = {
        {"normal_force", "N"}, {"hertz_pressure", "Pa"}, {"half_width", "m"},  {"contact_angle", "rad"},
        {"gap", "m"},          {"separated", "1"},       {"cam_torque", "N m"}};
    if (crowned()) c.push_back({"half_length", "m"});
    if (has_friction()) {
      c.push_back({"friction_force", "N"});
      c.push_back({"slip_speed", "m/s"});
      c.push_back({"roller_speed", "rad/s"});
      c.push_back({"friction_power", "W"});
    }
    return c;
  }
  void channel_values(const ElementInput& in, std::span<double> out) const override {
    const Contact k = contact(in);
    const double fn = normal_force(k);
    const Friction f = friction(in, k, fn);
    const double r_cam = k.pitch_radius - rr_;
    const double r_rel = hertz::relative_radius(rr_, r_cam);
    out[0] = fn;
    double half_length = 0;
    if (crowned()) {
      // the semi-axes along the rolling direction (half_width) and along the roller's axis (half_length)
      const hertz::PointContact pc = hertz::point_contact(fn, r_rel, p_.crown_radius, p_.e_star,
                                                          point_law_->shape(r_rel, p_.crown_radius));
      out[1] = pc.p0;
      out[2] = pc.ax;
      half_length = pc.ay;
    } else {
      out[1] = hertz::max_pressure(fn, p_.width, r_rel, p_.e_star);
      out[2] = hertz::half_width(fn, p_.width, r_rel, p_.e_star);
    }
    out[3] = std::fmod(std::fmod(-k.psi, kTwoPi) + kTwoPi, kTwoPi);  // the lift's cam angle of the contact
    out[4] = k.gap;
    out[5] = k.gap > 0 ? 1.0 : 0.0;
    // The cam gets -F at the contact point p_i - Rr n: its moment about the cam axis (through p_j along z_j).
    const Vec3 force = fn * k.n + f.ft * k.t;
    out[6] = k.z.dot((k.r - rr_ * k.n).cross(-force));
    std::size_t next = 7;
    if (crowned()) out[next++] = half_length;
    if (has_friction()) {
      out[next++] = f.ft;
      out[next++] = slips() ? f.v : 0.0;  // pure rolling: no slip by assumption
      out[next++] = f.spin;
      out[next++] = f.power;
    }
  }
  ElementEnergy energy(const ElementInput& in) const override {
    const Contact k = contact(in);
    const double delta = -k.gap;
    const double fn = normal_force(k);
    ElementEnergy e;
    if (slips()) e.stored = 0.5 * p_.roller_inertia * in.z[0] * in.z[0];
    if (delta <= 0) return e;
    const double fe = elastic(k);
    e.stored += fe * delta / (exponent() + 1.0);
    e.dissipated = (fn - fe) * k.rate + friction(in, k, fn).power;
    // The crowned law's K changes as the foot moves: d/dt (K delta^2.5 / 2.5) = F delta' + K' psi' delta^2.5
    // / 2.5; the second part is work the normal force does not see (zero on circular arcs), booked here.
    if (crowned() && p_.stiffness <= 0)
      e.dissipated -= point_k_rate(k) * foot_factor(k) * k.t.dot(k.vr) * std::pow(delta, 2.5) / 2.5;
    return e;
  }
  int gap_count() const override { return 1; }
  void gaps(const ElementInput& in, std::span<double> out) const override { out[0] = contact(in).gap; }

 private:
  std::unique_ptr<cam::CamProfile> profile_;
  Parameters p_;
  hertz::PalmgrenLine law_;
  std::optional<hertz::PointLaw> point_law_;  // a crowned roller's law (its ellipse table), else empty
  contact::Law traction_;
  double rr_;
  double initial_spin_ = 0;
};

}  // namespace

void register_roller_cam(ElementRegistry& r) {
  r.add({"force",
         "roller-cam",
         "roller follower (i: the roller's centre) on a cam profile (j: on the camshaft, z_j its axis): "
         "contact "
         "found on the profile, Hertz line contact (Palmgren) or a crowned roller's point contact, "
         "Hunt-Crossley damping, the roller's friction: profile and its keys "
         "(docs/valvetrain.md), roller_width, roller_modulus, roller_poisson, cam_modulus, cam_poisson, "
         "stiffness, restitution, reference_speed, crown_radius, pin_friction, pin_radius, "
         "rolling_resistance, roller_inertia, mu_static, mu_dynamic, stribeck_speed, regularization_speed",
         {"i", "j"},
         [](ElementContext& c) -> std::unique_ptr<ForceElement> {
           using input::Range;
           const auto& t = c.table;
           auto profile = cam::read_cam_profile(t, c.base, c.input_files);  // with its undercut check
           Parameters p;
           read_cam_contact(t, "roller_width", "roller", p);
           p.crown_radius = t.number_or("crown_radius", 0.0, Range::closed(0.0, bounds::kLength));
           if (p.crown_radius > 0 && p.stiffness > 0)
             t.fail("crown_radius",
                    "a crowned roller has Hertz's point law; it cannot be combined with a linear "
                    "'stiffness'");
           // The roller's resistance moment M = (mu_pin r_pin + f_r) fn.
           const double mu_pin = t.number_or("pin_friction", 0.0, Range::closed(0.0, 10.0));
           const double r_pin = t.number_or("pin_radius", 0.0, Range::closed(0.0, bounds::kLength));
           if (mu_pin > 0 && r_pin <= 0)
             t.fail("pin_friction", "needs 'pin_radius' (m, > 0): the pin's radius");
           if (r_pin >= profile->roller_radius())
             t.fail("pin_radius", "the pin's radius must be smaller than the roller's (roller_radius)");
           const double f_r = t.number_or("rolling_resistance", 0.0, Range::closed(0.0, bounds::kLength));
           if (f_r >= profile->roller_radius())
             t.fail("rolling_resistance",
                    "the rolling-resistance arm (m) must be smaller than the roller's radius");
           p.resistance_arm = mu_pin * r_pin + f_r;
           p.roller_inertia = t.number_or("roller_inertia", 0.0, Range::closed(0.0, bounds::kCoefficient));
           if (p.roller_inertia > 0) {
             contact::read_friction(t, p.traction);
             if (p.traction.mu_static <= 0 && p.traction.mu_dynamic <= 0)
               t.fail("roller_inertia", "a roller that can slip needs its traction: 'mu_static' > 0");
           } else if (p.resistance_arm > 0) {
             p.traction.regularization_speed =
                 t.number_or("regularization_speed", 1e-4, Range::closed(1e-9, bounds::kSpeed));
           }
           auto element = std::make_unique<RollerCam>(std::move(profile), p);
           if (p.roller_inertia > 0 && c.initial.size() == 2) {
             // The roller starts rolling without slip on the initial motion as given.
             const ElementInput in{0.0, 0.0, c.initial, {}, {}};
             element->set_initial_spin(-element->contact(in).surface / element->roller_radius());
           }
           return element;
         }});
}

}  // namespace nvh::solve
