#include "solve/bearing/bearing_map_cli.hpp"

#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <optional>

#include "common/error.hpp"
#include "common/hdf5.hpp"
#include "common/input.hpp"
#include "common/interrupt.hpp"
#include "common/log.hpp"
#include "common/output_path.hpp"
#include "common/provenance.hpp"
#include "common/version.hpp"
#include "solve/bearing/bearing_map.hpp"
#include "solve/bearing/bearing_reader.hpp"

namespace nvh::bearing {

namespace {

constexpr const char* kDescription =
    R"(solve bearing-map - static characteristics of a journal bearing over eccentricity ratio

Reads a bearing file (TOML: a [bearing] table with geometry, oil, model, feeds and grid, and a [map] table
with speed_rpm, optional eccentricities and load_angle_deg; see docs/bearing.md) and writes, for each
eccentricity ratio, the Sommerfeld number, attitude angle, load, minimum film, peak pressure, friction,
power loss, oil flows and the 8 linear stiffness and damping coefficients at that static equilibrium.

Example:
  solve bearing-map main_bearing.toml -o main_bearing_map.h5 --csv main_bearing_map.csv
  h5dump -d /map/sommerfeld main_bearing_map.h5

Exit codes: 0 success; 1 bad input or failed run (message names file, line, key); 2 bad command line.)";

const std::vector<double> kDefaultEccentricities = {0.05, 0.1, 0.2, 0.3, 0.4,  0.5,
                                                    0.6,  0.7, 0.8, 0.9, 0.95, 0.97};

const char* to_string(Model m) {
  return m == Model::kShort ? "short" : m == Model::kLong ? "long" : "finite";
}
const char* to_string(Cavitation c) {
  return c == Cavitation::kJfo ? "jfo" : c == Cavitation::kSwiftStieber ? "swift-stieber" : "none";
}

// Written to its temporary and closed; the caller commits it together with the map file.
TextOutput write_csv(const std::filesystem::path& path, const std::vector<MapRow>& rows) {
  TextOutput csv(path);
  std::ostream& out = csv.stream();
  const auto names = map_column_names();
  for (std::size_t i = 0; i < names.size(); ++i) out << (i ? "," : "") << names[i];
  out << "\n";
  out.precision(10);
  for (const MapRow& row : rows) {
    const auto values = map_row_values(row);
    for (std::size_t i = 0; i < values.size(); ++i) out << (i ? "," : "") << values[i];
    out << "\n";
  }
  csv.close();
  return csv;
}

}  // namespace

// The fastest journal the map accepts (as solve's rpm, docs/scene-format.md): beyond it the film's pressure
// scale overflows.
constexpr double kMaxRpm = 1e7;

