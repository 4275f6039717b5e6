// A chain of N internal point masses between marker i (one end: a valve spring's retainer) and marker j (the
// other end: the spring's seat on the head), moving along the line j -> i (issue 13, item 2). Two types share
// the class: `mass-chain` (masses, rate, damping given) and `valve-spring` (the chain generated from wire
// data).
//
//   e = (p_i - p_j) / L,  L = |p_i - p_j|,  L' = e . (v_i - v_j)
//   nodes y_0 = h, y_k = x_k (k = 1..N, the internal states), y_{N+1} = L - h   (h: the dead coils' height)
//   segment s = 0..N from node s to node s+1: l_s = y_{s+1} - y_s, rate r_s (v_k - u_j for the internal
//   nodes, 0 at j, L' at i)
//   f_s = k_s (l0 - l_s) - c_s r_s + k_c max(0, l_solid - l_s)     segment force, compression positive (N)
//   states x_k (m, from j along the line) and v_k (m/s, the mass's ABSOLUTE velocity along the line), both
//   differential; with u_j = e . v_j (j's velocity along the line) their rows
//     x_k' - (v_k - u_j) = 0
//     m_k v_k' - (f_{k-1} - f_k) = 0
//   are the chain's equations of motion along the line, in an inertial frame: a chain between two moving
//   bodies (a pushrod between tappet and rocker) carries its own inertia. Neglected: the turning of the line
//   (e' terms, the masses' lateral motion; their inertia acts along the line only) and gravity on the masses
//   (a valve spring's few grams against hundreds of newtons of preload).
//   wrenches at the markers' origins: F_i = f_N e (the i-end segment pushes i away from j), F_j = -f_0 e.
// Each segment has free length l0 = (free_length - 2 h) / (N + 1) and rate k_s = (N + 1) k, so the chain's
// static rate is k. Coil clash: a segment shorter than its solid length l_solid gets the penalty k_c
// (linear, clash_factor x k_s, default 100): the stiffening contact between neighbouring masses.
// Initial states: the static equilibrium at the initial marker distance L0 (equal segments: linear
// interpolation, x_k = h + k (L0 - 2 h) / (N + 1), v_k interpolated between e . v_j and e . v_i), plus
// `initial_displacement` if given.
//
// Energy: stored = sum k_s (l_s - l0)^2 / 2 + k_c max(0, l_solid - l_s)^2 / 2 + sum m_k v_k^2 / 2 (absolute
// velocities); dissipated = sum c_s r_s^2. The model's balance closes up to the neglected turning of the
// line.
//
// valve-spring (Wahl, Mechanical Springs, 2nd ed. 1963, ch. 2 and 25; Shigley's Mechanical Engineering
// Design, 10th ed., sec. 10-3 and 10-8): wire d, mean coil diameter D, active coils n_a, dead coils n_d
// per end, shear modulus G, density rho:
//   k = G d^4 / (8 D^3 n_a),   m_a = rho (pi d^2 / 4) (pi D n_a)   (active mass)
//   N + 1 equal segments of the active coils; each internal mass m_a / (N + 1) (consistent lumping: the
//   fixed-fixed first frequency (1/pi) sqrt((N+1)^2 k / m_a) sin(pi / (2 (N+1))) tends to the continuous
//   spring's (1/2) sqrt(k / m_a) = d / (2 pi n_a D^2) sqrt(G / (2 rho)) as 1 - (pi / (2 (N+1)))^2 / 6).
//   The half segments at the two ends (m_a / (2 (N+1)) each) and the dead coils (rho (pi d^2/4) pi D n_d
//   each) belong to the end bodies: the channel `end_mass` is that mass, to add to the retainer side's body.
//   Dead coils: solid, height h = n_d d at each end; solid length (n_a + 2 n_d) d (squared and ground ends,
//   Shigley table 10-1), each segment's share l_solid = n_a d / (N + 1).
#include <cmath>
#include <numbers>

#include <Eigen/Eigenvalues>

#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"

