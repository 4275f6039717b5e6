// Which unknowns set the step (IntegratorStatistics::error_test_steps, /solver/statistics/error_test_steps
// and the run summary's "steps set by" line). Two undamped oscillators on sliders, the same initial speed,
// natural frequencies 100 x apart: BDF's local error of order k on a harmonic x = A sin(w t) is about (w
// h)^(k+1) A (Hairer & Wanner, Solving ODEs II, section V.1), so with equal speeds v = w A the fast one's
// velocity error is (w_fast / w_slow)^(k+1) = 100^(k+1) times the slow one's: it must hold IDA's error test
// in (nearly) every step. The count is per accepted step, so the counts sum to the steps.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <string>

#include "common/hdf5.hpp"
#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::num;
using testing::run_text;

constexpr double kMass = 1.0, kFastK = 1.0e7, kSlowK = 1.0e3;  // kg, N/m: 503 Hz and 5.03 Hz

std::string two_oscillators(const std::string& integrator) {
  const auto slider = [](const std::string& name, double x, double k) {
    return "[[body]]\nname = \"" + name + "\"\ntype = \"slider\"\naxis = [0, 1, 0]\nmass = " + num(kMass) +
           "\nposition = [" + num(x) +
           ", 0, 0]\nspeed = 0.1\n  [[body.marker]]\n  name = \"m\"\n  at = [0, 0, 0]\n"
           "[[force]]\nname = \"" +
           name + "_spring\"\ntype = \"spring-damper\"\ni = \"" + name + ".m\"\nj = \"ground." + name +
           "_anchor\"\nk = " + num(k) + "\nd = 0\nfree_length = 1.0\n";
  };
  return R"(
[scene]
gravity = [0, 0, 0]
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "fast_anchor"
  at = [0, -1, 0]
  [[body.marker]]
  name = "slow_anchor"
  at = [1, -1, 0]
)" + slider("fast", 0.0, kFastK) +
         slider("slow", 1.0, kSlowK) + R"(
[clock]
end_time = 0.02
[integrator]
)" + integrator +
         R"(
[output]
sample_rate_hz = 5000
)";
}

/// The share of the counted steps held by the states whose name starts with "body '<body>'".
double share_of(const Model& model, const std::vector<long>& steps, const std::string& body) {
  long mine = 0, all = 0;
  for (int k = 0; k < static_cast<int>(steps.size()); ++k) {
    all += steps[k];
    if (model.describe_state(k).rfind("body '" + body + "'", 0) == 0) mine += steps[k];
  }
  return all > 0 ? static_cast<double>(mine) / static_cast<double>(all) : 0.0;
}

TEST(ErrorTestHolders, TheFasterOscillatorSetsIdasSteps) {
  const std::string text = two_oscillators("rtol = 1e-6\natol = 1e-9\n");
  RunSummary summary;
  const auto out = run_text(text, "error_test_holders_ida", &summary);
  const Scene scene = parse_scene(text, "error_test_holders_ida.toml", ".");
  const std::vector<long>& held = summary.statistics.error_test_steps;
  ASSERT_EQ(static_cast<int>(held.size()), scene.model.size());
  EXPECT_EQ(std::accumulate(held.begin(), held.end(), 0L), summary.statistics.steps);  // one per step
  const double fast = share_of(scene.model, held, "fast");
  std::printf("measured: %ld steps, the fast oscillator held the error test in %.1f %% of them\n",
              summary.statistics.steps, 100 * fast);
  EXPECT_GT(fast, 0.95);  // 100^(k+1) larger errors: the slow one may hold only the first steps at order 1
  // The summary's words: the leading holder first, with its meaning.
  const std::string words = error_test_holders(scene.model, held);
  EXPECT_EQ(words.rfind("body 'fast' ", 0), 0u) << words;
  EXPECT_NE(words.find("(speed s')"), std::string::npos) << words;
  // The file holds the same counts, one per unknown of /checkpoint/state_names.
  h5::File file = h5::File::open_read(out);
  const h5::Group root = file.root();
  const Eigen::VectorXd stored = root.read_vector("solver/statistics/error_test_steps");
  ASSERT_EQ(stored.size(), static_cast<Eigen::Index>(held.size()));
  for (std::size_t k = 0; k < held.size(); ++k) EXPECT_EQ(stored[static_cast<Eigen::Index>(k)], held[k]);
  EXPECT_EQ(root.read_strings("checkpoint/state_names").size(), held.size());
}

TEST(ErrorTestHolders, TheSplitIntegratorCountsEachGroupsSteps) {
  // Each slider its own group (no joint ties them): every group's IDA counts its own steps, so the counts
  // still sum to the steps, and the fast group takes more of them (both restart at order 1 at each 1 ms
  // exchange, so the slow group's share stays large: measured 46 %).
  const std::string text =
      two_oscillators("method = \"split\"\nmacro_step = 1e-3\nrtol = 1e-6\natol = 1e-9\n");
  RunSummary summary;
  run_text(text, "error_test_holders_split", &summary);
  const Scene scene = parse_scene(text, "error_test_holders_split.toml", ".");
  const std::vector<long>& held = summary.statistics.error_test_steps;
  ASSERT_EQ(static_cast<int>(held.size()), scene.model.size());
  EXPECT_EQ(std::accumulate(held.begin(), held.end(), 0L), summary.statistics.steps);
  const double fast = share_of(scene.model, held, "fast"), slow = share_of(scene.model, held, "slow");
  std::printf("measured: split, %ld steps: fast %.1f %%, slow %.1f %%\n", summary.statistics.steps,
              100 * fast, 100 * slow);
  EXPECT_GT(slow, 0.0);  // its own group's steps
  EXPECT_GT(fast, slow);
  EXPECT_NEAR(fast + slow, 1.0, 1e-12);
}

TEST(ErrorTestHolders, GeneralizedAlphaCountsNothing) {
  const std::string text = two_oscillators("method = \"generalized-alpha\"\nstep = 1e-5\n");
  RunSummary summary;
  const auto out = run_text(text, "error_test_holders_galpha", &summary);
  EXPECT_TRUE(summary.statistics.error_test_steps.empty());
  const Scene scene = parse_scene(text, "error_test_holders_galpha.toml", ".");
  EXPECT_EQ(error_test_holders(scene.model, summary.statistics.error_test_steps), "");
  EXPECT_FALSE(h5::File::open_read(out).root().exists("solver/statistics/error_test_steps"));
}

}  // namespace
}  // namespace nvh::solve
