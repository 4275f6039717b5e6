#include "solve/bearing/skirt_film.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

#include "common/error.hpp"

namespace nvh::bearing {

namespace {
constexpr double kPi = std::numbers::pi;

[[noreturn]] void bad(const SkirtSpec& s, const std::string& field, const std::string& expected) {
  throw Error("skirt '" + s.name + "': '" + field + "': expected " + expected);
}

void check_table(const SkirtSpec& s, const ProfileTable& t, const std::string& name, bool angles) {
  if (t.at.size() != t.value.size()) bad(s, name, "as many values as positions");
  for (std::size_t j = 0; j < t.at.size(); ++j) {
    if (!std::isfinite(t.at[j]) || !std::isfinite(t.value[j])) bad(s, name, "finite numbers (m)");
    if (j > 0 && !(t.at[j] > t.at[j - 1])) bad(s, name + ".at", "strictly ascending positions");
  }
  if (angles && !t.at.empty() && !(t.at.back() - t.at.front() < 2 * kPi))
    bad(s, name + ".at", "angles spanning less than 2 pi (the table is periodic)");
}

/// The barrel table at y: linear, held constant beyond its ends; 0 if empty.
double barrel_at(const ProfileTable& t, double y) {
  if (t.at.empty()) return 0;
  if (y <= t.at.front()) return t.value.front();
  if (y >= t.at.back()) return t.value.back();
  const std::size_t j = std::upper_bound(t.at.begin(), t.at.end(), y) - t.at.begin();
  const double s = (y - t.at[j - 1]) / (t.at[j] - t.at[j - 1]);
  return t.value[j - 1] + s * (t.value[j] - t.value[j - 1]);
}

/// The ovality table at theta: linear, periodic (the last point joins the first + 2 pi); 0 if empty.
double ovality_at(const ProfileTable& t, double theta) {
  if (t.at.empty()) return 0;
  if (t.at.size() == 1) return t.value.front();
  const double a0 = t.at.front();
  const double a = a0 + (theta - a0) - 2 * kPi * std::floor((theta - a0) / (2 * kPi));  // in [a0, a0 + 2 pi)
  if (a >= t.at.back()) {
    const double s = (a - t.at.back()) / (a0 + 2 * kPi - t.at.back());
    return t.value.back() + s * (t.value.front() - t.value.back());
  }
  const std::size_t j = std::upper_bound(t.at.begin(), t.at.end(), a) - t.at.begin();
  const double s = (a - t.at[j - 1]) / (t.at[j] - t.at[j - 1]);
  return t.value[j - 1] + s * (t.value[j] - t.value[j - 1]);
}

bool full_circle(const SkirtArc& a) {
  return std::abs(a.end - a.start - 2 * kPi) <= 1e-12 * 2 * kPi;
}
}  // namespace

void validate(const SkirtSpec& s) {
  auto positive = [&](double v, const char* field, const char* unit) {
    if (!(v > 0 && std::isfinite(v))) bad(s, field, std::string("a finite number > 0 (") + unit + ")");
  };
  positive(s.bore_radius, "bore_radius", "m");
  positive(s.radial_clearance, "radial_clearance", "m");
  if (!(s.radial_clearance < s.bore_radius)) bad(s, "radial_clearance", "less than bore_radius");
  positive(s.skirt_length, "skirt_length", "m");
  if (!std::isfinite(s.skirt_top)) bad(s, "skirt_top", "a finite number (m)");
  positive(s.viscosity, "viscosity", "Pa s");
  if (!(s.fill_bottom >= 0 && s.fill_bottom <= 1)) bad(s, "fill_bottom", "a number in [0, 1]");
  if (!(s.fill_top >= 0 && s.fill_top <= 1)) bad(s, "fill_top", "a number in [0, 1]");
  if (!(s.pressure_bottom >= 0 && std::isfinite(s.pressure_bottom)))
    bad(s, "pressure_bottom", "a finite number >= 0 (Pa, gauge)");
  if (!(s.pressure_top >= 0 && std::isfinite(s.pressure_top)))
    bad(s, "pressure_top", "a finite number >= 0 (Pa, gauge)");
  if (s.cells_axial < 2 || s.cells_axial > kMaxCellsPerDirection)
    bad(s, "cells_axial", "an integer in [2, " + std::to_string(kMaxCellsPerDirection) + "]");
  if (s.cells_around < 3 || s.cells_around > kMaxCellsPerDirection)
    bad(s, "cells_around", "an integer in [3, " + std::to_string(kMaxCellsPerDirection) + "]");
  if (std::int64_t(s.cells_axial) * s.cells_around * std::int64_t(std::max<std::size_t>(1, s.arcs.size())) >
      kMaxCells)
    bad(s, "cells_axial", "at most " + std::to_string(kMaxCells) + " cells in all arcs");
  if (s.arcs.empty()) bad(s, "arcs", "at least one arc");
  // Arcs: each in (0, 2 pi], a full circle alone, no two overlapping (start mod 2 pi, sorted).
  std::vector<std::pair<double, double>> spans;
  for (std::size_t j = 0; j < s.arcs.size(); ++j) {
    const SkirtArc& a = s.arcs[j];
    const std::string f = "arcs[" + std::to_string(j) + "]";
    const double width = a.end - a.start;
    if (!std::isfinite(a.start) || !std::isfinite(a.end) || !(width > 0) ||
        !(width <= 2 * kPi || full_circle(a)))
      bad(s, f, "finite angles with 0 < end - start <= 2 pi (rad)");
    if (full_circle(a) && s.arcs.size() > 1) bad(s, f, "no other arc with a full circle");
    const double start = a.start - 2 * kPi * std::floor(a.start / (2 * kPi));
    spans.emplace_back(start, start + width);
  }
  std::sort(spans.begin(), spans.end());
  const double slack = 1e-12;
  for (std::size_t j = 0; j < spans.size(); ++j) {
    const double next = j + 1 < spans.size() ? spans[j + 1].first : spans[0].first + 2 * kPi;
    if (spans.size() > 1 && spans[j].second > next + slack) bad(s, "arcs", "arcs that do not overlap");
  }
  check_table(s, s.barrel, "barrel", false);
  check_table(s, s.ovality, "ovality", true);
  if (!(s.film_floor >= 0 && s.film_floor < s.radial_clearance))
    bad(s, "film_floor", "a number in [0, radial_clearance) (m)");
  if (!(s.oil_layer >= 0 && std::isfinite(s.oil_layer))) bad(s, "oil_layer", "a finite number >= 0 (m)");
  if (s.asperity.sigma != 0) {
    if (!(s.asperity.sigma > 0 && std::isfinite(s.asperity.sigma)))
      bad(s, "sigma", "a finite number >= 0 (m)");
    if (!(s.asperity.K > 0 && std::isfinite(s.asperity.K))) bad(s, "K", "a finite number > 0");
    if (!(s.asperity.modulus > 0 && std::isfinite(s.asperity.modulus)))
      bad(s, "modulus", "a finite number > 0 (Pa)");
  }
}

double oil_layer_squeeze_factor(double h, double oil_layer) {
  if (!(oil_layer > 0)) return 1.0;
  const double x = (h - oil_layer) / (oil_layer / 8), ex = std::exp(-std::abs(x));
  return x >= 0 ? ex / (1 + ex) : 1 / (1 + ex);
}

EffectiveFilm effective_film(double h, double film_floor) {
  if (!(film_floor > 0)) return {h, 1.0};
  // h_f (1 + softplus(x)), x = (h - h_f) / h_f, softplus(x) = max(x, 0) + log1p(exp(-|x|)) (no overflow)
  const double x = (h - film_floor) / film_floor, ex = std::exp(-std::abs(x));
  const double softplus = std::max(x, 0.0) + std::log1p(ex);
  const double sigmoid = x >= 0 ? 1 / (1 + ex) : ex / (1 + ex);
  return {film_floor * (1 + softplus), sigmoid};
}

double skirt_film_thickness(const SkirtSpec& s, const SkirtKinematics& k, double theta, double y) {
  const double y_bottom = s.skirt_top - s.skirt_length;
  const double e = k.e_bottom + (k.e_top - k.e_bottom) * (y - y_bottom) / s.skirt_length;
  return s.radial_clearance - e * std::cos(theta) + barrel_at(s.barrel, y) + ovality_at(s.ovality, theta);
}

SkirtFilm::SkirtFilm(SkirtSpec spec, FiniteSolverOptions options)
    : spec_(std::move(spec)), options_(options) {
  validate(spec_);
  nx_ = spec_.cells_axial;
  nz_ = spec_.cells_around;
  dy_ = spec_.skirt_length / nx_;
  const double R = spec_.bore_radius, y_bottom = spec_.skirt_top - spec_.skirt_length;
  y_c_.resize(nx_), barrel_c_.resize(nx_), y_f_.resize(nx_ + 1), barrel_f_.resize(nx_ + 1);
  for (int i = 0; i < nx_; ++i)
    y_c_[i] = y_bottom + (i + 0.5) * dy_, barrel_c_[i] = barrel_at(spec_.barrel, y_c_[i]);
  for (int i = 0; i <= nx_; ++i)
    y_f_[i] = y_bottom + i * dy_, barrel_f_[i] = barrel_at(spec_.barrel, y_f_[i]);
  y_lattice_.resize(2 * nx_ + 1), barrel_lattice_.resize(2 * nx_ + 1);
  for (int i = 0; i <= 2 * nx_; ++i)
    y_lattice_[i] = y_bottom + 0.5 * i * dy_,
    barrel_lattice_[i] = i % 2 ? barrel_c_[i / 2] : barrel_f_[i / 2];
  const int n = nx_ * nz_;
  const double c0 = spec_.radial_clearance;
  for (const SkirtArc& a : spec_.arcs) {
    Arc arc;
    arc.full = full_circle(a);
    arc.start = a.start;
    arc.width = arc.full ? 2 * kPi : a.end - a.start;
    const double dtheta = arc.width / nz_;
    arc.cos_c.resize(nz_), arc.sin_c.resize(nz_), arc.ovality_c.resize(nz_);
    arc.cos_f.resize(nz_ + 1), arc.ovality_f.resize(nz_ + 1);
    for (int k = 0; k < nz_; ++k) {
      const double t = arc.start + (k + 0.5) * dtheta;
      arc.cos_c[k] = std::cos(t), arc.sin_c[k] = std::sin(t), arc.ovality_c[k] = ovality_at(spec_.ovality, t);
    }
    for (int k = 0; k <= nz_; ++k) {
      const double t = arc.start + k * dtheta;
      arc.cos_f[k] = std::cos(t), arc.ovality_f[k] = ovality_at(spec_.ovality, t);
    }
    FilmProblem& f = arc.film.problem;
    f.nx = nx_, f.nz = nz_, f.dx = dy_ / R, f.dz = dtheta;
    f.periodic_x = false;
    f.z_edges = !arc.full;
    f.periodic_z = arc.full;
    f.supply.assign(n, 0);
    f.cavitation = spec_.cavitation;
    f.fill_west = spec_.fill_bottom;
    f.fill_east = spec_.fill_top;
    f.closing_film_full = true;
    for (auto* v : {&f.g_east_cells, &f.h_east_cells, &f.g_north_cells, &f.h_centre_cells, &f.hdot_cells})
      v->assign(n, 0.0);
    f.g_west_rows.assign(nz_, 0.0), f.h_west_rows.assign(nz_, 0.0);
    arc.P = Eigen::VectorXd::Zero(n);
    arc.r = Eigen::VectorXd::Zero(n);
    arc.h_nominal.assign(n, c0);
    arcs_.push_back(std::move(arc));
  }
}

// The film's coefficients for this motion (nondimensional, see the header): the exact film at each face for
// the conductance H^3 and the Couette film, at the centres for the edges and the squeeze.
void SkirtFilm::set_motion(const SkirtKinematics& k, bool hold_scale) {
  const double c = spec_.radial_clearance, R = spec_.bore_radius, mu = spec_.viscosity,
               L = spec_.skirt_length;
  const double U = -0.5 * k.speed;  // mean surface speed along y in the piston's frame (the liner at -V)
  double e_rate = std::max(std::abs(k.e_top_dot), std::abs(k.e_bottom_dot));
  if (liner_)  // the liner's squeeze rate enters the time scale as the piston's does
    for (const auto& rate : liner_->rate)
      for (double r : rate) e_rate = std::max(e_rate, std::abs(r));
  const double p_scale = std::max(spec_.pressure_bottom, spec_.pressure_top) * c * c / (12 * mu * R * R);
  if (!hold_scale) {
    omega_ref_ = std::max({std::abs(U) / R, e_rate / c, p_scale, 1e-9});
    p_ref_ = 12 * mu * R * R * omega_ref_ / (c * c);
  }
  const double y_bottom = y_f_[0];
  auto e_at = [&](double y) { return k.e_bottom + (k.e_top - k.e_bottom) * (y - y_bottom) / L; };
  auto e_dot_at = [&](double y) {
    return k.e_bottom_dot + (k.e_top_dot - k.e_bottom_dot) * (y - y_bottom) / L;
  };
  // H = h_eff / c: the nominal film itself without a floor
  auto eff = [&](double h) { return effective_film(h, spec_.film_floor).h / c; };
  for (int a = 0; a < static_cast<int>(arcs_.size()); ++a) {
    Arc& arc = arcs_[a];
    FilmProblem& f = arc.film.problem;
    f.couette = U / (R * omega_ref_);
    f.p_west = spec_.pressure_bottom / p_ref_;
    f.p_east = spec_.pressure_top / p_ref_;
    for (int kz = 0; kz < nz_; ++kz) {
      const double cos_c = arc.cos_c[kz], cos_n = arc.cos_f[kz + 1];
      const double ov_c = arc.ovality_c[kz], ov_n = arc.ovality_f[kz + 1];
      for (int i = 0; i < nx_; ++i) {
        const int m = i + nx_ * kz;
        const double e_c = e_at(y_c_[i]), e_e = e_at(y_f_[i + 1]);
        // the liner's displacement (LinerField: 0 on a rigid liner) at the centre, east and north faces
        const double hc = c - e_c * cos_c + barrel_c_[i] + ov_c + liner_u(a, 2 * i + 1, 2 * kz + 1);
        arc.h_nominal[m] = hc;
        const double Hc = eff(hc);
        const double He = eff(c - e_e * cos_c + barrel_f_[i + 1] + ov_c + liner_u(a, 2 * i + 2, 2 * kz + 1));
        const double Hn = eff(c - e_c * cos_n + barrel_c_[i] + ov_n + liner_u(a, 2 * i + 1, 2 * kz + 2));
        f.h_centre_cells[m] = Hc;
        f.h_east_cells[m] = He;
        f.g_east_cells[m] = He * He * He;
        f.g_north_cells[m] = Hn * Hn * Hn;
        f.hdot_cells[m] = (-e_dot_at(y_c_[i]) * cos_c + liner_rate(a, m)) / (c * omega_ref_) *
                          oil_layer_squeeze_factor(hc, spec_.oil_layer);
      }
      const double Hw = eff(c - e_at(y_f_[0]) * cos_c + barrel_f_[0] + ov_c + liner_u(a, 0, 2 * kz + 1));
      f.h_west_rows[kz] = Hw;
      f.g_west_rows[kz] = Hw * Hw * Hw;
    }
  }
}

SkirtResult SkirtFilm::evaluate(const SkirtKinematics& k) {
  return evaluate(k, nullptr);
}

void SkirtFilm::check_liner(const LinerField* liner) const {
  if (liner) {
    const std::size_t lattice = std::size_t(2 * nx_ + 1) * (2 * nz_ + 1), cells = std::size_t(nx_) * nz_;
    bool sized = liner->lattice.size() == arcs_.size() && liner->rate.size() == arcs_.size();
    for (std::size_t a = 0; sized && a < arcs_.size(); ++a)
      sized = liner->lattice[a].size() == lattice && liner->rate[a].size() == cells;
    if (!sized)
      throw Error("skirt '" + spec_.name + "': the liner field does not match the film's arcs and grid");
  }
}

SkirtResult SkirtFilm::evaluate(const SkirtKinematics& k, const LinerField* liner) {
  check_liner(liner);
  linearization_.valid = false;  // the film's coefficients and solution move on
  struct Reset {  // the liner is seen during this evaluation only
    const LinerField*& at;
    ~Reset() { at = nullptr; }
  } reset{liner_};
  liner_ = liner;
  for (double v : {k.e_top, k.e_bottom, k.e_top_dot, k.e_bottom_dot, k.speed})
    if (!std::isfinite(v)) throw Error("skirt '" + spec_.name + "': a kinematic input is not finite");
  // The thinnest film over the cells' centres, faces and corners (the lattice of half cells): the
  // hydrodynamic model ends at contact.
  double h_min = std::numeric_limits<double>::infinity(), h_min_angle = 0, h_min_y = 0;
  const double c = spec_.radial_clearance, L = spec_.skirt_length;
  for (int a = 0; a < static_cast<int>(arcs_.size()); ++a) {
    const Arc& arc = arcs_[a];
    for (int kz = 0; kz <= 2 * nz_; ++kz) {
      const double cs = kz % 2 ? arc.cos_c[kz / 2] : arc.cos_f[kz / 2];
      const double ov = kz % 2 ? arc.ovality_c[kz / 2] : arc.ovality_f[kz / 2];
      for (int i = 0; i <= 2 * nx_; ++i) {
        const double s = 0.5 * i * dy_ / L;
        const double h =
            c - (k.e_bottom + (k.e_top - k.e_bottom) * s) * cs + barrel_lattice_[i] + ov + liner_u(a, i, kz);
        if (h < h_min) {
          h_min = h, h_min_y = y_lattice_[i];
          h_min_angle = std::remainder(arc.start + 0.5 * kz * arc.width / nz_, 2 * kPi);
        }
      }
    }
  }
  if (!(h_min > 0) && !(spec_.film_floor > 0)) {
    std::ostringstream msg;
    msg << "skirt '" << spec_.name << "': the film closes (h = " << h_min << " m at theta = " << h_min_angle
        << " rad, y = " << h_min_y << " m; e_top = " << k.e_top << " m, e_bottom = " << k.e_bottom
        << " m): contact is not modelled by the film";
    throw Error(msg.str());
  }
  set_motion(k);
  int iterations = 0;
  for (Arc& arc : arcs_) {
    if (!has_solution_) {
      arc.film.cold_start(arc.P, arc.r);
    } else {
      arc.P *= p_ref_of_solution_ / p_ref_;  // the same dimensional pressures under the new scale
    }
    const int it = arc.film.solve(arc.P, arc.r, options_);
    if (it < 0) {
      has_solution_ = false;
      std::ostringstream msg;
      msg << "skirt '" << spec_.name << "': the film's Newton solve did not converge in " << -it
          << " iterations at e_top = " << k.e_top << " m, e_bottom = " << k.e_bottom << " m, rates ("
          << k.e_top_dot << ", " << k.e_bottom_dot << ") m/s, speed " << k.speed
          << " m/s; try a finer grid or check the input";
      throw Error(msg.str());
    }
    iterations += it;
  }
  has_solution_ = true;
  p_ref_of_solution_ = p_ref_;
  SkirtResult result = post_process(k);
  result.iterations = iterations;
  result.min_film = h_min, result.min_film_angle = h_min_angle, result.min_film_position = h_min_y;
  return result;
}

// Forces, moment, friction and power from the cell pressures and fill ratios (midpoint rule); the flows from
// the fluxes of one more assembly at the solution. The Poiseuille shear takes dp/dy from the two axial
// neighbours (the edge pressure half a cell beyond the end cells). Shear on the piston's surface (u = 0
// there, -V on the liner): tau = mu (-V) / h theta_f - (h / 2) dp/dy (the Couette part carried by the fill
// ratio, as for the journal's torque).
SkirtResult SkirtFilm::post_process(const SkirtKinematics& k, bool flows) {
  const double R = spec_.bore_radius, c = spec_.radial_clearance, mu = spec_.viscosity,
               L = spec_.skirt_length;
  const bool jfo = spec_.cavitation == Cavitation::kJfo;
  const double flow_scale = c * R * R * omega_ref_;  // m^3/s per unit of nondimensional flux
  const double y_bottom = y_f_[0], V = k.speed;
  auto e_dot_at = [&](double y) {
    return k.e_bottom_dot + (k.e_top_dot - k.e_bottom_dot) * (y - y_bottom) / L;
  };
  SkirtResult out;
  double lateral_power = 0;  // of the pressure forces on the piston
  out.max_pressure = -std::numeric_limits<double>::infinity();
  for (int a = 0; a < static_cast<int>(arcs_.size()); ++a) {
    Arc& arc = arcs_[a];
    const FilmProblem& f = arc.film.problem;
    arc.p_total.assign(std::size_t(nx_) * nz_, 0.0);
    const double dtheta = arc.width / nz_, dA = R * dtheta * dy_;
    for (int kz = 0; kz < nz_; ++kz) {
      const double cs = arc.cos_c[kz], sn = arc.sin_c[kz];
      for (int i = 0; i < nx_; ++i) {
        const int m = i + nx_ * kz;
        const double p = p_ref_ * arc.P[m];
        const double h = c * f.h_centre_cells[m];
        const double fill = jfo ? 1 - arc.r[m] : 1.0;
        const double y_lo = i > 0 ? y_c_[i - 1] : y_f_[0], y_hi = i + 1 < nx_ ? y_c_[i + 1] : y_f_[nx_];
        const double p_lo = i > 0 ? p_ref_ * arc.P[m - 1] : spec_.pressure_bottom;
        const double p_hi = i + 1 < nx_ ? p_ref_ * arc.P[m + 1] : spec_.pressure_top;
        const double tau = -mu * V / h * fill - 0.5 * h * (p_hi - p_lo) / (y_hi - y_lo);
        out.side_force -= p * cs * dA;
        out.pin_force -= p * sn * dA;
        out.moment += (p * y_c_[i] + R * tau) * cs * dA;
        out.shear_moment += R * tau * cs * dA;
        out.friction_force += tau * dA;
        lateral_power -= p * cs * e_dot_at(y_c_[i]) * dA;
        if (liner_) lateral_power += p * liner_rate(a, m) * dA;  // the pressure's power on the liner: p dh/dt
        arc.p_total[m] = p;
        if (spec_.asperity.active()) {
          const AsperityPressure ap = asperity_pressure(spec_.asperity, arc.h_nominal[m]);
          out.asperity_load += ap.p * dA;
          out.asperity_side_force -= ap.p * cs * dA;
          out.asperity_moment += ap.p * y_c_[i] * cs * dA;
          out.asperity_energy += ap.energy * dA;
          out.asperity_power -= ap.p * cs * e_dot_at(y_c_[i]) * dA;
          arc.p_total[m] += ap.p;
          out.asperity_max_pressure = std::max(out.asperity_max_pressure, ap.p);
        }
        if (p > out.max_pressure) {
          out.max_pressure = p;
          out.max_pressure_angle = std::remainder(arc.start + (kz + 0.5) * dtheta, 2 * kPi);
          out.max_pressure_position = y_c_[i];
        }
      }
    }
    if (!flows) continue;
    arc.film.assemble(arc.P, arc.r, false, arc.fluxes);
    out.flow_bottom += arc.fluxes.west_flow;
    out.flow_top -= arc.fluxes.east_flow;
    out.flow_sides += arc.fluxes.side_flow;
    out.stored_flow += arc.fluxes.squeeze_flow;
  }
  out.flow_bottom *= flow_scale, out.flow_top *= flow_scale, out.flow_sides *= flow_scale;
  out.stored_flow *= flow_scale;
  out.power_loss = -(out.friction_force * V + lateral_power);
  out.side_force += out.asperity_side_force;
  out.moment += out.asperity_moment;
  return out;
}

bool SkirtFilm::linearize() {
  Linearization& l = linearization_;
  l.valid = false;
  if (!has_solution_) return false;
  const int n = static_cast<int>(arcs_.size());
  l.P.resize(n), l.r.resize(n), l.M.resize(n);
  for (int a = 0; a < n; ++a) {
    Arc& arc = arcs_[a];
    if (!arc.film.factorize_at(arc.P, arc.r)) return false;
    l.P[a] = arc.P, l.r[a] = arc.r, l.M[a] = arc.film.last_step().M;
  }
  l.omega_ref = omega_ref_, l.p_ref = p_ref_;
  l.valid = true;
  return true;
}

SkirtResult SkirtFilm::evaluate_linearized(const SkirtKinematics& k, const LinerField* liner) {
  Linearization& l = linearization_;
  if (!l.valid) throw Error("skirt '" + spec_.name + "': evaluate_linearized() without linearize()");
  check_liner(liner);
  struct Reset {  // the liner is seen during this evaluation only; the warm start stays (P0, r0)
    SkirtFilm& film;
    ~Reset() {
      film.liner_ = nullptr;
      for (std::size_t a = 0; a < film.arcs_.size(); ++a)
        film.arcs_[a].P = film.linearization_.P[a], film.arcs_[a].r = film.linearization_.r[a];
    }
  } reset{*this};
  liner_ = liner;
  omega_ref_ = l.omega_ref, p_ref_ = l.p_ref;
  set_motion(k, /*hold_scale=*/true);
  for (int a = 0; a < static_cast<int>(arcs_.size()); ++a) {
    Arc& arc = arcs_[a];
    arc.film.assemble(l.P[a], l.r[a], false, l.scratch);
    const int n = arc.film.cells();
    l.y.resize(n);
    for (int m = 0; m < n; ++m) l.y[m] = arc.film.problem.supply[m] ? 0.0 : l.M[a][m] - l.scratch.M[m];
    arc.film.solve_last(l.y);
    // the eliminated unknown of each cell from its complementarity row (unchanged: ap dP + ar dr = 0)
    const FilmAssembly& base = arc.film.last_step();
    for (int m = 0; m < n; ++m) {
      if (arc.film.problem.supply[m]) continue;
      if (base.primary_is_p[m])
        arc.P[m] = l.P[a][m] + l.y[m], arc.r[m] = l.r[a][m] - base.ap[m] / base.ar[m] * l.y[m];
      else
        arc.r[m] = l.r[a][m] + l.y[m], arc.P[m] = l.P[a][m] - base.ar[m] / base.ap[m] * l.y[m];
    }
  }
  return post_process(k, /*flows=*/false);
}

Eigen::MatrixXd SkirtFilm::pressure(int a) const {
  const Arc& arc = arcs_.at(a);
  Eigen::MatrixXd p(nx_, nz_);
  for (int kz = 0; kz < nz_; ++kz)
    for (int i = 0; i < nx_; ++i) p(i, kz) = has_solution_ ? p_ref_of_solution_ * arc.P[i + nx_ * kz] : 0.0;
  return p;
}

Eigen::MatrixXd SkirtFilm::fill_ratio(int a) const {
  const Arc& arc = arcs_.at(a);
  Eigen::MatrixXd fill = Eigen::MatrixXd::Ones(nx_, nz_);
  if (spec_.cavitation == Cavitation::kJfo && has_solution_)
    for (int kz = 0; kz < nz_; ++kz)
      for (int i = 0; i < nx_; ++i) fill(i, kz) = 1 - arc.r[i + nx_ * kz];
  return fill;
}

double SkirtFilm::axial_position(int i) const {
  return y_c_.at(i);
}

double SkirtFilm::angle(int a, int k) const {
  const Arc& arc = arcs_.at(a);
  return arc.start + (k + 0.5) * arc.width / nz_;
}

}  // namespace nvh::bearing
