// postproc erp: surface normal velocity and equivalent radiated power (docs/postproc.md sections 3.5, 4.5),
// on synthetic superelement and results files written with common/'s HDF5 and superelement code. Every
// expectation is a closed form evaluated here (1/2 rho c A v^2, the hand sum over the surface, the modal
// superposition written out as loops, the baffled piston's Rayleigh-integral power), never a number taken
// from this code.
//
// Amplitude convention: the modal velocity is eta'(t) = v sin(2 pi f t) with v the PEAK amplitude, f on a
// bin, one Hann segment; ERP at the bin (erp_bin_w), in the band (erp_band_w) and over all bins
// (overall_erp_w) must each equal 1/2 rho c sum_k A_k v_n,k^2 (= rho c sum_k A_k v_rms,k^2).
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/error.hpp"
#include "common/hdf5.hpp"
#include "common/provenance.hpp"
#include "common/superelement.hpp"
#include "tests/postproc/synthetic_superelement.hpp"
#include "postproc/analyses/erp.hpp"
#include "postproc/spectrum.hpp"
#include "postproc/surface_radiation.hpp"

namespace fs = std::filesystem;
using namespace nvh;
using namespace nvh::postproc;
using nvh::testing::superelement_with;

namespace {

constexpr double kPi = std::numbers::pi;

/// A results file as solve writes it: /time, root sample_rate_hz, /bodies/<body>/modal_velocities.
void write_results(const fs::path& path, const std::string& body, const Eigen::MatrixXd& eta_dot, double fs) {
  h5::File file = h5::File::create(path);
  h5::Group root = file.root();
  root.set_attribute("sample_rate_hz", fs);
  Eigen::VectorXd t(eta_dot.rows());
  for (Eigen::Index i = 0; i < t.size(); ++i) t[i] = static_cast<double>(i) / fs;
  root.write("time", t);
  root.set_attribute("unit", "s", "time");
  h5::Group b = root.create_group("bodies/" + body);
  b.write("modal_velocities", eta_dot);
  b.set_attribute("unit", "superelement coordinates / s", "modal_velocities");
  file.commit();
}

/// eta'_j(t) = amplitude[j] sin(2 pi f t), samples at fs.
Eigen::MatrixXd sine_velocities(const std::vector<double>& amplitude, double f, double fs, int samples) {
  Eigen::MatrixXd eta(samples, static_cast<Eigen::Index>(amplitude.size()));
  for (int i = 0; i < samples; ++i)
    for (std::size_t j = 0; j < amplitude.size(); ++j)
      eta(i, static_cast<Eigen::Index>(j)) = amplitude[j] * std::sin(2.0 * kPi * f * i / fs);
  return eta;
}

/// A flat n x n grid of nodes in z = 0 with normal +z, unequal areas, and mode shapes given per node.
SurfaceExport plate(int n, int modes, const std::function<Eigen::Vector3d(int node, int mode)>& shape) {
  SurfaceExport s;
  const int nodes = n * n;
  s.position.resize(nodes, 3);
  s.normal.resize(nodes, 3);
  s.area.resize(nodes);
  for (int k = 0; k < nodes; ++k) {
    s.labels.push_back(100 + k);
    s.position.row(k) << 0.1 * (k % n), 0.1 * (k / n), 0.0;
    s.normal.row(k) << 0.0, 0.0, 1.0;
    s.area[k] = 1e-3 * (1.0 + 0.5 * (k % 3));
  }
  s.shape.resize(static_cast<std::size_t>(nodes * 3 * modes));
  for (int k = 0; k < nodes; ++k)
    for (int d = 0; d < 3; ++d)
      for (int j = 0; j < modes; ++j) s.shape[(k * 3 + d) * modes + j] = shape(k, j)[d];
  return s;
}

class postproc_erp : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nvh_erp_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!std::getenv("NVH_KEEP_TEST_FILES")) fs::remove_all(dir_);
  }

  /// Write the inputs, run the analysis, open its output.
  h5::File run(const SurfaceExport& surface, int modes, const Eigen::MatrixXd& eta_dot, double fs,
               ErpCommand command = {}) {
    write_superelement(dir_ / "se.h5", superelement_with(surface, modes),
                       make_provenance("test", 0, nullptr, {}));
    write_results(dir_ / "results.h5", "block", eta_dot, fs);
    command.results = dir_ / "results.h5";
    command.superelement = dir_ / "se.h5";
    command.body = "block";
    command.common.output = dir_ / "erp.h5";
    run_erp(command, log_, 0, nullptr);
    return h5::File::open_read(dir_ / "erp.h5");
  }

  /// Index of the band containing f.
  static Eigen::Index band_of(const h5::Group& g, double f) {
    const Eigen::VectorXd lo = g.read_vector("lower_hz"), hi = g.read_vector("upper_hz");
    for (Eigen::Index b = 0; b < lo.size(); ++b)
      if (lo[b] <= f && f < hi[b]) return b;
    ADD_FAILURE() << "no band holds " << f << " Hz";
    return 0;
  }

  fs::path dir_;
  std::ostringstream sink_;
  Logger log_{sink_, "postproc", Verbosity::kQuiet};
};

