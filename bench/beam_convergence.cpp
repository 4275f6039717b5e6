// bench_beam_convergence: accuracy against cost of the beam element and of the reductions, charted
// against references not computed with this code.
//
// a) Element convergence, slender cantilever: steel rod L = 1 m, d = 10 mm, Euler-Bernoulli element
//    (no shear factor, rotary_inertia = false), 1..64 elements. Bending modes 1-4 against the
//    Euler-Bernoulli cantilever, beta_n L = 1.8751040687, 4.6940911330, 7.8547574382, 10.9955407349
//    (roots of cos(bL) cosh(bL) = -1; Blevins, Formulas for Natural Frequency and Mode Shape, 1979,
//    Table 8-1), omega = (beta L)^2 sqrt(E I / (rho A L^4)).
// b) Element convergence, thick simply supported beam: L = 0.6 m, square 0.1 m (L/h = 6), steel,
//    1..64 elements. The Timoshenko element (kappa = 5/6) and the Euler-Bernoulli element, both against
//    the Timoshenko frequency equation k = n pi / L,
//      (kGA k^2 - rho A w^2)(EI k^2 + kGA - rho I w^2) - (kGA k)^2 = 0   (lower root),
//    (Timoshenko 1921; Han, Benaroya and Wei, J. Sound Vib. 225(5), 1999, eq. 61), and each against its
//    own theory (the Euler-Bernoulli element against w = k^2 sqrt(EI / (rho A))).
// c) Craig-Bampton convergence on the free L-frame of tests/condense/test_reduction.cpp: 1..48
//    fixed-interface modes, the first 6 elastic modes against the unreduced model solved densely by
//    Eigen's GeneralizedSelfAdjointEigenSolver; Guyan and a full modal reduction for reference.
//
// The frequencies of (a) and (b) come from the bending sub-problem of the assembled model (nodal DOF
// v, theta_z of every node, as in test_beam_frequencies.cpp: a straight beam decouples exactly into its
// planes), solved densely by Eigen in long double, so that the columns err_n show the discretization
// error down to ~1e-10. `pipeline_diff` is the largest relative difference between those and the
// frequencies condense_component returns (double precision; only bending modes among its lowest ones).
//
// Cost: wall time of condense_component (build, modal reduction with 8 modes or Craig-Bampton / Guyan,
// invariants), minimum over repeated calls in several rounds; backend dense unless --backend says
// otherwise. Every case is also run once with the library default (Spectra): column spectra_check.
// CSV files: DIR/cantilever_euler_bernoulli.csv, thick_beam_timoshenko.csv, craig_bampton_frame.csv;
// bench/plot_convergence.py plots them. See bench/README.md.
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "common/error.hpp"
#include "common/log.hpp"
#include "condense/beam_model.hpp"
#include "condense/component.hpp"
#include "condense/condense.hpp"
#include "condense/eigensolver.hpp"
#include "beam_fixtures.hpp"  // the test models, shared with tests/condense

namespace {

using namespace nvh;
using namespace nvh::condense;
using namespace nvh::condense::testing;



struct Options {
  std::string out_dir = "bench-out";
  double budget = 0.08;  // seconds of repeats per case and round
  int rounds = 3;        // rounds over all cases (min over all repeats of all rounds)
  EigenBackend backend = EigenBackend::kDense;
};

void usage(std::ostream& out) {
  out << "usage: bench_beam_convergence [--out DIR] [--budget S] [--rounds R] [--backend "
         "dense|spectra|arpack]\n"
         "  --out DIR     directory for the CSV files (default bench-out)\n"
         "  --budget S    seconds of repeated calls per case and round (default 0.08; at least 3 calls)\n"
         "  --rounds R    rounds over all cases; the time is the minimum over all calls (default 3)\n"
         "  --backend B   eigen-solver backend of the timed condense_component calls: dense (default),\n"
         "                spectra or arpack (the library solves models of up to 300 DOF densely anyway).\n"
         "                Every case is also run once with spectra (the library default); the\n"
         "                spectra_check column says whether that run passed\n";
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw Error("option " + a + " needs a value");
      return argv[++i];
    };
    if (a == "--out") {
      o.out_dir = value();
    } else if (a == "--budget") {
      o.budget = std::stod(value());
    } else if (a == "--rounds") {
      o.rounds = std::stoi(value());
    } else if (a == "--backend") {
      const std::string b = value();
      o.backend = parse_eigen_backend(b);
    } else if (a == "-h" || a == "--help") {
      usage(std::cout);
      std::exit(0);
    } else {
      throw Error("unknown option " + a);
    }
  }
  if (o.budget < 0.0 || o.rounds < 1) throw Error("--budget must be >= 0 and --rounds >= 1");
  return o;
}

