// Nastran DMIG export of a superelement (condense/matrix_export.hpp; format: docs/matrix-export.md).
//
// Card layouts, from the Nastran Quick Reference Guide (QRG), Bulk Data section, in large-field format
// (QRG "Format of Bulk Data Entries": a keyword with '*', 16-character fields, each small-field line of
// fields 2-9 split over two lines of four fields, continuation lines starting with '*'):
//
//   DMIG header   DMIG* | NAME | "0" | IFO | TIN  ||  *  | TOUT | POLAR | (blank) | NCOL
//   DMIG column   DMIG* | NAME | GJ  | CJ  |      ||  *  | G1 | C1 | A1 | B1  ||  * | G2 | C2 | A2 | B2 ...
//   GRID          GRID* | ID   | CP  | X1  | X2   ||  *  | X3 | CD | PS | SEID
//   SPOINT        SPOINT  ID1  THRU  ID2          (small field)
//
// DMIG: IFO = 6 symmetric, TIN = 2 real double precision, TOUT = 0 (precision of the run), POLAR and
// NCOL blank (not used for IFO = 6). One column entry per column j with nonzero terms, holding the terms
// (Gi, Ci, Ai) of rows i <= j (the upper triangle): for a symmetric matrix the QRG lets either triangle
// be given but not a term and its transpose both. Bi (imaginary part) is blank for real matrices. For a
// scalar point the component is 0. Integers and names are left-justified in their fields, reals
// right-justified (data may sit anywhere in a fixed-format field); reals take all 16 characters when that
// buys digits (nastran_real16).
#include "condense/matrix_export.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ostream>
#include <set>
#include <sstream>

#include "common/error.hpp"

namespace nvh::condense {
namespace {

constexpr int kMaxId = 99999999;  // QRG: grid and scalar point ids 0 < ID < 100,000,000
constexpr std::array<const char*, 6> kDofSuffix = {"x", "y", "z", "rx", "ry", "rz"};

/// "1.2345e+06" -> mantissa "1.2345" and exponent 6, from printf's %.*e.
std::string scientific(double value, int digits, char letter) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.*e", digits - 1, value);
  const std::string s(buffer);
  const std::size_t e = s.find('e');
  std::string mantissa = s.substr(0, e);
  if (mantissa.find('.') == std::string::npos) mantissa += '.';
  const int exponent = std::atoi(s.c_str() + e + 1);
  return mantissa + letter + (exponent < 0 ? '-' : '+') + std::to_string(std::abs(exponent));
}

double parse_real(std::string text, char letter) {
  std::replace(text.begin(), text.end(), letter, 'e');
  return std::strtod(text.c_str(), nullptr);
}

std::string right(const std::string& text, std::size_t width) {
  return text.size() >= width ? text : std::string(width - text.size(), ' ') + text;
}

std::string left(const std::string& text, std::size_t width) {
  return text.size() >= width ? text : text + std::string(width - text.size(), ' ');
}

/// Writes one bulk data entry in large-field format: the keyword with '*' in an 8-character field, then
/// 16-character fields four to a line, continuation lines starting with '*'. An entry fills whole
/// small-field lines (fields 2-9 = two large-field lines), so a last half line is written blank.
class LargeFieldEntry {
 public:
  LargeFieldEntry(std::ostream& out, const std::string& keyword) : out_(out) {
    line_ = left(keyword + "*", 8);
  }
  ~LargeFieldEntry() { finish(); }
  LargeFieldEntry(const LargeFieldEntry&) = delete;
  LargeFieldEntry& operator=(const LargeFieldEntry&) = delete;

  void text(const std::string& s) { put(left(s, 16)); }  // names: left-justified
  void number(const std::string& s) { put(right(s, 16)); }
  void integer(long long v) { text(std::to_string(v)); }  // left-justified: set apart from a 16-digit real
  void real(double v, char letter = 'D') { number(nastran_real16(v, letter)); }
  void blank() { put(std::string(16, ' ')); }

 private:
  void put(const std::string& field) {
    if (field.size() != 16)
      throw Error("internal: a large field of " + std::to_string(field.size()) + " characters");
    if (in_line_ == 4) {
      flush();
      line_ = "*       ";
      in_line_ = 0;
    }
    line_ += field;
    ++in_line_;
  }
  void flush() {
    const std::size_t end = line_.find_last_not_of(' ');
    out_ << line_.substr(0, end + 1) << '\n';
    ++lines_;
  }
  void finish() {
    flush();
    if (lines_ % 2 == 1) out_ << "*\n";
  }

