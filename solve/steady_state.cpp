#include "solve/steady_state.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "solve/element_registry.hpp"
#include "solve/results.hpp"
#include "solve/scene.hpp"

namespace nvh::solve {
namespace {

using input::Range;

/// Fewer samples than this in the first cycle cannot resolve it (the phases are those samples).
constexpr int kMinPhases = 8;
/// A channel that has decayed to ~0 is measured against this fraction of its largest cycle RMS so far.
constexpr double kDecayedFloor = 1e-3;

std::string sci(double v, int digits = 3) {
  std::ostringstream s;
  s << std::scientific << std::setprecision(digits) << v;
  return s.str();
}

/// "markers/a.b/acceleration[2]" -> {"markers/a.b/acceleration", 2}; no suffix: column -1. A leading '/'
/// is dropped. Returns false if the suffix is malformed.
bool split_channel(std::string name, std::string& path, int& column) {
  if (!name.empty() && name.front() == '/') name.erase(0, 1);
  column = -1;
  path = name;
  if (name.empty() || name.back() != ']') return !name.empty();
  const auto open = name.rfind('[');
  if (open == std::string::npos || open + 2 > name.size() - 1) return false;
  const std::string digits = name.substr(open + 1, name.size() - open - 2);
  if (digits.empty() || digits.size() > 6 || !std::all_of(digits.begin(), digits.end(), ::isdigit))
    return false;
  column = std::stoi(digits);
  path = name.substr(0, open);
  return !path.empty();
}

}  // namespace

SteadyStateSettings read_steady_state(const input::Table& t, bool clock_markers, double clock_cycle_deg) {
  SteadyStateSettings s;
  s.channels = t.strings("channels");
  if (s.channels.empty())
    t.fail("channels",
           "expected at least one result channel, e.g. [\"forces/mount/force\"] (a dataset's path in "
           "the results file, optionally with a column: \"markers/block.top/acceleration[2]\")");
  for (auto& c : s.channels) {
    std::string path;
    int column = 0;
    if (!split_channel(c, path, column))
      t.fail("channels", "'" + c +
                             "': expected a dataset path such as \"forces/mount/force\" or "
                             "\"markers/block.top/acceleration[2]\"");
    c = column < 0 ? path : path + "[" + std::to_string(column) + "]";
  }
  if (t.has("floors")) {
    s.floors = t.numbers("floors", Range::closed(0.0, bounds::kCoefficient));
    if (s.floors.size() != s.channels.size())
      t.fail("floors", "expected one floor per channel (" + std::to_string(s.channels.size()) +
                           "), in each channel's "
                           "unit, got " +
                           std::to_string(s.floors.size()));
  } else {
    s.floors.assign(s.channels.size(), 0.0);
  }
  s.tolerance = t.number_or("tolerance", s.tolerance, Range::open(0.0, 1.0));
  s.max_cycles =
      static_cast<int>(t.optional_integer("max_cycles", Range::closed(2, 1e6)).value_or(s.max_cycles));
  s.keep_cycles =
      static_cast<int>(t.optional_integer("keep_cycles", Range::closed(1, 1e6)).value_or(s.keep_cycles));
  if (s.keep_cycles > s.max_cycles)
    t.fail("keep_cycles", "expected at most max_cycles = " + std::to_string(s.max_cycles) +
                              " cycles to keep, got " + std::to_string(s.keep_cycles));
  s.keep_history = t.optional_boolean("keep_history").value_or(false);
  if (clock_markers) {
    if (t.has("period"))
      t.fail("period",
             "the scene's [clock] has markers: the cycle is a crank angle, give cycle_deg (default " +
                 std::string(clock_cycle_deg > 0 ? "the [clock]'s cycle_deg" : "720") + ")");
    s.by_angle = true;
    s.cycle = t.number_or("cycle_deg", clock_cycle_deg > 0 ? clock_cycle_deg : 720.0,
                          Range{0.0, bounds::kAngleDeg, true, false});
  } else {
    if (t.has("cycle_deg"))
      t.fail("cycle_deg",
             "a cycle of crank angle needs [clock] i and j markers; without them give period (s)");
    if (!t.has("period"))
      t.fail("period",
             "expected the cycle's period in s (the scene's [clock] has no markers, so no crank angle)");
    s.by_angle = false;
    s.cycle = t.number("period", Range{0.0, 1e9, true, false});
  }
  t.finish();
  return s;
}

void check_steady_state_channels(const input::Table& t, const SteadyStateSettings& s,
                                 const std::vector<std::string>& paths, const std::vector<int>& columns) {
  for (const auto& c : s.channels) {
    std::string path;
    int column = -1;
    split_channel(c, path, column);
    const auto it = std::find(paths.begin(), paths.end(), path);
    if (it == paths.end()) {
      const std::string near = input::closest(path, paths);
      t.fail("channels", "no result dataset '" + path + "' in this scene" +
                             (near.empty() ? "" : " (did you mean '" + near + "'?)") +
                             "; expected a path of the results file (docs/results-format.md), e.g. '" +
                             (paths.size() > 2 ? paths[2] : paths.front()) + "'");
    }
    const int width = columns[static_cast<std::size_t>(it - paths.begin())];
    if (column >= 0 && column >= std::max(width, 1))
      t.fail("channels",
             "'" + c + "': /" + path + " has " +
                 (width == 0 ? std::string("one column (a vector: give no [k])")
                             : std::to_string(width) + " columns (0 to " + std::to_string(width - 1) + ")"));
  }
}

SteadyStateMonitor::SteadyStateMonitor(const SteadyStateSettings& settings, const ResultsWriter& writer,
                                       double origin)
    : s_(settings), origin_(origin) {
  for (const auto& c : s_.channels) {
    std::string path;
    int column = -1;
    split_channel(c, path, column);
    const int index = writer.dataset_index(path);
    if (index < 0) throw Error("steady_state: the results have no dataset /" + path);
    const int width = static_cast<int>(writer.dataset_width(index));
    dataset_.push_back(index);
    first_column_.push_back(column);
    columns_.push_back(column >= 0 ? 1 : width);
    offset_.push_back(width_);
    width_ += columns_.back();
  }
  largest_rms_.assign(s_.channels.size(), 0.0);
  scratch_.resize(static_cast<std::size_t>(width_));
}

bool SteadyStateMonitor::add(double x, long row, const ResultsWriter& writer, const Logger& log) {
  for (std::size_t c = 0; c < dataset_.size(); ++c) {
    const std::span<const double> v = writer.last_sample(dataset_[c]);
    for (int k = 0; k < columns_[c]; ++k)
      scratch_[static_cast<std::size_t>(offset_[c] + k)] =
          v[static_cast<std::size_t>(first_column_[c] >= 0 ? first_column_[c] : k)];
  }
  return add_values(x, row, scratch_, log);
}

void SteadyStateMonitor::replay(const h5::Group& root, long rows, const Logger& log) {
  if (rows <= 0) return;
  const Eigen::VectorXd x = root.read_vector(s_.by_angle ? "crank_angle_deg" : "time");
  std::vector<Eigen::MatrixXd> data;
  for (const auto& c : s_.channels) {
    std::string path;
    int column = -1;
    split_channel(c, path, column);
    std::vector<hsize_t> dims;
    const std::vector<double> all = root.read_array(path, dims);
    const Eigen::Index n = static_cast<Eigen::Index>(dims.at(0)),
                       w = dims.size() > 1 ? static_cast<Eigen::Index>(dims[1]) : 1;
    data.push_back(Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        all.data(), n, w));
  }
  for (long r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < data.size(); ++c)
      for (int k = 0; k < columns_[c]; ++k)
        scratch_[static_cast<std::size_t>(offset_[c] + k)] =
            data[c](r, first_column_[c] >= 0 ? first_column_[c] : k);
    if (add_values(x[r], r, scratch_, log)) break;
  }
}