// ------------------------------------------------------------------------------------------------
// Models (the same constructions as tests/condense/beam_fixtures.hpp and test_reduction.cpp).


// ------------------------------------------------------------------------------------------------
// References and helpers.

/// Frequencies (Hz) of the sub-problem on nodal DOF `dofs` of every node with the (node, dof) pairs
/// `held` removed; dense, by Eigen, in long double: in double precision the round-off of the lowest
/// eigenvalue, about eps lambda_max / lambda_1, reaches 1e-8 for the 64-element cantilever (the
/// rotations carry almost no mass) and would hide the discretization error there.
std::vector<double> plane_frequencies(const FeModel& model, const std::vector<int>& dofs,
                                      const std::vector<std::pair<int, int>>& held) {
  using MatrixL = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
  std::vector<int> keep;
  for (int n = 0; n < static_cast<int>(model.nodes.size()); ++n)
    for (int d : dofs)
      if (std::find(held.begin(), held.end(), std::make_pair(n, d)) == held.end()) keep.push_back(6 * n + d);
  const Eigen::MatrixXd K(model.stiffness_all), M(model.mass_all);
  const int m = static_cast<int>(keep.size());
  MatrixL k(m, m), mm(m, m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      k(i, j) = K(keep[i], keep[j]);
      mm(i, j) = M(keep[i], keep[j]);
    }
  Eigen::GeneralizedSelfAdjointEigenSolver<MatrixL> eig(k, mm);
  std::vector<double> f;
  for (int i = 0; i < m; ++i) {
    f.push_back(static_cast<double>(std::sqrt(std::max(eig.eigenvalues()(i), 0.0L)) / (2.0L * kPi)));
  }
  return f;
}



/// Largest relative difference between each bending frequency `plane` and the nearest pipeline
/// frequency, over those bending frequencies that lie within the pipeline's range.
double pipeline_difference(const Eigen::VectorXd& pipeline, const std::vector<double>& plane) {
  double worst = 0.0;
  const double top = pipeline.maxCoeff() * (1.0 + 1e-9);
  for (double f : plane) {
    if (f > top) continue;
    double best = 1e300;
    for (Eigen::Index i = 0; i < pipeline.size(); ++i) best = std::min(best, std::abs(pipeline(i) - f) / f);
    worst = std::max(worst, best);
  }
  return worst;
}

/// condense_component, or nothing (and the message appended to g_failures) if it throws.
std::vector<std::string> g_failures;
std::optional<Superelement> run_once(const Component& c, EigenBackend backend, const Logger& log,
                                     const std::string& label) {
  try {
    return condense_component(c, backend, log);
  } catch (const Error& e) {
    g_failures.push_back(label + " (" + to_string(backend) + "): " + e.what());
    return std::nullopt;
  }
}

/// Run once with the library's default backend (Spectra): "ok" or "failed".
std::string spectra_check(const Component& c, const Logger& log, const std::string& label) {
  return run_once(c, EigenBackend::kSpectra, log, label) ? "ok" : "failed";
}

