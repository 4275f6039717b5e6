#pragma once
// The registration functions of the element types shipped with solve, one per element file.
#include "solve/element_registry.hpp"

namespace nvh::solve {

void register_spring_damper(ElementRegistry&);
void register_maxwell(ElementRegistry&);
void register_mass_chain(ElementRegistry&);  // mass-chain and valve-spring
void register_bushing(ElementRegistry&);
void register_bearing_spring(ElementRegistry&);
void register_torsional_spring_damper(ElementRegistry&);
void register_contact(ElementRegistry&);
void register_point_set_contact(ElementRegistry&);
void register_table_force(ElementRegistry&);
void register_motor(ElementRegistry&);
void register_loads(ElementRegistry&);
void register_journal_bearing(ElementRegistry&);
void register_roller_cam(ElementRegistry&);
void register_flat_face_cam(ElementRegistry&);
void register_valve_seat(ElementRegistry&);
void register_piston_liner(ElementRegistry&);

}  // namespace nvh::solve