// A sample within kBoundary of the cycle (1e-6 of it: 7e-4 deg of 720) counts as on the boundary: a crank
// angle from the integration lands a little off the exact multiple, and the kept cycle must then start at
// that sample, not at the next one (postproc's orders need the whole cycle).
constexpr double kBoundary = 1e-6;

bool SteadyStateMonitor::add_values(double x, long row, std::span<const double> values, const Logger& log) {
  const double rel = x - origin_, eps = kBoundary * s_.cycle;
  if (r_.cycle_first_row.empty()) {
    r_.cycle_first_row.push_back(row);
    r_.cycle_start.push_back(origin_);
  }
  last_row_ = row;
  xs_.push_back(rel);
  values_.insert(values_.end(), values.begin(), values.end());
  // A sample at or past the end of the open cycle closes it (the phases near its end need it).
  while (!done_ && rel >= (r_.cycles + 1) * s_.cycle - eps) {
    close_cycle(log);
    r_.cycle_first_row.push_back(row);
    r_.cycle_start.push_back(origin_ + r_.cycles * s_.cycle);
  }
  return done_;
}

void SteadyStateMonitor::close_cycle(const Logger& log) {
  const int k = r_.cycles;
  const double c0 = k * s_.cycle, c1 = (k + 1) * s_.cycle, eps = kBoundary * s_.cycle;
  const auto in_cycle =
      std::count_if(xs_.begin(), xs_.end(), [&](double x) { return x >= c0 - eps && x < c1 - eps; });
  const std::string unit = s_.by_angle ? " deg" : " s";
  if (phases_ == 0) {
    if (in_cycle < kMinPhases)
      throw Error("steady_state: the first cycle (" + sci(s_.cycle) + unit + ") holds only " +
                  std::to_string(in_cycle) + " samples; expected at least " + std::to_string(kMinPhases) +
                  ": raise [output] sample_rate_hz or lengthen the cycle");
    phases_ = static_cast<int>(in_cycle);
  } else if (in_cycle < 2) {
    throw Error("steady_state: cycle " + std::to_string(k + 1) + " holds " + std::to_string(in_cycle) +
                " samples (the clock has slowed down?); expected about " + std::to_string(phases_));
  }
  // The channels at the N phases of this cycle: linear interpolation in x between the samples around them.
  Eigen::MatrixXd p(phases_, width_);
  std::size_t i = 0;
  const std::size_t n = xs_.size();
  for (int j = 0; j < phases_; ++j) {
    const double xj = c0 + s_.cycle * j / phases_;
    while (i + 2 < n && xs_[i + 1] <= xj) ++i;
    const double a = xs_[i], b = xs_[std::min(i + 1, n - 1)];
    const double w = b > a ? std::clamp((xj - a) / (b - a), 0.0, 1.0) : 0.0;
    for (int c = 0; c < width_; ++c)
      p(j, c) = (1 - w) * values_[i * width_ + c] + w * values_[std::min(i + 1, n - 1) * width_ + c];
  }
  ++r_.cycles;
  std::vector<double> change(s_.channels.size(), 0.0);
  for (std::size_t c = 0; c < s_.channels.size(); ++c) {
    const auto cols = p.middleCols(offset_[c], columns_[c]);
    const double count = static_cast<double>(cols.size());
    const double rms = std::sqrt(cols.squaredNorm() / count);
    largest_rms_[c] = std::max(largest_rms_[c], rms);
    if (k == 0) continue;
    const double diff =
        std::sqrt((cols - previous_.middleCols(offset_[c], columns_[c])).squaredNorm() / count);
    const double denominator = std::max({rms, kDecayedFloor * largest_rms_[c], s_.floors[c]});
    change[c] = denominator > 0 ? diff / denominator : 0.0;
  }
  previous_ = std::move(p);
  // Keep the last sample before the next cycle's start and those after it.
  std::size_t keep = 0;
  while (keep + 1 < n && xs_[keep + 1] < c1 - eps) ++keep;
  xs_.erase(xs_.begin(), xs_.begin() + static_cast<std::ptrdiff_t>(keep));
  values_.erase(values_.begin(), values_.begin() + static_cast<std::ptrdiff_t>(keep * width_));

  std::ostringstream line;
  line << "steady state: cycle " << r_.cycles << " of at most " << s_.max_cycles;
  if (k == 0) {
    line << ": the first (" << phases_ << " phases), nothing to compare yet";
    r_.final_change.assign(s_.channels.size(), std::numeric_limits<double>::quiet_NaN());
    r_.final_distance = r_.final_change;
  } else {
    // The estimated distance to the periodic solution (steady_state.hpp): change q / (1 - q), q the
    // channel's last ratio of changes held to [0.5, 0.95].
    // A channel whose change grew in one of the last two cycles no longer decays geometrically: it sits at
    // its noise floor (the integrator's tolerance, a chaotic contact), where the series has nothing left to
    // sum, and its distance is its change.
    std::vector<double> distance(change.size());
    for (std::size_t c = 0; c < change.size(); ++c) {
      double q = 0.95;
      if (!changes_.empty()) {
        const double before = changes_.back()[c];
        q = before > 0 ? std::clamp(change[c] / before, 0.5, 0.95) : (change[c] > 0 ? 0.95 : 0.5);
        const std::size_t m = changes_.size();
        const bool grew = change[c] > before || (m >= 2 && changes_[m - 1][c] > changes_[m - 2][c]);
        if (grew && m >= 2) q = 0.5;
      }
      distance[c] = change[c] * q / (1 - q);
    }
    changes_.push_back(change);
    r_.final_change = change;
    r_.final_distance = distance;
    const auto worst = std::max_element(distance.begin(), distance.end()) - distance.begin();
    line << ": largest change " << sci(*std::max_element(change.begin(), change.end())) << ", distance "
         << sci(distance[worst]) << " in " << s_.channels[worst] << " (tolerance " << sci(s_.tolerance, 1)
         << ")";
    r_.converged = distance[worst] < s_.tolerance;
  }
  log.info(line.str());
  done_ = r_.converged || r_.cycles >= s_.max_cycles;
}

