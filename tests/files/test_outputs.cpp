// What every tool guarantees on its output paths (issue 18, items 1, 2 and 12), through the binaries:
// - an output that is an input (by any path: "./a", a symbolic link) is refused before any work, exit 1, the
//   message names both paths, the input is unchanged;
// - an output that cannot be written (missing directory, a file where a directory is expected) is refused
//   before any work, and no output of the run is left (HDF5, CSV);
// - a full disk (a small tmpfs, when the test runs as root and may mount one) gives exit 1, a message
//   naming the file and "No space left on device", no segfault, and no temporary left;
// - postproc stats --csv writes the statistics table.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

struct CliRun {
  int exit_code = 0;
  std::string output;
};

CliRun run(const std::string& command) {
  CliRun r;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  std::array<char, 512> buffer;
  while (fgets(buffer.data(), buffer.size(), pipe)) r.output += buffer.data();
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;  // -1: killed by a signal (a crash)
  return r;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

const std::string kCondense = NVH_CONDENSE_EXE;
const std::string kSolve = NVH_SOLVE_EXE;
const std::string kPostproc = NVH_POSTPROC_EXE;
const std::string kSource = NVH_SOURCE_DIR;

const char* kBearing = R"([bearing]
name = "test"
model = "short"
diameter = 0.05
width = 0.02
radial_clearance = 25e-6
viscosity = 0.01

[map]
speed_rpm = 3000
eccentricities = [0.2, 0.5, 0.8]
)";

class files : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nvh_files_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(dir_ / "bearing.toml") << kBearing;
    fs::copy_file(kSource + "/testdata/crankshaft.toml", dir_ / "crankshaft.toml");
    fs::copy_file(kSource + "/testdata/scenes/slider_crank.toml", dir_ / "scene.toml");
  }
  void TearDown() override {
    if (mounted_) {
      EXPECT_EQ(std::system(("umount " + full_.string()).c_str()), 0);
    }
    fs::remove_all(dir_);
  }
  std::string at(const std::string& name) const { return (dir_ / name).string(); }
  fs::path results() {
    if (!fs::exists(dir_ / "results.h5")) {
      const CliRun r = run(kSolve + " " + at("scene.toml") + " -o " + at("results.h5") + " -q");
      EXPECT_EQ(r.exit_code, 0) << r.output;
    }
    return dir_ / "results.h5";
  }
  /// Expect a refusal naming both paths, with `input` unchanged.
  void expect_refused(const CliRun& r, const std::string& output, const fs::path& input,
                      const std::string& before) {
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, output)) << r.output;
    EXPECT_TRUE(contains(r.output, input.filename().string())) << r.output;
    EXPECT_TRUE(contains(r.output, "would destroy the input")) << r.output;
    EXPECT_EQ(read_text(input), before) << input << " was changed";
  }
  /// A tmpfs of `kib` KiB at dir_/full, false (and the test skipped) where one cannot be mounted.
  bool mount_small_disk(int kib) {
    if (::geteuid() != 0) return false;
    full_ = dir_ / "full";
    fs::create_directories(full_);
    const std::string command =
        "mount -t tmpfs -o size=" + std::to_string(kib) + "k tmpfs " + full_.string() + " 2>/dev/null";
    mounted_ = std::system(command.c_str()) == 0;
    return mounted_;
  }
  /// Fill the small disk up to `kib` KiB short of full.
  void fill_disk_leaving(int kib) {
    std::system(("dd if=/dev/zero of=" + (full_ / "filler").string() + " bs=1k 2>/dev/null").c_str());
    std::system(("truncate -s -" + std::to_string(kib) + "k " + (full_ / "filler").string()).c_str());
  }
  /// Files in the small disk other than the filler.
  std::string left_on_disk() const {
    std::string names;
    for (const auto& e : fs::directory_iterator(full_))
      if (e.path().filename() != "filler") names += e.path().filename().string() + " ";
    return names;
  }
  /// Exit 1 on a full disk, the file and the reason named.
  static void expect_disk_full(const CliRun& r, const std::string& file) {
    EXPECT_EQ(r.exit_code, 1) << r.output;  // -1 would be a crash
    EXPECT_TRUE(contains(r.output, file)) << r.output;
    EXPECT_TRUE(contains(r.output, "No space left on device")) << r.output;
  }

  fs::path dir_, full_;
  bool mounted_ = false;
};

