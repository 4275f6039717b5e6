// bench_condense_beam: wall time and peak memory of condense on a large beam model built in code.
//
// The model is a crankshaft-like zig-zag polyline of 100 segments (25 throws of journal, web, pin, web;
// throws turned 90 degrees each, so the model is fully 3D), passenger-car sections, a pulley mass at
// the front and a flywheel mass at the rear, free-free. With --elements 10000 (the default: 100 elements
// per segment) it has 10,001 nodes and 60,006 DOF.
//
// Stages: building the model (K, M on the free DOF), the bare eigen-solve (modes + 6 rigid-body modes,
// the call the modal reduction makes), then the full library pipeline condense_component() for a modal
// and a Craig-Bampton reduction (5 journal interfaces). --export DIR writes K and M (Matrix Market,
// lower triangle, "symmetric") and the frequencies for bench/peer_scipy_eigsh.py.
#include <Eigen/SparseCore>
#include <unsupported/Eigen/SparseExtra>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/log.hpp"
#include "common/resources.hpp"
#include "condense/beam_model.hpp"
#include "condense/component.hpp"
#include "condense/condense.hpp"
#include "condense/eigensolver.hpp"

namespace {

using namespace nvh;
using namespace nvh::condense;

constexpr int kSegments = 100;  // 25 throws x (journal, web, pin, web)
constexpr int kRigidModes = 6;

struct Options {
  int elements = 10000;
  int modes = 200;
  double fmax_hz = 0.0;  ///< > 0: the bare eigen-solve by this band instead of the count
  EigenBackend backend = EigenBackend::kSpectra;
  std::string export_dir;
  bool pipeline = true;
};

void usage(std::ostream& out) {
  out << "usage: bench_condense_beam [--elements N] [--modes M] [--fmax HZ] "
         "[--backend spectra|block-lanczos|arpack]\n"
         "                           [--export DIR] [--solve-only]\n"
         "  --elements N   beam elements (default 10000; rounded to a multiple of 100 segments)\n"
         "  --modes M      elastic modes to keep (default 200)\n"
         "  --fmax HZ      the bare eigen-solve by a band (all modes up to HZ) instead of M + 6 modes; the\n"
         "                 pipelines keep the count\n"
         "  --backend B    eigen-solver backend: spectra (default), block-lanczos or arpack\n"
         "  --export DIR   write K.mtx, M.mtx (free DOF, Matrix Market) and bench.json (shift, our\n"
         "                 frequencies and time) for bench/peer_scipy_eigsh.py\n"
         "  --solve-only   stop after the bare eigen-solve (skip the modal and Craig-Bampton pipelines)\n";
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw Error("option " + a + " needs a value");
      return argv[++i];
    };
    // The whole value as a number, or an error naming the option and the value.
    auto number = [&]() -> double {
      const std::string text = value();
      std::size_t used = 0;
      double x = 0;
      try {
        x = std::stod(text, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != text.size()) throw Error(a + " needs a number, got '" + text + "'");
      return x;
    };
    if (a == "--elements") {
      o.elements = static_cast<int>(number());
    } else if (a == "--modes") {
      o.modes = static_cast<int>(number());
    } else if (a == "--fmax") {
      o.fmax_hz = number();
      if (!(o.fmax_hz > 0.0))
        throw Error("--fmax must be a positive frequency in Hz, got " + std::string(argv[i]));
    } else if (a == "--backend") {
      const std::string b = value();
      if (b != "spectra" && b != "block-lanczos" && b != "arpack")
        throw Error("--backend must be spectra, block-lanczos or arpack, got " + b);
      o.backend = parse_eigen_backend(b);
    } else if (a == "--export") {
      o.export_dir = value();
    } else if (a == "--solve-only") {
      o.pipeline = false;
    } else if (a == "-h" || a == "--help") {
      usage(std::cout);
      std::exit(0);
    } else {
      throw Error("unknown option " + a);
    }
  }
  if (o.elements < kSegments) throw Error("--elements must be at least " + std::to_string(kSegments));
  if (o.modes < 1) throw Error("--modes must be positive");
  return o;
}

BeamSection circle(double d) {
  BeamSection s;
  s.A = std::numbers::pi * d * d / 4.0;
  s.Iy = s.Iz = std::numbers::pi * std::pow(d, 4) / 64.0;
  s.J = 2.0 * s.Iy;
  s.shear_factor = 0.9;
  return s;
}

/// Web: b = 70 mm wide (in the plane normal to the crank axis), t = 20 mm thick along the crank axis x.
BeamSection web() {
  const double b = 0.070, t = 0.020;
  BeamSection s;
  s.A = b * t;
  s.Iy = t * b * b * b / 12.0;  // local y = global x (y_axis below): about the crank axis direction
  s.Iz = b * t * t * t / 12.0;
  s.J = 0.27331 * b * t * t * t;  // Saint-Venant, b/t = 3.5
  s.shear_factor = 0.833;
  s.y_axis = Vec3{1.0, 0.0, 0.0};
  return s;
}