struct Timing {
  double min_s = 1e300;
  std::vector<double> samples;
  double median_s() const {
    std::vector<double> s = samples;
    std::sort(s.begin(), s.end());
    return s.empty() ? 0.0 : s[s.size() / 2];
  }
};

/// Call `f` at least 3 times and until `budget` seconds have passed; add the samples to `t`.
void time_calls(const std::function<void()>& f, double budget, Timing& t) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  for (int calls = 0;; ++calls) {
    const auto now = clock::now();
    if (calls >= 3 && std::chrono::duration<double>(now - start).count() >= budget) break;
    const auto a = clock::now();
    f();
    const double s = std::chrono::duration<double>(clock::now() - a).count();
    t.samples.push_back(s);
    t.min_s = std::min(t.min_s, s);
  }
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}
std::string err(double v) {
  return fmt("%.4e", v);
}
std::string ms(double seconds) {
  return fmt("%.4g", seconds * 1e3);
}

/// A CSV table, printed and written to DIR/NAME.csv.
struct Table {
  std::string name;
  std::string title;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  std::string csv() const {
    std::ostringstream out;
    auto line = [&](const std::vector<std::string>& cells) {
      for (std::size_t i = 0; i < cells.size(); ++i) out << (i ? "," : "") << cells[i];
      out << "\n";
    };
    line(header);
    for (const auto& r : rows) line(r);
    return out.str();
  }
  void emit(const std::filesystem::path& dir) const {
    std::printf("# %s (%s.csv)\n%s\n", title.c_str(), name.c_str(), csv().c_str());
    const std::filesystem::path file = dir / (name + ".csv");
    std::ofstream out(file);
    out << csv();
    if (!out) throw Error("cannot write " + file.string());
  }
};

const std::vector<int> kElements = {1, 2, 4, 8, 16, 32, 64};
constexpr int kModes = 8;

// ------------------------------------------------------------------------------------------------
// a) Cantilever.

struct BeamCase {
  std::string model;
  int elements = 0;
  Component component;
  std::vector<double> err;      // against the main reference, modes 1-4 (NaN: not in the model)
  std::vector<double> own_err;  // against the model's own theory
  int free_dofs = 0, modes = 0;
  double pipeline_diff = 0.0;
  bool ok = false;      // the run with the chosen backend passed (else: not timed)
  std::string spectra;  // spectra_check
  Timing timing;
};

std::vector<BeamCase> cantilever_cases(const Logger& log, EigenBackend backend) {
  const Steel steel;
  const double L = 1.0;
  BeamSection s = circle(0.01);
  s.rotary_inertia = false;
  const double beta_l[4] = {1.8751040687, 4.6940911330, 7.8547574382, 10.9955407349};
  std::vector<BeamCase> cases;
  for (int n : kElements) {
    BeamCase c;
    c.model = "euler-bernoulli";
    c.elements = n;
    c.component = straight_beam(L, s, n);
    c.component.supports = {fixed({0, 0, 0}, "111111")};
    const FeModel model = build_beam_model(c.component);
    c.free_dofs = model.free_dofs();
    c.modes = std::min(kModes, c.free_dofs);
    c.component.reduction.modes = c.modes;
    const std::vector<double> f = plane_frequencies(model, {1, 5}, {{0, 1}, {0, 5}});
    for (int m = 0; m < 4; ++m) {
      const double ref = beta_l[m] * beta_l[m] / (2.0 * kPi) *
                         std::sqrt(steel.E * s.Iz / (steel.rho * s.A * std::pow(L, 4)));
      c.err.push_back(m < static_cast<int>(f.size()) ? f[m] / ref - 1.0 : std::nan(""));
    }
    c.own_err = c.err;
    const std::string label = "a) cantilever, " + std::to_string(n) + " elements";
    const std::optional<Superelement> se = run_once(c.component, backend, log, label);
    c.ok = se.has_value();
    c.pipeline_diff = se ? pipeline_difference(se->frequency_hz, f) : std::nan("");
    c.spectra =
        backend == EigenBackend::kSpectra ? (c.ok ? "ok" : "failed") : spectra_check(c.component, log, label);
    cases.push_back(std::move(c));
  }
  return cases;
}

