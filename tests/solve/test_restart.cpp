// A run stopped by SIGTERM (Slurm's time limit) keeps its samples, writes a checkpoint and exits 3;
// `solve --restart` continues it, and the result equals an uninterrupted run within the integrator tolerance.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <random>
#include <thread>

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

/// Runs `text` whole, and again stopped by SIGTERM after `fraction` of the whole run's wall time then
/// continued with --restart. Returns the two results files, or an empty pair (after GTEST_SKIP) when the
/// signal did not land inside the run. (The signal's time follows the machine: a fixed time missed the run
/// on a machine, or a build, fast enough to finish before it.)
std::pair<std::filesystem::path, std::filesystem::path> whole_and_restarted(const std::string& text,
                                                                            const std::string& name,
                                                                            double fraction) {
  const auto scene = testing::temp_path(name + ".toml");
  std::ofstream(scene) << text;
  const std::string solve = std::string(NVH_BINARY_DIR) + "/solve/solve ";
  const auto whole = testing::temp_path(name + "_whole.h5"), parts = testing::temp_path(name + "_parts.h5");
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(WEXITSTATUS(std::system((solve + scene.string() + " -o " + whole.string() + " -q").c_str())), 0);
  const double seconds =
      fraction * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // Stop the second run part-way with SIGTERM, then continue it.
  const int stopped = std::system(("timeout --preserve-status -s TERM " + std::to_string(seconds) + " " +
                                   solve + scene.string() + " -o " + parts.string() + " -q 2>/dev/null")
                                      .c_str());
  if (!std::filesystem::exists(
          parts)) {  // the signal came before the results file existed: nothing to restart
    EXPECT_EQ(WEXITSTATUS(stopped), 3);
    return {};
  }
  {
    const h5::File f = h5::File::open_read(parts);
    if (WEXITSTATUS(stopped) == 0) return {};  // the run finished before the signal
    EXPECT_EQ(WEXITSTATUS(stopped), 3);
    EXPECT_EQ(f.root().string_attribute("status"), "interrupted");
  }
  EXPECT_EQ(
      WEXITSTATUS(std::system((solve + scene.string() + " -o " + parts.string() + " --restart -q").c_str())),
      0);
  const h5::File f = h5::File::open_read(parts);
  EXPECT_EQ(f.root().string_attribute("status"), "complete");
  return {whole, parts};
}

TEST(SolveRestart, InterruptedAndRestartedRunEqualsAnUninterruptedOne) {
  const auto [whole, parts] = whole_and_restarted(slider_crank(20), "restart", 0.6);
  if (whole.empty()) GTEST_SKIP() << "the signal did not land inside the run";
  const Eigen::VectorXd t1 = testing::signal(whole, "time"), t2 = testing::signal(parts, "time");
  ASSERT_EQ(t1.size(), t2.size());
  EXPECT_LT((t1 - t2).cwiseAbs().maxCoeff(), 1e-12);
  const Eigen::VectorXd y1 = testing::signal(whole, "markers/piston.pin/position", 1),
                        y2 = testing::signal(parts, "markers/piston.pin/position", 1);
  EXPECT_LT((y1 - y2).cwiseAbs().maxCoeff(), 1e-7);  // rtol 1e-8 on 0.25 m positions, accumulated
}

// Element states and the energy integrals are unknowns of the state vector: a restart continues them from the
// checkpoint. A torsional spring-damper from the driven crank to ground winds up by 2 pi per revolution (its
// twist state reaches 251 rad, far beyond any wrap), a Maxwell mount on the piston carries a damper
// deflection.
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
  if (whole.empty()) GTEST_SKIP() << "the signal did not land inside the run";
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