TEST_F(postproc_erp, RigidPlateMovingUniformlyRadiatesHalfRhoCAvSquared) {
  // One "mode" whose shape is a unit translation along the normal: every node moves with v sin(2 pi f t).
  const double fs = 8192.0, f = 500.0, v = 2.5e-3;
  const SurfaceExport s = plate(6, 1, [](int, int) { return Eigen::Vector3d(0.0, 0.0, 1.0); });
  ErpCommand command;
  command.regions = {{"left", Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(0.25, 1, 1)}};
  h5::File out = run(s, 1, sine_velocities({v}, f, fs, 8192), fs, command);
  const h5::Group g = out.root().open_group("erp/block");

  const double rho_c = 1.204 * 343.2, area = s.area.sum();
  const double expected = 0.5 * rho_c * area * v * v;  // W
  const Eigen::VectorXd freq = g.read_vector("frequency_hz"), bin = g.read_vector("erp_bin_w");
  const auto k = static_cast<Eigen::Index>(std::lround(f / (freq[1] - freq[0])));
  ASSERT_DOUBLE_EQ(freq[k], f);
  EXPECT_NEAR(bin[k] / expected, 1.0, 1e-9) << "at the bin";
  const Eigen::Index b = band_of(g, f);
  EXPECT_NEAR(g.read_vector("erp_band_w")[b] / expected, 1.0, 1e-9) << "in its 1/3-octave band";
  EXPECT_NEAR(g.read_double("overall_erp_w") / expected, 1.0, 1e-9) << "over all bins";
  EXPECT_NEAR(g.read_vector("erp_level_db")[b], 10.0 * std::log10(expected / 1e-12), 1e-8);
  // Velocity level of the area-mean square velocity: v_rms = v / sqrt 2 re 5e-8 m/s.
  EXPECT_NEAR(g.read_vector("velocity_level_db")[b], 20.0 * std::log10(v / std::sqrt(2.0) / 5e-8), 1e-8);
  EXPECT_EQ(g.string_attribute("units", "erp_level_db"), "dB re 1e-12 W");
  // The region x <= 0.25 m holds 3 of the 6 columns of nodes: its share is its area's.
  double left_area = 0.0;
  for (Eigen::Index n = 0; n < s.area.size(); ++n)
    if (s.position(n, 0) <= 0.25) left_area += s.area[n];
  const h5::Group r = g.open_group("regions/left");
  EXPECT_EQ(r.read_int("node_count"), 18);
  EXPECT_NEAR(r.read_vector("erp_share")[b], left_area / area, 1e-12);
  EXPECT_NEAR(r.read_vector("velocity_level_db")[b], g.read_vector("velocity_level_db")[b], 1e-9);
}