namespace nvh::solve {
namespace {

struct ChainParameters {
  std::string type;
  std::vector<double> mass;              // kg, each internal mass (N of them)
  double k_s = 0, c_s = 0;               // N/m, N s/m per segment
  double free_length = 0;                // m, the whole chain (spring)
  double end_height = 0;                 // m, h: rigid length at each end (the dead coils)
  double solid = 0;                      // m, each segment's solid length (0: no clash)
  double k_clash = 0;                    // N/m, the penalty below it
  double end_mass = -1;                  // kg, valve-spring: mass for the retainer side (< 0: no channel)
  std::vector<double> initial;           // m, initial x_k
  std::vector<double> initial_velocity;  // m/s, initial v_k
};

class MassChain final : public ForceElement {
 public:
  explicit MassChain(ChainParameters p)
      : p_(std::move(p)),
        n_(static_cast<int>(p_.mass.size())),
        segments_(n_ + 1),
        l0_((p_.free_length - 2 * p_.end_height) / (n_ + 1)) {}
  std::string type() const override { return p_.type; }
  int marker_count() const override { return 2; }
  std::vector<StateDefinition> states() const override {
    std::vector<StateDefinition> s;
    for (int k = 1; k <= n_; ++k) {
      s.push_back({"position_" + std::to_string(k), "m", true, p_.initial[k - 1]});
      s.push_back({.name = "velocity_" + std::to_string(k),
                   .unit = "m/s",
                   .differential = true,
                   .initial = p_.initial_velocity[k - 1],
                   .velocity = true});
    }
    return s;
  }

  struct Line {
    Vec3 e;
    double length, rate;
    Vec3 g;     // dL'/dd = (w - e (e . w)) / L, w = v_i - v_j
    double uj;  // e . v_j (m/s)
    Vec3 gj;    // duj/dd = (v_j - e (e . v_j)) / L
  };
  static Line line(const ElementInput& in) {
    const Vec3 d = in.markers[0].position - in.markers[1].position;
    const Vec3 w = in.markers[0].velocity - in.markers[1].velocity;
    const double l = d.norm();
    const Vec3 e = l > 1e-12 ? Vec3(d / l) : Vec3::UnitZ();
    const double rate = e.dot(w);
    const Vec3& vj = in.markers[1].velocity;
    const double uj = e.dot(vj);
    return {e,    l,
            rate, l > 1e-12 ? Vec3((w - rate * e) / l) : Vec3::Zero(),
            uj,   l > 1e-12 ? Vec3((vj - uj * e) / l) : Vec3::Zero()};
  }
  // Node n's position and rate: 0 = the j end, 1..N the masses, N+1 the i end.
  double node(const ElementInput& in, const Line& s, int n) const {
    return n == 0 ? p_.end_height : n > n_ ? s.length - p_.end_height : in.z[2 * std::size_t(n - 1)];
  }
  double node_rate(const ElementInput& in, const Line& s, int n) const {
    return n == 0 ? 0.0 : n > n_ ? s.rate : in.z[2 * std::size_t(n - 1) + 1] - s.uj;
  }
  struct Segment {
    double length, rate, force, stiffness;  // m, m/s, N (compression positive), -df/dl (N/m)
    bool clash;
  };
  Segment segment(const ElementInput& in, const Line& s, int k) const {
    Segment g;
    g.length = node(in, s, k + 1) - node(in, s, k);
    g.rate = node_rate(in, s, k + 1) - node_rate(in, s, k);
    g.clash = p_.solid > 0 && g.length < p_.solid;
    g.force =
        p_.k_s * (l0_ - g.length) - p_.c_s * g.rate + (g.clash ? p_.k_clash * (p_.solid - g.length) : 0.0);
    g.stiffness = p_.k_s + (g.clash ? p_.k_clash : 0.0);
    return g;
  }

  void evaluate(const ElementInput& in, ElementOutput& out) const override {
    const Line s = line(in);
    Segment below = segment(in, s, 0);
    out.wrenches[1].force = -below.force * s.e;
    for (int k = 1; k < segments_; ++k) {
      const Segment above = segment(in, s, k);
      out.state_residual[2 * (k - 1)] = in.zp[2 * (k - 1)] - (in.z[2 * (k - 1) + 1] - s.uj);
      out.state_residual[2 * (k - 1) + 1] =
          p_.mass[k - 1] * in.zp[2 * (k - 1) + 1] - (below.force - above.force);
      below = above;
    }
    out.wrenches[0].force = below.force * s.e;
  }

