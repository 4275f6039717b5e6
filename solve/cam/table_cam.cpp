// The tabulated cam profile: follower lift s_i (m) at cam angles theta_i (rad), i = 0..n-1, interpolated by
// the periodic cubic spline of period 2 pi (C2: lift, velocity and acceleration continuous, also across the
// wrap).
//
// Spline (e.g. C. de Boor, A Practical Guide to Splines, rev. ed., Springer 2001, chapter IV; the periodic
// case as in W. H. Press et al., Numerical Recipes, 3rd ed., section 3.3 and 2.7.2): with h_i = theta_{i+1} -
// theta_i (theta_n = theta_0 + 2 pi, s_n = s_0, indices cyclic) and M_i = s''(theta_i), continuity of s' at
// every node gives the cyclic tridiagonal system
//   h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 ((s_{i+1} - s_i)/h_i - (s_i -
//   s_{i-1})/h_{i-1}),
// solved here by the Thomas algorithm with the Sherman-Morrison correction for the two corner entries
// (Numerical Recipes, section 2.7.2, "cyclic tridiagonal systems"). On [theta_i, theta_{i+1}], t = theta -
// theta_i:  s = s_i + b t + c t^2 + d t^3,  c = M_i / 2,  d = (M_{i+1} - M_i) / (6 h_i),
//           b = (s_{i+1} - s_i)/h_i - h_i (2 M_i + M_{i+1}) / 6.
// The interpolation error of a smooth lift falls as h^4 (lift), h^3 (velocity), h^2 (acceleration).
//
// Checks (errors name the table's file or key and the cam angle in deg): at least 8 points; angles strictly
// increasing and spanning less than 360 deg (a last row at first + 360 deg closes the table and must repeat
// the first lift; it is then dropped); lift >= 0 and <= 10 m; and smooth enough: the spline through all
// points and the spline through every other point (the even-numbered ones) must agree, at the nodes and the
// mid-points of the table, to 1 % of the largest lift (lift), 5 % of the largest |velocity| (velocity) and
// 25 % of the largest |acceleration| (acceleration), the largest values those of the spline through all
// points. Where they do not, the table is too coarse or has a step or a kink there, and the dynamics would
// see the spline's wiggles (an acceleration of order jump / h) as if they were the cam's. read_cam_profile
// then runs check_roller_fits.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "common/error.hpp"
#include "solve/cam/profiles.hpp"
#include "solve/table.hpp"

namespace nvh::solve::cam {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2 * kPi;
constexpr double kDeg = kPi / 180.0;

std::string deg(double rad) {
  return format_number(rad / kDeg, 8) + " deg";
}

/// A periodic cubic spline through (x_i, y_i), period T > x_{n-1} - x_0, n >= 3.
class PeriodicSpline {
 public:
  PeriodicSpline(std::vector<double> x, std::vector<double> y, double period)
      : x_(std::move(x)), y_(std::move(y)), period_(period) {
    const int n = static_cast<int>(x_.size());
    Eigen::VectorXd h(n), a(n), b(n), c(n), r(n);
    for (int i = 0; i < n; ++i) h[i] = (i + 1 < n ? x_[i + 1] : x_[0] + period_) - x_[i];
    for (int i = 0; i < n; ++i) {
      const int im = (i + n - 1) % n, ip = (i + 1) % n;
      a[i] = h[im];
      b[i] = 2 * (h[im] + h[i]);
      c[i] = h[i];
      r[i] = 6 * ((y_[ip] - y_[i]) / h[i] - (y_[i] - y_[im]) / h[im]);
    }
    const Eigen::VectorXd m = solve_cyclic(a, b, c, r);
    coef_.resize(n);
    for (int i = 0; i < n; ++i) {
      const int ip = (i + 1) % n;
      coef_[i] = {y_[i], (y_[ip] - y_[i]) / h[i] - h[i] * (2 * m[i] + m[ip]) / 6, m[i] / 2,
                  (m[ip] - m[i]) / (6 * h[i]), h[i]};
    }
  }

