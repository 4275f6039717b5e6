#pragma once
// Hydrodynamic journal bearings: the data every model shares.
//
// Frame: the shell's axes, z along the bearing axis, x and y across it. The journal centre sits at
// e = (ex, ey) from the shell centre; the film thickness at the shell angle theta (from x towards y) is
//   h(theta) = c - ex cos(theta) - ey sin(theta)                       (c: radial clearance)
// so the thinnest film lies in the direction of e. de/dt is the rate of e as seen from a non-rotating
// frame (components on the shell's axes at this instant); omega_journal and omega_shell are the absolute
// angular speeds of the two surfaces about z. With these inputs the Reynolds equation holds in its usual
// form with the mean surface speed U = R (omega_journal + omega_shell) / 2 (wedge) and dh/dt = -de/dt . n
// (squeeze), n = (cos theta, sin theta); see docs/bearing.md.
//
// Units SI: m, m/s, rad/s, Pa, Pa s, N, N m, W, m^3/s.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace nvh::bearing {

enum class Model { kShort, kLong, kFinite };
/// How the finite bearing treats sub-ambient pressure.
enum class Cavitation {
  kJfo,           ///< mass-conserving Jakobsson-Floberg-Olsson / Elrod: p >= 0, fill ratio < 1 where p = 0
  kSwiftStieber,  ///< Reynolds (Swift-Stieber) condition: p >= 0 only, mass not conserved in the rupture zone
  kNone           ///< full film, negative pressure kept (full Sommerfeld); for verification
};

/// An oil feed hole in the shell: a circle on the developed shell surface held at the supply pressure.
struct FeedHole {
  double angle = 0;           ///< rad, position of the centre on the shell (from x towards y)
  double axial_position = 0;  ///< m, from the bearing's mid-plane
  double diameter = 0;        ///< m
};

/// A groove held at the supply pressure: circumferential (a band of the width around an arc of the shell)
/// or axial (a strip of an angular width along part of the width).
struct Groove {
  enum class Kind { kCircumferential, kAxial };
  Kind kind = Kind::kCircumferential;
  double axial_position = 0;  ///< m, centre line from the mid-plane
  double width = 0;           ///< m, axial extent (circumferential groove)
  double arc_start = 0;       ///< rad, circumferential groove: start of the arc (default full circle)
  double arc_end = 0;         ///< rad, end of the arc; arc_end - arc_start = 2 pi for a full groove
  double angle = 0;           ///< rad, axial groove: centre angle
  double angular_width = 0;   ///< rad, axial groove: angular extent
  double length = 0;          ///< m, axial groove: axial length (centred on axial_position)
};

/// Geometry, oil and numerical model of one bearing (read from TOML by read_bearing, bearing_reader.hpp).
struct BearingSpec {
  std::string name = "bearing";
  Model model = Model::kFinite;
  double diameter = 0;          ///< m, journal diameter D = 2 R
  double width = 0;             ///< m, bearing width L
  double radial_clearance = 0;  ///< m, c
  double viscosity = 0;         ///< Pa s, at ambient pressure (mu0)
  double barus = 0;             ///< 1/Pa, pressure-viscosity coefficient: mu = mu0 exp(barus p)
  double supply_pressure = 0;   ///< Pa (gauge), at feed holes and grooves
  Cavitation cavitation = Cavitation::kJfo;
  int cells_around = 60;  ///< finite bearing: cells around the circumference
  int cells_across = 20;  ///< finite bearing: cells across the width
  std::vector<FeedHole> holes;
  std::vector<Groove> grooves;

  double radius() const { return 0.5 * diameter; }
};

/// The motion the film sees (see the frame convention at the top of this file).
struct Kinematics {
  Eigen::Vector2d e = Eigen::Vector2d::Zero();      ///< m, journal centre from shell centre
  Eigen::Vector2d e_dot = Eigen::Vector2d::Zero();  ///< m/s
  double omega_journal = 0;                         ///< rad/s
  double omega_shell = 0;                           ///< rad/s
};

/// How much of FilmResult an evaluation fills: everything, or the forces, torques, power loss and Jacobian
/// alone (the short bearing's peak-pressure search is most of its cost, the finite film's flows one assembly
/// more, and only output channels need them).
enum class Detail { kFull, kForces };

/// What one evaluation of the film returns.
struct FilmResult {
  Eigen::Vector2d force = Eigen::Vector2d::Zero();  ///< N, film force on the journal (the shell gets -force)
  double torque_journal = 0;      ///< N m about z, friction torque of the film on the journal
  double torque_shell = 0;        ///< N m about z, on the shell (about its centre)
  double min_film = 0;            ///< m
  double min_film_angle = 0;      ///< rad, shell angle of the minimum film
  double max_pressure = 0;        ///< Pa
  double max_pressure_angle = 0;  ///< rad
  double side_flow = 0;           ///< m^3/s, leaving through both edges
  double feed_flow = 0;           ///< m^3/s, entering through holes and grooves (0 without them)
  double power_loss = 0;          ///< W, mechanical power into the film: -(Tj wj + Ts ws + F . de/dt)
  /// d(force)/d(ex, ey, ex_dot, ey_dot): columns 0-1 in N/m, 2-3 in N s/m.
  Eigen::Matrix<double, 2, 4> jacobian = Eigen::Matrix<double, 2, 4>::Zero();
  /// When `has_full_jacobian` (the finite bearing, by the implicit function theorem): d(Fx, Fy, torque_journal)
  /// / d(ex, ey, ex_dot, ey_dot, omega_journal, omega_shell), N/m, N s/m, N s/rad; N m/m, N m s/m, N m s/rad.
  /// Closed-form models leave it empty: their users difference the torque and the speeds, which is cheap.
  bool has_full_jacobian = false;
  Eigen::Matrix<double, 3, 6> full_jacobian = Eigen::Matrix<double, 3, 6>::Zero();
  int iterations = 0;  ///< finite bearing: Newton iterations of this evaluation (0 for closed forms)
  int factorizations = 0;  ///< finite bearing: of them, the ones that factorized (the rest reused one)
};

/// Bounds of the finite bearing's grid: cells in one direction, and in all (the film's sparse Jacobian has
/// about 5 non-zeros per cell; 1e6 cells are some 1 GB in KLU, far beyond any converged grid).
inline constexpr int kMaxCellsPerDirection = 100000;
inline constexpr std::int64_t kMaxCells = 1000000;

/// Throws nvh::Error if the spec is not usable (clearance <= 0, viscosity <= 0, a number that is not finite,
/// a grid beyond the bounds above, ...), naming the field.
void validate(const BearingSpec& spec);

/// Throws nvh::Error if |e| >= c: the journal would touch the shell; the hydrodynamic models end there.
void check_eccentricity(const BearingSpec& spec, const Kinematics& k);

/// The minimum film from the geometry alone (shared by all models).
void set_min_film(const BearingSpec& spec, const Kinematics& k, FilmResult& r);

}  // namespace nvh::bearing
