// In-process gmsh meshing (condense/gmsh_mesh.hpp) against references that do not come from it: the exact
// volume of a box, the geometry of straight-sided tetrahedra (orientation, mid-edge nodes at the midpoints
// of the Abaqus edge pairs), the faces of the box, a hand-written .msh whose numbering is known, and the
// .msh and STEP files the gmsh command-line program (Debian package gmsh, same library) writes.
#include <gtest/gtest.h>

#include <unistd.h>
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "common/error.hpp"
#include "condense/gmsh_mesh.hpp"

namespace fs = std::filesystem;

namespace nvh::condense {
namespace {

constexpr double kLx = 0.2, kLy = 0.05, kLz = 0.04;  // the box, m

class GmshMesh : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("nvh_gmsh_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path path = dir_ / name;
    std::ofstream(path) << text;
    return path;
  }
  /// The box with its solid and its x = 0 face as physical groups (the face found by its bounding box).
  fs::path box_geo() const {
    return write("box.geo",
                 "SetFactory(\"OpenCASCADE\");\n"
                 "Box(1) = {0, 0, 0, " +
                     std::to_string(kLx) + ", " + std::to_string(kLy) + ", " + std::to_string(kLz) +
                     "};\n"
                     "Physical Volume(\"solid\") = {1};\n"
                     "eps = 1e-6;\n"
                     "left() = Surface In BoundingBox{-eps, -eps, -eps, eps, 0.05 + eps, 0.04 + eps};\n"
                     "Physical Surface(\"left\") = {left()};\n");
  }
  /// Run the gmsh program; false if it is not installed.
  static bool run_gmsh(const std::string& arguments) {
    if (std::system("command -v gmsh > /dev/null 2>&1") != 0) return false;
    const int status = std::system(("gmsh " + arguments + " > /dev/null 2>&1").c_str());
    EXPECT_EQ(status, 0) << "gmsh " << arguments;
    return true;
  }

  fs::path dir_;
};

/// Signed volume of the straight-sided tetrahedron on the first four (corner) nodes of an element.
double corner_volume(const Mesh& mesh, const MeshElement& e) {
  const Eigen::Vector3d& x1 = mesh.nodes[e.nodes[0]];
  return (mesh.nodes[e.nodes[1]] - x1).cross(mesh.nodes[e.nodes[2]] - x1).dot(mesh.nodes[e.nodes[3]] - x1) /
         6.0;
}

/// Checks every element: type, orientation, mid-edge nodes at the midpoints of the Abaqus pairs; returns
/// the summed volume.
double check_tetrahedra(const Mesh& mesh, const std::string& type) {
  // Abaqus/CalculiX C3D10: 5: 1-2, 6: 2-3, 7: 3-1, 8: 1-4, 9: 2-4, 10: 3-4 (0-based below).
  static const int kEdges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  const std::size_t n = type == "C3D4" ? 4 : 10;
  double volume = 0, worst_midpoint = 0;
  int inverted = 0;
  for (const MeshElement& e : mesh.elements) {
    EXPECT_EQ(e.type, type);
    EXPECT_EQ(e.nodes.size(), n);
    const double v = corner_volume(mesh, e);
    if (v <= 0) ++inverted;
    volume += v;
    if (n == 10) {
      for (int k = 0; k < 6; ++k) {
        const Eigen::Vector3d mid =
            0.5 * (mesh.nodes[e.nodes[kEdges[k][0]]] + mesh.nodes[e.nodes[kEdges[k][1]]]);
        worst_midpoint = std::max(worst_midpoint, (mesh.nodes[e.nodes[4 + k]] - mid).norm());
      }
    }
  }
  EXPECT_EQ(inverted, 0) << "tetrahedra with (x2-x1)x(x3-x1).(x4-x1) <= 0 in Abaqus order";
  EXPECT_LT(worst_midpoint, 1e-12) << "a mid-edge node is off the midpoint of its Abaqus edge";
  return volume;
}

/// Every node is used by an element (only the tetrahedra's nodes are kept) and the labels ascend.
void check_nodes(const Mesh& mesh) {
  std::vector<bool> used(mesh.nodes.size(), false);
  for (const MeshElement& e : mesh.elements)
    for (int n : e.nodes) {
      ASSERT_GE(n, 0);
      ASSERT_LT(n, static_cast<int>(mesh.nodes.size()));
      used[n] = true;
    }
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);
  ASSERT_EQ(mesh.node_ids.size(), mesh.nodes.size());
  EXPECT_TRUE(std::is_sorted(mesh.node_ids.begin(), mesh.node_ids.end()));
}