TEST_F(postproc_erp, SingleModesErpEqualsTheHandSumOverItsSurface) {
  // A curved, unevenly meshed surface: varying normals and areas; two modes with unrelated shapes, only the
  // second one moving, so that a mix-up of columns shows.
  const int nodes = 9, modes = 2;
  SurfaceExport s;
  s.position.resize(nodes, 3);
  s.normal.resize(nodes, 3);
  s.area.resize(nodes);
  for (int k = 0; k < nodes; ++k) {
    const double phi = 0.3 * k, theta = 0.2 + 0.1 * k;
    s.labels.push_back(k + 1);
    s.normal.row(k) << std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta);
    s.position.row(k) = 0.2 * s.normal.row(k);
    s.area[k] = 1e-4 * (1.0 + k * k);
  }
  for (int k = 0; k < nodes; ++k)
    for (int d = 0; d < 3; ++d)
      for (int j = 0; j < modes; ++j) s.shape.push_back(j == 0 ? 1.0 : std::cos(1.0 + k + 2.0 * d));
  const double fs = 4096.0, f = 320.0, v = 0.7;
  h5::File out = run(s, modes, sine_velocities({0.0, v}, f, fs, 4096), fs);
  const h5::Group g = out.root().open_group("erp/block");

  double hand = 0.0;  // 1/2 rho c sum_k A_k (n_k . phi_k2 v)^2
  for (int k = 0; k < nodes; ++k) {
    double vn = 0.0;
    for (int d = 0; d < 3; ++d) vn += s.normal(k, d) * s.shape[(k * 3 + d) * modes + 1] * v;
    hand += 0.5 * 1.204 * 343.2 * s.area[k] * vn * vn;
  }
  const Eigen::VectorXd freq = g.read_vector("frequency_hz"), bin = g.read_vector("erp_bin_w");
  const auto k = static_cast<Eigen::Index>(std::lround(f / (freq[1] - freq[0])));
  EXPECT_NEAR(bin[k] / hand, 1.0, 1e-12);
  EXPECT_NEAR(g.read_double("overall_erp_w") / hand, 1.0, 1e-12);
}

TEST_F(postproc_erp, NormalVelocityIsTheModalSuperpositionOfTheModalVelocities) {
  const int nodes = 5, modes = 3, samples = 1024;
  SurfaceExport s;
  s.position = Eigen::MatrixXd::Zero(nodes, 3);
  s.normal.resize(nodes, 3);
  s.area = Eigen::VectorXd::Constant(nodes, 1e-3);
  for (int k = 0; k < nodes; ++k) {
    s.labels.push_back(k);
    s.normal.row(k) = Eigen::Vector3d(1.0 + k, -0.5 * k, 2.0).normalized().transpose();
  }
  for (int i = 0; i < nodes * 3 * modes; ++i) s.shape.push_back(std::sin(0.7 * i + 0.1));
  Eigen::MatrixXd eta(samples, modes);
  for (int i = 0; i < samples; ++i)
    for (int j = 0; j < modes; ++j) eta(i, j) = std::cos(0.01 * (j + 1) * i + j) + 0.1 * j;

  // v_n,k(t) = sum_j sum_d n_k,d Phi_(k,d),j eta'_j(t), written out.
  const Eigen::MatrixXd vn = normal_velocity(eta, surface_normal_shapes(s, modes));
  double worst = 0.0;
  for (int i = 0; i < samples; ++i)
    for (int k = 0; k < nodes; ++k) {
      double hand = 0.0;
      for (int j = 0; j < modes; ++j)
        for (int d = 0; d < 3; ++d) hand += s.normal(k, d) * s.shape[(k * 3 + d) * modes + j] * eta(i, j);
      worst = std::max(worst, std::abs(vn(i, k) - hand));
    }
  EXPECT_LT(worst, 1e-14);

  // The per-node PSD formed in modal space equals postproc's Welch PSD of the superposed time signal.
  const double fs = 1000.0;
  ErpCommand command;
  command.segment_length = 256;
  command.node_spectra = true;
  h5::File out = run(s, modes, eta, fs, command);
  const Eigen::MatrixXd node_psd = out.root().read_matrix("erp/block/node_velocity_psd");
  SpectrumOptions o;
  o.segment_length = 256;
  o.type = SpectrumType::kPsd;
  for (int k = 0; k < nodes; ++k) {
    std::vector<double> x(samples);
    for (int i = 0; i < samples; ++i) x[i] = vn(i, k);
    const Spectrum ref = welch_spectrum(x, fs, o);
    ASSERT_EQ(ref.values.size(), node_psd.cols());
    EXPECT_LT((node_psd.row(k).transpose() - ref.values).cwiseAbs().maxCoeff(), 1e-12 * ref.values.maxCoeff())
        << "node " << k;
  }
}

