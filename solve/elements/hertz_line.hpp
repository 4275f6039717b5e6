#pragma once
// Line contact of two cylinders with parallel axes (a roller on a cam, a valve face on its seat ring): the
// Hertz pressure and contact width, and a force-approach law, shared by the valvetrain's contact elements.
//
// Hertz (K. L. Johnson, Contact Mechanics, Cambridge 1985, section 4.3, eqs. 4.43 and 4.45), load F (N) on a
// contact line of length L (m), relative radius R (1/R = 1/R1 + 1/R2, a concave surface's radius negative):
//   half-width  b  = sqrt(4 F R / (pi L E*)),   maximum pressure  p0 = 2 F / (pi b L) = sqrt(F E* / (pi L R)),
//   1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2.
// The approach of two bodies in line contact is not fixed by the contact alone (it depends on the bodies'
// depth); the classic engineering law is Palmgren's for steel rollers (A. Palmgren, Ball and Roller Bearing
// Engineering, 3rd ed., SKF 1959; T. A. Harris, M. N. Kotzalas, Rolling Bearing Analysis, 5th ed. 2007,
// eq. 6.46):  delta = 3.84e-5 F^0.9 / l^0.8  (mm, N, mm). Written in SI and scaled to other materials by E*
// (the law in terms of F / (E* L), which has the dimension of a length; exact for steel on steel):
//   delta = C (F / (E* L))^0.9 L^0.1,   C = 3.84e-5 * 1e-3 * 1e3^-0.8 * (E*_steel)^0.9 (SI),
//   F(delta) = E* L (delta / (C L^0.1))^(1/0.9)   (a stiffening law, exponent 10/9).
#include <cmath>
#include <numbers>

namespace nvh::solve::hertz {

/// Steel on steel as in Palmgren's law: E = 207 GPa, nu = 0.3 for both bodies (Pa).
inline constexpr double kSteelModulus = 207e9;
inline constexpr double kSteelPoisson = 0.3;

/// The contact modulus E* (Pa) of two materials.
inline double contact_modulus(double e1, double nu1, double e2, double nu2) {
  return 1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2);
}
inline double steel_contact_modulus() {
  return contact_modulus(kSteelModulus, kSteelPoisson, kSteelModulus, kSteelPoisson);
}

/// The relative radius R (m) of two radii (a concave one negative); inf (flat on flat) gives inf.
inline double relative_radius(double r1, double r2) { return 1.0 / (1.0 / r1 + 1.0 / r2); }

/// Hertz half-width b (m) and maximum pressure p0 (Pa) for force f (N) on length l (m), radius r (m), E* (Pa).
inline double half_width(double f, double l, double r, double e_star) {
  return f > 0 ? std::sqrt(4.0 * f * r / (std::numbers::pi * l * e_star)) : 0.0;
}
inline double max_pressure(double f, double l, double r, double e_star) {
  return f > 0 ? std::sqrt(f * e_star / (std::numbers::pi * l * r)) : 0.0;
}

/// Palmgren's approach law in SI, scaled by E*: the force (N) at approach delta (m) and its derivative (N/m).
class PalmgrenLine {
 public:
  PalmgrenLine(double length, double e_star) : length_(length), e_star_(e_star) {
    const double c = 3.84e-5 * 1e-3 * std::pow(1e3, -0.8) * std::pow(steel_contact_modulus(), 0.9);
    scale_ = c * std::pow(length, 0.1);
  }
  double force(double delta) const {
    return delta > 0 ? e_star_ * length_ * std::pow(delta / scale_, kExponent) : 0.0;
  }
  double stiffness(double delta) const {
    return delta > 0 ? kExponent * force(delta) / delta : 0.0;
  }
  /// The approach (m) under force f (N): the inverse of force().
  double approach(double f) const {
    return f > 0 ? scale_ * std::pow(f / (e_star_ * length_), 0.9) : 0.0;
  }
  static constexpr double kExponent = 1.0 / 0.9;

 private:
  double length_, e_star_, scale_;
};

}  // namespace nvh::solve::hertz
