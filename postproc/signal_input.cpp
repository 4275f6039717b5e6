#include "postproc/signal_input.hpp"

#include <algorithm>
#include <memory>
#include <set>

#include "common/error.hpp"
#include "common/progress.hpp"

namespace nvh::postproc {

/// Read a signal block by block (with a progress bar on long signals) and hand each block on.
void for_each_block(const SignalSource& source, std::int64_t block, const Logger& log,
                    const std::string& label,
                    const std::function<void(std::int64_t, std::span<const double>)>& consume) {
  const std::int64_t n = source.size();
  std::unique_ptr<Progress> progress;
  if (n > 4 * block) progress = std::make_unique<Progress>(log, label, n);
  std::vector<double> buffer;
  for (std::int64_t offset = 0; offset < n; offset += block) {
    const std::int64_t count = std::min(block, n - offset);
    buffer.resize(static_cast<std::size_t>(count));
    source.read(offset, buffer);
    consume(offset, buffer);
    if (progress) progress->update(offset + count);
  }
  if (progress) progress->finish();
}

std::vector<SignalSource> open_signals(const CommonOptions& common) {
  if (common.signals.empty())
    throw Error("no signal given; expected FILE.h5:/dataset, FILE.csv:column or FILE.uff");
  std::vector<SignalSource> sources;
  std::set<std::string> names;
  for (const std::string& address : common.signals) {
    sources.push_back(SignalSource::open(address));
    const std::string& name = sources.back().info().name;
    if (!names.insert(name).second)
      throw Error("two signals are named '" + name + "' in the output; name them with NAME=ADDRESS");
  }
  return sources;
}

std::string quantity_for(const CommonOptions& common, const SignalInfo& info, int derivative) {
  std::string q = common.quantity.empty() ? quantity_of_unit(info.unit) : common.quantity;
  if (derivative == 0) return q;
  const std::vector<std::string> chain = {"displacement", "velocity", "acceleration"};
  const auto at = std::find(chain.begin(), chain.end(), q);
  if (at == chain.end()) return "";
  const long j = (at - chain.begin()) + derivative;
  return j >= 0 && j < 3 ? chain[static_cast<std::size_t>(j)] : "";
}

}  // namespace nvh::postproc
