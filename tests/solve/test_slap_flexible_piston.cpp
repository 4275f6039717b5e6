// The slap scene's film on the piston's skirt given as markers (`skirt`, docs/bearing.md section 18), against
// references not computed with the skirt path:
// 1. The skirt as 50 markers (5 levels x 10 angles) of the rigid piston of level (b) (slap_film.toml)
//    reproduces the rigid-skirt run over its first 20 deg (the gas-exchange TDC's thrust change: the skirt
//    crosses the clearance into the film): the markers' states enter IDA's Newton through the element's skirt
//    columns and the force transfer to the markers and back to the pin, but not the answer. Measure: the
//    pin's lateral position against 1e-3 of the clearance (30 nm, the integrator's tolerance) and the side
//    force against 1e-3 of its peak.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "common/provenance.hpp"
#include "condense/component_reader.hpp"
#include "condense/condense.hpp"
#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::column;
using testing::run_text;
using testing::shipped_scene;
using testing::signal;

constexpr double kPi = std::numbers::pi;

/// The rigid piston's skirt markers (level (b): the piston's centre of mass at the pin, body axes the
/// scene's): 5 levels along the axis (scene y) x 10 angles from the thrust side +x towards w = +z, on the
/// skirt's radius 43 mm; the `skirt` list for the element.
std::string skirt_markers(std::string& list) {
  std::ostringstream s;
  s.precision(9);
  list = "skirt = [";
  const double levels[] = {0.012, 0.002, -0.008, -0.018, -0.028};
  for (int a = 0; a < 10; ++a)
    for (int l = 0; l < 5; ++l) {
      const double th = 2 * kPi * a / 10;
      const std::string name = "sk_" + std::to_string(l) + "_" + std::to_string(36 * a);
      s << "  [[body.marker]]\n  name = \"" << name << "\"\n  at = [" << 0.043 * std::cos(th) << ", "
        << levels[l] << ", " << 0.043 * std::sin(th) << "]\n";
      list += (a + l > 0 ? ", \"piston." : "\"piston.") + name + "\"";
    }
  list += "]\n";
  return s.str();
}

TEST(SlapFlexiblePiston, SkirtMarkersOnTheRigidPistonReproduceTheRigidSkirt) {
  RunSummary rs, ms;
  const auto rigid =
      run_text(shipped_scene("slap/slap_film.toml", {{"end_cycles = 1", "end_angle_deg = 20"}}),
               "slap_skirt_rigid", &rs, "slap");
  std::string list;
  const std::string markers = skirt_markers(list);
  const std::string axis =
      "  name = \"axis\"              # the piston axis at the pin; z towards the crown, x "
      "the thrust side\n  z = [0, 1, 0]\n  x = [1, 0, 0]\n";
  const auto with_markers = run_text(
      shipped_scene("slap/slap_film.toml", {{axis, axis + markers},
                                            {"j = \"ground.bore\"\n", "j = \"ground.bore\"\n" + list},
                                            {"end_cycles = 1", "end_angle_deg = 20"}}),
      "slap_skirt_markers", &ms, "slap");
  const auto xr = column(rigid, "/markers/piston.pin/position", 0),
             xm = column(with_markers, "/markers/piston.pin/position", 0);
  const auto fr = column(rigid, "/forces/skirt/side_force"),
             fm = column(with_markers, "/forces/skirt/side_force");
  const auto load = column(with_markers, "/forces/skirt/skirt_force");
  ASSERT_EQ(xr.size(), xm.size());
  double dx = 0, df = 0, peak = 0, travel = 0, carried = 0;
  for (std::size_t k = 0; k < xr.size(); ++k) {
    dx = std::max(dx, std::abs(xr[k] - xm[k]));
    df = std::max(df, std::abs(fr[k] - fm[k]));
    peak = std::max(peak, std::abs(fr[k]));
    travel = std::max(travel, std::abs(xr[k] - xr[0]));
    carried = std::max(carried, std::abs(load[k]));
  }
  EXPECT_GT(peak, 100.0) << "the window should load the film";
  EXPECT_GT(travel, 10e-6) << "the window should move the piston across the clearance";
  EXPECT_GT(carried, 0.5 * peak) << "the skirt markers should carry the film's load";
  EXPECT_LT(dx, 30e-9);
  EXPECT_LT(df, 1e-3 * peak);
  std::printf(
      "measured: first 20 deg, skirt as 50 markers of the rigid piston against the rigid skirt: pin lateral "
      "difference %.3g m (tolerance 3e-8, pin travel %.3g m), side force difference %.3g N of peak %.5g N "
      "(tolerance 1e-3); the markers' largest load %.5g N; steps %d against %d, wall %.2f s against %.2f s\n",
      dx, travel, df, peak, carried, int(ms.statistics.steps), int(rs.statistics.steps), ms.wall_seconds,
      rs.wall_seconds);
}

