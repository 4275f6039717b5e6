#include "postproc/analyses/history.hpp"

#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "postproc/analysis.hpp"
#include "postproc/cli_options.hpp"
#include "postproc/csv.hpp"
#include "postproc/output.hpp"
#include "postproc/signal_input.hpp"
#include "postproc/windowing.hpp"

namespace nvh::postproc {

void run_history(const HistoryCommand& command, const Logger& log, int argc, const char* const* argv) {
  const CommonOptions& common = command.common;
  std::vector<SignalSource> sources = open_signals(common);
  check_outputs(common, sources, nullptr, "history_");
  for (SignalSource& s : sources) apply_window(s, common.window, nullptr, 0.0, common.block, log);
  std::future<Provenance> provenance = start_provenance(sources, argc, argv);
  Output out = create_output(common, provenance, "history");
  std::vector<TextOutput> csvs;
  for (const SignalSource& s : sources) {
    const SignalInfo& info = s.info();
    const std::vector<double> x = s.read_all();
    const auto n = static_cast<Eigen::Index>(x.size());
    const Eigen::VectorXd value = Eigen::Map<const Eigen::VectorXd>(x.data(), n);
    Eigen::VectorXd time(n);
    for (Eigen::Index i = 0; i < n; ++i)
      time[i] = info.start_time_s + static_cast<double>(i) / info.sample_rate_hz;
    const Eigen::VectorXd angle = shaft_angle_at_samples(s, common.window);

    h5::Group g = out.root.create_group("history/" + info.name);
    describe_signal(g, info, common.window);
    g.write("time_s", time);
    g.set_attribute("units", "s", "time_s");
    g.write("value", value);
    g.set_attribute("units", info.unit.empty() ? std::string("1") : info.unit, "value");
    g.set_attribute("quantity", quantity_for(common, info));
    std::vector<std::string> header = {"time_s"};
    std::vector<const Eigen::VectorXd*> columns = {&time};
    Eigen::VectorXd cycle_angle;
    if (angle.size() == n) {
      g.write("crank_angle_deg", angle);
      g.set_attribute("units", "deg", "crank_angle_deg");
      g.set_attribute("description", "the shaft angle, unwrapped", "crank_angle_deg");
      header.push_back("crank_angle_deg");
      columns.push_back(&angle);
      if (common.window.angle_period_deg && n > 0) {
        // The angle within the period: theta - k P, k that of the window's occurrence (its first sample).
        const double p = *common.window.angle_period_deg;
        const double k = std::floor((angle[0] - *common.window.angle_from_deg) / p + 0.5);
        cycle_angle = angle.array() - k * p;
        g.write("cycle_angle_deg", cycle_angle);
        g.set_attribute("units", "deg", "cycle_angle_deg");
        g.set_attribute("description", "the shaft angle within the period of --angle-period (theta - k P)",
                        "cycle_angle_deg");
        header.push_back("cycle_angle_deg");
        columns.push_back(&cycle_angle);
      }
    }
    header.push_back("value_" + (info.unit.empty() ? std::string("1") : info.unit));
    columns.push_back(&value);
    std::ostringstream msg;
    msg.precision(6);
    msg << info.name << ": " << n << " samples, " << info.start_time_s << " to " << window_end_s(info)
        << " s";
    if (angle.size() == n && n > 0) msg << ", " << angle[0] << " to " << angle[n - 1] << " deg";
    log.info(msg.str());
    if (common.csv_dir) write_csv(csvs, *common.csv_dir / ("history_" + info.name + ".csv"), header, columns);
  }
  commit_outputs(out, csvs);
}

namespace {

class HistoryAnalysis final : public Analysis {
 public:
  void add_options(CLI::App& h, CliShared& shared) override { add_common(h, command_.common, shared); }
  void run(const Logger& log, int argc, const char* const* argv) override {
    run_history(command_, log, argc, argv);
  }
  std::filesystem::path output() const override { return command_.common.output; }

 private:
  HistoryCommand command_;
};

}  // namespace

std::unique_ptr<Analysis> make_history_analysis() {
  return std::make_unique<HistoryAnalysis>();
}

}  // namespace nvh::postproc
