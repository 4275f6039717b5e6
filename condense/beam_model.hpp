#pragma once
// The finite-element model of a structured beam component: Timoshenko beam elements along the polyline
// of stations, point masses, rigid links (slave nodes tied to a master station) and supports.
#include "condense/component.hpp"
#include "condense/fe_model.hpp"

namespace nvh::condense {

/// Build the model; nvh::Error (with the input location) for a point that is not on the model, a
/// support on a rigid-link end, and similar.
FeModel build_beam_model(const Component& component);

}  // namespace nvh::condense
