// Every element type shipped with solve: one line per element file (force_element.hpp: how to add one).
#include "solve/elements/builtin.hpp"

namespace nvh::solve {

const ElementRegistry& builtin_elements() {
  static const ElementRegistry registry = [] {
    ElementRegistry r;
    register_spring_damper(r);
    register_maxwell(r);
    register_mass_chain(r);
    register_bushing(r);
    register_bearing_spring(r);
    register_torsional_spring_damper(r);
    register_contact(r);
    register_point_set_contact(r);
    register_table_force(r);
    register_motor(r);
    register_loads(r);
    register_journal_bearing(r);
    register_roller_cam(r);
    register_flat_face_cam(r);
    register_valve_seat(r);
    register_piston_liner(r);
    return r;
  }();
  return registry;
}

}  // namespace nvh::solve
