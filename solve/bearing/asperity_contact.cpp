#include "solve/bearing/asperity_contact.hpp"

#include <cmath>
#include <numbers>

namespace nvh::bearing {

namespace {
constexpr double kA = 4.4086e-5;  // Hu et al. (1994); Arcoumanis et al. (1997), eq. 10
constexpr double kExponent = 6.804;
constexpr double kHMax = 4.0;
}  // namespace

double roughness_constant(double sigma_beta_eta, double sigma_over_beta) {
  return 16 * std::numbers::sqrt2 * std::numbers::pi / 15 * sigma_beta_eta * sigma_beta_eta *
         std::sqrt(sigma_over_beta);
}

F52 f52(double H) {
  if (!(H < kHMax)) return {};
  const double s = kHMax - H;
  const double s5 = std::pow(s, kExponent - 1);
  return {kA * s5 * s, -kA * kExponent * s5};
}

AsperityPressure asperity_pressure(const GreenwoodTripp& law, double h) {
  if (!law.active()) return {};
  const double H = h / law.sigma;
  if (!(H < kHMax)) return {};
  const double s = kHMax - H, ke = law.K * law.modulus;
  const double s5 = std::pow(s, kExponent - 1);
  AsperityPressure out;
  out.p = ke * kA * s5 * s;
  out.dp_dh = -ke * kA * kExponent * s5 / law.sigma;
  out.energy = ke * law.sigma * kA * s5 * s * s / (kExponent + 1);
  return out;
}

}  // namespace nvh::bearing