// ------------------------------------------------------------------------------------------------
// b) Thick simply supported beam.

std::vector<BeamCase> thick_cases(const Logger& log, EigenBackend backend) {
  const Steel steel;
  const double L = 0.6, h = 0.1;
  const BeamSection timo = rectangle(h, h, 5.0 / 6.0);
  BeamSection eb = rectangle(h, h);
  eb.rotary_inertia = false;
  std::vector<BeamCase> cases;
  for (const bool timoshenko : {true, false}) {
    const BeamSection& s = timoshenko ? timo : eb;
    for (int n : kElements) {
      BeamCase c;
      c.model = timoshenko ? "timoshenko" : "euler-bernoulli";
      c.elements = n;
      c.component = straight_beam(L, s, n);
      // Simply supported in both bending planes; axial motion and torsion held at x = 0.
      c.component.supports = {fixed({0, 0, 0}, "111100"), fixed({L, 0, 0}, "011000")};
      const FeModel model = build_beam_model(c.component);
      c.free_dofs = model.free_dofs();
      c.modes = std::min(kModes, c.free_dofs);
      c.component.reduction.modes = c.modes;
      const std::vector<double> f = plane_frequencies(model, {1, 5}, {{0, 1}, {n, 1}});
      for (int m = 0; m < 4; ++m) {
        const bool have = m < static_cast<int>(f.size());
        const double ref = timoshenko_ss_hz(m + 1, L, timo, steel);
        const double own = timoshenko ? ref : euler_bernoulli_ss_hz(m + 1, L, eb, steel);
        c.err.push_back(have ? f[m] / ref - 1.0 : std::nan(""));
        c.own_err.push_back(have ? f[m] / own - 1.0 : std::nan(""));
      }
      const std::string label = "b) " + c.model + ", " + std::to_string(n) + " elements";
      const std::optional<Superelement> se = run_once(c.component, backend, log, label);
      c.ok = se.has_value();
      c.pipeline_diff = se ? pipeline_difference(se->frequency_hz, f) : std::nan("");
      c.spectra = backend == EigenBackend::kSpectra ? (c.ok ? "ok" : "failed")
                                                    : spectra_check(c.component, log, label);
      cases.push_back(std::move(c));
    }
  }
  return cases;
}

Table beam_table(const std::string& name, const std::string& title, const std::vector<BeamCase>& cases,
                 bool with_own, EigenBackend backend) {
  Table t{name,
          title,
          {"model", "elements", "free_dof", "modes", "solver", "t_min_ms", "t_median_ms", "calls"},
          {}};
  for (int m = 1; m <= 4; ++m) t.header.push_back("err_" + std::to_string(m));
  if (with_own)
    for (int m = 1; m <= 4; ++m) t.header.push_back("own_err_" + std::to_string(m));
  t.header.push_back("pipeline_diff");
  t.header.push_back("spectra_check");
  for (const BeamCase& c : cases) {
    std::vector<std::string> r = {
        c.model,
        std::to_string(c.elements),
        std::to_string(c.free_dofs),
        std::to_string(c.modes),
        c.free_dofs <= 300 || backend == EigenBackend::kDense ? "dense" : to_string(backend),
        c.ok ? ms(c.timing.min_s) : "",
        c.ok ? ms(c.timing.median_s()) : "",
        std::to_string(c.timing.samples.size())};
    for (double e : c.err) r.push_back(std::isnan(e) ? "" : err(e));
    if (with_own)
      for (double e : c.own_err) r.push_back(std::isnan(e) ? "" : err(e));
    r.push_back(std::isnan(c.pipeline_diff) ? "" : err(c.pipeline_diff));
    r.push_back(c.spectra);
    t.rows.push_back(r);
  }
  return t;
}

// ------------------------------------------------------------------------------------------------
// c) Craig-Bampton on the L-frame.