  std::ostream& out_;
  std::string line_;
  int in_line_ = 0;
  int lines_ = 0;
};

/// The interface name and component (1..6) of a coordinate "NAME.x" ... "NAME.rz" whose NAME is an
/// interface; component 0 for any other coordinate.
std::pair<std::string, int> interface_dof(const std::string& coordinate,
                                          const std::set<std::string>& interfaces) {
  const std::size_t dot = coordinate.rfind('.');
  if (dot == std::string::npos) return {"", 0};
  const std::string name = coordinate.substr(0, dot), suffix = coordinate.substr(dot + 1);
  if (!interfaces.contains(name)) return {"", 0};
  for (int d = 0; d < 6; ++d)
    if (suffix == kDofSuffix[d]) return {name, d + 1};
  return {"", 0};
}

/// The node whose DOF the coordinates NAME.* are. For an interface on a rigid-link end they are the DOF of
/// the link's master station, and the interface point p moves by theta x r for a unit master rotation
/// theta (r = point - master, docs/hdf5-format.md): the translations of p per unit rx, ry, rz give r,
///   rx: (0, -r_z, r_y)   ry: (r_z, 0, -r_x)   rz: (-r_y, r_x, 0),
/// each component from the first rotation that is a coordinate (r = 0 when none is: then only translations
/// are coordinates, and the offset has no effect on them).
Eigen::Vector3d grid_position(const SuperelementFile& se, int point, const std::array<int, 6>& column) {
  const Eigen::MatrixXd& shape = se.interfaces.shapes[point];
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  std::array<bool, 3> known{};
  auto take = [&](int axis, int dof, int row, double sign) {
    if (known[axis] || column[dof] < 0) return;
    r(axis) = sign * shape(row, column[dof]);
    known[axis] = true;
  };
  take(2, 3, 1, -1.0);  // rx: uy = -r_z
  take(1, 3, 2, 1.0);   // rx: uz = r_y
  take(2, 4, 0, 1.0);   // ry: ux = r_z
  take(0, 4, 2, -1.0);  // ry: uz = -r_x
  take(1, 5, 0, -1.0);  // rz: ux = -r_y
  take(0, 5, 1, 1.0);   // rz: uy = r_x
  return se.interfaces.position.row(point).transpose() - r;
}

void check_id(long long id, const std::string& what) {
  if (id < 1 || id > kMaxId) {
    throw Error(what + " id " + std::to_string(id) + " is outside 1.." + std::to_string(kMaxId) +
                " (Nastran point ids; see --first-grid, --first-spoint, --grid)");
  }
}

/// Text for a '$' comment line: a control character (a newline in a name) would end the comment and put
/// the rest of the line into the bulk data, so each becomes '?'.
std::string comment_safe(std::string s) {
  for (char& c : s)
    if (std::iscntrl(static_cast<unsigned char>(c))) c = '?';
  return s;
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

std::string format_g(double v, int digits = 10) {
  std::ostringstream s;
  s.precision(digits);
  s << v;
  return s.str();
}

std::string components_text(const std::vector<int>& components) {
  std::string s;
  for (int c : components) s += std::to_string(c);
  return s;
}

/// Check that `a` is finite and symmetric to 1e-10 of its largest entry; name the matrix otherwise.
void check_symmetric(const ExportedMatrix& m) {
  const Eigen::MatrixXd& a = *m.matrix;
  if (!a.allFinite())
    throw Error(m.name + " (" + m.description + "): has entries that are not finite numbers");
  const double scale = a.cwiseAbs().maxCoeff();
  const double asymmetry = (a - a.transpose()).cwiseAbs().maxCoeff();
  if (asymmetry > 1e-10 * scale) {
    throw Error(m.name + " (" + m.description + "): not symmetric (largest |a_ij - a_ji| = " +
                format_g(asymmetry, 3) + " against largest entry " + format_g(scale, 3) +
                "); a symmetric DMIG (IFO = 6) needs it symmetric");
  }
}

void write_header(std::ostream& out, const SuperelementFile& se, const NastranExportOptions& options,
                  const NastranLayout& layout, const std::vector<ExportedMatrix>& matrices) {
  const int n = se.size();
  // Fixed text within 80 columns (the QRG's card image); names and paths may make a line longer.
  out << "$ Nastran bulk data: the reduced matrices of a superelement as DMIG entries\n";
  out << "$   superelement \"" << comment_safe(se.name) << "\"";
  if (!options.source.empty()) out << ", file " << comment_safe(options.source);
  out << "\n";
  if (!options.source_sha256.empty()) out << "$   sha256 " << options.source_sha256 << "\n";
  out << "$   written by " << (options.tool_version.empty() ? "condense" : options.tool_version)
      << " (condense export --format nastran)\n";
  out << "$ layout: docs/matrix-export.md; cards per the Nastran Quick Reference Guide\n"
         "$   (DMIG, GRID, SPOINT), large-field format, reals with D exponents (double)\n";
  out << "$ units: SI (kg, m, s, N, rad); an entry has the units of its two coordinates:\n"
         "$   interface translation [m], rotation [rad]: K in N/m, N m/rad;\n"
         "$     M in kg, kg m^2; B in N s/m, N m s/rad\n"
         "$   mass-normalized mode [sqrt(kg) m]: K in rad^2/s^2, M in 1, B in 1/s\n"
         "$   mixed entries: the products\n";
  out << "$ basic coordinate system = the component frame; positions in m\n";
  out << "$ method " << se.method << (se.orthonormalized ? ", orthonormalized" : ", raw basis") << ", " << n
      << " coordinates\n";
  out << "$   rigid-body modes: " << se.rigid_body_modes_contained << " contained in (K, M), "
      << se.rigid_body_modes_removed << " removed (floating frame)\n";
  out << "$ matrices: symmetric (IFO 6), real double (TIN 2), upper triangle, no zeros\n";
  for (const ExportedMatrix& m : matrices) out << "$   " << left(m.name, 8) << " " << m.description << "\n";
  out << "$ to use them in Nastran: INCLUDE this file in the bulk data; case control:\n";
  for (const ExportedMatrix& m : matrices) {
    if (m.name[0] == 'K') out << "$   K2GG = " << m.name << "\n";
    if (m.name[0] == 'M') out << "$   M2GG = " << m.name << "\n";
    if (m.name[0] == 'B') out << "$   B2GG = " << m.name << "\n";
  }
  if (!options.grid_cards) out << "$ no GRID and SPOINT entries (--no-grid-cards): the deck defines them\n";

  out << "$ interfaces (/interface/name): GRID id, position [m] of the node whose DOF\n"
         "$   they are, components\n";
  std::set<std::string> gridded;
  for (const NastranGrid& g : layout.grids) {
    gridded.insert(g.interface);
    out << "$   " << left(comment_safe(g.interface), 16) << " GRID " << right(std::to_string(g.id), 8)
        << "   " << format_g(g.position(0)) << " " << format_g(g.position(1)) << " "
        << format_g(g.position(2)) << "   " << components_text(g.components) << "\n";
  }
  for (const std::string& name : se.interfaces.names) {
    if (gridded.contains(name)) continue;
    out << "$   " << left(comment_safe(name), 16) << " no GRID: "
        << (se.orthonormalized || se.method == "modal"
                ? "modal basis (motion in /interface/shape)"
                : "no coordinates (supported, or an earlier one's node)")
        << "\n";
  }
  out << "$ coordinates (q_j, /reduced/coordinates) -> DOF:\n";
  for (int j = 0; j < n; ++j) {
    const NastranDof& d = layout.dofs[j];
    out << "$   " << right(std::to_string(j + 1), 5) << "  " << left(comment_safe(se.coordinates[j]), 28)
        << " -> "
        << (d.component > 0 ? "GRID " + std::to_string(d.id) + " component " + std::to_string(d.component)
                            : "SPOINT " + std::to_string(d.id))
        << "\n";
  }
  out << "$ elastic eigenfrequencies of (K, M) [Hz], /modes/frequency_hz:\n";
  for (Eigen::Index i = 0; i < se.frequency_hz.size(); ++i)
    out << "$   " << right(std::to_string(i + 1), 5) << "  " << format_g(se.frequency_hz(i), 12) << "\n";
}

}  // namespace

std::string nastran_real16(double value, char exponent_letter) {
  if (!std::isfinite(value)) throw Error("cannot write " + format_g(value) + " as a Nastran real number");
  if (value == 0.0) return "0.0";
  std::string best;
  for (int digits = 2; digits <= 17; ++digits) {
    const std::string s = scientific(value, digits, exponent_letter);
    if (s.size() > 16) continue;  // rounding may shorten the exponent at more digits: keep trying
    best = s;
    if (parse_real(s, exponent_letter) == value) break;  // the shortest exact form
  }
  if (best.empty()) throw Error("cannot write " + format_g(value) + " in a 16-character Nastran field");
  return best;
}

NastranLayout nastran_layout(const SuperelementFile& se, const NastranExportOptions& options) {
  const int n = se.size();
  const int points = static_cast<int>(se.interfaces.names.size());
  const std::set<std::string> names(se.interfaces.names.begin(), se.interfaces.names.end());
  for (const auto& [name, id] : options.grid_ids) {
    if (!names.contains(name)) {
      std::string known;
      for (const std::string& s : se.interfaces.names) known += (known.empty() ? "" : ", ") + s;
      throw Error("--grid " + name + "=" + std::to_string(id) + ": the superelement has no interface '" +
                  name + "' (its interfaces: " + (known.empty() ? "none" : known) + ")");
    }
  }
  auto grid_id = [&](int p) {
    const auto it = options.grid_ids.find(se.interfaces.names[p]);
    return it != options.grid_ids.end() ? static_cast<long long>(it->second)
                                        : static_cast<long long>(options.first_grid) + p;
  };

  NastranLayout layout;
  layout.dofs.resize(n);
  // column[p][d]: the coordinate that is DOF d of interface p, or -1.
  std::vector<std::array<int, 6>> column(points);
  for (auto& c : column) c.fill(-1);
  std::map<std::string, int> index;
  for (int p = 0; p < points; ++p) index.emplace(se.interfaces.names[p], p);  // the first of equal names
  long long spoint = options.first_spoint;
  for (int j = 0; j < n; ++j) {
    const auto [name, component] = interface_dof(se.coordinates[j], names);
    if (component > 0) {
      const int p = index.at(name);
      if (column[p][component - 1] >= 0) {
        throw Error("coordinates " + std::to_string(column[p][component - 1] + 1) + " and " +
                    std::to_string(j + 1) + " are both '" + se.coordinates[j] + "'");
      }
      column[p][component - 1] = j;
      check_id(grid_id(p), "GRID");
      layout.dofs[j] = {static_cast<int>(grid_id(p)), component};
    } else {
      check_id(spoint, "SPOINT");
      layout.dofs[j] = {static_cast<int>(spoint), 0};
      layout.spoints.push_back(static_cast<int>(spoint));
      ++spoint;
    }
  }
  for (int p = 0; p < points; ++p) {
    NastranGrid g;
    for (int d = 0; d < 6; ++d)
      if (column[p][d] >= 0) g.components.push_back(d + 1);
    if (g.components.empty()) continue;
    g.interface = se.interfaces.names[p];
    g.id = static_cast<int>(grid_id(p));
    g.position = grid_position(se, p, column[p]);
    layout.grids.push_back(g);
  }
  // One id space for grid and scalar points (QRG: GRID and SPOINT ids must be unique together).
  std::map<int, std::string> owner;
  for (const NastranGrid& g : layout.grids) {
    const auto [it, fresh] = owner.emplace(g.id, "GRID of interface '" + g.interface + "'");
    if (!fresh)
      throw Error("id " + std::to_string(g.id) + " is given to both the " + it->second +
                  " and the GRID of interface '" + g.interface +
                  "'; choose other ids (--grid, --first-grid)");
  }
  for (int id : layout.spoints) {
    const auto it = owner.find(id);
    if (it != owner.end()) {
      throw Error("id " + std::to_string(id) + " is given to both the " + it->second +
                  " and an SPOINT of a modal coordinate; move the SPOINTs (--first-spoint) or the GRIDs");
    }
  }
  return layout;
}

std::vector<ExportedMatrix> exported_matrices(const SuperelementFile& se, const std::string& name_suffix) {
  const std::string suffix = upper(name_suffix);
  const bool valid = !suffix.empty() && suffix.size() <= 5 &&
                     std::all_of(suffix.begin(), suffix.end(),
                                 [](char c) { return std::isalnum(static_cast<unsigned char>(c)); });
  if (!valid) {
    throw Error("matrix name suffix '" + name_suffix +
                "': expected 1 to 5 letters or digits (DMIG names are at most 8 characters: "
                "K<suffix>, G<xx><suffix>)");
  }
  std::vector<ExportedMatrix> m;
  m.push_back({"K" + suffix, "stiffness K_r, /reduced/stiffness", &se.stiffness});
  m.push_back({"M" + suffix, "mass M_r, /reduced/mass", &se.mass});
  if (se.damping.size() > 0 && se.damping.cwiseAbs().maxCoeff() > 0.0) {
    m.push_back({"B" + suffix,
                 "viscous damping D_r, /reduced/damping (modal, zeta = " + format_g(se.damping_ratio) + ")",
                 &se.damping});
  }
  for (std::size_t p = 0; p < se.geometric_stiffness.size(); ++p) {
    const std::string product = kSpinProductNames[p];
    std::string name = "G";
    name += upper(product);
    name += suffix;
    std::string what = "K_G of w_";
    what += product.substr(0, 1) + " w_" + product.substr(1, 1) +
            " per (rad/s)^2, /reduced/geometric_stiffness/" + product;
    m.push_back({name, what, &se.geometric_stiffness[p]});
  }
  return m;
}

void write_nastran_dmig(std::ostream& out, const SuperelementFile& se, const NastranExportOptions& options) {
  const int n = se.size();
  if (n == 0) throw Error("the superelement has no coordinates: nothing to export");
  const NastranLayout layout = nastran_layout(se, options);
  const std::vector<ExportedMatrix> matrices = exported_matrices(se, options.name_suffix);
  for (const ExportedMatrix& m : matrices) check_symmetric(m);

  write_header(out, se, options, layout, matrices);

  if (options.grid_cards) {
    out << "$\n$ interface grid points (basic system = component frame, m)\n";
    for (const NastranGrid& g : layout.grids) {
      LargeFieldEntry grid(out, "GRID");
      grid.integer(g.id);
      grid.blank();  // CP: basic
      grid.real(g.position(0), 'E');
      grid.real(g.position(1), 'E');
      grid.real(g.position(2), 'E');
      // CD, PS, SEID blank: displacements in the basic system, no permanent constraints.
    }
    if (!layout.spoints.empty()) {
      out << "$ scalar points of the modal coordinates\n";
      // Consecutive ids: one SPOINT ID1 THRU ID2 entry (QRG SPOINT, alternate format).
      char line[81];
      if (layout.spoints.size() == 1) {
        std::snprintf(line, sizeof line, "SPOINT  %8d\n", layout.spoints.front());
      } else {
        std::snprintf(line, sizeof line, "SPOINT  %8dTHRU    %8d\n", layout.spoints.front(),
                      layout.spoints.back());
      }
      out << line;
    }
  }

  for (const ExportedMatrix& m : matrices) {
    const Eigen::MatrixXd& a = *m.matrix;
    out << "$\n$ " << m.name << ": " << m.description << "\n";
    {
      LargeFieldEntry header(out, "DMIG");
      header.text(m.name);
      header.integer(0);  // "0": the header entry
      header.integer(6);  // IFO: symmetric
      header.integer(2);  // TIN: real, double precision
      header.integer(0);  // TOUT: the precision of the run
      // POLAR, NCOL: blank
    }
    // The symmetric part: a(i, j) and a(j, i) agree to round-off (check_symmetric).
    auto entry = [&a](int i, int j) { return i == j ? a(i, j) : 0.5 * (a(i, j) + a(j, i)); };
    for (int j = 0; j < n; ++j) {
      bool any = false;
      for (int i = 0; i <= j && !any; ++i) any = entry(i, j) != 0.0;
      if (!any) continue;  // QRG: a column entry for each column with nonzero terms
      LargeFieldEntry column(out, "DMIG");
      column.text(m.name);
      column.integer(layout.dofs[j].id);
      column.integer(layout.dofs[j].component);
      column.blank();
      for (int i = 0; i <= j; ++i) {
        const double value = entry(i, j);
        if (value == 0.0) continue;
        column.integer(layout.dofs[i].id);
        column.integer(layout.dofs[i].component);
        column.real(value);
        column.blank();  // Bi: real matrix
      }
    }
  }
  if (!out) throw Error("writing the Nastran bulk data failed");
}

}  // namespace nvh::condense