// A flexible body on a fixed axis (`axis`, solve/flexible_rotor_body.hpp) across a restart: the valvetrain's
// rocker clamped at its pivot (testdata/valvetrain/rocker_on_shaft.toml, condensed here by the condense
// tool), swinging on its return spring from 20 rad/s with its foot on a stiff spring, so that its modes ring:
// its angle, its modal coordinates and the support's force continue from the checkpoint.
TEST(SolveRestart, FlexibleBodyOnAFixedAxisContinuesAcrossARestart) {
  const auto superelement = testing::temp_path("restart_rocker_on_shaft.h5");
  ASSERT_EQ(WEXITSTATUS(
                std::system((std::string(NVH_BINARY_DIR) + "/condense/condense " + NVH_SOURCE_DIR +
                             "/testdata/valvetrain/rocker_on_shaft.toml -o " + superelement.string() + " -q")
                                .c_str())),
            0);
  const std::string text = R"([scene]
gravity = [0, -9.81, 0]
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "pivot"
  [[body.marker]]
  name = "anchor"
  at = [0.058, -0.02, 0]
[[body]]
name = "rocker"
type = "flexible"
superelement = ")" + superelement.string() +
                           R"("
axis = [0, 0, 1]
speed = 20.0
[[force]]
name = "return"
type = "torsional-spring-damper"
i = "rocker.pivot"
j = "ground.pivot"
k = 10.0
d = 0.01
[[force]]
name = "foot"
type = "spring-damper"
i = "rocker.foot"
j = "ground.anchor"
k = 1e6
d = 5.0
free_length = 0.02
[clock]
end_time = 0.15
[integrator]
rtol = 1e-8
atol = 1e-11
[output]
sample_rate_hz = 10000
chunk_samples = 200
)";
  const auto [whole, parts] = whole_and_restarted(text, "restart_flexible_rotor", 0.6);
  if (whole.empty()) GTEST_SKIP() << "the signal did not land inside the run";
  ASSERT_EQ(testing::signal(whole, "time").size(), testing::signal(parts, "time").size());
  const auto worst = [&](const std::string& dataset) {
    const Eigen::MatrixXd a = testing::matrix(whole, dataset), b = testing::matrix(parts, dataset);
    EXPECT_EQ(a.rows(), b.rows()) << dataset;
    return a.rows() == b.rows() ? (a - b).cwiseAbs().maxCoeff() : 1e300;
  };
  const double angle = (testing::signal(whole, "bodies/rocker/coordinate") -
                        testing::signal(parts, "bodies/rocker/coordinate"))
                           .cwiseAbs()
                           .maxCoeff();
  const double modal = worst("bodies/rocker/modal_coordinates"),
               support = worst("bodies/rocker/support_force");
  const double support_peak = testing::matrix(whole, "bodies/rocker/support_force").cwiseAbs().maxCoeff();
  const double swing = testing::signal(whole, "bodies/rocker/coordinate").cwiseAbs().maxCoeff(),
               modal_peak = testing::matrix(whole, "bodies/rocker/modal_coordinates").cwiseAbs().maxCoeff();
  std::printf(
      "measured: restart of a flexible body on an axis: angle %.2e rad (of %.3f), modal coordinates "
      "%.2e (of %.2e), support force %.2e N (peak %.1f N)\n",
      angle, swing, modal, modal_peak, support, support_peak);
  EXPECT_LT(angle, 1e-6 * swing);  // rad: the integration error (rtol 1e-8) accumulated over the swing
  EXPECT_LT(modal, 1e-6 * modal_peak);
  EXPECT_LT(support, 1e-6 * support_peak);  // N
}

/// Starts `solve SCENE -o OUTPUT [--restart] -q` (output to /dev/null); returns its pid.
pid_t spawn_solve(const std::filesystem::path& scene, const std::filesystem::path& output, bool restart) {
  const std::string solve = std::string(NVH_BINARY_DIR) + "/solve/solve";
  const pid_t pid = fork();
  if (pid == 0) {
    std::freopen("/dev/null", "w", stderr);
    if (restart)
      execl(solve.c_str(), solve.c_str(), scene.c_str(), "-o", output.c_str(), "--restart", "-q", nullptr);
    else
      execl(solve.c_str(), solve.c_str(), scene.c_str(), "-o", output.c_str(), "-q", nullptr);
    std::_Exit(127);
  }
  return pid;
}

/// The largest difference of the piston's position between two results files (same sample times).
double piston_difference(const std::filesystem::path& a, const std::filesystem::path& b) {
  const Eigen::VectorXd t1 = testing::signal(a, "time"), t2 = testing::signal(b, "time");
  EXPECT_EQ(t1.size(), t2.size());
  if (t1.size() != t2.size()) return 1e300;
  EXPECT_LT((t1 - t2).cwiseAbs().maxCoeff(), 1e-12);
  const Eigen::VectorXd y1 = testing::signal(a, "markers/piston.pin/position", 1),
                        y2 = testing::signal(b, "markers/piston.pin/position", 1);
  return (y1 - y2).cwiseAbs().maxCoeff();
}

