#pragma once
// Impacts: the onsets of contact in a sampled contact force, and the state of the impacting body there - the
// piston's slap on the liner, a valve landing on its seat, a roller landing on its cam after separating.
//
// Definition (docs/postproc.md section 4.6; the slap's of docs/bearing.md section 16.3): with g = s F the
// force F seen in the contact's direction s (+1: F positive in contact, a contact's normal force; -1: F
// negative in contact, e.g. the thrust side of a piston's side force) and a threshold F_th > 0,
//   - the contact is closed at a sample where g >= F_th, open where g < F_th;
//   - an impact is a sample i where it closes after being open at i - 1; its instant is the threshold's
//     crossing interpolated linearly between the two samples,
//       t* = t_{i-1} + w dt,   w = (F_th - g_{i-1}) / (g_i - g_{i-1}),
//     and any other signal x sampled alike is taken there as x* = x_{i-1} + w (x_i - x_{i-1});
//   - the release is the first later sample where it opens, interpolated alike (none if the contact is still
//     closed at the last sample); the peak force is the largest g from the impact to the release.
// A contact closed at the first sample has no impact in the record (its onset is not in it). For samples
// that are linear in time between the two around a crossing, every value is exact.
#include <Eigen/Core>
#include <span>
#include <vector>

namespace nvh::postproc {

struct ImpactOptions {
  double threshold = 10;  ///< F_th, in the force's unit (> 0)
  int direction = 1;      ///< s: +1 or -1
};

struct Impact {
  Eigen::Index sample = 0;       ///< i: the first sample of the closed contact
  double fraction = 0;           ///< w in [0, 1]: the crossing between samples i - 1 and i
  double release_sample = -1;    ///< fractional sample index of the release; -1: not released in the record
  double peak_force = 0;         ///< the largest g = s F over the contact (>= F_th)
  Eigen::Index peak_sample = 0;  ///< where it is
};

/// The impacts of a sampled force, in order (an empty list if none). Throws nvh::Error for a threshold <= 0
/// or a direction other than +1 or -1.
std::vector<Impact> find_impacts(std::span<const double> force, const ImpactOptions& options);

/// Another signal x, sampled as the force, at the impact's instant (linear interpolation, as above).
double at_impact(const Impact& impact, std::span<const double> x);

}  // namespace nvh::postproc
