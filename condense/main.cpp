// condense: reduce a component (beam model) to a modal superelement for solve.
// A thin CLI over the condense library (condense/condense.hpp).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <string_view>

#include "common/blas_kernels.hpp"
#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "common/log.hpp"
#include "common/output_path.hpp"
#include "common/progress.hpp"
#include "common/provenance.hpp"
#include "common/resources.hpp"
#include "common/version.hpp"
#include "condense/component_reader.hpp"
#include "condense/condense.hpp"
#include "condense/export_command.hpp"

namespace {

constexpr const char* kDescription =
    R"(condense - reduce a component to a modal superelement (step 1 of 3: condense -> solve -> postproc)

Reads a component file (TOML: materials, a beam of stations and sections, point masses, rigid links,
supports, interface and observation points, and a [reduction] table; or, for kind = "volume", a solid
mesh from an Abaqus/CalculiX .inp file), builds its finite-element model (3D Timoshenko beams, or
C3D4/C3D10/C3D8/C3D20 solids), solves its eigenproblem (shift-invert Lanczos on a sparse Cholesky
factorization) and reduces it:
  modal          free-free (or supported) normal modes up to fmax; rigid-body modes left to solve's
                 floating frame of reference
  craig-bampton  interface DOF + constraint modes + fixed-interface modes up to fmax; with
                 orthonormalize = true the basis is rotated onto the modes of the reduced system.
                 fmax is the fixed-interface cut-off, not the band: 3-7 times the highest frequency
                 of interest (more with many interfaces) keeps the reduced frequencies within about
                 0.1 % (measured cases in docs/component-format.md section 5)
  guyan          interface DOF + constraint modes only (static condensation)
Or give the band the results must cover instead of a cut-off: band = 800 (Hz) chooses the cut-off
(from 1.5 x band up) until the estimated error of the receptance at every interface in 0 .. band, from
full-model solves at sampled frequencies, is below frf_tolerance (default 0.01); with fmax or modes
given, band only estimates and reports that error. The estimate goes to the log and to
/reduction_error of OUT.h5 (docs/component-format.md section 5.3).
Options of [reduction]: residual_modes = true (modal: static correction modes of the interface DOF);
geometric_stiffening = true (beams and solids: the centrifugal stress stiffness per product of the spin's
components, which solve scales with each flexible body's own spin; spin_speed_rpm and spin_axis reduce
at a speed; docs/component-format.md section 5.2). [[preload]] point = "NAME", force = [..] (N),
moment = [..] (N m): static loads whose prestress stiffens the part before it is reduced.
It writes OUT.h5: reduced mass, stiffness and damping, eigenfrequencies, interface and observation
shapes, mass properties and the floating-frame inertia invariants, with provenance. The layout is
documented in docs/hdf5-format.md, the input in docs/component-format.md.

Example:
  condense testdata/crankshaft.toml -o crankshaft.h5
  condense testdata/crankshaft.toml -o crank_modal.h5 --method modal --fmax 3000
  h5dump -H crankshaft.h5

condense export SUPERELEMENT.h5 -o OUT.pch writes the reduced matrices of a superelement file as Nastran
DMIG bulk data for other programs (GRID ids for interface DOF, SPOINTs for modes; SI units); see
condense export --help and docs/matrix-export.md.

Exit codes: 0 success; 1 bad input or failed run (message names file, line, key); 2 bad command line;
3 interrupted (SIGINT/SIGTERM: the temporary output is removed, nothing is left half-written).)";

std::string frequency_list(const Eigen::VectorXd& f, int max_count) {
  std::ostringstream out;
  out.precision(6);
  const int n = static_cast<int>(f.size());
  for (int i = 0; i < n && i < max_count; ++i) out << (i ? ", " : "") << f(i);
  if (n > max_count) out << ", ... (" << n << " in all)";
  return out.str();
}

/// The cost of the run, printed at the end: time of each stage, peak memory, and the factorization.
std::string run_report(const nvh::StageTimer& timer, const nvh::condense::Superelement& se) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(2);
  out << "stages [s]:";
  double total = 0.0;
  for (const auto& [name, seconds] : nvh::condense::stage_report(timer, se)) {
    out << " " << name << " " << seconds << ",";
    total += seconds;
  }
  out << " total " << total << "; peak memory " << static_cast<double>(nvh::peak_memory_bytes()) / (1 << 20)
      << " MiB";
  if (!se.factor_ordering.empty()) {
    out.unsetf(std::ios::fixed);
    out.precision(3);
    const bool lobpcg = se.eigensolver == "lobpcg";  // its factor is the preconditioner's coarse one
    out << "\n  " << (lobpcg ? "coarse factor: " : "factor: ") << se.factor_ordering << " ordering, nnz(L) "
        << se.factor_nonzeros << " = " << se.factor_nonzeros / se.matrix_nonzeros << " x nnz(tril A), "
        << se.factor_flops / 1e9 << " Gflop, " << se.factorizations << " factorization"
        << (se.factorizations == 1 ? "" : "s") << ", " << se.eigen_solves
        << (lobpcg ? " LOBPCG iterations" : " solves") << "; BLAS: " << nvh::blas_kernels();
  }
  return out.str();
}

}  // namespace

