#include "postproc/analyses/orders.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>

#include "common/error.hpp"
#include "postproc/analysis.hpp"
#include "postproc/cli_options.hpp"
#include "postproc/csv.hpp"
#include "postproc/levels.hpp"
#include "postproc/output.hpp"
#include "postproc/shaft_angle.hpp"
#include "postproc/signal_input.hpp"
#include "postproc/windowing.hpp"

namespace nvh::postproc {

void run_orders(const OrdersCommand& command, const Logger& log, int argc, const char* const* argv) {
  const CommonOptions& common = command.common;
  std::vector<SignalSource> sources = open_signals(common);
  check_outputs(common, sources, &command.angle, "orders_");
  std::vector<TextOutput> csvs;
  // The window's samples (`windows`); the tracker reads up to kTrackerMargin samples more on either side,
  // when the file has them, so that every cycle lying wholly inside the window is analysed (its kernel
  // reaches 131 samples beyond an angle sample, orders.cpp).
  constexpr std::int64_t kTrackerMargin = 256;
  std::vector<SignalInfo> windows;
  std::vector<SampleRange> in_window;  // the window inside the samples read
  for (SignalSource& s : sources) {
    apply_window(s, common.window, &command.angle, command.options.cycle_deg, common.block, log);
    windows.push_back(s.info());
    in_window.push_back({0, s.size()});
    if (common.window.active()) {
      const std::int64_t first = std::max<std::int64_t>(0, s.first_sample() - kTrackerMargin);
      const std::int64_t end = std::min(s.file_size(), s.first_sample() + s.size() + kTrackerMargin);
      in_window.back().first = s.first_sample() - first;
      s.restrict_to(first, end - first);
    }
  }
  std::future<Provenance> provenance = start_provenance(sources, argc, argv);
  std::vector<int> samples_per_cycle;
  for (const SignalSource& s : sources)
    samples_per_cycle.push_back(samples_per_cycle_from(command.angle, s, command.options, common.block, log));
  std::vector<OrderSpectra> results;
  std::vector<std::unique_ptr<CampbellAccumulator>> campbells;
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const SignalInfo& info = sources[i].info();
    AngleProvider angle(command.angle, sources[i], common.block, log);
    OrderTracker tracker(info.sample_rate_hz, command.options, samples_per_cycle[i]);
    std::unique_ptr<CampbellAccumulator> campbell;
    if (command.campbell) {
      std::int64_t n = 16;  // (an int overflowed on a tiny --campbell-resolution)
      while (n < info.sample_rate_hz / command.campbell_resolution_hz && n <= windows[i].size) n *= 2;
      if (n > windows[i].size)
        rethrow_in_window(
            Error("orders: signal '" + info.address + "' is too short for a Campbell frame of " +
                  std::to_string(n) + " samples; lower --campbell-resolution"),
            common.window, sources[i]);
      campbell = std::make_unique<CampbellAccumulator>(
          info.sample_rate_hz, static_cast<int>(n),
          std::min(command.campbell_fmax_hz, info.sample_rate_hz / 2), command.campbell_rpm_step);
    }
    std::vector<double> a;
    for_each_block(
        sources[i], common.block, log, "orders " + info.name,
        [&](std::int64_t offset, std::span<const double> x) {
          a.resize(x.size());
          angle.read(offset, a);
          tracker.push(x, a);
          if (!campbell) return;
          // The Campbell frames see the window only.
          const SampleRange w = in_window[i];
          const std::int64_t from = std::clamp<std::int64_t>(w.first - offset, 0, std::ssize(x));
          const std::int64_t to = std::clamp<std::int64_t>(w.first + w.count - offset, 0, std::ssize(x));
          if (to > from)
            campbell->push(x.subspan(static_cast<std::size_t>(from), static_cast<std::size_t>(to - from)),
                           std::span<const double>(a).subspan(static_cast<std::size_t>(from),
                                                              static_cast<std::size_t>(to - from)));
        });
    results.push_back(common.window.active() ? cycles_in_window(tracker.result(), in_window[i], sources[i])
                                             : tracker.result());
    if (results.back().amplitude.rows() == 0) {
      std::ostringstream msg;
      msg << "orders: signal '" << info.address << "' holds no complete " << command.options.cycle_deg
          << " deg cycle of the shaft angle; a longer signal is needed";
      rethrow_in_window(Error(msg.str()), common.window, sources[i]);
    }
    campbells.push_back(std::move(campbell));
  }

