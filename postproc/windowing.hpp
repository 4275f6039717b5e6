#pragma once
// Applying the analysis window to an opened signal (docs/postproc.md section 2.1): --start/--end, then
// --skip-cycles with the shaft angle; the cycles of an order analysis inside the window; and the window's
// description added to the error of an analysis the window made too short.
#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "common/error.hpp"
#include "common/log.hpp"
#include "postproc/analysis_window.hpp"
#include "postproc/options.hpp"
#include "postproc/orders.hpp"
#include "postproc/signal.hpp"

namespace nvh::postproc {

/// Restrict `signal` to the analysis window: --start/--end, then --skip-cycles with the shaft angle
/// (`angle` may be null when the subcommand has none). No-op without a window.
void apply_window(SignalSource& signal, const AnalysisWindow& window, const AngleSource* angle,
                  double cycle_deg, std::int64_t block, const Logger& log);

/// The address of --window-angle for `signal`: a dataset path (starting with '/') is looked for in the
/// signal's own file ("FILE:/path"), a full address is taken as it is.
std::string window_angle_address(const SignalInfo& signal, const AnalysisWindow& window);

/// The shaft angle (deg) at the samples of a windowed signal: the dataset --window-angle of the signal's own
/// file (or its full address), restricted like the signal; empty if there is none and no angle window asks
/// for it (an angle window without its angle dataset is an error).
Eigen::VectorXd shaft_angle_at_samples(const SignalSource& signal, const AnalysisWindow& window);

/// The cycles of `all` (tracked over the samples of `read`, a window with margins) lying wholly inside the
/// samples `window` of `read`; start times shifted to count from the file's first sample.
OrderSpectra cycles_in_window(const OrderSpectra& all, const SampleRange& window, const SignalSource& read);

/// Adds the window to an error of an analysis that the window made too short: the message names the options.
[[noreturn]] void rethrow_in_window(const Error& e, const AnalysisWindow& window, const SignalSource& s);

}  // namespace nvh::postproc
