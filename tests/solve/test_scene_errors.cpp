// Bad scenes: each error names the file, line and key and says what was expected; the CLI exits 1 and leaves
// no output.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iterator>

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

std::string error_of(const std::string& text) {
  return testing::scene_error(text);
}

TEST(SolveSceneErrors, UnknownBodyInAJointIsNamedWithASuggestion) {
  const std::string msg = error_of(
      kBase + "[[joint]]\nname = \"j\"\ntype = \"revolute\"\ni = \"amr.pivot\"\nj = \"ground.a\"\n" + kClock);
  EXPECT_NE(msg.find("bad.toml:17"), std::string::npos) << msg;
  EXPECT_NE(msg.find("no body 'amr' (did you mean 'arm'?)"), std::string::npos) << msg;
}

TEST(SolveSceneErrors, MarkerNotOnItsBodyListsTheMarkers) {
  const std::string msg = error_of(
      kBase + "[[joint]]\nname = \"j\"\ntype = \"revolute\"\ni = \"arm.tip\"\nj = \"ground.a\"\n" + kClock);
  EXPECT_NE(msg.find("body 'arm' has no marker 'tip'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("its markers: pivot"), std::string::npos) << msg;
}

TEST(SolveSceneErrors, NonPositiveMassAndInertia) {
  std::string text = kBase + kClock;
  EXPECT_NE(error_of(std::string(text).replace(text.find("mass = 1.0"), 10, "mass = 0.0"))
                .find("mass': expected a number in (0, 1e+12], got 0"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(text).replace(text.find("[0.1, 0.1, 0.1]"), 15, "[0.1, -0.1, 0.1]"))
                .find("positive definite"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(text).replace(text.find("[0.1, 0.1, 0.1]"), 15, "[0.1, 0.1, 0.5]"))
                .find("triangle inequality"),
            std::string::npos);
}

TEST(SolveSceneErrors, TableNotMonotonicInItsAbscissa) {
  const std::string msg =
      error_of(kBase +
               "[[load]]\nname = \"p\"\ntype = \"force\"\nat = \"arm.pivot\"\ndirection = [0, 0, 1]\n"
               "table = [[0.0, 1.0], [0.2, 2.0], [0.1, 3.0]]\n" +
               kClock);
  EXPECT_NE(msg.find("bad.toml:19"), std::string::npos) << msg;
  EXPECT_NE(msg.find("must increase strictly"), std::string::npos) << msg;
}

TEST(SolveSceneErrors, JointOnOneBodyAndMissingClock) {
  EXPECT_NE(
      error_of(kBase + "[[joint]]\nname = \"j\"\ntype = \"fixed\"\ni = \"arm.pivot\"\nj = \"arm.pivot\"\n" +
               kClock)
          .find("same body"),
      std::string::npos);
  EXPECT_NE(error_of(kBase).find("[clock]"), std::string::npos);
}

// The cam joint (docs/valvetrain.md section 2): its profile's keys are read as roller-cam's, each error
// naming the joint's key.
TEST(SolveSceneErrors, CamJointNamesItsProfileKeys) {
  const std::string joint =
      "[[joint]]\nname = \"cam\"\ntype = \"cam\"\ni = \"arm.pivot\"\nj = \"ground.a\"\n";
  const std::string no_profile = error_of(kBase + joint + kClock);
  EXPECT_NE(no_profile.find("bad.toml:14"), std::string::npos) << no_profile;
  EXPECT_NE(no_profile.find("'joint[1].profile': missing required key"), std::string::npos) << no_profile;
  const std::string eccentric =
      "profile = \"eccentric\"\nbase_radius = 0.02\neccentricity = 0.005\nroller_radius = 0.0\n";
  const std::string bad_roller = error_of(kBase + joint + eccentric + kClock);
  EXPECT_NE(bad_roller.find("'joint[1].roller_radius'"), std::string::npos) << bad_roller;
}

TEST(SolveSceneErrors, CliExitsOneAndWritesNothing) {
  const auto scene = testing::temp_path("bad_scene.toml");
  const auto out = testing::temp_path("bad_scene.h5");
  std::ofstream(scene) << kBase
                       << "[[joint]]\nname = \"j\"\ntype = \"hinge\"\ni = \"arm.pivot\"\nj = \"ground.a\"\n"
                       << kClock;
  const std::string cmd = std::string(NVH_BINARY_DIR) + "/solve/solve " + scene.string() + " -o " +
                          out.string() + " -q 2>/dev/null";
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_FALSE(std::filesystem::exists(out));
}

// Joints whose markers cannot meet (an arm of 0.5 m between pivots 1 m apart) fail the initial assembly; the
// error names the scene file and the joint violated most (the fuzzer found it naming neither), exit 1.
TEST(SolveSceneErrors, JointsThatCannotBeAssembledNameTheSceneAndTheJoint) {
  const auto scene = testing::temp_path("misfit.toml");
  const auto out = testing::temp_path("misfit.h5");
  const auto log = testing::temp_path("misfit.log");
  std::ofstream(scene) << R"(
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "a"
  [[body.marker]]
  name = "b"
  at = [1, 0, 0]
[[body]]
name = "arm"
type = "rigid"
mass = 1.0
inertia = [0.1, 0.1, 0.1]
  [[body.marker]]
  name = "pivot"
  [[body.marker]]
  name = "end"
  at = [0.5, 0, 0]
[[joint]]
name = "left"
type = "spherical"
i = "arm.pivot"
j = "ground.a"
[[joint]]
name = "right"
type = "spherical"
i = "arm.end"
j = "ground.b"
)" << kClock;
  const std::string cmd = std::string(NVH_BINARY_DIR) + "/solve/solve " + scene.string() + " -o " +
                          out.string() + " -q 2>" + log.string();
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_FALSE(std::filesystem::exists(out));
  std::ifstream in(log);
  const std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(err.find(scene.string() + ": the initial positions cannot be assembled"), std::string::npos)
      << err;
  EXPECT_NE(err.find("most in spherical '"), std::string::npos) << err;
}

// The accepted element types come from the registry: an unknown type's error lists every registered [[force]]
// type, and `solve --help` lists every registered type of every section.
TEST(SolveSceneErrors, UnknownForceTypeListsTheRegisteredOnes) {
  const std::string msg = error_of(kBase +
                                   "[[force]]\nname = \"f\"\ntype = \"springdamper\"\ni = \"arm.pivot\"\n"
                                   "j = \"ground.a\"\n" +
                                   kClock);
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

// Issue 18 item 4: numbers that are not finite, or absurd (a point mass of 1e308, a sample rate that never
// ends the run), are refused where they are read: the error names the file, the line of the value and the
// key. `value` is the text of the offending value; its line is found in `text`.
void expect_refused(const std::string& text, const std::string& value, const std::string& key,
                    const std::string& why = "") {
  const std::string msg = error_of(text);
  const auto at = text.find(value);
  ASSERT_NE(at, std::string::npos) << value;
  const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
  EXPECT_NE(msg.find("bad.toml:" + std::to_string(line) + ":"), std::string::npos) << value << ": " << msg;
  EXPECT_NE(msg.find("'" + key + "'"), std::string::npos) << value << ": " << msg;
  if (!why.empty()) {
    EXPECT_NE(msg.find(why), std::string::npos) << value << ": " << msg;
  }
}

const std::string kFinite = "numbers must be finite";
const std::string kContact =
    "[[force]]\nname = \"c\"\ntype = \"contact\"\ni = \"arm.pivot\"\nj = \"ground.a\"\nstiffness = 1e8\n";

TEST(SolveSceneErrors, NonFiniteNumbersAreRefusedNamingTheKey) {
  expect_refused(kBase + "  at = [0, 0, inf]\n" + kClock, "[0, 0, inf]", "body[2].marker[1].at[3]", kFinite);
  expect_refused(kBase + "  z = [0, -inf, 1]\n" + kClock, "[0, -inf, 1]", "body[2].marker[1].z[2]", kFinite);
  std::string body = kBase;
  body.replace(body.find("mass = 1.0"), 10, "mass = 1.0\nposition = [nan, 0, 0]");
  expect_refused(body + kClock, "[nan, 0, 0]", "body[2].position[1]", kFinite);
  expect_refused("[scene]\ngravity = [0, 0, -inf]\n" + kBase + kClock, "[0, 0, -inf]", "scene.gravity[3]",
                 kFinite);
  expect_refused(kBase + kContact + "clearance = inf\n" + kClock, "clearance = inf", "force[1].clearance",
                 kFinite);
  expect_refused(kBase + kContact + "clearance = -inf\n" + kClock, "clearance = -inf", "force[1].clearance",
                 kFinite);
  expect_refused(kBase + kContact + "clearance = 1e300\n" + kClock, "clearance = 1e300",
                 "force[1].clearance");
  expect_refused(kBase + "[clock]\nstart_time = -inf\nend_time = 0.01\n", "-inf", "clock.start_time",
                 kFinite);
  expect_refused(kBase + kClock + "[output]\nsample_rate_hz = inf\n", "inf", "output.sample_rate_hz",
                 kFinite);
  expect_refused(
      kBase + "[[driver]]\nname = \"d\"\ntype = \"speed\"\ni = \"arm.pivot\"\nj = \"ground.a\"\nrpm = inf\n" +
          kClock,
      "rpm = inf", "driver[1].rpm", kFinite);
  expect_refused(kBase +
                     "[[load]]\nname = \"p\"\ntype = \"force\"\nat = \"arm.pivot\"\ndirection = [0, 0, 1]\n"
                     "table = [[0.0, 1.0], [nan, 2.0]]\n" +
                     kClock,
                 "[nan, 2.0]", "load[1].table[2][1]", kFinite);
  expect_refused(
      kBase +
          "[[force]]\nname = \"s\"\ntype = \"spring-damper\"\ni = \"arm.pivot\"\nj = \"ground.a\"\n"
          "k = 1e5\nkB = -inf\n" +
          kClock,
      "kB = -inf", "force[1].kB", kFinite);
  expect_refused(
      kBase +
          "[[force]]\nname = \"s\"\ntype = \"spring-damper\"\ni = \"arm.pivot\"\nj = \"ground.a\"\n"
          "k = 1e5\nxB = 1e-320\n" +
          kClock,
      "xB = 1e-320", "force[1].xB", "subnormal");
}

TEST(SolveSceneErrors, AbsurdValuesAreRefusedNamingTheKey) {
  expect_refused(kBase + "[[body]]\nname = \"m\"\ntype = \"point-mass\"\nmass = 1e308\n" + kClock,
                 "mass = 1e308", "body[3].mass", "expected a number in (0, 1e+12]");
  expect_refused(kBase + kClock + "[output]\nsample_rate_hz = 1e308\n", "1e308", "output.sample_rate_hz");
  expect_refused(
      kBase +
          "[[driver]]\nname = \"d\"\ntype = \"speed\"\ni = \"arm.pivot\"\nj = \"ground.a\"\nrpm = 1e300\n" +
          kClock,
      "rpm = 1e300", "driver[1].rpm");
  // The number of samples: (end_time - start_time) * sample_rate_hz <= 1e9, named at the rate (or the end).
  expect_refused(kBase + "[clock]\nend_time = 1000.0\n[output]\nsample_rate_hz = 1e7\n", "sample_rate_hz",
                 "output.sample_rate_hz", "1e+10 samples, more than the limit of 1e+09 samples per run");
  expect_refused(kBase + "[clock]\nend_time = 1e9\n", "end_time", "clock.end_time",
                 "more than the limit of 1e+09");
  expect_refused(kBase + kClock + "[integrator]\natol = 1e308\n", "atol", "integrator.atol");
  expect_refused(kBase + kClock + "[integrator]\nlinear_solver = \"lu\"\n", "linear_solver",
                 "integrator.linear_solver", "\"auto\", \"klu\"");
  // A fixed generalized-alpha step that could never reach the end.
  expect_refused(kBase + kClock + "[integrator]\nmethod = \"generalized-alpha\"\nstep = 1e-300\n",
                 "step =", "integrator.step", "steps, more than the limit of 1e+10");
  expect_refused(kBase + "[clock]\ni = \"arm.pivot\"\nj = \"ground.a\"\nend_cycles = 1e300\n", "end_cycles",
                 "clock.end_cycles");
  // A run by crank angle: an end_time_limit given keeps within the samples too; the default does by itself.
  const std::string by_angle = kBase + "[clock]\ni = \"arm.pivot\"\nj = \"ground.a\"\nend_cycles = 2\n";
  expect_refused(by_angle + "end_time_limit = 1e6\n", "end_time_limit", "clock.end_time_limit",
                 "1e+10 samples, more than the limit of 1e+09");
  const Scene scene = parse_scene(by_angle + "[output]\nsample_rate_hz = 1e5\n", "ok.toml", ".");
  EXPECT_DOUBLE_EQ(scene.end_time, 1e4);  // 1e9 samples at 1e5 Hz
}

// CSV tables: a number that is not finite names the CSV file and its line, inside the error at the scene's
// key.
TEST(SolveSceneErrors, NonFiniteNumberInACsvTableNamesTheFileAndLine) {
  const auto csv = testing::temp_path("inf_table.csv");
  std::ofstream(csv) << "time,force\n0.0,1.0\n0.1,inf\n";
  const std::string text = kBase +
                           "[[load]]\nname = \"p\"\ntype = \"force\"\nat = \"arm.pivot\"\n"
                           "direction = [0, 0, 1]\nfile = \"" +
                           csv.string() + "\"\n" + kClock;
  expect_refused(text, "file =", "load[1].file", csv.string() + ":3: column 2: 'inf' is not a finite number");
  std::ofstream(csv) << "time,force\n0.0,1.0\nnan,2.0\n";
  expect_refused(text, "file =", "load[1].file", csv.string() + ":3: column 1: 'nan' is not a finite number");
  std::ofstream(csv) << "time,force\n0.0,1.0\n0.1,1e999\n";
  expect_refused(text, "file =", "load[1].file", csv.string() + ":3: column 2: '1e999'");
}

}  // namespace
}  // namespace nvh::solve
