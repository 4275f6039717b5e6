// Signal readers: solve's results layout (root sample_rate_hz, /time, (n, 3) marker datasets with a unit),
// a time dataset instead of the attribute, CSV, UFF58 ASCII and binary (round trip and a hand-written
// record after the SDRL description), and the bad inputs: missing dataset, non-uniform time, NaN samples,
// columns out of range.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/hdf5.hpp"
#include "postproc/signal.hpp"
#include "postproc/uff58.hpp"

using namespace nvh::postproc;
namespace fs = std::filesystem;

namespace {

class postproc_signal : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nvh_post_signal_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// A file like solve's results: n samples at 1 kHz, a marker acceleration (n, 3) and a crank angle.
  fs::path write_results(int n = 100) {
    const fs::path path = dir_ / "results.h5";
    nvh::h5::File file = nvh::h5::File::create(path);
    nvh::h5::Group root = file.root();
    root.set_attribute("sample_rate_hz", 1000.0);
    Eigen::VectorXd t(n), angle(n);
    Eigen::MatrixXd acc(n, 3);
    for (int i = 0; i < n; ++i) {
      t[i] = i / 1000.0;
      angle[i] = 36.0 * i;
      acc.row(i) << i, 10.0 * i, 100.0 * i;
    }
    root.write("time", t);
    root.write("crank_angle_deg", angle);
    nvh::h5::Group m = root.create_group("markers/top1");
    m.write("acceleration", acc);
    m.set_attribute("unit", "m/s^2", "acceleration");
    file.commit();
    return path;
  }

  /// A file without sample_rate_hz: x and a time dataset beside it.
  fs::path write_with_time(const std::vector<double>& time, const std::vector<double>& x) {
    const fs::path path = dir_ / "timed.h5";
    nvh::h5::File file = nvh::h5::File::create(path);
    nvh::h5::Group g = file.root().create_group("signals");
    g.write("time", Eigen::Map<const Eigen::VectorXd>(time.data(), static_cast<Eigen::Index>(time.size())));
    g.write("p", Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size())));
    file.commit();
    return path;
  }

  std::string error_of(const std::string& address) {
    try {
      SignalSource::open(address).read_all();
    } catch (const nvh::Error& e) {
      return e.what();
    }
    return "(no error)";
  }

  fs::path dir_;
};

}  // namespace

TEST_F(postproc_signal, ReadsAColumnOfSolvesMarkerDataset) {
  const fs::path path = write_results();
  for (const std::string column : {"2", "z"}) {
    const SignalSource s = SignalSource::open(path.string() + ":/markers/top1/acceleration[" + column + "]");
    EXPECT_EQ(s.info().name, "markers_top1_acceleration_z");
    EXPECT_EQ(s.info().unit, "m/s^2");
    EXPECT_DOUBLE_EQ(s.info().sample_rate_hz, 1000.0);
    ASSERT_EQ(s.size(), 100);
    std::vector<double> block(10);
    s.read(40, block);
    for (int i = 0; i < 10; ++i) EXPECT_DOUBLE_EQ(block[i], 100.0 * (40 + i));
  }
  const SignalSource named = SignalSource::open("top=" + path.string() + ":/markers/top1/acceleration[x]");
  EXPECT_EQ(named.info().name, "top");
  EXPECT_DOUBLE_EQ(named.read_all()[7], 7.0);
  const SignalSource angle = SignalSource::open(path.string() + ":/crank_angle_deg");
  EXPECT_DOUBLE_EQ(angle.read_all()[99], 3564.0);
}

TEST_F(postproc_signal, SampleRateFromATimeDataset) {
  std::vector<double> t, x;
  for (int i = 0; i < 50; ++i) {
    t.push_back(0.25 + i / 512.0);
    x.push_back(std::sin(i));
  }
  const SignalSource s = SignalSource::open(write_with_time(t, x).string() + ":/signals/p");
  EXPECT_NEAR(s.info().sample_rate_hz, 512.0, 1e-9);
  EXPECT_DOUBLE_EQ(s.info().start_time_s, 0.25);
}

TEST_F(postproc_signal, BadInputsNameTheInput) {
  const fs::path path = write_results();
  std::string e = error_of(path.string() + ":/markers/top1/jerk");
  EXPECT_NE(e.find("results.h5:/markers/top1/jerk: no such dataset"), std::string::npos) << e;
  e = error_of(path.string() + ":/markers/top1/acceleration");
  EXPECT_NE(e.find("choose a column"), std::string::npos) << e;
  e = error_of(path.string() + ":/markers/top1/acceleration[3]");
  EXPECT_NE(e.find("out of range"), std::string::npos) << e;
  e = error_of((dir_ / "missing.h5").string() + ":/x");
  EXPECT_NE(e.find("not found"), std::string::npos) << e;

  std::vector<double> t, x;
  for (int i = 0; i < 50; ++i) {
    t.push_back(i / 100.0 + (i == 30 ? 0.004 : 0.0));  // one sample 0.4 steps late
    x.push_back(i == 17 ? std::numeric_limits<double>::quiet_NaN() : 1.0);
  }
  e = error_of(write_with_time(t, x).string() + ":/signals/p");
  EXPECT_NE(e.find("timed.h5:/signals/time: times are not uniformly spaced: sample 30"), std::string::npos)
      << e;
  for (int i = 0; i < 50; ++i) t[i] = i / 100.0;
  e = error_of(write_with_time(t, x).string() + ":/signals/p");
  EXPECT_NE(e.find("sample 17 is nan"), std::string::npos) << e;
}

