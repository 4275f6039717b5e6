#pragma once
// Which mesh nodes an [[interface]] coupling or a [[fix]] of a volume component takes: a node set of the
// mesh (an .inp *NSET or a gmsh physical group), the nodes inside a box, or the nodes on a cylinder band
// (a bearing bore or a liner: radius band and axial range about an axis).
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "condense/abaqus_mesh.hpp"
#include "condense/component.hpp"

namespace nvh::condense {

/// One of three ways to name nodes; exactly one is set.
struct NodeSelector {
  std::string surface;                       ///< node set name, upper case
  std::optional<std::array<double, 6>> box;  ///< xmin ymin zmin xmax ymax zmax, m
  std::optional<CylinderSelector> cylinder;
  SourceLocation where;  ///< of the entry, for messages
  std::string path;      ///< key path of the entry, e.g. "interface[2]"
  std::string what;      ///< for messages, e.g. "the coupling of interface \"main1\""

  /// The key that set it: "surface", "box" or "cylinder".
  std::string key() const;
};

/// Geometric bounds are widened by this (m), so nodes exactly on a bound are taken despite round-off.
inline constexpr double kSelectorTolerance = 1e-6;

/// Indices (ascending) of the candidate mesh nodes (`candidates[n]`) that the selector takes. The
/// caller passes the nodes of elements for node sets and boxes, and the nodes of the outer surface for
/// cylinders (a band of radii inside a solid would also catch interior nodes).
/// nvh::Error located at the entry, key path + "." + key(), for an unknown node set (listing the mesh's
/// sets) and for a selector that catches no node (saying where the nearest node lies).
std::vector<int> select_nodes(const Mesh& mesh, const std::vector<bool>& candidates,
                              const NodeSelector& selector);

/// Distance (m) of point x from the cylinder's axis and its axial coordinate (see CylinderSelector).
std::array<double, 2> cylinder_coordinates(const CylinderSelector& cylinder, const Eigen::Vector3d& x);

}  // namespace nvh::condense
