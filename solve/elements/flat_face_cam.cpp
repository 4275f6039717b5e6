// A flat-faced (mushroom) follower on a cam: the follower's flat face (marker i on the tappet, origin on the
// face, z_i the face's normal pointing towards the cam) against a cam profile (marker j on the camshaft:
// origin on the cam's axis, z_j the axis, x_j the zero of the lift's cam angle; solve/cam/cam_profile.hpp).
// A type of its own rather than an option of roller-cam: the contact is found by the cam's support function
// (solve/cam/support_function.hpp), not by the foot of a point on the pitch curve, the follower gets a moment
// from the contact's offset and a sliding friction, and the keys differ; the Hertz and Palmgren law
// (hertz_line.hpp) and the friction law (contact_law.hpp) are shared, not copied.
//
// Geometry (R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. 2009, section 7.4: the flat-faced
// follower's lift is the cam's support function). With r = p_i - p_j, w = -z_i (from the cam towards the
// face), its part normal to the cam's axis w_perp = w - (w . z_j) z_j (the face's tilt out of the cam's plane
// is ignored: no edge loading), u = w_perp / |w_perp|, t = z_j x u (along the face, in the cam's plane), phi
// the angle of u in the cam's frame (A_j^T u = [cos phi, sin phi, 0]):
//   d = u . r                   the face's distance from the cam's axis
//   g = d - h(phi)              the gap (> 0: lifted off), approach delta = -g
//   e = h'(phi) - t . r         the contact point's offset along the face from marker i's origin (along t)
//   x = p_i + e t               the contact point on the face (at p_i's position along the axis)
//   vrel = v_i + w_i x (x - p_i) - v_j - w_j x (x - p_j)    the face's material point against the cam's at x
//   delta' = -u . vrel          (= d delta / dt for a face in the cam's plane)
//   v_s = -t . vrel             the sliding speed: the cam's surface speed minus the face's, along t
// Force on the face at x (the reaction on the cam at x):
//   fn = F(delta) (1 + alpha delta') >= 0,  F Palmgren's line law scaled by E* (or a linear `stiffness`),
//   alpha = 3 (1 - e_r) / (2 v_ref)  (Hunt & Crossley, J. Appl. Mech. 42, 1975, eq. 5);
//   ft = mu(v_s) fn  (contact_law.hpp's regularized Coulomb with Stribeck, odd in v_s: the cam drags the
//   face); F = fn u + ft t,  torque on the follower about p_i: e t x F = -e fn z_j.
// The contact's torque on the cam about z_j is fn h' - ft d (quasi-statically -F_line ds/dtheta). Hertz: a
// cylinder of the cam's local radius R_c = h + h'' on a flat: p0 = sqrt(fn E* / (pi L R_c)) (Johnson,
// Contact Mechanics 1985, eq. 4.45). Energy: stored F delta / (n + 1); dissipated (fn - F) delta' + ft v_s.
//
// Jacobian (force_element.hpp's columns: i at 0 (dp, dtheta, dv, domega), j at 12), with ~ the cross-product
// matrix:
//   dw = -w~ dtheta_i,  dz_j = -z_j~ dtheta_j,
//   dw_perp = (1 - z_j z_j^T) dw - z_j w^T dz_j - (w . z_j) dz_j,   du = (1 - u u^T) dw_perp / |w_perp|,
//   dt = z_j~ du - u~ dz_j,   dphi = t^T du - z_j^T dtheta_j,   dr = dp_i - dp_j,
//   d delta = h' dphi - r^T du - u^T dr,   de = h'' dphi - r^T dt - t^T dr,   a = e t, b = r + a,
//   dvrel = dv_i - dv_j - a~ domega_i + b~ domega_j + w_i~ da - w_j~ db,
//   d delta' = -vrel^T du - u^T dvrel,   dv_s = -vrel^T dt - t^T dvrel,
//   dfn = F' (1 + alpha delta') d delta + F alpha d delta',   dft = mu'(v_s) fn dv_s + mu dfn,
//   dF = u dfn + fn du + t dft + ft dt,   dT = -z_j (fn de + e dfn) - e fn dz_j.
#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.hpp"
#include "solve/cam/cam_profile.hpp"
#include "solve/cam/support_function.hpp"
#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"
#include "solve/elements/cam_contact_keys.hpp"
#include "solve/elements/contact_law.hpp"
#include "solve/elements/hertz_line.hpp"

