#pragma once
// One journal bearing of any model behind one call: what solve's force element holds.
//
//   nvh::bearing::JournalBearing b(spec);          // spec from read_bearing (bearing_reader.hpp)
//   FilmResult r = b.evaluate({e, e_dot, wj, ws});  // force on the journal, torques, flows, Jacobian
//
// The finite model keeps its last solution inside the object to warm-start the next call; copies are
// independent (value semantics).
#include <optional>

#include "solve/bearing/bearing.hpp"
#include "solve/bearing/finite_bearing.hpp"

namespace nvh::bearing {

class JournalBearing {
 public:
  /// Validates the spec (nvh::Error naming the field).
  explicit JournalBearing(BearingSpec spec, FiniteSolverOptions options = {});
  FilmResult evaluate(const Kinematics& k, Detail detail = Detail::kFull);
  /// As evaluate, with the finite model's Jacobian exact at the solution (FiniteBearing::evaluate_with_jacobian).
  FilmResult evaluate_with_jacobian(const Kinematics& k, Detail detail = Detail::kForces);
  const BearingSpec& spec() const { return spec_; }
  /// The finite model's solver (pressure field, fill ratio), or nullptr for the closed forms.
  const FiniteBearing* finite() const { return finite_ ? &*finite_ : nullptr; }
  FiniteBearing* finite() { return finite_ ? &*finite_ : nullptr; }

 private:
  BearingSpec spec_;
  std::optional<FiniteBearing> finite_;
};

}  // namespace nvh::bearing
