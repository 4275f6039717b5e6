// condense's superelement file: the contract through common's writer, then condense's /model record.
#include "condense/superelement.hpp"

#include <cstdint>

#include "common/hdf5.hpp"

namespace nvh::condense {

void write_model_record(h5::Group& root, const ModelRecord& se) {
  h5::Group model = root.create_group("model");
  model.set_attribute("nodes", static_cast<std::int64_t>(se.node_count));
  model.set_attribute("elements", static_cast<std::int64_t>(se.element_count));
  model.set_attribute("dofs", static_cast<std::int64_t>(se.dof_count));
  model.set_attribute("free_dofs", static_cast<std::int64_t>(se.free_dof_count));
  model.set_attribute("max_eigen_residual", se.max_residual);
  if (!se.stage_names.empty()) {
    model.set_attribute("stage_names", se.stage_names);
    model.set_attribute("stage_seconds", se.stage_seconds);
    model.set_attribute("peak_memory_bytes", se.peak_memory_bytes);
    if (!se.blas_kernels.empty()) model.set_attribute("blas_kernels", se.blas_kernels);
  }
  if (!se.factor_ordering.empty()) {
    model.set_attribute("factor_ordering", se.factor_ordering);
    model.set_attribute("matrix_nonzeros", se.matrix_nonzeros);
    model.set_attribute("factor_nonzeros", se.factor_nonzeros);
    model.set_attribute("factor_fill", se.factor_nonzeros / se.matrix_nonzeros);
    model.set_attribute("factor_flops", se.factor_flops);
    model.set_attribute("factorizations", static_cast<std::int64_t>(se.factorizations));
    model.set_attribute("eigen_solves", static_cast<std::int64_t>(se.eigen_solves));
  }
  if (!se.eigensolver.empty()) model.set_attribute("eigensolver", se.eigensolver);
}

void write_reduction_error(h5::Group& root, const ReductionErrorRecord& record) {
  const FrfErrorEstimate& e = record.estimate;
  if (e.empty()) return;
  h5::Group g = root.create_group("reduction_error");
  g.set_attribute("description",
                  "relative error of the reduced model's undamped receptance at the interface DOF against "
                  "the full model's, from deflated full-model solves at the sampled frequencies "
                  "(docs/component-format.md section 5.3)");
  g.set_attribute("band_hz", e.band_hz);
  g.set_attribute("tolerance", record.tolerance);
  g.set_attribute("cutoff_hz", record.cutoff_hz);
  g.set_attribute("max_error", e.max_error());
  g.set_attribute("length_scale_m", e.length_scale);
  g.set_attribute("solver_iterations", static_cast<std::int64_t>(e.solver_iterations));
  g.set_attribute("seconds", e.cost_seconds);
  g.write("frequency_hz", e.frequency_hz);
  g.set_attribute("units", "Hz", "frequency_hz");
  g.write("points", e.points);
  g.write("point_error", e.point_error);
  g.set_attribute("units", "1 (relative, points x frequencies)", "point_error");
  g.write("interface_error", e.interface_error);
  g.set_attribute("units", "1 (relative)", "interface_error");
  if (!record.passes.empty()) {
    std::vector<double> cutoffs, errors;
    for (const auto& [cutoff, error] : record.passes) {
      cutoffs.push_back(cutoff);
      errors.push_back(error);
    }
    g.set_attribute("pass_cutoff_hz", cutoffs);
    g.set_attribute("pass_max_error", errors);
  }
}

void write_superelement(const std::filesystem::path& path, const Superelement& se,
                        const Provenance& provenance) {
  nvh::write_superelement(path, se, provenance, [&se](h5::Group& root) {
    write_model_record(root, se);
    write_reduction_error(root, se.reduction_error);
  });
}

}  // namespace nvh::condense
