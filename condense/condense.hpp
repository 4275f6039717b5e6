#pragma once
// The condense pipeline as a library call: Component -> FeModel -> reduction -> invariants ->
// Superelement. The CLI (main.cpp) is a thin layer over this; tests and other tools call it directly.
#include <optional>

#include "common/log.hpp"
#include "common/resources.hpp"
#include "condense/component.hpp"
#include "condense/eigensolver.hpp"
#include "condense/mesh_export.hpp"
#include "condense/superelement.hpp"

namespace nvh::condense {

/// Command-line overrides of the component file's [reduction] table.
struct CondenseOptions {
  std::optional<double> fmax_hz;  ///< replaces fmax and clears modes
  std::optional<int> modes;       ///< replaces modes and clears fmax
  std::optional<ReductionMethod> method;
  std::optional<double> band_hz;  ///< replaces band (Hz)
  EigenBackend backend = EigenBackend::kBlockLanczos;
  Ordering ordering = Ordering::kAuto;
};

/// How to run condense_component, beyond the component itself. All optional.
struct CondenseRun {
  /// One lap per stage: mesh (volumes), assemble, reduce, invariants; the reduce lap includes the
  /// factorizations and eigen-solves, which the Superelement records separately (see stage_report).
  StageTimer* timer = nullptr;
  EigenProgress progress;  ///< follows the iterative eigen-solves
  Ordering ordering = Ordering::kAuto;
  /// Volume components: filled with the full mesh and the shapes of all coordinates (--keep-mesh).
  MeshExport* mesh_export = nullptr;
};

/// Apply the overrides to the component's reduction settings, then check_reduction().
void apply_options(Component& component, const CondenseOptions& options);

/// nvh::Error unless the settings ask for a count (fmax or modes) where the method needs one.
void check_reduction(const Component& component);

/// Build, reduce and describe the component. `timer` (optional) gets one lap per stage:
/// assemble, reduce, invariants; `progress` (optional) follows the iterative eigen-solves.
Superelement condense_component(const Component& component, EigenBackend backend, const Logger& log,
                                StageTimer* timer = nullptr, const EigenProgress& progress = {});
Superelement condense_component(const Component& component, EigenBackend backend, const Logger& log,
                                const CondenseRun& run);

/// The stages of a run for the report and /model: the timer's laps with "reduce" split into order
/// (fill-reducing ordering and symbolic analysis), factor (numeric factorizations), eigen-solve (the
/// Lanczos iterations) and reduce (the rest: constraint modes' solves, projections); in seconds.
std::vector<std::pair<std::string, double>> stage_report(const StageTimer& timer, const Superelement& se);

/// Number of rigid-body modes the supports leave: 6 - rank of the rigid-body field on the supported DOF.
int count_rigid_body_modes(const FeModel& model);

}  // namespace nvh::condense
