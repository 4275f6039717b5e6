// The scene file reader: TOML -> Model + run settings (keys documented in docs/scene-format.md).
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>

#include "common/input.hpp"
#include "solve/flexible_rotor_body.hpp"
#include "solve/cam/cam_joint.hpp"
#include "solve/cam/cam_profile.hpp"
#include "solve/element_registry.hpp"
#include "solve/fixed_axis_body.hpp"
#include "solve/flexible_body.hpp"
#include "solve/results.hpp"
#include "solve/scene.hpp"
#include "solve/steady_state.hpp"

namespace nvh::solve {
namespace {

using input::Range;
using input::Table;
constexpr double kPi = std::numbers::pi;

// The bounds of element_registry.hpp as ranges (docs/scene-format.md, "Numbers").
const Range kPosition = Range::magnitude(bounds::kLength);
const Range kDirection = Range::magnitude(bounds::kLength);  // normalized after reading
const Range kVelocity = Range::magnitude(bounds::kSpeed);
const Range kAngularVelocity = Range::magnitude(bounds::kAngularSpeed);
const Range kMass{0.0, bounds::kMass, true, false};
const Range kAngleDeg = Range::magnitude(bounds::kAngleDeg);
const Range kTime = Range::magnitude(bounds::kTime);

Vec3 to_vec(const std::array<double, 3>& a) {
  return {a[0], a[1], a[2]};
}

/// A number for messages: "0.1", "1e+09", "12345".
std::string format_number(double x) {
  std::ostringstream out;
  out << std::setprecision(6) << x;
  return out.str();
}

class SceneReader {
 public:
  SceneReader(std::filesystem::path base, Scene& scene) : base_(std::move(base)), s_(scene) {}

  void read(const Table& root) {
    const auto scene = root.optional_table("scene");
    if (scene) {
      s_.name = scene->optional_string("name").value_or("");
      if (auto g = scene->optional_vec3("gravity", Range::magnitude(bounds::kAcceleration)))
        s_.model.gravity = to_vec(*g);
      scene->finish();
    }
    for (const auto& b : root.table_array("body")) read_body(b);
    if (s_.model.bodies.empty()) root.fail("a scene needs at least one [[body]]");
    for (const auto& j : root.table_array("joint")) read_joint(j);
    // The start time before the drivers: a displacement driver's offset is taken there (read again below).
    if (const auto c = root.optional_table("clock")) s_.start_time = c->number_or("start_time", 0.0, kTime);
    for (const auto& d : root.table_array("driver")) read_driver(d);
    for (const auto& f : root.table_array("force")) read_element(f, "force");
    for (const auto& l : root.table_array("load")) read_element(l, "load");
    read_clock(root);
    read_steady_state_table(root);
    read_integrator(root);
    read_output(root);
    if (steady_) {  // the watched channels must be datasets the results will hold
      std::vector<std::string> paths;
      std::vector<int> columns;
      result_datasets(s_, paths, columns);
      check_steady_state_channels(*steady_, *s_.steady_state, paths, columns);
    }
    root.finish();
    s_.model.finalize();
  }

 private:
  // ------------------------------------------------------------------ bodies and markers
  /// `inertia`: about the centre of mass in body axes, 3 or 6 tensor components; positive definite, and the
  /// principal moments satisfy the triangle inequality.
  static Mat3 read_inertia(const Table& t) {
    const auto in = t.numbers("inertia", Range::magnitude(bounds::kInertia));
    Mat3 j = Mat3::Zero();
    if (in.size() == 3) {
      j.diagonal() << in[0], in[1], in[2];
    } else if (in.size() == 6) {  // Ixx Iyy Izz Ixy Ixz Iyz (tensor components, not products of inertia)
      j << in[0], in[3], in[4], in[3], in[1], in[5], in[4], in[5], in[2];
    } else {
      t.fail("inertia",
             "expected 3 numbers [Ixx, Iyy, Izz] or 6 [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] in kg m^2, got " +
                 std::to_string(in.size()));
    }
    Eigen::SelfAdjointEigenSolver<Mat3> eig(j);
    const Vec3 ev = eig.eigenvalues();
    if (ev.minCoeff() <= 0)
      t.fail("inertia", "the inertia tensor must be positive definite; its principal moments are " +
                            std::to_string(ev[0]) + ", " + std::to_string(ev[1]) + ", " + std::to_string(ev[2]));
    if (ev[0] + ev[1] < ev[2] * (1 - 1e-9))
      t.fail("inertia",
             "the principal moments violate the triangle inequality (I1 + I2 >= I3): no real body has them");
    return j;
  }

