#pragma once
// The body-wise partitioned ("split") integrator, [integrator] method = "split"
// (docs/theory/split-integrator.md, docs/scene-format.md section 7): the bodies are partitioned into groups,
// each group integrated by its own IDA instance (variable-order BDF, its own adaptive step) over a macro step
// H, the groups coupled only through the force elements between them. Bodies linked by a joint or driver (a
// constraint) are always in one group: the groups are the connected components of the joint graph, ground
// excluded, merged further by IntegratorSettings::split_groups.
#include <memory>
#include <string>
#include <vector>

#include "solve/integrator.hpp"

namespace nvh::solve {

/// Which group each unknown of y belongs to (Model's state layout, model.hpp).
struct SplitPartition {
  int groups = 0;
  std::vector<int> group_of_state;               // size Model::size()
  std::vector<std::vector<int>> states;          // per group: its unknowns, ascending
  std::vector<std::vector<std::string>> bodies;  // per group: its bodies' names (messages, tests)
};

/// The partition of `model`: bodies -> connected components of the joint graph (ground excluded), then the
/// components that share a body of one `merge` list are joined. Every other unknown follows a body: a
/// constraint's multipliers its bodies' group, an element's states the group of its first marker on a moving
/// body, the clock angle its body i's (or j's), the two energy integrals the last group. Groups are numbered
/// by their first body in the scene's order. Throws nvh::Error for a `merge` entry naming no moving body.
SplitPartition partition_model(const Model& model, const std::vector<std::vector<std::string>>& merge = {});

std::unique_ptr<Integrator> make_split_integrator(const Model& model, const IntegratorSettings& s, double t0,
                                                  const Eigen::VectorXd& y0, const Eigen::VectorXd& yp0);

}  // namespace nvh::solve
