#pragma once
// Components built in code for the condense tests (no files), SI units.
#include <cmath>
#include <string>

#include "condense/component.hpp"

namespace nvh::condense::testing {

constexpr double kPi = 3.14159265358979323846;

struct Steel {
  double E = 210e9, nu = 0.3, rho = 7850.0;
  double G() const { return E / (2.0 * (1.0 + nu)); }
};

/// A straight beam along x from 0 to L with one section, `elements` elements.
inline Component straight_beam(double L, const BeamSection& section, int elements, const Steel& steel = {}) {
  Component c;
  c.name = "beam";
  c.kind = "beam";
  c.materials["steel"] = Material{"steel", steel.E, steel.nu, steel.rho};
  c.beam.material = "steel";
  c.beam.points = {Vec3{0, 0, 0}, Vec3{L, 0, 0}};
  c.beam.elements_per_segment = elements;
  c.beam.segment_sections = {section};
  c.reduction.method = ReductionMethod::kModal;
  return c;
}

inline BeamSection circle(double d, std::optional<double> shear_factor = {}) {
  BeamSection s;
  s.A = kPi * d * d / 4.0;
  s.Iy = s.Iz = kPi * std::pow(d, 4) / 64.0;
  s.J = kPi * std::pow(d, 4) / 32.0;
  s.shear_factor = shear_factor;
  return s;
}

inline BeamSection rectangle(double b, double h, std::optional<double> shear_factor = {}) {
  // b along local y, h along local z. J: Saint-Venant approximation (only torsion uses it).
  BeamSection s;
  s.A = b * h;
  s.Iz = h * b * b * b / 12.0;
  s.Iy = b * h * h * h / 12.0;
  const double a = std::max(b, h), t = std::min(b, h);
  s.J = a * t * t * t * (1.0 / 3.0 - 0.21 * t / a * (1.0 - std::pow(t / a, 4) / 12.0));
  s.shear_factor = shear_factor;
  return s;
}

inline Support fixed(const Vec3& at, const std::string& dofs_mask = "111111") {
  Support s;
  s.at = at;
  for (int d = 0; d < 6; ++d) s.dofs[d] = dofs_mask[d] == '1';
  return s;
}

inline NamedPoint point(const std::string& name, const Vec3& at) {
  NamedPoint p;
  p.name = name;
  p.at = at;
  p.path = name;
  return p;
}

/// An L-shaped, free frame of two round bars with a point mass at the corner on a rigid link: modes
/// couple bending, torsion and axial motion, so the reduction has real work to do.
inline Component frame(int elements_per_segment = 16) {
  Component c = straight_beam(0.8, circle(0.03, 0.9), elements_per_segment);
  c.beam.points = {Vec3{0, 0, 0}, Vec3{0.8, 0, 0}, Vec3{0.8, 0.5, 0.1}};
  c.beam.segment_sections = {circle(0.03, 0.9), circle(0.02, 0.9)};
  c.beam.rigid_links = {RigidLink{{0.8, 0, 0}, {0.8, -0.05, 0.02}, {}, {}}};
  c.beam.masses = {PointMass{{0.8, -0.05, 0.02}, 1.5, {2e-3, 3e-3, 4e-3}, {}, {}}};
  c.interfaces = {point("a", {0, 0, 0}), point("b", {0.8, 0.5, 0.1})};
  return c;
}


/// Lower root (bending branch) of the simply supported Timoshenko frequency equation, Hz.
inline double timoshenko_ss_hz(int n, double L, const BeamSection& s, const Steel& steel) {
  const double k = n * kPi / L;
  const double kGA = *s.shear_factor * steel.G() * s.A;
  const double EI = steel.E * s.Iz, rA = steel.rho * s.A, rI = steel.rho * s.Iz;
  // (kGA k^2 - rA x)(EI k^2 + kGA - rI x) - (kGA k)^2 = 0 with x = omega^2.
  const double a = rA * rI;
  const double b = -(rA * (EI * k * k + kGA) + rI * kGA * k * k);
  const double c = kGA * k * k * (EI * k * k + kGA) - kGA * kGA * k * k;
  const double x = (-b - std::sqrt(b * b - 4.0 * a * c)) / (2.0 * a);
  return std::sqrt(x) / (2.0 * kPi);
}

/// Euler-Bernoulli simply supported beam, mode n, Hz: k^2 sqrt(EI / (rho A)) / 2 pi, k = n pi / L.
inline double euler_bernoulli_ss_hz(int n, double L, const BeamSection& s, const Steel& steel) {
  const double k = n * kPi / L;
  return k * k * std::sqrt(steel.E * s.Iz / (steel.rho * s.A)) / (2.0 * kPi);
}

}  // namespace nvh::condense::testing