  /// `orientation`: Euler parameters of body -> global, normalized.
  static Mat3 read_orientation(const Table& t) {
    const auto p = t.numbers("orientation", kDirection);
    if (p.size() != 4) t.fail("orientation", "expected 4 Euler parameters [e0, e1, e2, e3]");
    const Vec4 pv(p[0], p[1], p[2], p[3]);
    if (pv.norm() < 1e-12) t.fail("orientation", "the Euler parameters must not all be zero");
    return rotation_matrix(pv.normalized());
  }

  /// type = "slider" or "rotor": a rigid body of one coordinate on a fixed axis of the ground
  /// (fixed_axis_body.hpp). `position` is its centre of mass at coordinate 0.
  static std::unique_ptr<Body> read_fixed_axis_body(const Table& t, const std::string& name, const std::string& type,
                                                    InitialState init) {
    const bool slider = type == "slider";
    const char* rate_unit = slider ? "m/s" : "rad/s";
    for (const char* key : {"velocity", "angular_velocity"})
      if (t.has(key))
        t.fail(key, std::string(slider ? "a slider moves along" : "a rotor turns about") +
                        " its axis only: give its initial rate as `speed` (" + rate_unit +
                        (slider ? " along the axis)" : " about the axis, right-handed)"));
    const double mass = t.number("mass", kMass);
    const Vec3 axis = to_vec(t.vec3("axis", kDirection));
    if (axis.norm() < 1e-12) t.fail("axis", "the axis must not be zero");
    if (t.has("orientation")) init.orientation = read_orientation(t);
    const double speed = t.number_or("speed", 0.0, slider ? kVelocity : kAngularVelocity);
    if (slider) {
      for (const char* key : {"inertia", "pivot"})
        if (t.has(key))
          t.fail(key, std::string("a slider translates and does not turn: it takes no `") + key +
                          "` (a body that also turns is a rotor, or a rigid body with joints)");
      init.velocity = speed * axis.normalized();
      return std::make_unique<SliderBody>(name, mass, axis, init);
    }
    const Mat3 j = read_inertia(t);
    const Vec3 pivot = t.has("pivot") ? to_vec(t.vec3("pivot", kPosition)) : init.position;
    init.angular_velocity = speed * axis.normalized();
    return std::make_unique<RotorBody>(name, mass, j, axis, pivot, init);
  }

