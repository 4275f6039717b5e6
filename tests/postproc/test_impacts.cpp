// postproc impacts (postproc/impacts.hpp, docs/postproc.md sections 3.8 and 4.6) against closed forms.
//
// The contact force is piecewise linear in time: zero, a ramp of slope k from a sample instant t_a to a
// plateau F_p, a ramp down at -k to zero; the impacting body's velocity and angular velocity are linear in
// time, v = v0 + a t, omega = w0 + b t. Linear interpolation between samples is then exact, so the impact
// t* = t_a + F_th / k, the release on the down ramp, the peak F_p, v(t*), omega(t*) and the energy
// 1/2 m v^2 + 1/2 J omega^2 must all come out to round-off. The same through the command line (HDF5 and CSV),
// and bad options exit with 1 naming the option and leaving no output.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/hdf5.hpp"
#include "postproc/impacts.hpp"

namespace fs = std::filesystem;
using nvh::postproc::find_impacts;
using nvh::postproc::Impact;
using nvh::postproc::ImpactOptions;

namespace {

constexpr double kFs = 1000.0;           // Hz
constexpr double kK = 2.5e5;             // N/s: ramp slope
constexpr double kV0 = -0.4, kA = 2.0;   // m/s, m/s^2
constexpr double kW0 = 3.0, kB = -10.0;  // rad/s, rad/s^2
constexpr double kM = 0.42, kJ = 3.2e-4;

/// One pulse: up from t_up (a sample instant) at kK to `peak`, held, down at -kK from t_down.
struct Pulse {
  double t_up, peak, t_down;
};
// The ramps begin and end at sample instants (peak / kK: 8 and 4 ms), so that every crossing lies between two
// samples of one linear segment.
const std::vector<Pulse> kPulses = {{0.1, 2000.0, 0.15}, {0.3, 1000.0, 0.32}};
constexpr double kEnd = 0.5;

double force_at(double t) {
  for (const Pulse& p : kPulses) {
    const double up = (t - p.t_up) * kK, down = p.peak - (t - p.t_down) * kK;
    if (t >= p.t_up && t <= p.t_down + p.peak / kK) return std::max(0.0, std::min({up, p.peak, down}));
  }
  return 0.0;
}

std::vector<double> sampled(double (*f)(double)) {
  std::vector<double> x;
  for (int i = 0; i <= static_cast<int>(kEnd * kFs); ++i) x.push_back(f(i / kFs));
  return x;
}
double velocity_at(double t) {
  return kV0 + kA * t;
}
double omega_at(double t) {
  return kW0 + kB * t;
}

TEST(postproc_impacts, PiecewiseLinearPulsesGiveTheClosedFormsToRoundOff) {
  const std::vector<double> f = sampled(force_at), v = sampled(velocity_at);
  for (const double threshold : {10.0, 333.0}) {
    ImpactOptions o;
    o.threshold = threshold;
    const std::vector<Impact> impacts = find_impacts(f, o);
    ASSERT_EQ(impacts.size(), kPulses.size()) << threshold;
    for (std::size_t e = 0; e < impacts.size(); ++e) {
      const Pulse& p = kPulses[e];
      const Impact& i = impacts[e];
      const double t = (static_cast<double>(i.sample - 1) + i.fraction) / kFs;
      const double t_release = i.release_sample / kFs;
      EXPECT_NEAR(t, p.t_up + threshold / kK, 1e-14) << "impact " << e;
      EXPECT_NEAR(t_release, p.t_down + (p.peak - threshold) / kK, 1e-14) << "release " << e;
      EXPECT_NEAR(i.peak_force, p.peak, 1e-9 * p.peak);
      EXPECT_NEAR(nvh::postproc::at_impact(i, v), velocity_at(t), 1e-14);
    }
  }
  // The other side: the force negated, direction -1, gives the same instants.
  std::vector<double> negated = f;
  for (double& x : negated) x = -x;
  ImpactOptions o;
  o.direction = -1;
  const std::vector<Impact> a = find_impacts(f, {}), b = find_impacts(negated, o);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t e = 0; e < a.size(); ++e) {
    EXPECT_EQ(a[e].sample, b[e].sample);
    EXPECT_DOUBLE_EQ(a[e].fraction, b[e].fraction);
    EXPECT_DOUBLE_EQ(a[e].peak_force, b[e].peak_force);
  }
}

TEST(postproc_impacts, ContactClosedAtTheStartOrStillClosedAtTheEnd) {
  std::vector<double> f = sampled(force_at);
  // Cut the record inside the first pulse's plateau and before the second's release: the first pulse has no
  // onset in the record (no impact), the second is not released (release_sample -1).
  const std::vector<double> cut(f.begin() + 120, f.begin() + 310);
  const std::vector<Impact> impacts = find_impacts(cut, {});
  ASSERT_EQ(impacts.size(), 1u);
  EXPECT_NEAR((static_cast<double>(impacts[0].sample - 1) + impacts[0].fraction + 120) / kFs, 0.3 + 10.0 / kK,
              1e-14);
  EXPECT_EQ(impacts[0].release_sample, -1);
  // Non-finite samples neither close nor open a contact.
  std::vector<double> gap = f;
  gap[50] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(find_impacts(gap, {}).size(), kPulses.size());
}

