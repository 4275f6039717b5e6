// The condense command line: bad input gives a non-zero exit, a message naming file, line and key, and
// no output file; good input writes the documented layout.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "common/hdf5.hpp"
#include "common/superelement.hpp"

namespace fs = std::filesystem;

namespace {

struct CliRun {
  int exit_code = 0;
  std::string output;  // stdout and stderr
};

class CondenseCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nvh_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Write `text` to NAME.toml in the test directory and run condense on it.
  CliRun run_condense(const std::string& text, const std::string& extra = "") {
    const fs::path input = dir_ / "part.toml";
    std::ofstream(input) << text;
    const std::string command = std::string(NVH_CONDENSE_EXE) + " " + input.string() + " -o " +
                                output().string() + " " + extra + " 2>&1";
    CliRun run;
    FILE* pipe = popen(command.c_str(), "r");
    std::array<char, 512> buffer;
    while (fgets(buffer.data(), buffer.size(), pipe)) run.output += buffer.data();
    const int status = pclose(pipe);
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return run;
  }
  fs::path output() const { return dir_ / "part.h5"; }
  /// No output and no temporary left behind.
  bool directory_holds_only_the_input() const {
    for (const auto& entry : fs::directory_iterator(dir_))
      if (entry.path().filename() != "part.toml") return false;
    return true;
  }

  fs::path dir_;
};

// A valid cantilever; each bad-input test breaks one line of it. Line numbers matter below.
const std::string kGood = R"([component]
name = "rod"
kind = "beam"

[material.steel]
E = 210e9
nu = 0.3
rho = 7850.0

[beam]
material = "steel"
points = [[0, 0, 0], [0.5, 0, 0], [1.0, 0, 0]]
elements_per_segment = 10

[[beam.section]]
segments = [1, 2]
A = 7.85e-5
Iy = 4.9e-10
Iz = 4.9e-10
J = 9.8e-10

[[fix]]
at = [0, 0, 0]
dofs = "x y z rx ry rz"

[[interface]]
name = "tip"
at = [1.0, 0, 0]

[[observe]]
name = "middle"
at = [0.5, 0, 0]

[reduction]
method = "craig-bampton"
fmax = 2000.0
)";

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

/// The message must name the file and a line ("part.toml:LINE") and the key.
void expect_located(const CliRun& run, int line, const std::string& key, const std::string& what) {
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("part.toml:" + std::to_string(line)), std::string::npos)
      << "expected line " << line << " in: " << run.output;
  EXPECT_NE(run.output.find(key), std::string::npos) << "expected key " << key << " in: " << run.output;
  EXPECT_NE(run.output.find(what), std::string::npos) << "expected \"" << what << "\" in: " << run.output;
}

TEST_F(CondenseCli, GoodInputWritesTheDocumentedLayout) {
  const CliRun run = run_condense(kGood);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  nvh::h5::File file = nvh::h5::File::open_read(output());
  const nvh::h5::Group& root = file.root();
  EXPECT_EQ(root.string_attribute("format"), "superelement");
  EXPECT_EQ(root.string_attribute("format_version"), nvh::kSuperelementFormatVersion);
  EXPECT_EQ(root.string_attribute("units"), "SI");
  EXPECT_EQ(root.string_attribute("tool"), "condense");
  EXPECT_EQ(root.string_attribute("input_sha256").size(), 64u);
  for (const char* path :
       {"modes/frequency_hz", "reduced/mass", "reduced/stiffness", "reduced/damping", "interface/name",
        "interface/position", "interface/shape", "observe/name", "observe/position", "observe/shape",
        "invariants/mass", "invariants/center_of_mass", "invariants/inertia",
        "invariants/translational_coupling", "invariants/rotational_coupling", "invariants/quadratic"}) {
    EXPECT_TRUE(root.exists(path)) << path;
  }
  EXPECT_TRUE(root.has_attribute("stage_seconds", "model"));
  EXPECT_GT(root.double_attribute("peak_memory_bytes", "model"), 1e6);  // a process takes more than 1 MB
  const nvh::SuperelementFile se = nvh::read_superelement(output());
  EXPECT_EQ(se.interfaces.names.at(0), "tip");
  EXPECT_NEAR(se.inertia.mass, 7850.0 * 7.85e-5 * 1.0, 1e-9);
  EXPECT_TRUE(directory_holds_only_the_input() == false);
}