  void read_body(const Table& t) {
    const std::string name = t.name("name");
    if (name.empty() || name.find('.') != std::string::npos)
      t.fail("name", "a body name must be non-empty and contain no '.' (markers are named body.marker)");
    if (body_index_.count(name)) t.fail("name", "a body named '" + name + "' is defined twice");
    const std::string type = t.choice("type", {"ground", "rigid", "point-mass", "flexible", "slider", "rotor"});
    InitialState init;
    if (type != "ground") {
      init.position = to_vec(t.optional_vec3("position", kPosition).value_or(std::array<double, 3>{0, 0, 0}));
      init.velocity = to_vec(t.optional_vec3("velocity", kVelocity).value_or(std::array<double, 3>{0, 0, 0}));
    }
    std::unique_ptr<Body> body;
    if (type == "ground") {
      body = std::make_unique<Ground>(name);
    } else if (type == "slider" || type == "rotor") {
      body = read_fixed_axis_body(t, name, type, init);
    } else if (type == "rigid") {
      const double mass = t.number("mass", kMass);
      const Mat3 j = read_inertia(t);
      if (t.has("orientation")) init.orientation = read_orientation(t);
      init.angular_velocity = to_vec(
          t.optional_vec3("angular_velocity", kAngularVelocity).value_or(std::array<double, 3>{0, 0, 0}));
      body = std::make_unique<RigidBody>(name, mass, j, init);
    } else if (type == "point-mass") {
      body = std::make_unique<PointMass>(name, t.number("mass", kMass), init);
    } else {
      init.angular_velocity = to_vec(
          t.optional_vec3("angular_velocity", kAngularVelocity).value_or(std::array<double, 3>{0, 0, 0}));
      if (t.has("orientation")) init.orientation = read_orientation(t);
      body = make_flexible_body(t, name, init, base_, s_.input_files);

      // Fewer coordinates than a file with static correction holds drop that correction (its vectors lie
      // above the band, or are mixed into the orthonormalized modes): allowed, but say so.
      const FlexibleData& d = flexible_part(*body)->data();
      if (d.static_correction > 0 && d.size() < d.coordinates_in_file) {
        const SourceLocation at = t.location(t.has("mode_numbers") ? "mode_numbers" : "modes");
        s_.warnings.push_back(
            at.file + ":" + std::to_string(at.line) + ": flexible body '" + name + "' uses " +
            std::to_string(d.size()) + " of the " + std::to_string(d.coordinates_in_file) +
            " coordinates of " + d.file.filename().string() + ", whose basis holds " +
            std::to_string(d.static_correction) +
            " static-correction vectors (residual modes or vectors): loads at its points are "
            "no longer statically exact; leave `modes` out to use them all");
      }
    }
    for (const auto& m : t.table_array("marker")) {
      MarkerDefinition md;
      md.name = m.name("name");
      if (body->find_marker(md.name) >= 0)
        m.fail("name", "marker '" + md.name + "' is defined twice on body '" + name + "'");
      md.position = to_vec(m.optional_vec3("at", kPosition).value_or(std::array<double, 3>{0, 0, 0}));
      const Vec3 z = to_vec(m.optional_vec3("z", kDirection).value_or(std::array<double, 3>{0, 0, 1}));
      const Vec3 x = to_vec(m.optional_vec3("x", kDirection).value_or(std::array<double, 3>{1, 0, 0}));
      if (z.norm() < 1e-12) m.fail("z", "the z axis must not be zero");
      if (type == "point-mass" && md.position.norm() > 0)
        m.fail("at", "markers of a point mass sit on the point: 'at' must be [0, 0, 0] or omitted");
      md.axes = frame_from_z(z, x);
      m.finish();
      body->add_marker(std::move(md));
    }
    t.finish();
    body_index_[name] = static_cast<int>(s_.model.bodies.size());
    s_.model.bodies.push_back(std::move(body));
  }

  MarkerRef marker(const Table& t, std::string_view key) const { return marker(t, key, t.string(key)); }
  MarkerRef marker(const Table& t, std::string_view key, const std::string& full) const {
    const auto dot = full.find('.');
    if (dot == std::string::npos) t.fail(key, "expected a marker as \"body.marker\", got \"" + full + "\"");
    const std::string bname = full.substr(0, dot), mname = full.substr(dot + 1);
    const auto it = body_index_.find(bname);
    if (it == body_index_.end()) {
      std::vector<std::string> names;
      for (const auto& [n, i] : body_index_) names.push_back(n);
      const std::string near = input::closest(bname, names);
      t.fail(key, "no body '" + bname + "'" + (near.empty() ? "" : " (did you mean '" + near + "'?)"));
    }
    const Body& b = *s_.model.bodies[it->second];
    const int m = b.find_marker(mname);
    if (m < 0) {
      std::vector<std::string> names;
      for (const auto& md : b.markers()) names.push_back(md.name);
      const std::string near = input::closest(mname, names);
      std::string have;
      for (const auto& n : names) have += (have.empty() ? "" : ", ") + n;
      t.fail(key, "body '" + bname + "' has no marker '" + mname + "'" +
                      (near.empty() ? "" : " (did you mean '" + near + "'?)") +
                      (have.empty() ? "; it has no markers" : "; its markers: " + have));
    }
    return {it->second, m};
  }

  /// A marker's motion in the initial state as given (before assembly).
  MarkerMotion initial_motion(const MarkerRef& m) const {
    const Body& b = *s_.model.bodies[m.body];
    const Eigen::VectorXd q = b.initial_positions(), w = b.initial_velocities();
    return b.marker_motion(m.marker, {q.data(), std::size_t(q.size())}, {w.data(), std::size_t(w.size())});
  }

  // ------------------------------------------------------------------ joints and drivers
  void add_constraint(const Table& t, std::string name, std::unique_ptr<Constraint> c, MarkerRef i,
                      MarkerRef j) {
    if (i.body == j.body) t.fail("j", "markers i and j are on the same body: a joint connects two bodies");
    s_.model.constraints.push_back({std::move(name), std::move(c), i, j, 0, {}});
  }

