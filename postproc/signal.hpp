#pragma once
// Signals: uniformly sampled time histories read from HDF5, CSV or UFF58 files, in blocks.
//
// A signal is addressed on the command line as (docs/postproc.md section 2):
//   FILE.h5:/path/to/dataset          1-D dataset
//   FILE.h5:/markers/top1/acceleration[2]   column 2 (0-based; [x], [y], [z] also accepted) of an (n, m)
//                                      dataset, e.g. solve's marker signals in global axes
//   FILE.csv:column                    a column of a CSV file with a header row (name or 0-based index)
//   FILE.uff[:N]                       the N-th (1-based, default 1) dataset 58 of a Universal File
//   NAME=ADDRESS                       any of the above, named NAME in the outputs
// The sample rate comes from a `sample_rate_hz` attribute (on the dataset or on any group above it), else
// from a `time` dataset (or CSV column "time"/"time_s"/"t") which must be uniformly spaced.
//
// Signals are read in blocks (SignalSource::read), so a 31 M-sample HDF5 dataset is never held whole.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace nvh::postproc {

/// What is known of a signal without reading its samples.
struct SignalInfo {
  std::string name;            ///< output group name (sanitized: letters, digits, '_', '-')
  std::string address;         ///< as given, for messages and provenance
  std::filesystem::path file;  ///< the file it comes from (empty for in-memory signals)
  std::string unit;            ///< physical unit of the samples ("m/s^2", "m/s", "Pa", ...; "" unknown)
  double sample_rate_hz = 0.0;
  double start_time_s = 0.0;
  std::int64_t size = 0;  ///< number of samples
};

/// The physical quantity a unit stands for: "acceleration", "velocity", "displacement", "pressure",
/// "force", "power", or "" if the unit is not one of m/s^2, m/s, m, Pa, N, W.
std::string quantity_of_unit(const std::string& unit);

/// A readable signal. Cheap to move; reading never loads more than asked.
class SignalSource {
 public:
  /// Open an addressed signal (see the header comment). Errors name the address and say what was expected:
  /// missing file or dataset, wrong rank, column out of range, no sample rate, non-uniform time.
  static SignalSource open(const std::string& address);
  /// The file an address reads (without opening it): what an output must not overwrite.
  static std::filesystem::path file_of(const std::string& address);
  /// A signal held in memory (tests, the orders of a synthetic run-up).
  static SignalSource from_samples(std::string name, std::vector<double> samples, double sample_rate_hz,
                                   std::string unit = "");

  SignalSource(SignalSource&&) noexcept;
  SignalSource& operator=(SignalSource&&) noexcept;
  ~SignalSource();

  const SignalInfo& info() const { return info_; }
  std::int64_t size() const { return info_.size; }

  /// Restrict the signal to `count` samples from sample `first` of the file (an analysis window,
  /// docs/postproc.md section 2.1): afterwards size(), info().size and info().start_time_s describe the
  /// window and read() counts from its first sample. Calls are absolute, not cumulative.
  void restrict_to(std::int64_t first, std::int64_t count);
  /// Index in the file of sample 0 (0 unless restricted).
  std::int64_t first_sample() const { return first_; }
  /// Number of samples in the file, whatever the restriction.
  std::int64_t file_size() const { return file_size_ < 0 ? info_.size : file_size_; }
  /// Time of the file's first sample, s.
  double file_start_time_s() const { return file_size_ < 0 ? info_.start_time_s : file_start_s_; }

  /// Samples [offset, offset + out.size()). A NaN or infinite sample is an error naming the input and
  /// the sample index.
  void read(std::int64_t offset, std::span<double> out) const;
  /// All samples (for small signals; the analyses stream with read()).
  std::vector<double> read_all() const;

  struct Impl;  // the file handle or the samples (signal.cpp)

 private:
  SignalSource() = default;
  SignalInfo info_;
  std::unique_ptr<Impl> impl_;
  std::int64_t first_ = 0;       // restriction: first file sample
  std::int64_t file_size_ = -1;  // samples in the file once restricted (-1: not restricted)
  double file_start_s_ = 0.0;    // time of the file's first sample once restricted
};

/// A name usable as an HDF5 group: characters other than letters, digits, '_' and '-' become '_'.
std::string sanitize_name(const std::string& text);

/// Split "NAME=ADDRESS" into its name ("" if none) and address.
std::pair<std::string, std::string> split_named_address(const std::string& text);

}  // namespace nvh::postproc
