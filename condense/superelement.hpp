#pragma once
// The superelement as condense makes it: the file contract (common/superelement.hpp, docs/hdf5-format.md)
// plus condense's record of the run, which goes to the /model group of the file for the user's
// information and is not part of what solve reads.
#include <filesystem>
#include <string>
#include <vector>

#include "common/provenance.hpp"
#include "common/superelement.hpp"
#include "condense/frf_error.hpp"
#include "condense/invariants.hpp"

namespace nvh::condense {

using nvh::kSuperelementFormat;
using nvh::kSuperelementFormatVersion;
using nvh::PointSet;
using nvh::SurfaceExport;

/// Model size and cost of a condense run, for the user's information (/model, docs/hdf5-format.md).
struct ModelRecord {
  int node_count = 0;
  int element_count = 0;
  int dof_count = 0;
  int free_dof_count = 0;
  double max_residual = 0.0;
  /// Wall time (s) of each stage before writing, and the peak resident memory (bytes), for the record.
  std::vector<std::string> stage_names;
  std::vector<double> stage_seconds;
  double peak_memory_bytes = 0.0;
  std::string blas_kernels;  ///< the BLAS kernels under the factorization (common/blas_kernels.hpp)
  /// The sparse factorizations (empty ordering: none, e.g. a small model solved dense): the ordering,
  /// nnz of the matrix's lower triangle and of the largest factor L, its flops, their count.
  std::string factor_ordering;
  double matrix_nonzeros = 0.0;
  double factor_nonzeros = 0.0;
  double factor_flops = 0.0;
  int factorizations = 0;
  double order_seconds = 0.0;   ///< ordering and symbolic analysis of the factorizations
  double factor_seconds = 0.0;  ///< their numeric factorization
  double eigen_seconds = 0.0;   ///< Lanczos iterations (or the dense eigen-solve)
  int eigen_solves = 0;  ///< solves with the factorization in the Lanczos iterations (lobpcg: its iterations)
  std::string eigensolver;  ///< the eigen-solve's backend: "block-lanczos", "spectra", "arpack", "dense" or "lobpcg"
};

/// The error estimate of the reduction in the band (frf_error.hpp) and how the cut-off was chosen, for
/// /reduction_error (docs/hdf5-format.md). Empty without a band.
struct ReductionErrorRecord {
  FrfErrorEstimate estimate;
  double tolerance = 0.0;                         ///< frf_tolerance
  double cutoff_hz = 0.0;                         ///< the cut-off used (0: a count of modes was given)
  std::vector<std::pair<double, double>> passes;  ///< cut-offs tried (Hz) and their errors
};

/// The file's contents and condense's record of the run that made them.
struct Superelement : SuperelementFile, ModelRecord {
  ReductionErrorRecord reduction_error;
};

/// Write the /model group's attributes of `record` into `root`.
void write_model_record(h5::Group& root, const ModelRecord& record);

/// Write /reduction_error into `root` (nothing when the record is empty).
void write_reduction_error(h5::Group& root, const ReductionErrorRecord& record);

/// Write to `path` through common's writer (a temporary file renamed when complete), with /model.
void write_superelement(const std::filesystem::path& path, const Superelement& se,
                        const Provenance& provenance);

}  // namespace nvh::condense
