// The piston-liner element on a deformable liner given as markers (`liner`, docs/bearing.md section 17),
// against references not computed with the liner path:
// 1. A rigid liner given as markers (a ring grid on the bore's body, moving with j, no deformation) gives the
//    rigid-liner element's piston wrench, channels and total reaction on the liner's body to round-off
//    (1e-10).
// 2. A uniform radial liner displacement u (every marker moved outwards by u) is a clearance change: the
//    element's forces equal the rigid-liner element's with clearance c + u (the film's Newton tolerance:
//    1e-7).
// 3. Power balance over a closed cycle with a liner that breathes, ovalizes and waves along the axis while
// the
//    piston slides, swings and tilts into asperity contact: the work of all wrenches (from the prescribed
//    velocities, not from the element) plus the dissipated energy vanishes, the stored asperity energy
//    returning to its start (trapezoid rule: 1e-6 of the dissipated energy); the liner markers' work is a
//    sizeable part of it (so that leaving it out would fail).
#include <gtest/gtest.h>

#include <chrono>
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

/// The element from keys; `ring`: the liner markers' initial positions in j's frame (j at the origin with
/// identity axes; none: the rigid liner).
Built build(const std::string& keys, const std::vector<Vec3>& ring = {}) {
  Built b{input::Document::parse(keys, "piston-liner.toml"), nullptr};
  const input::Table t = b.doc.root();
  std::vector<std::filesystem::path> files;
  std::vector<MarkerMotion> initial(2);
  std::vector<std::string> bodies = {"piston", "block"};
  for (const Vec3& p : ring) {
    MarkerMotion m;
    m.position = p;
    initial.push_back(m), bodies.push_back("block");
  }
  ElementContext c{t, ".", files, initial, bodies};
  b.element = builtin_elements().find("force", "piston-liner")->make(c);
  t.finish();
  return b;
}

/// The liner's markers moving with j (rigid), at `ring` in j's frame.
void attach(std::vector<MarkerMotion>& markers, const std::vector<Vec3>& ring) {
  const MarkerMotion j = markers[1];
  for (const Vec3& local : ring) {
    MarkerMotion m = j;
    m.position = j.position + j.axes * local;
    m.velocity = j.velocity + j.angular_velocity.cross(m.position - j.position);
    markers.push_back(m);
  }
}

/// Total force and moment about the origin of markers [from, to).
std::pair<Vec3, Vec3> resultant(const Evaluated& r, const std::vector<MarkerMotion>& m, std::size_t from,
                                std::size_t to) {
  Vec3 f = Vec3::Zero(), t = Vec3::Zero();
  for (std::size_t k = from; k < to; ++k)
    f += r.w[k].force, t += r.w[k].torque + m[k].position.cross(r.w[k].force);
  return {f, t};
}

TEST(PistonLinerEhl, RigidLinerGivenAsMarkersReproducesTheRigidLiner) {
  const std::vector<Vec3> ring = ring_grid(0.043, linspace(-0.06, 0.06, 7), 16);
  const Built rigid = build(kKeys), markers = build(kKeys, ring);
  for (const double e : {5e-6, 25e-6}) {
    std::vector<MarkerMotion> m = piston_and_bore(e, 0.013);
    const Evaluated r = evaluate(*rigid.element, m);
    attach(m, ring);
    const Evaluated l = evaluate(*markers.element, m);
    const double scale = r.w[0].force.norm();
    EXPECT_GT(scale, 1.0);
    EXPECT_LE((l.w[0].force - r.w[0].force).norm(), 1e-10 * scale) << "e = " << e;
    EXPECT_LE((l.w[0].torque - r.w[0].torque).norm(), 1e-10 * r.w[0].torque.norm()) << "e = " << e;
    for (std::size_t c = 0; c < r.channels.size(); ++c)
      EXPECT_NEAR(l.channels[c], r.channels[c], 1e-10 * std::abs(r.channels[c]) + 1e-300) << "channel " << c;
    // the liner's body: j and the markers together take the rigid element's reaction on j
    const auto [fr, tr] = resultant(r, m, 1, 2);
    const auto [fl, tl] = resultant(l, m, 1, m.size());
    EXPECT_LE((fl - fr).norm(), 1e-10 * scale);
    EXPECT_LE((tl - tr).norm(), 1e-10 * tr.norm());
    EXPECT_GT(l.channels[13], 0.5 * std::abs(r.channels[2])) << "the markers carry the film's load";
    std::printf(
        "measured: rigid liner as %zu markers, e = %.0f um: piston force %.6g N, difference %.2e N; "
        "liner markers' load %.6g N\n",
        ring.size(), e * 1e6, scale, (l.w[0].force - r.w[0].force).norm(), l.channels[13]);
  }
}

