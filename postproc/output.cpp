#include "postproc/output.hpp"

#include <algorithm>

#include "common/output_path.hpp"

namespace nvh::postproc {

/// The provenance (SHA-256 of every input file) is computed on a second thread while the analysis runs: on a
/// 500 MB result file hashing costs about as much as a spectrum.
std::future<Provenance> start_provenance(const std::vector<SignalSource>& sources, int argc,
                                         const char* const* argv) {
  std::vector<std::filesystem::path> files;
  for (const SignalSource& s : sources) files.push_back(s.info().file);
  return start_provenance(files, argc, argv);
}

std::future<Provenance> start_provenance(const std::vector<std::filesystem::path>& files, int argc,
                                         const char* const* argv) {
  std::vector<std::filesystem::path> inputs;
  for (const std::filesystem::path& f : files)
    if (!f.empty() && std::find(inputs.begin(), inputs.end(), f) == inputs.end()) inputs.push_back(f);
  return std::async(std::launch::async,
                    [inputs, argc, argv] { return make_provenance("postproc", argc, argv, inputs); });
}

Output create_output(const CommonOptions& common, std::future<Provenance>& provenance,
                     const std::string& analysis) {
  const Provenance p = provenance.get();
  Output out{h5::File::create(common.output), {}};
  out.root = out.file.root();
  out.root.set_attribute("format", kPostprocFormat);
  out.root.set_attribute("format_version", kPostprocFormatVersion);
  out.root.set_attribute("units", "SI");
  out.root.set_attribute("analysis", analysis);
  write_provenance(out.root, p);
  return out;
}

/// Time of the last sample of a (windowed) signal, s.
double window_end_s(const SignalInfo& info) {
  return info.start_time_s + static_cast<double>(info.size - 1) / info.sample_rate_hz;
}

/// The signal and the analysis window (`info` describes the samples analysed: the window, if any).
void describe_signal(h5::Group& g, const SignalInfo& info, const AnalysisWindow& window) {
  g.set_attribute("signal", info.address);
  g.set_attribute("signal_unit", info.unit.empty() ? std::string("unknown") : info.unit);
  g.set_attribute("sample_rate_hz", info.sample_rate_hz);
  g.set_attribute("samples", static_cast<std::int64_t>(info.size));
  g.set_attribute("duration_s", static_cast<double>(info.size) / info.sample_rate_hz);
  g.set_attribute("window_start_s", info.start_time_s);
  g.set_attribute("window_end_s", window_end_s(info));
  g.set_attribute("window_skip_cycles", static_cast<std::int64_t>(window.skip_cycles));
}

void write_reference(h5::Group& g, const std::string& dataset, const LevelReference& ref, bool psd) {
  g.set_attribute("units", ref.label(psd), dataset);
  g.set_attribute("reference", ref.value, dataset);
  g.set_attribute("reference_unit", ref.unit, dataset);
  g.set_attribute("reference_source", ref.source, dataset);
  g.set_attribute("quantity", ref.quantity.empty() ? std::string("unknown") : ref.quantity, dataset);
}

/// The HDF5 output, then the CSV files: called once everything is written.
void commit_outputs(Output& out, std::vector<TextOutput>& csvs) {
  out.file.commit();
  for (TextOutput& csv : csvs) csv.commit();
}

/// Before any work: the outputs (HDF5 and the CSV files, `csv_prefix` + signal name, or `csv_names`) may not
/// replace an input signal or angle file, and must be writable.
void check_outputs(const CommonOptions& common, const std::vector<SignalSource>& sources,
                   const AngleSource* angle, const std::string& csv_prefix,
                   std::vector<std::string> csv_names) {
  std::vector<std::filesystem::path> inputs;
  for (const std::string& address : common.signals) inputs.push_back(SignalSource::file_of(address));
  if (angle && !angle->address.empty() && angle->address.front() != '/')
    inputs.push_back(SignalSource::file_of(angle->address));
  std::vector<std::filesystem::path> outputs{common.output};
  if (common.csv_dir) {
    if (csv_names.empty())
      for (const SignalSource& s : sources) csv_names.push_back(csv_prefix + s.info().name + ".csv");
    for (const std::string& name : csv_names) outputs.push_back(*common.csv_dir / name);
  }
  check_outputs_are_not_inputs(outputs, inputs);
  check_output_writable(common.output);
  if (common.csv_dir) check_output_directory(*common.csv_dir);
}

Eigen::VectorXd to_vector(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

}  // namespace nvh::postproc
