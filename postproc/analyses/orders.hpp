#pragma once
// postproc orders: computed order tracking, order spectra per cycle, order cuts and Campbell diagrams
// (docs/postproc.md sections 3.3, 4.3, 5).
#include "common/log.hpp"
#include "postproc/options.hpp"
#include "postproc/orders.hpp"

namespace nvh::postproc {

struct OrdersCommand {
  CommonOptions common;
  AngleSource angle;
  OrderOptions options;
  bool cut = false;  ///< also /orders/cut: one mean order spectrum per signal against rpm
  bool campbell = false;
  double campbell_rpm_step = 50.0;
  double campbell_fmax_hz = 2000.0;
  double campbell_resolution_hz = 2.0;
};

/// Runs the analysis on every signal and writes `common.output`; an error leaves no output.
void run_orders(const OrdersCommand& command, const Logger& log, int argc, const char* const* argv);

}  // namespace nvh::postproc
