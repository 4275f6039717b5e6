#include "solve/advise.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <numbers>
#include <sstream>

#include "common/error.hpp"
#include "solve/flexible_body.hpp"
#include "solve/flexible_rotor_body.hpp"
#include "solve/split_integrator.hpp"
#include "solve/stability.hpp"

namespace nvh::solve {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;
constexpr double kGrowthPerPeriod = 1.01;  // a mode growing by more than 1 % per period is worth a warning

std::string num(double v, int digits = 4) {
  std::ostringstream s;
  s << std::setprecision(digits) << v;
  return s.str();
}

/// Growth per period (amplitude factor) of BDF-k on a mode at step h.
double bdf_growth_per_period(int k, double omega, double zeta, double h) {
  return std::pow(bdf_growth(k, mode_z(omega, zeta, h)), kTwoPi / (omega * h));
}

/// The lowest BDF order in 3..max_order that grows the mode by more than 1 % per period at step h (0: none),
/// with its growth per period.
std::pair<int, double> bdf_trouble(const LinearMode& m, int max_order, double h) {
  for (int k = 3; k <= max_order; ++k) {
    if (m.damping_ratio < 0 || m.damping_ratio >= bdf_critical_damping(k)) continue;
    const double g = bdf_growth_per_period(k, m.omega, m.damping_ratio, h);
    if (g > kGrowthPerPeriod) return {k, g};
  }
  return {0, 1.0};
}

std::string who(const LinearMode& m) {
  std::string s;
  const auto list = [](const std::vector<std::pair<std::string, double>>& v) {
    std::string out;
    for (std::size_t i = 0; i < v.size() && i < 2; ++i)
      out += (i ? ", " : "") + v[i].first + " " + num(100 * v[i].second, 3) + " %";
    return out.empty() ? std::string("-") : out;
  };
  return "kinetic: " + list(m.kinetic) + "; elastic: " + list(m.elastic);
}

std::string mode_name(const LinearMode& m) {
  return num(m.frequency_hz(), 6) + " Hz (zeta " + num(m.damping_ratio, 3) + ", " +
         (m.elastic.empty() ? (m.kinetic.empty() ? std::string("?") : m.kinetic[0].first)
                            : m.elastic[0].first) +
         ")";
}

/// The split (docs/theory/split-integrator.md): the stiffest mode of the linearised start whose kinetic
/// energy two groups share (at least 1 % each) is the coupling the exchange carries. Without the coupling
/// correction the exchange is stable for omega_c H below about 1 (verification.md, the split's stability
/// map); with it, tested to omega_c H = 14. A fixed H can crawl where contacts close inside a macro step
/// (S7).
void advise_split(const Model& model, const IntegratorSettings& s, Advice& a) {
  const SplitPartition p = partition_model(model, s.split_groups);
  if (p.groups < 2) {
    a.notes.push_back(
        "split: the scene is one group (its bodies joined by joints): the split is IDA restarted at "
        "every macro step, at more cost (verification.md); method = \"ida\"");
    return;
  }
  std::map<std::string, int> group_of_body;
  for (int g = 0; g < p.groups; ++g)
    for (const std::string& body : p.bodies[g]) group_of_body[body] = g;
  const LinearMode* coupling = nullptr;
  for (const LinearMode& m : a.linear.modes) {  // ascending: the last one found is the stiffest
    std::vector<double> share(p.groups, 0.0);
    for (const auto& [body, e] : m.kinetic)
      if (const auto it = group_of_body.find(body); it != group_of_body.end()) share[it->second] += e;
    if (std::count_if(share.begin(), share.end(), [](double x) { return x >= 0.01; }) >= 2) coupling = &m;
  }
  if (!coupling) {
    a.notes.push_back("split: " + std::to_string(p.groups) +
                      " groups; no mode of the linearised start moves two of them");
  } else {
    const double wh = coupling->omega * s.macro_step;
    const std::string what = "the stiffest mode between the " + std::to_string(p.groups) + " groups, " +
                             mode_name(*coupling) + ", at macro_step " + num(s.macro_step) +
                             " s: omega_c H = " + num(wh);
    if (!s.coupling_correction && wh > 1)
      a.warnings.push_back("split without the coupling correction: " + what +
                           " > 1, where the exchange diverges (the split's stability map, verification.md); "
                           "coupling_correction = true, or macro_step <= " +
                           num(1 / coupling->omega) + " s");
    else
      a.notes.push_back(
          "split: " + what +
          (s.coupling_correction
               ? (wh > 14 ? " (the coupling correction: stable where tested, to omega_c H = 14; "
                            "this is beyond)"
                          : " (the coupling correction: stable, tested to omega_c H = 14)")
               : " (< 1 without the correction: stable)"));
  }
  if (model.gap_count() > 0 && s.macro_tolerance <= 0)
    a.notes.push_back(
        "split with a fixed macro step and " + std::to_string(model.gap_count()) +
        " contact gap(s): where a contact between groups closes inside a macro step the "
        "exchange's linearisation misses it, and the groups can crawl (the slap on the flexible "
        "block at H = 0.2 ms); macro_tolerance = 1e4 shortens H there only (scene-format.md 7.1)");
}

}  // namespace