  void read_joint(const Table& t) {
    const std::string name = t.name("name");
    static const std::map<std::string, JointType> types = {{"fixed", JointType::kFixed},
                                                           {"revolute", JointType::kRevolute},
                                                           {"spherical", JointType::kSpherical},
                                                           {"prismatic", JointType::kPrismatic},
                                                           {"cylindrical", JointType::kCylindrical},
                                                           {"in-line", JointType::kInLine}};
    const std::string type = t.choice("type", {"fixed", "revolute", "spherical", "prismatic", "cylindrical",
                                               "in-line", "distance", "in-plane", "cam"});
    const MarkerRef i = marker(t, "i"), j = marker(t, "j");
    std::unique_ptr<Constraint> c;
    if (type == "distance") {
      // The link's length: given, or the markers' initial distance (the geometry as drawn).
      const double initial = (initial_motion(i).position - initial_motion(j).position).norm();
      const double length = t.optional_number("length", Range::positive()).value_or(initial);
      if (!(length > 0))
        t.fail("i", "the markers of a distance joint start at one point: give its 'length' (m)");
      c = make_distance_joint(length);
    } else if (type == "in-plane") {
      c = make_in_plane_joint(t.optional_number("offset", Range::magnitude(1e3)).value_or(0.0));
    } else if (type == "cam") {
      // The roller's centre on the cam's pitch curve (the profile's keys as for roller-cam, section 2 of
      // docs/valvetrain.md; the reader refuses a roller that undercuts the profile).
      c = make_cam_joint(cam::read_cam_profile(t, base_, s_.input_files));
    } else {
      c = make_joint(types.at(type));
    }
    t.finish();
    add_constraint(t, name, std::move(c), i, j);
  }

  void read_driver(const Table& t);
  void read_displacement_driver(const Table& t);
  void read_element(const Table& t, const std::string& section);
  void read_clock(const Table& root);
  void read_steady_state_table(const Table& root);
  void read_integrator(const Table& root);
  void read_split(const Table& t);
  void read_output(const Table& root);

