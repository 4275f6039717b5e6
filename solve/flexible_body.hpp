#pragma once
// Flexible bodies in a floating frame of reference, from condense's superelements.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "common/input.hpp"
#include "solve/body.hpp"

namespace nvh::solve {

/// Build a flexible body from a scene's [[body]] table with type = "flexible" (keys read from `t`; the
/// caller calls t.finish()). `base` is the scene's folder; the superelement file is appended to `inputs`.
std::unique_ptr<Body> make_flexible_body(const input::Table& t, const std::string& name, const InitialState& init,
                                         const std::filesystem::path& base,
                                         std::vector<std::filesystem::path>& inputs);

}  // namespace nvh::solve
