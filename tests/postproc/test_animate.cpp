// postproc animate: a flexible body's deformed surface as XDMF 3 + HDF5 for ParaView (docs/postproc.md
// section 3.6), on synthetic superelement and results files. The XDMF is parsed here by a minimal XML
// reader and every DataItem followed into the HDF5 file: the dataset exists with the declared dimensions,
// number type and precision; the frames' times are the results' times; a frame's displacement and normal
// velocity equal the modal superposition written out as loops here (the rigid-body motion through Eigen's
// quaternion, not the code's A(p)); the topology's indices lie within the geometry's nodes.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/error.hpp"
#include "common/hdf5.hpp"
#include "common/provenance.hpp"
#include "common/superelement.hpp"
#include "tests/postproc/synthetic_superelement.hpp"
#include "postproc/analyses/animate.hpp"

namespace fs = std::filesystem;
using namespace nvh;
using namespace nvh::postproc;
using nvh::testing::superelement_with;

namespace {

// --- a minimal XML reader: elements, double-quoted attributes, text; enough for the XDMF written here ---
struct XmlNode {
  std::string tag;
  std::map<std::string, std::string> attributes;
  std::string text;
  std::vector<std::unique_ptr<XmlNode>> children;
  std::vector<const XmlNode*> all(const std::string& t) const {
    std::vector<const XmlNode*> out;
    for (const auto& c : children)
      if (c->tag == t) out.push_back(c.get());
    return out;
  }
  const XmlNode& one(const std::string& t) const {
    const auto v = all(t);
    if (v.size() != 1)
      throw std::runtime_error("<" + tag + "> has " + std::to_string(v.size()) + " <" + t + ">");
    return *v.front();
  }
};

std::unique_ptr<XmlNode> parse_xml(const std::string& s) {
  auto root = std::make_unique<XmlNode>();
  std::vector<XmlNode*> stack{root.get()};
  std::size_t i = 0;
  while (i < s.size()) {
    if (s[i] != '<') {
      const std::size_t j = s.find('<', i);
      stack.back()->text += s.substr(i, j - i);
      i = j;
      continue;
    }
    const std::size_t j = s.find('>', i);
    if (j == std::string::npos) throw std::runtime_error("unterminated tag");
    std::string tag = s.substr(i + 1, j - i - 1);
    i = j + 1;
    if (tag.front() == '?' || tag.front() == '!') continue;
    if (tag.front() == '/') {
      if (stack.size() < 2 || stack.back()->tag != tag.substr(1))
        throw std::runtime_error("mismatched </" + tag.substr(1) + ">");
      stack.pop_back();
      continue;
    }
    const bool closed = tag.back() == '/';
    if (closed) tag.pop_back();
    auto node = std::make_unique<XmlNode>();
    std::size_t k = tag.find_first_of(" \t\n");
    node->tag = tag.substr(0, k);
    while (k != std::string::npos && k < tag.size()) {
      const std::size_t eq = tag.find('=', k);
      if (eq == std::string::npos) break;
      const std::size_t q1 = tag.find('"', eq), q2 = tag.find('"', q1 + 1);
      std::string name = tag.substr(k, eq - k);
      name.erase(0, name.find_first_not_of(" \t\n"));
      node->attributes[name] = tag.substr(q1 + 1, q2 - q1 - 1);
      k = q2 + 1;
    }
    XmlNode* raw = node.get();
    stack.back()->children.push_back(std::move(node));
    if (!closed) stack.push_back(raw);
  }
  if (stack.size() != 1) throw std::runtime_error("unclosed <" + stack.back()->tag + ">");
  return root;
}

std::vector<hsize_t> dims_of(const std::string& text) {
  std::istringstream in(text);
  std::vector<hsize_t> d;
  for (hsize_t v; in >> v;) d.push_back(v);
  return d;
}

// --- synthetic inputs ---
constexpr int kGrid = 4;  // 4 x 4 nodes, 18 triangles
constexpr int kSeModes = 4, kModes = 3;

/// A curved patch: varying normals and areas, triangles of a 4 x 4 grid, shapes unrelated per node and mode.
SurfaceExport curved_surface() {
  SurfaceExport s;
  const int nodes = kGrid * kGrid;
  s.position.resize(nodes, 3);
  s.normal.resize(nodes, 3);
  s.area.resize(nodes);
  for (int k = 0; k < nodes; ++k) {
    const double x = 0.1 * (k % kGrid), y = 0.1 * (k / kGrid);
    s.labels.push_back(1000 + k);
    s.position.row(k) << x, y, 0.3 * x * x - 0.2 * y;
    s.normal.row(k) = Eigen::Vector3d(-0.6 * x, 0.2, 1.0).normalized().transpose();
    s.area[k] = 1e-3 * (1.0 + 0.1 * k);
  }
  for (int r = 0; r + 1 < kGrid; ++r)
    for (int c = 0; c + 1 < kGrid; ++c) {
      const int a = r * kGrid + c;
      s.triangles.push_back({a, a + 1, a + kGrid + 1});
      s.triangles.push_back({a, a + kGrid + 1, a + kGrid});
    }
  for (int i = 0; i < nodes * 3 * kSeModes; ++i) s.shape.push_back(std::sin(0.37 * i + 0.2) * 1e-2);
  return s;
}

/// What solve writes for a flexible body (docs/results-format.md), with arbitrary smooth histories.
struct Results {
  double fs = 1000.0, t0 = 0.25;
  int samples = 101;
  Eigen::VectorXd time, angle;
  Eigen::MatrixXd eta, eta_dot, position, euler, velocity, omega;
  Results() {
    time.resize(samples);
    angle.resize(samples);
    eta.resize(samples, kModes);
    eta_dot.resize(samples, kModes);
    position.resize(samples, 3);
    euler.resize(samples, 4);
    velocity.resize(samples, 3);
    omega.resize(samples, 3);
    for (int i = 0; i < samples; ++i) {
      const double t = t0 + i / fs;
      time[i] = t;
      angle[i] = 18000.0 * t;  // 3000 rpm
      for (int j = 0; j < kModes; ++j) {
        eta(i, j) = std::cos(40.0 * (j + 1) * t + j) * (1.0 + j);
        eta_dot(i, j) = std::sin(25.0 * (j + 2) * t - j) * 0.3;
      }
      position.row(i) << 0.1 + 0.01 * t, -0.2, 0.5 + 0.002 * std::sin(30.0 * t);
      const Eigen::Vector3d axis = Eigen::Vector3d(1.0, -2.0, 0.5 + t).normalized();
      const double half = 0.5 * (0.3 + 2.0 * t);
      euler.row(i) << std::cos(half), std::sin(half) * axis.transpose();
      velocity.row(i) << 0.01, 0.02 * t, -0.03;
      omega.row(i) << 0.5, -1.0 + t, 2.0;
    }
  }
  void write(const fs::path& path, bool with_angle = true) const {
    h5::File file = h5::File::create(path);
    h5::Group root = file.root();
    root.set_attribute("sample_rate_hz", fs);
    root.write("time", time);
    root.set_attribute("unit", "s", "time");
    if (with_angle) root.write("crank_angle_deg", angle);
    h5::Group b = root.create_group("bodies/block");
    b.write("modal_coordinates", eta);
    b.write("modal_velocities", eta_dot);
    b.write("position", position);
    b.write("euler_parameters", euler);
    b.write("velocity", velocity);
    b.write("angular_velocity", omega);
    file.commit();
  }
};

/// The samples an animation of [first, last] with at most `n` frames must show: evenly spaced by the
/// smallest stride that keeps their number within n.
std::vector<int> expected_frames(int first, int last, int n) {
  for (int stride = 1;; ++stride) {
    std::vector<int> f;
    for (int i = first; i <= last; i += stride) f.push_back(i);
    if (static_cast<int>(f.size()) <= n) return f;
  }
}

class postproc_animate : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nvh_animate_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    write_superelement(dir_ / "se.h5", superelement_with(surface_, kSeModes),
                       make_provenance("test", 0, nullptr, {}));
    results_.write(dir_ / "results.h5");
  }
  void TearDown() override {
    if (!std::getenv("NVH_KEEP_TEST_FILES")) fs::remove_all(dir_);
  }
  AnimateCommand command() const {
    AnimateCommand c;
    c.results = dir_ / "results.h5";
    c.superelement = dir_ / "se.h5";
    c.body = "block";
    c.output = dir_ / "anim.xdmf";
    return c;
  }
  std::unique_ptr<XmlNode> read_xdmf() const {
    std::ifstream in(dir_ / "anim.xdmf");
    std::stringstream text;
    text << in.rdbuf();
    return parse_xml(text.str());
  }
  /// Follow a DataItem into the HDF5 file: the file name, the dataset, its dims, number type and precision.
  std::vector<double> follow(const XmlNode& item, const h5::File& h5, std::vector<hsize_t>& dims) const {
    EXPECT_EQ(item.tag, "DataItem");
    EXPECT_EQ(item.attributes.at("Format"), "HDF");
    const std::string ref = item.text;
    const std::size_t colon = ref.find(':');
    EXPECT_EQ(ref.substr(0, colon), "anim.h5");
    const std::string path = ref.substr(colon + 1);
    EXPECT_TRUE(h5.root().exists(path)) << path;
    dims = h5.root().shape(path);
    EXPECT_EQ(dims, dims_of(item.attributes.at("Dimensions"))) << path;
    const h5::Handle set(H5Dopen2(h5.root().id(), path.c_str(), H5P_DEFAULT));
    const h5::Handle type(H5Dget_type(set.get()));
    const std::string number = item.attributes.at("NumberType");
    EXPECT_EQ(H5Tget_class(type.get()), number == "Float" ? H5T_FLOAT : H5T_INTEGER) << path;
    EXPECT_EQ(std::to_string(H5Tget_size(type.get())), item.attributes.at("Precision")) << path;
    std::vector<double> values(number == "Float" ? 0 : 1);
    if (number == "Float") {
      std::vector<hsize_t> d;
      values = h5.root().read_array(path, d);
    } else {
      hsize_t count = 1;
      for (const hsize_t n : dims) count *= n;
      std::vector<std::int64_t> ints(count);
      EXPECT_GE(H5Dread(set.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, ints.data()), 0) << path;
      values.assign(ints.begin(), ints.end());
    }
    return values;
  }
  const XmlNode& attribute(const XmlNode& grid, const std::string& name) const {
    for (const XmlNode* a : grid.all("Attribute"))
      if (a->attributes.at("Name") == name) return *a;
    throw std::runtime_error("no attribute " + name);
  }
  /// u_k,d = sum_j Phi_(k,d),j eta_j: loops over /surface/shape as the superelement stores it.
  double displacement(int sample, int k, int d) const {
    double u = 0.0;
    for (int j = 0; j < kModes; ++j)
      u += surface_.shape[(k * 3 + d) * kSeModes + j] * results_.eta(sample, j);
    return u;
  }
  double normal_velocity(int sample, int k) const {
    double v = 0.0;
    for (int d = 0; d < 3; ++d)
      for (int j = 0; j < kModes; ++j)
        v += surface_.normal(k, d) * surface_.shape[(k * 3 + d) * kSeModes + j] * results_.eta_dot(sample, j);
    return v;
  }
  bool no_output_left() const {
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string n = e.path().filename().string();
      if (n != "se.h5" && n != "results.h5" && n != "results2.h5") return false;
    }
    return true;
  }

  fs::path dir_;
  SurfaceExport surface_ = curved_surface();
  Results results_;
  std::ostringstream sink_;
  Logger log_{sink_, "postproc", Verbosity::kQuiet};
};

