#pragma once
// --keep-mesh: the full mesh and the shape of every coordinate on all its nodes, for ParaView. Two files
// beside the superelement OUT.h5: OUT.mesh.h5 (the arrays, HDF5 with provenance) and OUT.xdmf (XDMF 3
// XML that describes them: one grid per element type, one node vector per coordinate). Open the .xdmf
// in ParaView (Xdmf3ReaderS) and warp by any of the vectors. Layout in docs/hdf5-format.md.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "common/provenance.hpp"
#include "condense/abaqus_mesh.hpp"

namespace nvh::condense {

inline constexpr const char* kMeshExportFormat = "superelement-mesh";
inline constexpr const char* kMeshExportFormatVersion = "1.0";

struct MeshExport {
  Eigen::MatrixXd position;          ///< nodes x 3, m (the mesh nodes that elements use)
  std::vector<std::int64_t> labels;  ///< mesh node labels
  /// One block per element type: "C3D4", "C3D10", "C3D8", "C3D20", and its connectivity (elements x
  /// nodes per element, 0-based into `position`, Abaqus node order = XDMF/VTK order for these types).
  std::vector<std::string> block_types;
  std::vector<Eigen::Matrix<std::int64_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> blocks;
  std::vector<std::string> coordinates;  ///< name of each coordinate, e.g. "mode 3"
  Eigen::VectorXd frequency_hz;          ///< of each coordinate when it is a mode (else empty)
  std::vector<Eigen::MatrixXd> shapes;   ///< per coordinate: nodes x 3 translations per unit coordinate
};

/// The export of `mesh` with nodal shapes `shapes` (6 N x n over the model's nodes; the mesh nodes are
/// the model's first nodes).
MeshExport make_mesh_export(const Mesh& mesh, const Eigen::MatrixXd& shapes,
                            const std::vector<std::string>& coordinates, const Eigen::VectorXd& frequency_hz);

/// The two file names beside a superelement file: OUT.h5 -> {OUT.mesh.h5, OUT.xdmf}.
std::filesystem::path mesh_export_h5_path(const std::filesystem::path& superelement);
std::filesystem::path mesh_export_xdmf_path(const std::filesystem::path& superelement);

/// Write both (each through a temporary renamed when complete; the .h5 first, then the .xdmf).
void write_mesh_export(const std::filesystem::path& superelement, const MeshExport& mesh_export,
                       const Provenance& provenance);

}  // namespace nvh::condense