NamedPoint named_point(const std::string& name, const Vec3& at) {
  NamedPoint p;
  p.name = name;
  p.at = at;
  return p;
}

PointMass point_mass(const Vec3& at, double m, const Vec3& J) {
  PointMass p;
  p.at = at;
  p.m = m;
  p.J = J;
  return p;
}

/// The benchmark component (see the file comment). Journal stations of throws 0, 6, 12, 18, 24 are
/// the Craig-Bampton interfaces.
Component bench_component(int elements_per_segment, int modes) {
  Component c;
  c.name = "bench-crank-25";
  c.kind = "beam";
  c.materials["steel"] = Material{"steel", 210e9, 0.3, 7850.0};
  BeamGeometry& beam = c.beam;
  beam.material = "steel";
  beam.elements_per_segment = elements_per_segment;
  const double journal = 0.044, pin = 0.046, radius = 0.043;
  double x = 0.0;
  beam.points.push_back({x, 0.0, 0.0});
  for (int throw_index = 0; throw_index < kSegments / 4; ++throw_index) {
    const double angle = throw_index * std::numbers::pi / 2.0;
    const double y = radius * std::cos(angle), z = radius * std::sin(angle);
    if (throw_index % 6 == 0) {
      c.interfaces.push_back(named_point("journal" + std::to_string(throw_index), {x, 0.0, 0.0}));
    }
    x += journal;
    beam.points.push_back({x, 0.0, 0.0});
    beam.points.push_back({x, y, z});
    x += pin;
    beam.points.push_back({x, y, z});
    beam.points.push_back({x, 0.0, 0.0});
    beam.segment_sections.push_back(circle(0.055));
    beam.segment_sections.push_back(web());
    beam.segment_sections.push_back(circle(0.048));
    beam.segment_sections.push_back(web());
  }
  beam.masses.push_back(point_mass({0.0, 0.0, 0.0}, 1.5, {0.006, 0.0035, 0.0035}));  // pulley
  beam.masses.push_back(point_mass(beam.points.back(), 8.0, {0.10, 0.052, 0.052}));  // flywheel
  c.observers.push_back(named_point("pulley", {0.0, 0.0, 0.0}));
  c.reduction.method = ReductionMethod::kModal;
  c.reduction.modes = modes;
  c.reduction.orthonormalize = true;
  c.reduction.damping_ratio = 0.01;
  return c;
}

/// Reset the kernel's peak-RSS counter (VmHWM) so that the next stages report their own peak.
bool reset_peak_memory() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.flush();
  return static_cast<bool>(clear);
}

double mib(long long bytes) {
  return static_cast<double>(bytes) / (1024.0 * 1024.0);
}

void print_row(const std::string& name, double seconds, long long peak) {
  std::printf("  %-36s %10.3f %14.1f\n", name.c_str(), seconds, mib(peak));
}

void print_stages(const std::string& prefix, const StageTimer& timer) {
  for (const StageTimer::Stage& s : timer.stages()) print_row(prefix + s.name, s.seconds, s.peak_bytes);
}

std::string json_number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