TEST_F(CondenseCli, MissingKey) {
  expect_located(run_condense(replace(kGood, "E = 210e9\n", "")), 5, "material.steel.E", "missing");
  EXPECT_TRUE(directory_holds_only_the_input());
}

TEST_F(CondenseCli, WrongType) {
  expect_located(run_condense(replace(kGood, "E = 210e9", "E = \"210 GPa\"")), 6, "material.steel.E",
                 "expected a number");
  EXPECT_TRUE(directory_holds_only_the_input());
}

TEST_F(CondenseCli, NegativeYoungsModulus) {
  expect_located(run_condense(replace(kGood, "E = 210e9", "E = -210e9")), 6, "material.steel.E",
                 "expected a number in (0, 1e+18], got -2.1e+11");
  EXPECT_TRUE(directory_holds_only_the_input());
}

// Issue 18 item 4: inf, NaN, subnormal and absurd numbers once passed the reader and failed later with an
// error naming no key (a mass matrix that is not positive definite, ...); each is refused at its key now.
TEST_F(CondenseCli, NonFiniteAndAbsurdNumbersNameTheKey) {
  const std::string finite = "numbers must be finite";
  expect_located(run_condense(replace(kGood, "E = 210e9", "E = inf")), 6, "'material.steel.E'", finite);
  expect_located(run_condense(replace(kGood, "E = 210e9", "E = 1e308")), 6, "'material.steel.E'", "1e+18");
  expect_located(run_condense(replace(kGood, "rho = 7850.0", "rho = 1e-300")), 8, "'material.steel.rho'",
                 "expected a number in [1e-06, 1e+12], got 1e-300");
  expect_located(run_condense(replace(kGood, "rho = 7850.0", "rho = 1e-320")), 8, "'material.steel.rho'",
                 "subnormal");
  expect_located(run_condense(replace(kGood, "[0.5, 0, 0], [1.0", "[nan, 0, 0], [1.0")), 12,
                 "'beam.points[2][1]'", finite);
  expect_located(run_condense(replace(kGood, "A = 7.85e-5", "A = 1e308")), 17, "'beam.section[1].A'",
                 "expected a number in [1e-15, 1000]");
  expect_located(run_condense(replace(kGood, "J = 9.8e-10", "J = -inf")), 20, "'beam.section[1].J'", finite);
  expect_located(run_condense(replace(kGood, "at = [1.0, 0, 0]", "at = [1.0, 0, inf]")), 28,
                 "'interface[1].at[3]'", finite);
  expect_located(run_condense(replace(kGood, "fmax = 2000.0", "fmax = inf")), 36, "'reduction.fmax'", finite);
  EXPECT_TRUE(directory_holds_only_the_input());
}

TEST_F(CondenseCli, PoissonRatioOfAHalfOrMore) {
  expect_located(run_condense(replace(kGood, "nu = 0.3", "nu = 0.5")), 7, "material.steel.nu", "0.5");
  EXPECT_TRUE(directory_holds_only_the_input());
}

TEST_F(CondenseCli, ZeroLengthSegment) {
  expect_located(run_condense(replace(kGood, "[0.5, 0, 0], [1.0, 0, 0]]", "[0.5, 0, 0], [0.5, 0, 0]]")), 12,
                 "beam.points", "zero length");
  EXPECT_TRUE(directory_holds_only_the_input());
}

TEST_F(CondenseCli, SegmentWithoutSection) {
  expect_located(run_condense(replace(kGood, "segments = [1, 2]", "segments = [1, 1]")), 15, "beam.section",
                 "segment 2");
  EXPECT_TRUE(directory_holds_only_the_input());
}

TEST_F(CondenseCli, UnknownMaterial) {
  expect_located(run_condense(replace(kGood, "material = \"steel\"", "material = \"stel\"")), 11,
                 "beam.material", "unknown material \"stel\"");
  EXPECT_TRUE(directory_holds_only_the_input());
}

TEST_F(CondenseCli, InterfacePointNotOnTheModel) {
  expect_located(run_condense(replace(kGood, "at = [1.0, 0, 0]", "at = [1.0, 0.2, 0]")), 28, "at",
                 "not on the model");
  EXPECT_TRUE(directory_holds_only_the_input());
}