TEST_F(postproc_signal, CsvColumns) {
  const fs::path path = dir_ / "meas.csv";
  std::ofstream(path) << "time,acc [m/s^2],p\n0.000,1.5,3\n0.002,2.5,4\n0.004,-1,5\n";
  const SignalSource s = SignalSource::open(path.string() + ":acc");
  EXPECT_EQ(s.info().unit, "m/s^2");
  EXPECT_NEAR(s.info().sample_rate_hz, 500.0, 1e-9);
  EXPECT_EQ(s.read_all(), (std::vector<double>{1.5, 2.5, -1.0}));
  std::ofstream(path) << "time,acc\n0,1\n0.002,x\n";
  const std::string e = error_of(path.string() + ":acc");
  EXPECT_NE(e.find("meas.csv:3: column 'acc': 'x' is not a finite number"), std::string::npos) << e;
}

// Issue 18 item 4: samples and times that are not finite name the CSV file and line; a time step so small
// that the rate is infinite is refused.
TEST_F(postproc_signal, NonFiniteCsvNamesTheFileAndLine) {
  const fs::path path = dir_ / "meas.csv";
  for (const std::string bad : {"inf", "-inf", "nan", "1e999"}) {
    std::ofstream(path) << "time,acc\n0,1\n0.002,2\n0.004," << bad << "\n";
    const std::string e = error_of(path.string() + ":acc");
    EXPECT_NE(e.find("meas.csv:4: column 'acc': '" + bad + "' is not a finite number"), std::string::npos)
        << e;
  }
  std::ofstream(path) << "time,acc\n0,1\n1e-320,2\n2e-320,3\n";
  const std::string e = error_of(path.string() + ":acc");
  EXPECT_NE(e.find("gives no finite sample rate"), std::string::npos) << e;
  // Finite but beyond squaring (the fuzzer's 1e308 sample gave an RMS of inf with exit 0): refused by name.
  std::ofstream(path) << "time,acc\n0,1\n0.002,-1e308\n0.004,3\n";
  const std::string big = error_of(path.string() + ":acc");
  EXPECT_NE(big.find("sample 1 is -1e+308; expected a magnitude up to 1e+150"), std::string::npos) << big;
  EXPECT_NE(big.find("meas.csv:acc"), std::string::npos) << big;
}

// Round trip: ASCII keeps 13 significant digits (E20.12), binary is exact; the sample interval survives
// (E13.6 holds 1/51200 s exactly).
TEST_F(postproc_signal, Uff58RoundTrip) {
  Uff58Record r;
  r.id1 = "top1 z";
  r.ordinate_unit = "m/s^2";
  r.ordinate_label = "acceleration";
  r.response_node = 12;
  r.response_direction = 3;
  r.abscissa_min = 0.5;
  r.abscissa_increment = 1.0 / 51200.0;
  for (int i = 0; i < 1001; ++i) r.values.push_back(std::sin(0.1 * i) * std::pow(10.0, i % 7 - 3));
  Uff58Record second = r;
  second.id1 = "second";
  for (double& v : second.values) v = -v;
  for (bool binary : {false, true}) {
    const fs::path path = dir_ / (binary ? "b.uff" : "a.uff");
    write_uff58(path, {r, second}, binary);
    const std::vector<Uff58Record> back = read_uff58(path);
    ASSERT_EQ(back.size(), 2u);
    EXPECT_EQ(back[0].id1, "top1 z");
    EXPECT_EQ(back[0].ordinate_unit, "m/s^2");
    EXPECT_EQ(back[0].response_node, 12);
    EXPECT_EQ(back[0].response_direction, 3);
    EXPECT_DOUBLE_EQ(back[0].abscissa_increment, 1.0 / 51200.0);
    EXPECT_DOUBLE_EQ(back[0].abscissa_min, 0.5);
    ASSERT_EQ(back[1].values.size(), r.values.size());
    for (std::size_t i = 0; i < r.values.size(); ++i) {
      if (binary)
        EXPECT_EQ(back[1].values[i], -r.values[i]);
      else
        EXPECT_NEAR(back[1].values[i], -r.values[i], 1e-12 * std::abs(r.values[i]));
    }
    const SignalSource s = SignalSource::open(path.string() + ":2");
    EXPECT_EQ(s.info().name, "second");
    EXPECT_DOUBLE_EQ(s.info().sample_rate_hz, 51200.0);
  }
}

