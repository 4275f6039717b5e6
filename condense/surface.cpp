#include "condense/surface.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <limits>
#include <map>

namespace nvh::condense {
namespace {

/// A face of an element: its corner nodes (in order around the face) and, for quadratic elements, the
/// mid-side nodes between consecutive corners (mid[i] between corner i and i + 1).
struct Face {
  std::vector<int> corners;
  std::vector<int> mids;
};

/// Faces of one element in Abaqus/CalculiX node order (positions within the element's node list).
std::vector<Face> element_faces(const std::string& type) {
  if (type == "C3D4" || type == "C3D10") {
    // Corners 0-3; C3D10 mid-side nodes: 4 (0-1), 5 (1-2), 6 (2-0), 7 (0-3), 8 (1-3), 9 (2-3).
    const bool quadratic = type == "C3D10";
    std::vector<Face> f = {
        {{0, 1, 2}, {4, 5, 6}}, {{0, 1, 3}, {4, 8, 7}}, {{1, 2, 3}, {5, 9, 8}}, {{0, 2, 3}, {6, 9, 7}}};
    if (!quadratic)
      for (Face& face : f) face.mids.clear();
    return f;
  }
  // Hexahedra: corners 0-7; C3D20 mid-side nodes 8-11 (0-1 1-2 2-3 3-0), 12-15 (4-5 5-6 6-7 7-4),
  // 16-19 (0-4 1-5 2-6 3-7).
  const bool quadratic = type == "C3D20";
  std::vector<Face> f = {{{0, 1, 2, 3}, {8, 9, 10, 11}},   {{4, 5, 6, 7}, {12, 13, 14, 15}},
                         {{0, 1, 5, 4}, {8, 17, 12, 16}},  {{1, 2, 6, 5}, {9, 18, 13, 17}},
                         {{2, 3, 7, 6}, {10, 19, 14, 18}}, {{3, 0, 4, 7}, {11, 16, 15, 19}}};
  if (!quadratic)
    for (Face& face : f) face.mids.clear();
  return f;
}

/// Flat sub-triangles of a face, in mesh node indices (not yet oriented).
std::vector<std::array<int, 3>> split(const std::vector<int>& c, const std::vector<int>& m) {
  std::vector<std::array<int, 3>> t;
  if (c.size() == 3 && m.empty()) return {{c[0], c[1], c[2]}};
  if (c.size() == 3) return {{c[0], m[0], m[2]}, {m[0], c[1], m[1]}, {m[2], m[1], c[2]}, {m[0], m[1], m[2]}};
  if (m.empty()) return {{c[0], c[1], c[2]}, {c[0], c[2], c[3]}};
  // 8-node quadrilateral: a corner triangle at each corner and the inner quadrilateral of mid-side nodes.
  return {{c[0], m[0], m[3]}, {m[0], c[1], m[1]}, {m[1], c[2], m[2]},
          {m[2], c[3], m[3]}, {m[0], m[1], m[2]}, {m[0], m[2], m[3]}};
}

}  // namespace

Surface extract_surface(const Mesh& mesh) {
  // A boundary face is one that a single element owns: count faces by their sorted corner nodes.
  struct Owner {
    int element = -1;
    int face = -1;
    int count = 0;
  };
  std::map<std::vector<int>, Owner> faces;
  std::vector<std::vector<Face>> element_face_lists(mesh.elements.size());
  for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
    const MeshElement& element = mesh.elements[e];
    element_face_lists[e] = element_faces(element.type);
    for (std::size_t f = 0; f < element_face_lists[e].size(); ++f) {
      std::vector<int> key;
      for (int local : element_face_lists[e][f].corners) key.push_back(element.nodes[local]);
      std::sort(key.begin(), key.end());
      Owner& owner = faces[key];
      owner.element = static_cast<int>(e);
      owner.face = static_cast<int>(f);
      ++owner.count;
    }
  }

  Surface s;
  std::vector<std::array<int, 3>> triangles;  // mesh node indices, oriented outward
  for (const auto& [key, owner] : faces) {
    if (owner.count != 1) continue;
    const MeshElement& element = mesh.elements[owner.element];
    const Face& face = element_face_lists[owner.element][owner.face];
    std::vector<int> c, m;
    for (int local : face.corners) c.push_back(element.nodes[local]);
    for (int local : face.mids) m.push_back(element.nodes[local]);
    // Outward: away from the element's centroid.
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int n : element.nodes) centroid += mesh.nodes[n] / static_cast<double>(element.nodes.size());
    for (std::array<int, 3> t : split(c, m)) {
      const Eigen::Vector3d& a = mesh.nodes[t[0]];
      const Eigen::Vector3d normal = (mesh.nodes[t[1]] - a).cross(mesh.nodes[t[2]] - a);
      if (normal.dot(a - centroid) < 0.0) std::swap(t[1], t[2]);
      triangles.push_back(t);
    }
  }

  std::vector<int> index(mesh.nodes.size(), -1);
  for (const auto& t : triangles)
    for (int n : t) index[n] = 0;
  for (std::size_t n = 0; n < mesh.nodes.size(); ++n) {
    if (index[n] < 0) continue;
    index[n] = static_cast<int>(s.nodes.size());
    s.nodes.push_back(static_cast<int>(n));
  }
  s.normals = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(s.nodes.size()), 3);
  s.areas = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(s.nodes.size()));
  for (const auto& t : triangles) {
    const Eigen::Vector3d& a = mesh.nodes[t[0]];
    const Eigen::Vector3d twice_area = (mesh.nodes[t[1]] - a).cross(mesh.nodes[t[2]] - a);
    const std::array<int, 3> local = {index[t[0]], index[t[1]], index[t[2]]};
    for (int i : local) {
      s.normals.row(i) += twice_area.transpose();  // area-weighted
      s.areas(i) += twice_area.norm() / 6.0;
    }
    s.triangles.push_back(local);
  }
  for (Eigen::Index i = 0; i < s.normals.rows(); ++i) {
    const double norm = s.normals.row(i).norm();
    if (norm > 0.0) s.normals.row(i) /= norm;
  }
  return s;
}

int nearest_surface_node(const Surface& surface, const std::vector<Eigen::Vector3d>& nodes,
                         const Eigen::Vector3d& point) {
  int best = -1;
  double best_distance = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < surface.nodes.size(); ++i) {
    const double d = (nodes[surface.nodes[i]] - point).squaredNorm();
    if (d < best_distance) {
      best_distance = d;
      best = static_cast<int>(i);
    }
  }
  return best;
}

}  // namespace nvh::condense
