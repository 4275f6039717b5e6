#include "solve/bearing/slider.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/error.hpp"

namespace nvh::bearing {

namespace {
[[noreturn]] void bad(const SliderSpec& s, const std::string& field, const std::string& expected) {
  throw Error("slider '" + s.name + "': '" + field + "': expected " + expected);
}
}  // namespace

void validate(const SliderSpec& s) {
  if (!(s.length > 0)) bad(s, "length", "a number > 0 (m)");
  if (!(s.film_inlet > 0)) bad(s, "film_inlet", "a number > 0 (m)");
  if (!(s.film_outlet > 0)) bad(s, "film_outlet", "a number > 0 (m)");
  if (!(s.viscosity > 0)) bad(s, "viscosity", "a number > 0 (Pa s)");
  if (!(s.barus >= 0)) bad(s, "barus", "a number >= 0 (1/Pa)");
  if (!std::isfinite(s.speed)) bad(s, "speed", "a finite number (m/s)");
  if (!(s.pressure_inlet >= 0)) bad(s, "pressure_inlet", "a number >= 0 (Pa, gauge)");
  if (!(s.pressure_outlet >= 0)) bad(s, "pressure_outlet", "a number >= 0 (Pa, gauge)");
  if (s.cells < 2) bad(s, "cells", "an integer >= 2");
  for (std::size_t k = 0; k < s.pockets.size(); ++k) {
    const Pocket& p = s.pockets[k];
    const std::string f = "pockets[" + std::to_string(k) + "]";
    if (!(p.start >= 0 && p.end > p.start && p.end <= s.length)) bad(s, f, "0 <= start < end <= length (m)");
    if (!(p.depth > 0)) bad(s, f + ".depth", "a number > 0 (m)");
  }
}

double slider_film(const SliderSpec& s, double x, int side) {
  double h = s.film_inlet + (s.film_outlet - s.film_inlet) * x / s.length;
  for (const Pocket& p : s.pockets) {
    const bool inside = side < 0   ? (x > p.start && x <= p.end)
                        : side > 0 ? (x >= p.start && x < p.end)
                                   : (x >= p.start && x <= p.end);
    if (inside) h += p.depth;
  }
  return h;
}

// Nondimensional variables: X = x / L, H = h / h_ref (h_ref: the smaller end film), P = p / p_ref with
// p_ref = 12 mu L U_ref / h_ref^2, U_ref = |U| / 2 (or the pressure-driven scale without sliding). The
// equation becomes d/dX (H^3 / mu_r dP/dX) = C d(theta_f H)/dX with C = (U / 2) / U_ref, and a flux of 1
// is U_ref h_ref (m^2/s).
SliderResult solve_slider(const SliderSpec& spec_in, const FiniteSolverOptions& options) {
  validate(spec_in);
  const int n = spec_in.cells;
  const double L = spec_in.length, mu = spec_in.viscosity, dx = L / n;
  // Pocket edges within round-off of a face are put exactly on it (the faces are at k dx), so that the
  // step is seen on that face and not half on either side.
  SliderSpec spec = spec_in;
  for (Pocket& p : spec.pockets) {
    for (double* x : {&p.start, &p.end}) {
      const double k = std::round(*x / dx);
      if (std::abs(*x - k * dx) < 1e-9 * dx) *x = k * dx;
    }
  }
  const double h_ref = std::min(spec.film_inlet, spec.film_outlet);
  const double Um = 0.5 * spec.speed;
  const double p_scale = std::max(spec.pressure_inlet, spec.pressure_outlet) * h_ref * h_ref / (12 * mu * L);
  const double U_ref = std::max({std::abs(Um), p_scale, 1e-300});
  const double p_ref = 12 * mu * L * U_ref / (h_ref * h_ref);

  FilmSolver film;
  FilmProblem& f = film.problem;
  f.nx = n, f.nz = 1, f.dx = 1.0 / n, f.dz = 1;
  f.periodic_x = false;
  f.z_edges = false;
  f.supply.assign(n, 0);
  f.cavitation = spec.cavitation;
  f.couette = Um / U_ref;
  f.barus = spec.barus * p_ref;
  f.p_west = spec.pressure_inlet / p_ref;
  f.p_east = spec.pressure_outlet / p_ref;
  // Face films: h(x_face) where h is continuous; at a step the values that make a piecewise-linear full
  // film's flux exact (slider.hpp).
  auto face = [&](double x, double& G, double& H) {
    const double hm = slider_film(spec, x, -1) / h_ref, hp = slider_film(spec, x, +1) / h_ref;
    if (hm == hp) {
      G = hm * hm * hm, H = hm;
    } else {
      const double s3 = 1 / (hm * hm * hm) + 1 / (hp * hp * hp), s2 = 1 / (hm * hm) + 1 / (hp * hp);
      G = 2 / s3, H = s2 / s3;
    }
  };
  f.g_east.resize(n), f.h_east.resize(n), f.h_centre.resize(n), f.hdot.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    face((i + 1) * dx, f.g_east[i], f.h_east[i]);
    f.h_centre[i] = slider_film(spec, (i + 0.5) * dx) / h_ref;
  }
  f.h_west = slider_film(spec, 0, +1) / h_ref;
  f.g_west = f.h_west * f.h_west * f.h_west;
  f.h_east[n - 1] = slider_film(spec, L, -1) / h_ref;  // the east end: the film just inside
  f.g_east[n - 1] = f.h_east[n - 1] * f.h_east[n - 1] * f.h_east[n - 1];

