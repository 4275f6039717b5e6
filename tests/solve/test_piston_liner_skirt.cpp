// The piston-liner element on a flexible piston's skirt given as markers (`skirt`, docs/bearing.md section
// 18), against references not computed with the skirt path:
// 1. A rigid skirt given as markers (a grid on the piston's body, moving with i, no deformation) gives the
//    rigid-skirt element's film, channels and wrenches to round-off (1e-10): the piston's body (i and the
//    skirt markers together) takes the rigid element's wrench on i, the liner's body the same reaction.
// 2. A uniform inward skirt displacement u (every skirt marker moved towards the piston axis by u) is a
//    clearance change: the element's forces equal the rigid element's with clearance c + u (the film's Newton
//    tolerance: 1e-7).
// 3. Liner and skirt moved outwards by the same u leave the film as it was: the rigid element's forces
// (1e-7);
//    the signs of the two surfaces in the film thickness are opposite.
// 4. Power balance over a closed cycle with a skirt that breathes, ovalizes and waves along the axis while
// the
//    piston slides, swings and tilts into asperity contact: the work of all wrenches (from the prescribed
//    velocities, not from the element) plus the dissipated energy vanishes (trapezoid rule: 1e-6 of the
//    dissipated energy); the skirt markers' work is a sizeable part of it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <vector>

#include <Eigen/Geometry>

#include "common/input.hpp"
#include "piston_liner_fixture.hpp"
#include "solve/element_registry.hpp"

