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
// passes through the roller's centre, so the follower gets no torque from it (the roller turns freely:
// rolling friction is neglected), and the cam's reaction gives the camshaft's drive torque. Channels: normal
// force, Hertz pressure p0 = sqrt(fn E* / (pi L R)) with 1/R = 1/Rr + 1/R_cam (the cam surface's radius of
// curvature at the contact, concave negative), its half-width, the cam angle of the contact point, the gap, a
// separation flag, the torque on the cam about z_j.
//
// Jacobian (force_element.hpp's columns): with r = p_i - p_j, dc = dr + r~ dtheta_j (the relative position as
// the cam sees it, in global axes), the distance field's gradient n and Hessian H = t t^T / (R_p + g) (R_p
// the pitch curve's radius of curvature at the foot, t its tangent):
//   d delta = -n^T dc,   dn = H dc - n~ dtheta_j,
//   delta' = -n . vr,  vr = v_i - v_j - omega_j x r,  dvr = dv_i - dv_j + r~ domega_j - omega_j~ dr,
//   d delta' = -vr^T dn - n^T dvr,   dfn = F' (1 + alpha delta') d delta + F alpha d delta',   dF = n dfn +
//   fn dn.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "solve/cam/cam_profile.hpp"
#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"
#include "solve/elements/hertz_line.hpp"

namespace nvh::solve {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

struct Parameters {
  double width = 0;          // m, the roller's contact length
  double e_star = 0;         // Pa
  double stiffness = 0;      // N/m; > 0: a linear law instead of Palmgren's
  double restitution = 1.0;  // at the reference speed
  double reference_speed = 1.0;
};

/// The roller against the pitch curve at one state.
struct Contact {
  Vec3 r;                   // p_i - p_j (m)
  Vec3 n;                   // outward normal of the pitch curve at the foot, global
  Vec3 t;                   // its tangent (d/dpsi direction), global unit
  double gap = 0;           // m
  double rate = 0;          // delta' (m/s), > 0 closing
  Vec3 vr;                  // v_i - v_j - omega_j x r
  double psi = 0;           // the foot's polar angle in the cam frame (rad)
  double pitch_radius = 0;  // signed radius of curvature of the pitch curve at the foot (m)
};

class RollerCam final : public ForceElement {
 public:
  RollerCam(std::unique_ptr<cam::CamProfile> profile, Parameters p)
      : profile_(std::move(profile)), p_(p), law_(p.width, p.e_star) {}
  std::string type() const override { return "roller-cam"; }
  int marker_count() const override { return 2; }

  Contact contact(const ElementInput& in) const {
    const MarkerMotion& mi = in.markers[0];
    const MarkerMotion& mj = in.markers[1];
    Contact k;
    k.r = mi.position - mj.position;
    const Vec3 c = mj.axes.transpose() * k.r;
    double psi = std::atan2(c.y(), c.x());
    cam::PitchPoint pp = cam::pitch_point(*profile_, psi);
    // Newton on f(psi) = (P - c) . P' (the foot of the normal); a convex pitch curve near c converges in a
    // few steps; the step is limited so that a poor start cannot jump to another lobe.
    for (int it = 0; it < 30; ++it) {
      const double ex = pp.x - c.x(), ey = pp.y - c.y();
      const double f = ex * pp.dx + ey * pp.dy;
      const double df = pp.dx * pp.dx + pp.dy * pp.dy + ex * pp.ddx + ey * pp.ddy;
      double step = df > 0 ? -f / df : -f / (pp.dx * pp.dx + pp.dy * pp.dy);
      step = std::clamp(step, -0.2, 0.2);
      psi += step;
      pp = cam::pitch_point(*profile_, psi);
      if (std::abs(step) < 1e-14) break;
    }
    k.psi = psi;
    k.pitch_radius = pp.radius_of_curvature;
    const Vec3 n_cam(pp.nx, pp.ny, 0.0);
    const double tl = std::hypot(pp.dx, pp.dy);
    k.n = mj.axes * n_cam;
    k.t = mj.axes * Vec3(pp.dx / tl, pp.dy / tl, 0.0);
    k.gap = n_cam.x() * (c.x() - pp.x) + n_cam.y() * (c.y() - pp.y);
    k.vr = mi.velocity - mj.velocity - mj.angular_velocity.cross(k.r);
    k.rate = -k.n.dot(k.vr);
    return k;
  }

  double elastic(double delta) const {
    if (delta <= 0) return 0.0;
    return p_.stiffness > 0 ? p_.stiffness * delta : law_.force(delta);
  }
  double elastic_stiffness(double delta) const {
    if (delta <= 0) return 0.0;
    return p_.stiffness > 0 ? p_.stiffness : law_.stiffness(delta);
  }
  double alpha() const { return 3.0 * (1.0 - p_.restitution) / (2.0 * p_.reference_speed); }
  double normal_force(const Contact& k) const {
    const double delta = -k.gap;
    if (delta <= 0) return 0.0;
    return std::max(0.0, elastic(delta) * (1.0 + alpha() * k.rate));
  }