TEST_F(CondenseCli, FmaxBelowTheFirstMode) {
  expect_located(run_condense(replace(kGood, "fmax = 2000.0", "fmax = 1.0")), 36, "reduction.fmax",
                 "below the first fixed-interface mode");
  EXPECT_TRUE(directory_holds_only_the_input());
}

TEST_F(CondenseCli, UnknownKeyWithDidYouMean) {
  expect_located(run_condense(replace(kGood, "J = 9.8e-10", "J = 9.8e-10\nshear_factr = 0.9")), 21,
                 "shear_factr", "did you mean 'shear_factor'");
  EXPECT_TRUE(directory_holds_only_the_input());
}

TEST_F(CondenseCli, MisspeltRequiredKeyPointsAtTheMisspelling) {
  expect_located(run_condense(replace(kGood, "Iy = 4.9e-10", "Iyy = 4.9e-10")), 18, "Iyy",
                 "did you mean 'Iy'");
  EXPECT_TRUE(directory_holds_only_the_input());
}

TEST_F(CondenseCli, BadCommandLineExitsWithTwo) {
  const CliRun run = run_condense(kGood, "--method craig");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_TRUE(directory_holds_only_the_input());
}

TEST_F(CondenseCli, CommandLineOverridesTheFile) {
  const CliRun run = run_condense(kGood, "--method modal --modes 3");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nvh::SuperelementFile se = nvh::read_superelement(output());
  EXPECT_EQ(se.method, "modal");
  EXPECT_EQ(se.size(), 3);
}

TEST_F(CondenseCli, OverridingGuyanWithoutACountIsAClearError) {
  std::string guyan = replace(kGood, "method = \"craig-bampton\"", "method = \"guyan\"");
  guyan = replace(guyan, "fmax = 2000.0\n", "");
  ASSERT_EQ(run_condense(guyan).exit_code, 0);
  fs::remove(output());
  const CliRun run = run_condense(guyan, "--method modal");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("fmax (Hz) or modes (a count)"), std::string::npos) << run.output;
  EXPECT_TRUE(directory_holds_only_the_input());
}

TEST_F(CondenseCli, InterruptedRunLeavesNoOutputAndExitsWithThree) {
  // A model big enough to take a few seconds; SIGTERM arrives while it works.
  std::string big = replace(kGood, "elements_per_segment = 10", "elements_per_segment = 6000");
  big = replace(big, "fmax = 2000.0", "modes = 300");
  const fs::path input = dir_ / "part.toml";
  std::ofstream(input) << big;
  const std::string command = "timeout --preserve-status -s TERM 1 " + std::string(NVH_CONDENSE_EXE) + " " +
                              input.string() + " -o " + output().string() + " --method modal 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::string text;
  std::array<char, 512> buffer;
  while (fgets(buffer.data(), buffer.size(), pipe)) text += buffer.data();
  const int status = pclose(pipe);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 3) << text;
  EXPECT_NE(text.find("terminated (SIGTERM)"), std::string::npos) << text;
  EXPECT_TRUE(directory_holds_only_the_input());
}

// ---------------------------------------------------------------------------------------------
// Volume components: bad input gives exit 1, a located message and no output (issue 3, section 5).

class VolumeCli : public CondenseCli {
 protected:
  void SetUp() override {
    CondenseCli::SetUp();
    // A 0.1 x 0.02 x 0.02 m steel bar with its end faces as physical groups.
    std::ofstream(dir_ / "bar.geo")
        << "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 0.1, 0.02, 0.02};\n"
           "Physical Surface(\"LEFT\") = Surface In BoundingBox{-1e-4, -1, -1, 1e-4, 1, 1};\n"
           "Physical Surface(\"RIGHT\") = Surface In BoundingBox{0.0999, -1, -1, 0.1001, 1, 1};\n"
           "Physical Volume(\"BAR\") = {1};\nMesh.MeshSizeMax = 0.01;\n";
  }
  /// Line 10: [volume] mesh; 13-16: the [[interface]] (15: its `at`); then [reduction] and `extra`.
  static std::string component(const std::string& mesh, const std::string& interface_lines,
                               const std::string& extra = "") {
    return "[component]\nname = \"bar\"\nkind = \"volume\"\n[material.steel]\nE = 210e9\nnu = 0.3\n"
           "rho = 7850.0\n\n[volume]\nmesh = \"" +
           mesh + "\"\nmaterial = \"steel\"\n\n[[interface]]\nname = \"end\"\n" + interface_lines +
           "\n[reduction]\nmethod = \"modal\"\nmodes = 4\n" + extra;
  }
  /// No output, no temporary: only the inputs the test wrote.
  bool only_inputs() const {
    for (const auto& entry : fs::directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      if (name != "part.toml" && name != "bar.geo" && name != "bad.geo" && name != "tet.inp") return false;
    }
    return true;
  }
};