TEST_F(GmshMesh, BoxOrder2GivesC3D10WithExactVolumeAndSets) {
  const fs::path geo = box_geo();
  const Mesh mesh = mesh_with_gmsh({.geometry = geo, .order = 2, .size = 0.01});
  EXPECT_EQ(mesh.file, geo.string());
  ASSERT_FALSE(mesh.elements.empty());
  check_nodes(mesh);
  const double volume = check_tetrahedra(mesh, "C3D10");
  EXPECT_NEAR(volume, kLx * kLy * kLz, 1e-12 * kLx * kLy * kLz);
  std::cout << "box at 0.01 m, C3D10: " << mesh.nodes.size() << " nodes, " << mesh.elements.size()
            << " elements\n";

  ASSERT_TRUE(mesh.node_sets.count("LEFT"));
  const std::vector<int>& left = mesh.node_sets.at("LEFT");
  EXPECT_GT(left.size(), 4u);
  int on_face = 0;
  for (const Eigen::Vector3d& x : mesh.nodes)
    if (std::abs(x.x()) < 1e-12) ++on_face;
  EXPECT_EQ(static_cast<int>(left.size()), on_face) << "LEFT must hold every node of the x = 0 face";
  for (int n : left) EXPECT_EQ(mesh.nodes[n].x(), 0.0);

  ASSERT_TRUE(mesh.element_sets.count("SOLID"));
  EXPECT_EQ(mesh.element_sets.at("SOLID").size(), mesh.elements.size());
  ASSERT_TRUE(mesh.node_sets.count("SOLID"));
  EXPECT_EQ(mesh.node_sets.at("SOLID").size(), mesh.nodes.size());
  for (const MeshElement& e : mesh.elements) EXPECT_EQ(e.elset, "SOLID");
  EXPECT_EQ(mesh.node_sets.size(), 2u);
  EXPECT_EQ(mesh.element_sets.size(), 1u);
}

TEST_F(GmshMesh, Order1GivesC3D4) {
  const Mesh mesh = mesh_with_gmsh({.geometry = box_geo(), .order = 1, .size = 0.01});
  check_nodes(mesh);
  const double volume = check_tetrahedra(mesh, "C3D4");
  EXPECT_NEAR(volume, kLx * kLy * kLz, 1e-12 * kLx * kLy * kLz);
  // The corners of the order-2 mesh at the same size are the order-1 mesh.
  const Mesh quadratic = mesh_with_gmsh({.geometry = box_geo(), .order = 2, .size = 0.01});
  EXPECT_EQ(quadratic.elements.size(), mesh.elements.size());
  std::cout << "box at 0.01 m, C3D4: " << mesh.nodes.size() << " nodes, " << mesh.elements.size()
            << " elements\n";
}

TEST_F(GmshMesh, MshFromGmshProgramReadsBackAsInProcess) {
  const fs::path geo = box_geo();
  const fs::path msh = dir_ / "box.msh";
  if (!run_gmsh(geo.string() + " -3 -order 2 -clmax 0.01 -format msh4 -o " + msh.string()))
    GTEST_SKIP() << "the gmsh program (Debian gmsh) is not installed";
  const Mesh read = mesh_with_gmsh({.geometry = msh});
  const Mesh made = mesh_with_gmsh({.geometry = geo, .order = 2, .size = 0.01});
  ASSERT_EQ(read.nodes.size(), made.nodes.size());
  ASSERT_EQ(read.elements.size(), made.elements.size());
  EXPECT_EQ(read.node_ids, made.node_ids);
  double worst = 0;
  for (std::size_t i = 0; i < read.nodes.size(); ++i)
    worst = std::max(worst, (read.nodes[i] - made.nodes[i]).norm());
  EXPECT_LT(worst, 1e-15);
  for (std::size_t e = 0; e < read.elements.size(); ++e) {
    EXPECT_EQ(read.elements[e].nodes, made.elements[e].nodes);
    if (HasFailure()) break;
  }
  EXPECT_EQ(read.node_sets, made.node_sets);
  EXPECT_EQ(read.element_sets, made.element_sets);
  EXPECT_NEAR(check_tetrahedra(read, "C3D10"), kLx * kLy * kLz, 1e-12 * kLx * kLy * kLz);
}