// Issue 18 item 4: a dataset 58 sample or record-7 field that is not finite (inf, nan, an overflow such as
// 1e999, a subnormal increment whose rate is infinite) or a point count beyond any measurement is refused,
// naming the file and line.
TEST_F(postproc_signal, NonFiniteUff58NamesTheFileAndLine) {
  const std::string good =
      "    -1\n    58\nAccelerometer 7\nNONE\n21-Nov-26 08:00:00\nNONE\nNONE\n"
      "    1         0    0         0 NONE              7   3 NONE              0   0\n"
      "         2         4         1  0.00000E+00  1.00000E-03  0.00000E+00\n"
      "        17    0    0    0 Time                 s                   \n"
      "        12    0    0    0 Acceleration         m/s^2               \n"
      "         0    0    0    0 NONE                 NONE                \n"
      "         0    0    0    0 NONE                 NONE                \n"
      "  1.00000E+00  2.00000E+00 -3.50000E+00  4.00000E-01\n    -1\n";
  const fs::path path = dir_ / "bad.unv";
  std::ofstream(path) << good;
  EXPECT_EQ(read_uff58(path).at(0).values.size(), 4u);
  struct Case {
    std::string from, to, expected;
  };
  const std::vector<Case> cases = {
      {"-3.50000E+00", "         inf", "bad.unv:14: dataset 58: 'inf' is not a finite number (sample 2"},
      {"-3.50000E+00", "        -nan", "bad.unv:14: dataset 58: '-nan' is not a finite number"},
      {"-3.50000E+00", "       1e999", "bad.unv:14: dataset 58: '1e999' is not a finite number"},
      {"  1.00000E-03", "  1.0000E-320",
       "bad.unv:9: dataset 58: record 7: abscissa increment: '1.0000E-320'"},
      {"  1.00000E-03", "          inf", "bad.unv:9: dataset 58: record 7: abscissa increment: 'inf'"},
      {"         4         1", "     1e300         1", "bad.unv:9: dataset 58: record 7: number of points"},
      {"         4         1", "       nan         1", "bad.unv:9: dataset 58: record 7: number of points"},
  };
  for (const Case& c : cases) {
    std::string text = good;
    text.replace(text.find(c.from), c.from.size(), c.to);
    std::ofstream(path) << text;
    try {
      read_uff58(path);
      ADD_FAILURE() << "expected an error for " << c.to;
    } catch (const nvh::Error& e) {
      EXPECT_NE(std::string(e.what()).find(c.expected), std::string::npos) << e.what();
    }
  }
}

// A record written by hand after the SDRL description of dataset 58 (real single precision, 6E13.5 per line,
// even abscissa), preceded by another dataset (164, units) that must be skipped.
TEST_F(postproc_signal, ReadsHandWrittenUff58) {
  const fs::path path = dir_ / "lab.unv";
  std::ofstream(path) << "    -1\n   164\n         1SI - mks (Newton)  2\n"
                         "  1.00000000000000000E+00  1.00000000000000000E+00  1.00000000000000000E+00\n"
                         "  2.73150000000000000E+02\n    -1\n"
                         "    -1\n    58\nAccelerometer 7\nNONE\n21-Nov-26 08:00:00\nNONE\nNONE\n"
                         "    1         0    0         0 NONE              7   3 NONE              0   0\n"
                         "         2         8         1  0.00000E+00  1.00000E-03  0.00000E+00\n"
                         "        17    0    0    0 Time                 s                   \n"
                         "        12    0    0    0 Acceleration         m/s^2               \n"
                         "         0    0    0    0 NONE                 NONE                \n"
                         "         0    0    0    0 NONE                 NONE                \n"
                         "  1.00000E+00  2.00000E+00 -3.50000E+00  4.00000E-01  5.00000E+00  6.00000E+00\n"
                         "  7.00000E+00 -8.00000E+00\n    -1\n";
  const std::vector<Uff58Record> records = read_uff58(path);
  ASSERT_EQ(records.size(), 1u);
  EXPECT_EQ(records[0].id1, "Accelerometer 7");
  EXPECT_EQ(records[0].ordinate_unit, "m/s^2");
  EXPECT_EQ(records[0].response_node, 7);
  EXPECT_EQ(records[0].values, (std::vector<double>{1, 2, -3.5, 0.4, 5, 6, 7, -8}));
  const SignalSource s = SignalSource::open(path.string());
  EXPECT_DOUBLE_EQ(s.info().sample_rate_hz, 1000.0);
  // A record announcing more points than it holds is an error naming the file and line.
  std::string text;
  {
    std::ifstream in(path);
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  text.replace(text.find("         8         1"), 20, "         9         1");
  std::ofstream(path) << text;
  try {
    read_uff58(path);
    FAIL() << "expected an error";
  } catch (const nvh::Error& e) {
    EXPECT_NE(std::string(e.what()).find("lab.unv:15: dataset 58: record 7 announces 9 points, found 8"),
              std::string::npos)
        << e.what();
  }
}
