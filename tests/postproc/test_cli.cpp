// The postproc command line on synthetic result files: each subcommand writes the documented layout
// (fixed paths, units and reference attributes, format and provenance) with numbers that match the closed
// form of the signal; bad inputs (missing dataset, non-uniform time, NaN samples, a band above the Nyquist
// frequency, too short a signal) exit with 1, name the input, and leave no output behind.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <string>

#include "common/hdf5.hpp"

namespace fs = std::filesystem;

namespace {

constexpr double kPi = std::numbers::pi;

struct CliRun {
  int exit_code = 0;
  std::string output;
};

class postproc_cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nvh_post_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  CliRun run(const std::string& args) {
    const std::string command = std::string(NVH_POSTPROC_EXE) + " " + args + " 2>&1";
    CliRun r;
    FILE* pipe = popen(command.c_str(), "r");
    std::array<char, 512> buffer;
    while (fgets(buffer.data(), buffer.size(), pipe)) r.output += buffer.data();
    const int status = pclose(pipe);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
  }

  /// solve's layout: 4 s at 4096 Hz of a run-up 10 -> 40 rev/s; z acceleration = cos(theta/2) + 0.5 cos(2
  /// theta)
  /// + 0.2 sin(2 pi 500 t). `time_jitter` moves one time sample (and drops the rate attribute); `nan` puts a
  /// NaN into the signal.
  fs::path write_results(bool time_jitter = false, bool nan = false, double seconds = 4.0) {
    const fs::path path = dir_ / "results.h5";
    const double fs = 4096.0;
    const int n = static_cast<int>(seconds * fs) + 1;
    nvh::h5::File file = nvh::h5::File::create(path);
    nvh::h5::Group root = file.root();
    if (!time_jitter) root.set_attribute("sample_rate_hz", fs);
    Eigen::VectorXd t(n), angle(n);
    Eigen::MatrixXd acc = Eigen::MatrixXd::Zero(n, 3);
    for (int i = 0; i < n; ++i) {
      t[i] = i / fs + (time_jitter && i == 1000 ? 0.3 / fs : 0.0);
      const double th = 2 * kPi * (10.0 * t[i] + 30.0 * t[i] * t[i] / 8.0);
      angle[i] = th * 180 / kPi;
      acc(i, 2) = std::cos(0.5 * th) + 0.5 * std::cos(2 * th) + 0.2 * std::sin(2 * kPi * 500 * t[i]);
    }
    if (nan) acc(2000, 2) = std::numeric_limits<double>::quiet_NaN();
    root.write("time", t);
    root.write("crank_angle_deg", angle);
    nvh::h5::Group m = root.create_group("markers/top1");
    m.write("acceleration", acc);
    m.set_attribute("unit", "m/s^2", "acceleration");
    file.commit();
    return path;
  }

  std::string signal() const { return (dir_ / "results.h5").string() + ":/markers/top1/acceleration[2]"; }
  fs::path out() const { return dir_ / "post.h5"; }
  bool only_results_left() const {
    for (const auto& entry : fs::directory_iterator(dir_))
      if (entry.path().filename() != "results.h5") return false;
    return true;
  }

  fs::path dir_;
};

}  // namespace

