#include "postproc/impacts.hpp"

#include <string>

#include "common/error.hpp"

namespace nvh::postproc {

std::vector<Impact> find_impacts(std::span<const double> force, const ImpactOptions& options) {
  if (!(options.threshold > 0))
    throw Error("impacts: the threshold must be a force > 0, got " + std::to_string(options.threshold));
  if (options.direction != 1 && options.direction != -1)
    throw Error("impacts: the direction must be +1 or -1, got " + std::to_string(options.direction));
  const double s = options.direction, th = options.threshold;
  const auto n = static_cast<Eigen::Index>(force.size());
  std::vector<Impact> impacts;
  for (Eigen::Index i = 1; i < n; ++i) {
    const double before = s * force[i - 1], now = s * force[i];
    if (!(before < th && now >= th)) continue;  // (NaN samples never open or close a contact)
    Impact impact;
    impact.sample = i;
    impact.fraction = now > before ? (th - before) / (now - before) : 1.0;
    impact.peak_force = now, impact.peak_sample = i;
    Eigen::Index k = i + 1;
    for (; k < n && s * force[k] >= th; ++k)
      if (s * force[k] > impact.peak_force) impact.peak_force = s * force[k], impact.peak_sample = k;
    if (k < n) {  // opens between k - 1 (closed) and k
      const double a = s * force[k - 1], b = s * force[k];
      impact.release_sample = static_cast<double>(k - 1) + (a > b ? (a - th) / (a - b) : 1.0);
    }
    impacts.push_back(impact);
    i = k;  // the next impact closes after this release
  }
  return impacts;
}

double at_impact(const Impact& impact, std::span<const double> x) {
  const auto i = static_cast<std::size_t>(impact.sample);
  return x[i - 1] + impact.fraction * (x[i] - x[i - 1]);
}

}  // namespace nvh::postproc
