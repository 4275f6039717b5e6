// [output] compression (docs/scene-format.md section 8): the gzip level of the time histories. Level 0 writes
// them without filters (faster: 25 % less CPU on the valvetrain at 40 kHz, files 2.75 x larger), any level
// writes the same numbers (deflate is lossless), and a level outside 0..9 is refused naming the key.
#include <gtest/gtest.h>

#include <hdf5.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

/// The number of filters on a dataset (0: stored raw; shuffle and deflate: 2).
int filters(const std::filesystem::path& file, const char* dataset) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, dataset, H5P_DEFAULT);
  const hid_t p = H5Dget_create_plist(d);
  const int n = H5Pget_nfilters(p);
  H5Pclose(p), H5Dclose(d), H5Fclose(f);
  return n;
}

TEST(OutputCompression, LevelZeroStoresRawAndEveryLevelTheSameNumbers) {
  auto scene_at = [](const std::string& level) {
    return testing::shipped_scene(
        "scenes/slider_crank.toml",
        {{"sample_rate_hz = 10000", "sample_rate_hz = 10000\ncompression = " + level}});
  };
  const auto raw = testing::run_text(scene_at("0"), "compression_0");
  const auto packed = testing::run_text(scene_at("6"), "compression_6");
  const auto plain =
      testing::run_text(testing::shipped_scene("scenes/slider_crank.toml"), "compression_default");
  EXPECT_EQ(filters(raw, "/time"), 0);
  EXPECT_EQ(filters(packed, "/time"), 2);  // shuffle and deflate
  EXPECT_EQ(filters(plain, "/time"), 2);
  auto read = [](const std::filesystem::path& f, const std::string& path) -> Eigen::MatrixXd {
    if (path == "time") return testing::signal(f, path);
    return testing::matrix(f, path);
  };
  for (const std::string path : {"time", "bodies/crank/position", "joints/big_end/reaction_force"}) {
    const Eigen::MatrixXd a = read(raw, path), b = read(packed, path), c = read(plain, path);
    ASSERT_EQ(a.rows(), b.rows()) << path;
    ASSERT_EQ(a.rows(), c.rows()) << path;
    EXPECT_EQ((a - b).cwiseAbs().maxCoeff(), 0.0) << path;  // bit for bit
    EXPECT_EQ((a - c).cwiseAbs().maxCoeff(), 0.0) << path;
  }
  EXPECT_GT(std::filesystem::file_size(raw), std::filesystem::file_size(packed));
}

/// The chunk dims of a dataset.
std::vector<hsize_t> chunk_of(const std::filesystem::path& file, const char* dataset) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, dataset, H5P_DEFAULT);
  const hid_t p = H5Dget_create_plist(d);
  std::vector<hsize_t> dims(2, 0);
  dims.resize(std::max(0, H5Pget_chunk(p, 2, dims.data())));
  H5Pclose(p), H5Dclose(d), H5Fclose(f);
  return dims;
}

// A time history's chunk is one flush of samples (chunk_samples rows, halved while it would hold more than
// 128 Ki values), so that deflate passes over each sample once or twice, not at every flush that adds to a
// larger chunk (docs/results-format.md, Storage). Exact: the chunk dims as stored.
TEST(OutputCompression, AChunkHoldsOneFlushOfSamples) {
  auto run_with = [](int chunk_samples) {
    return testing::run_text(
        testing::shipped_scene("scenes/slider_crank.toml",
                               {{"sample_rate_hz = 10000", "sample_rate_hz = 10000\nchunk_samples = " +
                                                               std::to_string(chunk_samples)}}),
        "chunks_" + std::to_string(chunk_samples));
  };
  const auto small = run_with(512), large = run_with(65536);
  EXPECT_EQ(chunk_of(small, "/time"), (std::vector<hsize_t>{512}));
  EXPECT_EQ(chunk_of(small, "/bodies/crank/position"), (std::vector<hsize_t>{512, 3}));
  EXPECT_EQ(chunk_of(large, "/time"), (std::vector<hsize_t>{65536}));
  EXPECT_EQ(chunk_of(large, "/bodies/crank/position"), (std::vector<hsize_t>{32768, 3}));  // 98,304 values
}

TEST(OutputCompression, ALevelOutsideZeroToNineIsRefusedNamingTheKey) {
  const std::string text = testing::shipped_scene(
      "scenes/slider_crank.toml", {{"sample_rate_hz = 10000", "sample_rate_hz = 10000\ncompression = 10"}});
  const std::string msg = testing::scene_error(text);
  EXPECT_NE(msg.find("output.compression"), std::string::npos) << msg;
}

}  // namespace
}  // namespace nvh::solve
