#pragma once
// CalculiX (ccx 2.20, Debian's calculix-ccx) as the outside reference of the volume tests: the steel bar both
// tools solve, CalculiX's *FREQUENCY run on it and its frequencies read from the job's .dat file.
#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "condense/component.hpp"

namespace nvh::condense::testing {

/// The steel bar (E 210 GPa, nu 0.3, rho 7850 kg/m^3) of the mesh file `mesh` as a volume component, modal by
/// `modes`; `clamped`: held in x, y, z on its face x = 0 (the node set NFIX of the ccx job).
inline Component steel_bar(const std::filesystem::path& mesh, bool clamped, int modes,
                           bool mass_like_calculix) {
  Component c;
  c.name = "bar";
  c.kind = "volume";
  c.materials["steel"] = Material{"steel", 210e9, 0.3, 7850.0};
  c.volume.mesh = mesh;
  c.volume.material = "steel";
  c.volume.mass_like_calculix = mass_like_calculix;
  if (clamped) {
    Support clamp;
    clamp.box = std::array<double, 6>{-1e-9, -1, -1, 1e-9, 1, 1};
    clamp.dofs = {true, true, true, false, false, false};
    c.supports = {clamp};
  }
  c.reduction.method = ReductionMethod::kModal;
  c.reduction.modes = modes;
  return c;
}

/// CalculiX's `modes` lowest frequencies (Hz) of the same bar: `dir`/bar.inp (elements in `elset`, the
/// clamped nodes in NFIX, or free without `clamped`: its 6 rigid-body modes first), one thread. Empty if ccx
/// failed (its log: `dir`/ccx.log).
inline std::vector<double> ccx_bar_frequencies(const std::filesystem::path& dir, const std::string& elset,
                                               int modes, bool clamped = true);

/// Frequencies (Hz) from ccx's job.dat: the rows under "E I G E N V A L U E   O U T P U T" are
/// "mode  eigenvalue  omega[rad/s]  f[Hz]  imaginary".
inline std::vector<double> ccx_frequencies(const std::filesystem::path& dat) {
  std::ifstream in(dat);
  std::string line;
  bool table = false;
  std::vector<double> f;
  while (std::getline(in, line)) {
    if (line.find("E I G E N V A L U E   O U T P U T") != std::string::npos) {
      table = true;
      continue;
    }
    if (!table) continue;
    std::istringstream row(line);
    int mode = 0;
    double eigenvalue = 0, omega = 0, hz = 0;
    if (row >> mode >> eigenvalue >> omega >> hz) {
      f.push_back(hz);
    } else if (!f.empty()) {
      break;  // end of the table
    }
  }
  return f;
}

inline std::vector<double> ccx_bar_frequencies(const std::filesystem::path& dir, const std::string& elset,
                                               int modes, bool clamped) {
  std::ofstream(dir / "job.inp")
      << "*INCLUDE, INPUT=bar.inp\n*MATERIAL, NAME=STEEL\n*ELASTIC\n210000000000., 0.3\n"
      << "*DENSITY\n7850.\n*SOLID SECTION, ELSET=" << elset << ", MATERIAL=STEEL\n"
      << (clamped ? "*BOUNDARY\nNFIX, 1, 3\n" : "") << "*STEP\n*FREQUENCY\n"
      << modes << "\n*END STEP\n";
  const std::string command = "cd " + dir.string() + " && OMP_NUM_THREADS=1 ccx -i job > ccx.log 2>&1";
  if (std::system(command.c_str()) != 0) return {};
  return ccx_frequencies(dir / "job.dat");
}

}  // namespace nvh::condense::testing