  Output out = create_output(common, provenance, "orders");
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const SignalInfo& info = sources[i].info();
    const OrderSpectra& s = results[i];
    const LevelReference ref =
        level_reference(quantity_for(common, info), info.unit, common.velocity_reference);
    Eigen::MatrixXd level(s.amplitude.rows(), s.amplitude.cols());
    for (Eigen::Index r = 0; r < level.rows(); ++r)
      for (Eigen::Index c = 0; c < level.cols(); ++c)
        level(r, c) = level_db(c == 0 ? s.amplitude(r, c) : s.amplitude(r, c) / std::sqrt(2.0), ref);
    h5::Group g = out.root.create_group("orders/" + info.name);
    describe_signal(g, windows[i], common.window);
    g.write("order", s.order);
    g.set_attribute("units", "1 (multiples of the shaft speed)", "order");
    g.write("rpm", s.rpm);
    g.set_attribute("units", "rpm", "rpm");
    g.set_attribute("description", "mean shaft speed of each cycle", "rpm");
    g.write("start_time_s", s.start_time_s);
    g.set_attribute("units", "s", "start_time_s");
    g.write("amplitude", s.amplitude);
    g.set_attribute("units", info.unit.empty() ? std::string("1") : info.unit, "amplitude");
    g.set_attribute("description", "peak amplitude per (cycle, order)", "amplitude");
    g.write("phase_deg", s.phase_deg);
    g.set_attribute("units", "deg", "phase_deg");
    g.set_attribute("description", "cosine phase per (cycle, order), angle zero at the cycle start",
                    "phase_deg");
    g.write("level_db", level);
    write_reference(g, "level_db", ref);
    g.set_attribute("cycle_deg", s.cycle_deg);
    g.set_attribute("samples_per_cycle", static_cast<std::int64_t>(s.samples_per_cycle));
    g.set_attribute("interpolation", command.options.interpolation == Interpolation::kSinc
                                         ? std::string("band-limited (Kaiser-windowed sinc, half-width 16)")
                                         : std::string("linear"));
    g.set_attribute("angle_source", command.angle.kind + " " + command.angle.address);
    if (campbells[i]) {
      h5::Group c = g.create_group("campbell");
      const Eigen::VectorXd rpm = campbells[i]->rpm(), f = campbells[i]->frequency_hz();
      const Eigen::MatrixXd amp = campbells[i]->amplitude();
      Eigen::MatrixXd lv(amp.rows(), amp.cols());
      for (Eigen::Index r = 0; r < amp.rows(); ++r)
        for (Eigen::Index k = 0; k < amp.cols(); ++k) lv(r, k) = level_db(amp(r, k), ref);
      c.write("rpm", rpm);
      c.set_attribute("units", "rpm", "rpm");
      c.write("frequency_hz", f);
      c.set_attribute("units", "Hz", "frequency_hz");
      c.write("amplitude", amp);
      c.set_attribute("units", info.unit.empty() ? std::string("1") : info.unit, "amplitude");
      c.set_attribute("description",
                      "RMS per (speed bin, frequency), Hann frames power-averaged per speed bin",
                      "amplitude");
      c.write("level_db", lv);
      write_reference(c, "level_db", ref);
      c.set_attribute("rpm_step", command.campbell_rpm_step);
    }
    std::ostringstream msg;
    msg.precision(5);
    msg << info.name << ": " << s.amplitude.rows() << " cycles of " << s.cycle_deg << " deg, "
        << s.samples_per_cycle << " samples per cycle, orders 0-" << s.order[s.order.size() - 1] << ", "
        << s.rpm.minCoeff() << "-" << s.rpm.maxCoeff() << " rpm";
    log.info(msg.str());
    if (common.csv_dir) {
      std::vector<std::string> header = {"rpm", "start_time_s"};
      std::vector<Eigen::VectorXd> cols;
      for (Eigen::Index k = 0; k < s.order.size(); ++k) {
        std::ostringstream name;
        name << "order_" << s.order[k];
        header.push_back(name.str());
        cols.push_back(s.amplitude.col(k));
      }
      std::vector<const Eigen::VectorXd*> ptrs = {&s.rpm, &s.start_time_s};
      for (const auto& c : cols) ptrs.push_back(&c);
      write_csv(csvs, *common.csv_dir / ("orders_" + info.name + ".csv"), header, ptrs);
    }
  }
  if (command.cut) {
    // One mean order spectrum per signal (steady runs at different speeds) against its mean speed.
    const Eigen::Index orders =
        std::min_element(results.begin(), results.end(), [](const auto& a, const auto& b) {
          return a.order.size() < b.order.size();
        })->order.size();
    Eigen::VectorXd rpm(static_cast<Eigen::Index>(results.size()));
    Eigen::MatrixXd amp(static_cast<Eigen::Index>(results.size()), orders);
    std::vector<std::string> names;
    for (std::size_t i = 0; i < results.size(); ++i) {
      rpm[static_cast<Eigen::Index>(i)] = results[i].rpm.mean();
      amp.row(static_cast<Eigen::Index>(i)) = results[i].amplitude.leftCols(orders).colwise().mean();
      names.push_back(sources[i].info().name);
    }
    h5::Group c = out.root.create_group("orders/cut");
    c.write("rpm", rpm);
    c.set_attribute("units", "rpm", "rpm");
    c.write("order", Eigen::VectorXd(results.front().order.head(orders)));
    c.write("amplitude", amp);
    c.set_attribute("description", "mean peak amplitude over the cycles of each signal, per (signal, order)",
                    "amplitude");
    c.write("signal", names);
  }
  commit_outputs(out, csvs);
}