namespace nvh::solve {
namespace {

struct Parameters {
  double width = 0;          // m, the contact length (the cam's width under the face)
  double e_star = 0;         // Pa
  double stiffness = 0;      // N/m; > 0: a linear law instead of Palmgren's
  double restitution = 1.0;  // at the reference speed
  double reference_speed = 1.0;
};

/// The face against the cam at one state (header's symbols).
struct Contact {
  bool valid = false;  // false: the face's normal is (nearly) along the cam's axis: no contact
  Vec3 r, w, zj, u, t;
  double perp = 0;  // |w_perp|
  double phi = 0;
  cam::Support s;
  double gap = 0, offset = 0, rate = 0, slide = 0;
  Vec3 vrel;
};

class FlatFaceCam final : public ForceElement {
 public:
  FlatFaceCam(std::unique_ptr<cam::CamProfile> profile, Parameters p, contact::Parameters friction)
      : profile_(std::move(profile)),
        p_(p),
        law_(p.width, p.e_star),
        friction_(friction),
        has_friction_(friction.mu_static > 0 || friction.mu_dynamic > 0) {}
  std::string type() const override { return "flat-face-cam"; }
  int marker_count() const override { return 2; }

  Contact contact(const ElementInput& in) const {
    const MarkerMotion& mi = in.markers[0];
    const MarkerMotion& mj = in.markers[1];
    Contact k;
    k.r = mi.position - mj.position;
    k.w = -mi.axes.col(2);
    k.zj = mj.axes.col(2);
    const Vec3 wp = k.w - k.w.dot(k.zj) * k.zj;
    k.perp = wp.norm();
    if (k.perp < 1e-6) {
      k.gap = 1.0;  // the face lies in the cam's plane: it cannot touch the profile
      return k;
    }
    k.valid = true;
    k.u = wp / k.perp;
    k.t = k.zj.cross(k.u);
    const Vec3 uc = mj.axes.transpose() * k.u;
    k.phi = std::atan2(uc.y(), uc.x());
    k.s = cam::support(*profile_, k.phi);
    k.gap = k.u.dot(k.r) - k.s.h;
    k.offset = k.s.dh - k.t.dot(k.r);
    const Vec3 a = k.offset * k.t, b = k.r + a;
    k.vrel = mi.velocity + mi.angular_velocity.cross(a) - mj.velocity - mj.angular_velocity.cross(b);
    k.rate = -k.u.dot(k.vrel);
    k.slide = -k.t.dot(k.vrel);
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
    if (!k.valid || delta <= 0) return 0.0;
    return std::max(0.0, elastic(delta) * (1.0 + alpha() * k.rate));
  }
  double friction_force(const Contact& k, double fn) const {
    return has_friction_ && fn > 0 ? friction_.mu(k.slide) * fn : 0.0;
  }

  void evaluate(const ElementInput& in, ElementOutput& out) const override {
    const Contact k = contact(in);
    const double fn = normal_force(k);
    if (fn <= 0) return;
    const double ft = friction_force(k, fn);
    apply_at_i(in, out, fn * k.u + ft * k.t, -k.offset * fn * k.zj, in.markers[0].position);
  }

  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override {
    const Contact k = contact(in);
    const double fn = normal_force(k);
    if (fn <= 0) return true;  // no force around here
    const double delta = -k.gap, ft = friction_force(k, fn);
    using Rows = Eigen::Matrix<double, 3, 24>;
    using Row = Eigen::Matrix<double, 1, 24>;
    const MarkerMotion& mi = in.markers[0];
    const MarkerMotion& mj = in.markers[1];
    const Mat3 eye = Mat3::Identity(), zx = skew(k.zj);
    Rows dw = Rows::Zero(), dzj = Rows::Zero(), dr = Rows::Zero();
    dw.block<3, 3>(0, 3) = -skew(k.w);
    dzj.block<3, 3>(0, 15) = -zx;
    dr.block<3, 3>(0, 0) = eye;
    dr.block<3, 3>(0, 12) = -eye;
    const Rows dwp =
        (eye - k.zj * k.zj.transpose()) * dw - k.zj * (k.w.transpose() * dzj) - k.w.dot(k.zj) * dzj;
    const Rows du = (eye - k.u * k.u.transpose()) * dwp / k.perp;
    const Rows dt = zx * du - skew(k.u) * dzj;
    Row dphi = k.t.transpose() * du;
    dphi.segment<3>(15) -= k.zj.transpose();
    // h'' is infinite only where the face is exactly parallel to a straight flank (a set of measure zero).
    const double ddh = std::isfinite(k.s.ddh) ? k.s.ddh : 0.0;
    const Row ddelta = k.s.dh * dphi - k.r.transpose() * du - k.u.transpose() * dr;
    const Row doffset = ddh * dphi - k.r.transpose() * dt - k.t.transpose() * dr;
    const Vec3 a = k.offset * k.t, b = k.r + a;
    const Rows da = k.t * doffset + k.offset * dt;
    const Rows db = dr + da;
    Rows dvrel = skew(mi.angular_velocity) * da - skew(mj.angular_velocity) * db;
    dvrel.block<3, 3>(0, 6) += eye;
    dvrel.block<3, 3>(0, 18) -= eye;
    dvrel.block<3, 3>(0, 9) -= skew(a);
    dvrel.block<3, 3>(0, 21) += skew(b);
    const Row drate = -k.vrel.transpose() * du - k.u.transpose() * dvrel;
    const Row dslide = -k.vrel.transpose() * dt - k.t.transpose() * dvrel;
    const double fe = elastic(delta), al = alpha();
    const Row dfn = elastic_stiffness(delta) * (1.0 + al * k.rate) * ddelta + fe * al * drate;
    Row dft = Row::Zero();
    if (has_friction_) dft = friction_.mu_derivative(k.slide) * fn * dslide + friction_.mu(k.slide) * dfn;
    ElementRows dforce = zero_rows(jac), dtorque = zero_rows(jac);
    dforce.leftCols<24>() = k.u * dfn + fn * du + k.t * dft + ft * dt;
    dtorque.leftCols<24>() = -k.zj * (fn * doffset + k.offset * dfn) - k.offset * fn * dzj;
    jacobian_at_i(in, jac, dforce, dtorque, fn * k.u + ft * k.t);
    return true;
  }