struct ReductionCase {
  std::string method;
  int fixed_modes = 0;
  Component component;
  int basis = 0, coordinates = 0;
  double cutoff_ratio = 0.0;  // highest fixed-interface frequency / 6th elastic frequency
  std::vector<double> err;
  bool ok = false;
  std::string spectra;
  Timing timing;
};

std::vector<ReductionCase> frame_cases(const Logger& log, EigenBackend backend, int& free_dofs) {
  const Component base = frame();
  const FeModel model = build_beam_model(base);
  free_dofs = model.free_dofs();
  const Eigen::MatrixXd K(model.stiffness()), M(model.mass());
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(K, M);
  const Eigen::VectorXd ref = eig.eigenvalues().tail(K.rows() - 6).cwiseMax(0.0).cwiseSqrt() / (2.0 * kPi);

  std::vector<ReductionCase> cases;
  auto add = [&](const std::string& method, ReductionMethod m, int fixed_modes) {
    ReductionCase c;
    c.method = method;
    c.fixed_modes = fixed_modes;
    c.component = base;
    c.component.reduction.method = m;
    c.component.reduction.modes = m == ReductionMethod::kModal ? 6 : fixed_modes;
    const std::string label = "c) " + method + ", " + std::to_string(fixed_modes) + " fixed-interface modes";
    const std::optional<Superelement> se = run_once(c.component, backend, log, label);
    c.ok = se.has_value();
    c.basis = m == ReductionMethod::kModal ? 6 : 12 + fixed_modes;
    if (se) {
      c.coordinates = se->size();
      if (se->fixed_interface_hz.size() > 0) c.cutoff_ratio = se->fixed_interface_hz.maxCoeff() / ref(5);
      for (int i = 0; i < 6; ++i) c.err.push_back(se->frequency_hz(i) / ref(i) - 1.0);
    } else {
      c.err.assign(6, std::nan(""));
    }
    c.spectra =
        backend == EigenBackend::kSpectra ? (c.ok ? "ok" : "failed") : spectra_check(c.component, log, label);
    cases.push_back(std::move(c));
  };
  add("guyan", ReductionMethod::kGuyan, 0);
  for (int m : {1, 2, 4, 8, 12, 16, 20, 24, 32, 48}) add("craig-bampton", ReductionMethod::kCraigBampton, m);
  add("modal", ReductionMethod::kModal, 0);
  return cases;
}

Table frame_table(const std::vector<ReductionCase>& cases, int free_dofs) {
  Table t{"craig_bampton_frame",
          "c) L-frame (" + std::to_string(free_dofs) +
              " free DOF, 12 interface DOF): first 6 elastic modes against the unreduced dense solve",
          {"method", "fixed_interface_modes", "basis_size", "coordinates", "cutoff_ratio", "t_min_ms",
           "t_median_ms", "calls", "max_err"},
          {}};
  for (int m = 1; m <= 6; ++m) t.header.push_back("err_" + std::to_string(m));
  t.header.push_back("spectra_check");
  for (const ReductionCase& c : cases) {
    double worst = 0.0;
    for (double e : c.err) worst = std::max(worst, std::abs(e));
    std::vector<std::string> r = {c.method,
                                  std::to_string(c.fixed_modes),
                                  std::to_string(c.basis),
                                  c.ok ? std::to_string(c.coordinates) : "",
                                  c.cutoff_ratio > 0 ? fmt("%.3f", c.cutoff_ratio) : "",
                                  c.ok ? ms(c.timing.min_s) : "",
                                  c.ok ? ms(c.timing.median_s()) : "",
                                  std::to_string(c.timing.samples.size()),
                                  c.ok ? err(worst) : ""};
    for (double e : c.err) r.push_back(std::isnan(e) ? "" : err(e));
    r.push_back(c.spectra);
    t.rows.push_back(r);
  }
  return t;
}

