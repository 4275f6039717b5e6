#pragma once
// Asperity contact between two rough surfaces separated by a nominal gap h: the Greenwood-Tripp law with the
// polynomial fit of its statistical integral F_5/2 (the mixed-lubrication term of the piston-skirt film,
// skirt_film.hpp; issue 14).
//
// Greenwood and Tripp (Proc. IMechE 185 (1970-71) 625, eq. 12), for Gaussian asperity heights of composite
// standard deviation sigma, asperity density eta (1/m^2) and asperity tip radius beta (m):
//   p_c(h) = K E' F_5/2(H),   H = h / sigma,
//   K = (16 sqrt(2) pi / 15) (sigma beta eta)^2 sqrt(sigma / beta)                       (dimensionless)
// with E' the composite modulus (Pa; 1/E' = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2 in the form the roughness
// constant K above was fitted with). F_5/2 is the fifth-halves moment of the Gaussian's tail; the fit of Hu,
// Cheng, Arai, Kobayashi and Aoyama (Tribol. Trans. 37 (1994) 445) used by Arcoumanis, Ostovar and Mortier
// (SAE 970630, 1997, eq. 10) for the piston ring and skirt:
//   F_5/2(H) = 4.4086e-5 (4 - H)^6.804   for H < 4,     0 for H >= 4.
// The fit is continuous with its first six derivatives at H = 4 and increases monotonically without bound as
// H falls through 0 into negative values (the surfaces' mean planes interpenetrating): the law goes from no
// contact to hard contact without a switch. Below H = 0 it is an extrapolation of the fit (the statistical
// integral itself grows like |H|^2.5); it acts there as a stiff penalty, which is what a solver needs of it.
//
// The stored elastic energy per unit area (J/m^2): u(h) = int_h^(4 sigma) p_c dh'
//   = K E' sigma 4.4086e-5 (4 - H)^7.804 / 7.804,  so that p_c = -du/dh.
//
// Units SI: m, Pa, J/m^2.

namespace nvh::bearing {

struct GreenwoodTripp {
  double sigma = 0;    ///< m, composite RMS roughness (sqrt(sigma_1^2 + sigma_2^2)); 0: no asperity contact
  double K = 0;        ///< the roughness constant (dimensionless), see roughness_constant()
  double modulus = 0;  ///< Pa, the composite modulus E'
  bool active() const { return sigma > 0; }
};

/// K = (16 sqrt(2) pi / 15) (sigma beta eta)^2 sqrt(sigma / beta) (Greenwood and Tripp, eq. 12).
double roughness_constant(double sigma_beta_eta, double sigma_over_beta);

/// F_5/2(H) of Hu et al. (1994) and its derivative dF/dH.
struct F52 {
  double value = 0;
  double derivative = 0;
};
F52 f52(double H);

struct AsperityPressure {
  double p = 0;       ///< Pa, contact pressure
  double dp_dh = 0;   ///< Pa/m (<= 0)
  double energy = 0;  ///< J/m^2, stored elastic energy per area u(h)
};

/// The contact pressure at the nominal gap h (m, any sign). Zero for h >= 4 sigma or an inactive law.
AsperityPressure asperity_pressure(const GreenwoodTripp& law, double h);

}  // namespace nvh::bearing