// ---- output = input ----

TEST_F(files, CondenseRefusesToOverwriteItsComponent) {
  const std::string before = read_text(dir_ / "crankshaft.toml");
  const std::string output = (dir_ / "." / "crankshaft.toml").string();
  expect_refused(run(kCondense + " " + at("crankshaft.toml") + " -o " + output), output,
                 dir_ / "crankshaft.toml", before);
}

TEST_F(files, SolveRefusesToOverwriteItsSceneOrASuperelementItReads) {
  const std::string before = read_text(dir_ / "scene.toml");
  fs::create_symlink(dir_ / "scene.toml", dir_ / "link.h5");
  expect_refused(run(kSolve + " " + at("scene.toml") + " -o " + at("link.h5")), at("link.h5"),
                 dir_ / "scene.toml", before);
  // A flexible scene: the superelement it reads.
  fs::copy_file(kSource + "/testdata/scenes/slider_crank_flexible.toml", dir_ / "flexible.toml");
  ASSERT_EQ(run(kCondense + " " + kSource + "/testdata/conrod.toml -o " + at("conrod.h5") + " -q").exit_code,
            0);
  const std::string superelement = read_text(dir_ / "conrod.h5");
  const std::string output = (dir_ / "." / "conrod.h5").string();
  expect_refused(run(kSolve + " " + at("flexible.toml") + " -o " + output), output, dir_ / "conrod.h5",
                 superelement);
}

TEST_F(files, PostprocRefusesToOverwriteTheResultsItReads) {
  const fs::path r = results();
  const std::string before = read_text(r);
  fs::create_symlink(r, dir_ / "link.h5");
  expect_refused(run(kPostproc + " stats " + r.string() + ":/time -o " + at("link.h5")), at("link.h5"), r,
                 before);
}

TEST_F(files, BearingMapRefusesToOverwriteItsBearingFileOrItsOwnMap) {
  const std::string before = read_text(dir_ / "bearing.toml");
  const std::string csv = (dir_ / "." / "bearing.toml").string();
  expect_refused(run(kSolve + " bearing-map " + at("bearing.toml") + " -o " + at("map.h5") + " --csv " + csv),
                 csv, dir_ / "bearing.toml", before);
  EXPECT_FALSE(fs::exists(dir_ / "map.h5"));
  const CliRun same =
      run(kSolve + " bearing-map " + at("bearing.toml") + " -o " + at("map.h5") + " --csv " + at("map.h5"));
  EXPECT_EQ(same.exit_code, 1) << same.output;
  EXPECT_TRUE(contains(same.output, "are the same file")) << same.output;
}

// ---- outputs that cannot be written: refused before the work, nothing left ----

TEST_F(files, UnwritableOutputsAreRefusedBeforeTheWorkAndLeaveNothing) {
  std::ofstream(dir_ / "a_file") << "x";
  const std::string nowhere = at("a_file") + "/sub";  // a path below a regular file
  const CliRun c = run(kCondense + " " + at("crankshaft.toml") + " -o " + nowhere + "/c.h5");
  EXPECT_EQ(c.exit_code, 1) << c.output;
  EXPECT_TRUE(contains(c.output, "cannot write the output")) << c.output;
  EXPECT_FALSE(contains(c.output, "reduction")) << "condense started the work: " << c.output;

  const CliRun m = run(kSolve + " bearing-map " + at("bearing.toml") + " -o " + at("map.h5") + " --csv " +
                       nowhere + "/map.csv");
  EXPECT_EQ(m.exit_code, 1) << m.output;
  EXPECT_FALSE(fs::exists(dir_ / "map.h5")) << "the map was written although its CSV cannot be";

  const fs::path r = results();
  const CliRun p =
      run(kPostproc + " stats " + r.string() + ":/time -o " + at("stats.h5") + " --plot " + nowhere);
  EXPECT_EQ(p.exit_code, 1) << p.output;
  EXPECT_FALSE(fs::exists(dir_ / "stats.h5")) << "the output was written although its plots cannot be";
  const CliRun q = run(kPostproc + " spectrum " + r.string() + ":/energy/kinetic -o " + at("s.h5") +
                       " --csv " + nowhere + " --resolution 100");
  EXPECT_EQ(q.exit_code, 1) << q.output;
  EXPECT_FALSE(fs::exists(dir_ / "s.h5"));
  for (const auto& e : fs::directory_iterator(dir_))
    EXPECT_FALSE(contains(e.path().filename().string(), ".tmp-")) << e.path();
}

