// The journal bearing force element (see journal_bearing_element.hpp for the kinematics and conventions).
#include "solve/journal_bearing_element.hpp"

#include <cmath>
#include <limits>

#include "common/error.hpp"
#include "solve/bearing/bearing_reader.hpp"

namespace nvh::solve {

JournalBearingElement::JournalBearingElement(bearing::BearingSpec spec) : bearing_(std::move(spec)) {}

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

const bearing::FilmResult& JournalBearingElement::film(const MarkerMotion& i, const MarkerMotion& j) const {
  const bearing::Kinematics k = kinematics(i, j);
  if (last_kinematics_ && same(*last_kinematics_, k)) return last_result_;
  try {
    last_result_ = bearing_.evaluate(k);
  } catch (const Error&) {
    // |e| >= c or no convergence: a non-finite force makes the integrator cut its step.
    last_result_ = bearing::FilmResult{};
    last_result_.force.setConstant(std::numeric_limits<double>::quiet_NaN());
    last_result_.torque_journal = std::numeric_limits<double>::quiet_NaN();
  }
  last_kinematics_ = k;
  return last_result_;
}

ElementForce JournalBearingElement::evaluate(const ForceContext&, const MarkerMotion& i,
                                             const MarkerMotion& j) const {
  const bearing::FilmResult& r = film(i, j);
  const Vec3 force = j.axes.col(0) * r.force.x() + j.axes.col(1) * r.force.y();
  return {force, r.torque_journal * j.axes.col(2), i.position};
}

std::vector<std::string> JournalBearingElement::channel_names() const {
  return {"eccentricity_ratio", "attitude_angle_rad", "min_film_m",   "max_pressure_pa",
          "friction_torque_nm", "power_loss_w",       "oil_flow_m3_s"};
}

void JournalBearingElement::channels(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j,
                                     std::span<double> out) const {
  const bearing::Kinematics k = kinematics(i, j);
  const bearing::FilmResult& r = film(i, j);
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

std::unique_ptr<ForceElement> make_journal_bearing(const input::Table& t) {
  return std::make_unique<JournalBearingElement>(bearing::read_bearing(t));
}

}  // namespace nvh::solve