  Lift operator()(double x) const {
    const std::size_t i = piece(x);
    const Piece& p = coef_[i];
    const double t = x - x_[i];
    return {p.y + t * (p.b + t * (p.c + t * p.d)), p.b + t * (2 * p.c + 3 * t * p.d), 2 * p.c + 6 * t * p.d,
            6 * p.d};
  }

  /// The largest value and where it is: the ends of each piece and the roots of its derivative inside.
  std::pair<double, double> maximum() const {
    double best = -std::numeric_limits<double>::infinity(), where = 0;
    const auto consider = [&](double x) {
      const double v = (*this)(x).s;
      if (v > best) best = v, where = x;
    };
    for (std::size_t i = 0; i < coef_.size(); ++i) {
      const Piece& p = coef_[i];
      consider(x_[i]);
      // s' = b + 2 c t + 3 d t^2 = 0
      const double qa = 3 * p.d, qb = 2 * p.c, qc = p.b;
      std::vector<double> roots;
      if (std::abs(qa) * p.h < 1e-12 * (std::abs(qb) + std::abs(qc) / p.h)) {
        if (qb != 0) roots.push_back(-qc / qb);
      } else {
        const double disc = qb * qb - 4 * qa * qc;
        if (disc >= 0) {
          const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
          if (q != 0) roots.push_back(qc / q);
          roots.push_back(q / qa);
        }
      }
      for (const double t : roots)
        if (t > 0 && t < p.h) consider(x_[i] + t);
    }
    return {best, where};
  }

  const std::vector<double>& x() const { return x_; }
  double interval(std::size_t i) const { return coef_[i].h; }

 private:
  struct Piece {
    double y, b, c, d, h;
  };

  /// a_i M_{i-1} + b_i M_i + c_i M_{i+1} = r_i, indices cyclic: Thomas on the matrix with the corners
  /// removed and b_0, b_{n-1} changed, plus the Sherman-Morrison correction (Numerical Recipes 2.7.2).
  static Eigen::VectorXd solve_cyclic(const Eigen::VectorXd& a, Eigen::VectorXd b, const Eigen::VectorXd& c,
                                      const Eigen::VectorXd& r) {
    const int n = static_cast<int>(b.size());
    const double alpha = c[n - 1], beta = a[0];  // the corners: row n-1, column 0 and row 0, column n-1
    const double gamma = -b[0];
    b[0] -= gamma;
    b[n - 1] -= alpha * beta / gamma;
    const auto thomas = [&](const Eigen::VectorXd& rhs) {
      Eigen::VectorXd cp(n), x(n);
      double den = b[0];
      cp[0] = c[0] / den;
      x[0] = rhs[0] / den;
      for (int i = 1; i < n; ++i) {
        den = b[i] - a[i] * cp[i - 1];
        cp[i] = c[i] / den;
        x[i] = (rhs[i] - a[i] * x[i - 1]) / den;
      }
      for (int i = n - 2; i >= 0; --i) x[i] -= cp[i] * x[i + 1];
      return x;
    };
    const Eigen::VectorXd x = thomas(r);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
    u[0] = gamma;
    u[n - 1] = alpha;
    const Eigen::VectorXd z = thomas(u);
    const double fact = (x[0] + beta * x[n - 1] / gamma) / (1.0 + z[0] + beta * z[n - 1] / gamma);
    return x - fact * z;
  }

  std::size_t piece(double& x) const {
    double w = std::fmod(x - x_.front(), period_);
    if (w < 0) w += period_;
    if (!(w < period_)) w = 0;  // fmod of a value just below a multiple of the period, rounded up
    x = x_.front() + w;
    const auto it = std::upper_bound(x_.begin(), x_.end(), x);
    return it == x_.begin() ? 0 : static_cast<std::size_t>(it - x_.begin()) - 1;
  }

