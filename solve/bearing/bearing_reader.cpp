#include "solve/bearing/bearing_reader.hpp"

#include <numbers>
#include <string>

namespace nvh::bearing {

namespace {
constexpr double kDeg = std::numbers::pi / 180;
}

BearingSpec read_bearing(const input::Table& t) {
  using input::Range;
  // Physical ranges, generous by orders of magnitude around real bearings (docs/bearing.md section 6): beyond
  // them the film's scales (p_ref = 12 mu R^2 omega / c^2, exp(barus p), cells of width / cells_across)
  // overflow or underflow and the results are NaN, not a bearing.
  BearingSpec s;
  s.name = t.optional_string("name").value_or(t.path().empty() ? "bearing" : t.path());
  const std::string model = t.optional_choice("model", {"short", "long", "finite"}).value_or("finite");
  s.model = model == "short" ? Model::kShort : model == "long" ? Model::kLong : Model::kFinite;
  s.diameter = t.number("diameter", Range::closed(1e-4, 10.0));
  s.width = t.number("width", Range::closed(1e-5, 10.0));
  s.radial_clearance = t.number("radial_clearance", Range::at_least(1e-8));
  if (s.radial_clearance >= 0.5 * s.diameter) {
    t.fail("radial_clearance", "expected a clearance smaller than the radius (" +
                                   std::to_string(0.5 * s.diameter) + " m); got " +
                                   std::to_string(s.radial_clearance) + " m");
  }
  s.viscosity = t.number("viscosity", Range::closed(1e-6, 1e5));
  s.barus = t.number_or("barus", 0.0, Range::closed(0.0, 1e-7));
  s.supply_pressure = t.number_or("supply_pressure", 0.0, Range::closed(0.0, 1e8));
  const std::string cavitation =
      t.optional_choice("cavitation", {"jfo", "swift-stieber", "none"}).value_or("jfo");
  s.cavitation = cavitation == "jfo"             ? Cavitation::kJfo
                 : cavitation == "swift-stieber" ? Cavitation::kSwiftStieber
                                                 : Cavitation::kNone;
  if (t.has("grid")) {
    const std::vector<std::int64_t> grid = t.integers("grid", Range::closed(1, kMaxCellsPerDirection));
    if (grid.size() != 2 || grid[0] < 8) {
      t.fail("grid", "expected two integers [cells around >= 8, cells across >= 1], e.g. grid = [60, 20]");
    }
    if (grid[0] * grid[1] > kMaxCells) {
      t.fail("grid", "expected at most " + std::to_string(kMaxCells) + " cells (around x across), got " +
                         std::to_string(grid[0] * grid[1]));
    }
    s.cells_around = static_cast<int>(grid[0]);
    s.cells_across = static_cast<int>(grid[1]);
  }
  // Positions on the shell: angles within a turn either way, axial positions within the width.
  const Range angle = Range::closed(-360.0, 360.0);
  const Range axial = Range::closed(-0.5 * s.width, 0.5 * s.width);
  for (const input::Table& h : t.table_array("hole")) {
    FeedHole hole;
    hole.angle = h.number("angle_deg", angle) * kDeg;
    hole.axial_position = h.number_or("axial_position", 0.0, axial);
    hole.diameter = h.number("diameter", Range{0.0, 10.0, true, false});
    h.finish();
    s.holes.push_back(hole);
  }
  for (const input::Table& g : t.table_array("groove")) {
    Groove groove;
    const std::string kind = g.choice("kind", {"circumferential", "axial"});
    groove.axial_position = g.number_or("axial_position", 0.0, axial);
    if (kind == "circumferential") {
      groove.kind = Groove::Kind::kCircumferential;
      groove.width = g.number("width", Range{0.0, 10.0, true, false});
      groove.arc_start = g.number_or("arc_start_deg", 0.0, Range::closed(-720.0, 720.0)) * kDeg;
      groove.arc_end = g.number_or("arc_end_deg", 360.0, Range::closed(-720.0, 720.0)) * kDeg;
      if (groove.arc_end <= groove.arc_start) g.fail("arc_end_deg", "expected arc_end_deg > arc_start_deg");
    } else {
      groove.kind = Groove::Kind::kAxial;
      groove.angle = g.number("angle_deg", angle) * kDeg;
      groove.angular_width = g.number("angular_width_deg", Range{0.0, 360.0, true, false}) * kDeg;
      groove.length = g.number("length", Range{0.0, 10.0, true, false});
    }
    g.finish();
    s.grooves.push_back(groove);
  }
  validate(s);
  return s;
}

}  // namespace nvh::bearing
