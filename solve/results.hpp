#pragma once
// The results file of solve (layout in docs/results-format.md): sampled signals written in chunks while the
// run goes on, so a killed run leaves a readable file up to its last chunk (root attribute status = "running"
// until the end), and a checkpoint after every chunk from which `solve --restart` continues.
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/hdf5.hpp"
#include "common/provenance.hpp"
#include "solve/scene.hpp"

namespace nvh::solve {

inline constexpr const char* kResultsFormat = "nvh-results";
inline constexpr const char* kResultsFormatVersion = "1.1";  // 1.1: sliders and rotors (results-format.md)

/// The signal datasets the scene writes, in file order: their paths (no leading '/') and columns (0: a
/// vector).
void result_datasets(const Scene& scene, std::vector<std::string>& paths, std::vector<int>& columns);

struct Checkpoint {
  double time = 0;
  long samples = 0;  // samples written before it
  Eigen::VectorXd y, yp;
};

class ResultsWriter {
 public:
  /// A new file at `path` with the layout for `scene` and a first checkpoint `start` (the consistent state at
  /// the start time, no samples), written complete and renamed into place, then reopened for appending: a run
  /// killed at any moment after leaves a file that --restart continues.
  static ResultsWriter create(const std::filesystem::path& path, const Scene& scene,
                              const Provenance& provenance, const Checkpoint& start);
  /// Reopen a file of an interrupted run; rows after its last checkpoint are dropped. Error if the file was
  /// written for another scene layout or has no checkpoint.
  static ResultsWriter reopen(const std::filesystem::path& path, const Scene& scene, Checkpoint& checkpoint);

  /// Buffer one output sample at time t.
  void add_sample(double t, const Scene& scene, const Eigen::VectorXd& y, const Eigen::VectorXd& yp);
  long samples() const { return samples_; }
  /// Samples buffered in memory, not yet on disk.
  long buffered() const { return samples_ - written_; }
  /// Write the buffered samples and a checkpoint (t, y, y') to disk.
  void flush(const Checkpoint& checkpoint);
  /// Write the buffered samples without a checkpoint (memory bound inside a long integrator step, and the
  /// failure path when the state is not finite); a restart drops them, back to the last checkpoint.
  void flush_samples();
  /// Final status ("complete", "interrupted", "failed"), a message, and the integrator statistics.
  void finish(const std::string& status, const std::string& message, const IntegratorStatistics& stats,
              double wall_seconds);
  /// The largest constraint drift seen at the checkpoints, as /solver/statistics attributes.
  void set_drift(double position, double velocity);

  // For the periodic steady state (steady_state.hpp):
  /// The index of the signal dataset at `path` (no leading '/'), or -1.
  int dataset_index(const std::string& path) const;
  /// Values per sample of dataset `index` (1 for a vector).
  std::size_t dataset_width(int index) const {
    return static_cast<std::size_t>(channels_.at(static_cast<std::size_t>(index)).width);
  }
  /// The last added sample's values of dataset `index` (one value, or its columns).
  std::span<const double> last_sample(int index) const;
  /// Append the rows [first, end) of every signal dataset of `source` (a results file of the same layout,
  /// with its /energy reference) as samples; no checkpoint.
  void append_rows(const h5::Group& source, hsize_t first, hsize_t end);
  h5::Group root() { return file_->root(); }

 private:
  ResultsWriter() = default;
  void open_datasets(const Scene& scene);
  struct Channel {
    h5::AppendableDataset dataset;
    std::vector<double> buffer;
    std::string path;
    int width = 1;  // values per sample
  };

  std::unique_ptr<h5::File> file_;
  std::vector<Channel> channels_;  // in the order of the scene's signals
  std::optional<double> energy_reference_;  // kinetic + potential + dissipated - input at the first sample, J
  std::vector<MarkerMotion> motions_;
  std::vector<Wrench> wrenches_;
  std::vector<double> state_rows_, values_;
  std::vector<std::size_t>
      channel_counts_;  // per force element: its channels (channels() builds their names)
  long samples_ = 0;
  long written_ = 0;  // samples on disk
};

}  // namespace nvh::solve
