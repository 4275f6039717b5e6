#pragma once
// SHA-256 (FIPS 180-4), for input hashes in provenance; computed by OpenSSL's libcrypto (EVP).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace nvh {

/// Lower-case hex digest of a byte buffer.
std::string sha256_hex(std::span<const std::byte> data);
std::string sha256_hex(const std::string& text);
/// Lower-case hex digest of a file's contents; nvh::Error naming the file if it cannot be read. Remembered in
/// the file's extended attribute user.nvh.sha256 with its size and mtime, and read from there while both are
/// unchanged (best effort; NVH_HASH_CACHE=0 turns it off; sha256.cpp).
std::string sha256_file(const std::filesystem::path& path);

}  // namespace nvh
