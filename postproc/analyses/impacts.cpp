// postproc impacts: the impacts of a contact (postproc/impacts.hpp) with the impacting body's velocity and
// kinetic energy at each, as HDF5, CSV and PNG (docs/postproc.md sections 3.8, 4.6, 5).
//
//   postproc impacts slap.h5:/forces/skirt/side_force --direction -1 --velocity
//   slap.h5:/markers/piston.pin/velocity[x]
//       --mass 0.42 --angle-window 340,400 -o impacts.h5
#include "postproc/impacts.hpp"

#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "common/error.hpp"
#include "postproc/analysis.hpp"
#include "postproc/cli_options.hpp"
#include "postproc/csv.hpp"
#include "postproc/output.hpp"
#include "postproc/signal_input.hpp"
#include "postproc/windowing.hpp"

namespace nvh::postproc {
namespace {

struct ImpactsCommand {
  CommonOptions common;  // the one force signal, output, window
  ImpactOptions impact;
  std::string velocity;          // the impacting body's velocity along the contact normal
  std::string angular_velocity;  // optional: its angular velocity (the tilt of a piston)
  std::optional<double> mass, inertia;
};

/// A companion signal (velocity, angular velocity) of the force: the same file's samples, windowed as the
/// force. An error names the option and what differs.
std::vector<double> companion(const std::string& option, const std::string& address,
                              const SignalSource& force) {
  SignalSource s = SignalSource::open(address);
  const SignalInfo &a = s.info(), &f = force.info();
  if (s.size() != force.file_size() ||
      std::abs(a.sample_rate_hz - f.sample_rate_hz) > 1e-9 * f.sample_rate_hz ||
      std::abs(a.start_time_s - force.file_start_time_s()) > 0.5 / f.sample_rate_hz) {
    std::ostringstream msg;
    msg << option << " '" << address << "': " << s.size() << " samples at " << a.sample_rate_hz << " Hz from "
        << a.start_time_s << " s; expected the force's sampling (" << force.file_size() << " samples at "
        << f.sample_rate_hz << " Hz from " << force.file_start_time_s() << " s), e.g. a signal of the same "
        << "results file";
    throw Error(msg.str());
  }
  s.restrict_to(force.first_sample(), force.size());
  return s.read_all();
}

void run_impacts(const ImpactsCommand& command, const Logger& log, int argc, const char* const* argv) {
  const CommonOptions& common = command.common;
  if (common.signals.size() != 1)
    throw Error("postproc impacts: expected one contact force signal, got " +
                std::to_string(common.signals.size()));
  if (command.inertia && command.angular_velocity.empty())
    throw Error("--inertia needs --angular-velocity (the kinetic energy of the rotation)");
  if (!command.angular_velocity.empty() && command.inertia.value_or(0) <= 0 && command.mass)
    throw Error("--angular-velocity with --mass needs --inertia > 0 (kg m^2) for the rotation's energy");
  std::vector<SignalSource> sources = open_signals(common);
  check_outputs(common, sources, nullptr, "impacts_");
  SignalSource& force = sources.front();
  apply_window(force, common.window, nullptr, 0.0, common.block, log);
  const SignalInfo& info = force.info();
  const std::vector<double> f = force.read_all();
  const std::vector<double> v = companion("--velocity", command.velocity, force);
  const std::vector<double> w = command.angular_velocity.empty()
                                    ? std::vector<double>{}
                                    : companion("--angular-velocity", command.angular_velocity, force);
  const Eigen::VectorXd angle = shaft_angle_at_samples(force, common.window);
  std::future<Provenance> provenance = start_provenance(sources, argc, argv);

  const std::vector<Impact> impacts = find_impacts(f, command.impact);
  const auto n = static_cast<Eigen::Index>(impacts.size());
  const double dt = 1 / info.sample_rate_hz, nan = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd time(n), release(n), duration(n), peak(n), velocity(n), omega(n), energy(n), theta(n);
  for (Eigen::Index e = 0; e < n; ++e) {
    const Impact& i = impacts[static_cast<std::size_t>(e)];
    const double sample = static_cast<double>(i.sample - 1) + i.fraction;
    time[e] = info.start_time_s + sample * dt;
    release[e] = i.release_sample < 0 ? nan : info.start_time_s + i.release_sample * dt;
    duration[e] = release[e] - time[e];
    peak[e] = command.impact.direction * i.peak_force;
    velocity[e] = at_impact(i, v);
    omega[e] = w.empty() ? nan : at_impact(i, w);
    energy[e] = nan;
    if (command.mass)
      energy[e] = 0.5 * *command.mass * velocity[e] * velocity[e] +
                  (w.empty() ? 0.0 : 0.5 * *command.inertia * omega[e] * omega[e]);
    theta[e] =
        angle.size() == static_cast<Eigen::Index>(f.size())
            ? at_impact(i, std::span<const double>(angle.data(), static_cast<std::size_t>(angle.size())))
            : nan;
  }

  Output out = create_output(common, provenance, "impacts");
  h5::Group g = out.root.create_group("impacts/" + info.name);
  describe_signal(g, info, common.window);
  g.set_attribute("threshold", command.impact.threshold);
  g.set_attribute("direction", static_cast<std::int64_t>(command.impact.direction));
  g.set_attribute("velocity_signal", command.velocity);
  const std::string force_unit = info.unit.empty() ? std::string("1") : info.unit;
  const std::string velocity_unit = SignalSource::open(command.velocity).info().unit;
  auto dataset = [&](const char* name, const Eigen::VectorXd& x, const std::string& unit, const char* what) {
    g.write(name, x);
    g.set_attribute("units", unit.empty() ? std::string("1") : unit, name);
    g.set_attribute("description", what, name);
  };
  dataset("time_s", time, "s", "the impact: the threshold's crossing, interpolated");
  dataset("release_time_s", release, "s", "the contact's release (NaN: still closed at the last sample)");
  dataset("duration_s", duration, "s", "release - impact");
  dataset("peak_force", peak, force_unit, "the force's extreme over the contact (its sign: the contact's)");
  dataset("velocity", velocity, velocity_unit, "the --velocity signal at the impact");
  std::vector<std::string> header = {
      "time_s", "release_time_s", "duration_s", "peak_force_" + force_unit,
      "velocity_" + (velocity_unit.empty() ? std::string("1") : velocity_unit)};
  std::vector<const Eigen::VectorXd*> columns = {&time, &release, &duration, &peak, &velocity};
  if (!w.empty()) {
    dataset("angular_velocity", omega, SignalSource::open(command.angular_velocity).info().unit,
            "the --angular-velocity signal at the impact");
    header.push_back("angular_velocity_rad/s");
    columns.push_back(&omega);
  }
  if (command.mass) {
    dataset("energy_j", energy, "J", "1/2 m v^2 (+ 1/2 J omega^2) at the impact");
    g.set_attribute("mass_kg", *command.mass);
    if (command.inertia) g.set_attribute("inertia_kg_m2", *command.inertia);
    header.push_back("energy_J");
    columns.push_back(&energy);
  }
  if (angle.size() == static_cast<Eigen::Index>(f.size())) {
    dataset("crank_angle_deg", theta, "deg", "the shaft angle at the impact (unwrapped)");
    header.push_back("crank_angle_deg");
    columns.push_back(&theta);
  }
  // The force itself over the window, for the plot (the events drawn on it).
  Eigen::VectorXd t_all(static_cast<Eigen::Index>(f.size()));
  for (Eigen::Index k = 0; k < t_all.size(); ++k) t_all[k] = info.start_time_s + static_cast<double>(k) * dt;
  dataset("force_time_s", t_all, "s", "the samples' times");
  dataset("force", Eigen::Map<const Eigen::VectorXd>(f.data(), t_all.size()), force_unit,
          "the force analysed");
  if (angle.size() == t_all.size())
    dataset("force_crank_angle_deg", angle, "deg", "the samples' shaft angle");
  std::vector<TextOutput> csvs;
  if (common.csv_dir) write_csv(csvs, *common.csv_dir / ("impacts_" + info.name + ".csv"), header, columns);

  std::ostringstream msg;
  msg.precision(6);
  msg << info.name << ": " << n << " impact" << (n == 1 ? "" : "s") << " (threshold "
      << command.impact.threshold << " " << force_unit << ")";
  for (Eigen::Index e = 0; e < std::min<Eigen::Index>(n, 5); ++e) {
    msg << "; t " << time[e] << " s";
    if (!std::isnan(theta[e])) msg << " (" << theta[e] << " deg)";
    msg << " v " << velocity[e];
    if (command.mass) msg << " E " << energy[e] << " J";
  }
  log.info(msg.str());
  commit_outputs(out, csvs);
}

class ImpactsAnalysis final : public Analysis {
 public:
  void add_options(CLI::App& sub, CliShared& shared) override {
    CommonOptions& c = command_.common;
    sub.add_option("FORCE", c.signals, "the contact force (see postproc --help)")->required()->expected(1);
    add_output_options(sub, c, shared);
    add_time_window(sub, c);
    sub.add_option(
           "--velocity", command_.velocity,
           "the impacting body's velocity along the contact normal, sampled as FORCE (a signal of the "
           "same results file)")
        ->required();
    sub.add_option("--angular-velocity", command_.angular_velocity,
                   "its angular velocity, rad/s (the tilt of a piston), for the energy with --inertia");
    sub.add_option_function<double>(
           "--mass", [this](double m) { command_.mass = m; },
           "its mass, kg: the energy 1/2 m v^2 at each impact")
        ->check(CLI::PositiveNumber);
    sub.add_option_function<double>(
           "--inertia", [this](double j) { command_.inertia = j; },
           "its moment of inertia about the --angular-velocity axis, kg m^2: adds 1/2 J omega^2")
        ->check(CLI::PositiveNumber);
    sub.add_option("--threshold", command_.impact.threshold,
                   "the contact is closed where direction x FORCE >= this, in FORCE's unit (default 10)")
        ->check(CLI::PositiveNumber);
    sub.add_option(
           "--direction", command_.impact.direction,
           "+1: FORCE is positive in contact (a normal force; default); -1: negative (the thrust side "
           "of a piston's side force)")
        ->check(CLI::IsMember({1, -1}));
  }
  void run(const Logger& log, int argc, const char* const* argv) override {
    run_impacts(command_, log, argc, argv);
  }
  std::filesystem::path output() const override { return command_.common.output; }

 private:
  ImpactsCommand command_;
};

}  // namespace

std::unique_ptr<Analysis> make_impacts_analysis() {
  return std::make_unique<ImpactsAnalysis>();
}

}  // namespace nvh::postproc
