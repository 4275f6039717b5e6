#pragma once
// The superelement's reduced matrices written for another program: Nastran DMIG bulk data (Direct Matrix
// Input at Grid points), the form in which Nastran itself exports a reduced component (EXTSEOUT,
// PARAM,EXTOUT,DMIGPCH) and which tools that import Nastran superelements read. The card layouts follow
// the MSC/NX Nastran Quick Reference Guide (QRG), Bulk Data entries DMIG, GRID and SPOINT; the format as
// written here (ids, names, precision, an example) is documented in docs/matrix-export.md.
//
// Input is the file contract (common/superelement.hpp: what is in the .h5), so any superelement file can
// be exported, not only the one a run has just made. Units stay SI (kg, m, s, N, rad) as in the file.
//
// The coordinates q_j of the superelement become the DOF of the Nastran deck:
//   - an interface DOF coordinate "NAME.x" ... "NAME.rz" (raw Craig-Bampton and Guyan bases) is component
//     1 ... 6 of the GRID point of interface NAME: id first_grid + p, p its 0-based index in
//     /interface/name (or the id given in grid_ids);
//   - every other coordinate (modes, fixed-interface modes, residual modes) is a scalar point (SPOINT),
//     id first_spoint + k for the k-th such coordinate in coordinate order, component 0.
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "common/superelement.hpp"

namespace nvh::condense {

struct NastranExportOptions {
  int first_grid = 1;                   ///< GRID id of interface 0 (interface p gets first_grid + p)
  int first_spoint = 100001;            ///< SPOINT id of the first coordinate that is not an interface DOF
  std::map<std::string, int> grid_ids;  ///< interface name -> GRID id, replacing first_grid + p
  std::string name_suffix = "AAX";      ///< matrix names: K<suffix>, M<suffix>, B<suffix>, G<xx><suffix>
  bool grid_cards = true;               ///< write GRID and SPOINT cards (false: the deck defines them)
  std::string source;                   ///< the superelement file's name, for the header comment
  std::string source_sha256;            ///< its SHA-256, for the header comment (empty: not written)
  std::string tool_version;             ///< e.g. "condense 0.1.0", for the header comment
};

/// One DOF of the Nastran deck: component 1..6 of a GRID point, or a scalar point (component 0).
struct NastranDof {
  int id = 0;
  int component = 0;
  bool operator==(const NastranDof&) const = default;
};

/// A GRID point of the deck: an interface whose DOF are coordinates.
struct NastranGrid {
  std::string interface;     ///< /interface/name
  int id = 0;                ///< GRID id
  Eigen::Vector3d position;  ///< m, component frame (= Nastran's basic system): the node whose DOF they are
  std::vector<int> components;  ///< the components (1..6) that are coordinates, ascending
};

/// How the superelement's coordinates map to the deck's DOF.
struct NastranLayout {
  std::vector<NastranDof> dofs;  ///< per coordinate q_j
  std::vector<NastranGrid> grids;
  std::vector<int> spoints;  ///< ids of the scalar points, in coordinate order
};

/// The mapping of the coordinates to GRID components and SPOINTs (rules in the file comment). nvh::Error
/// if an id is outside 1..99999999, ids collide, or grid_ids names an interface the file does not have.
NastranLayout nastran_layout(const SuperelementFile& se, const NastranExportOptions& options);

/// A matrix of the export: its DMIG name, what it is, and the matrix (n x n, symmetric).
struct ExportedMatrix {
  std::string name;         ///< e.g. "KAAX"
  std::string description;  ///< e.g. "stiffness K_r, /reduced/stiffness"
  const Eigen::MatrixXd* matrix = nullptr;
};

/// The matrices written: stiffness, mass, damping (if not all zero), geometric stiffness (if present).
std::vector<ExportedMatrix> exported_matrices(const SuperelementFile& se, const std::string& name_suffix);

/// Write the Nastran bulk data (header comments, GRID, SPOINT, one symmetric DMIG per matrix) to `out`.
/// Every matrix must be symmetric to 1e-10 of its largest entry (its upper triangle is written) and
/// finite; nvh::Error otherwise.
void write_nastran_dmig(std::ostream& out, const SuperelementFile& se, const NastranExportOptions& options);

/// A real number in a Nastran large field (16 characters): the fewest significant digits that read back
/// as exactly `value`, or if none fits, the most that fit (>= 10 for |exponent| < 100: relative error at
/// most 5e-10); always a decimal point and an exponent with `exponent_letter`, e.g. "-1.234567890D+10",
/// "1.0D+0", "0.0". 'D' marks double precision (DMIG with TIN = 2), 'E' single (GRID coordinates).
std::string nastran_real16(double value, char exponent_letter = 'D');

}  // namespace nvh::condense
