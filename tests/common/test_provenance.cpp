// Provenance: command-line quoting, input hashes, time stamp and host, and the root attributes written.
#include "common/provenance.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <climits>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/version.hpp"

namespace nvh {
namespace {

namespace fs = std::filesystem;

TEST(CommandLine, PlainArgumentsAreJoinedWithSpaces) {
  const char* argv[] = {"condense", "--input", "engine/model.toml", "-o", "out.h5", "--tol=1e-8"};
  EXPECT_EQ(join_command_line(6, argv), "condense --input engine/model.toml -o out.h5 --tol=1e-8");
}

TEST(CommandLine, ArgumentsTheShellWouldSplitAreSingleQuoted) {
  const char* argv[] = {"solve", "my model.toml", "it's", "", "$HOME", "a;b", "*.h5", "\"q\""};
  EXPECT_EQ(join_command_line(8, argv), R"(solve 'my model.toml' 'it'\''s' '' '$HOME' 'a;b' '*.h5' '"q"')");
  EXPECT_EQ(join_command_line(0, argv), "");
}

class ProvenanceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device random;
    directory_ = fs::temp_directory_path() /
                 ("nvh_test_provenance_" + std::to_string(::getpid()) + "_" + std::to_string(random()));
    fs::create_directories(directory_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(directory_, ignored);
  }
  fs::path write(const std::string& name, const std::string& content) {
    const fs::path path = directory_ / name;
    std::ofstream(path, std::ios::binary) << content;
    return path;
  }
  fs::path directory_;
};

// Parse "YYYY-MM-DDTHH:MM:SSZ" as UTC seconds since the epoch.
std::time_t parse_utc(const std::string& text) {
  std::tm utc{};
  std::sscanf(text.c_str(), "%d-%d-%dT%d:%d:%dZ", &utc.tm_year, &utc.tm_mon, &utc.tm_mday, &utc.tm_hour,
              &utc.tm_min, &utc.tm_sec);
  utc.tm_year -= 1900;
  utc.tm_mon -= 1;
  return timegm(&utc);
}

TEST_F(ProvenanceTest, MakeProvenanceHashesInputsAndStampsTimeAndHost) {
  // FIPS 180-2 digests of "abc" and of the empty message.
  const fs::path abc = write("abc.toml", "abc");
  const fs::path empty = write("empty.toml", "");
  const char* argv[] = {"condense", "-i", "abc.toml"};
  const auto before = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  const Provenance provenance = make_provenance("condense", 3, argv, {abc, empty});
  const auto after = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());

  EXPECT_EQ(provenance.tool, "condense");
  EXPECT_EQ(provenance.tool_version, std::string(kVersion));
  EXPECT_EQ(provenance.command_line, "condense -i abc.toml");
  EXPECT_EQ(provenance.inputs, (std::vector<fs::path>{abc, empty}));
  EXPECT_EQ(provenance.input_sha256,
            (std::vector<std::string>{"ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad",
                                      "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"}));

  EXPECT_TRUE(std::regex_match(provenance.created_utc, std::regex(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ)")))
      << provenance.created_utc;
  const std::time_t stamped = parse_utc(provenance.created_utc);
  EXPECT_GE(stamped, before);
  EXPECT_LE(stamped, after);

  char host[HOST_NAME_MAX + 1] = {};
  ASSERT_EQ(gethostname(host, HOST_NAME_MAX), 0);
  EXPECT_EQ(provenance.host, std::string(host));
  EXPECT_FALSE(provenance.host.empty());
}

TEST_F(ProvenanceTest, MissingInputIsNamed) {
  const fs::path missing = directory_ / "missing.toml";
  const char* argv[] = {"solve"};
  try {
    make_provenance("solve", 1, argv, {write("present.toml", "x"), missing});
    FAIL() << "expected nvh::Error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(missing.string()), std::string::npos) << error.what();
  }
}

TEST_F(ProvenanceTest, WrittenAsRootAttributes) {
  const fs::path input = write("model.toml", "abc");
  const char* argv[] = {"postproc", "--out", "my results.h5"};
  const Provenance provenance = make_provenance("postproc", 3, argv, {input});
  const fs::path path = directory_ / "results.h5";
  {
    h5::File out = h5::File::create(path);
    h5::Group root = out.root();
    write_provenance(root, provenance);
    out.commit();
  }
  h5::File in = h5::File::open_read(path);
  const h5::Group& root = in.root();
  EXPECT_EQ(root.string_attribute("tool"), "postproc");
  EXPECT_EQ(root.string_attribute("tool_version"), std::string(kVersion));
  EXPECT_EQ(root.string_attribute("command_line"), "postproc --out 'my results.h5'");
  EXPECT_EQ(root.string_attribute("created_utc"), provenance.created_utc);
  EXPECT_EQ(root.string_attribute("host"), provenance.host);
  EXPECT_EQ(root.strings_attribute("input_files"), std::vector<std::string>{input.string()});
  EXPECT_EQ(root.strings_attribute("input_sha256"),
            std::vector<std::string>{"ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"});
}

TEST_F(ProvenanceTest, NoInputsIsValid) {
  const char* argv[] = {"solve"};
  const Provenance provenance = make_provenance("solve", 1, argv, {});
  const fs::path path = directory_ / "none.h5";
  {
    h5::File out = h5::File::create(path);
    h5::Group root = out.root();
    write_provenance(root, provenance);
    out.commit();
  }
  h5::File in = h5::File::open_read(path);
  EXPECT_TRUE(in.root().strings_attribute("input_files").empty());
  EXPECT_TRUE(in.root().strings_attribute("input_sha256").empty());
}

TEST_F(ProvenanceTest, MismatchedHashesAreRejected) {
  Provenance provenance;
  provenance.inputs = {"a.toml", "b.toml"};
  provenance.input_sha256 = {"00"};
  h5::File out = h5::File::create(directory_ / "bad.h5");
  h5::Group root = out.root();
  EXPECT_THROW(write_provenance(root, provenance), Error);
}

}  // namespace
}  // namespace nvh
