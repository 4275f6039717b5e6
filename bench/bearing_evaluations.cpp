// Evaluations per second of the journal-bearing models (solve/bearing), the cost of each level of fidelity.
//
// A journal runs on a circular orbit at eps = 0.6 +- 0.1 (one film evaluation per time step, 360 steps per
// orbit, as an integrator would call it). Warm: the finite bearing starts each Newton solve from the last
// solution. Cold: it forgets it (reset) before every call. The short bearing (closed form) is the yardstick:
// the ratio column says how many short-bearing evaluations one finite evaluation costs.
//
//   build/bench/bench_bearing_evaluations [seconds per case, default 2] [AROUNDxACROSS ...: the finite grids,
//                                                                     default 60x20 180x40]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <numbers>
#include <utility>
#include <vector>

#include "solve/bearing/finite_bearing.hpp"
#include "solve/bearing/short_bearing.hpp"

using namespace nvh::bearing;

namespace {

BearingSpec spec(Model model, int around, int across) {
  BearingSpec s;
  s.model = model;
  s.diameter = 0.055;
  s.width = 0.024;
  s.radial_clearance = 30e-6;
  s.viscosity = 0.008;
  s.supply_pressure = 3e5;
  s.cavitation = Cavitation::kJfo;
  s.holes.push_back({std::numbers::pi / 2, 0.0, 0.005});
  s.cells_around = around;
  s.cells_across = across;
  return s;
}

Kinematics orbit_point(int step, double c) {
  const double a = 2 * std::numbers::pi * step / 360.0;
  const double eps = 0.6 + 0.1 * std::sin(3 * a);
  Kinematics k;
  k.e = eps * c * Eigen::Vector2d(std::cos(a), std::sin(a));
  const double rate = 2 * std::numbers::pi * 50;  // orbit at 50 Hz, journal at 3000 rpm
  k.e_dot = rate * Eigen::Vector2d(-k.e.y(), k.e.x()) * 0.1;
  k.omega_journal = 2 * std::numbers::pi * 50;
  return k;
}

// Evaluations per second of CPU time (process CPU: robust on a shared machine) and of wall time.
struct Rate {
  double cpu, wall;
};
template <typename F>
Rate per_second(F&& evaluate, double seconds) {
  int n = 0;
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  double elapsed = 0;
  do {
    evaluate(n++);
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } while (elapsed < seconds && n < 1000000);
  const double cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
  return {n / std::max(cpu, 1e-9), n / elapsed};
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 2.0;
  const BearingSpec s_short = spec(Model::kShort, 60, 20);
  const double c = s_short.radial_clearance;
  const Rate short_rate = per_second([&](int i) { evaluate_short(s_short, orbit_point(i, c)); }, seconds);
  std::printf("%-44s %12s %12s %12s %10s\n", "model", "evals/s CPU", "ms/eval CPU", "evals/s wall",
              "cost/short");
  std::printf("%-44s %12.0f %12.4f %12.0f %10.0f\n", "short (Ocvirk, closed form)", short_rate.cpu,
              1e3 / short_rate.cpu, short_rate.wall, 1.0);
  std::vector<std::pair<int, int>> grids;
  for (int a = 2; a < argc; ++a) {
    int around = 0, across = 0;
    if (std::sscanf(argv[a], "%dx%d", &around, &across) == 2 && around > 2 && across > 0)
      grids.emplace_back(around, across);
  }
  if (grids.empty()) grids = {{60, 20}, {180, 40}};
  for (auto [around, across] : grids) {
    for (bool warm : {true, false}) {
      FiniteBearing b(spec(Model::kFinite, around, across));
      int iterations = 0, calls = 0;
      const Rate rate = per_second(
          [&](int i) {
            if (!warm) b.reset();
            iterations += b.evaluate(orbit_point(i, c)).iterations;
            ++calls;
          },
          seconds);
      char name[64];
      std::snprintf(name, sizeof name, "finite JFO %dx%d %s (%.2f Newton/eval)", around, across,
                    warm ? "warm" : "cold", double(iterations) / calls);
      std::printf("%-44s %12.1f %12.3f %12.1f %10.0f\n", name, rate.cpu, 1e3 / rate.cpu, rate.wall,
                  short_rate.cpu / rate.cpu);
    }
  }
  return 0;
}