TEST(PistonLinerEhl, UniformRadialDisplacementIsAClearanceChange) {
  const double c = 30e-6, R = 0.043;
  const std::string film =
      "bore_radius = 0.043\nskirt_length = 0.04\nskirt_top = 0.012\nviscosity = 0.007\ncells_axial = 16\n"
      "cells_around = 12\nfilm_tolerance = 1e-12\n";
  const std::vector<Vec3> ring = ring_grid(R, linspace(-0.06, 0.06, 5), 12);
  const Built ehl = build(film + "radial_clearance = 30e-6\n", ring);
  for (const double u : {4e-6, -6e-6}) {
    std::ostringstream k;
    k.precision(17);
    k << film << "radial_clearance = " << c + u << "\n";
    const Built rigid = build(k.str());
    for (const auto& [e, squeeze_only] : {std::pair{0.0, true}, std::pair{12e-6, false}}) {
      std::vector<MarkerMotion> m = piston_and_bore(e, -0.004);
      if (squeeze_only) {  // a centred piston moving across: the pure squeeze
        m[0].axes = m[1].axes;
        m[0].velocity = m[1].velocity + m[1].angular_velocity.cross(m[0].position - m[1].position) +
                        2e-3 * m[1].axes.col(0);
        m[0].angular_velocity = m[1].angular_velocity;
      }
      const Evaluated r = evaluate(*rigid.element, m);
      std::vector<Vec3> moved;
      for (const Vec3& p : ring) moved.push_back(p + u * Vec3(p.x(), p.y(), 0).normalized());
      attach(m, moved);
      const Evaluated l = evaluate(*ehl.element, m);
      const double F = r.channels[2];
      EXPECT_NEAR(l.channels[2], F, 1e-7 * std::abs(F)) << "side force, u = " << u << ", e = " << e;
      EXPECT_NEAR(l.channels[3], r.channels[3], 1e-7 * std::abs(r.channels[3])) << "moment";
      // (no sliding in the pure squeeze: the friction is round-off there, measured against 1e-9 of the side
      // force)
      EXPECT_NEAR(l.channels[4], r.channels[4], 1e-7 * std::abs(r.channels[4]) + 1e-9 * std::abs(F))
          << "friction";
      EXPECT_NEAR(l.channels[12], std::abs(u), 1e-12) << "liner_displacement";
      std::printf(
          "measured: uniform liner displacement %+.0f um, e = %.0f um: side force %.9g N against the rigid "
          "liner with c + u %.9g N (relative %.2e, tolerance 1e-7)\n",
          u * 1e6, e * 1e6, l.channels[2], F, l.channels[2] / F - 1);
    }
  }
}