const std::string kRightFace = "at = [0.1, 0.01, 0.01]\nsurface = \"RIGHT\"";

TEST_F(VolumeCli, GoodInputCondenses) {
  const CliRun run = run_condense(component("bar.geo", kRightFace));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("stages [s]: read"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("factor: "), std::string::npos) << run.output;
  nvh::h5::File file = nvh::h5::File::open_read(output());
  const nvh::h5::Group model = file.root().open_group("model");
  const std::vector<std::string> stages = model.strings_attribute("stage_names");
  for (const char* stage : {"mesh", "assemble", "order", "factor", "eigen-solve", "reduce"})
    EXPECT_NE(std::find(stages.begin(), stages.end(), stage), stages.end()) << stage;
  // The fill of the factor: nnz(L) / nnz(tril A) >= 1, and METIS or AMD chose the ordering.
  EXPECT_GE(model.double_attribute("factor_fill"), 1.0);
  EXPECT_FALSE(model.string_attribute("factor_ordering").empty());
}

TEST_F(VolumeCli, UnreadableGeometry) {
  std::ofstream(dir_ / "bad.geo") << "this is not a gmsh script {\n";
  const CliRun run = run_condense(component("bad.geo", kRightFace));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("bad.geo"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("gmsh"), std::string::npos) << run.output;
  EXPECT_TRUE(only_inputs());
}

TEST_F(VolumeCli, PhysicalGroupThatDoesNotExist) {
  const CliRun run = run_condense(component("bar.geo", "at = [0.1, 0.01, 0.01]\nsurface = \"TIP\""));
  expect_located(run, 15, "interface[1].surface", "\"TIP\" is not in the mesh");
  EXPECT_NE(run.output.find("LEFT"), std::string::npos) << run.output;  // the sets it has
  EXPECT_TRUE(only_inputs());
}

TEST_F(VolumeCli, SelectorThatCatchesNoNode) {
  const CliRun run =
      run_condense(component("bar.geo", "at = [0.1, 0.01, 0.01]\nbox = [0.2, 0, 0, 0.3, 1, 1]"));
  expect_located(run, 15, "interface[1].box", "the box holds no node of the mesh");
  EXPECT_TRUE(only_inputs());
}

TEST_F(VolumeCli, InvertedElement) {
  // One C3D4 with nodes 2 and 3 exchanged: inside out.
  std::ofstream(dir_ / "tet.inp")
      << "*NODE\n1, 0, 0, 0\n2, 0.01, 0, 0\n3, 0, 0.01, 0\n4, 0, 0, 0.01\n"
         "*ELEMENT, TYPE=C3D4, ELSET=E\n7, 1, 3, 2, 4\n*NSET, NSET=FACE\n1, 2, 3\n";
  const CliRun run = run_condense(component("tet.inp", "at = [0, 0, 0]\nsurface = \"FACE\""));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("tet.inp:7"), std::string::npos) << run.output;  // file and line of the element
  EXPECT_NE(run.output.find("element 7 (C3D4)"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("inverted"), std::string::npos) << run.output;
  EXPECT_TRUE(only_inputs());
}

TEST_F(VolumeCli, ConnectionPointFarFromItsSurface) {
  // 100 mm typed as 100 m.
  const CliRun run = run_condense(component("bar.geo", "at = [100, 0.01, 0.01]\nsurface = \"RIGHT\""));
  expect_located(run, 15, "interface[1].at", "farther than the size of the surface");
  EXPECT_TRUE(only_inputs());
}

TEST_F(VolumeCli, KeepMeshIsForVolumes) {
  const CliRun run = run_condense(kGood, "--keep-mesh");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("--keep-mesh is for volume components"), std::string::npos) << run.output;
  EXPECT_TRUE(only_inputs());
}

}  // namespace
