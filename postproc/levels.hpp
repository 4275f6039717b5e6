#pragma once
// Levels in decibels and their reference values.
//
//   field quantities (acceleration, velocity, displacement, pressure, force):  L = 20 log10(x_rms / x_0)
//   power quantities (sound power):                                              L = 10 log10(P / P_0)
// References (ISO 1683:2015 Table 1 unless stated): acceleration 1e-6 m/s^2; velocity 1e-9 m/s (ISO 1683)
// or 5e-8 m/s (engine practice after DIN 45630-1, default here); displacement 1e-12 m;
// sound pressure 2e-5 Pa; force 1e-6 N; sound power 1e-12 W.
#include <string>

namespace nvh::postproc {

struct LevelReference {
  std::string quantity;  ///< "acceleration", ...
  double value = 1.0;    ///< x_0 (or P_0)
  std::string unit;      ///< unit of value
  std::string source;    ///< where the value comes from, stored beside every level
  bool power = false;    ///< power quantity: 10 log10 instead of 20 log10
  /// "dB re 1e-06 m/s^2" (for a PSD level: "dB re (1e-06 m/s^2)^2/Hz").
  std::string label(bool psd = false) const;
};

/// The reference of a quantity; velocity_convention is "engine" (5e-8 m/s) or "iso" (1e-9 m/s).
/// An empty or unknown quantity gives a reference of 1 in the signal's unit (source "none").
LevelReference level_reference(const std::string& quantity, const std::string& unit,
                               const std::string& velocity_convention = "engine");

/// Level of an RMS value (field) or of a power; -infinity is clamped to -400 dB so files stay finite.
double level_db(double rms_or_power, const LevelReference& ref);
/// Level of a power spectral density (unit^2/Hz) re ref^2/Hz.
double psd_level_db(double psd, const LevelReference& ref);

/// Energy sum of levels: 10 log10(sum 10^(L_i/10)).
double energy_sum_db(const double* levels, int count);

}  // namespace nvh::postproc