// SIGKILL the moment the results file appears (before, a run killed in its first 0.2 s left a "running"
// file without a checkpoint that --restart refused): the file is born with a checkpoint at t0, and
// --restart from it gives the uninterrupted run.
TEST(SolveRestart, KilledTheMomentItsFileAppearsTheRunRestartsFromTheStart) {
  const auto scene = testing::temp_path("kill_start.toml");
  std::ofstream(scene) << slider_crank(20);
  const std::string solve = std::string(NVH_BINARY_DIR) + "/solve/solve ";
  const auto whole = testing::temp_path("kill_start_whole.h5"),
             parts = testing::temp_path("kill_start_parts.h5");
  ASSERT_EQ(WEXITSTATUS(std::system((solve + scene.string() + " -o " + whole.string() + " -q").c_str())), 0);
  std::filesystem::remove(parts);
  const pid_t pid = spawn_solve(scene, parts, false);
  const auto start = std::chrono::steady_clock::now();
  while (!std::filesystem::exists(parts) &&
         std::chrono::steady_clock::now() - start < std::chrono::seconds(20))
    std::this_thread::sleep_for(std::chrono::microseconds(100));
  ::kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before the kill";
  {
    const h5::File f = h5::File::open_read(parts);
    EXPECT_EQ(f.root().string_attribute("status"), "running");
    const Eigen::VectorXd cp = f.root().read_vector("checkpoint/time");
    ASSERT_GE(cp.size(), 1);
    EXPECT_EQ(cp[0], 0.0);
  }
  ASSERT_EQ(
      WEXITSTATUS(std::system((solve + scene.string() + " -o " + parts.string() + " --restart -q").c_str())),
      0);
  EXPECT_EQ(h5::File::open_read(parts).root().string_attribute("status"), "complete");
  const double worst = piston_difference(whole, parts);
  std::printf("measured: killed at start, restarted: largest piston difference %.3g m\n", worst);
  EXPECT_LT(worst, 1e-7);
}

// SIGKILL at four random moments of the run, each time continued with --restart (or started again when the
// file did not exist yet), then run to the end: equal to the uninterrupted run within the integrator
// tolerance (each restart starts IDA again at order 1, so not to round-off). Seeded: the same times each run.
TEST(SolveRestart, KilledAtRandomTimesAndRestartedEqualsAnUninterruptedRun) {
  const auto scene = testing::temp_path("kill_random.toml");
  std::ofstream(scene) << slider_crank(20);
  const std::string solve = std::string(NVH_BINARY_DIR) + "/solve/solve ";
  const auto whole = testing::temp_path("kill_random_whole.h5"),
             parts = testing::temp_path("kill_random_parts.h5");
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(WEXITSTATUS(std::system((solve + scene.string() + " -o " + whole.string() + " -q").c_str())), 0);
  const double whole_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::filesystem::remove(parts);
  std::mt19937 random(18);
  std::uniform_real_distribution<double> fraction(0.0, 0.6);
  int kills = 0;
  bool finished = false;
  // A kill inside HDF5's flush can leave a dataset's new extent on disk without its chunk (seen once in about
  // 30 kills of a restarted run: "cannot shrink (HDF5: addr overflow ...)" on the next --restart). That is
  // the HDF5 layer's crash consistency, not the run loop's: the restart must then refuse the file cleanly
  // (exit 1, naming it), and the run starts again from scratch.
  auto refused_cleanly = [&](int status) {
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 1) return false;
    std::printf("measured: --restart refused a file damaged by the kill; started again\n");
    std::filesystem::remove(parts);
    return true;
  };
  for (int attempt = 0; attempt < 4 && !finished; ++attempt) {
    const double after = fraction(random) * whole_s;
    const bool restart = std::filesystem::exists(parts);
    const pid_t pid = spawn_solve(scene, parts, restart);
    std::this_thread::sleep_for(std::chrono::duration<double>(after));
    ::kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    if (WIFSIGNALED(status)) {
      ++kills;
      std::printf("measured: killed %s run after %.3f s\n", restart ? "a restarted" : "a new", after);
    } else if (!(restart && refused_cleanly(status))) {
      ASSERT_EQ(WEXITSTATUS(status), 0);
      finished = true;
    }
  }
  for (int attempt = 0; attempt < 2 && !finished; ++attempt) {
    const std::string again = std::filesystem::exists(parts) ? " --restart" : "";
    const int status =
        std::system((solve + scene.string() + " -o " + parts.string() + again + " -q 2>/dev/null").c_str());
    finished = WEXITSTATUS(status) == 0;
    if (!finished) {
      ASSERT_TRUE(!again.empty() && refused_cleanly(status)) << "exit status " << status;
    }
  }
  ASSERT_TRUE(finished);
  EXPECT_EQ(h5::File::open_read(parts).root().string_attribute("status"), "complete");
  EXPECT_GE(kills, 1);
  const double worst = piston_difference(whole, parts);
  std::printf("measured: %d kills, restarted: largest piston difference %.3g m\n", kills, worst);
  EXPECT_LT(worst, 1e-7);  // as the SIGTERM restart above
}

}  // namespace
}  // namespace nvh::solve