  void evaluate(const ElementInput& in, ElementOutput& out) const override {
    const Contact k = contact(in);
    const double fn = normal_force(k);
    if (fn <= 0) return;
    apply_at_i(in, out, fn * k.n, Vec3::Zero(), in.markers[0].position);
  }

  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override {
    const Contact k = contact(in);
    const double delta = -k.gap, fn = normal_force(k);
    if (fn <= 0) return true;  // no force around here
    using Rows = Eigen::Matrix<double, 3, 24>;
    using Row = Eigen::Matrix<double, 1, 24>;
    const Mat3 eye = Mat3::Identity(), rx = skew(k.r), wx = skew(in.markers[1].angular_velocity);
    Rows dc = Rows::Zero(), dvr = Rows::Zero(), dn = Rows::Zero();
    dc.block<3, 3>(0, 0) = eye;
    dc.block<3, 3>(0, 12) = -eye;
    dc.block<3, 3>(0, 15) = rx;
    // The distance field's Hessian; on a flank (R_p = inf) the normal does not turn with the foot.
    const double denom = k.pitch_radius + k.gap;
    const Mat3 hessian =
        std::isfinite(denom) && std::abs(denom) > 1e-12 ? Mat3(k.t * k.t.transpose() / denom) : Mat3::Zero();
    dn = hessian * dc;
    dn.block<3, 3>(0, 15) -= skew(k.n);
    dvr.block<3, 3>(0, 6) = eye;
    dvr.block<3, 3>(0, 18) = -eye;
    dvr.block<3, 3>(0, 21) = rx;
    dvr.block<3, 3>(0, 0) -= wx;
    dvr.block<3, 3>(0, 12) += wx;
    const Row ddelta = -k.n.transpose() * dc;
    const Row drate = -k.vr.transpose() * dn - k.n.transpose() * dvr;
    const double fe = elastic(delta), a = alpha();
    const Row dfn = elastic_stiffness(delta) * (1.0 + a * k.rate) * ddelta + fe * a * drate;
    ElementRows dforce = zero_rows(jac);
    dforce.leftCols<24>() = k.n * dfn + fn * dn;
    jacobian_at_i(in, jac, dforce, zero_rows(jac), fn * k.n);
    return true;
  }

  std::vector<Channel> channels() const override {
    return {{"normal_force", "N"}, {"hertz_pressure", "Pa"}, {"half_width", "m"},  {"contact_angle", "rad"},
            {"gap", "m"},          {"separated", "1"},       {"cam_torque", "N m"}};
  }
  void channel_values(const ElementInput& in, std::span<double> out) const override {
    const Contact k = contact(in);
    const double fn = normal_force(k);
    const double r_cam = k.pitch_radius - profile_->roller_radius();
    const double r_rel = hertz::relative_radius(profile_->roller_radius(), r_cam);
    out[0] = fn;
    out[1] = hertz::max_pressure(fn, p_.width, r_rel, p_.e_star);
    out[2] = hertz::half_width(fn, p_.width, r_rel, p_.e_star);
    out[3] = std::fmod(std::fmod(-k.psi, kTwoPi) + kTwoPi, kTwoPi);  // the lift's cam angle of the contact
    out[4] = k.gap;
    out[5] = k.gap > 0 ? 1.0 : 0.0;
    // The cam gets -fn n at p_i - Rr n: its moment about the cam axis (the line through p_j along z_j).
    const Vec3 zj = in.markers[1].axes.col(2);
    out[6] = zj.dot(k.r.cross(-fn * k.n));
  }
  ElementEnergy energy(const ElementInput& in) const override {
    const Contact k = contact(in);
    const double delta = -k.gap;
    if (delta <= 0) return {};
    const double fe = elastic(delta);
    const double exponent = p_.stiffness > 0 ? 1.0 : hertz::PalmgrenLine::kExponent;
    return {fe * delta / (exponent + 1.0), (normal_force(k) - fe) * k.rate};
  }
  int gap_count() const override { return 1; }
  void gaps(const ElementInput& in, std::span<double> out) const override { out[0] = contact(in).gap; }

 private:
  std::unique_ptr<cam::CamProfile> profile_;
  Parameters p_;
  hertz::PalmgrenLine law_;
};

}  // namespace

void register_roller_cam(ElementRegistry& r) {
  r.add({"force",
         "roller-cam",
         "roller follower (i: the roller's centre) on a cam profile (j: on the camshaft, z_j its axis): "
         "contact "
         "found on the profile, Hertz line contact (Palmgren), Hunt-Crossley damping: profile and its keys "
         "(docs/valvetrain.md), roller_width, roller_modulus, roller_poisson, cam_modulus, cam_poisson, "
         "stiffness, restitution, reference_speed",
         {"i", "j"},
         [](ElementContext& c) -> std::unique_ptr<ForceElement> {
           using input::Range;
           const auto& t = c.table;
           auto profile = cam::read_cam_profile(t, c.base, c.input_files);  // with its undercut check
           Parameters p;
           p.width = t.number("roller_width", Range{0.0, bounds::kLength, true, false});
           const Range modulus = Range{0.0, 1e15, true, false};
           const Range poisson = Range::closed(0.0, 0.5);
           const double er = t.number_or("roller_modulus", hertz::kSteelModulus, modulus);
           const double nr = t.number_or("roller_poisson", hertz::kSteelPoisson, poisson);
           const double ec = t.number_or("cam_modulus", hertz::kSteelModulus, modulus);
           const double nc = t.number_or("cam_poisson", hertz::kSteelPoisson, poisson);
           p.e_star = hertz::contact_modulus(er, nr, ec, nc);
           p.stiffness = t.number_or("stiffness", 0.0, Range::closed(0.0, bounds::kCoefficient));
           p.restitution = t.number_or("restitution", 1.0, Range::open(0.0, 1.0 + 1e-12));
           p.reference_speed = t.number_or("reference_speed", 1.0, Range::closed(1e-9, bounds::kSpeed));
           return std::make_unique<RollerCam>(std::move(profile), p);
         }});
}

}  // namespace nvh::solve