TEST(postproc_impacts, BadOptionsAreErrors) {
  const std::vector<double> f = sampled(force_at);
  ImpactOptions o;
  o.threshold = 0;
  EXPECT_THROW(find_impacts(f, o), nvh::Error);
  o.threshold = 10, o.direction = 2;
  EXPECT_THROW(find_impacts(f, o), nvh::Error);
}

// ---------------------------------------------------------------- the command line

struct CliRun {
  int exit_code = 0;
  std::string output;
};

class postproc_impacts_cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nvh_post_impacts_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // solve's layout: /time, /crank_angle_deg (720 deg per second), /forces/c/normal_force (the contact),
    // /bodies/b/velocity and angular_velocity (n, 3), the motion along x and about z
    const int n = static_cast<int>(kEnd * kFs) + 1;
    nvh::h5::File file = nvh::h5::File::create(dir_ / "results.h5");
    nvh::h5::Group root = file.root();
    root.set_attribute("sample_rate_hz", kFs);
    Eigen::VectorXd t(n), angle(n), force(n);
    Eigen::MatrixXd v = Eigen::MatrixXd::Zero(n, 3), w = Eigen::MatrixXd::Zero(n, 3);
    for (int i = 0; i < n; ++i) {
      t[i] = i / kFs, angle[i] = 720.0 * t[i], force[i] = force_at(t[i]);
      v(i, 0) = velocity_at(t[i]), w(i, 2) = omega_at(t[i]);
    }
    root.write("time", t);
    root.write("crank_angle_deg", angle);
    nvh::h5::Group c = root.create_group("forces/c");
    c.write("normal_force", force);
    c.set_attribute("unit", "N", "normal_force");
    nvh::h5::Group b = root.create_group("bodies/b");
    b.write("velocity", v);
    b.set_attribute("unit", "m/s", "velocity");
    b.write("angular_velocity", w);
    b.set_attribute("unit", "rad/s", "angular_velocity");
    file.commit();
  }
  void TearDown() override { fs::remove_all(dir_); }

  CliRun run(const std::string& args) {
    const std::string command = std::string(NVH_POSTPROC_EXE) + " impacts " + args + " 2>&1";
    CliRun r;
    FILE* pipe = popen(command.c_str(), "r");
    std::array<char, 512> buffer;
    while (fgets(buffer.data(), buffer.size(), pipe)) r.output += buffer.data();
    const int status = pclose(pipe);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
  }
  std::string at(const std::string& path) const { return (dir_ / "results.h5").string() + ":" + path; }
  fs::path dir_;
};

TEST_F(postproc_impacts_cli, WritesTheImpactsVelocityAndEnergyOfTheClosedForm) {
  const fs::path out = dir_ / "impacts.h5";
  const CliRun r =
      run(at("/forces/c/normal_force") + " --velocity " + at("/bodies/b/velocity[x]") +
          " --angular-velocity " + at("/bodies/b/angular_velocity[z]") + " --mass 0.42 --inertia " +
          "3.2e-4 --threshold 50 -o " + out.string() + " --csv " + (dir_ / "csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  nvh::h5::File file = nvh::h5::File::open_read(out);
  const nvh::h5::Group g = file.root().open_group("impacts/forces_c_normal_force");
  const Eigen::VectorXd t = g.read_vector("time_s"), v = g.read_vector("velocity"),
                        w = g.read_vector("angular_velocity"), e = g.read_vector("energy_j"),
                        peak = g.read_vector("peak_force"), angle = g.read_vector("crank_angle_deg"),
                        duration = g.read_vector("duration_s");
  ASSERT_EQ(t.size(), 2);
  for (int k = 0; k < 2; ++k) {
    const Pulse& p = kPulses[static_cast<std::size_t>(k)];
    const double tk = p.t_up + 50.0 / kK;
    EXPECT_NEAR(t[k], tk, 1e-14);
    EXPECT_NEAR(angle[k], 720.0 * tk, 1e-11);
    EXPECT_NEAR(v[k], velocity_at(tk), 1e-14);
    EXPECT_NEAR(w[k], omega_at(tk), 1e-13);
    EXPECT_NEAR(e[k], 0.5 * kM * velocity_at(tk) * velocity_at(tk) + 0.5 * kJ * omega_at(tk) * omega_at(tk),
                1e-15);
    EXPECT_NEAR(peak[k], p.peak, 1e-9 * p.peak);
    EXPECT_NEAR(duration[k], p.t_down + (p.peak - 50.0) / kK - tk, 1e-14);
  }
  std::ifstream csv(dir_ / "csv" / "impacts_forces_c_normal_force.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_NE(header.find("energy_J"), std::string::npos) << header;
}

TEST_F(postproc_impacts_cli, BadOptionsNameTheOptionExitWithOneAndLeaveNoOutput) {
  const fs::path out = dir_ / "impacts.h5";
  for (const auto& [args, expected] : std::vector<std::pair<std::string, std::string>>{
           {at("/forces/c/normal_force") + " --velocity " + at("/bodies/b/velocity[x]") + " --inertia 1e-3",
            "--inertia needs --angular-velocity"},
           {at("/forces/c/normal_force") + " --velocity " + at("/time") + "x", "time"},
           {at("/forces/c/normal_force") + " --velocity " + at("/bodies/b/velocity[x]") +
                " --end 0.2 --start 0.3",
            "start"},
       }) {
    const CliRun r = run(args + " -o " + out.string());
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(out)) << args;
  }
}

}  // namespace