  std::filesystem::path base_;
  Scene& s_;
  std::map<std::string, int> body_index_;
  bool needs_clock_ = false;
  std::optional<Table> clock_user_;  // a load that needs the crank angle (for the message)
  std::optional<Table> clock_;       // the [clock] table (for messages about the run's length)
  std::optional<Table> steady_;      // the [steady_state] table
  double clock_cycle_deg_ = 0;       // [clock] cycle_deg with a steady state (0: not given)
};

void SceneReader::read_driver(const Table& t) {
  std::vector<std::string> types = {"speed", "lift", "displacement"};
  for (const auto& n : builtin_elements().names("driver")) types.push_back(n);
  const std::string type = t.choice("type", types);
  if (type == "displacement") return read_displacement_driver(t);
  if (type != "speed" && type != "lift")
    return read_element(t, "driver");  // a torque-speed curve: a force element
  const std::string name = t.name("name");
  const MarkerRef i = marker(t, "i"), j = marker(t, "j");
  // Prescribed speed: the angle theta(t) = theta0 + integral of omega(t); theta0 is the initial angle of i
  // about z_j (speed) or `phase_deg`, the cam angle at the start (lift).
  const double theta0 = type == "speed"
                            ? relative_angle(initial_motion(i), initial_motion(j))
                            : t.number_or("phase_deg", 0.0, Range::magnitude(bounds::kAngleDeg)) * kPi / 180;
  std::function<double(double)> theta, rate;
  constexpr double kRpm = 2 * kPi / 60.0;
  // The lift driver turns at a constant speed: its `table` and `file` keys are the cam profile's.
  if (type == "speed" && t.has("rpm") && t.has("table"))
    t.fail("table", "give either 'rpm' (constant) or 'table' (rpm against time)");
  if (type == "lift" || t.has("rpm")) {
    const double w = t.number("rpm", Range::magnitude(bounds::kRpm)) * kRpm;
    theta = [=](double time) { return theta0 + w * time; };
    rate = [=](double) { return w; };
  } else {
    ElementContext context{t, base_, s_.input_files, {}, {}};
    auto table = std::make_shared<Table1D>(context.table_from(name + "'s rpm(t)"));
    theta = [=](double time) { return theta0 + kRpm * table->integral(time) - kRpm * table->integral(0.0); };
    rate = [=](double time) { return kRpm * (*table)(time); };
  }
  if (type == "speed") {
    t.finish();
    return add_constraint(t, name, std::make_unique<AngleDriver>(theta, rate), i, j);
  }
  // A kinematic cam: the follower's lift along z_j from a cam profile (docs/valvetrain.md).
  std::shared_ptr<const cam::CamProfile> profile = cam::read_cam_profile(t, base_, s_.input_files);
  t.finish();
  const MarkerMotion mi = initial_motion(i), mj = initial_motion(j);
  const double offset = mj.axes.col(2).dot(mi.position - mj.position) - profile->lift(theta(0.0)).s;
  auto lift = [profile](double th) {
    const cam::Lift l = profile->lift(th);
    return std::pair{l.s, l.ds};
  };
  add_constraint(t, name, std::make_unique<LiftDriver>(lift, theta, rate, offset), i, j);
}

// A prescribed harmonic displacement of i along z_j, constraint.hpp (D1):
//   s(t) = A sin(2 pi f t + phase), s'(t) = 2 pi f A cos(2 pi f t + phase),
// the convention of the harmonic loads; the offset makes the start consistent with the initial geometry.
void SceneReader::read_displacement_driver(const Table& t) {
  const std::string name = t.name("name");
  const MarkerRef i = marker(t, "i"), j = marker(t, "j");
  const double a = t.number("amplitude", kPosition);
  const double w = 2 * kPi * t.number("frequency_hz", Range::closed(0.0, bounds::kFrequencyHz));
  const double phase = t.number_or("phase_deg", 0.0, kAngleDeg) * kPi / 180;
  t.finish();
  auto motion = [=](double time) {
    return std::pair{a * std::sin(w * time + phase), a * w * std::cos(w * time + phase)};
  };
  const MarkerMotion mi = initial_motion(i), mj = initial_motion(j);
  const double offset = mj.axes.col(2).dot(mi.position - mj.position) - motion(s_.start_time).first;
  add_constraint(t, name, make_displacement_driver(motion, offset), i, j);
}

void SceneReader::read_element(const Table& t, const std::string& section) {
  const std::string name = t.name("name");
  const ElementRegistry& registry = builtin_elements();
  const std::string type = section == "driver" ? t.string("type") : t.choice("type", registry.names(section));
  const ElementType& et = *registry.find(section, type);
  std::vector<MarkerRef> markers;
  bool lists = false;
  for (const auto& key : et.marker_keys) {
    if (key.ends_with("[]") || key.ends_with("[]?")) {  // a list of markers (element_registry.hpp)
      const std::string list = key.substr(0, key.find('['));
      if (key.ends_with("?") && !t.has(list)) {  // an optional list, absent: no markers
        t.accept(list);
        continue;
      }
      lists = true;
      const auto names = t.strings(list);
      if (names.empty()) t.fail(list, "expected at least one marker \"body.marker\"");
      for (const auto& full : names) markers.push_back(marker(t, list, full));
    } else {
      markers.push_back(marker(t, key));
    }
  }
  ElementContext context{t, base_, s_.input_files, {}, {}};
  for (const auto& m : markers) {
    context.initial.push_back(initial_motion(m));
    context.marker_bodies.push_back(s_.model.bodies[m.body]->name());
  }
  std::unique_ptr<ForceElement> e = et.make(context);
  t.finish();
  if (!lists && markers.size() == 2 && markers[0].body == markers[1].body)  // lists: the element checks them
    t.fail(et.marker_keys.back(),
           "markers i and j are on the same body: a force element connects two bodies");
  for (const auto& f : s_.model.forces)
    if (f.name == name) t.fail("name", "a force, load or driver named '" + name + "' is defined twice");
  if (e->uses_crank_angle()) {
    needs_clock_ = true;
    clock_user_ = t;
  }
  s_.model.forces.push_back({name, std::move(e), std::move(markers)});
}

void SceneReader::read_clock(const Table& root) {
  const auto c = root.optional_table("clock");
  const bool steady = root.has("steady_state");
  if (!c) {
    if (needs_clock_)
      clock_user_->fail("abscissa",
                        "a load against crank angle needs a [clock] that defines the crank angle");
    if (steady) return;  // a steady state over a period in s needs no clock: it sets the end
    root.fail("the scene needs a [clock] with end_time (s), or i/j markers and end_angle_deg or end_cycles");
  }
  clock_ = c;
  s_.start_time = c->number_or("start_time", 0.0, kTime);
  if (c->has("i") || c->has("j")) {
    ClockDefinition def;
    def.i = marker(*c, "i");
    def.j = marker(*c, "j");
    def.zero_angle = c->number_or("zero_deg", 0.0, kAngleDeg) * kPi / 180.0;
    s_.model.clock = def;
  } else if (needs_clock_) {
    clock_user_->fail("abscissa",
                      "a load against crank angle needs [clock] i and j markers (the crank's rotation)");
  }
  const int ends = c->has("end_time") + c->has("end_angle_deg") + c->has("end_cycles");
  if (steady) {  // the run ends when it has converged or after max_cycles ([steady_state], steady_state.hpp)
    for (const char* key : {"end_time", "end_angle_deg", "end_cycles"})
      if (c->has(key))
        c->fail(key,
                "with [steady_state] the run ends when it has converged or after its max_cycles: remove " +
                    std::string(key) + " (end_time_limit may bound the time)");
    clock_cycle_deg_ = c->number_or("cycle_deg", 0.0, Range{0.0, bounds::kAngleDeg, true, false});
    s_.end_time = c->number_or("end_time_limit", 1e9, Range{s_.start_time, bounds::kTime, true, false});
    c->finish();
    return;
  }
  if (ends != 1) c->fail("give exactly one of end_time (s), end_angle_deg or end_cycles");
  if (c->has("end_time")) {
    s_.end_time = c->number("end_time", Range{s_.start_time, bounds::kTime, true, false});
  } else {
    if (!s_.model.clock)
      c->fail(c->has("end_angle_deg") ? "end_angle_deg" : "end_cycles",
              "an end by angle needs the clock's i and j markers");
    // The end angle is bounded like a time: 1e12 deg are some 3e9 turns.
    const double cycle = c->number_or("cycle_deg", 720.0, Range{0.0, bounds::kAngleDeg, true, false});
    s_.end_angle_deg = c->has("end_angle_deg")
                           ? c->number("end_angle_deg", Range{0.0, bounds::kTime, true, false})
                           : c->number("end_cycles", Range{0.0, bounds::kTime / cycle, true, false}) * cycle;
    // The end time follows from the speed at run time; end_time_limit (default: a generous bound) stops a
    // stalled or slow run.
    s_.end_time = c->number_or("end_time_limit", 1e9, Range{s_.start_time, bounds::kTime, true, false});
  }
  c->accept("end_time_limit");
  c->finish();
}

void SceneReader::read_steady_state_table(const Table& root) {
  steady_ = root.optional_table("steady_state");
  if (!steady_) return;
  s_.steady_state = read_steady_state(*steady_, s_.model.clock.has_value(), clock_cycle_deg_);
  // The run's bound: one cycle past max_cycles (the monitor ends the run; the sample after the last cycle
  // closes it).
  const SteadyStateSettings& ss = *s_.steady_state;
  if (ss.by_angle)
    s_.end_angle_deg = (ss.max_cycles + 1) * ss.cycle;
  else
    s_.end_time = s_.start_time + (ss.max_cycles + 1) * ss.cycle;
}

void SceneReader::read_integrator(const Table& root) {
  const auto t = root.optional_table("integrator");
  if (!t) return;
  auto& s = s_.integrator;
  s.method = t->optional_choice("method", {"ida", "generalized-alpha", "split"}).value_or(s.method);
  s.rtol = t->number_or("rtol", s.rtol, Range::open(0.0, 1.0));
  // Absolute tolerances of positions (m, rad) above 1 and of multipliers (N, N m) above the coefficients'
  // bound let the error test accept anything: the run ends "complete" with meaningless results.
  s.atol = t->number_or("atol", s.atol, Range{0.0, 1.0, true, false});
  s.multiplier_atol =
      t->number_or("multiplier_atol", s.multiplier_atol, Range{0.0, bounds::kCoefficient, true, false});
  s.velocity_atol = t->number_or("velocity_atol", s.velocity_atol, Range{0.0, 1e3, true, false});
  s.max_step = t->number_or("max_step", s.max_step, Range::closed(0.0, bounds::kTime));
  s.initial_step = t->number_or("initial_step", s.initial_step, Range::closed(0.0, bounds::kTime));
  s.max_order = static_cast<int>(t->optional_integer("max_order", Range::closed(1, 5)).value_or(s.max_order));
  s.jacobian_cj_change = t->number_or("jacobian_cj_change", s.jacobian_cj_change, Range::open(0.0, 1.0));
  s.rho_inf = t->number_or("rho_inf", s.rho_inf, Range::closed(0.0, 1.0));
  s.newton_tolerance = t->number_or("newton_tolerance", s.newton_tolerance, Range{0.0, 1.0, true, false});
  s.step = t->number_or("step", s.step, Range{0.0, bounds::kTime, true, false});
  // A fixed step so small that the run never ends (or that t + step == t): refuse it where the end is a time.
  const double span = s_.end_time - s_.start_time;
  if (s_.end_angle_deg == 0 && t->has("step") && span / s.step > bounds::kMaxSteps) {
    t->fail("step", "expected a step >= " + format_number(span / bounds::kMaxSteps) + " s: the run from " +
                        format_number(s_.start_time) + " s to " + format_number(s_.end_time) +
                        " s would take " + format_number(span / s.step) + " steps, more than the limit of " +
                        format_number(bounds::kMaxSteps));
  }
  s.adaptive = t->optional_boolean("adaptive").value_or(s.adaptive);
  s.jacobian = t->optional_choice("jacobian", {"analytic", "colored-fd", "dense-fd"}).value_or(s.jacobian);
  s.linear_solver = t->optional_choice("linear_solver", {"auto", "klu", "dense"}).value_or(s.linear_solver);
  s.events = t->optional_boolean("events").value_or(s.events);
  read_split(*t);
  t->finish();
}

// method = "split" (split_integrator.hpp; docs/scene-format.md section 7): its keys, refused for other
// methods.
void SceneReader::read_split(const Table& t) {
  auto& s = s_.integrator;
  const bool split = s.method == "split";
  for (const char* key : {"macro_step", "macro_tolerance", "exchange", "extrapolation", "coupling_correction",
                          "iterations", "groups"})
    if (!split && t.has(key))
      t.fail(key, "applies to method = \"split\" only (method is \"" + s.method + "\")");
  if (!split) return;
  if (!t.has("macro_step"))
    t.fail("macro_step",
           "method = \"split\" needs macro_step, the exchange interval H between the groups (s)");
  s.macro_step = t.number("macro_step", Range{0.0, bounds::kTime, true, false});
  const double span = s_.end_time - s_.start_time;
  if (s_.end_angle_deg == 0 && span / s.macro_step > bounds::kMaxSteps)
    t.fail("macro_step", "expected a macro_step >= " + format_number(span / bounds::kMaxSteps) +
                             " s: the run would take " + format_number(span / s.macro_step) +
                             " macro steps, more than the limit of " + format_number(bounds::kMaxSteps));
  s.macro_tolerance = t.optional_number("macro_tolerance", Range::positive()).value_or(s.macro_tolerance);
  s.exchange = t.optional_choice("exchange", {"jacobi", "gauss-seidel"}).value_or(s.exchange);
  s.extrapolation =
      static_cast<int>(t.optional_integer("extrapolation", Range::closed(0, 2)).value_or(s.extrapolation));
  s.coupling_correction = t.optional_boolean("coupling_correction").value_or(s.coupling_correction);
  s.iterations =
      static_cast<int>(t.optional_integer("iterations", Range::closed(0, 100)).value_or(s.iterations));
  if (t.has("groups")) {
    for (const auto& text : t.strings("groups")) {  // "crank+conrod+piston": bodies integrated together
      std::vector<std::string> names;
      std::size_t from = 0;
      while (from <= text.size()) {
        const std::size_t to = std::min(text.find('+', from), text.size());
        names.push_back(text.substr(from, to - from));
        from = to + 1;
      }
      for (const auto& name : names) {
        const auto it = body_index_.find(name);
        if (it == body_index_.end() || s_.model.bodies[it->second]->state_count() == 0)
          t.fail("groups",
                 "'" + text + "': no moving body '" + name +
                     "' (a group is the names of moving bodies joined by '+', e.g. \"crank+block\")");
      }
      s.split_groups.push_back(names);
    }
  }
  if (s.jacobian != "analytic")
    t.fail("jacobian",
           "method = \"split\" uses the analytic Jacobian (its coupling correction needs it); "
           "expected \"analytic\"");
}

void SceneReader::read_output(const Table& root) {
  auto& o = s_.output;
  if (const auto t = root.optional_table("output")) {
    o.sample_rate_hz =
        t->number_or("sample_rate_hz", o.sample_rate_hz, Range{0.0, bounds::kFrequencyHz, true, false});

    o.chunk_samples = static_cast<int>(
        t->optional_integer("chunk_samples", Range::closed(1, 1e7)).value_or(o.chunk_samples));
    o.compression =
        static_cast<int>(t->optional_integer("compression", Range::closed(0, 9)).value_or(o.compression));
    o.bodies = t->optional_boolean("bodies").value_or(true);
    o.forces = t->optional_boolean("forces").value_or(true);
    o.joints = t->optional_boolean("joints").value_or(true);
    if (t->has("markers")) {
      o.markers = t->strings("markers");
      for (const auto& name : o.markers) {
        // reuse the marker lookup's messages through a one-key check
        const auto dot = name.find('.');
        const auto it = dot == std::string::npos ? body_index_.end() : body_index_.find(name.substr(0, dot));
        if (it == body_index_.end() || s_.model.bodies[it->second]->find_marker(name.substr(dot + 1)) < 0)
          t->fail("markers", "no marker '" + name + "' (markers are named \"body.marker\")");
        s_.output_markers.push_back(
            {it->second, s_.model.bodies[it->second]->find_marker(name.substr(dot + 1))});
        s_.marker_names.push_back(name);
      }
    }
    t->finish();
  }
  // Every sample is written: a run may hold at most kMaxSamples of them (a larger count is a mistake of
  // units, and it would fill the disk or never end). A run that ends by crank angle is bounded by its
  // end_time_limit: by default the time of kMaxSamples samples (a stalled crank then still ends), and one
  // given must keep within them too. Named at the rate if given, else at the end.
  const bool by_angle = s_.end_angle_deg > 0;
  if (by_angle && !clock_->has("end_time_limit"))
    s_.end_time = std::min(s_.end_time, s_.start_time + bounds::kMaxSamples / o.sample_rate_hz);
  const double samples = (s_.end_time - s_.start_time) * o.sample_rate_hz;
  if (samples > bounds::kMaxSamples) {
    const auto output = root.optional_table("output");
    const bool at_rate = output && output->has("sample_rate_hz");
    const bool at_steady = !at_rate && !by_angle && steady_;  // the end is max_cycles periods
    const Table& where = at_rate ? *output : at_steady ? *steady_ : *clock_;
    where.fail(at_rate     ? "sample_rate_hz"
               : at_steady ? "max_cycles"
               : by_angle  ? "end_time_limit"
                           : "end_time",
               "the run from " + format_number(s_.start_time) + " s to " + format_number(s_.end_time) +
                   " s at " + format_number(o.sample_rate_hz) + " Hz gives " + format_number(samples) +
                   " samples, more than the limit of " + format_number(bounds::kMaxSamples) +
                   " samples per run: lower the rate or shorten the run");
  }
  if (o.markers.empty()) {
    for (std::size_t b = 0; b < s_.model.bodies.size(); ++b) {
      const auto& body = *s_.model.bodies[b];
      if (body.velocity_count() == 0) continue;
      for (std::size_t m = 0; m < body.markers().size(); ++m) {
        s_.output_markers.push_back({static_cast<int>(b), static_cast<int>(m)});
        s_.marker_names.push_back(body.name() + "." + body.markers()[m].name);
      }
    }
  }
}

}  // namespace

Scene parse_scene(const std::string& text, const std::string& name, const std::filesystem::path& base) {
  Scene scene;
  const auto doc = input::Document::parse(text, name);
  SceneReader(base, scene).read(doc.root());
  return scene;
}

Scene read_scene(const std::filesystem::path& path) {
  Scene scene;
  const auto doc = input::Document::load(path);
  scene.input_files.push_back(path);
  SceneReader(path.parent_path(), scene).read(doc.root());
  return scene;
}

}  // namespace nvh::solve