/// Observed order of convergence log2(e(N/2) / e(N)) of mode `m` at the finest pair of meshes where
/// both errors lie above 2e-10 (the long-double solve and the 11 digits of beta_n L are good to ~1e-10).
std::string observed_order(const std::vector<BeamCase>& cases, const std::string& model, int m) {
  double order = std::nan("");
  int at = 0;
  for (std::size_t i = 1; i < cases.size(); ++i) {
    const BeamCase &a = cases[i - 1], &b = cases[i];
    if (a.model != model || b.model != model || b.elements != 2 * a.elements) continue;
    const double ea = std::abs(a.own_err[m]), eb = std::abs(b.own_err[m]);
    if (std::isnan(ea) || std::isnan(eb) || eb < 2e-10) continue;
    order = std::log2(ea / eb);
    at = b.elements;
  }
  return std::isnan(order)
             ? "n/a"
             : fmt("%.2f", order) + " (" + std::to_string(at / 2) + "->" + std::to_string(at) + ")";
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    const Logger log(std::cerr, "bench", Verbosity::kQuiet);
    const auto start = std::chrono::steady_clock::now();
    std::filesystem::create_directories(o.out_dir);

    std::vector<BeamCase> cantilever = cantilever_cases(log, o.backend);
    std::vector<BeamCase> thick = thick_cases(log, o.backend);
    int frame_dofs = 0;
    std::vector<ReductionCase> reductions = frame_cases(log, o.backend, frame_dofs);

    // Timing: `rounds` passes over all cases, so that a transient load does not hit one case only.
    for (int round = 0; round < o.rounds; ++round) {
      for (BeamCase& c : cantilever)
        if (c.ok) time_calls([&] { condense_component(c.component, o.backend, log); }, o.budget, c.timing);
      for (BeamCase& c : thick)
        if (c.ok) time_calls([&] { condense_component(c.component, o.backend, log); }, o.budget, c.timing);
      for (ReductionCase& c : reductions)
        if (c.ok) time_calls([&] { condense_component(c.component, o.backend, log); }, o.budget, c.timing);
    }

    std::printf(
        "bench_beam_convergence: condense_component wall time (build + reduce + invariants), "
        "minimum over all calls; backend %s\n"
        "errors: f / f_ref - 1 (signed); empty: the model has fewer modes\n\n",
        to_string(o.backend).c_str());
    beam_table("cantilever_euler_bernoulli",
               "a) cantilever L = 1 m, d = 10 mm, Euler-Bernoulli element; err_n against beta_n L",
               cantilever, false, o.backend)
        .emit(o.out_dir);
    beam_table("thick_beam_timoshenko",
               "b) simply supported L = 0.6 m, square 0.1 m (L/h = 6); err_n against the Timoshenko "
               "equation (kappa 5/6), own_err_n against the model's own theory",
               thick, true, o.backend)
        .emit(o.out_dir);
    frame_table(reductions, frame_dofs).emit(o.out_dir);

    std::printf("observed order of convergence, log2(e(N/2)/e(N)), modes 1..4:\n");
    for (const auto& [label, cases, model] :
         {std::tuple<std::string, const std::vector<BeamCase>*, std::string>{"  a) cantilever, E-B",
                                                                             &cantilever, "euler-bernoulli"},
          {"  b) thick, Timoshenko", &thick, "timoshenko"},
          {"  b) thick, E-B (vs E-B theory)", &thick, "euler-bernoulli"}}) {
      std::printf("%-34s", label.c_str());
      for (int m = 0; m < 4; ++m) std::printf("  %s", observed_order(*cases, model, m).c_str());
      std::printf("\n");
    }
    std::printf("condense_component failures (backend in brackets; failed runs are not timed): %s\n",
                g_failures.empty() ? "none" : "");
    for (const std::string& f : g_failures) std::printf("  %s\n", f.c_str());
    std::printf("total run time %.1f s; CSV files in %s\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                o.out_dir.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "bench_beam_convergence: " << e.what() << "\n";
    return 1;
  }
}