TEST_F(postproc_animate, XdmfDataItemsTimesDisplacementAndNormalVelocityMatchTheResults) {
  AnimateCommand c = command();
  c.from_s = 0.2625;  // samples 12.5 .. 87 of t0 + i / fs: 13 to 87
  c.to_s = 0.337;
  c.max_frames = 9;
  c.scale = 250.0;
  run_animate(c, log_, 0, nullptr);
  const std::vector<int> frames = expected_frames(13, 87, 9);

  const auto doc = read_xdmf();
  const XmlNode& xdmf = doc->one("Xdmf");
  EXPECT_EQ(xdmf.attributes.at("Version"), "3.0");
  const XmlNode& domain = xdmf.one("Domain");
  bool scale_found = false;
  for (const XmlNode* info : domain.all("Information"))
    if (info->attributes.at("Name") == "scale")
      scale_found = std::stod(info->attributes.at("Value")) == 250.0;
  EXPECT_TRUE(scale_found);
  const XmlNode& collection = domain.one("Grid");
  EXPECT_EQ(collection.attributes.at("CollectionType"), "Temporal");
  const auto grids = collection.all("Grid");
  ASSERT_EQ(grids.size(), frames.size());

  const h5::File h5 = h5::File::open_read(dir_ / "anim.h5");
  EXPECT_EQ(h5.root().string_attribute("analysis"), "animate");
  EXPECT_TRUE(h5.root().has_attribute("input_sha256"));
  EXPECT_EQ(h5.root().double_attribute("scale"), 250.0);
  EXPECT_EQ(h5.root().string_attribute("units", "frames/time"), "s");
  const int nodes = kGrid * kGrid;
  double worst_u = 0.0, worst_v = 0.0;
  for (std::size_t f = 0; f < grids.size(); ++f) {
    const XmlNode& g = *grids[f];
    const int sample = frames[f];
    EXPECT_EQ(std::stod(g.one("Time").attributes.at("Value")), results_.time[sample]) << "frame " << f;
    std::vector<hsize_t> dims;
    const XmlNode& topology = g.one("Topology");
    EXPECT_EQ(topology.attributes.at("TopologyType"), "Triangle");
    const std::vector<double> tri = follow(topology.one("DataItem"), h5, dims);
    EXPECT_EQ(std::to_string(dims[0]), topology.attributes.at("NumberOfElements"));
    const std::vector<double> geometry = follow(g.one("Geometry").one("DataItem"), h5, dims);
    const auto geometry_nodes = static_cast<double>(dims[0]);
    ASSERT_EQ(dims[0], static_cast<hsize_t>(nodes));
    for (const double i : tri) EXPECT_TRUE(i >= 0 && i < geometry_nodes) << i;
    for (std::size_t t = 0; t < surface_.triangles.size(); ++t)
      for (int v = 0; v < 3; ++v) EXPECT_EQ(tri[3 * t + v], surface_.triangles[t][v]);
    for (int k = 0; k < nodes; ++k)
      for (int d = 0; d < 3; ++d) EXPECT_EQ(geometry[3 * k + d], surface_.position(k, d));
    const XmlNode& u_attr = attribute(g, "displacement");
    EXPECT_EQ(u_attr.attributes.at("AttributeType"), "Vector");
    EXPECT_EQ(u_attr.attributes.at("Center"), "Node");
    const std::vector<double> u = follow(u_attr.one("DataItem"), h5, dims);
    EXPECT_EQ(dims, (std::vector<hsize_t>{static_cast<hsize_t>(nodes), 3}));
    const XmlNode& v_attr = attribute(g, "normal_velocity");
    EXPECT_EQ(v_attr.attributes.at("AttributeType"), "Scalar");
    const std::vector<double> vn = follow(v_attr.one("DataItem"), h5, dims);
    EXPECT_EQ(dims, (std::vector<hsize_t>{static_cast<hsize_t>(nodes)}));
    for (int k = 0; k < nodes; ++k) {
      for (int d = 0; d < 3; ++d)
        worst_u = std::max(worst_u, std::abs(u[3 * k + d] - displacement(sample, k, d)));
      worst_v = std::max(worst_v, std::abs(vn[k] - normal_velocity(sample, k)));
    }
  }
  // Values of order 1e-2 m and 1e-2 m/s: round-off.
  EXPECT_LT(worst_u, 1e-16);
  EXPECT_LT(worst_v, 1e-16);
  const Eigen::VectorXd crank = h5.root().read_vector("frames/crank_angle_deg");
  for (std::size_t f = 0; f < frames.size(); ++f)
    EXPECT_EQ(crank[static_cast<Eigen::Index>(f)], results_.angle[frames[f]]);
}

