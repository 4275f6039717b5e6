#pragma once
// The 1D slider: the Reynolds equation along a slider of length L and infinite width, solved by the same
// finite-volume JFO (mass-conserving) or Swift-Stieber discretisation and complementarity Newton solve as
// the finite journal bearing (film_solver.hpp), with given pressures at both ends instead of periodicity.
//
// Film: h(x) = h_in + (h_out - h_in) x / L outside the pockets (parallel: h_in = h_out; inclined otherwise),
// deeper by each pocket's depth inside [start, end]. One surface moves at U along +x, the other is at rest:
// the Couette flux is U h / 2 (times the fill ratio). Steady, per unit width:
//   d/dx ( h^3 / (12 mu) dp/dx ) = U / 2 d(theta_f h)/dx,   p >= 0, 1 - theta_f >= 0, p (1 - theta_f) = 0
// with p(0) = p_inlet, p(L) = p_outlet and a full film (theta_f = 1) entering from outside.
//
// Faces: where h is continuous the face takes h(x_face) for both the Poiseuille conductance h^3 and the
// Couette film. At a step of h on a face (h_- to h_+), the face takes the values that make the flux exact
// for a full film that is piecewise linear on the two half cells (docs/bearing.md, section 13):
//   G = 2 / (h_-^-3 + h_+^-3),   H_couette = (h_-^-2 + h_+^-2) / (h_-^-3 + h_+^-3)
// A step inside a cell acts on the cell's nearer face: put pocket edges on faces (L / cells) for accuracy.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "solve/bearing/bearing.hpp"
#include "solve/bearing/film_solver.hpp"

namespace nvh::bearing {

/// A pocket (or a step, if it starts at 0): the film is `depth` deeper on [start, end].
struct Pocket {
  double start = 0;  ///< m
  double end = 0;    ///< m, > start
  double depth = 0;  ///< m, > 0
};

struct SliderSpec {
  std::string name = "slider";
  double length = 0;       ///< m, L
  double film_inlet = 0;   ///< m, h at x = 0 outside the pockets
  double film_outlet = 0;  ///< m, h at x = L outside the pockets (= film_inlet: parallel slider)
  std::vector<Pocket> pockets;
  double speed = 0;            ///< m/s, U of the moving surface along +x (the other surface at rest)
  double viscosity = 0;        ///< Pa s, mu0
  double barus = 0;            ///< 1/Pa, mu = mu0 exp(barus p)
  double pressure_inlet = 0;   ///< Pa (gauge), p(0)
  double pressure_outlet = 0;  ///< Pa (gauge), p(L)
  Cavitation cavitation = Cavitation::kJfo;
  int cells = 200;  ///< finite volumes along x
};

struct SliderResult {
  Eigen::VectorXd x;           ///< m, cell centres (x_i = (i + 1/2) L / cells)
  Eigen::VectorXd film;        ///< m, h at the cell centres
  Eigen::VectorXd pressure;    ///< Pa, at the cell centres
  Eigen::VectorXd fill_ratio;  ///< 1 in the full film (JFO); 1 everywhere otherwise
  /// Pa, at the cells + 1 faces x = i L / cells (the ends: the given pressures): from flux continuity across
  /// the face, exact for a film that is linear on both half cells; clipped at 0.
  Eigen::VectorXd face_pressure;
  double load = 0;                   ///< N/m, integral of p over [0, L] (midpoint rule on the cells)
  double max_pressure = 0;           ///< Pa, largest of the cell and face pressures
  double max_pressure_position = 0;  ///< m
  double flow_at_start = 0;          ///< m^2/s, volume flow along +x through x = 0, per unit width
  double flow_at_end = 0;            ///< m^2/s, volume flow along +x through x = L, per unit width
  int iterations = 0;                ///< Newton iterations
};

/// Throws nvh::Error naming the field if the spec is not usable (length, films, viscosity <= 0, a pocket
/// outside [0, L] or with end <= start or depth <= 0, cells < 2, negative end pressures).
void validate(const SliderSpec& spec);

/// The film thickness at x: side < 0 the limit from the left, side > 0 from the right, 0 the value with
/// pockets closed at both ends.
double slider_film(const SliderSpec& spec, double x, int side = 0);

/// Solves the slider (cold start). Throws nvh::Error if the Newton solve does not converge.
SliderResult solve_slider(const SliderSpec& spec, const FiniteSolverOptions& options = {});

}  // namespace nvh::bearing
