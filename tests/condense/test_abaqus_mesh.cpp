// The .inp mesh reader and writer: hand-written decks (C3D10, two-line C3D20, sets, comments, keywords to
// skip), each error with its line, *INCLUDE, a round trip, the speed on a 100k-node deck, and CalculiX
// (ccx) accepting what the writer writes: a cantilever's first bending frequency against beam theory.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "condense/abaqus_mesh.hpp"

namespace fs = std::filesystem;
using nvh::condense::Mesh;
using nvh::condense::MeshElement;
using nvh::condense::parse_abaqus_mesh;
using nvh::condense::read_abaqus_mesh;
using nvh::condense::write_abaqus_mesh;

namespace {

// Line numbers matter below.
const std::string kTets = R"(** two quadratic tets as a mesher writes them
*HEADING
Two tets, with commas, in the title,
*Node, nset=Nall
1, 0.0, 0.0, 0.0
2, 1.0, 0.0, 0.0
3, 0.0, 1.0, 0.0
4, 0.0, 0.0, 1.0
5, 0.5, 0.0, 0.0
6, 0.5, 0.5, 0.0
7, 0.0, 0.5, 0.0
8, 0.0, 0.0, 0.5
9, 0.5, 0.0, 0.5
10, 0.0, 0.5, 0.5
11, 1., 1., 1.E+0
** midside nodes of the second tet
12, 1.0, 0.5, 0.5
13,5.0e-1,1.0,0.5
14, +0.5, 0.5, 1.0
*ELEMENT, TYPE=CPS6, ELSET=Surface1
101, 1, 2, 3, 5, 6, 7
102, 1, 2, 4, 5, 9, 8
*element, type=c3d10, elset=Volume1
1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10
2, 2, 3, 4, 11, 6, 10, 9, 12, 13, 14
*ELSET, ELSET=Surface1
101, 102
*ELSET,ELSET=FIRST
1
*NSET, NSET=Base
1, 2, 3, 5, 6,
7
*Nset, Nset=Range, Generate
2, 10, 4
*NSET, NSET=BOTH
BASE, 11
*MATERIAL, NAME=STEEL
*ELASTIC
210e9, 0.3
*STEP
*FREQUENCY
6
*END STEP
)";

// One 20-node brick, the element on two lines (label and 15 nodes, then 5).
const std::string kBrick = R"(*NODE
101, 0, 0, 0
102, 1, 0, 0
103, 1, 1, 0
104, 0, 1, 0
105, 0, 0, 1
106, 1, 0, 1
107, 1, 1, 1
108, 0, 1, 1
109, 0.5, 0, 0
110, 1, 0.5, 0
111, 0.5, 1, 0
112, 0, 0.5, 0
113, 0.5, 0, 1
114, 1, 0.5, 1
115, 0.5, 1, 1
116, 0, 0.5, 1
117, 0, 0, 0.5
118, 1, 0, 0.5
119, 1, 1, 0.5
120, 0, 1, 0.5
*ELEMENT, TYPE=C3D20, ELSET=BRICK
7, 101, 102, 103, 104, 105, 106, 107, 108, 109, 110, 111, 112, 113, 114, 115,
   116, 117, 118, 119, 120
*ELSET, ELSET=ALL, GENERATE
1, 100
)";

std::string error_of(const std::string& text) {
  try {
    parse_abaqus_mesh(text, "deck.inp");
  } catch (const nvh::Error& e) {
    return e.what();
  }
  return "no error";
}

/// The text with line `line` (1-based) replaced.
std::string replace_line(const std::string& text, int line, const std::string& replacement) {
  std::istringstream in(text);
  std::string out, current;
  for (int n = 1; std::getline(in, current); ++n) out += (n == line ? replacement : current) + "\n";
  return out;
}

void expect_same_mesh(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (std::size_t i = 0; i < a.nodes.size(); ++i) EXPECT_EQ(a.nodes[i], b.nodes[i]) << "node " << i;
  EXPECT_EQ(a.node_ids, b.node_ids);
  ASSERT_EQ(a.elements.size(), b.elements.size());
  for (std::size_t i = 0; i < a.elements.size(); ++i) {
    EXPECT_EQ(a.elements[i].type, b.elements[i].type);
    EXPECT_EQ(a.elements[i].id, b.elements[i].id);
    EXPECT_EQ(a.elements[i].nodes, b.elements[i].nodes);
    EXPECT_EQ(a.elements[i].elset, b.elements[i].elset);
  }
  EXPECT_EQ(a.node_sets, b.node_sets);
  EXPECT_EQ(a.element_sets, b.element_sets);
}