TEST_F(postproc_erp, BaffledCircularPistonAtHighKaRadiatesItsErp) {
  // A rigid piston of radius a in a baffle, uniform normal velocity v sin(omega t). Rayleigh integral, closed
  // form (Kinsler, Frey, Coppens, Sanders, "Fundamentals of Acoustics", 4th ed., section 7.5: radiation
  // resistance rho c pi a^2 R_1(2ka), R_1(x) = 1 - 2 J_1(x) / x):
  //   W = 1/2 rho c pi a^2 v^2 (1 - J1(2ka) / (ka)),
  // so the radiation efficiency 1 - J1(2ka)/(ka) -> 1 at ka >> 1; it lies above 1 where J1(2ka) < 0.
  // The piston face: rings of nodes, each node a sector of its ring (areas exact: sum = pi a^2).
  const double a = 0.5, rho = 1.204, c = 343.2, v = 1e-3, fs = 16384.0;
  const int rings = 12, sectors = 16;
  SurfaceExport s;
  std::vector<Eigen::Vector3d> p;
  std::vector<double> area;
  for (int r = 0; r < rings; ++r) {
    const double r0 = a * r / rings, r1 = a * (r + 1) / rings, rm = 0.5 * (r0 + r1);
    for (int q = 0; q < sectors; ++q) {
      const double phi = 2.0 * kPi * (q + 0.5) / sectors;
      p.emplace_back(rm * std::cos(phi), rm * std::sin(phi), 0.0);
      area.push_back(kPi * (r1 * r1 - r0 * r0) / sectors);
    }
  }
  const auto nodes = static_cast<Eigen::Index>(p.size());
  s.position.resize(nodes, 3);
  s.normal.resize(nodes, 3);
  s.area.resize(nodes);
  for (Eigen::Index k = 0; k < nodes; ++k) {
    s.labels.push_back(k);
    s.position.row(k) = p[static_cast<std::size_t>(k)].transpose();
    s.normal.row(k) << 0.0, 0.0, 1.0;
    s.area[k] = area[static_cast<std::size_t>(k)];
    for (int d = 0; d < 3; ++d) s.shape.push_back(d == 2 ? 1.0 : 0.0);
  }
  ASSERT_NEAR(s.area.sum(), kPi * a * a, 1e-14);
  // ka = 20 (J1(40) > 0: W below ERP) and ka = 21.5 (J1(43) < 0: W slightly above ERP).
  for (const double f : {2185.0, 2349.0}) {
    ErpCommand command;
    command.density_kg_m3 = rho;
    command.sound_speed_m_s = c;
    h5::File out = run(s, 1, sine_velocities({v}, f, fs, 16384), fs, command);
    const h5::Group g = out.root().open_group("erp/block");
    const double ka = 2.0 * kPi * f / c * a;
    const double w_piston =
        0.5 * rho * c * kPi * a * a * v * v * (1.0 - std::cyl_bessel_j(1.0, 2.0 * ka) / ka);
    const double erp = g.read_double("overall_erp_w");
    EXPECT_NEAR(erp / w_piston, 1.0, 0.03) << "ka = " << ka;
    if (std::cyl_bessel_j(1.0, 2.0 * ka) > 0.0) {
      EXPECT_GE(erp, w_piston) << "ka = " << ka;
      EXPECT_GT(erp / w_piston - 1.0, 1e-3) << "ka = " << ka << ": the difference must show";
    }
    fs::remove(dir_ / "erp.h5");
  }
}