TEST_F(postproc_cli, SpectrumWritesLevelsWithTheirReference) {
  write_results();
  const CliRun r = run("spectrum acc=" + signal() + " -o " + out().string() +
                       " --window flattop --type amplitude --resolution 4 --csv " + dir_.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  nvh::h5::File file = nvh::h5::File::open_read(out());
  const nvh::h5::Group& root = file.root();
  EXPECT_EQ(root.string_attribute("format"), "nvh-postproc");
  EXPECT_EQ(root.string_attribute("tool"), "postproc");
  const nvh::h5::Group g = root.open_group("spectrum/acc");
  const Eigen::VectorXd f = g.read_vector("frequency_hz"), a = g.read_vector("amplitude"),
                        level = g.read_vector("level_db");
  EXPECT_EQ(g.string_attribute("units", "amplitude"), "m/s^2");
  EXPECT_DOUBLE_EQ(g.double_attribute("reference", "level_db"), 1e-6);
  EXPECT_EQ(g.string_attribute("units", "level_db"), "dB re 1e-06 m/s^2");
  // The 500 Hz sine of amplitude 0.2: 0.2 peak, 20 log10(0.2 / sqrt 2 / 1e-6) dB (flat-top, 0.01 dB).
  const auto k = static_cast<Eigen::Index>(std::lround(500.0 / (f[1] - f[0])));
  EXPECT_NEAR(20 * std::log10(a[k] / 0.2), 0.0, 0.01);
  EXPECT_NEAR(level[k], 20 * std::log10(0.2 / std::sqrt(2.0) / 1e-6), 0.01);
  EXPECT_TRUE(fs::exists(dir_ / "spectrum_acc.csv"));
}

TEST_F(postproc_cli, OctaveOrdersAndStatsWriteTheirGroups) {
  write_results();
  CliRun r = run("octave " + signal() + " -o " + out().string() + " --fmin 100 --fmax 1000 --interval 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  {
    nvh::h5::File file = nvh::h5::File::open_read(out());
    const nvh::h5::Group g = file.root().open_group("octave/markers_top1_acceleration_z");
    const Eigen::VectorXd center = g.read_vector("center_hz"), level = g.read_vector("level_db");
    ASSERT_EQ(center.size(), 11);  // 100 ... 1000 Hz
    EXPECT_EQ(g.read_vector("lower_hz").size(), 11);
    EXPECT_EQ(g.read_vector("upper_hz").size(), 11);
    // The 500 Hz band holds the 0.2 sine: 20 log10(0.2/sqrt 2 / 1e-6) = 103.01 dB (0.1 dB).
    EXPECT_NEAR(level[7], 20 * std::log10(0.2 / std::sqrt(2.0) / 1e-6), 0.1);
    EXPECT_EQ(g.read_matrix("leq_db").cols(), 11);
  }
  r = run("orders " + signal() + " -o " + out().string() + " --cut");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  {
    nvh::h5::File file = nvh::h5::File::open_read(out());
    const nvh::h5::Group g = file.root().open_group("orders/markers_top1_acceleration_z");
    const Eigen::VectorXd order = g.read_vector("order"), rpm = g.read_vector("rpm");
    const Eigen::MatrixXd amp = g.read_matrix("amplitude");
    EXPECT_DOUBLE_EQ(order[1], 0.5);
    EXPECT_EQ(amp.rows(), rpm.size());
    // Orders 0.5 (amplitude 1) and 2 (0.5) in every cycle: within 0.1 % (the 500 Hz sine is not an order and
    // leaks a little into neighbouring order bins: it is checked loosely here, strictly in test_orders).
    for (Eigen::Index c = 0; c < amp.rows(); ++c) {
      EXPECT_NEAR(amp(c, 1), 1.0, 1e-2);
      EXPECT_NEAR(amp(c, 4), 0.5, 1e-2);
    }
    EXPECT_TRUE(file.root().exists("orders/cut/rpm"));
  }
  r = run("stats " + signal() + " -o " + out().string() + " --band 400 600");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  nvh::h5::File file = nvh::h5::File::open_read(out());
  const nvh::h5::Group g = file.root().open_group("stats/markers_top1_acceleration_z");
  EXPECT_NEAR(g.read_double("band_rms"), 0.2 / std::sqrt(2.0), 1e-3);
  // RMS of three incoherent components: sqrt(1/2 + 0.25/2 + 0.04/2).
  EXPECT_NEAR(g.read_double("rms"), std::sqrt(0.5 + 0.125 + 0.02), 5e-3);
}

// Options that made the tools run without bound or abort (issue 18, item 7) are refused before any FFT plan
// or allocation, naming the option and the limit: at most 16 x the signal's samples after resampling to angle
// (here 50 cycles of 720 deg in 16,385 samples), at most 2^24 samples per cycle, Leq intervals of 10 samples
// or more. Each refusal is immediate (the FFTW abort of 2^31 - 1 points, the unbounded runs of --cycle 0.01
// and --interval 1e-9).
TEST_F(postproc_cli, OptionsThatRanWithoutBoundAreRefusedNamingTheLimit) {
  write_results();
  const auto start = std::chrono::steady_clock::now();
  struct Case {
    std::string args, expected;
  };
  const Case cases[] = {
      {"orders --samples-per-cycle 2147483647", "--samples-per-cycle 2147483647: more than 262160"},
      {"orders --samples-per-cycle 1000000", "--samples-per-cycle 1000000: more than 262160"},
      {"orders --samples-per-cycle 8192", "expected at most 5243 samples per cycle"},
      {"orders --cycle 0.01", "--cycle 0.01 deg: signal"},
      {"stats --harmonics 1 --cycle 0.01", "--cycle 0.01 deg: signal"},
      {"octave --fmax 1000 --interval 1e-9", "--interval 1e-09 s: expected at least"},
      // found by the fuzzer (tests/fuzz): a resolution above Nyquist named no option
      {"spectrum --resolution 1e308", "--resolution 1e+308 Hz is coarser than the sample rate allows"},
  };
  for (const Case& c : cases) {
    const std::string sub = c.args.substr(0, c.args.find(' ')), rest = c.args.substr(c.args.find(' '));
    const CliRun r = run(sub + " " + signal() + " -o " + out().string() + rest);
    EXPECT_EQ(r.exit_code, 1) << c.args << ": " << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << ": " << r.output;
    EXPECT_TRUE(only_results_left()) << c.args;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("measured: %zu refusals in %.2f s\n", std::size(cases), seconds);
  EXPECT_LT(seconds, 30.0);
  // At the limit's side that is allowed: 5000 samples per cycle (250,000 angle samples) runs.
  const CliRun ok = run("orders " + signal() + " -o " + out().string() + " --samples-per-cycle 5000 -q");
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  // --max-order beyond an int (the fuzzer's 1.8e308 overflowed the cast to a negative bin count): the orders
  // stop at the angle's Nyquist order, as for any --max-order above it.
  const CliRun huge = run("orders " + signal() + " -o " + out().string() + " --max-order 1.7976931348623157e308 -q");
  EXPECT_EQ(huge.exit_code, 0) << huge.output;
}

// Non-finite numbers on the command line (CLI11 reads "nan" and "inf"; NaN passes every range check) and
// absurd --fraction values are usage errors naming the option (the fuzzer's --campbell-fmax nan sized a
// vector from NaN; --fraction 2147483647 left no band and named the wrong options).
TEST_F(postproc_cli, NonFiniteOptionValuesAreUsageErrorsNamingTheOption) {
  write_results();
  const std::pair<std::string, std::string> cases[] = {
      {"orders --campbell --campbell-fmax nan", "--campbell-fmax: 'nan' is not a finite number"},
      {"spectrum --start -inf", "--start: '-inf' is not a finite number"},
      {"stats --band nan 3", "--band: 'nan' is not a finite number"},
      {"octave --fraction 2147483647", "--fraction: Value 2147483647 not in range 1 to 48"},
  };
  for (const auto& [args, expected] : cases) {
    const std::string sub = args.substr(0, args.find(' ')), rest = args.substr(args.find(' '));
    const CliRun r = run(sub + " " + signal() + " -o " + out().string() + rest);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << args << ": " << r.output;
    EXPECT_TRUE(only_results_left()) << args;
  }
}

TEST_F(postproc_cli, BadInputsExitWithOneNameTheInputAndLeaveNoOutput) {
  write_results();
  CliRun r =
      run("spectrum " + (dir_ / "results.h5").string() + ":/markers/top1/jerk[2] -o " + out().string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("results.h5:/markers/top1/jerk: no such dataset"), std::string::npos) << r.output;
  EXPECT_TRUE(only_results_left());

  r = run("octave " + signal() + " -o " + out().string() + " --fmax 2000");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("band 2000 Hz has its upper edge"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Nyquist"), std::string::npos) << r.output;
  EXPECT_TRUE(only_results_left());

  r = run("spectrum " + signal() + " -o " + out().string() + " --resolution 0.1");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("too short for the asked resolution"), std::string::npos) << r.output;
  EXPECT_TRUE(only_results_left());

  write_results(/*time_jitter=*/true);
  r = run("spectrum " + signal() + " -o " + out().string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("results.h5:/time: times are not uniformly spaced: sample 1000"), std::string::npos)
      << r.output;
  EXPECT_TRUE(only_results_left());

  write_results(false, /*nan=*/true);
  r = run("octave " + signal() + " -o " + out().string() + " --fmax 1000");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("acceleration[2]': sample 2000 is nan"), std::string::npos) << r.output;
  EXPECT_TRUE(only_results_left());

  write_results(false, false, /*seconds=*/0.05);
  r = run("orders " + signal() + " -o " + out().string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("no complete 720 deg cycle"), std::string::npos) << r.output;
  EXPECT_TRUE(only_results_left());

  r = run("spectrum " + signal() + " -o " + out().string() + " --window kaiser");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("expected one of rectangular, hann, hamming, flattop, blackman-harris"),
            std::string::npos)
      << r.output;
  r = run("spectrum " + signal());
  EXPECT_EQ(r.exit_code, 2) << r.output;  // -o missing: bad command line
  EXPECT_TRUE(only_results_left());
}