int bearing_map_main(int argc, char** argv) {
  CLI::App app{kDescription, "bearing-map"};
  std::string input_file, output_file, csv_file;
  std::vector<double> eccentricities;
  std::optional<double> speed_rpm;
  bool quiet = false;
  app.add_option("BEARING", input_file, "bearing file (.toml); see docs/bearing.md")->required();
  app.add_option("-o,--output", output_file, "map file to write (.h5)")->required();
  app.add_option("--csv", csv_file, "also write the map as CSV");
  app.add_option("--eccentricities", eccentricities, "eccentricity ratios, each in (0, 1) (overrides [map])")
      ->delimiter(',');
  app.add_option("--speed-rpm", speed_rpm, "journal speed, rpm (overrides [map] speed_rpm)")
      ->check(CLI::PositiveNumber);
  app.add_flag("-q,--quiet", quiet, "print errors only");
  app.set_version_flag("--version", std::string("solve bearing-map ") + kVersion);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : static_cast<int>(ExitCode::kUsage);
  }
  const Logger log(std::cerr, "bearing-map", quiet ? Verbosity::kQuiet : Verbosity::kNormal);
  try {
    // Before any work: no output may replace the bearing file or the other output, and both are writable.
    std::vector<std::filesystem::path> outputs{output_file};
    if (!csv_file.empty()) outputs.push_back(csv_file);
    check_outputs_are_not_inputs(outputs, {input_file});
    for (const auto& output : outputs) check_output_writable(output);
    const input::Document doc = input::Document::load(input_file);
    const input::Table root = doc.root();
    const input::Table table = root.table("bearing");
    const BearingSpec spec = read_bearing(table);
    table.finish();
    double rpm = 0, load_angle_deg = -90;
    std::vector<double> from_file;
    if (const auto map = root.optional_table("map")) {
      rpm = map->number_or("speed_rpm", 0.0, input::Range::closed(0.0, kMaxRpm));
      load_angle_deg = map->number_or("load_angle_deg", -90.0, input::Range::closed(-360.0, 360.0));
      if (map->has("eccentricities")) from_file = map->numbers("eccentricities", input::Range::open(0, 1));
      map->finish();
    }
    root.finish();
    if (speed_rpm) rpm = *speed_rpm;
    if (speed_rpm && !(rpm <= kMaxRpm)) {
      throw Error("--speed-rpm: " + std::to_string(rpm) +
                  " is not a finite speed <= " + std::to_string(kMaxRpm) + " rpm");
    }
    if (!(rpm > 0)) {
      throw Error(input_file + ": no journal speed: give [map] speed_rpm = ... (rpm, > 0) or --speed-rpm");
    }
    if (eccentricities.empty()) eccentricities = from_file.empty() ? kDefaultEccentricities : from_file;
    for (double e : eccentricities) {
      if (!(e > 0 && e < 1)) {
        throw Error("--eccentricities: " + std::to_string(e) + " is outside (0, 1); expected 0 < eps < 1");
      }
    }
    const double omega = rpm * 2 * std::numbers::pi / 60;
    log.info("bearing '" + spec.name + "' (" + to_string(spec.model) + "): " +
             std::to_string(eccentricities.size()) + " eccentricities at " + std::to_string(rpm) + " rpm");
    const std::vector<MapRow> rows = [&] {
      try {
        return bearing_map(spec, omega, eccentricities, load_angle_deg * std::numbers::pi / 180);
      } catch (const Interrupted&) {
        throw;
      } catch (const Error& e) {
        // A film that cannot carry the load (no solution of the model) comes from the file's numbers: name it,
        // so a log of many maps points at the file to change.
        throw Error(input_file + ": " + e.what());
      }
    }();

    h5::File file = h5::File::create(output_file);
    h5::Group out = file.root();
    out.set_attribute("format", "nvh-bearing-map");
    out.set_attribute("format_version", "1.0");
    out.set_attribute("units", "SI");
    write_provenance(out, make_provenance("solve bearing-map", argc, argv, {input_file}));
    h5::Group b = out.create_group("bearing");
    b.set_attribute("name", spec.name);
    b.set_attribute("model", to_string(spec.model));
    b.set_attribute("cavitation", to_string(spec.cavitation));
    b.set_attribute("diameter_m", spec.diameter);
    b.set_attribute("width_m", spec.width);
    b.set_attribute("radial_clearance_m", spec.radial_clearance);
    b.set_attribute("viscosity_pa_s", spec.viscosity);
    b.set_attribute("barus_per_pa", spec.barus);
    b.set_attribute("supply_pressure_pa", spec.supply_pressure);
    b.set_attribute("grid", std::vector<double>{double(spec.cells_around), double(spec.cells_across)});
    b.set_attribute("speed_rpm", rpm);
    b.set_attribute("load_angle_deg", load_angle_deg);
    h5::Group map = out.create_group("map");
    const auto names = map_column_names();
    const auto units = map_column_units();
    for (std::size_t c = 0; c < names.size(); ++c) {
      Eigen::VectorXd column(rows.size());
      for (std::size_t i = 0; i < rows.size(); ++i) column[i] = map_row_values(rows[i])[c];
      map.write(names[c], column);
      map.set_attribute("units", units[c], names[c]);
    }
    map.write("columns", names);
    // Both outputs are written in full before either is renamed into place: a failure leaves neither.
    std::optional<TextOutput> csv;
    if (!csv_file.empty()) csv.emplace(write_csv(csv_file, rows));
    file.commit();
    if (csv) csv->commit();
    log.info("wrote " + output_file + (csv_file.empty() ? "" : " and " + csv_file));
    return 0;
  } catch (const Interrupted& e) {
    log.error(e.what());
    return static_cast<int>(ExitCode::kInterrupted);
  } catch (const Error& e) {
    log.error(e.what());
    return static_cast<int>(ExitCode::kFailure);
  }
}

}  // namespace nvh::bearing