  // Swift-Stieber: inside a cavitated run of constant film the mass source is zero, so the active set of
  // the clipped cold start shrinks by about one cell per step; a 1D step is cheap, so allow one per cell.
  FiniteSolverOptions o = options;
  o.active_set_iterations = std::max(options.active_set_iterations, n);
  o.max_iterations = std::max(options.max_iterations, o.active_set_iterations + 60);
  Eigen::VectorXd P, r;
  film.cold_start(P, r);
  const int iterations = film.solve(P, r, o);
  if (iterations < 0) {
    std::ostringstream msg;
    msg << "slider '" << spec.name << "': the Newton solve did not converge in " << -iterations
        << " iterations; try another grid or check the input";
    throw Error(msg.str());
  }
  FilmAssembly a;
  film.assemble(P, r, false, a);

  SliderResult out;
  out.iterations = iterations;
  out.x.resize(n), out.film.resize(n), out.pressure.resize(n), out.fill_ratio.resize(n);
  for (int i = 0; i < n; ++i) {
    out.x[i] = (i + 0.5) * dx;
    out.film[i] = h_ref * f.h_centre[i];
    out.pressure[i] = p_ref * P[i];
    out.fill_ratio[i] = spec.cavitation == Cavitation::kJfo ? 1 - r[i] : 1.0;
  }
  out.load = out.pressure.sum() * dx;
  // Face pressures from flux continuity (isoviscous): -h_-^3 (p_f - p_i) / (12 mu dx/2) + Um h_- equals
  // -h_+^3 (p_j - p_f) / (12 mu dx/2) + Um h_+. Next to a cavitated cell: the mean of the two cells.
  out.face_pressure.resize(n + 1);
  out.face_pressure[0] = spec.pressure_inlet;
  out.face_pressure[n] = spec.pressure_outlet;
  for (int i = 0; i + 1 < n; ++i) {
    const double pi = out.pressure[i], pj = out.pressure[i + 1];
    double pf = 0.5 * (pi + pj);
    if (pi > 0 && pj > 0) {
      const double hm = slider_film(spec, (i + 1) * dx, -1), hp = slider_film(spec, (i + 1) * dx, +1);
      const double am = hm * hm * hm, ap = hp * hp * hp;
      pf = (am * pi + ap * pj + 12 * mu * 0.5 * dx * Um * (hm - hp)) / (am + ap);
    }
    out.face_pressure[i + 1] = std::max(pf, 0.0);
  }
  out.max_pressure = -1;
  for (int i = 0; i < n; ++i)
    if (out.pressure[i] > out.max_pressure)
      out.max_pressure = out.pressure[i], out.max_pressure_position = out.x[i];
  for (int i = 0; i <= n; ++i)
    if (out.face_pressure[i] > out.max_pressure)
      out.max_pressure = out.face_pressure[i], out.max_pressure_position = i * dx;
  const double flow_scale = U_ref * h_ref;
  out.flow_at_start = flow_scale * a.west_flow;
  out.flow_at_end = flow_scale * a.east_flow;
  return out;
}

}  // namespace nvh::bearing