TEST_F(postproc_animate, IncludeRigidAddsTheFramesMotionAndDisplacedGeometryIsScaled) {
  AnimateCommand c = command();
  c.include_rigid = true;
  c.displaced_geometry = true;
  c.scale = 40.0;
  c.max_frames = 4;
  run_animate(c, log_, 0, nullptr);
  const std::vector<int> frames = expected_frames(0, results_.samples - 1, 4);
  const auto doc = read_xdmf();
  const auto grids = doc->one("Xdmf").one("Domain").one("Grid").all("Grid");
  ASSERT_EQ(grids.size(), frames.size());
  const h5::File h5 = h5::File::open_read(dir_ / "anim.h5");
  double worst_d = 0.0, worst_v = 0.0, worst_x = 0.0;
  for (std::size_t f = 0; f < grids.size(); ++f) {
    const int i = frames[f];
    // Rotation through Eigen's quaternion (w, x, y, z) = Euler parameters (e0, e1, e2, e3).
    const Eigen::Matrix3d a = Eigen::Quaterniond(results_.euler(i, 0), results_.euler(i, 1),
                                                 results_.euler(i, 2), results_.euler(i, 3))
                                  .toRotationMatrix();
    const Eigen::Vector3d r0 = results_.position.row(i).transpose();
    const Eigen::Vector3d v0 = results_.velocity.row(i).transpose(), w = results_.omega.row(i).transpose();
    std::vector<hsize_t> dims;
    const std::vector<double> geometry = follow(grids[f]->one("Geometry").one("DataItem"), h5, dims);
    const std::vector<double> d = follow(attribute(*grids[f], "displacement").one("DataItem"), h5, dims);
    const std::vector<double> vn = follow(attribute(*grids[f], "normal_velocity").one("DataItem"), h5, dims);
    for (int k = 0; k < kGrid * kGrid; ++k) {
      const Eigen::Vector3d x = surface_.position.row(k).transpose();
      const Eigen::Vector3d u(displacement(i, k, 0), displacement(i, k, 1), displacement(i, k, 2));
      const Eigen::Vector3d expected_d = r0 + a * (x + u) - x;
      const Eigen::Vector3d expected_x = r0 + a * (x + 40.0 * u);
      // v_n = n . (elastic velocity) + (A n) . (v_O + omega x A x) (global axes; lever arm undeformed).
      const Eigen::Vector3d n = surface_.normal.row(k).transpose();
      const double expected_v = normal_velocity(i, k) + (a * n).dot(v0 + w.cross(a * x));
      for (int dd = 0; dd < 3; ++dd) {
        worst_d = std::max(worst_d, std::abs(d[3 * k + dd] - expected_d[dd]));
        worst_x = std::max(worst_x, std::abs(geometry[3 * k + dd] - expected_x[dd]));
      }
      worst_v = std::max(worst_v, std::abs(vn[k] - expected_v));
    }
  }
  EXPECT_LT(worst_d, 1e-15);  // m, positions of order 1 m
  EXPECT_LT(worst_x, 1e-15);
  EXPECT_LT(worst_v, 1e-14);  // m/s, velocities of order 1 m/s
}

