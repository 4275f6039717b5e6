#pragma once
// The oil film between a piston skirt and the liner: the 2D Reynolds equation over the skirt (axial x
// circumferential) with mass-conserving cavitation, the wedge term of the piston's axial sliding and the
// squeeze term of its lateral motion and tilt - eq. 12 of the engine paper (../shared/papers/000_*.txt,
// "piston to liner contact"), written in the piston's frame. A library piece: solve's piston-liner element
// (issue 14) will call it; see docs/bearing.md, section 14.
//
// Frame (the piston's, a rigid liner): y along the piston axis towards the crown, the pin axis at y = 0; x
// the thrust direction (in the plane of the conrod's swing), w = x cross y along the pin. A point of the
// skirt sits at the angle theta from x towards w, n = (cos theta, sin theta) in (x, w). The piston's axis is
// displaced from the bore's by e(y) along x, linear between the skirt's bottom and top edges:
//   e(y) = e_bottom + (e_top - e_bottom) (y - y_bottom) / L            (tilt (e_top - e_bottom) / L, small)
// and the film thickness (liner radius minus the skirt's local radius minus the displacement along n) is
//   h(theta, y) = c - e(y) cos(theta) + barrel(y) + ovality(theta)
// with c the radial clearance of the nominal (largest) skirt radius and the profile tables the skirt's radius
// reduction along the axis and around it. Squeeze: dh/dt = -de(y)/dt cos(theta).
//
// Reynolds (eq. 12 of the engine paper; Elrod's and JFO's fill ratio theta_f), with y the sliding direction
// and s = R theta around, in the piston's frame where the liner slides at -V along y (V: the piston's axial
// velocity relative to the liner), so the mean surface speed is U = -V / 2:
//   d/dy (h^3 / (12 mu) dp/dy) + d/ds (h^3 / (12 mu) dp/ds) = U d(theta_f h)/dy + d(theta_f h)/dt
// with p >= 0, 1 - theta_f >= 0, p (1 - theta_f) = 0 (JFO; Swift-Stieber or a full film as for the journal).
// No Couette flux around (the piston does not rotate).
//
// Boundaries. Along the axis: given pressures at the bottom and top edges (ambient 0 by default); the film
// the liner drags in through the inlet edge (the bottom one when V < 0, the top one when V > 0) carries the
// fill ratio fill_bottom or fill_top (1: flooded; < 1: starved, partial flooding). Around: each arc of the
// skirt is a film of its own with p = 0 at its two edges (the recessed pin-boss regions between the skirt
// panels are at ambient pressure); a single arc of 2 pi is a full circle, periodic around.
//
// Discretisation and solve: film_solver.hpp (finite volumes, per-cell coefficients: the exact film at each
// face for the conductance H^3 and the Couette film; KLU; semismooth Newton for the complementarity), one
// FilmSolver per arc, x = axial (not periodic), z = around. Nondimensional as the finite journal bearing
// (finite_bearing.cpp): X = y / R, Z = theta, H = h / c, P = p / p_ref, p_ref = 12 mu R^2 omega_ref / c^2,
// tau = omega_ref t, with omega_ref = max(|U| / R, |de/dt|max / c, the end pressures' scale).
//
// The squeeze term (1 - r) dh/dt is quasi-steady (as for the journal bearing): one evaluation depends on the
// state (e, de/dt, V) alone; the fill ratio's own rate in the cavitated zone is not followed. Isoviscous.
//
// Film to dry contact without a switch (both off by default): with a film floor h_f > 0 the Reynolds equation
// sees the effective film
//   h_eff(h) = h_f (1 + ln(1 + exp((h - h_f) / h_f)))                     (a softplus floor;
//   docs/bearing.md 15.3)
// - smooth and increasing, h_eff -> h for h >> h_f (h_eff - h = h_f ln(1 + exp(-(h - h_f)/h_f)): 0.13 h_f at
// h = 3 h_f, 1.2e-4 h_f at 10 h_f), h_eff -> h_f as h -> -infinity - in its conductance, Couette film and
// shear, while the squeeze term keeps the nominal gap's rate dh/dt (the roughness valleys hold oil the
// closing gap still expels, so the squeeze load does not vanish at contact); a nominal film <= 0 is then no
// error. The asperity pressure of the Greenwood-Tripp law (asperity_contact.hpp), evaluated per cell from the
// nominal h, adds to the film pressure in the side force and the moment; it stores elastic energy and
// dissipates none.
//
// Units SI: m, m/s, rad, Pa, Pa s, N, N m, W, m^3/s.
#include <Eigen/Core>
#include <numbers>
#include <string>
#include <vector>

