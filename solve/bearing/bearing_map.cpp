#include "solve/bearing/bearing_map.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "solve/bearing/journal_bearing.hpp"

namespace nvh::bearing {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = 180 / kPi;
}  // namespace

std::vector<std::string> map_column_names() {
  return {"eccentricity",
          "sommerfeld",
          "attitude_deg",
          "load_n",
          "min_film_m",
          "max_pressure_pa",
          "max_pressure_angle_deg",
          "friction_coefficient",
          "friction_torque_nm",
          "power_loss_w",
          "side_flow_m3s",
          "feed_flow_m3s",
          "Kxx",
          "Kxy",
          "Kyx",
          "Kyy",
          "Dxx",
          "Dxy",
          "Dyx",
          "Dyy"};
}

std::vector<std::string> map_column_units() {
  return {"1",     "1",     "deg", "N",   "m",   "Pa",  "deg",   "1",     "N m",   "W",
          "m^3/s", "m^3/s", "N/m", "N/m", "N/m", "N/m", "N s/m", "N s/m", "N s/m", "N s/m"};
}

std::vector<double> map_row_values(const MapRow& r) {
  return {r.eccentricity,
          r.sommerfeld,
          r.attitude_deg,
          r.load_n,
          r.min_film_m,
          r.max_pressure_pa,
          r.max_pressure_angle_deg,
          r.friction_coefficient,
          r.friction_torque_nm,
          r.power_loss_w,
          r.side_flow_m3s,
          r.feed_flow_m3s,
          r.K[0][0],
          r.K[0][1],
          r.K[1][0],
          r.K[1][1],
          r.D[0][0],
          r.D[0][1],
          r.D[1][0],
          r.D[1][1]};
}

std::vector<MapRow> bearing_map(const BearingSpec& spec, double omega,
                                const std::vector<double>& eccentricities, double load_angle) {
  if (!(omega > 0)) throw Error("bearing map: the journal speed must be > 0 rad/s");
  JournalBearing bearing(spec);
  const double c = spec.radial_clearance, R = spec.radius();
  std::vector<MapRow> rows;
  double attitude = 0.5 * kPi;  // first guess; each row starts from the previous one
  for (double eps : eccentricities) {
    // Outside solve's run a signal ends the process at once; called from a graceful context, it is heard
    // here.
    if (interrupt_requested()) throw Interrupted("bearing map: interrupted");
    if (!(eps > 0 && eps < 1)) {
      std::ostringstream msg;
      msg << "bearing map: eccentricity ratio " << eps << " is outside (0, 1); expected 0 < eps < 1";
      throw Error(msg.str());
    }
    Kinematics k;
    k.omega_journal = omega;
    FilmResult r;
    for (int it = 0; it < 30; ++it) {  // turn e until the film force points against the load
      const double angle = load_angle + attitude;
      k.e = eps * c * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      r = bearing.evaluate(k);
      const double force_angle =
          std::atan2(-r.force.y(), -r.force.x());  // direction of -F (the load it carries)
      const double miss = std::remainder(force_angle - load_angle, 2 * kPi);
      attitude -= miss;
      if (std::abs(miss) < 1e-9) break;
    }
    MapRow row;
    row.eccentricity = eps;
    row.load_n = r.force.norm();
    const double P = row.load_n / (spec.width * spec.diameter);
    row.sommerfeld = (R / c) * (R / c) * spec.viscosity * omega / (2 * kPi) / P;
    row.attitude_deg = std::remainder(attitude, 2 * kPi) * kDeg;
    row.min_film_m = r.min_film;
    row.max_pressure_pa = r.max_pressure;
    row.max_pressure_angle_deg = r.max_pressure_angle * kDeg;
    row.friction_torque_nm = r.torque_journal;
    row.friction_coefficient = std::abs(r.torque_journal) / (R * row.load_n);
    row.power_loss_w = r.power_loss;
    row.side_flow_m3s = r.side_flow;
    row.feed_flow_m3s = r.feed_flow;
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) {
        row.K[i][j] = -r.jacobian(i, j);
        row.D[i][j] = -r.jacobian(i, 2 + j);
      }
    rows.push_back(row);
  }
  return rows;
}

}  // namespace nvh::bearing
