// Unilateral contact of marker i's origin against the plane through marker j normal to z_j (pointing out of j's
// material), with clearance: gap = z_j . (p_i - p_j) + clearance, penetration delta = -gap (> 0 in contact).
// With the markers at the nominal (line-to-line) geometry, `clearance` is the free play.
// The law (contact_law.hpp): Hunt & Crossley normal force fn = k delta^n (1 + alpha delta') (J. Appl. Mech. 42,
// 1975, eq. 5), never pulling, with regularized Coulomb/Stribeck friction in the plane; F on i, the reaction on j.
// Stored energy k delta^(n+1)/(n+1); dissipated: the damping part's power and the friction power.
// The gap is reported to the integrators as a contact event (onset and release are step boundaries).
#include <algorithm>

#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"
#include "solve/elements/contact_law.hpp"

namespace nvh::solve {
namespace {

class Contact final : public ForceElement {
 public:
  explicit Contact(contact::Parameters p) : law_(p) {}
  std::string type() const override { return "contact"; }
  int marker_count() const override { return 2; }
  contact::State state(const ElementInput& in) const { return law_.state(in.markers[0], in.markers[1]); }

  void evaluate(const ElementInput& in, ElementOutput& out) const override {
    const contact::State s = state(in);
    if (s.delta <= 0) return;
    apply_at_i(in, out, law_.force(s), Vec3::Zero(), in.markers[0].position);
  }

  // dF by the law (contact_law.cpp: columns i then j, as here); the reaction on j by jacobian_at_i.
  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override {
    contact::PointJacobian df;
    if (!law_.jacobian(in.markers[0], in.markers[1], df)) return true;  // no force around here
    ElementRows dforce = zero_rows(jac);
    dforce.leftCols<24>() = df;
    jacobian_at_i(in, jac, dforce, zero_rows(jac), law_.force(state(in)));
    return true;
  }

  std::vector<Channel> channels() const override {
    return {{"gap", "m"}, {"normal_force", "N"}, {"slip_speed", "m/s"}};
  }
  void channel_values(const ElementInput& in, std::span<double> out) const override {
    const auto v = law_.channel_values(state(in));
    std::copy(v.begin(), v.end(), out.begin());
  }
  ElementEnergy energy(const ElementInput& in) const override { return law_.energy(state(in)); }
  int gap_count() const override { return 1; }
  void gaps(const ElementInput& in, std::span<double> out) const override { out[0] = -state(in).delta; }

 private:
  contact::Law law_;
};

}  // namespace

void register_contact(ElementRegistry& r) {
  r.add({"force", "contact",
         std::string("unilateral point-plane contact with clearance, Hunt-Crossley damping, Coulomb/Stribeck "
                     "friction: ") + contact::kKeys,
         {"i", "j"}, [](ElementContext& c) -> std::unique_ptr<ForceElement> {
           return std::make_unique<Contact>(contact::read_parameters(c.table));
         }});
}

}  // namespace nvh::solve