/// The slap's impact (bench/slap_impact.py): the first sample after 340 deg with side force <= -10 N that
/// follows a sample with > +10 N, interpolated; the crank angle and the pin's lateral velocity there.
std::pair<double, double> impact(const std::filesystem::path& h5) {
  const auto th = column(h5, "/crank_angle_deg"), F = column(h5, "/forces/skirt/side_force"),
             v = column(h5, "/markers/piston.pin/velocity", 0);
  bool lifted = false;
  for (std::size_t k = 1; k < th.size(); ++k) {
    if (th[k] < 340) continue;
    if (F[k] > 10.0) lifted = true;
    if (lifted && F[k] <= -10.0) {
      const double w = (F[k - 1] + 10.0) / (F[k - 1] - F[k]);
      return {th[k - 1] + w * (th[k] - th[k - 1]), v[k - 1] + w * (v[k] - v[k - 1])};
    }
  }
  ADD_FAILURE() << "no impact in " << h5;
  return {0, 0};
}

TEST(SlapFlexiblePiston, StiffFlexiblePistonReproducesItsRigidTwin) {
  namespace fs = std::filesystem;
  const fs::path dir = testing::temp_path("stiff_piston");
  fs::create_directories(dir);
  const fs::path data = fs::path(NVH_SOURCE_DIR) / "testdata";
  {  // the component, stiffened, its mesh found from the temporary folder
    std::string text =
        shipped_scene("slap/piston_skirt.toml",
                      {{"mesh = \"../piston.geo\"", "mesh = \"" + (data / "piston.geo").string() + "\""},
                       {"E = 80e9", "E = 80e11"},
                       {"fmax = 30000.0", "fmax = 100000.0"}});
    std::ofstream(dir / "piston_stiff.toml") << text;
  }
  std::ostringstream quiet;
  const Logger log(quiet, "test", Verbosity::kQuiet);
  const condense::Superelement se = condense::condense_component(
      condense::read_component(dir / "piston_stiff.toml"), condense::EigenBackend::kBlockLanczos, log);
  // make_flexible_piston.py's PISTON: the rigid twin's mass properties
  const auto& in = se.inertia;
  EXPECT_NEAR(in.mass, 0.3187013, 1e-6 * 0.3187013);
  EXPECT_NEAR(in.center_of_mass.z(), 0.0093969, 1e-7);
  EXPECT_NEAR(in.inertia(0, 0), 3.024342e-4, 1e-6 * 3.024342e-4);
  EXPECT_NEAR(in.inertia(1, 1), 2.697329e-4, 1e-6 * 2.697329e-4);
  EXPECT_NEAR(in.inertia(2, 2), 3.757883e-4, 1e-6 * 3.757883e-4);
  condense::write_superelement(dir / "piston_stiff.h5", se, make_provenance("test", 0, nullptr, {}));

  RunSummary fs_, rs;
  const auto flex =
      run_text(shipped_scene("slap/slap_flexible_piston.toml",
                             {{"superelement = \"piston_skirt.h5\"",
                               "superelement = \"" + (dir / "piston_stiff.h5").string() + "\"\nmodes = 4"},
                              {"end_cycles = 1", "end_angle_deg = 370"}}),
               "slap_stiff_piston", &fs_, "slap");
  const auto twin =
      run_text(shipped_scene("slap/slap_piston_rigid.toml", {{"end_cycles = 1", "end_angle_deg = 370"}}),
               "slap_piston_twin", &rs, "slap");
  const auto [tf, vf] = impact(flex);
  const auto [tr, vr] = impact(twin);
  const double u = column(flex, "/forces/skirt/skirt_displacement").back();
  EXPECT_NEAR(tf, tr, 0.01);
  EXPECT_NEAR(vf, vr, 0.01 * std::abs(vr));
  EXPECT_GT(vr, 0.1) << "the twin should slap";
  std::printf(
      "measured: stiff flexible piston (E x 100, 4 coordinates %.0f - %.0f Hz) against its rigid twin: "
      "impact "
      "%.4f deg against %.4f deg (tolerance 0.01), v_pin %.5f m/s against %.5f m/s (%.2e relative, tolerance "
      "1e-2); skirt deformation at the end %.3g m; steps %d against %d, wall %.1f s against %.1f s\n",
      se.frequency_hz.size() ? se.frequency_hz[0] : 0.0,
      se.frequency_hz.size() > 3 ? se.frequency_hz[3] : 0.0, tf, tr, vf, vr, vf / vr - 1, u,
      int(fs_.statistics.steps), int(rs.statistics.steps), fs_.wall_seconds, rs.wall_seconds);
}

}  // namespace
}  // namespace nvh::solve
