#include "condense/block_assembly.hpp"

#include <algorithm>

namespace nvh::condense {

int NodeGraph::position(int n, int m) const {
  const auto first = neighbours.begin() + start[n], last = neighbours.begin() + start[n + 1];
  return static_cast<int>(std::lower_bound(first, last, m) - first);
}

NodeGraph node_graph(int node_count, const std::vector<MeshElement>& elements) {
  // Node -> elements (CSR), then each node's neighbours as the sorted union of its elements' nodes.
  std::vector<int> count(node_count + 1, 0);
  for (const MeshElement& e : elements)
    for (int n : e.nodes) ++count[n + 1];
  for (int n = 0; n < node_count; ++n) count[n + 1] += count[n];
  std::vector<int> element_of(count[node_count]);
  {
    std::vector<int> fill(count.begin(), count.end() - 1);
    for (std::size_t e = 0; e < elements.size(); ++e)
      for (int n : elements[e].nodes) element_of[fill[n]++] = static_cast<int>(e);
  }
  NodeGraph g;
  g.start.assign(node_count + 1, 0);
  std::vector<int> scratch;
  std::vector<int> listed(node_count, -1);  // the last node whose list took m: duplicates skipped
  for (int n = 0; n < node_count; ++n) {
    scratch.clear();
    for (int k = count[n]; k < count[n + 1]; ++k)
      for (int m : elements[element_of[k]].nodes)
        if (listed[m] != n) listed[m] = n, scratch.push_back(m);
    std::sort(scratch.begin(), scratch.end());
    g.neighbours.insert(g.neighbours.end(), scratch.begin(), scratch.end());
    g.start[n + 1] = static_cast<int>(g.neighbours.size());
  }
  return g;
}

BlockAssembler::BlockAssembler(const NodeGraph& graph, int total_nodes,
                               const std::array<std::array<bool, 3>, 3>& couple) {
  const int graph_nodes = static_cast<int>(graph.start.size()) - 1;
  for (int b = 0; b < 3; ++b)
    for (int a = 0; a < 3; ++a)
      if (couple[a][b]) offset_[a][b] = per_neighbour_[b]++;
  const Eigen::Index size = 6 * static_cast<Eigen::Index>(total_nodes);
  matrix_.resize(size, size);
  std::size_t nonzeros = 0;
  for (int n = 0; n < graph_nodes; ++n)
    for (int b = 0; b < 3; ++b)
      nonzeros += static_cast<std::size_t>(per_neighbour_[b]) * (graph.start[n + 1] - graph.start[n]);
  matrix_.resizeNonZeros(static_cast<Eigen::Index>(nonzeros));
  int* outer = matrix_.outerIndexPtr();
  int* inner = matrix_.innerIndexPtr();
  int k = 0;
  for (Eigen::Index col = 0; col < size; ++col) {
    outer[col] = k;
    const int n = static_cast<int>(col / 6), b = static_cast<int>(col % 6);
    if (n >= graph_nodes || b >= 3) continue;
    for (int p = graph.start[n]; p < graph.start[n + 1]; ++p)
      for (int a = 0; a < 3; ++a)
        if (couple[a][b]) inner[k++] = 6 * graph.neighbours[p] + a;
  }
  outer[size] = k;
  std::fill(matrix_.valuePtr(), matrix_.valuePtr() + k, 0.0);
}

NodeAssembler::NodeAssembler(const NodeGraph& graph, int total_nodes) {
  const int graph_nodes = static_cast<int>(graph.start.size()) - 1;
  matrix_.resize(total_nodes, total_nodes);
  matrix_.resizeNonZeros(static_cast<Eigen::Index>(graph.neighbours.size()));
  int* outer = matrix_.outerIndexPtr();
  for (int n = 0; n <= total_nodes; ++n) outer[n] = graph.start[std::min(n, graph_nodes)];
  std::copy(graph.neighbours.begin(), graph.neighbours.end(), matrix_.innerIndexPtr());
  std::fill(matrix_.valuePtr(), matrix_.valuePtr() + graph.neighbours.size(), 0.0);
}

}  // namespace nvh::condense