int main(int argc, char** argv) {
  using namespace nvh;
  using namespace nvh::condense;

  select_blas_kernels(argv);  // may re-execute condense with OpenBLAS's right kernels (blas_kernels.hpp)
  install_interrupt_handler("condense");
  // `condense export ...`: the superelement file written for another program (export_command.hpp).
  if (argc > 1 && std::string_view(argv[1]) == "export") return run_export_command(argc - 1, argv + 1);
  CLI::App app{kDescription, "condense"};
  app.get_formatter()->column_width(34);
  std::string component_file, output_file, method, eigensolver = "block-lanczos";
  std::optional<double> fmax;
  std::optional<int> modes;
  std::optional<double> band;
  bool quiet = false, verbose = false, keep_mesh = false;
  std::string ordering = "auto";
  app.add_option("COMPONENT", component_file, "component file (.toml); see docs/component-format.md")
      ->required();
  app.add_option("-o,--output", output_file,
                 "superelement file to write (.h5); written to a temporary and "
                 "renamed when complete")
      ->required();
  app.add_option("--fmax", fmax, "keep modes up to this frequency, Hz (overrides [reduction] fmax/modes)")
      ->check(CLI::PositiveNumber);
  app.add_option("--band", band,
                 "the band the results must cover, Hz: estimate the reduced model's receptance error in it, "
                 "and choose the cut-off unless --fmax/--modes (or fmax/modes in the file) give one "
                 "(overrides [reduction] band)")
      ->check(CLI::PositiveNumber);
  app.add_option("--modes", modes, "keep this many modes (overrides [reduction] fmax/modes)")
      ->check(CLI::PositiveNumber);
  app.add_option("--method", method, "reduction method (overrides [reduction] method)")
      ->check(CLI::IsMember({"modal", "craig-bampton", "guyan"}));
  app.add_option(
         "--eigensolver", eigensolver,
         "eigen-solver backend: block-lanczos (shift-invert Lanczos a block of columns at a time, "
         "default: one solve with the factor serves several vectors), spectra (the same one vector at "
         "a time), arpack (for comparison), dense (small models), lobpcg (large compact solids of "
         "second-order tetrahedra, any "
         "reduction, by modes or fmax: no factor of K, about half the memory; docs/cli.md)")
      ->check(CLI::IsMember({"spectra", "block-lanczos", "arpack", "dense", "lobpcg"}));
  app.add_option("--ordering", ordering,
                 "fill-reducing ordering of the sparse factorizations: auto (CHOLMOD's choice: AMD, or METIS "
                 "when AMD fills much; default), amd, metis, nesdis")
      ->check(CLI::IsMember({"auto", "amd", "metis", "nesdis"}));
  app.add_flag("--keep-mesh", keep_mesh,
               "volume components: also write the mesh and the shapes of all coordinates on it for ParaView, "
               "OUT.xdmf with its arrays in OUT.mesh.h5 (beside OUT.h5)");
  CLI::Option* quiet_flag = app.add_flag("-q,--quiet", quiet, "print errors only");
  app.add_flag("-v,--verbose", verbose, "print more detail (stage timings, all frequencies)")
      ->excludes(quiet_flag);
  app.set_version_flag("--version", std::string("condense ") + kVersion);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : static_cast<int>(ExitCode::kUsage);
  }
  if (fmax && modes) {
    std::cerr << "condense: give either --fmax or --modes, not both\n";
    return static_cast<int>(ExitCode::kUsage);
  }

  const Logger log(std::cerr, "condense",
                   quiet     ? Verbosity::kQuiet
                   : verbose ? Verbosity::kVerbose
                             : Verbosity::kNormal);
  try {
    StageTimer timer;
    // Before any work: no output may replace an input, and every output must be writable.
    std::vector<std::filesystem::path> outputs{output_file};
    if (keep_mesh) {
      outputs.push_back(mesh_export_xdmf_path(output_file));
      outputs.push_back(mesh_export_h5_path(output_file));
    }
    check_outputs_are_not_inputs(outputs, {component_file});
    for (const auto& output : outputs) check_output_writable(output);
    Component component = read_component(component_file);
    if (component.kind == "volume") check_outputs_are_not_inputs(outputs, {component.volume.mesh});
    CondenseOptions options;
    options.fmax_hz = fmax;
    options.modes = modes;
    options.band_hz = band;
    if (!method.empty()) {
      options.method = method == "modal"   ? ReductionMethod::kModal
                       : method == "guyan" ? ReductionMethod::kGuyan
                                           : ReductionMethod::kCraigBampton;
    }
    options.backend = parse_eigen_backend(eigensolver);
    options.ordering = parse_ordering(ordering);
    apply_options(component, options);
    timer.lap("read");
    {
      const ReductionSettings& r = component.reduction;
      std::ostringstream what;
      what << "component \"" << component.name << "\": " << to_string(r.method) << " reduction";
      if (r.method == ReductionMethod::kGuyan) {
        what << " (interface DOF only)";
      } else if (r.modes > 0) {
        what << ", " << r.modes << " modes";
      } else if (r.fmax_hz <= 0.0) {
        what << ", cut-off chosen for the band 0 .. " << r.band_hz << " Hz";
      } else {
        what << ", modes up to " << r.fmax_hz << " Hz";
      }
      log.info(what.str());
    }

    // The eigen-solve is the long stage: a bar on a terminal, plain lines in batch logs.
    // A new Lanczos run (the count starts again) gets a new bar; a run that needs more solves than
    // expected (restarts) moves its bar's total.
    std::unique_ptr<Progress> bar;
    int bar_done = 0;
    const EigenProgress progress = [&](int done, int expected) {
      if (!bar || done < bar_done) {
        bar = std::make_unique<Progress>(log, "eigen-solve", expected);
      } else {
        bar->set_total(expected);
      }
      bar_done = done;
      bar->update(std::min(done, expected));
    };
    CondenseRun run;
    run.timer = &timer;
    run.progress = progress;
    run.ordering = options.ordering;
    MeshExport mesh_export;
    if (keep_mesh) {
      if (component.kind != "volume") {
        throw Error("--keep-mesh is for volume components (a beam model has no solid mesh to keep)");
      }
      run.mesh_export = &mesh_export;
    }
    Superelement se = [&] {
      try {
        return condense_component(component, options.backend, log, run);
      } catch (const Error& e) {
        // A failure of the model itself (a singular stiffness, an eigen-solve that does not converge) comes
        // from the component's numbers: name the file, so a batch log of many components points at it.
        const std::string name = std::filesystem::path(component_file).filename().string();
        if (std::string(e.what()).find(name) != std::string::npos) throw;
        throw Error(component_file + ": " + e.what() +
                    " (check the component's geometry, materials and supports)");
      }
    }();
    bar.reset();
    for (const auto& [name, seconds] : stage_report(timer, se)) {
      se.stage_names.push_back(name);
      se.stage_seconds.push_back(seconds);
    }
    se.peak_memory_bytes = static_cast<double>(peak_memory_bytes());
    se.blas_kernels = blas_kernels();
    // Every input is hashed: the component file, and a volume component's mesh.
    std::vector<std::filesystem::path> inputs{component_file};
    if (component.kind == "volume") inputs.push_back(component.volume.mesh);
    const Provenance provenance = make_provenance("condense", argc, argv, inputs);
    // The mesh export first: the superelement file, written last, marks a complete run.
    if (keep_mesh) write_mesh_export(output_file, mesh_export, provenance);
    write_superelement(output_file, se, provenance);
    timer.lap("write");

    std::ostringstream summary;
    summary.precision(6);
    summary << "wrote " << output_file << ": " << se.size() << " coordinates (" << se.method
            << (se.orthonormalized ? ", orthonormalized" : "") << "), " << se.interfaces.names.size()
            << " interface and " << se.observers.names.size() << " observation points\n";
    summary << "  frequencies [Hz]: " << frequency_list(se.frequency_hz, verbose ? 1000 : 8) << "\n";
    summary << "  mass " << se.inertia.mass << " kg, centre of mass ["
            << se.inertia.center_of_mass.transpose() << "] m";
    if (keep_mesh) {
      summary << "\n  mesh and shapes for ParaView: " << mesh_export_xdmf_path(output_file).string() << " ("
              << mesh_export_h5_path(output_file).filename().string() << ")";
    }
    log.info(summary.str());
    log.info(run_report(timer, se));
    return static_cast<int>(ExitCode::kSuccess);
  } catch (const Error& e) {
    log.error(e.what());
    return static_cast<int>(ExitCode::kFailure);
  } catch (const std::exception& e) {
    log.error(std::string("unexpected failure: ") + e.what());
    return static_cast<int>(ExitCode::kFailure);
  }
}