SteadyStateResult SteadyStateMonitor::result() const {
  SteadyStateResult r = r_;
  r.change.resize(static_cast<Eigen::Index>(changes_.size()), static_cast<Eigen::Index>(s_.channels.size()));
  for (std::size_t k = 0; k < changes_.size(); ++k)
    for (std::size_t c = 0; c < s_.channels.size(); ++c)
      r.change(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(c)) = changes_[k][c];
  r.kept_cycles = std::min(r.cycles, s_.keep_cycles);
  if (r.kept_cycles == 0) {  // no complete cycle (the run ended by its time limit): everything is kept
    r.kept_first = 0;
    r.kept_end = last_row_ + 1;
  } else {
    r.kept_first = r.cycle_first_row[static_cast<std::size_t>(r.cycles - r.kept_cycles)];
    r.kept_end = r.cycle_first_row[static_cast<std::size_t>(r.cycles)];
  }
  return r;
}

void refuse_restart_of_steady_state_result(const std::filesystem::path& path) {
  const h5::File f = h5::File::open_read(path);
  if (f.root().exists("solver/steady_state"))
    throw Error(path.string() +
                ": holds a finished steady-state result (/solver/steady_state): there is nothing to "
                "continue; run without --restart");
}

namespace {

void write_record(h5::Group& root, const SteadyStateSettings& s, const SteadyStateResult& r,
                  long first_sample, const std::string& message) {
  h5::Group g = root.create_group("solver/steady_state");
  g.set_attribute("converged", r.converged ? 1 : 0);
  g.set_attribute("cycles", r.cycles);
  g.set_attribute("tolerance", s.tolerance);
  g.set_attribute("max_cycles", s.max_cycles);
  g.set_attribute("cycle", s.cycle);
  g.set_attribute("cycle_unit", s.by_angle ? "deg" : "s");
  g.set_attribute("keep_cycles", r.kept_cycles);
  g.set_attribute("keep_history", s.keep_history ? 1 : 0);
  g.set_attribute("first_sample", static_cast<std::int64_t>(first_sample));
  g.set_attribute("samples", static_cast<std::int64_t>(r.kept_end - r.kept_first));
  g.set_attribute("message", message);
  g.write("channels", s.channels);
  g.write("final_change", Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(
                              r.final_change.data(), static_cast<Eigen::Index>(r.final_change.size()))));
  g.write("final_distance",
          Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(
              r.final_distance.data(), static_cast<Eigen::Index>(r.final_distance.size()))));
  g.set_attribute("unit", "1", "final_distance");
  if (r.change.rows() > 0) g.write("change", r.change);
  g.write("cycle_start", Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(
                             r.cycle_start.data(), static_cast<Eigen::Index>(r.cycle_start.size()))));
  g.set_attribute("unit", s.by_angle ? "deg" : "s", "cycle_start");
  g.set_attribute("unit", "1", "final_change");
  if (r.change.rows() > 0) g.set_attribute("unit", "1", "change");
}

}  // namespace

