// Loads on one marker ([[load]]): a force or a torque along a fixed direction (global, or the marker's axes)
//   table:    magnitude = scale * table(x), x the time (s) or the crank angle (deg, periodic over period_deg,
//             the load at crank angle a is table(a - offset_deg)): a cylinder pressure curve times a piston area;
//   harmonic: magnitude = amplitude * sin(2 pi f t + phase): frequency responses and verification.
// Loads are sources: their input power is F . v (or T . omega) at the marker.
#include <cmath>
#include <numbers>

#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"

namespace nvh::solve {
namespace {

constexpr double kPi = std::numbers::pi;

struct Direction {
  bool torque = false;
  Vec3 direction = Vec3::UnitZ();  // unit
  bool marker_axes = false;
};

/// The common part: the direction (global or rotating with the marker) and the wrench of a magnitude.
class Load : public ForceElement {
 public:
  explicit Load(Direction d) : d_(d) {}
  int marker_count() const override { return 1; }
  bool is_source() const override { return true; }
  virtual double magnitude(const ElementInput& in) const = 0;
  Vec3 direction(const ElementInput& in) const {
    return d_.marker_axes ? Vec3(in.markers[0].axes * d_.direction) : d_.direction;
  }
  void evaluate(const ElementInput& in, ElementOutput& out) const override {
    const Vec3 v = magnitude(in) * direction(in);
    (d_.torque ? out.wrenches[0].torque : out.wrenches[0].force) = v;
  }
  /// d(magnitude)/d(crank angle) (1/rad; 0 for loads against time).
  virtual double magnitude_by_crank(const ElementInput&) const { return 0.0; }
  // V = m e on the marker's force (rows 0-2) or torque (rows 3-5); no reaction (one marker).
  //   e along the marker's axes: e = A e0, dA = dtheta~ A, so de = -e~ dtheta (columns 3-5);
  //   m of time: no column (time is not a state); m of the crank angle: dV = m'(crank) e (the last column).
  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override {
    const Vec3 e = direction(in);
    const int row = d_.torque ? 3 : 0;
    if (d_.marker_axes) jac.matrix.block<3, 3>(row, 3) -= magnitude(in) * skew(e);
    jac.matrix.block<3, 1>(row, jac.crank_column()) += magnitude_by_crank(in) * e;
    return true;
  }
  std::vector<Channel> channels() const override { return {{"magnitude", d_.torque ? "N m" : "N"}}; }
  void channel_values(const ElementInput& in, std::span<double> out) const override { out[0] = magnitude(in); }

 protected:
  Direction d_;
};

class TableLoad final : public Load {
 public:
  TableLoad(Direction d, Table1D t, bool crank, double scale, double offset_deg)
      : Load(d), table_(std::move(t)), crank_(crank), scale_(scale), offset_deg_(offset_deg) {}
  std::string type() const override { return d_.torque ? "torque-load" : "force-load"; }
  bool uses_crank_angle() const override { return crank_; }
  double magnitude(const ElementInput& in) const override {
    const double x = crank_ ? in.crank_angle * 180.0 / kPi - offset_deg_ : in.time;
    return scale_ * table_(x);
  }
  // x = crank 180/pi - offset_deg: dm/dcrank = scale table'(x) 180/pi (the piece's slope, also across the
  // periodic wrap from the last point to the first).
  double magnitude_by_crank(const ElementInput& in) const override {
    if (!crank_) return 0.0;
    return scale_ * table_.slope(in.crank_angle * 180.0 / kPi - offset_deg_) * 180.0 / kPi;
  }

 private:
  Table1D table_;
  bool crank_;
  double scale_, offset_deg_;
};

class HarmonicLoad final : public Load {
 public:
  HarmonicLoad(Direction d, double amplitude, double hz, double phase)
      : Load(d), amplitude_(amplitude), hz_(hz), phase_(phase) {}
  std::string type() const override { return d_.torque ? "harmonic-torque" : "harmonic-force"; }
  double magnitude(const ElementInput& in) const override {
    return amplitude_ * std::sin(2 * kPi * hz_ * in.time + phase_);
  }

 private:
  double amplitude_, hz_, phase_;
};

std::unique_ptr<ForceElement> make_load(ElementContext& c, bool torque) {
  using input::Range;
  const auto& t = c.table;
  const Range angle = Range::magnitude(bounds::kAngleDeg);
  Direction d;
  d.torque = torque;
  const auto a = t.vec3("direction", Range::magnitude(bounds::kLength));  // normalized below
  d.direction = Vec3(a[0], a[1], a[2]);
  if (d.direction.norm() < 1e-12) t.fail("direction", "the direction must not be zero");
  d.direction.normalize();
  d.marker_axes = t.optional_choice("axes", {"global", "marker"}).value_or("global") == "marker";
  if (t.has("amplitude") || t.has("frequency_hz"))
    return std::make_unique<HarmonicLoad>(d, t.number("amplitude", Range::magnitude(bounds::kCoefficient)),
                                          t.number("frequency_hz", Range::closed(0.0, bounds::kFrequencyHz)),
                                          t.number_or("phase_deg", 0.0, angle) * kPi / 180.0);
  const std::string abscissa = t.optional_choice("abscissa", {"time", "crank-angle"}).value_or("time");
  const bool crank = abscissa == "crank-angle";
  const double scale = t.number_or("scale", 1.0, Range::magnitude(bounds::kCoefficient));
  const double offset = t.number_or("offset_deg", 0.0, angle);
  const double period =
      crank ? t.number_or("period_deg", 720.0, Range{0.0, bounds::kAngleDeg, true, false}) : 0.0;
  Table1D table = c.table_from("load table (" + std::string(crank ? "deg" : "s") + ", value)", period);
  return std::make_unique<TableLoad>(d, std::move(table), crank, scale, offset);
}

}  // namespace

void register_loads(ElementRegistry& r) {
  const char* keys = ": direction, axes; table/file against abscissa time or crank-angle (scale, offset_deg, "
                     "period_deg), or amplitude, frequency_hz, phase_deg (harmonic)";
  r.add({"load", "force", std::string("a force on one marker") + keys, {"at"},
         [](ElementContext& c) { return make_load(c, false); }});
  r.add({"load", "torque", std::string("a torque on one marker") + keys, {"at"},
         [](ElementContext& c) { return make_load(c, true); }});
}

}  // namespace nvh::solve
