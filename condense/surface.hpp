#pragma once
// The outer surface of a solid mesh: the element faces that belong to one element only, split into flat
// triangles through their mid-side nodes, with outward unit normals and the area each surface node
// represents. Used for observation points (the nearest surface node, its normal kept: normal velocity)
// and for the exported surface (surface velocity levels and radiated power in postproc).
#include <Eigen/Core>
#include <array>
#include <vector>

#include "condense/abaqus_mesh.hpp"

namespace nvh::condense {

struct Surface {
  std::vector<int> nodes;                     ///< mesh node indices on the surface, ascending
  std::vector<std::array<int, 3>> triangles;  ///< flat sub-triangles, as indices into `nodes`
  Eigen::MatrixXd normals;                    ///< nodes x 3: outward unit normal (area-weighted)
  Eigen::VectorXd areas;                      ///< per node: a third of its adjacent sub-triangles' area, m^2
};

/// Boundary faces of C3D4/C3D10/C3D8/C3D20 elements (Abaqus node order). Quadratic faces are split
/// through their mid-side nodes so every surface node carries area and normal.
Surface extract_surface(const Mesh& mesh);

/// Index into surface.nodes of the surface node nearest to `point`.
int nearest_surface_node(const Surface& surface, const std::vector<Eigen::Vector3d>& nodes,
                         const Eigen::Vector3d& point);

}  // namespace nvh::condense
