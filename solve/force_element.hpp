#pragma once
// Force elements: wrenches on one or more markers, from the markers' motion and the element's own states.
//
// How to add an element (docs/adding-an-element.md has the worked example):
//   1. One file solve/elements/NAME.cpp with a class derived from ForceElement and a function
//      `void register_NAME(ElementRegistry&)` that tells the registry its scene section and type name, the
//      marker keys it reads, its keys for --help, and how to build it from its TOML table.
//   2. One line in solve/elements/builtin.cpp calling register_NAME.
//   3. Its test (tests/solve/) against a closed form, and its row in docs/scene-format.md.
// The model never needs to know the element.
//
// What an element sees (ElementInput): the time, the crank angle, the motion of each of its markers in
// global axes (position, axes, velocity, angular velocity; MarkerMotion in body.hpp), and the values and rates
// of its internal states z, z'. What it returns (ElementOutput): one wrench per marker - a force and a torque in
// global axes acting on that marker's body AT THE MARKER'S ORIGIN - and one residual row per internal state.
// Action and reaction are the element's business: a two-marker element puts (F, T) on marker i and
// (-F, -T - (p_i - p_j) x F) on marker j, which is what `apply_at_i` below does. The model turns wrenches into
// generalized forces by virtual power: Q = Jv^T F + Jw^T T (body.hpp).
//
// Internal states (a Maxwell damper's deflection, a film's fill, a wound-up angle): the element declares them
// (name, unit, differential or algebraic, initial value) and writes their residual rows r(t, y, z, z') = 0.
// They sit in the model's state vector, so the integrators, checkpoints, --restart and the results see them.
//
// Jacobian (optional): d(wrenches, state rows) / d(marker motions, states). The columns per marker are the
// 12 perturbations [dp (3), dtheta (3, a small rotation of the marker frame in global axes: dA = dtheta~ A),
// dv (3), domega (3)], then the states as dF/dz + cj dF/dz', then one column for the crank angle. An element
// without an analytic Jacobian returns false and the model differentiates it locally (its own evaluate()
// around this state, 12 calls per marker plus one per state): cheap, because nothing else is re-evaluated.
//
// Energy (the run's energy balance, /energy in the results): an element reports the energy it stores (J) and
// the power it dissipates (W, >= 0 for a passive element). Sources - loads, motors - say so; the model takes
// their input power as the power of their wrenches on the markers.
//
// Contact events (optional): an element with intermittent contact returns signed gap functions (> 0 open);
// the integrators locate their sign changes, so a contact's onset is a step boundary.
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "solve/body.hpp"

namespace nvh::solve {

/// A force and a torque (global axes) on a body at a marker's origin: N, N m.
struct Wrench {
  Vec3 force = Vec3::Zero();
  Vec3 torque = Vec3::Zero();
};

/// An output channel of an element: its name in the results file and its unit.
struct Channel {
  std::string name;
  std::string unit;
};

/// An internal state of an element.
struct StateDefinition {
  std::string name;
  std::string unit;
  bool differential = true;  // false: algebraic (no rate in its residual row)
  double initial = 0.0;
  bool velocity = false;  // a mass's velocity (m/s, rad/s): the integrators give it `velocity_atol`
};

struct ElementInput {
  double time = 0;         // s
  double crank_angle = 0;  // rad, unwrapped, from the scene's clock (0 without a clock)
  std::span<const MarkerMotion> markers;
  std::span<const double> z;   // internal states
  std::span<const double> zp;  // their rates
};

struct ElementOutput {
  std::span<Wrench> wrenches;        // one per marker, zeroed by the caller
  std::span<double> state_residual;  // one per internal state
};

/// Rows: 6 per marker (force, torque), then one per state. Columns: 12 per marker (dp, dtheta, dv, domega),
/// then one per state (d/dz + cj d/dz'), then the crank angle. Zeroed by the caller.
struct ElementJacobian {
  double cj = 0;
  Eigen::Ref<Eigen::MatrixXd> matrix;
  static constexpr int kMarkerColumns = 12;
  int state_column(int markers, int s) const { return kMarkerColumns * markers + s; }
  int crank_column() const { return static_cast<int>(matrix.cols()) - 1; }
};

/// Three rows of an element Jacobian (d force or d torque by the columns above) on the stack: elements with up
/// to 64 columns (five markers) build their rows without touching the heap.
using ElementRows = Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::ColMajor, 3, 64>;
inline ElementRows zero_rows(const ElementJacobian& j) { return ElementRows::Zero(3, j.matrix.cols()); }

struct ElementEnergy {
  double stored = 0;       // J
  double dissipated = 0;   // W, power turned into heat
};

class ForceElement {
 public:
  virtual ~ForceElement() = default;
  virtual std::string type() const = 0;
  /// How many markers it acts on (the scene reader checks that it got as many).
  virtual int marker_count() const = 0;
  virtual std::vector<StateDefinition> states() const { return {}; }

  virtual void evaluate(const ElementInput& in, ElementOutput& out) const = 0;
  /// The analytic Jacobian; false: the model differentiates evaluate() locally.
  virtual bool jacobian(const ElementInput&, ElementJacobian&) const { return false; }
  /// True if evaluate() reads the crank angle (the model then couples the element to the clock).
  virtual bool uses_crank_angle() const { return false; }

  /// The results' /forces/<name>/force and torque: the sum of the wrenches of the first resultant_markers()
  /// markers, moved to marker 0's origin (1: marker i's wrench; a many-point element: all on the points' body).
  virtual int resultant_markers() const { return 1; }

  virtual std::vector<Channel> channels() const { return {}; }
  virtual void channel_values(const ElementInput&, std::span<double>) const {}

  /// Stored energy and dissipated power; a source (is_source) does work on the system instead.
  virtual ElementEnergy energy(const ElementInput&) const { return {}; }
  virtual bool is_source() const { return false; }

  /// Signed gaps (m; > 0 open, < 0 in contact) whose sign changes the integrator locates.
  virtual int gap_count() const { return 0; }
  virtual void gaps(const ElementInput&, std::span<double>) const {}
};

/// A two-marker element's force F and torque T on body i, with the opposite on body j: action = reaction,
/// momentum conserved. F acts at `point` (global); both wrenches are moved to their markers' origins.
inline void apply_at_i(const ElementInput& in, ElementOutput& out, const Vec3& force, const Vec3& torque,
                       const Vec3& point) {
  const Vec3& pi = in.markers[0].position;
  out.wrenches[0].force = force;
  out.wrenches[0].torque = torque + (point - pi).cross(force);
  if (out.wrenches.size() > 1) {
    const Vec3& pj = in.markers[1].position;
    out.wrenches[1].force = -force;
    out.wrenches[1].torque = -torque - (point - pj).cross(force);
  }
}

}  // namespace nvh::solve

namespace nvh::solve {

/// The Jacobian rows of `apply_at_i` (point = marker i's origin) from dF and dT (3 x columns, the columns of
/// ElementJacobian): marker i gets (dF, dT); marker j gets (-dF, -dT - d~ dF + F~ (dp_i - dp_j)), d = p_i - p_j.
void jacobian_at_i(const ElementInput& in, ElementJacobian& jac, const Eigen::Ref<const Eigen::MatrixXd>& d_force,
                   const Eigen::Ref<const Eigen::MatrixXd>& d_torque, const Vec3& force);

}  // namespace nvh::solve