#include "solve/bearing/asperity_contact.hpp"
#include "solve/bearing/bearing.hpp"
#include "solve/bearing/film_solver.hpp"

namespace nvh::bearing {

/// One panel of the skirt: the arc [start, end] of theta (rad, from the thrust direction x towards the pin
/// axis w). end - start in (0, 2 pi]; 2 pi is the full circle (then the only arc).
struct SkirtArc {
  double start = 0;  ///< rad
  double end = 0;    ///< rad
};

/// The thrust and anti-thrust panels: arcs of +-half_width (rad) about theta = 0 and theta = pi.
inline std::vector<SkirtArc> thrust_and_anti_thrust_arcs(double half_width = std::numbers::pi / 3) {
  std::vector<SkirtArc> arcs(2);
  arcs[0].start = -half_width, arcs[0].end = half_width;
  arcs[1].start = std::numbers::pi - half_width, arcs[1].end = std::numbers::pi + half_width;
  return arcs;
}

/// A profile as a table: `value` (m, the film's increase: the skirt's radius reduction) at `at` (strictly
/// ascending). Linear in between. Empty: zero.
struct ProfileTable {
  std::vector<double> at;
  std::vector<double> value;
};

struct SkirtSpec {
  std::string name = "skirt";
  double bore_radius = 0;       ///< m, R (the liner's)
  double radial_clearance = 0;  ///< m, c: the bore's radius minus the skirt's nominal (largest) radius
  double skirt_length = 0;      ///< m, L: axial length of the skirt
  double skirt_top = 0;         ///< m, y of the skirt's top edge (the pin axis at y = 0, y towards the crown)
  /// The skirt's panels: by default the thrust and anti-thrust sides, +-60 deg each.
  std::vector<SkirtArc> arcs = thrust_and_anti_thrust_arcs();
  /// Barrel profile: `at` y (m, the pin frame above), held constant beyond the table's ends.
  ProfileTable barrel;
  /// Ovality: `at` theta (rad, a span < 2 pi), periodic (from the last point back to the first + 2 pi).
  ProfileTable ovality;
  double viscosity = 0;  ///< Pa s, mu (isoviscous)
  Cavitation cavitation = Cavitation::kJfo;
  double fill_bottom = 1;  ///< fill ratio in [0, 1] of the film entering through the bottom edge (V < 0), JFO
  double fill_top = 1;     ///< same, top edge (V > 0)
  double pressure_bottom = 0;  ///< Pa (gauge) at the bottom edge
  double pressure_top = 0;     ///< Pa (gauge) at the top edge
  int cells_axial = 40;        ///< finite volumes along the axis (>= 2)
  int cells_around = 24;       ///< finite volumes around, in each arc (>= 3)
  /// m, the film floor h_f of the effective film h_eff(h) (see the top of this file); 0: off (a film <= 0 is
  /// an error).
  double film_floor = 0;
  /// m, the oil layer h_o of a partially flooded skirt's squeeze (0: off, the closing film is full). The oil
  /// held in a gap h is taken as the smooth minimum of h and h_o, so a cell's squeeze source is
  /// s(h) dh/dt with s(h) = 1 / (1 + exp((h - h_o) / (h_o / 8))): where the gap is wider than the oil layer
  /// the closing skirt pushes air, not oil (no squeeze pressure); below it the full squeeze of section 14.2.
  double oil_layer = 0;
  /// Asperity contact on the nominal film, per cell (inactive while asperity.sigma = 0).
  GreenwoodTripp asperity;
};

/// The effective film of the Reynolds equation for a film floor h_f > 0 (h itself for h_f = 0), and its
/// derivative dh_eff/dh.
struct EffectiveFilm {
  double h = 0;
  double dh = 1;
};
EffectiveFilm effective_film(double h, double film_floor);
/// The squeeze factor s(h) of a partially flooded skirt with an oil layer h_o (SkirtSpec::oil_layer; 1 when off).
double oil_layer_squeeze_factor(double h, double oil_layer);

/// The piston's motion the film sees (the liner at rest).
struct SkirtKinematics {
  double e_top = 0;         ///< m, displacement of the piston axis at the skirt's top edge along x
  double e_bottom = 0;      ///< m, same at the bottom edge
  double e_top_dot = 0;     ///< m/s
  double e_bottom_dot = 0;  ///< m/s
  double speed = 0;         ///< m/s, V: the piston's axial velocity relative to the liner along y
};

/// What one evaluation returns. Forces and moment are the film's and the asperities' on the piston (the liner
/// gets the opposite); p is the film pressure, p_a the asperity pressure.
struct SkirtResult {
  double side_force = 0;             ///< N, along x: -int (p + p_a) cos(theta) dA
  double pin_force = 0;              ///< N, along w: -int p sin(theta) dA (0 for a skirt symmetric about x)
  double moment = 0;                 ///< N m, about the pin axis w: int ((p + p_a) y + R tau) cos(theta) dA
  double shear_moment = 0;           ///< N m, the shear's part of `moment`: int R tau cos(theta) dA
  double friction_force = 0;         ///< N, along y: int tau dA, tau = -mu V theta_f / h - (h / 2) dp/dy
  double power_loss = 0;             ///< W, -(friction_force V - int p cos(theta) de(y)/dt dA) (the film's)
  double min_film = 0;               ///< m, over the cells' centres, faces and corners
  double min_film_angle = 0;         ///< rad
  double min_film_position = 0;      ///< m, y
  double max_pressure = 0;           ///< Pa, largest cell pressure
  double max_pressure_angle = 0;     ///< rad
  double max_pressure_position = 0;  ///< m, y
  double flow_bottom = 0;            ///< m^3/s, into the film through the bottom edge (negative: out)
  double flow_top = 0;               ///< m^3/s, into the film through the top edge
  double flow_sides = 0;             ///< m^3/s, out through the arcs' edges (0 for a full circle)
  /// m^3/s, rate of the oil volume held in the film, int theta_f dh/dt dA (quasi-steady). JFO conserves mass:
  /// flow_bottom + flow_top = flow_sides + stored_flow.
  double stored_flow = 0;
  int iterations = 0;  ///< Newton iterations, all arcs
  // Asperity contact (zero while the law is inactive); included in side_force and moment above.
  double asperity_load = 0;          ///< N, int p_a dA (the normal load the asperities carry)
  double asperity_side_force = 0;    ///< N, along x: -int p_a cos(theta) dA
  double asperity_moment = 0;        ///< N m, about w: int p_a y cos(theta) dA
  double asperity_energy = 0;        ///< J, stored: int u(h) dA
  double asperity_power = 0;         ///< W, of p_a on the piston's lateral motion: -d(asperity_energy)/dt
  double asperity_max_pressure = 0;  ///< Pa
};

/// A deformable liner (the elasto-hydrodynamic piston-liner element, docs/bearing.md section 17): the liner's
/// radial displacement u (m, outwards: the film grows) on the lattice of half cells of each arc - index
/// i2 + (2 nx + 1) k2, i2 = 0 .. 2 nx from the bottom edge (even: faces, odd: centres), k2 = 0 .. 2 nz from
/// the arc's start - and the liner's part of the squeeze dh/dt (m/s) at the cells' centres (index i + nx kz).
/// The film becomes h = (rigid-liner film) + u, dh/dt = (piston's part) + rate; the power of the pressure
/// counts both (SkirtResult::power_loss). One entry per arc; empty vectors: a rigid liner.
struct LinerField {
  std::vector<std::vector<double>> lattice;  ///< m, per arc
  std::vector<std::vector<double>> rate;     ///< m/s, per arc
};

/// Throws nvh::Error naming the field if the spec is not usable.
void validate(const SkirtSpec& spec);

/// h(theta, y) in m (may be <= 0: the skirt then touches the liner there).
double skirt_film_thickness(const SkirtSpec& spec, const SkirtKinematics& k, double theta, double y);

class SkirtFilm {
 public:
  /// Validates the spec and builds one film grid per arc.
  explicit SkirtFilm(SkirtSpec spec, FiniteSolverOptions options = {});

