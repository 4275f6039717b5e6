#pragma once
// A flexible body's inputs of the surface analyses (erp, animate): its columns in solve's results
// (/bodies/<body>/modal_coordinates, modal_velocities, and the floating frame's position, velocity,
// angular_velocity, euler_parameters; docs/results-format.md) and the exported surface of its superelement
// (/surface of docs/hdf5-format.md, read through common's superelement reader), each checked against the
// other with errors naming the file, the dataset and what was expected.
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "common/superelement.hpp"
#include "postproc/signal.hpp"

namespace nvh::postproc {

/// /bodies/<body>/<dataset> of solve's results, an (n, m) dataset of a flexible body: one signal per column.
/// A missing dataset is an error listing the bodies of the file that have it.
std::vector<SignalSource> open_body_columns(const std::filesystem::path& results, const std::string& body,
                                            const std::string& dataset);

/// The frame's datasets of /bodies/<body>/ as signals, `columns` each in order (e.g. {"velocity", 3}), each
/// checked to be sampled like `reference` (same sample count and rate).
std::vector<SignalSource> open_frame_columns(const std::filesystem::path& results, const std::string& body,
                                             const std::vector<std::pair<std::string, int>>& datasets,
                                             const SignalSource& reference);

/// The superelement of body `body`, with its exported surface, checked against the `modes` elastic
/// coordinates of the results: an error if the file has no /surface, is a raw (not orthonormalized) basis
/// holding rigid-body modes, or has fewer coordinates than the results.
SuperelementFile read_body_surface(const std::filesystem::path& superelement,
                                   const std::filesystem::path& results, const std::string& body,
                                   Eigen::Index modes);

}  // namespace nvh::postproc
