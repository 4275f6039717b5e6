// The valve seat contact (issue 13, item 2): the conical face of a poppet valve (marker i) on the seat insert
// of the head (marker j), a Hertz line contact around the seat ring.
//
// Markers: z_i and z_j along the valve stem, pointing in the OPENING direction (into the cylinder), both
// origins on the valve axis and placed at the seated, line-to-line position (faces touching, no load).
// Axial gap g = z_j . (p_i - p_j) (> 0 open), axial closure delta_a = -g (> 0 in contact).
//
// Geometry (half a section through the axis; beta = `seat_angle_deg`, the angle between the cone face and the
// valve's plane, 45 or 30 deg usually):
//
//   z ^ (opening, into the cylinder)
//     |________________________
//     |   valve head          /   n = cos(beta) z - sin(beta) r: the seat's normal on the valve (out of the
//     |                      /      seat's material), beta from the axis
//     |_____                / seat insert (in the head)
//     |     | stem         /
//     |     |             / beta  the face on the seat: a cone, its generator beta above the valve's plane
//     |     |            /_______
//     +---------------------------> r (the ring's radial direction at the point looked at)
//
// The face's generator makes beta with the radial direction, so its normal makes beta with the axis. A rigid
// axial closure delta_a moves the faces into each other by its normal component and slides them along the
// generator by delta_a sin(beta):
//   normal approach  delta_n = delta_a cos(beta)   (beta = 0: a flat seat, delta_n = delta_a)
// and the normal load F_n (N, on the whole ring) has the axial resultant (the radial parts cancel):
//   axial force      F_a = F_n cos(beta),  F_n / F_a = 1 / cos(beta)  (1.414 at 45 deg, 1.155 at 30 deg)
// acting on the valve along +z_j (the seat pushes it out of the seat, in the opening direction), the reaction
// on the seat. Virtual work agrees: F_a d(delta_a) = F_n d(delta_n).
//
// The ring: a line contact of length L = pi * `seat_diameter` (the mean seat diameter), relative radius R
// from the crowning radius of the valve face across the band `face_radius` and the seat's `seat_radius`
// (default flat: R = face_radius; concave negative), contact modulus E* of the valve's and the seat's
// materials (hertz_line.hpp, Johnson eq. 4.43/4.45 and Palmgren's law as written there):
//   elastic normal force: Palmgren's line law scaled by E* (hertz::PalmgrenLine, length L),
//     P(delta_n) = K delta_n^(10/9),  F_a,el = cos(beta) P(cos(beta) delta_a) = k_a delta_a^(10/9),
//     k_a = cos(beta) P(cos(beta))  (P at 1 m of approach: the law is a pure power law);
//   or, with `stiffness` k (N/m, a measured AXIAL seat stiffness): F_a,el = k delta_a, F_n = F_a / cos(beta);
//   damping (Hunt & Crossley, J. Appl. Mech. 42, 1975, eq. 5) as in contact_law.hpp:
//     F_a = F_a,el (1 + alpha delta_a') >= 0 (never pulling),  alpha = 3 (1 - e) / (2 v_ref).
// `restitution` e and `reference_speed` v_ref are in the AXIAL terms a valve rig measures: e is the ratio of
// the valve's axial rebound and seating speeds at the axial seating speed v_ref (for small alpha v; exactly
// G(v_out) = G(v_in), G(v) = v/alpha - ln(1 + alpha v)/alpha^2). In normal terms the factor is
// 1 + (alpha / cos(beta)) delta_n': Hunt-Crossley with the normal reference speed v_ref cos(beta).
// The axial law is a point-plane law along z_j, so the force, its Jacobian and the energy are those of
// contact::Law (contact_law.hpp: exponent 10/9 or 1, no friction, no clearance) with stiffness k_a.
// Stored energy: int F_a,el d(delta_a) = int P d(delta_n) = P delta_n / (n + 1), n = 10/9 (the geometry
// factor cancels); dissipated: the damping part's power (F_a - F_a,el) delta_a'.
//
// Not modelled: tilt and misalignment of the valve in its seat (the seating is axisymmetric: no torque, no
// radial force), friction and sliding along the face (the micro-slip delta_a sin(beta) that wears seats), the
// seat band's width (the ring is a line) and the valve head's bending (its own stiffness is in series with
// the contact: model it with the valve's flexible body, or fold it into `stiffness`).
//
// Channels: gap (m, axial), normal_force (N, F_n on the ring), axial_force (N, F_a), hertz_pressure (Pa, p0 =
// sqrt(F_n E* / (pi L R))), half_width (m, b = sqrt(4 F_n R / (pi L E*))), closing_speed (m/s, delta_a' =
// -g', positive closing: the seating velocity at impact). Contact events: the axial gap.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"
#include "solve/elements/contact_law.hpp"
#include "solve/elements/hertz_line.hpp"