Advice advise(Scene& scene, const AdviceOptions& options, const Logger& log) {
  if (!(options.steps_per_period > 0) || !(options.cutoff_factor > 0))
    throw Error("advise: steps per period and the cut-off factor must be positive");
  Advice a;
  a.warnings = scene.warnings;  // the reader's (a statically corrected superelement truncated)
  const double nyquist = scene.output.sample_rate_hz / 2;
  if (options.band_hz > 0) {
    a.band_hz = options.band_hz;
    a.band_source = "--band";
    if (a.band_hz > nyquist)
      a.warnings.push_back("the band (" + num(a.band_hz) +
                           " Hz) lies above the output's Nyquist frequency (" + num(nyquist) +
                           " Hz): the samples cannot show it; sample_rate_hz >= " + num(2.56 * a.band_hz) +
                           " (2.56 x the band, as FFT analysers do)");
  } else {
    a.band_hz = nyquist;
    a.band_source = "output.sample_rate_hz / 2";
  }
  const double omega_b = kTwoPi * a.band_hz;
  a.step = 1 / (options.steps_per_period * a.band_hz);
  a.rtol = std::min(scene.integrator.rtol, 1e-6);  // the documented default, or the scene's if tighter

  Model& model = scene.model;
  Eigen::VectorXd y, yp;
  model.consistent_initial_state(scene.start_time, y, yp, log);
  a.linear = linearize(model, scene.start_time, y, yp);
  for (const LinearMode& m : a.linear.modes)
    if (m.frequency_hz() <= a.band_hz) ++a.modes_in_band;

  // Method.
  const IntegratorSettings& s = scene.integrator;
  if (model.gap_count() > 0) {
    a.method = "generalized-alpha";
    a.method_reason =
        std::to_string(model.gap_count()) +
        " contact gap(s): generalized-alpha is stable at any step on damped modes and was faster "
        "at equal error on stiff contacts (piston slap: 0.8 % in 0.5 s, IDA 5 % in 21 s); "
        "rho_inf 0.8 damps the unresolved contact modes (5 % per step at omega h = 10)";
  } else {
    a.method = "ida";
    a.method_reason =
        "no contacts: IDA's error control was the fastest on smooth models (flexible slider-crank: 1e-8 in "
        "0.8 s); max_step holds the band's resolution";
    // max_order: the highest that grows no mode by more than 1 % per period at the recommended step.
    for (const LinearMode& m : a.linear.modes) {
      const auto [k, g] = bdf_trouble(m, a.max_order, a.step);
      if (k > 0) {
        a.max_order = std::max(2, k - 1);
        a.notes.push_back("max_order = " + std::to_string(a.max_order) + " recommended: at max_step " +
                          num(a.step) + " s the mode " + mode_name(m) + " grows x" + num(g) +
                          " per period under BDF" + std::to_string(k) +
                          " (omega h = " + num(m.omega * a.step) + ")");
      }
    }
  }
  if (a.max_order < 5 && a.method == "ida")
    a.method_reason += "; max_order lowered so that no mode lies in an unstable BDF band at that step";

  // The scene's own choice against the measured stable region. The split's groups each run IDA with the
  // scene's max_step and max_order.
  const bool ida = s.method == "ida" || s.method == "split";
  if (s.method == "split") advise_split(model, s, a);
  const double scene_step = ida ? s.max_step : s.step;
  if (scene_step > a.step)
    a.warnings.push_back(
        std::string(ida ? "max_step" : "step") + " = " + num(scene_step) +
        " s is above the band's resolution (" + num(a.step) + " s: " + num(options.steps_per_period) +
        " steps per period of " + num(a.band_hz) + " Hz); omega h = " + num(omega_b * scene_step) +
        " at the band's top" +
        (ida ? ""
             : ", where generalized-alpha damps x" +
                   num(std::pow(generalized_alpha_growth(s.rho_inf, mode_z(omega_b, 0, scene_step)),
                                1 / (a.band_hz * scene_step))) +
                   " per period"));
  if (ida && scene_step <= 0)
    a.notes.push_back(
        "no max_step: IDA's error test alone sets the step; where slower motion sets it, the "
        "band's top can be stepped over (max_step = " +
        num(a.step) + " s holds it)");
  if (ida && s.max_order >= 3) {
    int lightly = 0;
    for (const LinearMode& m : a.linear.modes) {
      if (m.damping_ratio >= 0 && m.damping_ratio < bdf_critical_damping(std::min(s.max_order, 5))) ++lightly;
      if (scene_step <= 0) continue;
      const auto [k, g] = bdf_trouble(m, s.max_order, scene_step);
      if (k == 0) continue;
      const auto band = bdf_unstable_band(k, m.damping_ratio);
      a.warnings.push_back("max_order = " + std::to_string(s.max_order) + ", max_step = " + num(scene_step) +
                           " s: the mode " + mode_name(m) + " at omega h = " + num(m.omega * scene_step) +
                           " lies in BDF" + std::to_string(k) + "'s unstable band (omega h " +
                           (band ? num(band->first, 3) + " .. " + num(band->second, 3) : std::string("?")) +
                           " at this damping): a step held there grows it x" + num(g) +
                           " per period; max_order = 2, generalized-alpha or more damping (zeta > " +
                           num(bdf_critical_damping(k), 3) + ") avoid it");
    }
    if (lightly > 0)
      a.notes.push_back(std::to_string(lightly) + " mode(s) damped below cos(alpha) of BDF" +
                        std::to_string(std::min(s.max_order, 5)) + " (" +
                        num(bdf_critical_damping(std::min(s.max_order, 5)), 3) +
                        "): steps in their unstable omega h bands make them grow; IDA's error test then "
                        "pays in rejected steps (/solver/statistics rejected_steps)");
  }
  if (!ida && s.rho_inf >= 1 && scene.output.joints && !model.constraints.empty())
    a.warnings.push_back(
        "generalized-alpha with rho_inf = 1 and joint reactions written: no numerical damping "
        "reaches the multipliers, the reactions oscillate and grow (scene-format.md section 2); "
        "rho_inf = 0.8");
  if (!ida && !a.linear.modes.empty()) {
    const LinearMode& top = a.linear.modes.back();
    const double rho = generalized_alpha_growth(s.rho_inf, mode_z(top.omega, top.damping_ratio, s.step));
    a.notes.push_back("generalized-alpha at step " + num(s.step) + " s: the stiffest mode " + mode_name(top) +
                      " (omega h = " + num(top.omega * s.step) + ") keeps x" + num(rho) +
                      " of its amplitude per step" +
                      (s.rho_inf >= 1 && top.omega * s.step > 1 ? ": unresolved, it rings on" : ""));
  }
  std::string growing;
  for (const LinearMode& m : a.linear.modes)
    if (m.damping_ratio < 0) growing += (growing.empty() ? "" : "; ") + mode_name(m) + " " + who(m);
  for (double r : a.linear.growth_rates)
    growing += (growing.empty() ? "" : "; ") + ("real " + num(r) + " 1/s");
  if (!growing.empty())
    a.warnings.push_back(
        "modes of the linearised start that grow (negative damping, real positive eigenvalues): " + growing +
        ". A physical instability (oil whirl, buckling, a negative slope of a motor curve) or a "
        "start away from equilibrium; no step choice makes them decay");

  // Flexible bodies.
  for (const auto& body : model.bodies) {
    const FlexibleBody* flex = flexible_part(*body);
    if (!flex) continue;
    FlexibleAdvice f;
    f.body = flex->name();
    f.cutoff_hz = options.cutoff_factor * a.band_hz;
    const Eigen::VectorXd& used = flex->data().frequency_hz;
    const Eigen::VectorXd all = load_flexible_data(flex->data().file, 0).frequency_hz;
    f.modes_used = static_cast<int>(used.size());
    f.mode_numbers = flex->data().mode_numbers;
    f.modes_in_file = static_cast<int>(all.size());
    f.highest_used_hz = used.size() ? used.maxCoeff() : 0;
    f.highest_in_file_hz = all.size() ? all.maxCoeff() : 0;
    f.modes_needed = std::max(1, static_cast<int>((all.array() <= f.cutoff_hz).count()));
    // A basis with static correction (residual modes or vectors above the band) needs all its coordinates.
    if (flex->data().static_correction > 0) f.modes_needed = f.modes_in_file;
    const std::string file = flex->data().file.filename().string();
    if (f.highest_in_file_hz < f.cutoff_hz)
      a.warnings.push_back("flexible body '" + f.body + "': " + file + " holds modes to " +
                           num(f.highest_in_file_hz) + " Hz only, below the cut-off " + num(f.cutoff_hz) +
                           " Hz (" + num(options.cutoff_factor) +
                           " x the band): condense it again with --fmax " + num(f.cutoff_hz) +
                           " (or --band " + num(a.band_hz) + ")");
    else if (const std::vector<int>& chosen = flex->data().mode_numbers; !chosen.empty()) {
      // Chosen by number: name the modes below the cut-off that the choice leaves out (a planar mechanism's
      // out-of-plane modes may rightly be among them; the advice cannot tell what the scene excites).
      std::string left_out;
      for (int j = 0; j < f.modes_needed; ++j)
        if (std::find(chosen.begin(), chosen.end(), j + 1) == chosen.end())
          left_out += (left_out.empty() ? "" : ", ") + std::to_string(j + 1);
      if (!left_out.empty())
        a.warnings.push_back("flexible body '" + f.body + "' takes mode_numbers of " + file + ", which leaves out " +
                             "its modes " + left_out + " below the cut-off " + num(f.cutoff_hz) +
                             " Hz: right only where the scene does not excite them (a planar mechanism's "
                             "out-of-plane modes); compare a run with them");
    } else if (f.modes_used < f.modes_needed)
      a.warnings.push_back("flexible body '" + f.body + "' uses " + std::to_string(f.modes_used) +
                           " modes (to " + num(f.highest_used_hz) + " Hz), fewer than the " +
                           std::to_string(f.modes_needed) + " of " + file + " up to the cut-off " +
                           num(f.cutoff_hz) + " Hz: modes = " + std::to_string(f.modes_needed));
    else if (f.modes_used > f.modes_needed && f.highest_used_hz > 1.5 * f.cutoff_hz)
      a.notes.push_back(
          "flexible body '" + f.body + "' uses " + std::to_string(f.modes_used) + " modes (to " +
          num(f.highest_used_hz) + " Hz); " + std::to_string(f.modes_needed) + " reach the cut-off " +
          num(f.cutoff_hz) + " Hz: modes = " + std::to_string(f.modes_needed) +
          " would remove stiff modes the band does not need (a Craig-Bampton file's higher "
          "coordinates also carry its interfaces' static shapes: compare a run before dropping them)");
    a.flexible.push_back(f);
  }
  return a;
}

