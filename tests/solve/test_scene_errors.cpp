// Bad scenes: each error names the file, line and key and says what was expected; the CLI exits 1 and leaves
// no output.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "common/error.hpp"
#include "solve/element_registry.hpp"
#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

const std::string kBase = R"(
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "a"
[[body]]
name = "arm"
type = "rigid"
mass = 1.0
inertia = [0.1, 0.1, 0.1]
  [[body.marker]]
  name = "pivot"
)";
const std::string kClock = "[clock]\nend_time = 0.01\n";

std::string error_of(const std::string& text) { return testing::scene_error(text); }

TEST(SolveSceneErrors, UnknownBodyInAJointIsNamedWithASuggestion) {
  const std::string msg = error_of(kBase + "[[joint]]\nname = \"j\"\ntype = \"revolute\"\ni = \"amr.pivot\"\nj = \"ground.a\"\n" + kClock);
  EXPECT_NE(msg.find("bad.toml:17"), std::string::npos) << msg;
  EXPECT_NE(msg.find("no body 'amr' (did you mean 'arm'?)"), std::string::npos) << msg;
}

TEST(SolveSceneErrors, MarkerNotOnItsBodyListsTheMarkers) {
  const std::string msg = error_of(kBase + "[[joint]]\nname = \"j\"\ntype = \"revolute\"\ni = \"arm.tip\"\nj = \"ground.a\"\n" + kClock);
  EXPECT_NE(msg.find("body 'arm' has no marker 'tip'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("its markers: pivot"), std::string::npos) << msg;
}

TEST(SolveSceneErrors, NonPositiveMassAndInertia) {
  std::string text = kBase + kClock;
  EXPECT_NE(error_of(std::string(text).replace(text.find("mass = 1.0"), 10, "mass = 0.0")).find("mass': expected a number > 0"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(text).replace(text.find("[0.1, 0.1, 0.1]"), 15, "[0.1, -0.1, 0.1]")).find("positive definite"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(text).replace(text.find("[0.1, 0.1, 0.1]"), 15, "[0.1, 0.1, 0.5]")).find("triangle inequality"),
            std::string::npos);
}

TEST(SolveSceneErrors, TableNotMonotonicInItsAbscissa) {
  const std::string msg = error_of(kBase + "[[load]]\nname = \"p\"\ntype = \"force\"\nat = \"arm.pivot\"\ndirection = [0, 0, 1]\n"
                                           "table = [[0.0, 1.0], [0.2, 2.0], [0.1, 3.0]]\n" + kClock);
  EXPECT_NE(msg.find("bad.toml:19"), std::string::npos) << msg;
  EXPECT_NE(msg.find("must increase strictly"), std::string::npos) << msg;
}

TEST(SolveSceneErrors, JointOnOneBodyAndMissingClock) {
  EXPECT_NE(error_of(kBase + "[[joint]]\nname = \"j\"\ntype = \"fixed\"\ni = \"arm.pivot\"\nj = \"arm.pivot\"\n" + kClock).find("same body"),
            std::string::npos);
  EXPECT_NE(error_of(kBase).find("[clock]"), std::string::npos);
}

TEST(SolveSceneErrors, CliExitsOneAndWritesNothing) {
  const auto scene = testing::temp_path("bad_scene.toml");
  const auto out = testing::temp_path("bad_scene.h5");
  std::ofstream(scene) << kBase << "[[joint]]\nname = \"j\"\ntype = \"hinge\"\ni = \"arm.pivot\"\nj = \"ground.a\"\n" << kClock;
  const std::string cmd = std::string(NVH_BINARY_DIR) + "/solve/solve " + scene.string() + " -o " + out.string() + " -q 2>/dev/null";
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_FALSE(std::filesystem::exists(out));
}

// The accepted element types come from the registry: an unknown type's error lists every registered [[force]]
// type, and `solve --help` lists every registered type of every section.
TEST(SolveSceneErrors, UnknownForceTypeListsTheRegisteredOnes) {
  const std::string msg = error_of(kBase + "[[force]]\nname = \"f\"\ntype = \"springdamper\"\ni = \"arm.pivot\"\n"
                                           "j = \"ground.a\"\n" + kClock);
  EXPECT_NE(msg.find("bad.toml"), std::string::npos) << msg;
  for (const std::string& name : builtin_elements().names("force"))
    EXPECT_NE(msg.find(name), std::string::npos) << "not listed: " << name << "\n" << msg;
}

TEST(SolveSceneErrors, HelpListsEveryRegisteredElementType) {
  const auto out = testing::temp_path("solve_help.txt");
  const std::string cmd = std::string(NVH_BINARY_DIR) + "/solve/solve --help > " + out.string();
  ASSERT_EQ(WEXITSTATUS(std::system(cmd.c_str())), 0);
  std::ifstream in(out);
  const std::string help((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  int listed = 0;
  for (const ElementType* et : builtin_elements().all()) {
    const std::string line = "[[" + et->section + "]] type = \"" + et->name + "\"";
    EXPECT_NE(help.find(line), std::string::npos) << "not in --help: " << line;
    ++listed;
  }
  EXPECT_GE(listed, 11);  // the shipped types (force_element.hpp); fewer means the registry lost some
}

}  // namespace
}  // namespace nvh::solve
