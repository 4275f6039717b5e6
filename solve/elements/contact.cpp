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

class Contact final : public contact::PointElement {
 public:
  using PointElement::PointElement;
  std::string type() const override { return "contact"; }
  std::vector<Channel> channels() const override {
    return {{"gap", "m"}, {"normal_force", "N"}, {"slip_speed", "m/s"}};
  }
  void channel_values(const ElementInput& in, std::span<double> out) const override {
    const auto v = law_.channel_values(state(in));
    std::copy(v.begin(), v.end(), out.begin());
  }
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
