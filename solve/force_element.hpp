#pragma once
// Force elements: forces and torques between two markers, from the markers' motion alone.
//
// An element sees only the motion of its markers i and j (global axes) and returns the force and torque it
// applies to body i at a point; body j receives the opposite force at the same point and the opposite torque
// (action = reaction; momentum is conserved). The model turns them into generalized forces by virtual power
// (body.hpp). An element never touches the integrator. Elements with one marker (loads) have no body j.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "solve/body.hpp"

namespace nvh::solve {

struct ForceContext {
  double time = 0;         // s
  double crank_angle = 0;  // rad, unwrapped, from the scene's clock (0 without a clock)
};

struct ElementForce {
  Vec3 force = Vec3::Zero();   // N, on body i, global axes
  Vec3 torque = Vec3::Zero();  // N m, on body i, global axes
  Vec3 point = Vec3::Zero();   // m, where the force acts (global)
};

class ForceElement {
 public:
  virtual ~ForceElement() = default;
  virtual std::string type() const = 0;
  /// Forces on body i (body j gets the opposite).
  virtual ElementForce evaluate(const ForceContext& c, const MarkerMotion& i, const MarkerMotion& j) const = 0;
  /// Extra scalar output channels (name with unit suffix, e.g. "deflection_m") and their values.
  virtual std::vector<std::string> channel_names() const { return {}; }
  virtual void channels(const ForceContext&, const MarkerMotion&, const MarkerMotion&, std::span<double>) const {}
};

}  // namespace nvh::solve
