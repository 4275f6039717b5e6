// Point-set contact: N >= 1 points (marker origins p_1 .. p_N, all on one body: the corners of a piston skirt,
// surface nodes of a flexible body exported as markers) against the plane through marker j normal to z_j on
// another body. Each point follows the law of `contact` (contact_law.hpp) with the same keys:
//   gap_k = z_j . (p_k - p_j) + clearance,  delta_k = -gap_k,
//   fn_k = k delta_k^n (1 + alpha delta_k') (Hunt & Crossley 1975, eq. 5), F_k = fn_k z_j + ft_k (friction).
// Markers: the points 0 .. N-1 (scene key `points`, a list), then j at N (key `j`). Wrenches at each marker's
// origin: point k gets (F_k, 0); j gets the sum of the reactions moved to its origin,
//   F_j = -sum F_k,  T_j = -sum (p_k - p_j) x F_k          (action = reaction: momentum conserved).
// The results' force and torque are the resultant on the points' body at p_1 (resultant_markers() = N).
// Stored energy sum k delta_k^(n+1)/(n+1); dissipated power the sum of the points' damping and friction powers.
// The N gaps are reported to the integrators as contact events.
#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"
#include "solve/elements/contact_law.hpp"

namespace nvh::solve {
namespace {

class PointSetContact final : public ForceElement {
 public:
  PointSetContact(int points, contact::Parameters p) : n_(points), law_(p) {}
  std::string type() const override { return "point-set-contact"; }
  int marker_count() const override { return n_ + 1; }
  int resultant_markers() const override { return n_; }
  contact::State state(const ElementInput& in, int k) const { return law_.state(in.markers[k], in.markers[n_]); }

  void evaluate(const ElementInput& in, ElementOutput& out) const override {
    const Vec3& pj = in.markers[n_].position;
    Wrench& wj = out.wrenches[n_];
    for (int k = 0; k < n_; ++k) {
      const contact::State s = state(in, k);
      if (s.delta <= 0) continue;
      const Vec3 f = law_.force(s);
      out.wrenches[k].force = f;
      wj.force -= f;
      wj.torque -= (in.markers[k].position - pj).cross(f);
    }
  }

  // Per point k in contact, dF_k (3 x 24: k's columns, then j's) from the law; with d = p_k - p_j:
  //   rows of k:      dF_k
  //   rows of j:      -dF_k  and  dT_j = -d~ dF_k + F_k~ (dp_k - dp_j)
  // Columns: point k at 12 k, j at 12 N.
  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override {
    auto& m = jac.matrix;
    const int cj = 12 * n_, rj = 6 * n_;
    const MarkerMotion& j = in.markers[n_];
    contact::PointJacobian df;
    for (int k = 0; k < n_; ++k) {
      if (!law_.jacobian(in.markers[k], j, df)) continue;  // no force around here
      const Vec3 f = law_.force(state(in, k));
      const Mat3 dx = skew(in.markers[k].position - j.position), fx = skew(f);
      for (const auto& [col, part] : {std::pair{12 * k, 0}, std::pair{cj, 12}}) {
        const auto d_force = df.middleCols<12>(part);
        m.block<3, 12>(6 * k, col) += d_force;
        m.block<3, 12>(rj, col) -= d_force;
        m.block<3, 12>(rj + 3, col).noalias() -= dx * d_force;
      }
      m.block<3, 3>(rj + 3, 12 * k) += fx;  // dp_k
      m.block<3, 3>(rj + 3, cj) -= fx;      // dp_j
    }
    return true;
  }

  std::vector<Channel> channels() const override {
    std::vector<Channel> c;
    for (int k = 1; k <= n_; ++k) {
      const std::string s = std::to_string(k);
      c.push_back({"gap_" + s, "m"});
      c.push_back({"normal_force_" + s, "N"});
      c.push_back({"slip_speed_" + s, "m/s"});
    }
    c.push_back({"normal_force", "N"});
    return c;
  }
  void channel_values(const ElementInput& in, std::span<double> out) const override {
    double total = 0;
    for (int k = 0; k < n_; ++k) {
      const auto v = law_.channel_values(state(in, k));
      for (int c = 0; c < 3; ++c) out[3 * k + c] = v[c];
      total += v[1];
    }
    out[3 * n_] = total;
  }
  ElementEnergy energy(const ElementInput& in) const override {
    ElementEnergy e;
    for (int k = 0; k < n_; ++k) {
      const ElementEnergy p = law_.energy(state(in, k));
      e.stored += p.stored;
      e.dissipated += p.dissipated;
    }
    return e;
  }
  int gap_count() const override { return n_; }
  void gaps(const ElementInput& in, std::span<double> out) const override {
    for (int k = 0; k < n_; ++k) out[k] = -state(in, k).delta;
  }

 private:
  int n_;
  contact::Law law_;
};

}  // namespace

void register_point_set_contact(ElementRegistry& r) {
  r.add({"force", "point-set-contact",
         std::string("points (a list, all on one body) against the plane of marker j, each with the law of "
                     "`contact`: ") + contact::kKeys,
         {"points[]", "j"}, [](ElementContext& c) -> std::unique_ptr<ForceElement> {
           const auto& t = c.table;
           const auto& bodies = c.marker_bodies;  // the points, then j
           const int n = static_cast<int>(bodies.size()) - 1;
           for (int k = 1; k < n; ++k)
             if (bodies[k] != bodies[0])
               t.fail("points", "all points must be on one body: point " + std::to_string(k + 1) + " is on '" +
                                    bodies[k] + "', point 1 on '" + bodies[0] + "'");
           if (bodies[n] == bodies[0])
             t.fail("j", "marker j is on the points' body '" + bodies[0] + "': the plane must be on another body");
           return std::make_unique<PointSetContact>(n, contact::read_parameters(t));
         }});
}

}  // namespace nvh::solve
