#include "condense/component_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>
#include <sstream>

#include "common/input.hpp"

namespace nvh::condense {
namespace {

using input::Range;
using input::Table;

// Bounds of a component's numbers (docs/component-format.md, "Numbers"). Every number is finite
// (input::Range); these bounds lie orders of magnitude beyond any machine part, so that the element matrices
// formed of them stay finite: beyond them a value ends as a singular or non-finite matrix, an error far from
// the key that caused it.
constexpr double kMaxLength = 1e3;  // m: coordinates, box and cylinder extents (as solve's scene positions)
const Range kCoordinate = Range::magnitude(kMaxLength);
const Range kMassRange = Range::closed(0.0, 1e12);  // kg, and kg m^2 for point inertias

Material read_material(const std::string& name, const Table& t) {
  Material m;
  m.name = name;
  // Wide bounds: equivalent materials (a coil spring as a straight beam, testdata/compressor/spring.toml)
  // fix only the products E A, E I, rho A and may be far from any real material.
  m.E = t.number("E", Range{0.0, 1e18, true, false});  // Pa; diamond is 1.2e12
  m.nu = t.number("nu", Range::open(-1.0, 0.5));
  m.rho = t.number("rho", Range::closed(1e-6, 1e12));  // kg/m^3; air is 1.2, osmium 2.3e4, that spring 3e8
  t.finish();
  return m;
}

std::string segment_text(const std::vector<Vec3>& points, int s) {
  std::ostringstream o;
  const Vec3& a = points[s];
  const Vec3& b = points[s + 1];
  o << "segment " << s + 1 << " ([" << a[0] << ", " << a[1] << ", " << a[2] << "] -> [" << b[0] << ", "
    << b[1] << ", " << b[2] << "])";
  return o.str();
}

void read_beam(const Table& t, Component& c) {
  BeamGeometry& beam = c.beam;
  beam.where = t.location();
  beam.material = t.string("material");
  if (!c.materials.count(beam.material)) t.fail("material", "unknown material \"" + beam.material + "\"");
  beam.points = t.vec3_list("points", kCoordinate);
  if (beam.points.size() < 2) t.fail("points", "expected at least 2 points (one segment)");
  const int segments = static_cast<int>(beam.points.size()) - 1;
  for (int s = 0; s < segments; ++s) {
    const Vec3& a = beam.points[s];
    const Vec3& b = beam.points[s + 1];
    const double length = std::hypot(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
    if (length <= c.point_tolerance) {
      t.fail("points", segment_text(beam.points, s) + " has zero length; consecutive points must differ");
    }
  }
  beam.elements_per_segment =
      static_cast<int>(t.optional_integer("elements_per_segment", Range::closed(1, 100000)).value_or(8));

  // Sections: each covers a range of segments (1-based, inclusive); every segment needs exactly one.
  std::vector<int> covered_by(segments, 0);
  beam.segment_sections.assign(segments, BeamSection{});
  const std::vector<Table> sections = t.table_array("section");
  for (std::size_t i = 0; i < sections.size(); ++i) {
    const Table& st = sections[i];
    BeamSection sec;
    sec.where = st.location();
    // m^2 and m^4: below a 1 um wire to beyond a 30 m shaft (equivalent sections included).
    sec.A = st.number("A", Range::closed(1e-15, 1e3));
    sec.Iy = st.number("Iy", Range::closed(1e-30, 1e6));
    sec.Iz = st.number("Iz", Range::closed(1e-30, 1e6));
    sec.J = st.number("J", Range::closed(1e-30, 1e6));
    sec.shear_factor = st.optional_number("shear_factor", Range::open(0.0, 2.0));
    sec.rotary_inertia = st.optional_boolean("rotary_inertia").value_or(true);
    sec.y_axis = st.optional_vec3("y_axis", kCoordinate);
    if (sec.y_axis && std::hypot((*sec.y_axis)[0], (*sec.y_axis)[1], (*sec.y_axis)[2]) == 0.0) {
      st.fail("y_axis", "expected a non-zero direction");
    }
    sec.material = st.optional_string("material").value_or("");
    if (!sec.material.empty() && !c.materials.count(sec.material)) {
      st.fail("material", "unknown material \"" + sec.material + "\"");
    }
    std::vector<std::int64_t> range = st.integers("segments", Range::closed(1, segments));
    if (range.size() == 1) range.push_back(range[0]);
    if (range.size() != 2 || range[0] > range[1]) {
      st.fail("segments", "expected [first, last] with 1 <= first <= last <= " + std::to_string(segments));
    }
    for (std::int64_t s = range[0]; s <= range[1]; ++s) {
      if (covered_by[s - 1]) {
        st.fail("segments", "segment " + std::to_string(s) + " already has a section (beam.section[" +
                                std::to_string(covered_by[s - 1]) + "])");
      }
      covered_by[s - 1] = static_cast<int>(i + 1);
      beam.segment_sections[s - 1] = sec;
    }
    st.finish();
  }
  for (int s = 0; s < segments; ++s) {
    if (!covered_by[s]) {
      t.fail("section", segment_text(beam.points, s) +
                            " has no section: add a [[beam.section]] with "
                            "segments = [" +
                            std::to_string(s + 1) + ", " + std::to_string(s + 1) +
                            "] or a range "
                            "that covers it");
    }
  }

  for (const Table& mt : t.table_array("mass")) {
    PointMass pm;
    pm.where = mt.location("at");
    pm.path = mt.path();
    pm.at = mt.vec3("at", kCoordinate);
    pm.m = mt.number("m", kMassRange);
    if (auto j = mt.optional_vec3("J", Range::magnitude(1e12))) {
      for (int k = 0; k < 3; ++k) {
        if ((*j)[k] < 0.0) mt.fail("J", "expected moments of inertia >= 0 (kg m^2)");
        pm.J[k] = (*j)[k];
      }
    }
    mt.finish();
    beam.masses.push_back(pm);
  }
  for (const Table& rt : t.table_array("rigid")) {
    RigidLink link;
    link.where = rt.location();
    link.path = rt.path();
    link.from = rt.vec3("from", kCoordinate);
    link.to = rt.vec3("to", kCoordinate);
    rt.finish();
    beam.rigid_links.push_back(link);
  }
  t.finish();
}

/// [xmin, ymin, zmin, xmax, ymax, zmax] in m.
std::array<double, 6> read_box(const Table& t, const std::string& key) {
  const std::vector<double> box = t.numbers(key, kCoordinate);
  if (box.size() != 6 || box[0] > box[3] || box[1] > box[4] || box[2] > box[5]) {
    t.fail(key, "expected [xmin, ymin, zmin, xmax, ymax, zmax] in m with min <= max");
  }
  return {box[0], box[1], box[2], box[3], box[4], box[5]};
}

/// cylinder = { point = [x, y, z], axis = [dx, dy, dz], radius = [r_min, r_max], length = [s_min, s_max] }
/// (length optional: the axial range from `point` along `axis`, m).
CylinderSelector read_cylinder(const Table& t, const std::string& key) {
  const Table ct = t.table(key);
  CylinderSelector c;
  c.point = ct.vec3("point", kCoordinate);
  c.axis = ct.vec3("axis", kCoordinate);
  if (std::hypot(c.axis[0], c.axis[1], c.axis[2]) == 0.0) ct.fail("axis", "expected a non-zero direction");
  const std::vector<double> r = ct.numbers("radius", Range::closed(0.0, kMaxLength));
  if (r.size() != 2 || r[0] > r[1]) {
    ct.fail("radius",
            "expected the radius band [r_min, r_max] in m with 0 <= r_min <= r_max (a bore of "
            "radius R: [R - a little, R + a little])");
  }
  c.r_min = r[0];
  c.r_max = r[1];
  if (ct.has("length")) {
    const std::vector<double> s = ct.numbers("length", kCoordinate);
    if (s.size() != 2 || s[0] > s[1]) {
      ct.fail("length",
              "expected the axial range [s_min, s_max] in m from `point` along `axis`, s_min <= s_max");
    }
    c.s_min = s[0];
    c.s_max = s[1];
  }
  ct.finish();
  return c;
}

/// A volume interface: a point coupled (RBE2 or RBE3) to a node set, or the nodes in a box or on a cylinder.
void read_coupling(const Table& pt, NamedPoint& p) {
  const auto surface = pt.optional_string("surface");
  if (surface) {
    p.surface = *surface;
    for (char& ch : p.surface) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  }
  if (pt.has("box")) p.box = read_box(pt, "box");
  if (pt.has("cylinder")) p.cylinder = read_cylinder(pt, "cylinder");
  if (int(surface.has_value()) + int(p.box.has_value()) + int(p.cylinder.has_value()) != 1) {
    pt.fail(
        "a volume interface couples to a surface: give surface = \"NSET name\", box = [...] or "
        "cylinder = {...}, one of them");
  }
  p.selector_where = pt.location(surface ? "surface" : p.box ? "box" : "cylinder");
  p.distributing = pt.optional_choice("coupling", {"rbe2", "rbe3"}).value_or("rbe2") == "rbe3";
  p.max_distance = pt.number_or("max_distance", 0.0, Range{0.0, kMaxLength, true, false});
}

std::vector<NamedPoint> read_points(const Table& root, const std::string& key, bool couplings = false) {
  std::vector<NamedPoint> points;
  std::set<std::string> names;
  for (const Table& pt : root.table_array(key)) {
    NamedPoint p;
    p.where = pt.location("at");
    p.path = pt.path();
    p.name = pt.name("name");
    if (p.name.empty()) pt.fail("name", "expected a non-empty name");
    if (!names.insert(p.name).second)
      pt.fail("name", "the name \"" + p.name + "\" is used twice in [[" + key + "]]");
    p.at = pt.vec3("at", kCoordinate);
    if (couplings) read_coupling(pt, p);
    pt.finish();
    points.push_back(p);
  }
  return points;
}

ReductionSettings read_reduction(const Table& t) {
  ReductionSettings r;
  r.where = t.location();
  const std::string method = t.choice("method", {"modal", "craig-bampton", "guyan"});
  r.method = method == "modal"   ? ReductionMethod::kModal
             : method == "guyan" ? ReductionMethod::kGuyan
                                 : ReductionMethod::kCraigBampton;
  const auto fmax = t.optional_number("fmax", Range{0.0, 1e7, true, false});  // Hz
  const auto modes = t.optional_integer("modes", Range::closed(1, 100000));
  if (fmax && modes) t.fail("modes", "give either fmax or modes, not both");
  // Whether a count is needed at all is checked after command-line overrides (check_reduction).
  r.fmax_hz = fmax.value_or(0.0);
  r.where = t.location(fmax ? "fmax" : "modes");
  r.where_key = fmax ? "reduction.fmax" : modes ? "reduction.modes" : "reduction";
  r.modes = static_cast<int>(modes.value_or(0));
  r.orthonormalize = t.optional_boolean("orthonormalize").value_or(true);
  // The band (Hz) the results must cover: an error estimate in it, and the cut-off chosen from it when
  // neither fmax nor modes is given (frf_error.hpp).
  const auto band = t.optional_number("band", Range{0.0, 1e7, true, false});
  r.band_hz = band.value_or(0.0);
  r.band_where = band ? t.location("band") : t.location();
  r.frf_tolerance = t.number_or("frf_tolerance", 0.01, Range{0.0, 1.0, true, false});
  r.error_samples =
      static_cast<int>(t.optional_integer("error_samples", Range::closed(1, 1000)).value_or(16));
  const auto residual = t.optional_boolean("residual_modes");
  r.residual_modes_given = residual.has_value();
  r.residual_modes = residual.value_or(false);
  default_residual_modes(r);
  if (t.has("residual_vectors")) {
    r.residual_vectors = t.strings("residual_vectors");
    r.residual_where = t.location("residual_vectors");
    if (r.residual_vectors.empty())
      t.fail("residual_vectors", "expected observation point names (\"prefix*\" for all that start so)");
    if (r.method != ReductionMethod::kCraigBampton)
      t.fail("residual_vectors", "residual vectors of load points need method = \"craig-bampton\"");
  } else {
    t.accept("residual_vectors");
  }
  r.residual_tolerance = t.number_or("residual_tolerance", 1e-4, Range{0.0, 1.0, false, false});
  r.residual_patch = t.number_or("residual_patch", 0.0, Range::closed(0.0, 10.0));
  if (r.residual_vectors.empty() && (t.has("residual_tolerance") || t.has("residual_patch")))
    t.fail(t.has("residual_patch") ? "residual_patch" : "residual_tolerance", "only with residual_vectors");
  const auto rpm = t.optional_number("spin_speed_rpm", Range{0.0, 1e6, false, false});  // rev/min
  const auto axis = t.optional_vec3("spin_axis", Range::magnitude(1e6));
  if (axis && !rpm) t.fail("spin_axis", "spin_axis needs spin_speed_rpm (the speed to reduce at)");
  if (rpm && !axis)
    t.fail("spin_speed_rpm", "spin_speed_rpm needs spin_axis, e.g. [1, 0, 0] (component axes)");
  r.geometric_stiffening = t.optional_boolean("geometric_stiffening").value_or(rpm.has_value());
  if (rpm) {
    const double norm =
        std::sqrt((*axis)[0] * (*axis)[0] + (*axis)[1] * (*axis)[1] + (*axis)[2] * (*axis)[2]);
    if (norm == 0.0) t.fail("spin_axis", "expected a direction, not [0, 0, 0]");
    if (!r.geometric_stiffening)
      t.fail("geometric_stiffening",
             "spin_speed_rpm reduces at a speed, which needs geometric_stiffening = true");
    for (int k = 0; k < 3; ++k) r.spin[k] = (*axis)[k] / norm * *rpm * 3.141592653589793 / 30.0;
  }
  r.damping_ratio = t.number_or("damping_ratio", 0.0, Range{0.0, 1.0, false, true});
  t.finish();
  return r;
}

void read_volume(const Table& t, Component& c) {
  VolumeGeometry& v = c.volume;
  v.where = t.location("mesh");
  const std::string mesh = t.string("mesh");
  v.mesh =
      std::filesystem::path(mesh).is_absolute() ? std::filesystem::path(mesh) : c.file.parent_path() / mesh;
  std::string ext = v.mesh.extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  const std::vector<std::string> known = {".inp", ".msh", ".geo", ".step", ".stp", ".iges", ".igs", ".brep"};
  if (std::find(known.begin(), known.end(), ext) == known.end()) {
    t.fail("mesh",
           "expected a mesh (.inp of Abaqus/CalculiX, .msh of gmsh) or a geometry for gmsh (.geo, "
           ".step, .stp, .iges, .igs, .brep), got \"" +
               mesh + "\"");
  }
  if (!std::filesystem::exists(v.mesh))
    t.fail("mesh", "the mesh file " + v.mesh.string() + " does not exist");
  v.order = static_cast<int>(t.optional_integer("order", input::Range::closed(1, 2)).value_or(2));
  v.size = t.number_or("size", 0.0, input::Range::closed(0.0, kMaxLength));
  // More than 100 elements per shear wavelength buys no accuracy (2nd-order elements converge at 6-10).
  v.elements_per_wavelength = t.number_or("elements_per_wavelength", 0.0, input::Range::closed(0.0, 100.0));
  if (v.size > 0.0 && v.elements_per_wavelength > 0.0) {
    t.fail("elements_per_wavelength", "give either size or elements_per_wavelength, not both");
  }
  v.material = t.string("material");
  if (!c.materials.count(v.material)) t.fail("material", "unknown material \"" + v.material + "\"");
  v.mass_like_calculix =
      t.optional_choice("mass_quadrature", {"exact", "stiffness"}).value_or("exact") == "stiffness";
  const std::string form =
      t.optional_choice("rbe3_form", {"auto", "multiplier", "elimination"}).value_or("auto");
  v.rbe3_form = form == "multiplier"    ? DistributingForm::kMultiplier
                : form == "elimination" ? DistributingForm::kElimination
                                        : DistributingForm::kAuto;
  // Regions with their own material; whether the group is in the mesh and whether two regions share
  // an element is checked when the mesh is read (build_volume_model).
  std::set<std::string> groups;
  for (const Table& rt : t.table_array("region")) {
    MaterialRegion r;
    r.where = rt.location("group");
    r.path = rt.path();
    r.group = rt.string("group");
    if (r.group.empty())
      rt.fail("group", "expected the name of a 3D physical group or an *ELSET of the mesh");
    for (char& ch : r.group) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    if (!groups.insert(r.group).second) {
      rt.fail("group",
              "the group \"" + r.group + "\" already has a region (group names are case-insensitive)");
    }
    r.material = rt.string("material");
    if (!c.materials.count(r.material)) rt.fail("material", "unknown material \"" + r.material + "\"");
    rt.finish();
    v.regions.push_back(r);
  }
  t.finish();
}

Component read(const input::Document& doc, const std::filesystem::path& file) {
  Component c;
  c.file = file;
  const Table root = doc.root();
  const Table comp = root.table("component");
  c.name = comp.name("name");
  c.kind = comp.choice("kind", {"beam", "volume"});
  comp.finish();

  const Table materials = root.table("material");
  for (const std::string& name : materials.table_keys())
    c.materials[name] = read_material(name, materials.table(name));
  if (c.materials.empty()) materials.fail("expected at least one [material.NAME] table");
  materials.finish();

  if (c.kind == "volume") {
    read_volume(root.table("volume"), c);
  } else {
    read_beam(root.table("beam"), c);
  }

  for (const Table& ft : root.table_array("fix")) {
    Support s;
    s.path = ft.path();
    if (c.kind == "volume") {
      // One selector: a box, a node set or a cylinder band.
      const int given = int(ft.has("box")) + int(ft.has("surface")) + int(ft.has("cylinder"));
      if (ft.has("at"))
        ft.fail("at", "a support of a volume takes nodes by box, surface or cylinder, not at");
      if (given != 1) {
        ft.fail(
            "a support of a volume needs one of box = [...], surface = \"NSET name\" or cylinder = {...}");
      }
      s.where = ft.location(ft.has("box") ? "box" : ft.has("surface") ? "surface" : "cylinder");
      if (ft.has("box")) s.box = read_box(ft, "box");
      if (ft.has("cylinder")) s.cylinder = read_cylinder(ft, "cylinder");
      if (ft.has("surface")) {
        s.surface = ft.string("surface");
        for (char& ch : s.surface) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
      }
    } else if (ft.has("box")) {
      s.where = ft.location("box");
      s.box = read_box(ft, "box");
      if (ft.has("at")) ft.fail("at", "give either at (one node) or box (every node inside), not both");
    } else {
      s.where = ft.location("at");
      s.at = ft.vec3("at", kCoordinate);
    }
    const std::string dofs = ft.string("dofs");
    try {
      s.dofs = parse_dof_list(dofs);
    } catch (const Error& e) {
      ft.fail("dofs", e.message());
    }
    ft.finish();
    c.supports.push_back(s);
  }
  c.interfaces = read_points(root, "interface", c.kind == "volume");
  c.observers = read_points(root, "observe");
  for (const Table& pt : root.table_array("preload")) {
    Preload p;
    p.path = pt.path();
    p.where = pt.location("point");
    p.point = pt.string("point");
    const bool named = std::any_of(c.interfaces.begin(), c.interfaces.end(),
                                   [&](const NamedPoint& n) { return n.name == p.point; }) ||
                       std::any_of(c.observers.begin(), c.observers.end(),
                                   [&](const NamedPoint& n) { return n.name == p.point; });
    if (!named)
      pt.fail("point", "expected the name of an [[interface]] or [[observe]] point, got \"" + p.point + "\"");
    const auto force = pt.optional_vec3("force", Range::magnitude(1e12));
    const auto moment = pt.optional_vec3("moment", Range::magnitude(1e12));
    if (!force && !moment)
      pt.fail("a preload needs force = [Fx, Fy, Fz] (N) and/or moment = [Mx, My, Mz] (N m)");
    if (force) p.force = *force;
    if (moment) p.moment = *moment;
    pt.finish();
    c.preloads.push_back(p);
  }
  if (const auto surface = root.optional_table("surface")) {
    c.export_surface = surface->optional_boolean("export").value_or(false);
    if (c.export_surface && c.kind != "volume") {
      surface->fail("export", "the surface export is for volume components (a beam has no surface mesh)");
    }
    surface->finish();
  }
  c.reduction = read_reduction(root.table("reduction"));
  root.finish();
  return c;
}

}  // namespace

std::array<bool, 6> parse_dof_list(const std::string& text) {
  static const char* kNames[6] = {"x", "y", "z", "rx", "ry", "rz"};
  std::array<bool, 6> mask{};
  std::istringstream words(text);
  std::string w;
  int count = 0;
  while (words >> w) {
    ++count;
    if (w == "all") {
      mask.fill(true);
      continue;
    }
    bool found = false;
    for (int d = 0; d < 6; ++d) {
      if (w == kNames[d]) {
        mask[d] = true;
        found = true;
      }
    }
    if (!found) {
      throw Error("expected DOF names from \"x y z rx ry rz\" (or \"all\"), got \"" + w + "\"");
    }
  }
  if (count == 0) throw Error("expected at least one DOF name from \"x y z rx ry rz\"");
  return mask;
}

Component read_component(const std::filesystem::path& file) {
  const input::Document doc = input::Document::load(file);
  return read(doc, file);
}

Component parse_component(const std::string& text, const std::string& name) {
  const input::Document doc = input::Document::parse(text, name);
  return read(doc, name);
}

std::string to_string(ReductionMethod method) {
  switch (method) {
    case ReductionMethod::kModal:
      return "modal";
    case ReductionMethod::kCraigBampton:
      return "craig-bampton";
    case ReductionMethod::kGuyan:
      return "guyan";
  }
  return "?";
}

}  // namespace nvh::condense
