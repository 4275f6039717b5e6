// SHA-256 against the FIPS 180-2 test vectors and digests from an independent implementation
// (Python's hashlib, i.e. OpenSSL), for strings, byte buffers and files.
#include "common/sha256.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/xattr.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "common/error.hpp"

namespace nvh {
namespace {

namespace fs = std::filesystem;

// FIPS 180-2, appendix B.1 (one block), B.2 (two blocks), B.3 (one million 'a'), and the empty message.
TEST(Sha256, FipsTestVectors) {
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256_hex(std::string(1000000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  // The 896-bit message of FIPS 180-4's SHA-512 examples, hashed with SHA-256.
  EXPECT_EQ(
      sha256_hex("abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmnoijklmnopjklmnopqklmnopqrlmn"
                 "opqrsmnopqrstnopqrstu"),
      "cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1");
}

// Lengths around the padding boundaries (55/56 bytes: length fits in the last block or not; 64: exactly
// one block), against Python's hashlib.sha256(b"a" * n).
TEST(Sha256, PaddingBoundaries) {
  const std::vector<std::pair<size_t, std::string>> cases = {
      {55, "9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318"},
      {56, "b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a"},
      {63, "7d3e74a05d7db15bce4ad9ec0658ea98e3f06eeecf16b4c6fff2da457ddc2f34"},
      {64, "ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb"},
      {65, "635361c48bb9eab14198e76ea8ab7f1a41685d6ad62aa9146d301d4f17eb0ae0"},
      {119, "31eba51c313a5c08226adf18d4a359cfdfd8d2e816b13f4af952f7ea6584dcfb"},
      {120, "2f3d335432c70b580af0e8e1b3674a7c020d683aa5f73aaaedfdc55af904c21c"},
      {1000, "41edece42d63e8d9bf515a9ba6932e1c20cbc9f5a5d134645adb5db1b9737ea3"},
  };
  for (const auto& [length, digest] : cases)
    EXPECT_EQ(sha256_hex(std::string(length, 'a')), digest) << length;
}

// All 256 byte values (300 times): hashlib.sha256(bytes(range(256)) * 300).
std::vector<std::byte> all_byte_values() {
  std::vector<std::byte> bytes;
  for (int repeat = 0; repeat < 300; ++repeat) {
    for (int value = 0; value < 256; ++value) bytes.push_back(static_cast<std::byte>(value));
  }
  return bytes;
}
constexpr const char* kAllByteValuesDigest =
    "f8b0585eb91f58c007a5634362c9f90d8543822c113f702523bc7b73408a9392";

TEST(Sha256, ByteBuffer) {
  EXPECT_EQ(sha256_hex(std::span<const std::byte>(all_byte_values())), kAllByteValuesDigest);
  const std::string abc = "abc";
  EXPECT_EQ(sha256_hex(std::as_bytes(std::span(abc))),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

class Sha256FileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device random;
    directory_ = fs::temp_directory_path() /
                 ("nvh_test_sha256_" + std::to_string(::getpid()) + "_" + std::to_string(random()));
    fs::create_directories(directory_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(directory_, ignored);
  }
  fs::path write(const std::string& name, const void* data, size_t size) {
    const fs::path path = directory_ / name;
    std::ofstream(path, std::ios::binary)
        .write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
    return path;
  }
  fs::path directory_;
};

TEST_F(Sha256FileTest, FilesAreHashedByContent) {
  // Larger than the read buffer, so the digest spans several reads.
  const std::string million(1000000, 'a');
  EXPECT_EQ(sha256_file(write("million.txt", million.data(), million.size())),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  const std::vector<std::byte> bytes = all_byte_values();  // includes NUL, CR, LF and 0x1a
  EXPECT_EQ(sha256_file(write("binary.bin", bytes.data(), bytes.size())), kAllByteValuesDigest);
  EXPECT_EQ(sha256_file(write("abc.txt", "abc", 3)),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_file(write("empty.txt", "", 0)),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

// The digest remembered in the file's attribute user.nvh.sha256 with its size and mtime: read back while both
// are unchanged (a forged record with the file's stat is believed: the cache trusts the stat, as make does),
// recomputed when the mtime changes, ignored with NVH_HASH_CACHE=0; a file modified within the last second is
// hashed but not remembered.
TEST_F(Sha256FileTest, DigestIsRememberedWhileSizeAndMtimeAreUnchanged) {
  const fs::path file = write("abc.bin", "abc", 3);
  const std::string abc = "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad";
  // Just written: hashed, but not remembered (a rewrite within the file system's clock tick keeps the mtime).
  EXPECT_EQ(sha256_file(file), abc);
  char value[256];
  EXPECT_LT(getxattr(file.c_str(), "user.nvh.sha256", value, sizeof value), 0);
  // Last modified long ago: remembered.
  struct timespec old_times[2] = {{0, UTIME_OMIT}, {1600000000, 5}};
  ASSERT_EQ(utimensat(AT_FDCWD, file.c_str(), old_times, 0), 0);
  EXPECT_EQ(sha256_file(file), abc);
  const ssize_t n = getxattr(file.c_str(), "user.nvh.sha256", value, sizeof value);
  if (n < 0) GTEST_SKIP() << "no user extended attributes here: " << std::strerror(errno);
  const std::string record(value, static_cast<size_t>(n));
  EXPECT_EQ(record.substr(record.size() - 64), abc);
  EXPECT_EQ(record, "nvh-sha256 v1 size=3 mtime_ns=1600000000000000005 " + abc);
  // A forged digest under the file's own size and mtime is returned: the content is not read again.
  const std::string forged = record.substr(0, record.size() - 64) + std::string(64, 'f');
  ASSERT_EQ(setxattr(file.c_str(), "user.nvh.sha256", forged.data(), forged.size(), 0), 0);
  EXPECT_EQ(sha256_file(file), std::string(64, 'f'));
  // ... but not with the cache turned off,
  setenv("NVH_HASH_CACHE", "0", 1);
  EXPECT_EQ(sha256_file(file), abc);
  unsetenv("NVH_HASH_CACHE");
  // ... and not once the content changes (same size, a new mtime): the new digest, and it is remembered.
  std::ofstream(file, std::ios::binary).write("abd", 3);
  struct timespec times[2] = {{0, UTIME_OMIT}, {1700000000, 123456789}};
  ASSERT_EQ(utimensat(AT_FDCWD, file.c_str(), times, 0), 0);
  const std::string abd = "a52d159f262b2c6ddb724a61840befc36eb30c88877a4030b65cbe86298449c9";
  EXPECT_EQ(sha256_file(file), abd);
  const ssize_t m = getxattr(file.c_str(), "user.nvh.sha256", value, sizeof value);
  ASSERT_GT(m, 0);
  EXPECT_EQ(std::string(value, static_cast<size_t>(m)),
            "nvh-sha256 v1 size=3 mtime_ns=1700000000123456789 " + abd);
  EXPECT_EQ(sha256_file(file), abd);
}

TEST_F(Sha256FileTest, UnreadableFilesAreNamed) {
  const fs::path missing = directory_ / "missing.toml";
  try {
    sha256_file(missing);
    FAIL() << "expected nvh::Error";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()), missing.string() + ": cannot read: No such file or directory");
  }
  try {
    sha256_file(directory_);
    FAIL() << "expected nvh::Error";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()),
              directory_.string() + ": cannot hash: is a directory, expected a file");
  }
}

}  // namespace
}  // namespace nvh
