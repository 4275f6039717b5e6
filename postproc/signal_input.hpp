#pragma once
// Opening the signals of an analysis and reading them block by block (docs/postproc.md section 2).
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "common/log.hpp"
#include "postproc/options.hpp"
#include "postproc/signal.hpp"

namespace nvh::postproc {

/// Read a signal block by block (with a progress bar on long signals) and hand each block on.
void for_each_block(const SignalSource& source, std::int64_t block, const Logger& log,
                    const std::string& label,
                    const std::function<void(std::int64_t, std::span<const double>)>& consume);

/// Open every signal of `common.signals`; error if none is given or two get the same name.
std::vector<SignalSource> open_signals(const CommonOptions& common);

/// The quantity of a signal (--quantity, else from its unit), `derivative` time derivatives on ("" if
/// unknown).
std::string quantity_for(const CommonOptions& common, const SignalInfo& info, int derivative = 0);

}  // namespace nvh::postproc
