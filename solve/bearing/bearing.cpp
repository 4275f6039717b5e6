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
  // Specs built in code (tests, tools) come here without the reader's ranges: refuse what is not finite too.
  using std::isfinite;
  require(s.diameter > 0 && isfinite(s.diameter), s, "diameter", "a finite number > 0 (m)", s.diameter);
  require(s.width > 0 && isfinite(s.width), s, "width", "a finite number > 0 (m)", s.width);
  require(s.radial_clearance > 0, s, "radial_clearance", "a number > 0 (m)", s.radial_clearance);
  require(s.radial_clearance < 0.5 * s.diameter, s, "radial_clearance", "a clearance smaller than the radius",
          s.radial_clearance);
  require(s.viscosity > 0 && isfinite(s.viscosity), s, "viscosity", "a finite number > 0 (Pa s)",
          s.viscosity);
  require(s.barus >= 0 && isfinite(s.barus), s, "barus", "a finite number >= 0 (1/Pa)", s.barus);
  require(s.supply_pressure >= 0 && isfinite(s.supply_pressure), s, "supply_pressure",
          "a finite number >= 0 (Pa, gauge)", s.supply_pressure);
  if (s.model == Model::kFinite) {
    require(s.cells_around >= 8 && s.cells_around <= kMaxCellsPerDirection, s, "grid[0] (cells around)",
            "an integer in [8, " + std::to_string(kMaxCellsPerDirection) + "]", s.cells_around);
    require(s.cells_across >= 1 && s.cells_across <= kMaxCellsPerDirection, s, "grid[1] (cells across)",
            "an integer in [1, " + std::to_string(kMaxCellsPerDirection) + "]", s.cells_across);
    require(std::int64_t{s.cells_around} * s.cells_across <= kMaxCells, s, "grid (cells around x across)",
            "at most " + std::to_string(kMaxCells) + " cells", double(s.cells_around) * s.cells_across);
  }
  for (const FeedHole& h : s.holes) {
    require(isfinite(h.angle), s, "hole angle", "a finite angle", h.angle);
    require(isfinite(h.axial_position), s, "hole axial_position", "a finite position (m)", h.axial_position);
    require(h.diameter > 0 && isfinite(h.diameter), s, "hole diameter", "a finite number > 0 (m)",
            h.diameter);
  }
  for (const Groove& g : s.grooves) {
    for (const double x :
         {g.axial_position, g.width, g.arc_start, g.arc_end, g.angle, g.angular_width, g.length})
      require(isfinite(x), s, "groove", "finite positions, angles and sizes", x);
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
