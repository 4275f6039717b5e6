#pragma once
// The superelement: what `condense` hands to `solve` and to the user, and its HDF5 file.
// The layout (every dataset's shape, unit and meaning) is documented in docs/hdf5-format.md; the
// paths below are fixed by that contract.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/provenance.hpp"
#include "condense/invariants.hpp"

namespace nvh::condense {

inline constexpr const char* kSuperelementFormat = "superelement";
inline constexpr const char* kSuperelementFormatVersion = "1.0";

/// Points of the component (interfaces or observation points) and their motion per coordinate.
struct PointSet {
  std::vector<std::string> names;
  Eigen::MatrixXd position;  ///< count x 3, m
  /// shapes[p] is 6 x n: (ux uy uz rx ry rz) of point p per unit of each coordinate.
  std::vector<Eigen::MatrixXd> shapes;
  /// Volume observation points: the outward unit normal at the surface node (count x 3); else empty.
  Eigen::MatrixXd normals;
};

/// The outer surface of a volume component with the translations of its nodes per coordinate.
struct SurfaceExport {
  std::vector<std::int64_t> labels;           ///< mesh node labels
  Eigen::MatrixXd position;                   ///< nodes x 3, m
  Eigen::MatrixXd normal;                     ///< nodes x 3, outward unit normals
  Eigen::VectorXd area;                       ///< nodes, m^2
  std::vector<std::array<int, 3>> triangles;  ///< flat sub-triangles, 0-based indices into the nodes
  std::vector<double> shape;                  ///< (nodes, 3, n) row-major: ux uy uz per unit coordinate
};

struct Superelement {
  std::string name;
  std::string kind;    ///< "beam"
  std::string method;  ///< "modal" | "craig-bampton" | "guyan"
  bool orthonormalized = false;
  double damping_ratio = 0.0;
  int rigid_body_modes_removed = 0;
  int rigid_body_modes_contained = 0;

  Eigen::VectorXd frequency_hz;  ///< /modes/frequency_hz
  Eigen::VectorXd fixed_interface_hz;
  std::vector<std::string> coordinates;
  Eigen::MatrixXd mass, stiffness, damping;  ///< /reduced/*

  PointSet interfaces;                   ///< /interface/*
  PointSet observers;                    ///< /observe/*
  std::optional<SurfaceExport> surface;  ///< /surface/* when exported

  RigidBodyInertia inertia;    ///< /invariants/mass, center_of_mass, inertia, ...
  ModalInvariants invariants;  ///< /invariants/translational_coupling, ...

  // Model size and cost, for the user's information (/model).
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
  int eigen_solves = 0;         ///< solves with the factorization in the Lanczos iterations

  int size() const { return static_cast<int>(mass.rows()); }
};

/// Write to `path` through a temporary file renamed when complete.
void write_superelement(const std::filesystem::path& path, const Superelement& se,
                        const Provenance& provenance);

/// Read a superelement file, checking format, version and every shape.
Superelement read_superelement(const std::filesystem::path& path);

}  // namespace nvh::condense
