#pragma once
// The journal bearing force element: solve/bearing's film models between two markers (journal i, shell j).
//
// Marker j is the shell centre, its z axis the bearing axis; marker i is the journal centre. Per call:
//   e      = (x_j . d, y_j . d),            d = p_i - p_j          (m, shell axes)
//   e_dot  = (x_j . d', y_j . d'),          d' = v_i - v_j         (m/s: the rate seen from a non-rotating
//                                                                   frame, on the shell axes; bearing.hpp)
//   omega_journal = z_j . omega_i,  omega_shell = z_j . omega_j     (rad/s, absolute)
// and the film force F (shell axes) acts on the journal at p_i, in global axes x_j Fx + y_j Fy, with the
// journal's friction torque Tj z_j. Body j receives -F at p_i and -Tj z_j, which is the film's torque on the
// shell about its own centre, Ts = -Tj - (e x F)_z (momentum balance of the film, docs/bearing.md).
// Tilt of the journal against the shell (misalignment) is not modelled: only the projection on the shell's
// x-y plane counts.
//
// Warm start: the finite model starts each Newton solve from the solution of the previous call (whatever
// state it was called with, including the integrator's perturbed states for its finite-difference Jacobian)
// and iterates to its tolerance, so the warm start is a starting guess only: the result is the solution of
// the discrete film equations at this state, independent of the call order to within the Newton tolerance
// (test WarmStartDoesNotDependOnHistory). A repeated call at the same state returns the cached result.
//
// Jacobian: the film force's derivatives by (e, de/dt) come from the bearing model itself (the finite model's
// implicit-function Jacobian, the closed forms' own); those by the two surface speeds and the torque's by six
// further film evaluations (forward differences, warm-started). Marker axes enter through e = A_j^T d: a small
// rotation dtheta of marker j changes x_j . d by (x_j x d) . dtheta.
//
// Failures inside a time step (|e| >= c, or a finite-bearing Newton solve that does not converge) return a
// non-finite force: the integrator treats that as a recoverable residual failure and cuts the step.
#include <memory>
#include <optional>

#include "common/input.hpp"
#include "solve/bearing/journal_bearing.hpp"
#include "solve/force_element.hpp"

namespace nvh::solve {

class JournalBearingElement final : public ForceElement {
 public:
  /// The finite film's Newton tolerance in a time integration (`film_tolerance`): 1e-8 of the peak pressure,
  /// a hundredth of the default rtol 1e-6 (the film's own default, 1e-9, is for characteristics).
  static constexpr double kFilmTolerance = 1e-8;
  explicit JournalBearingElement(bearing::BearingSpec spec, double film_tolerance = kFilmTolerance);
  std::string type() const override { return "journal-bearing"; }
  int marker_count() const override { return 2; }
  void evaluate(const ElementInput& in, ElementOutput& out) const override;
  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override;
  /// eccentricity_ratio, attitude_angle, min_film, max_pressure, friction_torque, power_loss, oil_flow (side flow
  /// through both edges).
  std::vector<Channel> channels() const override;
  void channel_values(const ElementInput& in, std::span<double> out) const override;
  /// The film's power loss is dissipated; a film stores no energy.
  ElementEnergy energy(const ElementInput& in) const override;

  /// The film kinematics this element sees between the two markers (see the top of this file).
  static bearing::Kinematics kinematics(const MarkerMotion& i, const MarkerMotion& j);
  /// The film result at these markers (cached for a repeated state); the force is NaN on failure.
  const bearing::FilmResult& film(const MarkerMotion& i, const MarkerMotion& j,
                                  bearing::Detail detail = bearing::Detail::kFull) const;
  const bearing::FilmResult& film(const bearing::Kinematics& k, bearing::Detail detail = bearing::Detail::kFull) const;
  const bearing::JournalBearing& bearing() const { return bearing_; }

 private:
  mutable bearing::JournalBearing bearing_;  // mutable: the finite model's warm-start state
  // The last two film results: the model's Jacobian perturbs a body and returns to the state before (the
  // radial direction of Euler parameters is differenced), and the second entry turns that return into a hit.
  struct CachedFilm {
    std::optional<bearing::Kinematics> kinematics;
    bearing::FilmResult result;
    bearing::Detail detail = bearing::Detail::kForces;
  };
  CachedFilm* cached(const bearing::Kinematics& k, bearing::Detail detail) const;
  /// The film result with the finite model's Jacobian exact at this state (it may refactorize once).
  const bearing::FilmResult& film_with_jacobian(const bearing::Kinematics& k) const;
  mutable CachedFilm cache_[2];
  mutable int newest_ = 0;  // index of the most recent entry of cache_
};


}  // namespace nvh::solve
