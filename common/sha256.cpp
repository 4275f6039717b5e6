#include "common/sha256.hpp"

#include <openssl/evp.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/xattr.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string_view>
#include <vector>

#include "common/error.hpp"

namespace nvh {
namespace {

// SHA-256 (FIPS 180-4) by OpenSSL's libcrypto through its EVP digest interface (EVP_DigestInit_ex,
// EVP_DigestUpdate, EVP_DigestFinal_ex; OpenSSL 3 manual page EVP_DigestInit(3)): its assembly kernels (SHA
// extensions, AVX2) hash several times faster than a portable C++ implementation.
class Sha256 {
 public:
  Sha256() : context_(EVP_MD_CTX_new()) {
    if (!context_ || EVP_DigestInit_ex(context_.get(), EVP_sha256(), nullptr) != 1)
      throw Error("SHA-256: OpenSSL's EVP_DigestInit_ex failed");
  }

  void update(std::span<const std::byte> data) {
    if (!data.empty() && EVP_DigestUpdate(context_.get(), data.data(), data.size()) != 1)
      throw Error("SHA-256: OpenSSL's EVP_DigestUpdate failed");
  }

  std::string hex_digest() {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    if (EVP_DigestFinal_ex(context_.get(), digest, &length) != 1 || length != 32)
      throw Error("SHA-256: OpenSSL's EVP_DigestFinal_ex failed");
    static constexpr char kHex[] = "0123456789abcdef";
    std::string hex(2 * length, '0');
    for (unsigned int i = 0; i < length; ++i) {
      hex[2 * i] = kHex[digest[i] >> 4];
      hex[2 * i + 1] = kHex[digest[i] & 0xf];
    }
    return hex;
  }

 private:
  struct ContextFree {
    void operator()(EVP_MD_CTX* context) const { EVP_MD_CTX_free(context); }
  };
  std::unique_ptr<EVP_MD_CTX, ContextFree> context_;
};

}  // namespace

std::string sha256_hex(std::span<const std::byte> data) {
  Sha256 hash;
  hash.update(data);
  return hash.hex_digest();
}

std::string sha256_hex(const std::string& text) {
  return sha256_hex(std::as_bytes(std::span(text)));
}

namespace {

// The digest of a file, remembered in its extended attribute kCacheAttribute with the size and the
// modification time (ns) it was computed for: a later hash of the unchanged file reads it instead of the
// content (hashing a 469 MB results file costs 0.3 s of CPU time, as much as postproc's spectrum of it).
// The same trust as make's and git's in a file's stat: a content change that keeps both the size and the
// nanosecond mtime goes unseen. Best effort: a file system without user attributes, or a file the user may
// not write, is hashed every time. NVH_HASH_CACHE=0 in the environment turns it off (read and write).
constexpr const char* kCacheAttribute = "user.nvh.sha256";
constexpr const char* kCacheTag = "nvh-sha256 v1";

bool cache_enabled() {
  const char* v = std::getenv("NVH_HASH_CACHE");
  return !(v && std::string_view(v) == "0");
}

long long nanoseconds(const struct timespec& t) {
  return static_cast<long long>(t.tv_sec) * 1000000000LL + t.tv_nsec;
}

std::string cache_record(const struct stat& st, const std::string& hex) {
  return std::string(kCacheTag) + " size=" + std::to_string(st.st_size) +
         " mtime_ns=" + std::to_string(nanoseconds(st.st_mtim)) + " " + hex;
}

bool same_stat(const struct stat& a, const struct stat& b) {
  return a.st_size == b.st_size && nanoseconds(a.st_mtim) == nanoseconds(b.st_mtim);
}

/// Whether the file's mtime lies more than a second before `now`.
bool modified_over_a_second_before(const struct stat& st, const struct timespec& now) {
  return nanoseconds(now) - nanoseconds(st.st_mtim) > 1000000000LL;
}

/// The cached digest if the attribute holds one for this size and mtime, else "".
std::string cached_digest(int fd, const struct stat& st) {
  char value[256];
  const ssize_t n = fgetxattr(fd, kCacheAttribute, value, sizeof value);
  if (n <= 0) return "";
  const std::string record(value, static_cast<std::size_t>(n));
  if (record.size() < 64) return "";
  const std::string hex = record.substr(record.size() - 64);
  if (hex.find_first_not_of("0123456789abcdef") != std::string::npos) return "";
  return record == cache_record(st, hex) ? hex : "";
}

struct FdCloser {
  int fd;
  ~FdCloser() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::string sha256_file(const std::filesystem::path& path) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) {
    throw Error(path.string() + ": cannot hash: is a directory, expected a file");
  }
  const FdCloser file{::open(path.c_str(), O_RDONLY | O_CLOEXEC)};
  if (file.fd < 0) throw Error(path.string() + ": cannot read: " + std::strerror(errno));
  struct stat before {};
  const bool cache = cache_enabled() && ::fstat(file.fd, &before) == 0 && S_ISREG(before.st_mode);
  if (cache) {
    std::string hex = cached_digest(file.fd, before);
    if (!hex.empty()) return hex;
  }
  Sha256 hash;
  std::vector<std::byte> buffer(1 << 20);
  while (true) {
    const ssize_t count = ::read(file.fd, buffer.data(), buffer.size());
    if (count < 0) {
      if (errno == EINTR) continue;
      throw Error(path.string() + ": cannot read: " + std::strerror(errno));
    }
    if (count == 0) break;
    hash.update(std::span(buffer.data(), static_cast<std::size_t>(count)));
  }
  std::string hex = hash.hex_digest();
  struct stat after {};
  // Stored only for a file unchanged while it was read and last modified over a second ago: file systems
  // stamp mtime at the kernel's clock tick (ext4: a few ms), so a rewrite within the tick of the last one
  // would keep the mtime; any later write stamps a time past the stored one (git's "racy" rule).
  struct timespec now {};
  ::clock_gettime(CLOCK_REALTIME, &now);
  const bool settled = modified_over_a_second_before(before, now);
  if (cache && settled && ::fstat(file.fd, &after) == 0 && same_stat(before, after)) {
    const std::string record = cache_record(after, hex);
    (void)fsetxattr(file.fd, kCacheAttribute, record.data(), record.size(), 0);  // best effort
  }
  return hex;
}

}  // namespace nvh