void write_steady_state_result(const std::filesystem::path& path, const Scene& scene,
                               const Provenance& provenance, std::unique_ptr<ResultsWriter>& writer,
                               const SteadyStateResult& r, const Checkpoint& final_state,
                               const IntegratorStatistics& statistics, double wall_seconds,
                               double max_position_drift, double max_velocity_drift, const Logger& log) {
  const SteadyStateSettings& s = *scene.steady_state;
  std::string message;
  std::string worst_channel = "-";
  double worst = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t c = 0; c < r.final_distance.size(); ++c)
    if (!(r.final_distance[c] <= worst)) {
      worst = r.final_distance[c];
      worst_channel = s.channels[c];
    }
  if (r.converged) {
    message = "steady state reached after " + std::to_string(r.cycles) +
              " cycles (largest estimated distance to the periodic solution " + sci(worst) + " in " +
              worst_channel + ", tolerance " + sci(s.tolerance, 1) + ")";
    log.info(message);
  } else {
    message = "steady state NOT reached after " + std::to_string(r.cycles) +
              " cycles (max_cycles = " + std::to_string(s.max_cycles) +
              "): the largest estimated distance to the periodic solution " + sci(worst) + " in " +
              worst_channel + " is above the tolerance " + sci(s.tolerance, 1) +
              "; the last " + std::to_string(r.kept_cycles) +
              " cycle(s) are written anyway, with /solver/steady_state converged = 0";
    log.warning(message);
  }
  {
    h5::Group root = writer->root();
    write_record(root, s, r, r.kept_first, message);
    root.set_attribute("message", message);
  }
  if (s.keep_history || r.kept_cycles == 0) {
    writer->set_drift(max_position_drift, max_velocity_drift);  // flushes
    writer.reset();
    return;
  }
  // The kept cycles in a file of their own, renamed over the history only once complete: a run killed in
  // here leaves the complete history (its /solver/steady_state says which rows the result would keep).
  writer->set_drift(max_position_drift, max_velocity_drift);
  std::filesystem::path temporary = path;
  temporary += ".steady-state.tmp";
  register_temporary(temporary);
  try {
    Checkpoint cp = final_state;
    cp.samples = r.kept_end - r.kept_first;
    {
      ResultsWriter kept = ResultsWriter::create(temporary, scene, provenance, cp);
      kept.append_rows(writer->root(), static_cast<hsize_t>(r.kept_first), static_cast<hsize_t>(r.kept_end));
      kept.finish("complete", message, statistics, wall_seconds);
      h5::Group kept_root = kept.root();
      write_record(kept_root, s, r, 0, message);
      kept.set_drift(max_position_drift, max_velocity_drift);
    }
    writer.reset();
    std::filesystem::rename(temporary, path);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    unregister_temporary(temporary);
    throw;
  }
  unregister_temporary(temporary);
  log.info("kept the last " + std::to_string(r.kept_cycles) + " cycle(s), " +
           std::to_string(r.kept_end - r.kept_first) + " samples, in " + path.string());
}

}  // namespace nvh::solve