  // With d = p_i - p_j, w = v_i - v_j: dL = e^T dd, dL' = g^T dd + e^T dw; df_s = -K_s (dy_{s+1} - dy_s)
  // - c_s (dy'_{s+1} - dy'_s), K_s = k_s (+ k_c in clash). F_i = f_N e: dF_i = e df_N + f_N (1 - e e^T)/L dd;
  // F_j = -f_0 e likewise. Row x_k: cj at x_k, -1 at v_k, + du_j; row v_k: cj m_k at v_k, -df_{k-1} + df_k.
  // An internal node's rate v_k - u_j: du_j = gj^T dd + e^T dv_j.
  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override {
    const Line s = line(in);
    if (s.length <= 1e-12) return false;
    auto& m = jac.matrix;
    const int states = jac.state_column(2, 0);
    // adds b du_j to row r
    auto add_uj = [&](int r, double b) {
      m.block<1, 3>(r, 0) += b * s.gj.transpose();
      m.block<1, 3>(r, 12) -= b * s.gj.transpose();
      m.block<1, 3>(r, 18) += b * s.e.transpose();
    };
    // adds a dy_n + b dy'_n to row r
    auto add_node = [&](int r, int n, double a, double b) {
      if (n == 0) return;
      if (n <= n_) {
        m(r, states + 2 * (n - 1)) += a;
        m(r, states + 2 * (n - 1) + 1) += b;
        add_uj(r, -b);
        return;
      }
      const Eigen::RowVector3d dd = a * s.e.transpose() + b * s.g.transpose(), dw = b * s.e.transpose();
      m.block<1, 3>(r, 0) += dd;
      m.block<1, 3>(r, 12) -= dd;
      m.block<1, 3>(r, 6) += dw;
      m.block<1, 3>(r, 18) -= dw;
    };
    // adds scale df_k to row r
    auto add_segment = [&](int r, int k, double scale) {
      const double stiffness = segment(in, s, k).stiffness;
      add_node(r, k + 1, -scale * stiffness, -scale * p_.c_s);
      add_node(r, k, scale * stiffness, scale * p_.c_s);
    };
    const double f_i = segment(in, s, n_).force, f_j = segment(in, s, 0).force;
    const Mat3 de = (Mat3::Identity() - s.e * s.e.transpose()) / s.length;
    for (int c = 0; c < 3; ++c) {
      add_segment(c, n_, s.e[c]);
      add_segment(6 + c, 0, -s.e[c]);
    }
    m.block<3, 3>(0, 0) += f_i * de;
    m.block<3, 3>(0, 12) -= f_i * de;
    m.block<3, 3>(6, 0) -= f_j * de;
    m.block<3, 3>(6, 12) += f_j * de;
    for (int k = 1; k < segments_; ++k) {
      const int rx = 12 + 2 * (k - 1), rv = rx + 1;
      m(rx, states + 2 * (k - 1)) += jac.cj;
      m(rx, states + 2 * (k - 1) + 1) -= 1.0;
      add_uj(rx, 1.0);
      m(rv, states + 2 * (k - 1) + 1) += jac.cj * p_.mass[k - 1];
      add_segment(rv, k - 1, -1.0);
      add_segment(rv, k, 1.0);
    }
    return true;
  }

