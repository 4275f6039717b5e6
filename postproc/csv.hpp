#pragma once
// CSV tables of the analyses (docs/postproc.md section 6).
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/output_path.hpp"

namespace nvh::postproc {

/// CSV with a header row; columns of equal length. Written to a temporary and closed; the command commits
/// the CSV files after the HDF5 output, so that a failure leaves none of them.
void write_csv(std::vector<TextOutput>& csvs, const std::filesystem::path& path,
               const std::vector<std::string>& header, const std::vector<const Eigen::VectorXd*>& columns);

}  // namespace nvh::postproc