  std::vector<double> x_, y_;
  double period_;
  std::vector<Piece> coef_;
};

/// The smoothness check of the header comment; throws Error(where + ...) naming the worst point.
void check_smooth(const PeriodicSpline& all, const std::vector<double>& angles,
                  const std::vector<double>& lifts, const std::string& where) {
  std::vector<double> xe, ye;
  for (std::size_t i = 0; i < angles.size(); i += 2) {
    xe.push_back(angles[i]);
    ye.push_back(lifts[i]);
  }
  const PeriodicSpline half(xe, ye, kTwoPi);
  std::vector<double> at;
  for (std::size_t i = 0; i < angles.size(); ++i) {
    at.push_back(angles[i]);
    at.push_back(angles[i] + 0.5 * all.interval(i));
  }
  double max_s = 0, max_v = 0, max_a = 0;
  for (const double x : at) {
    const Lift l = all(x);
    max_s = std::max(max_s, std::abs(l.s));
    max_v = std::max(max_v, std::abs(l.ds));
    max_a = std::max(max_a, std::abs(l.dds));
  }
  struct Quantity {
    const char* name;
    const char* unit;
    double limit_fraction;
    double largest;
  };
  const Quantity q[3] = {{"lift", "m", 0.01, max_s},
                         {"velocity", "m/rad", 0.05, max_v},
                         {"acceleration", "m/rad^2", 0.25, max_a}};
  double worst = 1.0, worst_x = 0, worst_all = 0, worst_half = 0;
  int worst_q = -1;
  for (const double x : at) {
    const Lift la = all(x), lh = half(x);
    const double va[3] = {la.s, la.ds, la.dds}, vh[3] = {lh.s, lh.ds, lh.dds};
    for (int k = 0; k < 3; ++k) {
      const double limit = q[k].limit_fraction * q[k].largest;
      if (limit <= 0) continue;
      const double ratio = std::abs(va[k] - vh[k]) / limit;
      if (ratio > worst) worst = ratio, worst_x = x, worst_q = k, worst_all = va[k], worst_half = vh[k];
    }
  }
  if (worst_q < 0) return;
  const Quantity& w = q[worst_q];
  throw Error(where + ": not smooth enough at cam angle " + deg(worst_x) + ": " + w.name +
              " of the spline through all points " + format_number(worst_all) + " " + w.unit +
              ", through every other point " + format_number(worst_half) + " " + w.unit + ", a difference of " +
              format_number(std::abs(worst_all - worst_half)) + " " + w.unit + ", more than " +
              format_number(100 * w.limit_fraction) + " % of the largest |" + w.name + "| (" + format_number(w.largest) +
              " " + w.unit + "): the table has a step or a kink there, or is too coarse for its " + w.name);
}

class TableCam final : public CamProfile {
 public:
  TableCam(PeriodicSpline spline, double rb, double rr) : spline_(std::move(spline)), rb_(rb), rr_(rr) {
    const auto [value, where] = spline_.maximum();
    max_lift_ = value;
    max_angle_ = wrap_2pi(where);
  }
  std::string kind() const override { return "table"; }
  Lift lift(double theta) const override { return spline_(theta); }
  double base_radius() const override { return rb_; }
  double roller_radius() const override { return rr_; }
  double max_lift() const override { return max_lift_; }
  double max_lift_angle() const override { return max_angle_; }

 private:
  PeriodicSpline spline_;
  double rb_, rr_;
  double max_lift_ = 0, max_angle_ = 0;
};

const input::Range kRadius{0.0, 10.0, true, false};  // m

}  // namespace

