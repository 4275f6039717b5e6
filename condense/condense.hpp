#pragma once
// The condense pipeline as a library call: Component -> FeModel -> reduction -> invariants ->
// Superelement. The CLI (main.cpp) is a thin layer over this; tests and other tools call it directly.
#include <optional>

#include "common/log.hpp"
#include "common/resources.hpp"
#include "condense/component.hpp"
#include "condense/eigensolver.hpp"
#include "condense/superelement.hpp"

namespace nvh::condense {

/// Command-line overrides of the component file's [reduction] table.
struct CondenseOptions {
  std::optional<double> fmax_hz;  ///< replaces fmax and clears modes
  std::optional<int> modes;       ///< replaces modes and clears fmax
  std::optional<ReductionMethod> method;
  EigenBackend backend = EigenBackend::kSpectra;
};

/// Apply the overrides to the component's reduction settings, then check_reduction().
void apply_options(Component& component, const CondenseOptions& options);

/// nvh::Error unless the settings ask for a count (fmax or modes) where the method needs one.
void check_reduction(const Component& component);

/// Build, reduce and describe the component. `timer` (optional) gets one lap per stage:
/// assemble, reduce, invariants; `progress` (optional) follows the iterative eigen-solves.
Superelement condense_component(const Component& component, EigenBackend backend, const Logger& log,
                                StageTimer* timer = nullptr, const EigenProgress& progress = {});

/// Number of rigid-body modes the supports leave: 6 - rank of the rigid-body field on the supported DOF.
int count_rigid_body_modes(const FeModel& model);

}  // namespace nvh::condense
