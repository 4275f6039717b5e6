// The journal bearing force element (see journal_bearing_element.hpp for the kinematics and conventions).
#include "solve/journal_bearing_element.hpp"

#include <cmath>
#include <limits>

#include "common/error.hpp"
#include "solve/bearing/bearing_reader.hpp"
#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"

namespace nvh::solve {

namespace {
// In a time integration successive film states are close: the finite film's Newton steps may reuse an
// earlier factorization (FiniteSolverOptions::reuse_factorization); jacobian() asks for the exact one.
bearing::FiniteSolverOptions film_options(double tolerance) {
  bearing::FiniteSolverOptions o;
  o.reuse_factorization = true;
  o.tolerance = tolerance;
  return o;
}
}  // namespace

JournalBearingElement::JournalBearingElement(bearing::BearingSpec spec, double film_tolerance)
    : bearing_(std::move(spec), film_options(film_tolerance)) {}

bearing::Kinematics JournalBearingElement::kinematics(const MarkerMotion& i, const MarkerMotion& j) {
  const Vec3 d = i.position - j.position, d_dot = i.velocity - j.velocity;
  const Vec3 x = j.axes.col(0), y = j.axes.col(1), z = j.axes.col(2);
  bearing::Kinematics k;
  k.e = {x.dot(d), y.dot(d)};
  k.e_dot = {x.dot(d_dot), y.dot(d_dot)};
  k.omega_journal = z.dot(i.angular_velocity);
  k.omega_shell = z.dot(j.angular_velocity);
  return k;
}

namespace {
bool same(const bearing::Kinematics& a, const bearing::Kinematics& b) {
  return a.e == b.e && a.e_dot == b.e_dot && a.omega_journal == b.omega_journal &&
         a.omega_shell == b.omega_shell;
}
}  // namespace

JournalBearingElement::CachedFilm* JournalBearingElement::cached(const bearing::Kinematics& k,
                                                                 bearing::Detail detail) const {
  for (int n : {newest_, 1 - newest_}) {
    CachedFilm& c = cache_[n];
    const bool enough = detail == bearing::Detail::kForces || c.detail == bearing::Detail::kFull;
    if (c.kinematics && same(*c.kinematics, k) && enough) return &c;
  }
  return nullptr;
}

namespace {
bearing::FilmResult failed_film() {  // |e| >= c or no convergence: a non-finite force makes IDA cut its step
  bearing::FilmResult r;
  r.force.setConstant(std::numeric_limits<double>::quiet_NaN());
  r.torque_journal = std::numeric_limits<double>::quiet_NaN();
  return r;
}
}  // namespace

const bearing::FilmResult& JournalBearingElement::film(const bearing::Kinematics& k, bearing::Detail detail) const {
  if (const CachedFilm* c = cached(k, detail)) return c->result;
  newest_ = 1 - newest_;  // overwrite the older entry
  CachedFilm& c = cache_[newest_];
  c.detail = detail;
  try {
    c.result = bearing_.evaluate(k, detail);
  } catch (const Error&) {
    c.result = failed_film();
  }
  c.kinematics = k;
  return c.result;
}

const bearing::FilmResult& JournalBearingElement::film_with_jacobian(const bearing::Kinematics& k) const {
  const bearing::FilmResult& r = film(k, bearing::Detail::kForces);
  if (!bearing_.finite() || r.has_full_jacobian || !r.force.allFinite()) return r;
  CachedFilm& c = *cached(k, bearing::Detail::kForces);  // the entry film() just returned
  try {
    c.result = bearing_.evaluate_with_jacobian(k, c.detail);
  } catch (const Error&) {
    c.result = failed_film();
  }
  return c.result;
}

const bearing::FilmResult& JournalBearingElement::film(const MarkerMotion& i, const MarkerMotion& j,
                                                       bearing::Detail detail) const {
  return film(kinematics(i, j), detail);
}

void JournalBearingElement::evaluate(const ElementInput& in, ElementOutput& out) const {
  const MarkerMotion &i = in.markers[0], &j = in.markers[1];
  const bearing::FilmResult& r = film(i, j, bearing::Detail::kForces);
  const Vec3 force = j.axes.col(0) * r.force.x() + j.axes.col(1) * r.force.y();
  apply_at_i(in, out, force, r.torque_journal * j.axes.col(2), i.position);
}

bool JournalBearingElement::jacobian(const ElementInput& in, ElementJacobian& jac) const {
  const MarkerMotion &i = in.markers[0], &j = in.markers[1];
  const bearing::Kinematics k0 = kinematics(i, j);
  const bearing::FilmResult r0 = film_with_jacobian(k0);
  if (!r0.force.allFinite()) return false;
  const Vec3 x = j.axes.col(0), y = j.axes.col(1), z = j.axes.col(2);
  const Vec3 d = i.position - j.position, dd = i.velocity - j.velocity;

  // G: d(Fx, Fy, Tj) / d(ex, ey, ex', ey', omega_journal, omega_shell). The finite bearing gives all of it
  // (implicit function theorem on its converged film: no further film solve); for the closed forms the
  // torque and the speed columns are differenced here, a few cheap evaluations.
  Eigen::Matrix<double, 3, 6> g = Eigen::Matrix<double, 3, 6>::Zero();
  g.topLeftCorner<2, 4>() = r0.jacobian;
  const double c = bearing_.spec().radial_clearance;
  const double omega_scale = std::max({1.0, std::abs(k0.omega_journal), std::abs(k0.omega_shell)});
  if (r0.has_full_jacobian) g = r0.full_jacobian;
  for (int col = 0; col < 6 && !r0.has_full_jacobian; ++col) {
    bearing::Kinematics k = k0;
    double* v = col < 2 ? &k.e[col] : col < 4 ? &k.e_dot[col - 2] : col == 4 ? &k.omega_journal : &k.omega_shell;
    const double step = col < 2 ? 1e-7 * c : col < 4 ? 1e-7 * (c * omega_scale + k0.e_dot.norm()) : 1e-7 * omega_scale;
    const double old = *v;
    *v += step;
    const double h = *v - old;  // the step as represented
    const bearing::FilmResult& r = film(k, bearing::Detail::kForces);
    if (!r.force.allFinite()) return false;
    g(2, col) = (r.torque_journal - r0.torque_journal) / h;
    if (col >= 4) g.block<2, 1>(0, col) = (r.force - r0.force) / h;
  }
  // K: d(kinematics)/d(marker columns): [dp_i 0-2, dth_i 3-5, dv_i 6-8, dw_i 9-11, dp_j 12-14, dth_j 15-17,
  // dv_j 18-20, dw_j 21-23].
  Eigen::Matrix<double, 6, 24> kin = Eigen::Matrix<double, 6, 24>::Zero();
  kin.block<1, 3>(0, 0) = x.transpose(), kin.block<1, 3>(0, 12) = -x.transpose();
  kin.block<1, 3>(1, 0) = y.transpose(), kin.block<1, 3>(1, 12) = -y.transpose();
  kin.block<1, 3>(0, 15) = x.cross(d).transpose(), kin.block<1, 3>(1, 15) = y.cross(d).transpose();
  kin.block<1, 3>(2, 6) = x.transpose(), kin.block<1, 3>(2, 18) = -x.transpose();
  kin.block<1, 3>(3, 6) = y.transpose(), kin.block<1, 3>(3, 18) = -y.transpose();
  kin.block<1, 3>(2, 15) = x.cross(dd).transpose(), kin.block<1, 3>(3, 15) = y.cross(dd).transpose();
  kin.block<1, 3>(4, 9) = z.transpose(), kin.block<1, 3>(4, 15) = z.cross(i.angular_velocity).transpose();
  kin.block<1, 3>(5, 21) = z.transpose(), kin.block<1, 3>(5, 15) += z.cross(j.angular_velocity).transpose();
  const Eigen::Matrix<double, 3, 24> dfilm = g * kin;  // d(Fx, Fy, Tj)/d(columns)

  Eigen::Matrix<double, 3, 2> xy;
  xy << x, y;
  const Vec3 force = xy * r0.force;
  ElementRows df = zero_rows(jac), dt = zero_rows(jac);
  df.leftCols<24>() = xy * dfilm.topRows<2>();
  df.block<3, 3>(0, 15) -= skew(force);  // the force turns with the shell's axes
  dt.leftCols<24>() = z * dfilm.row(2);
  dt.block<3, 3>(0, 15) -= r0.torque_journal * skew(z);
  jacobian_at_i(in, jac, df, dt, force);
  if (!r0.has_full_jacobian) film(k0, bearing::Detail::kForces);  // leave the cache (and warm start) here
  return true;
}

std::vector<Channel> JournalBearingElement::channels() const {
  return {{"eccentricity_ratio", "1"}, {"attitude_angle", "rad"}, {"min_film", "m"},      {"max_pressure", "Pa"},
          {"friction_torque", "N m"},  {"power_loss", "W"},        {"oil_flow", "m^3/s"}};
}

void JournalBearingElement::channel_values(const ElementInput& in, std::span<double> out) const {
  const bearing::Kinematics k = kinematics(in.markers[0], in.markers[1]);
  const bearing::FilmResult& r = film(k);
  const double c = bearing_.spec().radial_clearance;
  out[0] = k.e.norm() / c;
  // Attitude angle: from the load line (the external load on the journal, -F) to the line of centres (e),
  // measured in the sense of rotation (sign of omega_journal + omega_shell); as in bearing-map.
  const Eigen::Vector2d load = -r.force;
  const double sense = k.omega_journal + k.omega_shell >= 0 ? 1.0 : -1.0;
  const double cross = load.x() * k.e.y() - load.y() * k.e.x();
  out[1] = sense * std::atan2(cross, load.dot(k.e));
  out[2] = r.min_film;
  out[3] = r.max_pressure;
  out[4] = r.torque_journal;
  out[5] = r.power_loss;
  out[6] = r.side_flow;
}

ElementEnergy JournalBearingElement::energy(const ElementInput& in) const {
  return {0.0, film(in.markers[0], in.markers[1], bearing::Detail::kForces).power_loss};
}

void register_journal_bearing(ElementRegistry& r) {
  r.add({"force", "journal-bearing",
         "hydrodynamic journal bearing (short, long or finite Reynolds with JFO cavitation; keys of docs/bearing.md) "
         "between journal centre i and shell centre j (z_j the bearing axis)",
         {"i", "j"}, [](ElementContext& c) -> std::unique_ptr<ForceElement> {
           // The finite film's Newton tolerance in a run (relative to 1 + the peak pressure; docs/bearing.md
           // section 9): read here, not by read_bearing, because the bearing-map tool solves to 1e-9 always.
           const double tolerance = c.table.number_or("film_tolerance", JournalBearingElement::kFilmTolerance,
                                                      input::Range::closed(1e-13, 1e-4));
           return std::make_unique<JournalBearingElement>(bearing::read_bearing(c.table), tolerance);
         }});
}

}  // namespace nvh::solve
