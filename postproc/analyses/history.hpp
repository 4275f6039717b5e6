#pragma once
// postproc history: the samples of a signal inside its analysis window (a time or shaft-angle window, e.g.
// -30..+90 deg about a cylinder's firing TDC) with their time and shaft angle, as HDF5, CSV and PNG
// (docs/postproc.md sections 2.1, 5).
#include "common/log.hpp"
#include "postproc/options.hpp"

namespace nvh::postproc {

struct HistoryCommand {
  CommonOptions common;
};

/// Writes every signal's windowed samples to `common.output`; an error leaves no output.
void run_history(const HistoryCommand& command, const Logger& log, int argc, const char* const* argv);

}  // namespace nvh::postproc