void export_problem(const std::filesystem::path& dir, const SparseMatrix& K, const SparseMatrix& M,
                    const EigenResult& eig, double seconds, const Options& o, int elements) {
  std::filesystem::create_directories(dir);
  const SparseMatrix k_lower = K.triangularView<Eigen::Lower>();
  const SparseMatrix m_lower = M.triangularView<Eigen::Lower>();
  if (!Eigen::saveMarket(k_lower, (dir / "K.mtx").string(), Eigen::Symmetric) ||
      !Eigen::saveMarket(m_lower, (dir / "M.mtx").string(), Eigen::Symmetric)) {
    throw Error("cannot write the Matrix Market files in " + dir.string());
  }
  std::ofstream json(dir / "bench.json");
  json << "{\n  \"elements\": " << elements << ",\n  \"dof\": " << K.rows()
       << ",\n  \"k\": " << eig.eigenvalues.size() << ",\n  \"rigid_body_modes\": " << kRigidModes
       << ",\n  \"sigma\": " << json_number(eig.shift) << ",\n  \"shift\": " << json_number(-eig.shift)
       << ",\n  \"backend\": \"" << to_string(o.backend) << "\",\n  \"tolerance\": 1e-10"
       << ",\n  \"matrix_operations\": " << eig.matrix_operations
       << ",\n  \"seconds\": " << json_number(seconds) << ",\n  \"frequencies_hz\": [";
  for (Eigen::Index i = 0; i < eig.eigenvalues.size(); ++i) {
    json << (i ? ", " : "") << json_number(frequency_hz(eig.eigenvalues(i)));
  }
  json << "]\n}\n";
  if (!json) throw Error("cannot write " + (dir / "bench.json").string());
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    const int per = o.elements / kSegments;
    const int elements = per * kSegments;
    Component component = bench_component(per, o.modes);
    const Logger log(std::cerr, "bench", Verbosity::kQuiet);

    // 1. Model and the bare eigen-solve (in a block: its matrices are freed before the pipelines run).
    reset_peak_memory();
    StageTimer timer;
    Eigen::VectorXd bare_hz;
    {
      const FeModel model = build_beam_model(component);
      const SparseMatrix K = model.stiffness();
      const SparseMatrix M = model.mass();
      timer.lap("model: build, K and M");
      EigenRequest request;
      request.modes = o.fmax_hz > 0.0 ? 0 : o.modes + kRigidModes;
      request.fmax_hz = o.fmax_hz;
      request.backend = o.backend;
      const EigenResult eig = solve_eigenproblem(K, M, request);
      timer.lap("eigen-solve (" + std::to_string(eig.eigenvalues.size()) + " modes)");
      const double solve_seconds = timer.stages().back().seconds;
      std::printf(
          "bench_condense_beam: %d elements (%d segments x %d), %zu nodes, %d free DOF, %d modes, %s\n",
          elements, kSegments, per, model.nodes.size(), model.free_dofs(), o.modes,
          to_string(o.backend).c_str());
      std::printf(
          "  K: %lld non-zeros, M: %lld non-zeros; shift sigma = %.6g rad^2/s^2 (%.1f Hz), %d solves\n",
          static_cast<long long>(K.nonZeros()), static_cast<long long>(M.nonZeros()), eig.shift,
          std::sqrt(-eig.shift) / (2.0 * std::numbers::pi), eig.matrix_operations);
      const Eigen::Index n_found = eig.eigenvalues.size();
      std::printf("  frequencies: rigid max %.3g Hz; elastic %.6g .. %.6g Hz; max residual %.2e\n",
                  frequency_hz(eig.eigenvalues(kRigidModes - 1)), frequency_hz(eig.eigenvalues(kRigidModes)),
                  frequency_hz(eig.eigenvalues(n_found - 1)), eig.residuals.maxCoeff());
      if (!o.export_dir.empty()) {
        export_problem(o.export_dir, K, M, eig, solve_seconds, o, elements);
        timer.lap("export (bench only)");
        std::printf("  exported K.mtx, M.mtx, bench.json to %s\n", o.export_dir.c_str());
      }
      bare_hz = eig.eigenvalues.unaryExpr([](double l) { return frequency_hz(l); });
    }

    if (!o.pipeline) {
      std::printf("\n  %-36s %10s %14s\n", "stage", "wall [s]", "peak RSS [MiB]");
      print_stages("", timer);
      return 0;
    }

    // 2. The library pipeline, modal and Craig-Bampton (each with its own peak memory).
    const bool reset = reset_peak_memory();
    StageTimer modal_timer;
    component.reduction.method = ReductionMethod::kModal;
    const Superelement modal = condense_component(component, o.backend, log, &modal_timer);

    reset_peak_memory();
    StageTimer cb_timer;
    component.reduction.method = ReductionMethod::kCraigBampton;
    const Superelement cb = condense_component(component, o.backend, log, &cb_timer);

    std::printf("\n  %-36s %10s %14s\n", "stage", "wall [s]", "peak RSS [MiB]");
    print_stages("", timer);
    print_stages("modal: ", modal_timer);
    print_stages("craig-bampton: ", cb_timer);
    std::printf("  %-36s %10.3f\n", "total",
                timer.total_seconds() + modal_timer.total_seconds() + cb_timer.total_seconds());
    std::printf("  (peak RSS %s)\n", reset
                                         ? "since the start of each block: model+solve, modal, craig-bampton"
                                         : "of the whole process so far: /proc/self/clear_refs not writable");
    std::printf("\n  modal: %d coordinates, %.6g .. %.6g Hz\n", modal.size(), modal.frequency_hz(0),
                modal.frequency_hz(modal.frequency_hz.size() - 1));
    std::printf(
        "  craig-bampton: %d coordinates (%zu interfaces, %lld fixed-interface modes), %.6g .. %.6g Hz\n",
        cb.size(), cb.interfaces.names.size(), static_cast<long long>(cb.fixed_interface_hz.size()),
        cb.frequency_hz(0), cb.frequency_hz(cb.frequency_hz.size() - 1));
    // Agreement of the pipeline's modal frequencies with the bare solve (same call, same numbers).
    double worst = 0.0;
    for (Eigen::Index i = 0; i < modal.frequency_hz.size(); ++i) {
      const double ref = bare_hz(kRigidModes + i);
      worst = std::max(worst, std::abs(modal.frequency_hz(i) - ref) / ref);
    }
    std::printf("  modal vs bare eigen-solve: max relative difference %.2e\n", worst);
    return 0;
  } catch (const Error& e) {
    std::cerr << "bench_condense_beam: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "bench_condense_beam: " << e.what() << "\n";
    return 1;
  }
}
