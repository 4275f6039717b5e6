// The spin-up of a flexible beam (Kane, Ryan & Banerjee, J. Guidance 10(2), 1987, section VI): a 10 m
// beam clamped to a hub that spins up to 6 rad/s in 15 s, above its first bending frequency (3.80 rad/s).
// With the geometric stiffness the tip lags by about half a metre during the spin-up and returns; a floating
// frame with linear modes alone buckles (lead-lag omega^2 = omega_1^2 - Omega^2 < 0) and diverges - the
// paper's point. Reference: an independent assumed-modes model in SciPy (testdata/rotating_beam/
// kane_spinup_reference.py: 5 clamped-free modes, M q'' + (K + Omega^2 (K_G - M)) q = -Omega' p,
// DOP853 at rtol 1e-11), not this project's code.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "common/error.hpp"
#include "common/log.hpp"
#include "common/provenance.hpp"
#include "condense/condense.hpp"
#include "solve/flexible_body.hpp"
#include "solve/integrator.hpp"
#include "solve/scene.hpp"
#include "tests/condense/beam_fixtures.hpp"

namespace nvh::solve {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;
constexpr double kOmegaS = 6.0, kRampTime = 15.0, kEndTime = 20.0;

/// Kane et al.'s beam: L = 10 m, E = 7e10 Pa, A = 4e-4 m^2, I = 2e-7 m^4 (in the plane of the spin),
/// rho = 3000 kg/m^3; Euler-Bernoulli. Out of the plane 10 times stiffer (the paper's model is planar: the
/// flap modes are not excited and only kept apart from the lead-lag ones).
void write_beam(const fs::path& file, bool stiffening) {
  condense::BeamSection s;
  s.A = 4e-4;
  s.Iz = 2e-7;
  s.Iy = 2e-6;
  s.J = 2e-6;
  s.rotary_inertia = false;
  condense::Component c =
      condense::testing::straight_beam(10.0, s, 40, condense::testing::Steel{7e10, 0.3, 3000.0});
  c.supports = {condense::testing::fixed({0, 0, 0})};
  c.interfaces = {condense::testing::point("root", {0, 0, 0})};
  c.observers = {condense::testing::point("tip", {10.0, 0, 0})};
  c.reduction.method = condense::ReductionMethod::kModal;
  c.reduction.modes = 6;  // lead-lag 1-4, flap 1-2
  c.reduction.geometric_stiffening = stiffening;
  std::ostringstream quiet;
  const Logger log(quiet, "test", Verbosity::kQuiet);
  const condense::Superelement se =
      condense::condense_component(c, condense::EigenBackend::kBlockLanczos, log);
  condense::write_superelement(file, se, make_provenance("test", 0, nullptr, {}));
}

/// The spin-up profile Omega(t) (rad/s) as the speed driver's rpm table, every 0.02 s (the driver is
/// linear between points: its angle is within 2e-5 rad of the smooth profile's).
std::string scene_text(bool stiffening, double end_time) {
  std::ostringstream s;
  s.precision(12);
  s << "[[body]]\nname = \"ground\"\ntype = \"ground\"\n[[body.marker]]\nname = \"hub\"\n\n"
    << "[[body]]\nname = \"beam\"\ntype = \"flexible\"\nsuperelement = \"beam.h5\"\n"
    << (stiffening ? "" : "geometric_stiffening = false\n")
    << "\n[[joint]]\nname = \"hub\"\ntype = \"revolute\"\ni = \"beam.root\"\nj = \"ground.hub\"\n\n"
    << "[[driver]]\nname = \"spin\"\ntype = \"speed\"\ni = \"beam.root\"\nj = \"ground.hub\"\ntable = [";
  for (int k = 0; k <= 750; ++k) {
    const double t = 0.02 * k;
    const double w = kOmegaS / kRampTime * (t - kRampTime / (2 * kPi) * std::sin(2 * kPi * t / kRampTime));
    s << (k ? ", " : "") << "[" << t << ", " << w * 30 / kPi << "]";
  }
  s << ", [" << kEndTime << ", " << kOmegaS * 30 / kPi << "]]\n\n[clock]\nend_time = " << end_time
    << "\n\n[integrator]\nrtol = 1e-8\natol = 1e-10\nvelocity_atol = 1e-6\n";
  return s.str();
}

struct Sample {
  double t, v;
};
std::vector<Sample> reference() {
  std::ifstream in(fs::path(NVH_SOURCE_DIR) / "testdata" / "rotating_beam" / "kane_spinup_reference.csv");
  std::string line;
  std::getline(in, line);
  std::vector<Sample> out;
  while (std::getline(in, line)) {
    Sample s;
    if (std::sscanf(line.c_str(), "%lf,%lf", &s.t, &s.v) == 2) out.push_back(s);
  }
  return out;
}

/// The tip's in-plane deflection (m, along the body frame's y: the direction of the spin) at the times
/// asked, until `end_time`; stops early (returning fewer samples) if the integrator fails.
std::vector<double> tip_deflection(const fs::path& dir, bool stiffening, const std::vector<Sample>& at,
                                   double end_time) {
  Scene scene = parse_scene(scene_text(stiffening, end_time), "spinup.toml", dir);
  const FlexibleData data = load_flexible_data(dir / "beam.h5");
  const auto& tip = data.points[1];
  EXPECT_EQ(tip.name, "tip");
  std::ostringstream quiet;
  const Logger log(quiet, "test", Verbosity::kQuiet);
  Eigen::VectorXd y, yp;
  scene.model.consistent_initial_state(scene.start_time, y, yp, log);
  auto integrator = make_integrator(scene.model, scene.integrator, scene.start_time, y, yp);
  std::vector<double> v;
  try {
    for (const Sample& s : at) {
      if (s.t > end_time + 1e-12) break;
      while (integrator->time() < s.t) integrator->advance(s.t, scene.end_time);
      integrator->interpolate(s.t, y, yp);
      const auto q = scene.model.positions(1, y.data());
      double d = 0.0;
      for (int k = 0; k < data.size(); ++k) d += tip.translation(1, k) * q[7 + k];
      v.push_back(d);
    }
  } catch (const Error&) {
  }
  return v;
}

TEST(KaneSpinUp, WithTheGeometricStiffnessTheTipFollowsTheAssumedModesReference) {
  const fs::path dir = fs::temp_directory_path() / ("nvh_kane_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  write_beam(dir / "beam.h5", true);
  const std::vector<Sample> ref = reference();
  ASSERT_EQ(ref.size(), 401u);
  const std::vector<double> v = tip_deflection(dir, true, ref, kEndTime);
  ASSERT_EQ(v.size(), ref.size());
  double worst = 0.0, peak = 0.0, peak_solve = 0.0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    worst = std::max(worst, std::abs(v[k] - ref[k].v));
    peak = std::max(peak, std::abs(ref[k].v));
    peak_solve = std::max(peak_solve, std::abs(v[k]));
  }
  std::printf(
      "[ Kane ] with K_G: largest tip lag %.5f m (reference %.5f m), largest difference %.2e m (%.2e of "
      "it)\n",
      peak_solve, peak, worst, worst / peak);
  EXPECT_GT(peak, 0.5);
  // Measured: 4.1e-4 of the largest lag (6 modes against 5, the FE beam against the analytic modes, the
  // floating frame's second-order terms the reference leaves out). Asserted: 2e-3.
  EXPECT_LT(worst, 2e-3 * peak);

  // Without it the floating frame buckles once Omega passes 3.80 rad/s (t ~ 9.6 s): by t = 12 s the tip
  // is far beyond the stiffened beam's largest lag (or the run has failed).
  write_beam(dir / "beam.h5", false);
  const std::vector<double> soft = tip_deflection(dir, false, ref, 12.0);
  double soft_peak = 0.0;
  for (double d : soft) soft_peak = std::max(soft_peak, std::abs(d));
  std::printf("[ Kane ] without K_G: %zu samples to t = %.2f s, largest tip deflection %.3f m\n", soft.size(),
              soft.empty() ? 0.0 : ref[soft.size() - 1].t, soft_peak);
  EXPECT_TRUE(soft.size() < 241u || soft_peak > 5.0 * peak) << soft_peak;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace nvh::solve
