#pragma once
// Static characteristics of a bearing over eccentricity ratio: the data of a bearing design chart and of
// the `solve bearing-map` tool (bearing_map_cli.hpp). Columns and units in docs/bearing.md, section 8.
//
// For each eccentricity ratio the journal (speed omega, shell at rest) is placed at |e| = eps c in the
// direction where the film force balances a load acting along `load_angle` (shell frame): the attitude
// angle is found by a fixed-point iteration on the direction of e (exact after one step for a plain
// bearing; holes and grooves make it depend on the load direction). The linear stiffness and damping
// coefficients are K = -dF/de and D = -dF/d(de/dt) at that static equilibrium, in the shell's x-y axes.
#include <string>
#include <vector>

#include "solve/bearing/bearing.hpp"

namespace nvh::bearing {

struct MapRow {
  double eccentricity = 0;     ///< eps = |e| / c
  double sommerfeld = 0;       ///< S = (R/c)^2 mu N / P, N in rev/s, P = W / (L D)
  double attitude_deg = 0;     ///< angle from the load line to the line of centres, in the rotation sense
  double load_n = 0;           ///< W, N
  double min_film_m = 0;       ///< h_min, m
  double max_pressure_pa = 0;  ///< Pa
  double max_pressure_angle_deg = 0;  ///< shell angle of the peak, deg
  double friction_coefficient = 0;    ///< |T_journal| / (R W)
  double friction_torque_nm = 0;      ///< torque on the journal, N m
  double power_loss_w = 0;            ///< W
  double side_flow_m3s = 0;           ///< m^3/s
  double feed_flow_m3s = 0;           ///< m^3/s
  double K[2][2] = {{0, 0}, {0, 0}};  ///< N/m, K_ij = -dF_i/de_j (x, y of the shell)
  double D[2][2] = {{0, 0}, {0, 0}};  ///< N s/m, D_ij = -dF_i/d(de_j/dt)
};

/// Column names in file order (the HDF5 datasets and CSV header), and their units.
std::vector<std::string> map_column_names();
std::vector<std::string> map_column_units();
/// The row's values in the order of map_column_names().
std::vector<double> map_row_values(const MapRow& row);

/// The static characteristics at each eccentricity ratio (0 < eps < 1; nvh::Error otherwise).
/// omega: journal speed, rad/s (> 0); load_angle: direction of the load on the journal, rad (shell frame).
std::vector<MapRow> bearing_map(const BearingSpec& spec, double omega,
                                const std::vector<double>& eccentricities, double load_angle);

}  // namespace nvh::bearing