  // force_i, force_j (N, compression positive), deflection (m, free_length - L), clash (segments in clash),
  // x_1..x_N (m, each mass's displacement from its quasi-static position at the current length), end_mass
  // (kg).
  std::vector<Channel> channels() const override {
    std::vector<Channel> c = {{"force_i", "N"}, {"force_j", "N"}, {"deflection", "m"}, {"clash", "1"}};
    for (int k = 1; k <= n_; ++k) c.push_back({"x_" + std::to_string(k), "m"});
    if (p_.end_mass >= 0) c.push_back({"end_mass", "kg"});
    return c;
  }
  void channel_values(const ElementInput& in, std::span<double> out) const override {
    const Line s = line(in);
    out[0] = segment(in, s, n_).force;
    out[1] = segment(in, s, 0).force;
    out[2] = p_.free_length - s.length;
    int clash = 0;
    for (int k = 0; k < segments_; ++k) clash += segment(in, s, k).clash ? 1 : 0;
    out[3] = clash;
    const double pitch = (s.length - 2 * p_.end_height) / (n_ + 1);
    for (int k = 1; k <= n_; ++k) out[3 + k] = in.z[2 * (k - 1)] - (p_.end_height + k * pitch);
    if (p_.end_mass >= 0) out[4 + n_] = p_.end_mass;
  }
  ElementEnergy energy(const ElementInput& in) const override {
    const Line s = line(in);
    ElementEnergy e;
    for (int k = 0; k < segments_; ++k) {
      const Segment g = segment(in, s, k);
      const double pen = g.clash ? p_.solid - g.length : 0.0;
      e.stored += 0.5 * p_.k_s * (g.length - l0_) * (g.length - l0_) + 0.5 * p_.k_clash * pen * pen;
      e.dissipated += p_.c_s * g.rate * g.rate;
    }
    for (int k = 1; k <= n_; ++k) e.stored += 0.5 * p_.mass[k - 1] * in.z[2 * k - 1] * in.z[2 * k - 1];
    return e;
  }
  int gap_count() const override { return p_.solid > 0 ? n_ + 1 : 0; }
  void gaps(const ElementInput& in, std::span<double> out) const override {
    const Line s = line(in);
    for (int k = 0; k < segments_; ++k) out[k] = segment(in, s, k).length - p_.solid;
  }