std::unique_ptr<CamProfile> table_cam(std::vector<double> angles, std::vector<double> lifts,
                                      double base_radius, double roller_radius, const std::string& where) {
  if (angles.size() != lifts.size())
    throw Error(where + ": " + std::to_string(angles.size()) + " angles but " + std::to_string(lifts.size()) +
                " lifts");
  for (std::size_t i = 0; i < angles.size(); ++i)
    if (!std::isfinite(angles[i]) || !std::isfinite(lifts[i]))
      throw Error(where + ": row " + std::to_string(i + 1) + " is not a pair of finite numbers");
  for (std::size_t i = 1; i < angles.size(); ++i)
    if (!(angles[i] > angles[i - 1]))
      throw Error(where + ": the cam angles must increase strictly, but row " + std::to_string(i + 1) + " (" +
                  deg(angles[i]) + ") does not exceed row " + std::to_string(i) + " (" + deg(angles[i - 1]) +
                  ")");
  if (angles.size() >= 2) {
    const double span = angles.back() - angles.front();
    if (std::abs(span - kTwoPi) <= 1e-9) {  // a closing row: the first again, one turn later
      double largest = 0;
      for (const double s : lifts) largest = std::max(largest, std::abs(s));
      if (std::abs(lifts.back() - lifts.front()) > 1e-9 * largest)
        throw Error(where + ": the last row, at cam angle " + deg(angles.back()) +
                    " (one turn after the first), must repeat the first row's lift " + format_number(lifts.front()) +
                    " m, not " + format_number(lifts.back()) + " m (a step at the wrap)");
      angles.pop_back();
      lifts.pop_back();
    } else if (span > kTwoPi) {
      throw Error(where + ": the cam angles span " + deg(span) + " (from " + deg(angles.front()) + " to " +
                  deg(angles.back()) +
                  "), more than one turn: give less than 360 deg, the wrap from the last " +
                  "row to the first closes the table");
    }
  }
  if (angles.size() < 8)
    throw Error(where + ": a cam lift table needs at least 8 points in the turn, got " +
                std::to_string(angles.size()));
  for (std::size_t i = 0; i < lifts.size(); ++i) {
    if (lifts[i] < 0)
      throw Error(where + ": negative lift " + format_number(lifts[i]) + " m at cam angle " + deg(angles[i]) +
                  " (the lift is measured from the base circle: >= 0)");
    if (lifts[i] > 10.0)
      throw Error(where + ": lift " + format_number(lifts[i]) + " m at cam angle " + deg(angles[i]) +
                  " larger than 10 m (is lift_scale right?)");
  }
  if (!(base_radius > 0 && roller_radius > 0)) throw Error(where + ": the radii must be > 0");
  PeriodicSpline spline(angles, lifts, kTwoPi);
  check_smooth(spline, angles, lifts, where);
  return std::make_unique<TableCam>(std::move(spline), base_radius, roller_radius);
}

std::unique_ptr<CamProfile> read_table_cam(const input::Table& t, const std::filesystem::path& base,
                                           std::vector<std::filesystem::path>& inputs) {
  const double rb = t.number("base_radius", kRadius);
  const double rr = t.number("roller_radius", kRadius);
  const double scale = t.number_or("lift_scale", 1.0, input::Range{0.0, 1.0, true, false});
  if (t.has("table") && t.has("file")) t.fail("file", "give either 'table' or 'file', not both");
  std::vector<double> angles, lifts;
  std::string key, where;
  if (t.has("file")) {
    key = "file";
    const auto file = base / t.string("file");
    where = file.string();
    std::vector<std::string> cols = {"", ""};
    if (t.has("columns")) {
      cols = t.strings("columns");
      if (cols.size() != 2) t.fail("columns", "expected two column names [cam angle (deg), lift]");
    }
    inputs.push_back(file);
    try {
      const Table1D table = read_csv_table(file, cols[0], cols[1]);
      angles = table.xs();
      lifts = table.ys();
    } catch (const Error& e) {
      if (!e.where().file.empty()) throw;
      t.fail("file", e.message());
    }
  } else {
    key = "table";
    where = "the lift table";
    if (!t.has("table"))
      t.fail("a table cam needs 'table' = [[cam angle (deg), lift], ...] or 'file' = \"lift.csv\"");
    for (const auto& row : t.number_rows("table", 2, input::Range::magnitude(1e6))) {
      angles.push_back(row[0]);
      lifts.push_back(row[1]);
    }
  }
  for (double& a : angles) a *= kDeg;
  for (double& s : lifts) s *= scale;
  try {
    return table_cam(std::move(angles), std::move(lifts), rb, rr, where);
  } catch (const Error& e) {
    if (!e.where().file.empty()) throw;
    t.fail(key, e.message());
  }
}

}  // namespace nvh::solve::cam