  std::vector<Channel> channels() const override {
    return {{"normal_force", "N"}, {"hertz_pressure", "Pa"}, {"contact_offset", "m"}, {"gap", "m"},
            {"separated", "1"},    {"sliding_speed", "m/s"}, {"friction_force", "N"}, {"cam_torque", "N m"}};
  }
  void channel_values(const ElementInput& in, std::span<double> out) const override {
    const Contact k = contact(in);
    const double fn = normal_force(k), ft = friction_force(k, fn);
    out[0] = fn;
    // A cylinder of the cam's radius R_c on a flat (infinite radius): R = R_c.
    out[1] = k.valid ? hertz::max_pressure(fn, p_.width, k.s.radius, p_.e_star) : 0.0;
    out[2] = k.offset;
    out[3] = k.gap;
    out[4] = k.gap > 0 ? 1.0 : 0.0;
    out[5] = k.slide;
    out[6] = ft;
    // The cam gets -F at x: its moment about the cam's axis (the line through p_j along z_j).
    out[7] = k.valid ? k.zj.dot((k.r + k.offset * k.t).cross(-(fn * k.u + ft * k.t))) : 0.0;
  }
  ElementEnergy energy(const ElementInput& in) const override {
    const Contact k = contact(in);
    const double delta = -k.gap;
    if (!k.valid || delta <= 0) return {};
    const double fe = elastic(delta), fn = normal_force(k);
    const double exponent = p_.stiffness > 0 ? 1.0 : hertz::PalmgrenLine::kExponent;
    return {fe * delta / (exponent + 1.0), (fn - fe) * k.rate + friction_force(k, fn) * k.slide};
  }
  int gap_count() const override { return 1; }
  void gaps(const ElementInput& in, std::span<double> out) const override { out[0] = contact(in).gap; }

 private:
  std::unique_ptr<cam::CamProfile> profile_;
  Parameters p_;
  hertz::PalmgrenLine law_;
  contact::Law friction_;
  bool has_friction_;
};

}  // namespace

void register_flat_face_cam(ElementRegistry& r) {
  r.add({"force",
         "flat-face-cam",
         "flat-faced follower (i: on the face, z_i its normal towards the cam) on a cam profile (j: on the "
         "camshaft, z_j its axis): contact by the cam's support function, Hertz line contact (Palmgren), "
         "Hunt-Crossley damping, sliding friction: profile and its keys (docs/valvetrain.md), face_width, "
         "follower_modulus, follower_poisson, cam_modulus, cam_poisson, stiffness, restitution, "
         "reference_speed, mu_static, mu_dynamic, stribeck_speed, regularization_speed",
         {"i", "j"},
         [](ElementContext& c) -> std::unique_ptr<ForceElement> {
           const auto& t = c.table;
           auto profile = cam::read_cam_profile(t, c.base, c.input_files);  // with its undercut check
           try {
             cam::check_flat_follower_fits(*profile, "the " + profile->kind() + " cam profile");
           } catch (const Error& e) {
             t.fail("profile", e.message());
           }
           Parameters p;
           read_cam_contact(t, "face_width", "follower", p);
           contact::Parameters friction;
           contact::read_friction(t, friction);
           return std::make_unique<FlatFaceCam>(std::move(profile), p, friction);
         }});
}

}  // namespace nvh::solve
