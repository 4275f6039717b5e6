#pragma once
// The output of an analysis (docs/postproc.md section 5): the HDF5 file created with the format attributes
// and the provenance, the signal description and dB reference attributes, and the commit that renames the
// HDF5 file and then the CSV files (so that a failure leaves none of them).
#include <filesystem>
#include <future>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/hdf5.hpp"
#include "common/output_path.hpp"
#include "common/provenance.hpp"
#include "postproc/levels.hpp"
#include "postproc/options.hpp"
#include "postproc/signal.hpp"

namespace nvh::postproc {

struct Output {
  h5::File file;
  h5::Group root;
};

/// The provenance (SHA-256 of every input file) is computed on a second thread while the analysis runs.
std::future<Provenance> start_provenance(const std::vector<SignalSource>& sources, int argc,
                                         const char* const* argv);
/// The same for inputs given as files (each hashed once).
std::future<Provenance> start_provenance(const std::vector<std::filesystem::path>& files, int argc,
                                         const char* const* argv);

/// Create `common.output` (a temporary until committed) with the root attributes: format, units, `analysis`
/// and the provenance (waits for it).
Output create_output(const CommonOptions& common, std::future<Provenance>& provenance,
                     const std::string& analysis);

/// Time of the last sample of a (windowed) signal, s.
double window_end_s(const SignalInfo& info);

/// The signal and the analysis window (`info` describes the samples analysed: the window, if any).
void describe_signal(h5::Group& g, const SignalInfo& info, const AnalysisWindow& window);

/// The dB reference attributes of a level dataset (docs/postproc.md section 4.1).
void write_reference(h5::Group& g, const std::string& dataset, const LevelReference& ref, bool psd = false);

/// The HDF5 output, then the CSV files: called once everything is written.
void commit_outputs(Output& out, std::vector<TextOutput>& csvs);

/// Before any work: the outputs (HDF5 and the CSV files, `csv_prefix` + signal name, or `csv_names`) may not
/// replace an input signal or angle file, and must be writable.
void check_outputs(const CommonOptions& common, const std::vector<SignalSource>& sources,
                   const AngleSource* angle, const std::string& csv_prefix,
                   std::vector<std::string> csv_names = {});

Eigen::VectorXd to_vector(const std::vector<double>& v);

}  // namespace nvh::postproc