Mesh round_trip(const Mesh& mesh) {
  std::ostringstream out;
  write_abaqus_mesh(mesh, out);
  return parse_abaqus_mesh(out.str(), "written.inp");
}

class TempDir {
 public:
  TempDir() {
    // A parameterized test's name holds a '/' ("Name/0"): one folder level, not two.
    std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::replace(name.begin(), name.end(), '/', '_');
    path_ = fs::temp_directory_path() / ("nvh_abaqus_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

}  // namespace

TEST(AbaqusMesh, ReadsQuadraticTetsWithSetsAndComments) {
  std::vector<std::string> skipped;
  const Mesh mesh = parse_abaqus_mesh(kTets, "tets.inp", &skipped);
  EXPECT_EQ(mesh.file, "tets.inp");
  ASSERT_EQ(mesh.nodes.size(), 14u);
  EXPECT_EQ(mesh.node_ids.front(), 1);
  EXPECT_EQ(mesh.nodes[10], Eigen::Vector3d(1, 1, 1));
  EXPECT_EQ(mesh.nodes[12], Eigen::Vector3d(0.5, 1, 0.5));
  EXPECT_EQ(mesh.nodes[13], Eigen::Vector3d(0.5, 0.5, 1));

  ASSERT_EQ(mesh.elements.size(), 2u);  // the CPS6 faces are skipped
  const MeshElement& second = mesh.elements[1];
  EXPECT_EQ(second.type, "C3D10");
  EXPECT_EQ(second.id, 2);
  EXPECT_EQ(second.elset, "VOLUME1");
  EXPECT_EQ(second.line, 25);
  EXPECT_EQ(second.nodes, (std::vector<int>{1, 2, 3, 10, 5, 9, 8, 11, 12, 13}));
  EXPECT_EQ(mesh.elements[0].line, 24);

  EXPECT_EQ(mesh.node_index(11), 10);
  EXPECT_EQ(mesh.node_index(15), -1);
  EXPECT_EQ(mesh.node_index(0), -1);

  const std::map<std::string, std::vector<int>> node_sets{
      {"NALL", {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13}},
      {"BASE", {0, 1, 2, 4, 5, 6}},  // continued line
      {"RANGE", {1, 5, 9}},          // 2, 6, 10 by GENERATE
      {"BOTH", {0, 1, 2, 4, 5, 6, 10}},
  };
  EXPECT_EQ(mesh.node_sets, node_sets);
  // SURFACE1 held only skipped elements: dropped.
  const std::map<std::string, std::vector<int>> element_sets{{"VOLUME1", {0, 1}}, {"FIRST", {0}}};
  EXPECT_EQ(mesh.element_sets, element_sets);

  const std::vector<std::string> expected_skipped{
      "*MATERIAL", "*ELASTIC", "*STEP", "*FREQUENCY", "*END STEP", "*ELEMENT, TYPE=CPS6 (2 elements)"};
  EXPECT_EQ(skipped, expected_skipped);
}

TEST(AbaqusMesh, ReadsATwoLineC3D20) {
  const Mesh mesh = parse_abaqus_mesh(kBrick, "brick.inp");
  ASSERT_EQ(mesh.elements.size(), 1u);
  const MeshElement& e = mesh.elements[0];
  EXPECT_EQ(e.type, "C3D20");
  EXPECT_EQ(e.id, 7);
  EXPECT_EQ(e.line, 23);
  ASSERT_EQ(e.nodes.size(), 20u);
  for (int k = 0; k < 20; ++k) EXPECT_EQ(e.nodes[k], k);
  EXPECT_EQ(mesh.element_sets.at("ALL"), std::vector<int>{0});
  EXPECT_EQ(mesh.element_sets.at("BRICK"), std::vector<int>{0});
  EXPECT_EQ(mesh.node_index(120), 19);
}

TEST(AbaqusMesh, CrlfLinesAndBlankCoordinates) {
  const Mesh mesh = parse_abaqus_mesh("*NODE\r\n1, 2.5\r\n2,,1\r\n3\r\n", "crlf.inp");
  ASSERT_EQ(mesh.nodes.size(), 3u);
  EXPECT_EQ(mesh.nodes[0], Eigen::Vector3d(2.5, 0, 0));
  EXPECT_EQ(mesh.nodes[1], Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(mesh.nodes[2], Eigen::Vector3d(0, 0, 0));
}

TEST(AbaqusMesh, NodesMayComeAfterTheirElements) {
  const Mesh mesh = parse_abaqus_mesh(
      "*ELEMENT, TYPE=C3D4\n1, 4, 3, 2, 1\n*NODE\n1\n2, 1\n3, 0, 1\n4, 0, 0, 1\n", "late.inp");
  ASSERT_EQ(mesh.elements.size(), 1u);
  EXPECT_EQ(mesh.elements[0].nodes, (std::vector<int>{3, 2, 1, 0}));
}

TEST(AbaqusMesh, RoundTripIsExact) {
  for (const std::string& text : {kTets, kBrick}) {
    const Mesh mesh = parse_abaqus_mesh(text, "deck.inp");
    expect_same_mesh(mesh, round_trip(mesh));
  }
  // Interleaved blocks, an element set beyond its ELSET= blocks, non-consecutive labels, awkward numbers.
  Mesh mesh = parse_abaqus_mesh(kBrick, "brick.inp");
  mesh.nodes[3] = Eigen::Vector3d(1e-300, -0.1 / 3.0, 123456789.125);
  mesh.nodes[4] = Eigen::Vector3d(-0.012345678901234567, 2.0 / 3.0, -7.5e-12);
  mesh.node_ids[19] = 9'999'999'999;  // the widest label ccx reads
  MeshElement copy = mesh.elements[0];
  copy.id = 8;
  copy.elset = "";
  mesh.elements.push_back(copy);
  copy.id = 9;
  copy.elset = "BRICK";
  mesh.elements.push_back(copy);
  mesh.element_sets["BRICK"] = {0, 2};
  mesh.element_sets["ALL"] = {0, 1, 2};
  mesh.node_sets["CORNERS"] = {0, 1, 2, 3, 4, 5, 6, 7, 19};
  const Mesh back = round_trip(mesh);
  ASSERT_EQ(back.nodes.size(), mesh.nodes.size());
  // Coordinates are written in at most 20 characters (what ccx reads): exact where that is enough,
  // within 1e-13 relative otherwise (the 17-digit -0.0123... here).
  for (std::size_t i = 0; i < mesh.nodes.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const double x = mesh.nodes[i][k];
      if (i == 4 && k == 0) {
        EXPECT_NEAR(back.nodes[i][k], x, 1e-13 * std::abs(x));
      } else {
        EXPECT_EQ(back.nodes[i][k], x) << "node " << i << " component " << k;
      }
    }
  }
  Mesh exact = back;
  exact.nodes = mesh.nodes;
  expect_same_mesh(mesh, exact);
}

TEST(AbaqusMesh, WriterKeepsLinesShortForCalculix) {
  Mesh mesh = parse_abaqus_mesh(kBrick, "brick.inp");
  for (auto& id : mesh.node_ids) id += 9'000'000;  // 7-digit labels: 143 characters with ", "
  std::ostringstream out;
  write_abaqus_mesh(mesh, out);
  std::istringstream in(out.str());
  std::string line;
  int element_lines = 0;
  bool in_elements = false;
  while (std::getline(in, line)) {
    EXPECT_LE(line.size(), 132u) << line;
    if (line.rfind("*", 0) == 0)
      in_elements = line.rfind("*ELEMENT", 0) == 0;
    else if (in_elements)
      ++element_lines;
  }
  EXPECT_EQ(element_lines, 2);  // 16 entries, then 5
  expect_same_mesh(mesh, parse_abaqus_mesh(out.str(), "written.inp"));
}

TEST(AbaqusMesh, WriterRejectsAnInconsistentMesh) {
  Mesh mesh = parse_abaqus_mesh(kBrick, "brick.inp");
  mesh.elements[0].nodes[3] = 20;
  std::ostringstream out;
  EXPECT_THROW(write_abaqus_mesh(mesh, out), nvh::Error);
  mesh = parse_abaqus_mesh(kBrick, "brick.inp");
  mesh.nodes[0][1] = std::nan("");
  EXPECT_THROW(write_abaqus_mesh(mesh, out), nvh::Error);
}

TEST(AbaqusMesh, ErrorsNameFileAndLine) {
  struct Case {
    int line;
    std::string replacement;
    std::string expected;  // regex on what()
  };
  const std::vector<Case> cases{
      {25, "2, 2, 3, 4, 11, 6, 10, 9, 12, 13, 99",
       R"(deck\.inp:25: '\*ELEMENT': C3D10 element 2 refers to node 99, which is not defined)"},
      {8, "3, 0.0, 0.0, 1.0", R"(deck\.inp:8:1: '\*NODE': node 3 is defined twice \(first at deck\.inp:7\))"},
      {25, "1, 2, 3, 4, 11, 6, 10, 9, 12, 13, 14",
       R"(deck\.inp:25:1: '\*ELEMENT': element 1 is defined twice \(first at deck\.inp:24\))"},
      {21, "1, 1, 2, 3, 5, 6, 7", R"(deck\.inp:24:1: '\*ELEMENT': element 1 is defined twice$)"},
      {25, "2, 2, 3, 4, 11, 6, 10, 9, 12, 13",
       R"(deck\.inp:25: '\*ELEMENT': C3D10 element 2 has 9 nodes, expected 10$)"},
      {9, "5, 0.5, 0.0x, 0.0", R"(deck\.inp:9:9: '\*NODE': expected a number, found "0\.0x")"},
      {9, "5, 0.5, 1e999, 0.0", R"(deck\.inp:9:9: '\*NODE': expected a number, found "1e999")"},
      {9, "5.0, 0.5, 0.0, 0.0", R"(deck\.inp:9:1: '\*NODE': expected an integer label, found "5\.0")"},
      {9, "-5, 0.5, 0.0, 0.0", R"(deck\.inp:9:1: '\*NODE': expected a positive label, found -5)"},
      {24, "1, 1, 2, 3, 4, 5, 6, 7, 8, 9, x10",
       R"(deck\.inp:24:31: '\*ELEMENT': expected an integer label, found "x10")"},
      {31, "1, 2, 3, 5, 6, 66,", R"(deck\.inp:31:16: '\*NSET': node 66 in set BASE is not defined)"},
      {29, "7", R"(deck\.inp:29:1: '\*ELSET': element 7 in set FIRST is not defined)"},
      {36, "BASE, NOPE", R"(deck\.inp:36:7: '\*NSET': unknown node set NOPE)"},
      {34, "2, 10, 4, 5",
       R"(deck\.inp:34:1: '\*NSET': expected "first, last\[, increment\]" after GENERATE)"},
      {20, "",
       R"(deck\.inp:21:15: '\*NODE': expected a node line .*, found 7 entries \(is an \*ELEMENT keyword missing)"},
      {23, "*ELEMENT, ELSET=X", R"(deck\.inp:23: '\*ELEMENT': \*ELEMENT needs TYPE=)"},
      {1, "1, 2, 3", R"(deck\.inp:1:1: a data line before any keyword)"},
      {4, "*NODE, SYSTEM=C", R"(deck\.inp:4:15: '\*NODE': SYSTEM=C is not supported)"},
  };
  for (const Case& c : cases) {
    const std::string message = error_of(replace_line(kTets, c.line, c.replacement));
    EXPECT_TRUE(std::regex_search(message, std::regex(c.expected)))
        << "line " << c.line << " -> \"" << c.replacement << "\": " << message;
  }
  // A C3D20 as CalculiX reads it: without the comma after 16 entries; and one with too few on its first line.
  std::string brick = kBrick;
  brick.replace(brick.find("115,\n"), 5, "115\n");
  EXPECT_EQ(parse_abaqus_mesh(brick, "deck.inp").elements.at(0).nodes.size(), 20u);
  brick.replace(brick.find(", 115\n"), 6, "\n");
  EXPECT_TRUE(
      std::regex_search(error_of(brick), std::regex(R"(deck\.inp:23: .*C3D20 element 7 has 14 nodes, )"
                                                    R"(expected 20 \(a line that goes on)")))
      << error_of(brick);
}

TEST(AbaqusMesh, ErrorCarriesTheLocation) {
  try {
    parse_abaqus_mesh(replace_line(kTets, 9, "5, 0.5, bad, 0.0"), "deck.inp");
    FAIL() << "no error";
  } catch (const nvh::Error& e) {
    EXPECT_EQ(e.where().file, "deck.inp");
    EXPECT_EQ(e.where().line, 9);
    EXPECT_EQ(e.where().column, 9);
    EXPECT_EQ(e.key(), "*NODE");
  }
}

TEST(AbaqusMesh, MissingFile) {
  TempDir dir;
  try {
    read_abaqus_mesh(dir.path() / "nope.inp");
    FAIL() << "no error";
  } catch (const nvh::Error& e) {
    EXPECT_EQ(e.where().file, (dir.path() / "nope.inp").string());
    EXPECT_NE(std::string(e.what()).find("cannot read"), std::string::npos) << e.what();
  }
}

TEST(AbaqusMesh, IncludeIsRelativeToTheIncludingFile) {
  TempDir dir;
  fs::create_directories(dir.path() / "model" / "parts");
  std::ofstream(dir.path() / "model" / "parts" / "nodes.inp") << "** nodes\n*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n";
  std::ofstream(dir.path() / "model" / "parts" / "mesh.inp")
      << "*INCLUDE, INPUT=nodes.inp\n3, 0, 1, 0\n4, 0, 0, 1\n*ELEMENT, TYPE=C3D4, ELSET=TET\n1, 1, 2, 3, 4\n";
  std::ofstream(dir.path() / "model" / "job.inp")
      << "*HEADING\nincluded\n*include,\n  input=parts/mesh.inp\n*NSET, NSET=TOP\n4\n*INCLUDE, "
         "INPUT=\"bad.inp\"\n";
  try {
    read_abaqus_mesh(dir.path() / "model" / "job.inp");
    FAIL() << "no error";
  } catch (const nvh::Error& e) {
    EXPECT_EQ(e.where().file, (dir.path() / "model" / "job.inp").string());
    EXPECT_EQ(e.where().line, 7);
    EXPECT_NE(std::string(e.what()).find("cannot read the included file " +
                                         (dir.path() / "model" / "bad.inp").string()),
              std::string::npos)
        << e.what();
  }
  std::ofstream(dir.path() / "model" / "bad.inp") << "** empty\n";
  const Mesh mesh = read_abaqus_mesh(dir.path() / "model" / "job.inp");
  EXPECT_EQ(mesh.nodes.size(), 4u);  // the data after the *INCLUDE of nodes.inp goes on its *NODE block
  ASSERT_EQ(mesh.elements.size(), 1u);
  EXPECT_EQ(mesh.elements[0].line, 5);  // in mesh.inp
  EXPECT_EQ(mesh.node_sets.at("TOP"), std::vector<int>{3});

  // An error in an included file names that file.
  std::ofstream(dir.path() / "model" / "parts" / "nodes.inp") << "*NODE\n1, 0, 0, 0\n1, 1, 0, 0\n";
  try {
    read_abaqus_mesh(dir.path() / "model" / "job.inp");
    FAIL() << "no error";
  } catch (const nvh::Error& e) {
    EXPECT_EQ(e.where().file, (dir.path() / "model" / "parts" / "nodes.inp").string());
    EXPECT_EQ(e.where().line, 3);
  }
}

namespace {

/// A box of nx*ny*nz bricks (C3D8 or C3D20), or of 6 tets each (C3D4 or C3D10), as a Mesh. Node labels start
/// at `first_label`; the nodes at x = 0 form the node set FIXED; all elements are in ELSET=BEAM.
Mesh box_mesh(const std::string& type, double lx, double ly, double lz, int nx, int ny, int nz,
              std::int64_t first_label = 1) {
  Mesh mesh;
  const bool quadratic = type == "C3D10" || type == "C3D20";
  const int q = quadratic ? 2 : 1;  // grid points per element edge
  // Bricks and C3D4/C3D10 use the full grid of (q*n+1)^3 points; C3D20 leaves out face and body centres.
  std::map<std::array<int, 3>, int> index;
  const auto node = [&](int i, int j, int k) {
    const std::array<int, 3> key{i, j, k};
    const auto it = index.find(key);
    if (it != index.end()) return it->second;
    const int n = static_cast<int>(mesh.nodes.size());
    index[key] = n;
    mesh.nodes.emplace_back(lx * i / (q * nx), ly * j / (q * ny), lz * k / (q * nz));
    mesh.node_ids.push_back(first_label + n);
    if (i == 0) mesh.node_sets["FIXED"].push_back(n);
    return n;
  };
  std::int64_t id = 1;
  const auto add = [&](std::vector<int> nodes) {
    mesh.elements.push_back({type, id++, std::move(nodes), "BEAM", 0});
  };
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      for (int k = 0; k < nz; ++k) {
        // Corner c = (dx, dy, dz) in grid steps of q.
        const auto corner = [&](int dx, int dy, int dz) {
          return std::array<int, 3>{q * (i + dx), q * (j + dy), q * (k + dz)};
        };
        const auto at = [&](std::array<int, 3> p) { return node(p[0], p[1], p[2]); };
        const auto mid = [&](std::array<int, 3> a, std::array<int, 3> b) {
          return node((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2);
        };
        const std::array<std::array<int, 3>, 8> c{corner(0, 0, 0), corner(1, 0, 0), corner(1, 1, 0),
                                                  corner(0, 1, 0), corner(0, 0, 1), corner(1, 0, 1),
                                                  corner(1, 1, 1), corner(0, 1, 1)};
        if (type == "C3D8" || type == "C3D20") {
          std::vector<int> nodes;
          for (const auto& p : c) nodes.push_back(at(p));
          if (quadratic) {
            const int edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                      {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
            for (const auto& e : edges) nodes.push_back(mid(c[e[0]], c[e[1]]));
          }
          add(nodes);
          continue;
        }
        // Six tets around the diagonal 0-6 (conforming between neighbouring cubes).
        const int tets[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6},
                                {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
        for (const auto& t : tets) {
          std::array<std::array<int, 3>, 4> v{c[t[0]], c[t[1]], c[t[2]], c[t[3]]};
          const auto x = [&](int a) { return mesh.nodes[at(v[a])]; };
          if ((x(1) - x(0)).cross(x(2) - x(0)).dot(x(3) - x(0)) < 0) std::swap(v[1], v[2]);
          std::vector<int> nodes{at(v[0]), at(v[1]), at(v[2]), at(v[3])};
          if (quadratic) {
            const int edges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
            for (const auto& e : edges) nodes.push_back(mid(v[e[0]], v[e[1]]));
          }
          add(nodes);
        }
      }
    }
  }
  mesh.element_sets["BEAM"].resize(mesh.elements.size());
  for (std::size_t e = 0; e < mesh.elements.size(); ++e) mesh.element_sets["BEAM"][e] = static_cast<int>(e);
  return mesh;
}

}  // namespace

TEST(AbaqusMesh, ParsesAHundredThousandNodesQuickly) {
  // 47^3 = 103823 grid points, C3D8 bricks, written with the usual ", " spacing and long coordinates.
  const int nx = 46, ny = 46, nz = 46;
  std::string text = "** synthetic\n*NODE, NSET=NALL\n";
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-1e-4, 1e-4);
  char line[160];
  int count = 0;
  const auto label = [&](int i, int j, int k) { return 1 + i + (nx + 1) * (j + (ny + 1) * k); };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        std::snprintf(line, sizeof line, "%d, %.17g, %.17g, %.17g\n", label(i, j, k),
                      0.01 * i + jitter(random), 0.01 * j + jitter(random), 0.01 * k + jitter(random));
        text += line;
        ++count;
      }
  text += "*ELEMENT, TYPE=C3D8, ELSET=BLOCK\n";
  int id = 1;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        std::snprintf(line, sizeof line, "%d, %d, %d, %d, %d, %d, %d, %d, %d\n", id++, label(i, j, k),
                      label(i + 1, j, k), label(i + 1, j + 1, k), label(i, j + 1, k), label(i, j, k + 1),
                      label(i + 1, j, k + 1), label(i + 1, j + 1, k + 1), label(i, j + 1, k + 1));
        text += line;
      }
  ASSERT_GE(count, 100'000);

  const auto start = std::chrono::steady_clock::now();
  const Mesh mesh = parse_abaqus_mesh(text, "big.inp");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("parsed %d nodes and %d C3D8 elements (%.1f MB) in %.3f s\n", count, id - 1, text.size() / 1e6,
              seconds);
  EXPECT_EQ(mesh.nodes.size(), static_cast<std::size_t>(count));
  EXPECT_EQ(mesh.elements.size(), static_cast<std::size_t>(id - 1));
  EXPECT_EQ(mesh.elements.back().nodes.back(), label(nx - 1, ny, nz) - 1);
  EXPECT_LT(seconds, 10.0);

  std::ostringstream out;
  const auto write_start = std::chrono::steady_clock::now();
  write_abaqus_mesh(mesh, out);
  std::printf("wrote it back in %.3f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - write_start).count());
}

namespace {

struct CcxResult {
  int exit_code = -1;
  std::string log;
  std::vector<double> frequencies_hz;  // from job.dat
};

/// Write `mesh` with a steel section, clamped at FIXED, and a *FREQUENCY step for 6 modes; run ccx.
CcxResult run_ccx(const Mesh& mesh, const fs::path& dir) {
  {
    std::ofstream job(dir / "job.inp");
    write_abaqus_mesh(mesh, job);
    job << "*MATERIAL, NAME=STEEL\n*ELASTIC\n210e9, 0.3\n*DENSITY\n7850\n"
           "*SOLID SECTION, ELSET=BEAM, MATERIAL=STEEL\n"
           "*BOUNDARY\nFIXED, 1, 3\n"
           "*STEP\n*FREQUENCY\n6\n*NODE FILE\nU\n*END STEP\n";
  }
  CcxResult result;
  const std::string command = "cd '" + dir.string() + "' && OMP_NUM_THREADS=1 ccx -i job 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::array<char, 512> buffer;
  while (fgets(buffer.data(), buffer.size(), pipe)) result.log += buffer.data();
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;

  // job.dat: "E I G E N V A L U E   O U T P U T", a header, then "MODE  EIGENVALUE  RAD/TIME  CYCLES/TIME
  // IMAGINARY" rows.
  std::ifstream dat(dir / "job.dat");
  std::string line;
  bool table = false;
  const std::regex row(R"(^\s*(\d+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s*$)");
  while (std::getline(dat, line)) {
    if (line.find("E I G E N V A L U E   O U T P U T") != std::string::npos) table = true;
    if (line.find("P A R T I C I P A T I O N") != std::string::npos) table = false;
    std::smatch m;
    if (table && std::regex_match(line, m, row)) result.frequencies_hz.push_back(std::stod(m[4]));
  }
  return result;
}

bool ccx_on_path() {
  return std::system("command -v ccx > /dev/null 2>&1") == 0;
}

/// First bending frequency of a clamped square steel beam (Euler-Bernoulli, 1.8751^2 / (2 pi L^2) sqrt(EI/rho
/// A)).
double euler_bernoulli_f1(double length, double side) {
  const double E = 210e9, rho = 7850;
  const double I = std::pow(side, 4) / 12, A = side * side;
  return 1.87510407 * 1.87510407 / (2 * std::numbers::pi * length * length) * std::sqrt(E * I / (rho * A));
}

}  // namespace

class AbaqusCalculix : public ::testing::TestWithParam<const char*> {};

TEST_P(AbaqusCalculix, CcxAcceptsTheWrittenMesh) {
  if (!ccx_on_path()) GTEST_SKIP() << "ccx (CalculiX, Debian package calculix-ccx) is not on PATH";
  TempDir dir;
  const std::string type = GetParam();
  const double length = 0.4, side = 0.04;
  // Labels from 1,000,001 for the bricks: long element lines.
  const Mesh mesh =
      box_mesh(type, length, side, side, 10, 2, 2, type == std::string("C3D20") ? 1'000'001 : 1);
  expect_same_mesh(mesh, round_trip(mesh));

  const CcxResult ccx = run_ccx(mesh, dir.path());
  ASSERT_EQ(ccx.exit_code, 0) << ccx.log;
  EXPECT_EQ(ccx.log.find("*ERROR"), std::string::npos) << ccx.log;
  EXPECT_TRUE(fs::exists(dir.path() / "job.frd"));
  ASSERT_EQ(ccx.frequencies_hz.size(), 6u) << ccx.log;
  const double f1 = euler_bernoulli_f1(length, side);
  std::printf("%s: %zu nodes, %zu elements; ccx frequencies (Hz):", type.c_str(), mesh.nodes.size(),
              mesh.elements.size());
  for (double f : ccx.frequencies_hz) std::printf(" %.1f", f);
  std::printf("; Euler-Bernoulli f1 = %.1f Hz\n", f1);
  // The two first bending modes (square section) within 5% of beam theory (clamping and shear at L/h = 10).
  EXPECT_NEAR(ccx.frequencies_hz[0], f1, 0.05 * f1);
  EXPECT_NEAR(ccx.frequencies_hz[1], f1, 0.05 * f1);
}

INSTANTIATE_TEST_SUITE_P(Types, AbaqusCalculix, ::testing::Values("C3D10", "C3D20"));
