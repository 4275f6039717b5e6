#pragma once
// `solve --advise`: from the band a scene's results must cover and the modes of its model linearised at the
// start (linearize.hpp), recommend the integration method, step and tolerance and the flexible bodies' mode
// counts, and warn where the scene's own settings lie outside the stable or accurate region that
// bench/stability_map.py measured (docs/verification.md, "Stability map"; theory in stability.hpp).
//
// Rules (docs/cli.md, "solve --advise", says the same to users):
//   band       f_b = --band, else the Nyquist frequency of [output] sample_rate_hz (f_s / 2).
//   step       h_b = 1 / (steps_per_period f_b), 20 steps per period of the band's top (omega_b h = 0.31).
//              The map: IDA orders 3-5 keep 1 % over 20 periods at omega h <= 0.1 (63 steps per period),
//              generalized-alpha at 0.02-0.1; 20 steps per period is the usual resolution of a spectrum's top
//              line, and the report gives the numerical damping per period there for the scene's own step.
//   method     contact elements (gaps): generalized-alpha, rho_inf 0.8, step h_b - measured faster at equal
//              error on stiff contacts (piston slap: 0.8 % in 0.5 s against IDA's 5 % in 21 s) and stable at
//              any step on damped modes; otherwise IDA (BDF, error-controlled: the smooth flexible
//              slider-crank reached 1e-8 in 0.8 s), max_step h_b, rtol 1e-6 (or the scene's if tighter).
//   BDF        IDA's orders 3..max_order grow a mode of damping ratio below cos(alpha_k) (0.0698, 0.287,
//              0.618) for a band of omega h: a warning when the scene's max_step puts a mode inside it (a
//              step held there - by max_step, or by a tolerance that slower motion sets - makes it grow), a
//              note otherwise (IDA's error test pays for it in rejected steps); remedies max_order = 2
//              (A-stable) or generalized-alpha.
//   modes      each flexible body: the file's elastic modes up to cutoff_factor f_b (2 by default: a mode at
//              2 f_b responds at f_b with the dynamic amplification 1 / (1 - 1/4) = 1.33 of its static
//              response: a static correction within a third, which Craig-Bampton's static shapes carry); a
//              warning when the file holds none above the cut-off, a note when the body uses modes far above
//              it.
//   reactions  generalized-alpha with rho_inf = 1 and joint reactions written: the multipliers drift
//              (scene-format.md section 2).
#include <string>
#include <vector>

#include "common/log.hpp"
#include "solve/linearize.hpp"
#include "solve/scene.hpp"

namespace nvh::solve {

struct AdviceOptions {
  double band_hz = 0;            // > 0: the band's top (Hz); 0: the Nyquist frequency of the output rate
  double steps_per_period = 20;  // of the band's top frequency
  double cutoff_factor = 2;      // flexible bodies: modes up to this x the band
};

struct FlexibleAdvice {
  std::string body;
  int modes_used = 0, modes_in_file = 0, modes_needed = 0;  // needed: the file's modes up to the cut-off
  double highest_used_hz = 0, highest_in_file_hz = 0, cutoff_hz = 0;
  std::string method;  // the superelement's reduction
  std::vector<int> mode_numbers;  // the scene's `mode_numbers` (empty: the lowest modes_used)
};

struct Advice {
  double band_hz = 0;
  std::string band_source;  // "--band" or "output.sample_rate_hz / 2"
  Linearization linear;     // the model's modes at the start
  int modes_in_band = 0;
  // Recommendation
  std::string method;  // "ida" or "generalized-alpha"
  std::string method_reason;
  double step = 0;  // s: max_step (IDA) or step (generalized-alpha)
  double rtol = 1e-6;
  double rho_inf = 0.8;
  int max_order = 5;
  std::vector<FlexibleAdvice> flexible;
  std::vector<std::string> warnings;  // the scene's settings outside the measured stable / accurate region
  std::vector<std::string> notes;
};

/// Build the advice for `scene` (its model is brought to its consistent initial state; messages to `log`).
Advice advise(Scene& scene, const AdviceOptions& options, const Logger& log);
/// The readable report (what `solve --advise` prints).
std::string format_advice(const Advice& advice, const Scene& scene);

}  // namespace nvh::solve