std::string format_advice(const Advice& a, const Scene& scene) {
  std::ostringstream out;
  const IntegratorSettings& s = scene.integrator;
  out << "advice for scene \"" << scene.name << "\"\n";
  out << "band: 0 .. " << num(a.band_hz, 6) << " Hz (from " << a.band_source << ")\n";
  out << "scene's integrator: method " << s.method;
  if (s.method == "split")
    out << ", macro_step " << num(s.macro_step) << " s"
        << (s.macro_tolerance > 0 ? " (the largest; macro_tolerance " + num(s.macro_tolerance) + ")"
                                  : std::string(" (fixed)"))
        << ", exchange " << s.exchange << ", coupling_correction "
        << (s.coupling_correction ? "true" : "false") << "; each group's IDA";
  if (s.method == "ida" || s.method == "split")
    out << ", rtol " << num(s.rtol) << ", atol " << num(s.atol) << ", max_step "
        << (s.max_step > 0 ? num(s.max_step) + " s" : std::string("none")) << ", max_order " << s.max_order;
  else
    out << ", step " << num(s.step) << " s, rho_inf " << num(s.rho_inf) << (s.adaptive ? ", adaptive" : "");
  out << "\n\nmodel linearised at t = " << num(scene.start_time) << " s: " << a.linear.size
      << " first-order unknowns on the constraint manifold; " << a.linear.modes.size()
      << " oscillatory mode(s), " << a.modes_in_band << " in the band";
  if (!a.linear.relaxation_rates.empty())
    out << "; " << a.linear.relaxation_rates.size() << " relaxation rate(s), the fastest "
        << num(a.linear.relaxation_rates.back()) << " 1/s";
  out << "\n";
  if (!a.linear.modes.empty()) {
    out << "stiffest modes (undamped natural frequency, damping ratio, energy shares):\n";
    const std::size_t n = a.linear.modes.size(), shown = std::min<std::size_t>(n, 6);
    for (std::size_t i = n; i-- > n - shown;) {
      const LinearMode& m = a.linear.modes[i];
      out << "  " << std::setw(12) << num(m.frequency_hz(), 6) << " Hz  zeta " << std::setw(9)
          << num(m.damping_ratio, 3) << "  " << who(m) << "\n";
    }
    if (n > shown)
      out << "  ... " << n - shown << " more down to " << num(a.linear.modes.front().frequency_hz())
          << " Hz\n";
  }
  if (!a.flexible.empty()) {
    out << "flexible bodies (modes up to " << num(a.flexible.front().cutoff_hz / a.band_hz)
        << " x the band = " << num(a.flexible.front().cutoff_hz, 6) << " Hz):\n";
    for (const FlexibleAdvice& f : a.flexible) {
      out << "  " << f.body << ": uses " << f.modes_used << " of the file's " << f.modes_in_file;
      if (!f.mode_numbers.empty()) {
        out << " modes (mode_numbers";
        for (std::size_t k = 0; k < f.mode_numbers.size(); ++k) out << (k ? ", " : " ") << f.mode_numbers[k];
        out << ";";
      } else {
        out << " modes (";
      }
      out << " to " << num(f.highest_used_hz, 6) << " Hz; the file to " << num(f.highest_in_file_hz, 6)
          << " Hz); recommended modes = " << f.modes_needed
          << (f.mode_numbers.empty() ? "" : " by frequency, or the modes of them the scene excites") << "\n";
    }
  }
  out << "\nrecommended (rules: docs/cli.md 'solve --advise'; measured: docs/verification.md 'Stability "
         "map'):\n";
  out << "  [integrator]\n  method = \"" << a.method << "\"\n";
  if (a.method == "ida")
    out << "  max_step = " << num(a.step) << "\n  rtol = " << num(a.rtol) << "\n  max_order = " << a.max_order
        << "\n";
  else
    out << "  step = " << num(a.step) << "\n  rho_inf = " << num(a.rho_inf) << "\n";
  out << "  # " << num(1 / (a.step * a.band_hz)) << " steps per period of " << num(a.band_hz, 6) << " Hz; "
      << a.method_reason << "\n";
  out << "\nwarnings: " << (a.warnings.empty() ? "none" : "") << "\n";
  for (const std::string& w : a.warnings) out << "  - " << w << "\n";
  if (!a.notes.empty()) out << "notes:\n";
  for (const std::string& w : a.notes) out << "  - " << w << "\n";
  return out.str();
}

}  // namespace nvh::solve
