#include "common/sha256.hpp"

#include <openssl/evp.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
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

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
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

std::string sha256_file(const std::filesystem::path& path) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) {
    throw Error(path.string() + ": cannot hash: is a directory, expected a file");
  }
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file) throw Error(path.string() + ": cannot read: " + std::strerror(errno));

  Sha256 hash;
  std::vector<std::byte> buffer(1 << 20);
  while (true) {
    const size_t count = std::fread(buffer.data(), 1, buffer.size(), file.get());
    hash.update(std::span(buffer.data(), count));
    if (count < buffer.size()) break;
  }
  if (std::ferror(file.get())) throw Error(path.string() + ": cannot read: read error");
  return hash.hex_digest();
}

}  // namespace nvh
