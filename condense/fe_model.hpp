#pragma once
// The finite-element model of a component, whatever built it (beams: beam_model.hpp; solids:
// volume_model.hpp): nodes with 6 DOF each (ux uy uz rx ry rz, global axes), the assembled matrices on
// all nodal DOF, and the transformation to the independent ("free") DOF.
//
// Nodal DOF ("all") versus free DOF: slave nodes of rigid links, supported DOF and inactive DOF (the
// rotations of solid nodes, which carry no stiffness) are eliminated by a sparse transformation
// u_all = T u_free (master-slave elimination), so the matrices a reduction works on are
// K = T^T K_all T and M = T^T M_all T, always positive (semi-)definite.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <string>
#include <vector>

#include "condense/abaqus_mesh.hpp"
#include "condense/component.hpp"
#include "condense/solid_element.hpp"
#include "condense/surface.hpp"
#include "condense/timoshenko_beam.hpp"

namespace nvh::condense {

using SparseMatrix = Eigen::SparseMatrix<double>;

/// A linear multi-point constraint: the nodal DOF `dof` equals sum c_j u(dof_j) over independent DOF.
struct LinearConstraint {
  int dof = 0;
  std::vector<std::pair<int, double>> terms;  ///< (nodal DOF, coefficient)
};

/// A linear constraint sum c_j u(dof_j) = 0 over nodal DOF, kept as a row of C (multiplier form).
struct ConstraintRow {
  std::vector<std::pair<int, double>> terms;  ///< (nodal DOF, coefficient)
};

/// A beam element as the geometric stiffness needs it: its nodes, local axes (rows) and section data.
struct BeamElementRecord {
  int node1 = 0, node2 = 0;
  Eigen::Matrix3d axes;
  BeamElementData data;
};

struct FeModel {
  std::vector<Eigen::Vector3d> nodes;  ///< node positions, m
  int element_count = 0;
  std::string element_kind;  ///< for messages: "beam elements", "C3D10 elements", ...

  SparseMatrix stiffness_all;  ///< 6N x 6N, N/m and N m/rad

  // The mass, in one of two forms. Beam models (rotary inertia, rigid-link offsets): the nodal matrix
  // mass_all and its section-resolved parts. Volume models (translations only): the scalar mass alone,
  // since their nodal mass is scalar_mass (x) I_3 on the translations and zero on the rotations.
  SparseMatrix mass_all;  ///< beams: 6N x 6N, kg and kg m^2; volumes: empty
  /// Beams: section-resolved mass integrals int rho N_A^T N_B dV (A, B = global x, y, z), 6N x 6N
  /// each; sum of the diagonal ones = mass_all. For the floating-frame quadratic invariants.
  std::array<std::array<SparseMatrix, 3>, 3> component_mass_all;
  /// Beams: position moments, column 3k+A holds p with p^T u = int rho x_k u_A dV (6N x 9).
  Eigen::MatrixXd position_moment_all;
  /// Volumes: the consistent scalar mass m_ij = int rho N_i N_j dV (N x N, both triangles stored, kg;
  /// zero rows for coupling nodes); M_all(6i+a, 6j+a) = m_ij for a = x, y, z. Beams: empty.
  SparseMatrix scalar_mass;

  /// Beams: every element, for the geometric stiffness (geometric_stiffness.hpp); volumes: empty.
  std::vector<BeamElementRecord> beam_elements;
  /// Volumes, only when the reduction asks for geometric stiffening: every solid element (its nodes are
  /// model nodes) and its material, for the stress stiffness (geometric_stiffness.hpp); otherwise empty.
  std::vector<MeshElement> solid_elements;
  std::vector<IsotropicMaterial> solid_materials;

  SparseMatrix transform;           ///< T: 6N x n_free
  std::vector<bool> supported_dof;  ///< per nodal DOF: held by a support
  std::vector<bool> inactive_dof;   ///< per nodal DOF: not part of the model (rotations of solid nodes)
  std::vector<int> master_of;       ///< per node: itself, or its master node for a rigid-link slave
  std::vector<int> coupling_nodes;  ///< volume models: the coupling node of each interface, in order
  /// Dependent DOF given by linear constraints (distributing couplings); each refers to DOF of master
  /// nodes that are neither dependent nor slaves.
  std::vector<LinearConstraint> constraints;
  /// Distributing couplings in multiplier form: rows of C u = 0 over nodal DOF (the point's DOF and its
  /// surface's translations, which all stay free), and C on the free DOF (m x n_free, from
  /// build_transform; held DOF drop out). Empty in elimination form.
  std::vector<ConstraintRow> constraint_rows;
  SparseMatrix constraint_matrix;
  Surface surface;                   ///< volume models: the outer surface (node indices are model nodes)
  std::vector<std::int64_t> labels;  ///< volume models: the mesh's node labels (first nodes)

  int all_dofs() const { return 6 * static_cast<int>(nodes.size()); }
  int free_dofs() const { return static_cast<int>(transform.cols()); }
  /// True if the mass is held as scalar_mass (volume models).
  bool scalar_mass_only() const { return scalar_mass.rows() > 0; }
  /// Which triangles of the free-DOF matrices to store: both, or the lower one with the diagonal (half
  /// the memory, for code that reads one triangle, as CHOLMOD and Spectra's SparseSymMatProd<Lower> do).
  enum class Triangles { kBoth, kLower };
  /// The free-DOF stiffness and mass T^T K T, T^T M T, exactly symmetric.
  SparseMatrix stiffness(Triangles stored = Triangles::kBoth) const;
  SparseMatrix mass(Triangles stored = Triangles::kBoth) const;

  /// Index of the node at `at` within `tolerance` (m), or -1.
  int find_node(const Vec3& at, double tolerance) const;
  /// Index of the node nearest to `at` (-1 for an empty model).
  int nearest_node(const Vec3& at) const;

  /// Rigid-body motions of all nodes about the component origin (6N x 6): columns are unit
  /// translations x, y, z and unit rotations about x, y, z.
  Eigen::MatrixXd rigid_body_field() const;
  /// The combinations (6 x r) of rigid_body_field()'s columns that no support holds: the null space of
  /// the field on the supported DOF (rank threshold 1e-9); r is the number of rigid-body modes.
  Eigen::MatrixXd unsupported_rigid_motions() const;
  /// Per nodal DOF, its index among the free DOF (the identity entries of T on master nodes), else -1.
  std::vector<int> free_index() const;
};

/// Give back the storage of a sparse matrix now. Eigen 3.4's SparseMatrix has no move assignment:
/// `a = SparseMatrix()` keeps the old allocation (it only sets the size to zero); a swap frees it.
inline void release(SparseMatrix& a) {
  SparseMatrix().swap(a);
}

/// Mark supported DOF: a support `at` a point holds that node (error located at the entry if no node
/// is there, or if it is a rigid-link end); a `box` holds every node inside (error if none is). Sets
/// `supported_dof`; `inactive_dof` must be sized already.
void apply_supports(FeModel& model, const std::vector<Support>& supports, double tolerance);

/// Build `model.transform` from master_of, supported_dof and inactive_dof: the free DOF are the
/// active, unsupported DOF of master nodes; a slave follows its master, u_s = u_m + theta_m x r. Also
/// `model.constraint_matrix` from `constraint_rows`.
void build_transform(FeModel& model);

}  // namespace nvh::condense
