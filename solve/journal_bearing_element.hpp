#pragma once
// The journal bearing force element: solve/bearing's models between two markers (journal i, shell j).
#include <memory>

#include "common/input.hpp"
#include "solve/force_element.hpp"

namespace nvh::solve {

/// Build from a scene's [[force]] table with type = "journal-bearing" (bearing keys as in docs/bearing.md);
/// the caller calls t.finish().
std::unique_ptr<ForceElement> make_journal_bearing(const input::Table& t);

}  // namespace nvh::solve
