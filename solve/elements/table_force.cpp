// A force along z_j on i from a table of the deflection along z_j: f = table(z_j . (p_i - p_j)) (N), e.g. a
// measured mount or spring characteristic (positive pushes i along z_j). Stored energy: -integral of the table
// from 0 to the deflection (the table is the force of a conservative spring); no dissipation.
#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"

namespace nvh::solve {
namespace {

class TableForce final : public ForceElement {
 public:
  explicit TableForce(Table1D t) : table_(std::move(t)) {}
  std::string type() const override { return "table-force"; }
  int marker_count() const override { return 2; }
  static double deflection(const ElementInput& in) {
    return in.markers[1].axes.col(2).dot(in.markers[0].position - in.markers[1].position);
  }
  void evaluate(const ElementInput& in, ElementOutput& out) const override {
    apply_at_i(in, out, table_(deflection(in)) * in.markers[1].axes.col(2), Vec3::Zero(), in.markers[0].position);
  }

  // x = n.d, n = z_j, d = p_i - p_j; dn = -n~ dtheta_j (marker j's columns start at 12):
  //   dx = n^T (dp_i - dp_j) - d^T n~ dtheta_j;  F = f(x) n:  dF = n f'(x) dx - f(x) n~ dtheta_j.
  // f' is the slope of the table's piece (0 beyond its ends, where the table is constant); at a breakpoint the
  // force has a kink and this is the slope of the piece to the right.
  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override {
    const Vec3 n = in.markers[1].axes.col(2);
    const Vec3 d = in.markers[0].position - in.markers[1].position;
    const double x = n.dot(d), f = table_(x);
    const Mat3 nx = skew(n);
    Eigen::Matrix<double, 1, 24> dx = Eigen::Matrix<double, 1, 24>::Zero();
    dx.segment<3>(0) = n.transpose();                 // dp_i
    dx.segment<3>(12) = -n.transpose();               // dp_j
    dx.segment<3>(15) = -d.transpose() * nx;          // dtheta_j
    ElementRows df = zero_rows(jac);
    df.leftCols<24>() = table_.slope(x) * n * dx;
    df.block<3, 3>(0, 15) -= f * nx;
    jacobian_at_i(in, jac, df, zero_rows(jac), f * n);
    return true;
  }
  std::vector<Channel> channels() const override { return {{"deflection", "m"}, {"axial_force", "N"}}; }
  void channel_values(const ElementInput& in, std::span<double> out) const override {
    out[0] = deflection(in);
    out[1] = table_(out[0]);
  }
  ElementEnergy energy(const ElementInput& in) const override {
    return {-(table_.integral(deflection(in)) - table_.integral(0.0)), 0.0};
  }

 private:
  Table1D table_;
};

}  // namespace

void register_table_force(ElementRegistry& r) {
  r.add({"force", "table-force", "force along z_j from a force-deflection table (m, N): table or file + columns",
         {"i", "j"}, [](ElementContext& c) -> std::unique_ptr<ForceElement> {
           return std::make_unique<TableForce>(c.table_from("force-deflection table (m, N)"));
         }});
}

}  // namespace nvh::solve