namespace {

class OrdersAnalysis final : public Analysis {
 public:
  void add_options(CLI::App& r, CliShared& shared) override {
    add_common(r, command_.common, shared);
    add_angle(r, command_.angle);
    add_skip_cycles(r, command_.common);
    r.add_option("--cycle", command_.options.cycle_deg,
                 "analysis cycle, deg (720: 0.5-order resolution, default)")
        ->check(CLI::PositiveNumber);
    r.add_option("--samples-per-cycle", command_.options.samples_per_cycle,
                 "angle samples per cycle (default: auto)")
        ->check(CLI::PositiveNumber);
    r.add_option("--max-order", command_.options.max_order,
                 "highest order stored (default: 0.8 x angle Nyquist)")
        ->check(CLI::PositiveNumber);
    r.add_option("--interpolation", interpolation_, "sinc (band-limited, default) or linear")
        ->check(CLI::IsMember({"sinc", "linear"}));
    r.add_flag("--cut", command_.cut,
               "also /orders/cut: mean order spectrum of each signal against its mean rpm");
    r.add_flag("--campbell", command_.campbell, "also a Campbell diagram (rpm x frequency) per signal");
    r.add_option("--campbell-rpm-step", command_.campbell_rpm_step, "speed bin of the Campbell diagram, rpm")
        ->check(CLI::PositiveNumber);
    r.add_option("--campbell-fmax", command_.campbell_fmax_hz, "highest Campbell frequency, Hz")
        ->check(CLI::PositiveNumber);
    r.add_option("--campbell-resolution", command_.campbell_resolution_hz,
                 "Campbell frequency resolution, Hz")
        ->check(CLI::PositiveNumber);
  }

  void run(const Logger& log, int argc, const char* const* argv) override {
    command_.options.interpolation =
        interpolation_ == "linear" ? Interpolation::kLinear : Interpolation::kSinc;
    run_orders(command_, log, argc, argv);
  }

  std::filesystem::path output() const override { return command_.common.output; }

 private:
  OrdersCommand command_;
  std::string interpolation_ = "sinc";
};

}  // namespace

std::unique_ptr<Analysis> make_orders_analysis() {
  return std::make_unique<OrdersAnalysis>();
}

}  // namespace nvh::postproc
