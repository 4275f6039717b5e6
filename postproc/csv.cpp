#include "postproc/csv.hpp"

#include <ostream>

namespace nvh::postproc {

/// CSV with a header row; columns of equal length. Written to a temporary and closed; the command commits
/// the CSV files after the HDF5 output, so that a failure leaves none of them.
void write_csv(std::vector<TextOutput>& csvs, const std::filesystem::path& path,
               const std::vector<std::string>& header, const std::vector<const Eigen::VectorXd*>& columns) {
  TextOutput& csv = csvs.emplace_back(path);
  std::ostream& out = csv.stream();
  out.precision(10);
  for (std::size_t c = 0; c < header.size(); ++c) out << (c ? "," : "") << header[c];
  out << "\n";
  const Eigen::Index rows = columns.empty() ? 0 : columns.front()->size();
  for (Eigen::Index r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < columns.size(); ++c) out << (c ? "," : "") << (*columns[c])[r];
    out << "\n";
  }
  csv.close();
}

}  // namespace nvh::postproc