TEST_F(postproc_animate, CrankAngleWindowSelectsTheSamplesWithinIt) {
  AnimateCommand c = command();
  c.from_deg = 4700.0;  // samples with 18000 t in [4700, 5600]: t from 0.26111 to 0.31111 s
  c.to_deg = 5600.0;
  c.max_frames = 1000;
  run_animate(c, log_, 0, nullptr);
  std::vector<int> inside;
  for (int i = 0; i < results_.samples; ++i)
    if (results_.angle[i] >= 4700.0 && results_.angle[i] <= 5600.0) inside.push_back(i);
  const h5::File h5 = h5::File::open_read(dir_ / "anim.h5");
  const std::vector<std::int64_t> sample = h5.root().read_ints("frames/sample");
  ASSERT_EQ(sample.size(), inside.size());
  for (std::size_t f = 0; f < inside.size(); ++f) EXPECT_EQ(sample[f], inside[f]);
  const auto grids = read_xdmf()->one("Xdmf").one("Domain").one("Grid").all("Grid");
  EXPECT_EQ(grids.size(), inside.size());
}

TEST_F(postproc_animate, BadInputsAreNamedAndLeaveNoOutput) {
  auto fails_with = [&](AnimateCommand c, const std::string& part) {
    try {
      run_animate(c, log_, 0, nullptr);
      ADD_FAILURE() << "no error; expected one naming '" << part << "'";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
    EXPECT_TRUE(no_output_left());
  };
  AnimateCommand c = command();
  c.body = "crank";
  fails_with(c, "no dataset /bodies/crank/modal_coordinates");
  c = command();
  c.output = dir_ / "anim.h5";
  fails_with(c, "expected an .xdmf");
  c = command();
  c.from_s = 0.1;
  fails_with(c, "--from 0.1 s is outside the run");
  c = command();
  c.from_s = 0.3;
  c.to_s = 0.28;
  fails_with(c, "expected --from <= --to");
  results_.write(dir_ / "results2.h5", false);
  c = command();
  c.results = dir_ / "results2.h5";
  c.to_deg = 5000.0;
  fails_with(c, "has no /crank_angle_deg");
}

TEST_F(postproc_animate, CommandLineWritesBothFiles) {
  const std::string base = std::string(NVH_POSTPROC_EXE) + " animate " + (dir_ / "results.h5").string() +
                           " --superelement " + (dir_ / "se.h5").string() + " --body block -q -o " +
                           (dir_ / "anim.xdmf").string();
  ASSERT_EQ(std::system((base + " --frames 5 --scale 100").c_str()), 0);
  EXPECT_TRUE(fs::exists(dir_ / "anim.xdmf"));
  const h5::File h5 = h5::File::open_read(dir_ / "anim.h5");
  EXPECT_EQ(h5.root().read_vector("frames/time").size(), 5);
  EXPECT_EQ(read_xdmf()->one("Xdmf").one("Domain").one("Grid").all("Grid").size(), 5u);
  // A real XML parser and h5py (Debian's python3-h5py) read the same: every DataItem's dataset with its
  // dimensions, and the Temporal collection's 5 times.
  const std::string check =
      "/usr/bin/python3 -c \"import sys, xml.etree.ElementTree as ET, h5py\n"
      "root = ET.parse(sys.argv[1]).getroot(); f = h5py.File(sys.argv[2], 'r')\n"
      "for d in root.iter('DataItem'):\n"
      "    name, path = d.text.split(':')\n"
      "    assert name == 'anim.h5' and f[path].shape == tuple(map(int, d.get('Dimensions').split())), path\n"
      "assert len(root.find('Domain/Grid').findall('Grid/Time')) == 5\" " +
      (dir_ / "anim.xdmf").string() + " " + (dir_ / "anim.h5").string();
  EXPECT_EQ(std::system(check.c_str()), 0) << check;
  const int status = std::system((base + " --to 9 2>/dev/null").c_str());
  EXPECT_EQ(WEXITSTATUS(status), 1);
}

}  // namespace