namespace nvh::solve {
namespace {

struct Ring {
  double length;     // L (m)
  double radius;     // R (m)
  double e_star;     // E* (Pa)
  double cos_angle;  // cos(beta)
};

class ValveSeat final : public contact::PointElement {
 public:
  // law_: the axial law along z_j (the element's force, Jacobian, energy and event: contact::PointElement).
  ValveSeat(contact::Parameters axial, Ring ring) : PointElement(axial), ring_(ring) {}
  std::string type() const override { return "valve-seat"; }

  std::vector<Channel> channels() const override {
    return {{"gap", "m"},        {"normal_force", "N"},   {"axial_force", "N"}, {"hertz_pressure", "Pa"},
            {"half_width", "m"}, {"closing_speed", "m/s"}};
  }
  void channel_values(const ElementInput& in, std::span<double> out) const override {
    const contact::State s = state(in);
    const double axial = law_.normal_force(s), normal = axial / ring_.cos_angle;
    out[0] = -s.delta;
    out[1] = normal;
    out[2] = axial;
    out[3] = hertz::max_pressure(normal, ring_.length, ring_.radius, ring_.e_star);
    out[4] = hertz::half_width(normal, ring_.length, ring_.radius, ring_.e_star);
    out[5] = s.delta_rate;
  }

 private:
  Ring ring_;
};

std::unique_ptr<ForceElement> make_valve_seat(ElementContext& c) {
  using input::Range;
  const auto& t = c.table;
  const Range length = Range{0.0, bounds::kLength, true, false};
  const Range modulus = Range{0.0, bounds::kCoefficient, true, false};
  const Range poisson = Range{-1.0, 0.5, true, false};
  const double beta =
      t.number_or("seat_angle_deg", 45.0, Range::closed(0.0, 80.0)) * std::numbers::pi / 180.0;
  Ring ring;
  ring.cos_angle = std::cos(beta);
  ring.length = std::numbers::pi * t.number("seat_diameter", length);
  const double face = t.number("face_radius", length);
  const double seat = t.has("seat_radius") ? t.number("seat_radius", Range::magnitude(bounds::kLength))
                                           : std::numeric_limits<double>::infinity();
  if (seat == 0.0) t.fail("seat_radius", "must not be 0 (omit it for a flat seat)");
  ring.radius = hertz::relative_radius(face, seat);
  if (!(ring.radius > 0) || !std::isfinite(ring.radius))
    t.fail("seat_radius", "a concave seat must be flatter than the face (|seat_radius| > face_radius)");
  const double ev = t.number_or("valve_youngs_modulus", hertz::kSteelModulus, modulus);
  const double nv = t.number_or("valve_poisson", hertz::kSteelPoisson, poisson);
  const double es = t.number_or("seat_youngs_modulus", hertz::kSteelModulus, modulus);
  const double ns = t.number_or("seat_poisson", hertz::kSteelPoisson, poisson);
  ring.e_star = hertz::contact_modulus(ev, nv, es, ns);

  contact::Parameters axial;
  if (t.has("stiffness")) {
    axial.stiffness = t.number("stiffness", modulus);
    axial.exponent = 1.0;
  } else {
    const hertz::PalmgrenLine palmgren(ring.length, ring.e_star);
    axial.stiffness = ring.cos_angle * palmgren.force(ring.cos_angle);  // k_a (N/m^(10/9)); beta = 0: cos = 1
    axial.exponent = hertz::PalmgrenLine::kExponent;
  }
  axial.restitution = t.number_or("restitution", 1.0, Range::open(0.0, 1.0 + 1e-12));
  axial.reference_speed = t.number_or("reference_speed", 1.0, Range::closed(1e-9, bounds::kSpeed));
  return std::make_unique<ValveSeat>(axial, ring);
}

}  // namespace

void register_valve_seat(ElementRegistry& r) {
  r.add(
      {"force",
       "valve-seat",
       "valve face (i) on its seat insert (j), z along the stem in the opening direction: Hertz line "
       "contact on the seat cone, Palmgren's approach, Hunt-Crossley damping: seat_diameter, face_radius, "
       "seat_radius, seat_angle_deg, valve_youngs_modulus, valve_poisson, seat_youngs_modulus, seat_poisson, "
       "stiffness, restitution, reference_speed",
       {"i", "j"},
       make_valve_seat});
}

}  // namespace nvh::solve
