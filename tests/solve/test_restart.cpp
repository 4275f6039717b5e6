// A run stopped by SIGTERM (Slurm's time limit) keeps its samples, writes a checkpoint and exits 3;
// `solve --restart` continues it, and the result equals an uninterrupted run within the integrator tolerance.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

TEST(SolveRestart, InterruptedAndRestartedRunEqualsAnUninterruptedOne) {
  std::string text;
  {
    std::ifstream in(std::string(NVH_SOURCE_DIR) + "/testdata/scenes/slider_crank.toml");
    std::stringstream ss;
    ss << in.rdbuf();
    text = ss.str();
  }
  text.replace(text.find("end_cycles = 2"), 14, "end_cycles = 20");
  text += "\n# chunks of 500 samples\n";
  text.replace(text.find("sample_rate_hz = 10000"), 22, "sample_rate_hz = 10000\nchunk_samples = 500");
  const auto scene = testing::temp_path("restart.toml");
  std::ofstream(scene) << text;
  const std::string solve = std::string(NVH_BINARY_DIR) + "/solve/solve ";
  const auto whole = testing::temp_path("whole.h5"), parts = testing::temp_path("parts.h5");
  ASSERT_EQ(WEXITSTATUS(std::system((solve + scene.string() + " -o " + whole.string() + " -q").c_str())), 0);

  // Stop the second run part-way with SIGTERM, then continue it.
  const int stopped = std::system(
      ("timeout --preserve-status -s TERM 0.5 " + solve + scene.string() + " -o " + parts.string() + " -q 2>/dev/null").c_str());
  if (!std::filesystem::exists(parts)) {  // the signal came before the results file existed: nothing to restart
    EXPECT_EQ(WEXITSTATUS(stopped), 3);
    GTEST_SKIP() << "the signal arrived before the run created its output (machine too slow for 0.5 s)";
  }
  {
    const h5::File f = h5::File::open_read(parts);
    const std::string status = f.root().string_attribute("status");
    if (WEXITSTATUS(stopped) == 0) GTEST_SKIP() << "the run finished before the signal (machine too fast for 0.5 s)";
    EXPECT_EQ(WEXITSTATUS(stopped), 3);
    EXPECT_EQ(status, "interrupted");
  }
  ASSERT_EQ(WEXITSTATUS(std::system((solve + scene.string() + " -o " + parts.string() + " --restart -q").c_str())), 0);

  const Eigen::VectorXd t1 = testing::signal(whole, "time"), t2 = testing::signal(parts, "time");
  ASSERT_EQ(t1.size(), t2.size());
  EXPECT_LT((t1 - t2).cwiseAbs().maxCoeff(), 1e-12);
  const Eigen::VectorXd y1 = testing::signal(whole, "markers/piston.pin/position", 1),
                        y2 = testing::signal(parts, "markers/piston.pin/position", 1);
  EXPECT_LT((y1 - y2).cwiseAbs().maxCoeff(), 1e-7);  // rtol 1e-8 on 0.25 m positions, accumulated
  const h5::File f = h5::File::open_read(parts);
  EXPECT_EQ(f.root().string_attribute("status"), "complete");
}

}  // namespace
}  // namespace nvh::solve
