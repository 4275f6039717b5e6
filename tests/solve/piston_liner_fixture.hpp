#pragma once
// Shared by the piston-liner element's tests on surface markers (test_piston_liner_ehl.cpp, the liner's;
// test_piston_liner_skirt.cpp, the skirt's): marker grids, one evaluation of an element, the keys of the slap
// family's skirt and a piston off centre in a moving bore.
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "solve/element_registry.hpp"

namespace nvh::solve::piston_liner_testing {

/// Axial levels z (m, in the frame of the grid's marker) x angles around (from its x towards w = x x z = -y)
/// at radius r.
inline std::vector<Vec3> ring_grid(double r, const std::vector<double>& levels, int angles) {
  std::vector<Vec3> out;
  for (int b = 0; b < angles; ++b) {
    const double th = -std::numbers::pi + 2 * std::numbers::pi * (b + 0.5) / angles;
    for (double z : levels) out.emplace_back(r * std::cos(th), -r * std::sin(th), z);
  }
  return out;
}

inline std::vector<double> linspace(double a, double b, int n) {
  std::vector<double> v(n);
  for (int k = 0; k < n; ++k) v[k] = a + (b - a) * k / (n - 1);
  return v;
}

struct Evaluated {
  std::vector<Wrench> w;
  std::vector<double> channels;
  ElementEnergy energy;
};

inline Evaluated evaluate(const ForceElement& e, const std::vector<MarkerMotion>& markers) {
  Evaluated out;
  out.w.resize(markers.size());
  const ElementInput in{0.0, 0.0, markers, {}, {}};
  ElementOutput o{out.w, {}};
  e.evaluate(in, o);
  out.channels.resize(e.channels().size());
  e.channel_values(in, out.channels);
  out.energy = e.energy(in);
  return out;
}

inline const std::string kKeys =
    "bore_radius = 0.043\nradial_clearance = 30e-6\nskirt_length = 0.04\nskirt_top = 0.012\nviscosity = "
    "0.007\n"
    "barrel = [[-0.028, 12e-6], [-0.006, 0.0], [0.012, 8e-6]]\ncells_axial = 16\ncells_around = 12\n"
    "sigma = 1e-6\nK = 2.4e-4\nmodulus = 1.1e11\nmu_asperity = 0.1\nfilm_tolerance = 1e-12\n";

// The piston tilted, off centre, sliding and swinging; j turned and moving.
inline std::vector<MarkerMotion> piston_and_bore(double e, double axial) {
  MarkerMotion i, j;
  j.axes = Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  j.position = Vec3(0.1, -0.2, 0.3);
  j.velocity = Vec3(0.3, -0.1, 0.2);
  j.angular_velocity = Vec3(0.5, -1.0, 2.0);
  i.axes = Eigen::AngleAxisd(2e-4, -j.axes.col(1)).toRotationMatrix() * j.axes;
  i.position = j.position + e * j.axes.col(0) + axial * j.axes.col(2);
  i.velocity = j.velocity + j.angular_velocity.cross(i.position - j.position) + 8.0 * j.axes.col(2) +
               0.02 * j.axes.col(0);
  i.angular_velocity = j.angular_velocity + 0.5 * j.axes.col(1);
  return {i, j};
}

}  // namespace nvh::solve::piston_liner_testing
