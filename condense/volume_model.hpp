#pragma once
// The finite-element model of a 3D solid component from a mesh made elsewhere (Abaqus/CalculiX .inp
// with C3D4, C3D10, C3D8 or C3D20 elements): isotropic linear elasticity, consistent mass, supports
// on boxes of nodes. Solid nodes carry translations only; their rotation DOF are inactive. The mass is
// kept as the N x N scalar mass (FeModel::scalar_mass), not as a 6N x 6N matrix.
#include "condense/abaqus_mesh.hpp"
#include "condense/component.hpp"
#include "condense/fe_model.hpp"

namespace nvh::condense {

/// The component's mesh: an .inp read as it is, anything else through gmsh (a .msh read, a geometry
/// meshed). nvh::Error naming the file if it is unreadable or holds no solid element.
Mesh load_volume_mesh(const Component& component);

/// Build the model on a loaded mesh; nvh::Error naming the mesh file, line and element for inverted
/// elements, and the component entry for selectors that take no node, unknown node sets and connection
/// points far from their surface.
/// `form`: how distributing (RBE3) couplings enter (component.hpp, DistributingForm). The library's
/// default is the elimination form; condense_component passes the component's volume.rbe3_form.
FeModel build_volume_model(const Component& component, const Mesh& mesh,
                           DistributingForm form = DistributingForm::kElimination);

/// Both steps.
FeModel build_volume_model(const Component& component,
                           DistributingForm form = DistributingForm::kElimination);

}  // namespace nvh::condense