TEST_F(files, PostprocStatsWritesTheCsvTable) {
  const fs::path r = results();
  const CliRun p = run(kPostproc + " stats " + r.string() + ":/energy/kinetic " + r.string() +
                       ":/markers/piston.pin/position[0] -o " + at("stats.h5") + " --csv " + at("csv"));
  ASSERT_EQ(p.exit_code, 0) << p.output;
  std::istringstream table(read_text(dir_ / "csv" / "stats.csv"));
  std::string header, first, second, extra;
  std::getline(table, header);
  std::getline(table, first);
  std::getline(table, second);
  EXPECT_EQ(header, "signal,unit,mean,rms,peak,crest_factor");
  EXPECT_EQ(first.rfind("energy_kinetic,J,", 0), 0u) << first;
  EXPECT_EQ(second.rfind("markers_piston_pin_position_x,m,", 0), 0u) << second;
  EXPECT_FALSE(std::getline(table, extra));
}

// ---- a full disk ----

TEST_F(files, EveryToolFailsCleanlyOnAFullDisk) {
  if (!mount_small_disk(1024)) GTEST_SKIP() << "needs root and a mountable tmpfs for a small disk";
  const fs::path r = results();
  for (const int room : {8, 200}) {  // fails at the first write, or later in the run
    SCOPED_TRACE("room left: " + std::to_string(room) + " KiB");
    fill_disk_leaving(room);
    const std::string c = (full_ / "c.h5").string();
    expect_disk_full(run(kCondense + " " + at("crankshaft.toml") + " -o " + c + " -q"), c);
    EXPECT_EQ(left_on_disk(), "");

    const std::string m = (full_ / "map.h5").string();
    const CliRun map = run(kSolve + " bearing-map " + at("bearing.toml") + " -o " + m + " --csv " +
                           (full_ / "map.csv").string() + " -q");
    if (room < 20) {
      expect_disk_full(map, (full_ / "map.").string());  // the map or its CSV, whichever fails first
      EXPECT_EQ(left_on_disk(), "");
    }
    fs::remove(full_ / "map.h5");
    fs::remove(full_ / "map.csv");

    const std::string p = (full_ / "p.h5").string();
    const CliRun post = run(kPostproc + " spectrum " + r.string() +
                            ":/markers/piston.pin/acceleration[1] -o " + p + " --resolution 100 -q");
    if (room < 20) {
      expect_disk_full(post, p);
      EXPECT_EQ(left_on_disk(), "");
    } else {
      EXPECT_NE(post.exit_code, -1) << post.output;
    }
    fs::remove(p);

    // solve: the results file is made (layout), then grows at each checkpoint; a failure at either is an
    // error naming the file. Samples written before a failure during the run are kept (no temporary).
    const std::string s = (full_ / "r.h5").string();
    expect_disk_full(run(kSolve + " " + at("scene.toml") + " -o " + s + " -q"), s);
    EXPECT_FALSE(contains(left_on_disk(), ".tmp-")) << left_on_disk();
    fs::remove(full_ / "r.h5");
    fs::remove(full_ / "filler");
  }
}

}  // namespace
