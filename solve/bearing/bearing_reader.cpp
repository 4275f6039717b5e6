#include "solve/bearing/bearing_reader.hpp"

#include <numbers>

namespace nvh::bearing {

namespace {
constexpr double kDeg = std::numbers::pi / 180;
}

BearingSpec read_bearing(const input::Table& t) {
  using input::Range;
  BearingSpec s;
  s.name = t.optional_string("name").value_or(t.path().empty() ? "bearing" : t.path());
  const std::string model = t.optional_choice("model", {"short", "long", "finite"}).value_or("finite");
  s.model = model == "short" ? Model::kShort : model == "long" ? Model::kLong : Model::kFinite;
  s.diameter = t.number("diameter", Range::positive());
  s.width = t.number("width", Range::positive());
  s.radial_clearance = t.number("radial_clearance", Range::positive());
  if (s.radial_clearance >= 0.5 * s.diameter) {
    t.fail("radial_clearance", "expected a clearance smaller than the radius (" +
                                   std::to_string(0.5 * s.diameter) + " m); got " +
                                   std::to_string(s.radial_clearance) + " m");
  }
  s.viscosity = t.number("viscosity", Range::positive());
  s.barus = t.number_or("barus", 0.0, Range::non_negative());
  s.supply_pressure = t.number_or("supply_pressure", 0.0, Range::non_negative());
  const std::string cavitation =
      t.optional_choice("cavitation", {"jfo", "swift-stieber", "none"}).value_or("jfo");
  s.cavitation = cavitation == "jfo"             ? Cavitation::kJfo
                 : cavitation == "swift-stieber" ? Cavitation::kSwiftStieber
                                                 : Cavitation::kNone;
  if (t.has("grid")) {
    const std::vector<std::int64_t> grid = t.integers("grid", Range::at_least(1));
    if (grid.size() != 2 || grid[0] < 8) {
      t.fail("grid", "expected two integers [cells around >= 8, cells across >= 1], e.g. grid = [60, 20]");
    }
    s.cells_around = static_cast<int>(grid[0]);
    s.cells_across = static_cast<int>(grid[1]);
  }
  for (const input::Table& h : t.table_array("hole")) {
    FeedHole hole;
    hole.angle = h.number("angle_deg") * kDeg;
    hole.axial_position = h.number_or("axial_position", 0.0);
    hole.diameter = h.number("diameter", Range::positive());
    h.finish();
    s.holes.push_back(hole);
  }
  for (const input::Table& g : t.table_array("groove")) {
    Groove groove;
    const std::string kind = g.choice("kind", {"circumferential", "axial"});
    groove.axial_position = g.number_or("axial_position", 0.0);
    if (kind == "circumferential") {
      groove.kind = Groove::Kind::kCircumferential;
      groove.width = g.number("width", Range::positive());
      groove.arc_start = g.number_or("arc_start_deg", 0.0) * kDeg;
      groove.arc_end = g.number_or("arc_end_deg", 360.0) * kDeg;
      if (groove.arc_end <= groove.arc_start) g.fail("arc_end_deg", "expected arc_end_deg > arc_start_deg");
    } else {
      groove.kind = Groove::Kind::kAxial;
      groove.angle = g.number("angle_deg") * kDeg;
      groove.angular_width = g.number("angular_width_deg", Range::positive()) * kDeg;
      groove.length = g.number("length", Range::positive());
    }
    g.finish();
    s.grooves.push_back(groove);
  }
  validate(s);
  return s;
}

}  // namespace nvh::bearing
