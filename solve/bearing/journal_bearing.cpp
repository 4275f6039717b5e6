#include "solve/bearing/journal_bearing.hpp"

#include "solve/bearing/long_bearing.hpp"
#include "solve/bearing/short_bearing.hpp"

namespace nvh::bearing {

JournalBearing::JournalBearing(BearingSpec spec, FiniteSolverOptions options) : spec_(std::move(spec)) {
  validate(spec_);
  if (spec_.model == Model::kFinite) finite_.emplace(spec_, options);
}

FilmResult JournalBearing::evaluate(const Kinematics& k, Detail detail) {
  switch (spec_.model) {
    case Model::kShort:
      return evaluate_short(spec_, k, detail);
    case Model::kLong:
      return evaluate_long(spec_, k);
    case Model::kFinite:
      break;
  }
  return finite_->evaluate(k, detail);
}

FilmResult JournalBearing::evaluate_with_jacobian(const Kinematics& k, Detail detail) {
  return finite_ ? finite_->evaluate_with_jacobian(k, detail) : evaluate(k, detail);
}

}  // namespace nvh::bearing
