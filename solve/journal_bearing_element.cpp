#include "solve/journal_bearing_element.hpp"

namespace nvh::solve {

std::unique_ptr<ForceElement> make_journal_bearing(const input::Table& t) {
  t.fail("type", "journal bearings are not yet connected to solve in this build");
}

}  // namespace nvh::solve
