#pragma once
// The superelement file: the contract between `condense` (which writes it) and `solve` (which reads it),
// and the file a user opens with h5dump or h5py. The layout - every group, dataset and attribute with its
// shape, unit and meaning - is documented in docs/hdf5-format.md; the paths written and read here are fixed
// by that page. This is the one reader and writer of the layout: no tool reads the file through another
// tool's code.
//
// The /model group (model sizes, stage times, memory, factorization figures) is condense's record of its
// run, not part of the contract: the writer leaves it to a callback of the producing tool and the reader
// ignores it.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/hdf5.hpp"
#include "common/inertia_invariants.hpp"
#include "common/provenance.hpp"

namespace nvh {

inline constexpr const char* kSuperelementFormat = "superelement";
inline constexpr const char* kSuperelementFormatVersion = "1.1";  // 1.1: /reduced/geometric_stiffness

/// The products omega_a omega_b of the spin's components that the geometric stiffness matrices multiply,
/// in the file's order and with its names (/reduced/geometric_stiffness/xx, ...).
inline constexpr std::array<std::array<int, 2>, 6> kSpinProducts = {
    {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {2, 0}}};
inline constexpr std::array<const char*, 6> kSpinProductNames = {"xx", "yy", "zz", "xy", "yz", "zx"};

/// omega_a omega_b of each product, for omega (rad/s): the coefficients of the geometric stiffness matrices.
inline std::array<double, 6> spin_products(const Eigen::Vector3d& omega) {
  std::array<double, 6> c{};
  for (std::size_t p = 0; p < kSpinProducts.size(); ++p)
    c[p] = omega(kSpinProducts[p][0]) * omega(kSpinProducts[p][1]);
  return c;
}

/// Points of the component (interfaces or observation points) and their motion per coordinate
/// (/interface and /observe).
struct PointSet {
  std::vector<std::string> names;
  Eigen::MatrixXd position;  ///< count x 3, m
  /// shapes[p] is 6 x n: (ux uy uz rx ry rz) of point p per unit of each coordinate.
  std::vector<Eigen::MatrixXd> shapes;
  /// Volume observation points: the outward unit normal at the surface node (count x 3); else empty.
  Eigen::MatrixXd normals;
};

/// The outer surface of a volume component with the translations of its nodes per coordinate (/surface).
struct SurfaceExport {
  std::vector<std::int64_t> labels;           ///< mesh node labels
  Eigen::MatrixXd position;                   ///< nodes x 3, m
  Eigen::MatrixXd normal;                     ///< nodes x 3, outward unit normals
  Eigen::VectorXd area;                       ///< nodes, m^2
  std::vector<std::array<int, 3>> triangles;  ///< flat sub-triangles, 0-based indices into the nodes
  std::vector<double> shape;                  ///< (nodes, 3, n) row-major: ux uy uz per unit coordinate
};

/// Everything the superelement file carries apart from provenance and the producer's own record.
struct SuperelementFile {
  std::string name;    ///< root attribute component
  std::string kind;    ///< "beam" | "volume"
  std::string method;  ///< "modal" | "craig-bampton" | "guyan"
  bool orthonormalized = false;
  double damping_ratio = 0.0;  ///< zeta, attribute of /reduced/damping
  int rigid_body_modes_removed = 0;
  int rigid_body_modes_contained = 0;

  Eigen::VectorXd frequency_hz;          ///< /modes/frequency_hz, Hz
  Eigen::VectorXd fixed_interface_hz;    ///< /modes/fixed_interface_hz (Craig-Bampton), Hz; else empty
  std::vector<std::string> coordinates;  ///< /reduced/coordinates: what each q_j is
  /// /reduced attribute static_correction: how many static-correction vectors condense put in the basis
  /// (residual modes of a modal reduction, residual vectors of load points of a Craig-Bampton one); 0: none.
  /// Dropping coordinates (solve's `modes`) drops their static correction.
  int static_correction = 0;
  Eigen::MatrixXd mass, stiffness, damping;  ///< /reduced/*, n x n, generalized units

  /// /reduced/geometric_stiffness/<xx..zx>: empty, or the six n x n matrices K_ab of the centrifugal
  /// prestress, so that K(omega) = stiffness + sum_p (omega_a omega_b - w_ref,a w_ref,b) K_p for a body
  /// spinning at omega (rad/s, component axes); generalized stiffness per (rad/s)^2.
  std::vector<Eigen::MatrixXd> geometric_stiffness;
  /// The spin (rad/s, component axes) at which `stiffness` was reduced (attribute reference_spin); zero:
  /// at rest.
  Eigen::Vector3d reference_spin = Eigen::Vector3d::Zero();

  PointSet interfaces;                   ///< /interface/*
  PointSet observers;                    ///< /observe/*
  std::optional<SurfaceExport> surface;  ///< /surface/* when exported

  RigidBodyInertia inertia;    ///< /invariants/mass, center_of_mass, inertia, ...
  ModalInvariants invariants;  ///< /invariants/translational_coupling, ...

  /// n, the number of coordinates.
  int size() const { return static_cast<int>(mass.rows()); }
};

/// Writes the producing tool's own groups or attributes into the root group, after the contract's
/// groups and before the file is committed (condense: /model).
using SuperelementExtra = std::function<void(h5::Group& root)>;

/// Write `se` to `path` through a temporary file renamed when complete: the root attributes, the
/// provenance, /modes, /reduced, /interface, /observe, /surface (when present), /invariants, then `extra`.
void write_superelement(const std::filesystem::path& path, const SuperelementFile& se,
                        const Provenance& provenance, const SuperelementExtra& extra = {});

/// Read a superelement file, checking format, major version 1 and every shape; an error names the file
/// and the path of the dataset or attribute at fault. Members it does not know (/model) are ignored.
SuperelementFile read_superelement(const std::filesystem::path& path);

}  // namespace nvh