TEST_F(GmshMesh, HandWrittenMshWithSparseTagsIsRenumberedAndReordered) {
  // One 10-node tetrahedron in gmsh's order (mid-edge nodes 5: 1-2, 6: 2-3, 7: 3-1, 8: 1-4, 9: 3-4,
  // 10: 2-4) with node tags 100003 + 100000 k, plus a node no element uses.
  const double corners[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int gmsh_edges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {2, 3}, {1, 3}};
  auto tag = [](int k) { return 100003 + 100000 * static_cast<long>(k); };
  std::ostringstream text;
  text << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
       << "$Nodes\n2 11 100003 5000000\n3 1 0 10\n";
  for (int k = 0; k < 10; ++k) text << tag(k) << "\n";
  for (const auto& x : corners) text << x[0] << " " << x[1] << " " << x[2] << "\n";
  for (const auto& edge : gmsh_edges) {
    for (int c = 0; c < 3; ++c) text << 0.5 * (corners[edge[0]][c] + corners[edge[1]][c]) << " ";
    text << "\n";
  }
  text << "0 1 0 1\n5000000\n9 9 9\n$EndNodes\n"
       << "$Elements\n1 1 77 77\n3 1 11 1\n77";
  for (int k = 0; k < 10; ++k) text << " " << tag(k);
  text << "\n$EndElements\n";
  const fs::path msh = write("tet.msh", text.str());
  const Mesh mesh = mesh_with_gmsh({.geometry = msh});
  ASSERT_EQ(mesh.elements.size(), 1u);
  ASSERT_EQ(mesh.nodes.size(), 10u) << "the unused node is dropped";
  EXPECT_EQ(mesh.elements[0].id, 77);
  EXPECT_EQ(mesh.elements[0].type, "C3D10");
  for (int k = 0; k < 10; ++k) EXPECT_EQ(mesh.node_ids[k], tag(k));
  // Abaqus order: 9 on 2-4 = (0.5, 0, 0.5), 10 on 3-4 = (0, 0.5, 0.5).
  const std::vector<int> abaqus = {0, 1, 2, 3, 4, 5, 6, 7, 9, 8};
  EXPECT_EQ(mesh.elements[0].nodes, abaqus);
  EXPECT_EQ(mesh.nodes[mesh.elements[0].nodes[8]], Eigen::Vector3d(0.5, 0, 0.5));
  EXPECT_EQ(mesh.nodes[mesh.elements[0].nodes[9]], Eigen::Vector3d(0, 0.5, 0.5));
  EXPECT_NEAR(check_tetrahedra(mesh, "C3D10"), 1.0 / 6.0, 1e-15);
  EXPECT_EQ(mesh.node_index(tag(9)), 9);
  EXPECT_TRUE(mesh.node_sets.empty());
}

TEST_F(GmshMesh, TwoVolumesShareTheirInterfaceAndGetTheirOwnSets) {
  // Two boxes 0.1 x 0.05 x 0.04 glued at x = 0.1 (BooleanFragments makes the mesh conformal); the right
  // one's physical group is unnamed, and the interface is an unnamed physical surface.
  const fs::path geo =
      write("two.geo",
            "SetFactory(\"OpenCASCADE\");\n"
            "Box(1) = {0, 0, 0, 0.1, 0.05, 0.04};\nBox(2) = {0.1, 0, 0, 0.1, 0.05, 0.04};\n"
            "v() = BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; };\n"
            "eps = 1e-6;\n"
            "a() = Volume In BoundingBox{-eps, -eps, -eps, 0.1 + eps, 0.05 + eps, 0.04 + eps};\n"
            "b() = Volume In BoundingBox{0.1 - eps, -eps, -eps, 0.2 + eps, 0.05 + eps, 0.04 + eps};\n"
            "Physical Volume(\"left part\") = {a()};\nPhysical Volume(7) = {b()};\n"
            "s() = Surface In BoundingBox{0.1 - eps, -eps, -eps, 0.1 + eps, 0.05 + eps, 0.04 + eps};\n"
            "Physical Surface(3) = {s()};\n");
  const Mesh mesh = mesh_with_gmsh({.geometry = geo, .order = 2, .size = 0.01});
  check_nodes(mesh);
  EXPECT_NEAR(check_tetrahedra(mesh, "C3D10"), kLx * kLy * kLz, 1e-12 * kLx * kLy * kLz);
  ASSERT_TRUE(mesh.element_sets.count("LEFT PART"));
  ASSERT_TRUE(mesh.element_sets.count("PG3_7"));
  const auto& a = mesh.element_sets.at("LEFT PART");
  const auto& b = mesh.element_sets.at("PG3_7");
  EXPECT_EQ(a.size() + b.size(), mesh.elements.size());
  double va = 0;
  for (int e : a) {
    EXPECT_EQ(mesh.elements[e].elset, "LEFT PART");
    va += corner_volume(mesh, mesh.elements[e]);
  }
  for (int e : b) EXPECT_EQ(mesh.elements[e].elset, "PG3_7");
  EXPECT_NEAR(va, 0.5 * kLx * kLy * kLz, 1e-12 * kLx * kLy * kLz);
  // Conformal: the nodes of both parts meet exactly in the interface set.
  const auto& na = mesh.node_sets.at("LEFT PART");
  const auto& nb = mesh.node_sets.at("PG3_7");
  std::vector<int> shared;
  std::set_intersection(na.begin(), na.end(), nb.begin(), nb.end(), std::back_inserter(shared));
  ASSERT_TRUE(mesh.node_sets.count("PG2_3"));
  EXPECT_EQ(shared, mesh.node_sets.at("PG2_3"));
  EXPECT_EQ(na.size() + nb.size() - shared.size(), mesh.nodes.size());
  for (int n : shared) EXPECT_NEAR(mesh.nodes[n].x(), 0.1, 1e-15);
}