 private:
  ChainParameters p_;
  int n_, segments_;  // N masses, N + 1 segments (the loops calling segment(k + 1) run to segments_)
  double l0_;         // m, each segment's free length
};

/// The first fixed-fixed natural frequency (rad/s) of the chain: K tridiagonal (2 k_s, -k_s), M diagonal;
/// the lowest eigenvalue of the tridiagonal M^-1/2 K M^-1/2.
double first_frequency(const std::vector<double>& mass, double k_s) {
  const int n = static_cast<int>(mass.size());
  Eigen::VectorXd diagonal(n), off(std::max(n - 1, 0));
  for (int r = 0; r < n; ++r) {
    diagonal[r] = 2 * k_s / mass[r];
    if (r + 1 < n) off[r] = -k_s / std::sqrt(mass[r] * mass[r + 1]);
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver;
  solver.computeFromTridiagonal(diagonal, off, Eigen::EigenvaluesOnly);
  return std::sqrt(solver.eigenvalues()[0]);
}

/// The keys both types share: damping (segment, N s/m) or damping_ratio (of the first fixed-fixed mode,
/// stiffness-proportional: c_s = 2 zeta k_s / w_1, mode r gets zeta w_r / w_1), clash_factor, the initial
/// states.
void common_keys(ElementContext& c, ChainParameters& p) {
  using input::Range;
  const auto& t = c.table;
  const int n = static_cast<int>(p.mass.size());
  if (t.has("damping") && t.has("damping_ratio"))
    t.fail("damping_ratio", "give damping or damping_ratio, not both");
  if (t.has("damping_ratio"))
    p.c_s = 2 * t.number("damping_ratio", Range::closed(0.0, 10.0)) * p.k_s / first_frequency(p.mass, p.k_s);
  else
    p.c_s = t.number_or("damping", 0.0, Range::closed(0.0, bounds::kCoefficient));
  p.k_clash = t.number_or("clash_factor", 100.0, Range::closed(0.0, 1e6)) * p.k_s;
  const double l0 = (c.initial[0].position - c.initial[1].position).norm();
  std::vector<double> offset(n, 0.0);
  if (t.has("initial_displacement")) {
    offset = t.numbers("initial_displacement", Range::magnitude(bounds::kLength));
    if (static_cast<int>(offset.size()) != n)
      t.fail("initial_displacement", "needs one value per mass (" + std::to_string(n) + ")");
  }
  const Vec3 d = c.initial[0].position - c.initial[1].position;
  const Vec3 e = l0 > 1e-12 ? Vec3(d / l0) : Vec3::UnitZ();
  const double ui = e.dot(c.initial[0].velocity), uj = e.dot(c.initial[1].velocity);
  for (int k = 1; k <= n; ++k) {
    p.initial.push_back(p.end_height + k * (l0 - 2 * p.end_height) / (n + 1) + offset[k - 1]);
    p.initial_velocity.push_back(uj + (ui - uj) * k / (n + 1));
  }
}

}  // namespace

void register_mass_chain(ElementRegistry& r) {
  r.add({"force",
         "mass-chain",
         "N internal point masses along the line j -> i joined by N+1 equal spring-dampers (surge of a coil "
         "spring): masses, mass or mass_list, stiffness (overall static rate), damping or damping_ratio, "
         "free_length, solid_length, clash_factor, initial_displacement",
         {"i", "j"},
         [](ElementContext& c) -> std::unique_ptr<ForceElement> {
           using input::Range;
           const auto& t = c.table;
           ChainParameters p;
           p.type = "mass-chain";
           if (t.has("mass_list")) {
             p.mass = t.numbers("mass_list", Range{0.0, bounds::kMass, true, false});
             if (p.mass.empty()) t.fail("mass_list", "needs at least one mass");
             if (t.has("mass")) t.fail("mass", "give mass (the total) or mass_list, not both");
             if (t.has("masses") && t.integer("masses") != static_cast<std::int64_t>(p.mass.size()))
               t.fail("masses", "differs from the length of mass_list");
           } else {
             const auto n = t.integer("masses", Range::closed(1, 1000));
             p.mass.assign(n,
                           t.number("mass", Range{0.0, bounds::kMass, true, false}) / static_cast<double>(n));
           }
           const double n1 = static_cast<double>(p.mass.size() + 1);
           p.k_s = n1 * t.number("stiffness", Range{0.0, bounds::kCoefficient, true, false});
           p.free_length = t.has("free_length") ? t.number("free_length", Range::closed(0.0, bounds::kLength))
                                                : (c.initial[0].position - c.initial[1].position).norm();
           p.solid = t.number_or("solid_length", 0.0, Range::closed(0.0, bounds::kLength)) / n1;
           common_keys(c, p);
           return std::make_unique<MassChain>(std::move(p));
         }});
  r.add(
      {"force",
       "valve-spring",
       "helical valve spring as a chain of masses from wire data (surge, coil clash): wire_diameter, "
       "mean_diameter, active_coils, dead_coils, free_length, shear_modulus, density, masses, damping_ratio "
       "or damping, clash_factor, initial_displacement",
       {"i", "j"},
       [](ElementContext& c) -> std::unique_ptr<ForceElement> {
         using input::Range;
         constexpr double kPi = std::numbers::pi;
         const auto& t = c.table;
         const Range positive{0.0, bounds::kLength, true, false};
         const double d = t.number("wire_diameter", positive), dm = t.number("mean_diameter", positive);
         const double na = t.number("active_coils", Range{0.0, 1e4, true, false});
         const double nd = t.number_or("dead_coils", 1.0, Range::closed(0.0, 1e4));
         const double g = t.number_or("shear_modulus", 79.3e9, Range{0.0, bounds::kCoefficient, true, false});
         const double rho = t.number_or("density", 7850.0, Range{0.0, 1e6, true, false});
         const auto n = t.optional_integer("masses", Range::closed(1, 1000)).value_or(5);
         const double n1 = static_cast<double>(n + 1);
         const double k = g * std::pow(d, 4) / (8 * std::pow(dm, 3) * na);
         const double wire = rho * kPi * d * d / 4 * kPi * dm;  // kg per coil
         ChainParameters p;
         p.type = "valve-spring";
         p.mass.assign(n, wire * na / n1);
         p.k_s = n1 * k;
         p.free_length = t.number("free_length", positive);
         p.end_height = nd * d;
         p.solid = na * d / n1;
         if (p.free_length <= (na + 2 * nd) * d)
           t.fail("free_length",
                  "is not longer than the solid length (active_coils + 2 dead_coils) wire_diameter");
         p.end_mass = wire * na / (2 * n1) + wire * nd;
         common_keys(c, p);
         return std::make_unique<MassChain>(std::move(p));
       }});
}

}  // namespace nvh::solve
