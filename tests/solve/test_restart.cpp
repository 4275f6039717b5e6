// A run stopped by SIGTERM (Slurm's time limit) keeps its samples, writes a checkpoint and exits 3;
// `solve --restart` continues it, and the result equals an uninterrupted run within the integrator tolerance.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <numbers>

#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

std::string slider_crank(int cycles) {
  std::ifstream in(std::string(NVH_SOURCE_DIR) + "/testdata/scenes/slider_crank.toml");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  text.replace(text.find("end_cycles = 2"), 14, "end_cycles = " + std::to_string(cycles));
  text += "\n# chunks of 500 samples\n";
  text.replace(text.find("sample_rate_hz = 10000"), 22, "sample_rate_hz = 10000\nchunk_samples = 500");
  return text;
}

/// Runs `text` whole, and again stopped by SIGTERM after `seconds` then continued with --restart. Returns the
/// two results files, or an empty pair (after GTEST_SKIP) when the signal did not land inside the run.
std::pair<std::filesystem::path, std::filesystem::path> whole_and_restarted(const std::string& text,
                                                                          const std::string& name, double seconds) {
  const auto scene = testing::temp_path(name + ".toml");
  std::ofstream(scene) << text;
  const std::string solve = std::string(NVH_BINARY_DIR) + "/solve/solve ";
  const auto whole = testing::temp_path(name + "_whole.h5"), parts = testing::temp_path(name + "_parts.h5");
  EXPECT_EQ(WEXITSTATUS(std::system((solve + scene.string() + " -o " + whole.string() + " -q").c_str())), 0);

  // Stop the second run part-way with SIGTERM, then continue it.
  const int stopped = std::system(("timeout --preserve-status -s TERM " + std::to_string(seconds) + " " + solve +
                                   scene.string() + " -o " + parts.string() + " -q 2>/dev/null")
                                      .c_str());
  if (!std::filesystem::exists(parts)) {  // the signal came before the results file existed: nothing to restart
    EXPECT_EQ(WEXITSTATUS(stopped), 3);
    return {};
  }
  {
    const h5::File f = h5::File::open_read(parts);
    if (WEXITSTATUS(stopped) == 0) return {};  // the run finished before the signal
    EXPECT_EQ(WEXITSTATUS(stopped), 3);
    EXPECT_EQ(f.root().string_attribute("status"), "interrupted");
  }
  EXPECT_EQ(WEXITSTATUS(std::system((solve + scene.string() + " -o " + parts.string() + " --restart -q").c_str())), 0);
  const h5::File f = h5::File::open_read(parts);
  EXPECT_EQ(f.root().string_attribute("status"), "complete");
  return {whole, parts};
}

TEST(SolveRestart, InterruptedAndRestartedRunEqualsAnUninterruptedOne) {
  const auto [whole, parts] = whole_and_restarted(slider_crank(20), "restart", 0.5);
  if (whole.empty()) GTEST_SKIP() << "the signal did not land inside the run (machine too slow or too fast for 0.5 s)";
  const Eigen::VectorXd t1 = testing::signal(whole, "time"), t2 = testing::signal(parts, "time");
  ASSERT_EQ(t1.size(), t2.size());
  EXPECT_LT((t1 - t2).cwiseAbs().maxCoeff(), 1e-12);
  const Eigen::VectorXd y1 = testing::signal(whole, "markers/piston.pin/position", 1),
                        y2 = testing::signal(parts, "markers/piston.pin/position", 1);
  EXPECT_LT((y1 - y2).cwiseAbs().maxCoeff(), 1e-7);  // rtol 1e-8 on 0.25 m positions, accumulated
}

// Element states and the energy integrals are unknowns of the state vector: a restart continues them from the
// checkpoint. A torsional spring-damper from the driven crank to ground winds up by 2 pi per revolution (its
// twist state reaches 251 rad, far beyond any wrap), a Maxwell mount on the piston carries a damper deflection.
TEST(SolveRestart, ElementStatesAndEnergyContinueAcrossARestart) {
  const std::string elements = R"(
[[force]]
name = "coupling"
type = "torsional-spring-damper"
i = "crank.main"
j = "ground.main"
k = 10.0
d = 0.01

[[force]]
name = "mount"
type = "maxwell"
i = "piston.pin"
j = "ground.main"
k = 1e5
c = 100.0
)";
  std::string text = slider_crank(40);
  text.insert(text.find("[clock]"), elements + "\n");
  const auto [whole, parts] = whole_and_restarted(text, "restart_states", 0.6);
  if (whole.empty()) GTEST_SKIP() << "the signal did not land inside the run (machine too slow or too fast for 0.6 s)";
  const Eigen::VectorXd t = testing::signal(whole, "time");
  ASSERT_EQ(t.size(), testing::signal(parts, "time").size());
  const auto compare = [&](const std::string& dataset, double tolerance) {
    const Eigen::VectorXd a = testing::signal(whole, dataset), b = testing::signal(parts, dataset);
    ASSERT_EQ(a.size(), b.size()) << dataset;
    const double worst = (a - b).cwiseAbs().maxCoeff();
    std::printf("measured: restart, %s: largest difference %.3g (end value %.6g)\n", dataset.c_str(), worst,
                a[a.size() - 1]);
    EXPECT_LT(worst, tolerance) << dataset;
  };
  const Eigen::VectorXd twist = testing::signal(whole, "forces/coupling/states/twist");
  EXPECT_NEAR(twist[twist.size() - 1] - twist[0], 40 * 2 * std::numbers::pi, 1e-6);  // the crank's 40 turns
  compare("forces/coupling/states/twist", 1e-6);  // rad, of 251 rad (rtol 1e-8)
  // m, of a 5.4 mm deflection: the restarted run starts again at order 1 and takes other steps, so the two
  // agree to the integration error, not to round-off (the piston positions above: 1e-7 of 0.25 m)
  compare("forces/mount/states/damper_deflection", 1e-7);
  compare("energy/dissipated", 1e-6 * std::abs(testing::signal(whole, "energy/dissipated").maxCoeff()));
  compare("energy/balance", 1e-6 * std::abs(testing::signal(whole, "energy/input").cwiseAbs().maxCoeff()));
}

}  // namespace
}  // namespace nvh::solve
