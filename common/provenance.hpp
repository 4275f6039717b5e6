#pragma once
// Provenance written into every HDF5 output: which tool and version made it, with which command line,
// from which inputs (SHA-256 of each), when and where. The gather step of sweeps compares these hashes
// to tell stale results from fresh ones.
#include <filesystem>
#include <string>
#include <vector>

#include "common/hdf5.hpp"

namespace nvh {

struct Provenance {
  std::string tool;                           ///< "condense", "solve", "postproc"
  std::string tool_version;                   ///< nvh::kVersion
  std::string command_line;                   ///< argv joined, each argument shell-quoted when needed
  std::vector<std::filesystem::path> inputs;  ///< input files as given
  std::vector<std::string> input_sha256;      ///< lower-case hex, one per input
  std::string created_utc;                    ///< ISO 8601, e.g. "2026-11-21T06:10:00Z"
  std::string host;
};

/// Fill a Provenance: hashes each input (error naming a missing file), stamps time and host.
Provenance make_provenance(std::string tool, int argc, const char* const* argv,
                           const std::vector<std::filesystem::path>& inputs);

/// Root attributes: tool, tool_version, command_line, created_utc, host, input_files, input_sha256.
void write_provenance(h5::Group& root, const Provenance& provenance);

/// Join argv into one shell-readable line (arguments with spaces or quotes are single-quoted).
std::string join_command_line(int argc, const char* const* argv);

}  // namespace nvh