// A closed cycle of period T: the piston slides (V = V0 sin w t), swings and tilts into asperity contact;
// each liner marker at (Z, theta) moves radially by u = (a0 + a1 cos theta + a2 cos(2 pi Z / 0.05)) sin(w t +
// 0.4).
TEST(PistonLinerEhl, PowerBalanceOverACycleWithADeformingLiner) {
  const std::vector<Vec3> ring = ring_grid(0.043, linspace(-0.05, 0.07, 13), 16);
  const Built b = build(kKeys, ring);
  const double w = 2 * kPi * 50, T = 2 * kPi / w, V0 = 5, e0 = 5e-6, e1 = 26e-6, phi0 = 2e-4;
  const double a0 = 3e-6, a1 = -4e-6, a2 = 2e-6;
  const int n = 4000;
  double loss = 0, work = 0, liner_work = 0, largest_asperity = 0, largest_u = 0, u0 = 0, u_end = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k <= n; ++k) {
    const double t = k * T / n, weight = (k == 0 || k == n) ? 0.5 : 1.0;
    const double phi = phi0 * std::sin(2 * w * t), phi_dot = 2 * w * phi0 * std::cos(2 * w * t);
    const double x = e0 + e1 * std::sin(w * t + 0.7), x_dot = e1 * w * std::cos(w * t + 0.7);
    std::vector<MarkerMotion> m(2);
    m[0].axes = Eigen::AngleAxisd(phi, Vec3::UnitY()).toRotationMatrix();
    m[0].position = Vec3(x, 0, 0.01 - V0 / w * std::cos(w * t));
    m[0].velocity = Vec3(x_dot, 0, V0 * std::sin(w * t));
    m[0].angular_velocity = Vec3(0, phi_dot, 0);
    for (const Vec3& p : ring) {
      const Vec3 radial = Vec3(p.x(), p.y(), 0).normalized();
      const double th = std::atan2(-p.y(), p.x());
      const double amp = a0 + a1 * std::cos(th) + a2 * std::cos(2 * kPi * p.z() / 0.05);
      MarkerMotion q;
      q.position = p + amp * std::sin(w * t + 0.4) * radial;
      q.velocity = amp * w * std::cos(w * t + 0.4) * radial;
      m.push_back(q);
    }
    const Evaluated r = evaluate(*b.element, m);
    double power = 0, liner_power = 0;
    for (std::size_t c = 0; c < m.size(); ++c) {
      const double p = r.w[c].force.dot(m[c].velocity) + r.w[c].torque.dot(m[c].angular_velocity);
      power += p;
      if (c >= 2) liner_power += p;
    }
    loss += weight * r.energy.dissipated;
    work += weight * power;
    liner_work += weight * liner_power;
    largest_asperity = std::max(largest_asperity, r.channels[6]);
    largest_u = std::max(largest_u, r.channels[12]);
    EXPECT_EQ(r.channels[14], 0.0) << "the liner covers the skirt's travel";
    if (k == 0) u0 = r.energy.stored;
    if (k == n) u_end = r.energy.stored;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  {  // the cost of one Jacobian at the last state (printed, not checked)
    std::vector<MarkerMotion> m(2);
    m[0].position = Vec3(e0, 0, 0.01);
    m[0].velocity = Vec3(0.01, 0, V0);
    for (const Vec3& p : ring) {
      MarkerMotion q;
      q.position = p;
      m.push_back(q);
    }
    const int nm = static_cast<int>(m.size());
    Eigen::MatrixXd jm = Eigen::MatrixXd::Zero(6 * nm, 12 * nm + 1);
    const ElementInput in{0.0, 0.0, m, {}, {}};
    ElementJacobian jac{1.0, jm};
    const auto t0 = std::chrono::steady_clock::now();
    for (int rep = 0; rep < 5; ++rep) EXPECT_TRUE(b.element->jacobian(in, jac));
    std::printf("measured: one Jacobian with %d liner markers: %.2f ms\n", nm - 2,
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / 5);
  }
  const double dt = T / n;
  loss *= dt, work *= dt, liner_work *= dt;
  EXPECT_GT(largest_asperity, 10.0) << "the cycle should reach asperity contact";
  EXPECT_NEAR(u_end, u0, 1e-12 * std::max(1.0, u0));
  EXPECT_GT(loss, 0.0);
  EXPECT_NEAR(work + loss, 0.0, 1e-6 * loss);
  EXPECT_GT(std::abs(liner_work), 1e-3 * loss)
      << "the liner's share must matter for the test to mean anything";
  std::printf(
      "measured: EHL cycle: dissipated %.9g J, wrenches' work %.9g J (of which on the liner markers "
      "%.4g J), sum relative %.2e (tolerance 1e-6); largest asperity force %.4g N, largest liner "
      "displacement %.3g um; %d evaluations with %zu liner markers in %.3f s\n",
      loss, work, liner_work, (work + loss) / loss, largest_asperity, largest_u * 1e6, n + 1, ring.size(),
      seconds);
}

}  // namespace
}  // namespace nvh::solve
