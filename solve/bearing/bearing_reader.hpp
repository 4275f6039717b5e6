#pragma once
// Reading a bearing from TOML (keys, units and defaults in docs/bearing.md, section "Input").
//
// read_bearing takes any table that describes one bearing - the [bearing] table of a bearing-map file or a
// [[force]] entry of type "journal-bearing" in a scene - and marks the keys it reads as known. It does not
// call finish(): the caller reads its own keys (markers, type, ...) and then calls finish(), so unknown keys
// are reported once, with did-you-mean, against all accepted keys.
#include "common/input.hpp"
#include "solve/bearing/bearing.hpp"

namespace nvh::bearing {

/// Errors (nvh::Error) name the file, line, key and what was expected: clearance <= 0, viscosity <= 0,
/// a clearance not smaller than the radius, an unknown model, a grid that is not two integers >= 8 and >= 1.
BearingSpec read_bearing(const input::Table& table);

}  // namespace nvh::bearing