namespace nvh::solve {
namespace {

using namespace piston_liner_testing;

constexpr double kPi = std::numbers::pi;

struct Built {
  input::Document doc;
  std::unique_ptr<ForceElement> element;
};

/// The element from keys; `liner`: the liner markers' initial positions in j's frame, `skirt`: the skirt
/// markers' in i's frame (i and j at the origin with identity axes at the initial state).
Built build(std::string keys, const std::vector<Vec3>& liner, const std::vector<Vec3>& skirt) {
  if (!skirt.empty()) {
    keys += "skirt = [";
    for (std::size_t k = 0; k < skirt.size(); ++k)
      keys += (k ? ", \"piston.s" : "\"piston.s") + std::to_string(k) + "\"";
    keys += "]\n";
  }
  Built b{input::Document::parse(keys, "piston-liner.toml"), nullptr};
  const input::Table t = b.doc.root();
  std::vector<std::filesystem::path> files;
  std::vector<MarkerMotion> initial(2);
  std::vector<std::string> bodies = {"piston", "block"};
  for (const auto& [ring, body] : {std::pair{&liner, "block"}, std::pair{&skirt, "piston"}})
    for (const Vec3& p : *ring) {
      MarkerMotion m;
      m.position = p;
      initial.push_back(m), bodies.push_back(body);
    }
  ElementContext c{t, ".", files, initial, bodies};
  b.element = builtin_elements().find("force", "piston-liner")->make(c);
  t.finish();
  return b;
}

/// Markers moving rigidly with `carrier`, at `ring` in its frame, each moved radially (about the carrier's z
/// axis) by `u` (m).
void attach(std::vector<MarkerMotion>& markers, const MarkerMotion carrier, const std::vector<Vec3>& ring,
            double u = 0) {
  for (const Vec3& local : ring) {
    MarkerMotion m = carrier;
    m.position = carrier.position + carrier.axes * (local + u * Vec3(local.x(), local.y(), 0).normalized());
    m.velocity = carrier.velocity + carrier.angular_velocity.cross(m.position - carrier.position);
    markers.push_back(m);
  }
}

/// Total force and moment about the origin of markers `list`.
std::pair<Vec3, Vec3> resultant(const Evaluated& r, const std::vector<MarkerMotion>& m,
                                const std::vector<std::size_t>& list) {
  Vec3 f = Vec3::Zero(), t = Vec3::Zero();
  for (std::size_t k : list) f += r.w[k].force, t += r.w[k].torque + m[k].position.cross(r.w[k].force);
  return {f, t};
}

std::vector<std::size_t> indices(std::size_t from, std::size_t to, std::vector<std::size_t> also = {}) {
  for (std::size_t k = from; k < to; ++k) also.push_back(k);
  return also;
}

// The skirt's grid: 5 levels over the skirt (top 0.012 m above the pin, bottom 0.028 m below) x 12 angles.
const std::vector<Vec3> kSkirt = ring_grid(0.043, linspace(-0.028, 0.012, 5), 12);

TEST(PistonLinerSkirt, RigidSkirtGivenAsMarkersReproducesTheRigidSkirt) {
  const Built rigid = build(kKeys, {}, {}), markers = build(kKeys, {}, kSkirt);
  for (const double e : {5e-6, 25e-6}) {
    std::vector<MarkerMotion> m = piston_and_bore(e, 0.013);
    const Evaluated r = evaluate(*rigid.element, m);
    attach(m, m[0], kSkirt);
    const Evaluated s = evaluate(*markers.element, m);
    const double scale = r.w[0].force.norm();
    EXPECT_GT(scale, 1.0);
    for (std::size_t c = 0; c < r.channels.size(); ++c)
      EXPECT_NEAR(s.channels[c], r.channels[c], 1e-10 * std::abs(r.channels[c]) + 1e-300) << "channel " << c;
    // the piston's body: i and the skirt markers together take the rigid element's wrench on i
    const auto [fr, tr] = resultant(r, m, {0});
    const auto [fs, ts] = resultant(s, m, indices(2, m.size(), {0}));
    EXPECT_LE((fs - fr).norm(), 1e-10 * scale);
    EXPECT_LE((ts - tr).norm(), 1e-10 * tr.norm());
    EXPECT_LE((s.w[1].force - r.w[1].force).norm(), 1e-10 * scale) << "the liner's reaction";
    EXPECT_LE((s.w[1].torque - r.w[1].torque).norm(), 1e-10 * r.w[1].torque.norm());
    EXPECT_NEAR(s.channels[12], 0.0, 1e-15) << "skirt_displacement (round-off of the markers' radii)";
    EXPECT_LT(s.channels[13], -0.5 * std::abs(r.channels[2])) << "the skirt markers carry the film's load";
    std::printf(
        "measured: rigid skirt as %zu markers, e = %.0f um: piston force %.6g N, difference %.2e N; skirt "
        "markers' load %.6g N\n",
        kSkirt.size(), e * 1e6, scale, (fs - fr).norm(), s.channels[13]);
  }
}

TEST(PistonLinerSkirt, UniformInwardDisplacementIsAClearanceChange) {
  const double c = 30e-6;
  const std::string film =
      "bore_radius = 0.043\nskirt_length = 0.04\nskirt_top = 0.012\nviscosity = 0.007\ncells_axial = 16\n"
      "cells_around = 12\nfilm_tolerance = 1e-12\n";
  const Built ehl = build(film + "radial_clearance = 30e-6\n", {}, kSkirt);
  for (const double u : {4e-6, -6e-6}) {  // inwards
    std::ostringstream k;
    k.precision(17);
    k << film << "radial_clearance = " << c + u << "\n";
    const Built rigid = build(k.str(), {}, {});
    for (const auto& [e, squeeze_only] : {std::pair{0.0, true}, std::pair{12e-6, false}}) {
      std::vector<MarkerMotion> m = piston_and_bore(e, -0.004);
      if (squeeze_only) {  // a centred piston moving across: the pure squeeze
        m[0].axes = m[1].axes;
        m[0].velocity = m[1].velocity + m[1].angular_velocity.cross(m[0].position - m[1].position) +
                        2e-3 * m[1].axes.col(0);
        m[0].angular_velocity = m[1].angular_velocity;
      }
      const Evaluated r = evaluate(*rigid.element, m);
      attach(m, m[0], kSkirt, -u);
      const Evaluated s = evaluate(*ehl.element, m);
      const double F = r.channels[2];
      EXPECT_NEAR(s.channels[2], F, 1e-7 * std::abs(F)) << "side force, u = " << u << ", e = " << e;
      EXPECT_NEAR(s.channels[3], r.channels[3], 1e-7 * std::abs(r.channels[3])) << "moment";
      EXPECT_NEAR(s.channels[4], r.channels[4], 1e-7 * std::abs(r.channels[4]) + 1e-9 * std::abs(F))
          << "friction";
      EXPECT_NEAR(s.channels[12], std::abs(u), 1e-12) << "skirt_displacement";
      std::printf(
          "measured: uniform skirt displacement %+.0f um inwards, e = %.0f um: side force %.9g N against the "
          "rigid skirt with c + u %.9g N (relative %.2e, tolerance 1e-7)\n",
          u * 1e6, e * 1e6, s.channels[2], F, s.channels[2] / F - 1);
    }
  }
}

TEST(PistonLinerSkirt, LinerAndSkirtMovedOutwardsTogetherLeaveTheFilm) {
  const std::vector<Vec3> liner = ring_grid(0.043, linspace(-0.06, 0.06, 7), 16);
  const Built rigid = build(kKeys, {}, {}), both = build(kKeys, liner, kSkirt);
  for (const double u : {5e-6, -3e-6}) {
    std::vector<MarkerMotion> m = piston_and_bore(18e-6, 0.006);
    const Evaluated r = evaluate(*rigid.element, m);
    const MarkerMotion i = m[0], j = m[1];
    attach(m, j, liner, u);
    attach(m, i, kSkirt, u);
    const Evaluated s = evaluate(*both.element, m);
    for (int c : {2, 3, 4, 0, 1})
      EXPECT_NEAR(s.channels[c], r.channels[c], 1e-7 * std::abs(r.channels[c]))
          << "channel " << c << ", u = " << u;
    EXPECT_NEAR(s.channels[12], std::abs(u), 1e-12) << "liner_displacement";
    EXPECT_NEAR(s.channels[15], std::abs(u), 1e-12) << "skirt_displacement";
    // the skirt markers and the liner markers carry opposite loads
    EXPECT_NEAR(s.channels[16], -s.channels[13], 1e-9 * std::abs(s.channels[13]));
    std::printf(
        "measured: liner and skirt both %+.0f um outwards: side force %.9g N against the rigid %.9g N\n",
        u * 1e6, s.channels[2], r.channels[2]);
  }
}

// A closed cycle of period T: the piston slides (V = V0 sin w t), swings and tilts into asperity contact;
// each skirt marker at (Z, theta) of the piston moves radially by
// u = (a0 + a1 cos theta + a2 cos(2 pi Z / 0.04)) sin(w t + 0.4).
TEST(PistonLinerSkirt, PowerBalanceOverACycleWithADeformingSkirt) {
  const Built b = build(kKeys, {}, kSkirt);
  const double w = 2 * kPi * 50, T = 2 * kPi / w, V0 = 5, e0 = 5e-6, e1 = 26e-6, phi0 = 2e-4;
  const double a0 = -3e-6, a1 = 4e-6, a2 = 2e-6;
  const int n = 4000;
  double loss = 0, work = 0, skirt_work = 0, largest_asperity = 0, largest_u = 0, u0 = 0, u_end = 0;
  for (int k = 0; k <= n; ++k) {
    const double t = k * T / n, weight = (k == 0 || k == n) ? 0.5 : 1.0;
    const double phi = phi0 * std::sin(2 * w * t), phi_dot = 2 * w * phi0 * std::cos(2 * w * t);
    const double x = e0 + e1 * std::sin(w * t + 0.7), x_dot = e1 * w * std::cos(w * t + 0.7);
    MarkerMotion i;
    i.axes = Eigen::AngleAxisd(phi, Vec3::UnitY()).toRotationMatrix();
    i.position = Vec3(x, 0, 0.01 - V0 / w * std::cos(w * t));
    i.velocity = Vec3(x_dot, 0, V0 * std::sin(w * t));
    i.angular_velocity = Vec3(0, phi_dot, 0);
    std::vector<MarkerMotion> m = {i, MarkerMotion{}};
    for (const Vec3& p : kSkirt) {
      const Vec3 radial = Vec3(p.x(), p.y(), 0).normalized();
      const double th = std::atan2(-p.y(), p.x());
      const double amp = a0 + a1 * std::cos(th) + a2 * std::cos(2 * kPi * p.z() / 0.04);
      MarkerMotion q;
      const Vec3 local = p + amp * std::sin(w * t + 0.4) * radial;
      q.position = i.position + i.axes * local;
      q.velocity = i.velocity + i.angular_velocity.cross(i.axes * local) +
                   i.axes * (amp * w * std::cos(w * t + 0.4) * radial);
      m.push_back(q);
    }
    const Evaluated r = evaluate(*b.element, m);
    double power = 0, skirt_power = 0;
    for (std::size_t c = 0; c < m.size(); ++c) {
      const double p = r.w[c].force.dot(m[c].velocity) + r.w[c].torque.dot(m[c].angular_velocity);
      power += p;
      if (c >= 2) skirt_power += p;
    }
    loss += weight * r.energy.dissipated;
    work += weight * power;
    skirt_work += weight * skirt_power;
    largest_asperity = std::max(largest_asperity, r.channels[6]);
    largest_u = std::max(largest_u, r.channels[12]);
    if (k == 0) u0 = r.energy.stored;
    if (k == n) u_end = r.energy.stored;
  }
  const double dt = T / n;
  loss *= dt, work *= dt, skirt_work *= dt;
  EXPECT_GT(largest_asperity, 10.0) << "the cycle should reach asperity contact";
  EXPECT_NEAR(u_end, u0, 1e-12 * std::max(1.0, u0));
  EXPECT_GT(loss, 0.0);
  EXPECT_NEAR(work + loss, 0.0, 1e-6 * loss);
  EXPECT_GT(std::abs(skirt_work), 1e-3 * loss)
      << "the skirt's share must matter for the test to mean anything";
  std::printf(
      "measured: deforming skirt cycle: dissipated %.9g J, wrenches' work %.9g J (of which on the skirt "
      "markers "
      "%.4g J), sum relative %.2e (tolerance 1e-6); largest asperity force %.4g N, largest skirt "
      "displacement %.3g um\n",
      loss, work, skirt_work, (work + loss) / loss, largest_asperity, largest_u * 1e6);
}

}  // namespace
}  // namespace nvh::solve