  /// Solves the film for this motion, warm-started from the previous solution (if any). Throws nvh::Error if
  /// the film is <= 0 somewhere without a film floor, or the Newton solve does not converge.
  SkirtResult evaluate(const SkirtKinematics& k);
  /// The same on a deformable liner (LinerField above, sized for this film's arcs and grid); nullptr: rigid.
  SkirtResult evaluate(const SkirtKinematics& k, const LinerField* liner);
  /// Pa, the last solution's film plus asperity pressure at the cells' centres of arc a (index i + nx kz).
  const std::vector<double>& cell_pressure(int a) const { return arcs_.at(a).p_total; }
  /// Forget the previous solution: the next evaluation starts cold.
  void reset() { has_solution_ = false, linearization_.valid = false; }

  /// The film's linearization about the last solution (docs/bearing.md section 17.6): factorizes each arc's
  /// reduced Newton matrix at that solution in the min form of the complementarity, so that the cavitated
  /// set of the solution is held (a cavitated cell keeps p = 0, a full one r = 0). False without a solution
  /// or if a matrix is singular (then take differences of evaluate()).
  bool linearize();
  /// The film after one Newton correction from the linearized solution (P0, r0) with the factorization of
  /// linearize(), at the coefficients of (k, liner) and the linearization's pressure scale:
  ///   A0 (dP, dr) = -(M(P0, r0; k, liner) - M(P0, r0; k0, liner0))        (M: the cells' mass balance)
  /// first-order exact in the change of (k, liner) with the cavitated set held, so that central differences
  /// of it give the derivatives of the film's outputs for the price of an assembly and a back-substitution
  /// per input instead of a Newton solve (Newton's method's own linearization: the implicit function
  /// theorem, dP/dq = -A0^-1 dM/dq). Leaves (P0, r0) as the warm start; cell_pressure() returns this
  /// evaluation's pressures. The flows and the minimum film are not computed (0). Throws nvh::Error without
  /// linearize().
  SkirtResult evaluate_linearized(const SkirtKinematics& k, const LinerField* liner);

