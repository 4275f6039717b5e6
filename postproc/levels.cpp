#include "postproc/levels.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/error.hpp"

namespace nvh::postproc {
namespace {
constexpr double kFloorDb = -400.0;
}

std::string LevelReference::label(bool psd) const {
  std::ostringstream out;
  out << "dB re ";
  if (psd) out << "(";
  out << value << " " << unit;
  if (psd) out << ")^2/Hz";
  return out.str();
}

LevelReference level_reference(const std::string& quantity, const std::string& unit,
                               const std::string& velocity_convention) {
  if (quantity == "acceleration") return {quantity, 1e-6, "m/s^2", "ISO 1683:2015", false};
  if (quantity == "velocity") {
    if (velocity_convention == "iso") return {quantity, 1e-9, "m/s", "ISO 1683:2015", false};
    if (velocity_convention == "engine")
      return {quantity, 5e-8, "m/s", "engine practice (DIN 45630-1: rho c v0^2 = 1e-12 W/m^2 in air)", false};
    throw Error("velocity reference '" + velocity_convention +
                "': expected engine (5e-8 m/s) or iso (1e-9 m/s)");
  }
  if (quantity == "displacement") return {quantity, 1e-12, "m", "ISO 1683:2015", false};
  if (quantity == "pressure") return {quantity, 2e-5, "Pa", "ISO 1683:2015 (sound pressure in air)", false};
  if (quantity == "force") return {quantity, 1e-6, "N", "ISO 1683:2015", false};
  if (quantity == "power") return {quantity, 1e-12, "W", "ISO 1683:2015 (sound power)", true};
  return {quantity, 1.0, unit.empty() ? "1" : unit, "none (unknown quantity: re 1 signal unit)", false};
}

double level_db(double value, const LevelReference& ref) {
  const double ratio = std::abs(value) / ref.value;
  if (ratio <= 0.0) return kFloorDb;
  return std::max(kFloorDb, (ref.power ? 10.0 : 20.0) * std::log10(ratio));
}

double psd_level_db(double psd, const LevelReference& ref) {
  const double ratio = psd / (ref.power ? ref.value : ref.value * ref.value);
  if (ratio <= 0.0) return kFloorDb;
  return std::max(kFloorDb, 10.0 * std::log10(ratio));
}

double energy_sum_db(const double* levels, int count) {
  double sum = 0.0;
  for (int i = 0; i < count; ++i) sum += std::pow(10.0, levels[i] / 10.0);
  return sum > 0.0 ? std::max(kFloorDb, 10.0 * std::log10(sum)) : kFloorDb;
}

}  // namespace nvh::postproc
