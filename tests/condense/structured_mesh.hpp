#pragma once
// Structured meshes of a box for the volume tests: 20-node bricks (C3D20), or 10-node tetrahedra
// (C3D10) from the Kuhn split of every brick into 6 tetrahedra around its main diagonal, which is
// conforming because every cell splits its faces the same way. Node orders are Abaqus/CalculiX's.
#include <Eigen/Geometry>
#include <array>
#include <map>
#include <utility>

#include "condense/abaqus_mesh.hpp"

namespace nvh::condense::testing {

class BoxMesher {
 public:
  BoxMesher(Eigen::Vector3d size, std::array<int, 3> cells) : size_(std::move(size)), cells_(cells) {}

  Mesh hex20() {
    Mesh mesh = start();
    for (int k = 0; k < cells_[2]; ++k)
      for (int j = 0; j < cells_[1]; ++j)
        for (int i = 0; i < cells_[0]; ++i) {
          const auto c = cell_corners(i, j, k);
          MeshElement e;
          e.type = "C3D20";
          e.elset = "EALL";
          e.nodes.assign(c.begin(), c.end());
          // Mid-edge nodes 9..20: bottom 1-2 2-3 3-4 4-1, top 5-6 6-7 7-8 8-5, vertical 1-5 2-6 3-7 4-8.
          const int edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                    {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
          for (const auto& edge : edges) e.nodes.push_back(midside(mesh, c[edge[0]], c[edge[1]]));
          add(mesh, e);
        }
    return mesh;
  }

  Mesh tet10() {
    Mesh mesh = start();
    // Kuhn split around the diagonal 0-6 of a cell with corners 0..7 as in cell_corners().
    const int tets[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
    for (int k = 0; k < cells_[2]; ++k)
      for (int j = 0; j < cells_[1]; ++j)
        for (int i = 0; i < cells_[0]; ++i) {
          const auto c = cell_corners(i, j, k);
          for (const auto& t : tets) {
            std::array<int, 4> v = {c[t[0]], c[t[1]], c[t[2]], c[t[3]]};
            // Positive volume: (x2 - x1) x (x3 - x1) . (x4 - x1) > 0.
            const Eigen::Vector3d& a = mesh.nodes[v[0]];
            if ((mesh.nodes[v[1]] - a).cross(mesh.nodes[v[2]] - a).dot(mesh.nodes[v[3]] - a) < 0) std::swap(v[1], v[2]);
            MeshElement e;
            e.type = "C3D10";
            e.elset = "EALL";
            e.nodes.assign(v.begin(), v.end());
            const int edges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
            for (const auto& edge : edges) e.nodes.push_back(midside(mesh, v[edge[0]], v[edge[1]]));
            add(mesh, e);
          }
        }
    return mesh;
  }

 private:
  Mesh start() {
    Mesh mesh;
    mesh.file = "structured";
    midsides_.clear();
    for (int k = 0; k <= cells_[2]; ++k)
      for (int j = 0; j <= cells_[1]; ++j)
        for (int i = 0; i <= cells_[0]; ++i)
          add_node(mesh, Eigen::Vector3d(size_(0) * i / cells_[0], size_(1) * j / cells_[1], size_(2) * k / cells_[2]));
    return mesh;
  }
  int corner(int i, int j, int k) const { return (k * (cells_[1] + 1) + j) * (cells_[0] + 1) + i; }
  /// Corners in Abaqus order: bottom (z low) 1-2-3-4 counter-clockwise seen from above, top 5-8.
  std::array<int, 8> cell_corners(int i, int j, int k) const {
    return {corner(i, j, k),         corner(i + 1, j, k),         corner(i + 1, j + 1, k),
            corner(i, j + 1, k),     corner(i, j, k + 1),         corner(i + 1, j, k + 1),
            corner(i + 1, j + 1, k + 1), corner(i, j + 1, k + 1)};
  }
  int add_node(Mesh& mesh, const Eigen::Vector3d& x) {
    mesh.nodes.push_back(x);
    mesh.node_ids.push_back(static_cast<std::int64_t>(mesh.nodes.size()));
    return static_cast<int>(mesh.nodes.size()) - 1;
  }
  int midside(Mesh& mesh, int a, int b) {
    const auto key = std::minmax(a, b);
    const auto it = midsides_.find(key);
    if (it != midsides_.end()) return it->second;
    const int n = add_node(mesh, 0.5 * (mesh.nodes[a] + mesh.nodes[b]));
    midsides_[key] = n;
    return n;
  }
  static void add(Mesh& mesh, MeshElement e) {
    e.id = static_cast<std::int64_t>(mesh.elements.size()) + 1;
    mesh.element_sets["EALL"].push_back(static_cast<int>(mesh.elements.size()));
    mesh.elements.push_back(std::move(e));
  }

  Eigen::Vector3d size_;
  std::array<int, 3> cells_;
  std::map<std::pair<int, int>, int> midsides_;
};

}  // namespace nvh::condense::testing
