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
  explicit JournalBearingElement(bearing::BearingSpec spec);
  std::string type() const override { return "journal-bearing"; }
  ElementForce evaluate(const ForceContext& c, const MarkerMotion& i, const MarkerMotion& j) const override;
  /// eccentricity_ratio, attitude_angle_rad, min_film_m, max_pressure_pa, friction_torque_nm, power_loss_w,
  /// oil_flow_m3_s (side flow through both edges).
  std::vector<std::string> channel_names() const override;
  void channels(const ForceContext& c, const MarkerMotion& i, const MarkerMotion& j,
                std::span<double> out) const override;

  /// The film kinematics this element sees between the two markers (see the top of this file).
  static bearing::Kinematics kinematics(const MarkerMotion& i, const MarkerMotion& j);
  /// The film result at these markers (cached for a repeated state); the force is NaN on failure.
  const bearing::FilmResult& film(const MarkerMotion& i, const MarkerMotion& j) const;
  const bearing::JournalBearing& bearing() const { return bearing_; }

 private:
  mutable bearing::JournalBearing bearing_;  // mutable: the finite model's warm-start state
  mutable std::optional<bearing::Kinematics> last_kinematics_;
  mutable bearing::FilmResult last_result_;
};

/// Build from a scene's [[force]] table with type = "journal-bearing" (bearing keys as in docs/bearing.md,
/// read by bearing::read_bearing); the caller calls t.finish().
std::unique_ptr<ForceElement> make_journal_bearing(const input::Table& t);

}  // namespace nvh::solve
