#include "solve/bearing/bearing.hpp"

#include <cmath>
#include <sstream>

#include "common/error.hpp"

namespace nvh::bearing {

namespace {
void require(bool ok, const BearingSpec& s, const std::string& field, const std::string& expected,
             double value) {
  if (ok) return;
  std::ostringstream msg;
  msg << "bearing '" << s.name << "': " << field << " = " << value << " is not usable; expected " << expected;
  throw Error(msg.str());
}
}  // namespace

void validate(const BearingSpec& s) {
  require(s.diameter > 0, s, "diameter", "a number > 0 (m)", s.diameter);
  require(s.width > 0, s, "width", "a number > 0 (m)", s.width);
  require(s.radial_clearance > 0, s, "radial_clearance", "a number > 0 (m)", s.radial_clearance);
  require(s.radial_clearance < 0.5 * s.diameter, s, "radial_clearance", "a clearance smaller than the radius",
          s.radial_clearance);
  require(s.viscosity > 0, s, "viscosity", "a number > 0 (Pa s)", s.viscosity);
  require(s.barus >= 0, s, "barus", "a number >= 0 (1/Pa)", s.barus);
  require(s.supply_pressure >= 0, s, "supply_pressure", "a number >= 0 (Pa, gauge)", s.supply_pressure);
  if (s.model == Model::kFinite) {
    require(s.cells_around >= 8, s, "grid[0] (cells around)", "an integer >= 8", s.cells_around);
    require(s.cells_across >= 1, s, "grid[1] (cells across)", "an integer >= 1", s.cells_across);
  }
}

void check_eccentricity(const BearingSpec& s, const Kinematics& k) {
  const double eps = k.e.norm() / s.radial_clearance;
  if (eps < 1 && std::isfinite(eps)) return;
  std::ostringstream msg;
  msg << "bearing '" << s.name << "': eccentricity ratio |e|/c = " << eps << " (e = (" << k.e.x() << ", "
      << k.e.y() << ") m, c = " << s.radial_clearance
      << " m); expected < 1: the journal touches the shell, where the hydrodynamic film model ends";
  throw Error(msg.str());
}

void set_min_film(const BearingSpec& s, const Kinematics& k, FilmResult& r) {
  r.min_film = s.radial_clearance - k.e.norm();
  r.min_film_angle = k.e.norm() > 0 ? std::atan2(k.e.y(), k.e.x()) : 0.0;
}

}  // namespace nvh::bearing