TEST_F(postproc_erp, BadInputsAreNamedAndLeaveNoOutput) {
  const SurfaceExport s = plate(2, 1, [](int, int) { return Eigen::Vector3d(0.0, 0.0, 1.0); });
  const Eigen::MatrixXd eta = sine_velocities({1.0}, 100.0, 1024.0, 1024);
  auto expect_error = [&](ErpCommand command, const std::string& part) {
    try {
      run(s, 1, eta, 1024.0, command);
      ADD_FAILURE() << "no error, expected one naming '" << part << "'";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(dir_ / "erp.h5"));
  };
  ErpCommand outside;
  outside.regions = {{"pan", Eigen::Vector3d(5, 5, 5), Eigen::Vector3d(6, 6, 6)}};
  expect_error(outside, "--region pan: no surface node");
  // A body that is not in the results: the message names the file, the dataset and the bodies there.
  write_superelement(dir_ / "se.h5", superelement_with(s, 1), make_provenance("test", 0, nullptr, {}));
  write_results(dir_ / "results.h5", "block", eta, 1024.0);
  ErpCommand wrong;
  wrong.results = dir_ / "results.h5";
  wrong.superelement = dir_ / "se.h5";
  wrong.body = "crank";
  wrong.common.output = dir_ / "erp.h5";
  try {
    run_erp(wrong, log_, 0, nullptr);
    ADD_FAILURE() << "no error for a missing body";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/bodies/crank/modal_velocities"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("flexible bodies in the file: block"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(dir_ / "erp.h5"));
  EXPECT_THROW(parse_region("pan=0,0,0,1,1"), Error);
  EXPECT_THROW(parse_region("pan=0,0,0,1,1,x"), Error);
  EXPECT_THROW(parse_region("pan=1,0,0,0,1,1"), Error);
  const SurfaceRegion r = parse_region("oil_pan=-0.2,-0.1,-0.5,0.2,0.1,-0.3");
  EXPECT_EQ(r.name, "oil_pan");
  EXPECT_EQ(r.upper.z(), -0.3);
}

TEST_F(postproc_erp, IncludeRigidAddsTheFramesTranslationAndRotationInBodyAxes) {
  // The plate of the first test, elastically at rest; its frame turned 60 deg about global x, translating
  // along d = (0, -1, 1) with v sin(2 pi f1 t) and rocking about x with w sin(2 pi f2 t). Every node's
  // normal is the body z axis, A e_z in global axes (A from Eigen's angle-axis, not from the Euler
  // parameters): the translation gives v_n = v d . A e_z (a transposed A would give v d . A^T e_z, another
  // number); the rotation about the body x axis gives v_n,k = w y_k.
  const double fs = 8192.0, f1 = 500.0, f2 = 1000.0, v = 2e-3, w = 0.05, angle = kPi / 3.0;
  const Eigen::Vector3d d(0.0, -1.0, 1.0);
  const SurfaceExport s = plate(6, 1, [](int, int) { return Eigen::Vector3d(0.0, 0.0, 1.0); });
  const int samples = 8192;
  write_superelement(dir_ / "se.h5", superelement_with(s, 1), make_provenance("test", 0, nullptr, {}));
  write_results(dir_ / "results.h5", "block", Eigen::MatrixXd::Zero(samples, 1), fs);
  {
    h5::File file = h5::File::open_append(dir_ / "results.h5");
    h5::Group b = file.root().open_group("bodies/block");
    Eigen::MatrixXd vel = Eigen::MatrixXd::Zero(samples, 3), omega = vel, p(samples, 4);
    for (int i = 0; i < samples; ++i) {
      vel.row(i) = v * std::sin(2.0 * kPi * f1 * i / fs) * d.transpose();
      omega(i, 0) = w * std::sin(2.0 * kPi * f2 * i / fs);
      p.row(i) << std::cos(angle / 2.0), std::sin(angle / 2.0), 0.0, 0.0;
    }
    b.write("velocity", vel);
    b.write("angular_velocity", omega);
    b.write("euler_parameters", p);
  }
  ErpCommand command;
  command.results = dir_ / "results.h5";
  command.superelement = dir_ / "se.h5";
  command.body = "block";
  command.common.output = dir_ / "erp.h5";
  command.include_rigid = true;
  run_erp(command, log_, 0, nullptr);
  h5::File out = h5::File::open_read(dir_ / "erp.h5");
  const h5::Group g = out.root().open_group("erp/block");
  const Eigen::VectorXd bin = g.read_vector("erp_bin_w");
  const double rho_c = 1.204 * 343.2;
  double rocking = 0.0;
  for (Eigen::Index k = 0; k < s.area.size(); ++k)
    rocking += 0.5 * rho_c * s.area[k] * std::pow(w * s.position(k, 1), 2);
  const double vn = v * d.dot(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitX()) * Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(bin[static_cast<Eigen::Index>(f1)] / (0.5 * rho_c * s.area.sum() * vn * vn), 1.0, 1e-9);
  EXPECT_NEAR(bin[static_cast<Eigen::Index>(f2)] / rocking, 1.0, 1e-9);
  // Without the option the elastic part alone is zero.
  fs::remove(dir_ / "erp.h5");
  command.include_rigid = false;
  run_erp(command, log_, 0, nullptr);
  EXPECT_LT(h5::File::open_read(dir_ / "erp.h5").root().read_double("erp/block/overall_erp_w"), 1e-30);
}

TEST_F(postproc_erp, CommandLineWritesHdf5AndCsvAndRefusesABadRegion) {
  const SurfaceExport s = plate(4, 1, [](int, int) { return Eigen::Vector3d(0.0, 0.0, 1.0); });
  write_superelement(dir_ / "se.h5", superelement_with(s, 1), make_provenance("test", 0, nullptr, {}));
  write_results(dir_ / "results.h5", "block", sine_velocities({1e-3}, 250.0, 2048.0, 2048), 2048.0);
  const std::string base = std::string(NVH_POSTPROC_EXE) + " erp " + (dir_ / "results.h5").string() +
                           " --superelement " + (dir_ / "se.h5").string() + " --body block -q -o " +
                           (dir_ / "cli.h5").string();
  const std::string plots = (dir_ / "plots").string();
  ASSERT_EQ(std::system((base + " --csv " + (dir_ / "csv").string() + " --plot " + plots +
                         " --region 'edge=-1,-1,-1,0.05,1,1' > /dev/null")
                            .c_str()),
            0);
  EXPECT_TRUE(fs::exists(dir_ / "plots" / "erp_block.png"));
  h5::File out = h5::File::open_read(dir_ / "cli.h5");
  EXPECT_EQ(out.root().string_attribute("analysis"), "erp");
  EXPECT_TRUE(out.root().has_attribute("input_sha256"));
  EXPECT_EQ(out.root().read_int("erp/block/regions/edge/node_count"), 4);
  EXPECT_TRUE(fs::exists(dir_ / "csv" / "erp_block.csv"));
  EXPECT_TRUE(fs::exists(dir_ / "csv" / "erp_spectrum_block.csv"));
  const int status = std::system((base + "2 --region 'edge=0,0,0,1,1' 2>/dev/null").c_str());
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_FALSE(fs::exists(dir_ / "cli.h52"));
}

}  // namespace
