#include "condense/node_selector.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace nvh::condense {

namespace {

std::string format(double value) {
  std::ostringstream s;
  s.precision(6);
  s << value;
  return s.str();
}

std::string format(const Vec3& v) {
  return "[" + format(v[0]) + ", " + format(v[1]) + ", " + format(v[2]) + "]";
}

/// Distance from x to the box (0 inside).
double box_distance(const std::array<double, 6>& b, const Eigen::Vector3d& x) {
  double squared = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double d = std::max({b[k] - x(k), 0.0, x(k) - b[3 + k]});
    squared += d * d;
  }
  return std::sqrt(squared);
}

}  // namespace

std::string NodeSelector::key() const {
  return box ? "box" : cylinder ? "cylinder" : "surface";
}

std::array<double, 2> cylinder_coordinates(const CylinderSelector& c, const Eigen::Vector3d& x) {
  const Eigen::Vector3d axis = Eigen::Vector3d(c.axis[0], c.axis[1], c.axis[2]).normalized();
  const Eigen::Vector3d d = x - Eigen::Vector3d(c.point[0], c.point[1], c.point[2]);
  const double s = d.dot(axis);
  return {(d - s * axis).norm(), s};
}

std::vector<int> select_nodes(const Mesh& mesh, const std::vector<bool>& used, const NodeSelector& sel) {
  const std::string key = sel.path + "." + sel.key();
  std::vector<int> nodes;
  const int count = static_cast<int>(mesh.nodes.size());
  if (!sel.box && !sel.cylinder) {
    const auto it = mesh.node_sets.find(sel.surface);
    if (it == mesh.node_sets.end()) {
      std::string sets;
      for (const auto& [name, members] : mesh.node_sets) sets += (sets.empty() ? "" : ", ") + name;
      throw Error(
          "the node set \"" + sel.surface + "\" is not in the mesh " + mesh.file +
              (sets.empty() ? " (it has no *NSET or physical group)" : " (its node sets: " + sets + ")"),
          sel.where, key);
    }
    for (int n : it->second)
      if (used[n]) nodes.push_back(n);
    if (nodes.empty()) {
      throw Error("the node set \"" + sel.surface + "\" holds no node of an element", sel.where, key);
    }
    return nodes;
  }

  const double tol = kSelectorTolerance;
  double nearest = std::numeric_limits<double>::infinity();  // for the message if nothing is caught
  if (sel.box) {
    const auto& b = *sel.box;
    for (int n = 0; n < count; ++n) {
      if (!used[n]) continue;
      const double d = box_distance(b, mesh.nodes[n]);
      if (d <= tol) nodes.push_back(n);
      nearest = std::min(nearest, d);
    }
    if (nodes.empty()) {
      throw Error(sel.what + ": the box holds no node of the mesh (the nearest node is " + format(nearest) +
                      " m outside it)",
                  sel.where, key);
    }
    return nodes;
  }

  // Cylinder band: r_min <= r <= r_max and s_min <= s <= s_max, each widened by the tolerance.
  const CylinderSelector& c = *sel.cylinder;
  double nearest_r = std::numeric_limits<double>::quiet_NaN();
  for (int n = 0; n < count; ++n) {
    if (!used[n]) continue;
    const auto [r, s] = cylinder_coordinates(c, mesh.nodes[n]);
    if (s < c.s_min - tol || s > c.s_max + tol) continue;
    const double d = std::max({c.r_min - r, 0.0, r - c.r_max});
    if (d <= tol) nodes.push_back(n);
    if (d < nearest) {
      nearest = d;
      nearest_r = r;
    }
  }
  if (nodes.empty()) {
    std::string band = "radius " + format(c.r_min) + " .. " + format(c.r_max) + " m";
    if (c.s_min > -1e299 || c.s_max < 1e299)
      band += ", axial " + format(c.s_min) + " .. " + format(c.s_max) + " m";
    throw Error(sel.what + ": the cylinder (axis through " + format(c.point) + " along " + format(c.axis) +
                    ", " + band + ") catches no node of the mesh" +
                    (std::isnan(nearest_r) ? std::string(" (no node lies in its axial range)")
                                           : " (in its axial range the nearest node lies at radius " +
                                                 format(nearest_r) + " m)"),
                sel.where, key);
  }
  return nodes;
}

}  // namespace nvh::condense
