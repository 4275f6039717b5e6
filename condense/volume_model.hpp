#pragma once
// The finite-element model of a 3D solid component from a mesh made elsewhere (Abaqus/CalculiX .inp
// with C3D4, C3D10, C3D8 or C3D20 elements): isotropic linear elasticity, consistent mass, supports
// on boxes of nodes. Solid nodes carry translations only; their rotation DOF are inactive.
#include "condense/component.hpp"
#include "condense/fe_model.hpp"

namespace nvh::condense {

/// Build the model; nvh::Error naming the mesh file, line and element for unreadable meshes and
/// inverted elements, and the component entry for supports that hold nothing.
FeModel build_volume_model(const Component& component);

}  // namespace nvh::condense
