#pragma once
// Reading COMPONENT.toml into a validated Component. Every error names the file, line, column and key
// and says what was expected; unknown keys are errors with a did-you-mean. Format: docs/component-format.md.
#include <filesystem>
#include <string>

#include "condense/component.hpp"

namespace nvh::condense {

Component read_component(const std::filesystem::path& file);
/// The same from text (tests); `name` stands for the file name in messages.
Component parse_component(const std::string& text, const std::string& name);

/// "x y z rx ry rz" (any subset, any order, or "all") -> mask; nvh::Error naming the bad word.
std::array<bool, 6> parse_dof_list(const std::string& text);

}  // namespace nvh::condense
