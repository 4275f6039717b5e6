// Maxwell element: a spring k in series with a damper c along the line from marker j to marker i - the
// simplest frequency-dependent mount (dynamic stiffness k c w i / (k + c w i): a damper at low frequency, a
// spring at high frequency). The worked example of docs/adding-an-element.md.
//
//   x = |p_i - p_j| - free_length            total deflection (m)
//   u                                        the damper's deflection: an internal state (m)
//   f = k (x - u)                            the force in the series pair, tension positive (N)
//   c u' = k (x - u)                         the damper carries the spring's force: the state's row
//   F_i = -f e,  e = (p_i - p_j) / |p_i - p_j|   (body j gets the reaction)
// Stored energy k (x - u)^2 / 2 (the spring), dissipated power c u'^2 = f^2 / c (the damper).
#include <cmath>

#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"

namespace nvh::solve {
namespace {

class Maxwell final : public ForceElement {
 public:
  Maxwell(double k, double c, double free_length) : k_(k), c_(c), free_length_(free_length) {}
  std::string type() const override { return "maxwell"; }
  int marker_count() const override { return 2; }
  std::vector<StateDefinition> states() const override { return {{"damper_deflection", "m", true, 0.0}}; }

  struct Line {
    Vec3 e;
    double length;
  };
  static Line line(const ElementInput& in) {
    const Vec3 d = in.markers[0].position - in.markers[1].position;
    const double l = d.norm();
    return {l > 1e-12 ? Vec3(d / l) : Vec3::UnitZ(), l};
  }
  double force(const ElementInput& in) const { return k_ * (line(in).length - free_length_ - in.z[0]); }

  void evaluate(const ElementInput& in, ElementOutput& out) const override {
    const Line s = line(in);
    const double f = k_ * (s.length - free_length_ - in.z[0]);
    apply_at_i(in, out, -f * s.e, Vec3::Zero(), in.markers[0].position);
    out.state_residual[0] = c_ * in.zp[0] - f;
  }

  // With d = p_i - p_j: dx/dd = e^T, de/dd = (1 - e e^T) / |d|; df = k (dx - du).
  //   F = -f e:  dF/dd = -k e e^T - f (1 - e e^T) / |d|,  dF/du = k e;
  //   row r = c u' - f:  dr/dd = -k e^T,  dr/du + cj dr/du' = k + cj c.
  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override {
    const Line s = line(in);
    if (s.length <= 1e-12) return false;
    const double f = force(in);
    const Mat3 ee = s.e * s.e.transpose();
    const Mat3 df_dd = -k_ * ee - f * (Mat3::Identity() - ee) / s.length;
    const int state = jac.state_column(2, 0);
    ElementRows df = zero_rows(jac);
    df.block<3, 3>(0, 0) = df_dd;    // dp_i
    df.block<3, 3>(0, 12) = -df_dd;  // dp_j
    df.col(state) = k_ * s.e;
    jacobian_at_i(in, jac, df, zero_rows(jac), -f * s.e);
    auto row = jac.matrix.row(12);  // the state's row, after 6 rows per marker
    row.segment<3>(0) = -k_ * s.e.transpose();
    row.segment<3>(12) = k_ * s.e.transpose();
    row[state] = k_ + jac.cj * c_;
    return true;
  }

  std::vector<Channel> channels() const override { return {{"deflection", "m"}, {"tension", "N"}}; }
  void channel_values(const ElementInput& in, std::span<double> out) const override {
    out[0] = line(in).length - free_length_;
    out[1] = force(in);
  }
  ElementEnergy energy(const ElementInput& in) const override {
    const double f = force(in);
    return {0.5 * f * f / k_, f * f / c_};
  }

 private:
  double k_, c_, free_length_;
};

}  // namespace

void register_maxwell(ElementRegistry& r) {
  r.add({"force", "maxwell",
         "spring k in series with a damper c along the line j -> i (a frequency-dependent mount): k, c, free_length",
         {"i", "j"}, [](ElementContext& c) -> std::unique_ptr<ForceElement> {
           using input::Range;
           const auto& t = c.table;
           const double free_length = t.has("free_length")
                                          ? t.number("free_length", Range::closed(0.0, bounds::kLength))
                                          : (c.initial[0].position - c.initial[1].position).norm();
           return std::make_unique<Maxwell>(t.number("k", Range{0.0, bounds::kCoefficient, true, false}),
                                            t.number("c", Range{0.0, bounds::kCoefficient, true, false}),
                                            free_length);
         }});
}

}  // namespace nvh::solve
