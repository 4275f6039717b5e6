#pragma once
// The keys a follower's contact on a cam reads alike (roller-cam, flat-face-cam): the contact length, the
// materials (Young's modulus and Poisson's ratio of the follower and of the cam, steel by default) giving
// E* (hertz_line.hpp), an optional linear `stiffness` instead of Palmgren's law, and the Hunt-Crossley
// `restitution` at `reference_speed`. SI units.
#include <string>

#include "common/input.hpp"
#include "solve/element_registry.hpp"
#include "solve/elements/hertz_line.hpp"

namespace nvh::solve {

/// Reads the keys into p.width (key `width_key`), p.e_star (`<follower>_modulus`, `<follower>_poisson`,
/// `cam_modulus`, `cam_poisson`), p.stiffness, p.restitution and p.reference_speed; errors located at the
/// key.
template <class Parameters>
void read_cam_contact(const input::Table& t, const std::string& width_key, const std::string& follower,
                      Parameters& p) {
  using input::Range;
  p.width = t.number(width_key, Range{0.0, bounds::kLength, true, false});
  const Range modulus = Range{0.0, 1e15, true, false};
  const Range poisson = Range::closed(0.0, 0.5);
  const double ef = t.number_or(follower + "_modulus", hertz::kSteelModulus, modulus);
  const double nf = t.number_or(follower + "_poisson", hertz::kSteelPoisson, poisson);
  const double ec = t.number_or("cam_modulus", hertz::kSteelModulus, modulus);
  const double nc = t.number_or("cam_poisson", hertz::kSteelPoisson, poisson);
  p.e_star = hertz::contact_modulus(ef, nf, ec, nc);
  p.stiffness = t.number_or("stiffness", 0.0, Range::closed(0.0, bounds::kCoefficient));
  p.restitution = t.number_or("restitution", 1.0, Range::open(0.0, 1.0 + 1e-12));
  p.reference_speed = t.number_or("reference_speed", 1.0, Range::closed(1e-9, bounds::kSpeed));
}

}  // namespace nvh::solve
