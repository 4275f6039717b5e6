// `condense export SUPERELEMENT.h5 -o OUT.pch`: the reduced matrices as Nastran DMIG bulk data.
#include "condense/export_command.hpp"

#include <CLI/CLI.hpp>
#include <iostream>
#include <sstream>

#include "common/error.hpp"
#include "common/log.hpp"
#include "common/output_path.hpp"
#include "common/sha256.hpp"
#include "common/superelement.hpp"
#include "common/version.hpp"
#include "condense/matrix_export.hpp"

namespace nvh::condense {
namespace {

constexpr const char* kExportDescription =
    R"(condense export - write a superelement's reduced matrices for another program

Reads a superelement file written by condense (docs/hdf5-format.md) and writes its reduced stiffness,
mass and damping (and the geometric stiffness matrices, if the file has them) as Nastran bulk data:
symmetric DMIG matrices KAAX, MAAX, BAAX (GXXAAX ... GZXAAX) in large-field format, real double
precision, upper triangle; GRID entries for the interface points and SPOINTs for the modal
coordinates. INCLUDE the file in a Nastran bulk data section and select the matrices in case control
with K2GG = KAAX, M2GG = MAAX, B2GG = BAAX. The layout is documented in docs/matrix-export.md.

What the ids mean:
  GRID    an interface DOF coordinate NAME.x .. NAME.rz (raw Craig-Bampton or Guyan basis) is
          component 1..6 (x y z rx ry rz in component axes) of the GRID of interface NAME, id
          FIRST_GRID + p for the p-th interface of /interface/name (0-based), or the id of --grid
  SPOINT  every other coordinate (modes, fixed-interface modes, residual modes) is a scalar point:
          FIRST_SPOINT, FIRST_SPOINT + 1, ... in coordinate order
The header comments of the file list every coordinate with its id, the interfaces with their GRID
positions, and the eigenfrequencies. A modal or orthonormalized file has no interface DOF among its
coordinates: all are SPOINTs, and the interface motion (/interface/shape) is not exported.
Units: SI as in the .h5 (kg, m, s, N, rad). K is in N/m and N m/rad on interface DOF and in rad^2/s^2
on mass-normalized modes, M in kg, kg m^2 or 1 (mixed entries: the products); GRID positions are in m
in the component frame, Nastran's basic system.
Precision: a 16-character field holds 10 to 12 significant digits (relative rounding at most 5e-10,
the shortest exact form when it fits); the .h5 stays the exact form.

Examples:
  condense crankshaft.toml -o crankshaft.h5
  condense export crankshaft.h5 -o crankshaft.pch
  condense export crank.h5 -o crank.pch --first-grid 1001 --first-spoint 900001 --grid main1=501

Exit codes: 0 success; 1 bad input (the message names the file and what was expected) or failed write;
2 bad command line; 3 interrupted (the temporary output is removed). The output is written to a
temporary beside it and renamed when complete.)";

/// "NAME=ID" of --grid.
std::pair<std::string, int> parse_grid_option(const std::string& text) {
  const std::size_t eq = text.rfind('=');
  const std::string name = eq == std::string::npos ? "" : text.substr(0, eq);
  const std::string id = eq == std::string::npos ? "" : text.substr(eq + 1);
  std::size_t used = 0;
  long long value = 0;
  try {
    value = std::stoll(id, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (name.empty() || id.empty() || used != id.size() || value < 1 || value > 99999999) {
    throw CLI::ValidationError(
        "--grid", "'" + text + "': expected NAME=ID, an interface name and a GRID id 1..99999999");
  }
  return {name, static_cast<int>(value)};
}

}  // namespace

int run_export_command(int argc, char** argv) {
  CLI::App app{kExportDescription, "condense export"};
  app.get_formatter()->column_width(34);
  std::string input, output, format = "nastran", suffix = "AAX";
  std::vector<std::string> grids;
  NastranExportOptions options;
  bool quiet = false, no_grid_cards = false;
  app.add_option("SUPERELEMENT", input, "superelement file written by condense (.h5)")->required();
  app.add_option("-o,--output", output,
                 "file to write (e.g. .pch or .bdf); written to a temporary and renamed when complete")
      ->required();
  app.add_option("--format", format,
                 "export format: nastran (DMIG bulk data; the default and only one so far)")
      ->check(CLI::IsMember({"nastran"}));
  app.add_option("--first-grid", options.first_grid,
                 "GRID id of the first interface; interface p gets this + p (default 1)")
      ->check(CLI::Range(1, 99999999));
  app.add_option("--first-spoint", options.first_spoint,
                 "SPOINT id of the first modal coordinate, the next ones follow (default 100001)")
      ->check(CLI::Range(1, 99999999));
  app.add_option("--grid", grids,
                 "NAME=ID: the GRID id of interface NAME (repeatable), replacing first-grid + p");
  app.add_option(
      "--suffix", suffix,
      "matrix name suffix, 1-5 letters or digits: K<suffix>, M<suffix>, B<suffix> (default AAX: KAAX, ...)");
  app.add_flag("--no-grid-cards", no_grid_cards,
               "do not write GRID and SPOINT entries (the deck that includes the file defines them)");
  app.add_flag("-q,--quiet", quiet, "print errors only");
  app.set_version_flag("--version", std::string("condense ") + kVersion);
  try {
    // argv[0] is "export": CLI11 takes it as the program name.
    app.parse(argc, argv);
    for (const std::string& g : grids) {
      const auto [name, id] = parse_grid_option(g);
      if (!options.grid_ids.emplace(name, id).second) {
        throw CLI::ValidationError("--grid", "interface '" + name + "' is given twice");
      }
    }
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : static_cast<int>(ExitCode::kUsage);
  }

  const Logger log(std::cerr, "condense", quiet ? Verbosity::kQuiet : Verbosity::kNormal);
  try {
    check_outputs_are_not_inputs({output}, {input});
    check_output_writable(output);
    const SuperelementFile se = read_superelement(input);
    options.name_suffix = suffix;
    options.grid_cards = !no_grid_cards;
    options.source = input;
    options.source_sha256 = sha256_file(input);
    options.tool_version = std::string("condense ") + kVersion;
    const NastranLayout layout = nastran_layout(se, options);
    const std::vector<ExportedMatrix> matrices = exported_matrices(se, suffix);

    TextOutput text(output);
    write_nastran_dmig(text.stream(), se, options);
    text.commit();

    std::ostringstream summary;
    summary << "wrote " << output << ": Nastran DMIG";
    for (const ExportedMatrix& m : matrices) summary << " " << m.name;
    summary << " (" << se.size() << " x " << se.size() << ", " << se.method
            << (se.orthonormalized ? ", orthonormalized" : "") << ")";
    if (!layout.grids.empty()) {
      summary << "; GRID";
      for (const NastranGrid& g : layout.grids) summary << " " << g.interface << "=" << g.id;
    }
    if (!layout.spoints.empty()) {
      summary << "; SPOINT " << layout.spoints.front();
      if (layout.spoints.size() > 1) summary << " THRU " << layout.spoints.back();
    }
    log.info(summary.str());
    if (layout.grids.empty() && !se.interfaces.names.empty()) {
      log.warning(
          input + ": the coordinates are modal (" + se.method +
          (se.orthonormalized ? ", orthonormalized" : "") +
          "): no interface DOF among them, so the matrices connect to no GRID point; for a Craig-Bampton "
          "superelement to connect at its interfaces, condense with method = \"craig-bampton\" and "
          "orthonormalize = false");
    }
    return static_cast<int>(ExitCode::kSuccess);
  } catch (const Error& e) {
    log.error(e.what());
    return static_cast<int>(ExitCode::kFailure);
  } catch (const std::exception& e) {
    log.error(std::string("unexpected failure: ") + e.what());
    return static_cast<int>(ExitCode::kFailure);
  }
}

}  // namespace nvh::condense
