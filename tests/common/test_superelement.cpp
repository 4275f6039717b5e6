// The superelement file contract (common/superelement.hpp, docs/hdf5-format.md): a synthetic superelement
// with known values written through common's writer comes back from common's reader with every field equal
// (exactly: the values are stored as float64 and read back unchanged); the producing tool's own record
// (a callback, condense's /model) is written but is not part of what the reader needs; and a file missing a
// required dataset is an nvh::Error naming the file and the dataset's path.
#include "common/superelement.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/hdf5.hpp"
#include "common/provenance.hpp"

namespace nvh {
namespace {

namespace fs = std::filesystem;

constexpr int kN = 3;  // coordinates

// A matrix of known, distinct values: entry (i, j) = offset + 10 i + j + 0.125 (exact in binary).
Eigen::MatrixXd known(int rows, int cols, double offset) {
  Eigen::MatrixXd m(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) m(i, j) = offset + 10.0 * i + j + 0.125;
  return m;
}

PointSet points(const std::vector<std::string>& names, double offset, bool with_normals) {
  PointSet p;
  p.names = names;
  const int count = static_cast<int>(names.size());
  p.position = known(count, 3, offset);
  for (int k = 0; k < count; ++k) p.shapes.push_back(known(6, kN, offset + 100.0 * (k + 1)));
  if (with_normals) {
    p.normals = Eigen::MatrixXd::Zero(count, 3);
    for (int k = 0; k < count; ++k) p.normals(k, k % 3) = 1.0;
  }
  return p;
}

// Every field of the contract set to a value of its own.
SuperelementFile synthetic() {
  SuperelementFile se;
  se.name = "synthetic-bar";
  se.kind = "volume";
  se.method = "craig-bampton";
  se.orthonormalized = true;
  se.damping_ratio = 0.02;
  se.rigid_body_modes_removed = 6;
  se.rigid_body_modes_contained = 0;
  se.frequency_hz = Eigen::Vector3d(101.5, 202.25, 404.125);
  se.fixed_interface_hz = Eigen::Vector2d(150.5, 300.75);
  se.coordinates = {"mode 1", "mode 2", "mode 3"};
  se.mass = Eigen::MatrixXd::Identity(kN, kN);
  se.stiffness = known(kN, kN, 1e6);
  se.damping = known(kN, kN, 2.5);
  se.interfaces = points({"main1", "main2"}, 0.5, false);
  se.observers = points({"top"}, 7.0, true);
  SurfaceExport s;
  s.labels = {11, 12, 13, 14};
  s.position = known(4, 3, -1.0);
  s.normal = known(4, 3, 0.0);
  s.area = Eigen::Vector4d(1e-4, 2e-4, 3e-4, 4e-4);
  s.triangles = {{0, 1, 2}, {0, 2, 3}};
  for (int i = 0; i < 4 * 3 * kN; ++i) s.shape.push_back(0.25 * i - 3.0);
  se.surface = s;
  se.inertia.mass = 2.875;
  se.inertia.center_of_mass = Eigen::Vector3d(0.125, -0.25, 0.0625);
  se.inertia.inertia = known(3, 3, 0.001);
  se.inertia.inertia_origin = known(3, 3, 0.002);
  se.inertia.second_moment = known(3, 3, 0.003);
  se.invariants.translational = known(3, kN, -5.0);
  se.invariants.rotational = known(3, kN, -6.0);
  for (int kl = 0; kl < 9; ++kl) {
    se.invariants.position.push_back(known(kN, 1, 20.0 * kl));
    se.invariants.quadratic.push_back(known(kN, kN, 30.0 * kl));
  }
  return se;
}

void expect_same(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, const std::string& what) {
  ASSERT_EQ(a.rows(), b.rows()) << what;
  ASSERT_EQ(a.cols(), b.cols()) << what;
  EXPECT_TRUE(a == b) << what << ":\n" << a << "\nread back as\n" << b;
}

void expect_same(const PointSet& a, const PointSet& b, const std::string& what) {
  EXPECT_EQ(a.names, b.names) << what;
  expect_same(a.position, b.position, what + " position");
  ASSERT_EQ(a.shapes.size(), b.shapes.size()) << what;
  for (std::size_t k = 0; k < a.shapes.size(); ++k) expect_same(a.shapes[k], b.shapes[k], what + " shape");
  if (a.normals.rows() > 0) {
    expect_same(a.normals, b.normals, what + " normals");
  } else {
    EXPECT_EQ(b.normals.rows(), 0) << what;
  }
}

void expect_same(const SuperelementFile& a, const SuperelementFile& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.method, b.method);
  EXPECT_EQ(a.orthonormalized, b.orthonormalized);
  EXPECT_EQ(a.damping_ratio, b.damping_ratio);
  EXPECT_EQ(a.rigid_body_modes_removed, b.rigid_body_modes_removed);
  EXPECT_EQ(a.rigid_body_modes_contained, b.rigid_body_modes_contained);
  expect_same(a.frequency_hz, b.frequency_hz, "frequency_hz");
  expect_same(a.fixed_interface_hz, b.fixed_interface_hz, "fixed_interface_hz");
  EXPECT_EQ(a.coordinates, b.coordinates);
  expect_same(a.mass, b.mass, "mass");
  expect_same(a.stiffness, b.stiffness, "stiffness");
  expect_same(a.damping, b.damping, "damping");
  expect_same(a.interfaces, b.interfaces, "interfaces");
  expect_same(a.observers, b.observers, "observers");
  ASSERT_EQ(a.surface.has_value(), b.surface.has_value());
  if (a.surface) {
    const SurfaceExport &s = *a.surface, &t = *b.surface;
    EXPECT_EQ(s.labels, t.labels);
    expect_same(s.position, t.position, "surface position");
    expect_same(s.normal, t.normal, "surface normal");
    expect_same(s.area, t.area, "surface area");
    EXPECT_EQ(s.triangles, t.triangles);
    EXPECT_EQ(s.shape, t.shape);
  }
  EXPECT_EQ(a.inertia.mass, b.inertia.mass);
  expect_same(a.inertia.center_of_mass, b.inertia.center_of_mass, "center_of_mass");
  expect_same(a.inertia.inertia, b.inertia.inertia, "inertia");
  expect_same(a.inertia.inertia_origin, b.inertia.inertia_origin, "inertia_origin");
  expect_same(a.inertia.second_moment, b.inertia.second_moment, "second_moment");
  expect_same(a.invariants.translational, b.invariants.translational, "translational_coupling");
  expect_same(a.invariants.rotational, b.invariants.rotational, "rotational_coupling");
  ASSERT_EQ(a.invariants.position.size(), b.invariants.position.size());
  ASSERT_EQ(a.invariants.quadratic.size(), b.invariants.quadratic.size());
  for (std::size_t kl = 0; kl < a.invariants.position.size(); ++kl) {
    expect_same(a.invariants.position[kl], b.invariants.position[kl], "position_coupling");
    expect_same(a.invariants.quadratic[kl], b.invariants.quadratic[kl], "quadratic");
  }
}

class SuperelementFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nvh_superelement_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(SuperelementFileTest, RoundTripKeepsEveryField) {
  const SuperelementFile se = synthetic();
  const fs::path file = dir_ / "synthetic.h5";
  write_superelement(file, se, make_provenance("test", 0, nullptr, {}));
  expect_same(se, read_superelement(file));