  int arcs() const { return static_cast<int>(arcs_.size()); }
  /// Pressure (Pa) of the last solution on arc a: cells_axial x cells_around, cell (i, k) centred at
  /// axial_position(i), angle(a, k).
  Eigen::MatrixXd pressure(int a) const;
  /// Fill ratio of the last solution on arc a (1 everywhere unless JFO), same layout.
  Eigen::MatrixXd fill_ratio(int a) const;
  double axial_position(int i) const;  ///< m, y of the cells' centres
  double angle(int a, int k) const;    ///< rad, theta of the cells' centres
  const SkirtSpec& spec() const { return spec_; }

 private:
  struct Arc {
    double start = 0, width = 0;                  // rad
    bool full = false;                            // the full circle: periodic around
    std::vector<double> cos_c, sin_c, ovality_c;  // at the cells' centres
    std::vector<double> cos_f, ovality_f;         // at the nz + 1 faces around (the start edge first)
    std::vector<double> h_nominal;                // m, the nominal film at the cells' centres (asperities)
    std::vector<double> p_total;  // Pa, film + asperity pressure at the centres (last solution)
    FilmSolver film;
    Eigen::VectorXd P, r;
    FilmAssembly fluxes;  // at the last solution (the flows)
  };
  /// `hold_scale`: keep omega_ref and p_ref (the linearized evaluations; the dimensional solution does not
  /// depend on them).
  void set_motion(const SkirtKinematics& k, bool hold_scale = false);
  /// `flows`: also the flows (one more assembly).
  SkirtResult post_process(const SkirtKinematics& k, bool flows = true);
  void check_liner(const LinerField* liner) const;
  const LinerField* liner_ = nullptr;  // during one evaluation: the deformable liner, or nullptr (rigid)
  /// m, the liner's displacement on arc a's lattice point (i2, k2), m/s its squeeze rate at cell m; 0 if
  /// rigid
  double liner_u(int a, int i2, int k2) const {
    return liner_ ? liner_->lattice[a][i2 + (2 * nx_ + 1) * k2] : 0.0;
  }
  double liner_rate(int a, int m) const { return liner_ ? liner_->rate[a][m] : 0.0; }

  SkirtSpec spec_;
  FiniteSolverOptions options_;
  int nx_ = 0, nz_ = 0;                                  // cells along the axis, around (per arc)
  double dy_ = 0;                                        // m
  std::vector<double> y_c_, y_f_, barrel_c_, barrel_f_;  // centres, the nx + 1 faces (bottom edge first)
  std::vector<double> y_lattice_, barrel_lattice_;       // faces and centres alternating (2 nx + 1)
  std::vector<Arc> arcs_;
  double omega_ref_ = 1, p_ref_ = 1;
  bool has_solution_ = false;
  double p_ref_of_solution_ = 1;
  struct Linearization {  // see linearize()
    bool valid = false;
    std::vector<Eigen::VectorXd> P, r, M;  // per arc: the solution and its mass-balance residual
    double omega_ref = 1, p_ref = 1;
    FilmAssembly scratch;
    Eigen::VectorXd y;
  } linearization_;
};

}  // namespace nvh::bearing