TEST_F(GmshMesh, StepInMillimetresIsMeshedInMetres) {
  // The gmsh program writes a STEP file of the box in millimetres (its default unit, declared in the file).
  const fs::path script =
      write("make_step.geo", "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 200, 50, 40};\n");
  const fs::path step = dir_ / "box.step";
  if (!run_gmsh(script.string() + " -0 -o " + step.string()))
    GTEST_SKIP() << "the gmsh program (Debian gmsh) is not installed";
  const Mesh mesh = mesh_with_gmsh({.geometry = step, .order = 2, .size = 0.01});
  check_nodes(mesh);
  EXPECT_NEAR(check_tetrahedra(mesh, "C3D10"), kLx * kLy * kLz, 1e-12 * kLx * kLy * kLz);
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(-1e9), lo = Eigen::Vector3d::Constant(1e9);
  for (const Eigen::Vector3d& x : mesh.nodes) {
    hi = hi.cwiseMax(x);
    lo = lo.cwiseMin(x);
  }
  EXPECT_LT((hi - Eigen::Vector3d(kLx, kLy, kLz)).norm(), 1e-12);
  EXPECT_LT(lo.norm(), 1e-12);
  EXPECT_TRUE(mesh.node_sets.empty());
  EXPECT_TRUE(mesh.element_sets.empty());
  std::cout << "STEP box at 0.01 m: " << mesh.nodes.size() << " nodes, " << mesh.elements.size()
            << " elements\n";
}

/// The message of the nvh::Error that `f` throws ("" and a failure if none).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no nvh::Error";
  return "";
}

TEST_F(GmshMesh, ErrorsNameTheFile) {
  const fs::path missing = dir_ / "missing.geo";
  std::string what = error_of([&] { mesh_with_gmsh({.geometry = missing}); });
  EXPECT_NE(what.find(missing.string()), std::string::npos) << what;
  EXPECT_NE(what.find("no such file"), std::string::npos) << what;

  const fs::path txt = write("box.txt", "Box(1) = {0, 0, 0, 1, 1, 1};\n");
  what = error_of([&] { mesh_with_gmsh({.geometry = txt}); });
  EXPECT_NE(what.find(txt.string()), std::string::npos) << what;
  EXPECT_NE(what.find("unsupported extension"), std::string::npos) << what;

  const fs::path flat =
      write("flat.geo", "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 0.2, 0.05};\n");
  what = error_of([&] { mesh_with_gmsh({.geometry = flat}); });
  EXPECT_NE(what.find(flat.string()), std::string::npos) << what;
  EXPECT_NE(what.find("no volume"), std::string::npos) << what;

  const fs::path bad = write("bad.geo", "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 1, 1, 1;\n");
  what = error_of([&] { mesh_with_gmsh({.geometry = bad}); });
  EXPECT_NE(what.find(bad.string()), std::string::npos) << what;
  EXPECT_NE(what.find("syntax error"), std::string::npos) << what;

  what = error_of([&] { mesh_with_gmsh({.geometry = box_geo(), .order = 3}); });
  EXPECT_NE(what.find("order 3"), std::string::npos) << what;

  // A 2D-only mesh file has no volume either.
  const fs::path msh2d = dir_ / "flat.msh";
  if (run_gmsh(flat.string() + " -2 -format msh4 -o " + msh2d.string())) {
    what = error_of([&] { mesh_with_gmsh({.geometry = msh2d}); });
    EXPECT_NE(what.find(msh2d.string()), std::string::npos) << what;
  }

  // gmsh works again after an error (the session was finalized).
  EXPECT_FALSE(mesh_with_gmsh({.geometry = box_geo(), .order = 1, .size = 0.02}).elements.empty());
}

TEST_F(GmshMesh, TimingOfAFineBox) {
  const fs::path geo = box_geo();
  for (int threads : {1, 2}) {
    const auto start = std::chrono::steady_clock::now();
    const Mesh mesh = mesh_with_gmsh({.geometry = geo, .order = 2, .size = 0.004, .threads = threads});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "box at 0.004 m, C3D10, " << threads << " thread(s): " << mesh.nodes.size() << " nodes, "
              << mesh.elements.size() << " elements, " << seconds << " s\n";
    EXPECT_NEAR(check_tetrahedra(mesh, "C3D10"), kLx * kLy * kLz, 1e-12 * kLx * kLy * kLz);
  }
}

}  // namespace
}  // namespace nvh::condense