  // The documented root attributes (docs/hdf5-format.md, "Root attributes" and provenance).
  const h5::File f = h5::File::open_read(file);
  const h5::Group& root = f.root();
  EXPECT_EQ(root.string_attribute("format"), "superelement");
  EXPECT_EQ(root.string_attribute("format_version"), kSuperelementFormatVersion);
  EXPECT_EQ(root.string_attribute("units"), "SI");
  EXPECT_EQ(root.int_attribute("coordinates"), kN);
  EXPECT_EQ(root.string_attribute("tool"), "test");
  EXPECT_FALSE(root.exists("model")) << "/model is the producing tool's record, written only by its callback";
}

TEST_F(SuperelementFileTest, WithoutSurfaceOrFixedInterfaceModes) {
  SuperelementFile se = synthetic();
  se.method = "modal";
  se.surface.reset();
  se.fixed_interface_hz.resize(0);
  se.observers = points({}, 0.0, false);  // empty lists are still written: (0,), (0, 3), (0, 6, n)
  const fs::path file = dir_ / "modal.h5";
  write_superelement(file, se, make_provenance("test", 0, nullptr, {}));
  const SuperelementFile back = read_superelement(file);
  expect_same(se, back);
  const h5::File f = h5::File::open_read(file);
  EXPECT_FALSE(f.root().exists("surface"));
  EXPECT_FALSE(f.root().exists("modes/fixed_interface_hz"));
  EXPECT_EQ(f.root().shape("observe/shape"), (std::vector<hsize_t>{0, 6, kN}));
}

TEST_F(SuperelementFileTest, TheProducersRecordGoesThroughItsCallbackAndIsIgnoredByTheReader) {
  const SuperelementFile se = synthetic();
  const fs::path file = dir_ / "with_model.h5";
  write_superelement(file, se, make_provenance("test", 0, nullptr, {}), [](h5::Group& root) {
    h5::Group model = root.create_group("model");
    model.set_attribute("nodes", std::int64_t{42});
  });
  {
    const h5::File f = h5::File::open_read(file);
    EXPECT_EQ(f.root().int_attribute("nodes", "model"), 42);
  }
  expect_same(se, read_superelement(file));
}

// Remove one dataset of a good file; reading it must name the file and that dataset.
class MissingDataset : public SuperelementFileTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(MissingDataset, IsAnErrorNamingTheFileAndThePath) {
  const std::string dataset = GetParam();
  const fs::path file = dir_ / "broken.h5";
  write_superelement(file, synthetic(), make_provenance("test", 0, nullptr, {}));
  {
    h5::File f = h5::File::open_append(file);
    ASSERT_GE(H5Ldelete(f.root().id(), dataset.c_str(), H5P_DEFAULT), 0) << dataset;
  }
  try {
    read_superelement(file);
    FAIL() << "reading a file without /" << dataset << " did not throw";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_NE(message.find("/" + dataset), std::string::npos) << message;
  }
}

INSTANTIATE_TEST_SUITE_P(Contract, MissingDataset,
                         ::testing::Values("modes/frequency_hz", "reduced/stiffness", "reduced/coordinates",
                                           "interface/shape", "observe/position", "invariants/mass",
                                           "invariants/quadratic", "surface/triangles"));

TEST_F(SuperelementFileTest, AnotherMajorVersionIsRefused) {
  const fs::path file = dir_ / "v2.h5";
  write_superelement(file, synthetic(), make_provenance("test", 0, nullptr, {}));
  {
    h5::File f = h5::File::open_append(file);
    f.root().set_attribute("format_version", "2.0");
  }
  try {
    read_superelement(file);
    FAIL() << "a format_version 2.0 file was read";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_NE(message.find("format_version 2.0 is not supported (expected 1.x)"), std::string::npos)
        << message;
  }
}

// Garbled numbers (issue 18): what no shape check sees is refused, naming the file and the dataset.
TEST_F(SuperelementFileTest, GarbledNumbersAreRefusedNamingTheDataset) {
  struct Case {
    const char* dataset;
    std::function<void(SuperelementFile&)> garble;
    const char* says;
  };
  const std::vector<Case> cases = {
      {"/reduced/mass", [](SuperelementFile& se) { se.mass(0, 1) = 0.5; }, "not symmetric"},
      {"/reduced/mass", [](SuperelementFile& se) { se.mass(2, 2) = -1.0; }, "not positive definite"},
      {"/reduced/stiffness", [](SuperelementFile& se) { se.stiffness(1, 0) = std::nan(""); }, "finite"},
      {"/modes/frequency_hz", [](SuperelementFile& se) { se.frequency_hz[1] = 1.0; }, "ascending"},
      {"/modes/frequency_hz", [](SuperelementFile& se) { se.frequency_hz[0] = -5.0; }, "non-negative"},
      {"/interface/shape", [](SuperelementFile& se) { se.interfaces.shapes[0](3, 1) = INFINITY; }, "finite"},
      {"/invariants/mass", [](SuperelementFile& se) { se.inertia.mass = 0.0; }, "positive mass"},
      {"/surface/triangles", [](SuperelementFile& se) { se.surface->triangles[0][2] = 99; }, "outside"},
  };
  for (const Case& c : cases) {
    SuperelementFile se = synthetic();
    c.garble(se);
    const fs::path file = dir_ / "garbled.h5";
    write_superelement(file, se, make_provenance("test", 0, nullptr, {}));
    try {
      read_superelement(file);
      ADD_FAILURE() << c.dataset << ": garbled numbers were read";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(file.string() + ":" + c.dataset), std::string::npos) << message;
      EXPECT_NE(message.find(c.says), std::string::npos) << message;
    }
  }
}

}  // namespace
}  // namespace nvh
