// Nastran DMIG export (condense/matrix_export.hpp, docs/matrix-export.md): round trips through the text.
//
// A component is condensed, written to the superelement file and read back through the contract
// (read_superelement: what `condense export` reads), exported, and the DMIG text parsed again by a reader
// written here from the Nastran Quick Reference Guide's card layouts (large-field DMIG, GRID, SPOINT), not
// from the writer. The coordinates are mapped back by the documented numbering rule (interface p:
// GRID first_grid + p; every other coordinate: the next SPOINT), re-implemented here.
//
// Tolerances. A 16-character field holds 10 to 12 significant digits, so an entry reads back within half
// a unit of its 10th digit: relative 5e-10. Eigenfrequencies of the re-read (K, M): for mass-orthonormal
// coordinates (M = I, K diagonal) the rounding of an entry moves lambda by as much, so 1e-9 relative; for
// the raw Craig-Bampton basis the frequencies are bounded by the first-order perturbation of the rounded
// entries, |d lambda| <= eps x^T (|K| + lambda |M|) x with |x| the entry-wise absolute mode (x^T M x = 1),
// and the test asserts that bound (factor 2) and states the measured error.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Eigenvalues>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>

#include "beam_fixtures.hpp"
#include "common/error.hpp"
#include "common/log.hpp"
#include "common/provenance.hpp"
#include "condense/condense.hpp"
#include "condense/matrix_export.hpp"

namespace nvh::condense {
namespace {

namespace fs = std::filesystem;
using namespace testing;

const Logger kQuiet{std::cerr, "test", Verbosity::kQuiet};

// ---------------------------------------------------------------------------------------------------------
// A reader of the large-field bulk data the export writes, from the QRG card layouts.

/// A Nastran real: "1.5D+3", "-2.0E-7", "7.+5" (exponent without a letter), ".5".
double nastran_real(std::string s) {
  const std::size_t b = s.find_first_not_of(' '), e = s.find_last_not_of(' ');
  s = s.substr(b, e - b + 1);
  for (char& c : s)
    if (c == 'D' || c == 'd') c = 'E';
  if (s.find('E') == std::string::npos && s.find('e') == std::string::npos) {
    const std::size_t sign = s.find_first_of("+-", 1);
    if (sign != std::string::npos) s.insert(sign, "E");
  }
  std::size_t used = 0;
  const double v = std::stod(s, &used);
  EXPECT_EQ(used, s.size()) << "not a Nastran real: '" << s << "'";
  return v;
}

std::string trim(const std::string& s) {
  const std::size_t b = s.find_first_not_of(' ');
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(' ') - b + 1);
}

using Dof = std::pair<int, int>;  // (point id, component; 0 for a scalar point)

struct Dmig {
  int ifo = 0, tin = 0;
  std::map<std::pair<Dof, Dof>, double> terms;  // (row, column) -> value, as written
};

struct Deck {
  std::map<std::string, Dmig> dmig;
  std::map<int, Eigen::Vector3d> grids;
  std::vector<int> spoints;
  int large_field_entries_with_odd_lines = 0;
  int lines_over_80 = 0;
};

/// Fields 2.. of an entry: large-field lines (keyword with '*', then '*' continuations) give four
/// 16-character fields each after the 8-character first field; small-field lines eight 8-character ones.
Deck parse_deck(const fs::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << path;
  std::vector<std::vector<std::string>> lines_of_entry;
  Deck deck;
  std::vector<std::pair<std::string, std::vector<std::string>>> entries;  // keyword, fields
  int lines_in_entry = 0;
  bool large = false;
  std::string line;
  auto close_entry = [&] {
    if (!entries.empty() && large && lines_in_entry % 2 == 1) ++deck.large_field_entries_with_odd_lines;
  };
  while (std::getline(in, line)) {
    if (line.size() > 80) ++deck.lines_over_80;  // comments too: short names keep them within 80
    if (line.empty() || line[0] == '$') continue;
    const bool continuation = line[0] == '*';
    if (!continuation) {
      close_entry();
      std::string keyword = trim(line.substr(0, 8));
      large = !keyword.empty() && keyword.back() == '*';
      if (large) keyword.pop_back();
      entries.push_back({keyword, {}});
      lines_in_entry = 0;
    }
    ++lines_in_entry;
    const int width = large ? 16 : 8, count = large ? 4 : 8;
    line.resize(8 + width * count, ' ');
    for (int f = 0; f < count; ++f) entries.back().second.push_back(line.substr(8 + f * width, width));
  }
  close_entry();
  for (const auto& [keyword, f] : entries) {
    if (keyword == "DMIG") {
      Dmig& m = deck.dmig[trim(f[0])];
      if (trim(f[1]) == "0") {  // header: NAME "0" IFO TIN TOUT POLAR - NCOL
        m.ifo = std::stoi(trim(f[2]));
        m.tin = std::stoi(trim(f[3]));
        continue;
      }
      const Dof column{std::stoi(trim(f[1])), trim(f[2]).empty() ? 0 : std::stoi(trim(f[2]))};
      EXPECT_EQ(trim(f[3]), "") << "field 5 of a DMIG column entry is blank";
      for (std::size_t k = 4; k + 3 < f.size(); k += 4) {            // (Gi, Ci, Ai, Bi)
        if (trim(f[k]).empty() && trim(f[k + 2]).empty()) continue;  // the blank half line
        const Dof row{std::stoi(trim(f[k])), trim(f[k + 1]).empty() ? 0 : std::stoi(trim(f[k + 1]))};
        EXPECT_EQ(trim(f[k + 3]), "") << "Bi is blank for a real matrix";
        const bool fresh = m.terms.emplace(std::pair{row, column}, nastran_real(f[k + 2])).second;
        EXPECT_TRUE(fresh) << "a term given twice";
      }
    } else if (keyword == "GRID") {  // ID CP X1 X2 X3 CD PS SEID
      EXPECT_EQ(trim(f[1]), "") << "CP blank: basic system";
      deck.grids[std::stoi(trim(f[0]))] = {nastran_real(f[2]), nastran_real(f[3]), nastran_real(f[4])};
    } else if (keyword == "SPOINT") {  // ID1 THRU ID2, or a list
      if (trim(f[1]) == "THRU") {
        for (int id = std::stoi(trim(f[0])); id <= std::stoi(trim(f[2])); ++id) deck.spoints.push_back(id);
      } else {
        for (const std::string& s : f)
          if (!trim(s).empty()) deck.spoints.push_back(std::stoi(trim(s)));
      }
    } else {
      ADD_FAILURE() << "unexpected entry " << keyword;
    }
  }
  return deck;
}

/// The documented numbering: coordinate "NAME.x".."NAME.rz" of interface p -> (first_grid + p, 1..6), unless
/// `grid_ids` names it; every other coordinate -> the next SPOINT from first_spoint.
std::vector<Dof> documented_dofs(const SuperelementFile& se, int first_grid, int first_spoint,
                                 const std::map<std::string, int>& grid_ids = {}) {
  const std::array<std::string, 6> suffix = {"x", "y", "z", "rx", "ry", "rz"};
  std::vector<Dof> dofs;
  int spoint = first_spoint;
  for (const std::string& c : se.coordinates) {
    Dof d{spoint, 0};
    const std::size_t dot = c.rfind('.');
    for (std::size_t p = 0; dot != std::string::npos && p < se.interfaces.names.size(); ++p) {
      if (c.substr(0, dot) != se.interfaces.names[p]) continue;
      for (int k = 0; k < 6; ++k) {
        if (c.substr(dot + 1) != suffix[k]) continue;
        const auto it = grid_ids.find(se.interfaces.names[p]);
        d = {it != grid_ids.end() ? it->second : first_grid + static_cast<int>(p), k + 1};
      }
      break;
    }
    if (d.second == 0) ++spoint;
    dofs.push_back(d);
  }
  return dofs;
}

/// The full symmetric matrix of a DMIG (IFO 6: a term stands for itself and its transpose).
Eigen::MatrixXd assemble(const Dmig& m, const std::vector<Dof>& dofs) {
  std::map<Dof, int> index;
  for (std::size_t j = 0; j < dofs.size(); ++j) index[dofs[j]] = static_cast<int>(j);
  const int n = static_cast<int>(dofs.size());
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  for (const auto& [rc, v] : m.terms) {
    const auto i = index.find(rc.first), j = index.find(rc.second);
    EXPECT_TRUE(i != index.end() && j != index.end()) << "a DOF that is no coordinate";
    if (i == index.end() || j == index.end()) continue;
    EXPECT_EQ(a(i->second, j->second), 0.0) << "a term and its transpose both given";
    a(i->second, j->second) = a(j->second, i->second) = v;
  }
  return a;
}

/// Largest |read - exact| / |exact| over the nonzero entries, and whether every zero stayed zero.
double max_relative_error(const Eigen::MatrixXd& read, const Eigen::MatrixXd& exact) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < exact.rows(); ++i)
    for (Eigen::Index j = 0; j < exact.cols(); ++j) {
      if (exact(i, j) == 0.0) {
        EXPECT_EQ(read(i, j), 0.0);
      } else {
        worst = std::max(worst, std::abs(read(i, j) - exact(i, j)) / std::abs(exact(i, j)));
      }
    }
  return worst;
}

struct Exported {
  SuperelementFile se;  // as read back from the .h5
  Deck deck;
};

/// Condense `c`, write and re-read the superelement file, export it, parse the export.
Exported condense_and_export(const Component& c, const std::string& tag,
                             const NastranExportOptions& options = {}) {
  const fs::path dir = fs::temp_directory_path() / ("nvh_dmig_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path h5 = dir / (tag + ".h5"), pch = dir / (tag + ".pch");
  const Superelement made = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
  write_superelement(h5, made, make_provenance("test", 0, nullptr, {}));
  Exported e;
  e.se = read_superelement(h5);
  {
    std::ofstream out(pch);
    write_nastran_dmig(out, e.se, options);
  }
  e.deck = parse_deck(pch);
  fs::remove_all(dir);
  return e;
}

/// Frequencies (Hz) of (K, M) above the `rigid` lowest, and the first-order bound of their change under a
/// relative rounding `eps` of every entry: eps x^T (|K| + lambda |M|) x / lambda / 2 (relative, in f).
struct Spectrum {
  Eigen::VectorXd hz, bound;
};
Spectrum spectrum(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M, int rigid, double eps) {
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(K, M);
  const int elastic = static_cast<int>(K.rows()) - rigid;
  Spectrum s;
  s.hz.resize(elastic);
  s.bound.resize(elastic);
  for (int i = 0; i < elastic; ++i) {
    const double lambda = eig.eigenvalues()(rigid + i);
    const Eigen::VectorXd x = eig.eigenvectors().col(rigid + i).cwiseAbs();
    s.hz(i) = std::sqrt(std::max(lambda, 0.0)) / (2.0 * kPi);
    s.bound(i) = eps * x.dot((K.cwiseAbs() + lambda * M.cwiseAbs()) * x) / lambda / 2.0;
  }
  return s;
}

constexpr double kEntryTolerance = 5e-10;  // half a unit in the 10th significant digit

Component raw_craig_bampton_frame() {
  Component c = frame(12);
  c.reduction.method = ReductionMethod::kCraigBampton;
  c.reduction.orthonormalize = false;
  c.reduction.modes = 10;
  c.reduction.damping_ratio = 0.02;
  return c;
}

// ---------------------------------------------------------------------------------------------------------

TEST(NastranReal, ShortestExactFormOrTheMostDigitsThatFitSixteenCharacters) {
  EXPECT_EQ(nastran_real16(0.0), "0.0");
  EXPECT_EQ(nastran_real16(1.0), "1.0D+0");
  EXPECT_EQ(nastran_real16(-2.5e-3), "-2.5D-3");
  EXPECT_EQ(nastran_real16(7850.0, 'E'), "7.85E+3");
  EXPECT_EQ(nastran_real16(1.0 / 3.0), "3.33333333333D-1");  // 12 digits, 16 characters
  // Over 60 decades, both signs: at most 16 characters, 10 significant digits at least.
  std::mt19937_64 random(17);
  std::uniform_real_distribution<double> mantissa(1.0, 10.0), exponent(-30.0, 30.0);
  double worst = 0.0;
  for (int k = 0; k < 20000; ++k) {
    const double v = (k % 2 ? -1.0 : 1.0) * mantissa(random) * std::pow(10.0, std::floor(exponent(random)));
    const std::string s = nastran_real16(v);
    ASSERT_LE(s.size(), 16u) << v;
    const double back = nastran_real(s);
    worst = std::max(worst, std::abs(back - v) / std::abs(v));
  }
  EXPECT_LE(worst, kEntryTolerance);
  std::printf("nastran_real16: worst relative rounding over 20000 values, 1e-30..1e30: %.2e\n", worst);
}

TEST(DmigExport, RawCraigBamptonMatricesAndFrequenciesSurviveTheText) {
  const Exported e = condense_and_export(raw_craig_bampton_frame(), "raw");
  const SuperelementFile& se = e.se;
  ASSERT_FALSE(se.orthonormalized);
  ASSERT_EQ(se.size(), 22);  // 2 interfaces x 6 + 10 fixed-interface modes
  EXPECT_EQ(e.deck.large_field_entries_with_odd_lines, 0);
  EXPECT_EQ(e.deck.lines_over_80, 0);  // the QRG's 80-column card image

  const std::vector<Dof> dofs = documented_dofs(se, 1, 100001);
  for (const char* name : {"KAAX", "MAAX", "BAAX"}) {
    ASSERT_TRUE(e.deck.dmig.contains(name)) << name;
    EXPECT_EQ(e.deck.dmig.at(name).ifo, 6);
    EXPECT_EQ(e.deck.dmig.at(name).tin, 2);
  }
  const Eigen::MatrixXd K = assemble(e.deck.dmig.at("KAAX"), dofs);
  const Eigen::MatrixXd M = assemble(e.deck.dmig.at("MAAX"), dofs);
  const Eigen::MatrixXd B = assemble(e.deck.dmig.at("BAAX"), dofs);
  const double eK = max_relative_error(K, se.stiffness), eM = max_relative_error(M, se.mass),
               eB = max_relative_error(B, se.damping);
  EXPECT_LE(eK, kEntryTolerance);
  EXPECT_LE(eM, kEntryTolerance);
  EXPECT_LE(eB, kEntryTolerance);

  // Grid points: a at the origin, b at (0.8, 0.5, 0.1); the modes on SPOINT 100001..100010.
  ASSERT_EQ(e.deck.grids.size(), 2u);
  EXPECT_LE((e.deck.grids.at(1) - Eigen::Vector3d(0, 0, 0)).norm(), 1e-15);
  EXPECT_LE((e.deck.grids.at(2) - Eigen::Vector3d(0.8, 0.5, 0.1)).norm(), 1e-12);
  std::vector<int> expected_spoints(10);
  for (int k = 0; k < 10; ++k) expected_spoints[k] = 100001 + k;
  EXPECT_EQ(e.deck.spoints, expected_spoints);

  // Frequencies of the re-read (K, M), rigid-body modes contained (6, free frame) skipped.
  ASSERT_EQ(se.rigid_body_modes_contained, 6);
  const Spectrum s = spectrum(K, M, 6, kEntryTolerance);
  ASSERT_EQ(s.hz.size(), se.frequency_hz.size());
  double worst = 0.0, worst_bound_ratio = 0.0;
  for (Eigen::Index i = 0; i < s.hz.size(); ++i) {
    const double rel = std::abs(s.hz(i) - se.frequency_hz(i)) / se.frequency_hz(i);
    worst = std::max(worst, rel);
    worst_bound_ratio = std::max(worst_bound_ratio, rel / s.bound(i));
    EXPECT_LE(rel, 2.0 * s.bound(i) + 1e-13) << "mode " << i + 1;
  }
  std::printf(
      "raw Craig-Bampton: entries K %.2e M %.2e B %.2e; frequencies %.2e (largest rounding bound %.2e, "
      "measured/bound at most %.3f)\n",
      eK, eM, eB, worst, s.bound.maxCoeff(), worst_bound_ratio);
}

TEST(DmigExport, OrthonormalCoordinatesReproduceTheFrequenciesToOneInABillion) {
  Component c = frame(12);
  c.reduction.method = ReductionMethod::kModal;
  c.reduction.modes = 12;
  c.reduction.damping_ratio = 0.01;
  NastranExportOptions options;
  options.first_spoint = 9001;
  const Exported e = condense_and_export(c, "modal", options);
  const SuperelementFile& se = e.se;
  const std::vector<Dof> dofs = documented_dofs(se, 1, 9001);
  EXPECT_TRUE(e.deck.grids.empty());  // modal coordinates only
  ASSERT_EQ(e.deck.spoints.size(), 12u);
  EXPECT_EQ(e.deck.spoints.front(), 9001);
  const Eigen::MatrixXd K = assemble(e.deck.dmig.at("KAAX"), dofs);
  const Eigen::MatrixXd M = assemble(e.deck.dmig.at("MAAX"), dofs);
  const Eigen::MatrixXd B = assemble(e.deck.dmig.at("BAAX"), dofs);
  const double eK = max_relative_error(K, se.stiffness), eM = max_relative_error(M, se.mass),
               eB = max_relative_error(B, se.damping);
  EXPECT_LE(std::max({eK, eM, eB}), kEntryTolerance);
  const Spectrum s = spectrum(K, M, 0, kEntryTolerance);
  double worst = 0.0;
  for (Eigen::Index i = 0; i < s.hz.size(); ++i)
    worst = std::max(worst, std::abs(s.hz(i) - se.frequency_hz(i)) / se.frequency_hz(i));
  EXPECT_LE(worst, 1e-9);
  std::printf("modal: entries K %.2e M %.2e B %.2e; frequencies %.2e\n", eK, eM, eB, worst);
}

TEST(DmigExport, RigidLinkEndInterfaceIsTheGridOfTheMasterStation) {
  // The frame's link runs from the beam node (0.8, 0, 0) to the mass at (0.8, -0.05, 0.02). An interface
  // on the link end has the master node's DOF as its coordinates: its GRID is the master node.
  Component c = raw_craig_bampton_frame();
  c.interfaces.push_back(point("arm", {0.8, -0.05, 0.02}));
  const Exported e = condense_and_export(c, "link");
  ASSERT_EQ(e.se.interfaces.names.size(), 3u);
  EXPECT_LE((e.se.interfaces.position.row(2).transpose() - Eigen::Vector3d(0.8, -0.05, 0.02)).norm(), 1e-12);
  ASSERT_TRUE(e.deck.grids.contains(3));
  EXPECT_LE((e.deck.grids.at(3) - Eigen::Vector3d(0.8, 0, 0)).norm(), 1e-12);
}

TEST(DmigExport, SupportedInterfaceDofsAreNoDofsOfTheDeck) {
  // Interface "a" held in translation: its coordinates are a.rx, a.ry, a.rz only (GRID 1 components 4-6),
  // and the three rotations about it stay as rigid-body modes inside (K, M).
  Component c = raw_craig_bampton_frame();
  c.supports = {fixed({0, 0, 0}, "111000")};
  const Exported e = condense_and_export(c, "held");
  ASSERT_EQ(e.se.rigid_body_modes_contained, 3);
  std::set<int> components_of_a;
  for (const auto& [rc, v] : e.deck.dmig.at("KAAX").terms)
    for (const Dof& d : {rc.first, rc.second})
      if (d.first == 1) components_of_a.insert(d.second);
  EXPECT_EQ(components_of_a, (std::set<int>{4, 5, 6}));
  const std::vector<Dof> dofs = documented_dofs(e.se, 1, 100001);
  const Eigen::MatrixXd K = assemble(e.deck.dmig.at("KAAX"), dofs);
  const Eigen::MatrixXd M = assemble(e.deck.dmig.at("MAAX"), dofs);
  EXPECT_LE(std::max(max_relative_error(K, e.se.stiffness), max_relative_error(M, e.se.mass)),
            kEntryTolerance);
  const Spectrum s = spectrum(K, M, 3, kEntryTolerance);
  ASSERT_EQ(s.hz.size(), e.se.frequency_hz.size());
  for (Eigen::Index i = 0; i < s.hz.size(); ++i)
    EXPECT_LE(std::abs(s.hz(i) - e.se.frequency_hz(i)) / e.se.frequency_hz(i), 2.0 * s.bound(i) + 1e-13);
}

TEST(DmigExport, GridIdsSuffixAndGeometricStiffnessAsAsked) {
  // A synthetic superelement: two interface DOF of "hub", one of "tip", two modes; geometric stiffness.
  SuperelementFile se;
  se.name = "synthetic";
  se.method = "craig-bampton";
  se.coordinates = {"hub.x", "hub.rz", "tip.y", "fixed-interface mode 1", "fixed-interface mode 2"};
  const int n = 5;
  Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n);
  se.stiffness = a * a.transpose() * 1e7 + Eigen::MatrixXd::Identity(n, n);
  se.mass = Eigen::MatrixXd::Identity(n, n) * 3.0;
  se.damping = Eigen::MatrixXd::Zero(n, n);  // no damping: no BAAX
  for (int p = 0; p < 6; ++p) se.geometric_stiffness.push_back(Eigen::MatrixXd::Identity(n, n) * (p + 1));
  se.interfaces.names = {"hub", "tip"};
  se.interfaces.position = Eigen::MatrixXd::Zero(2, 3);
  se.interfaces.shapes = {Eigen::MatrixXd::Zero(6, n), Eigen::MatrixXd::Zero(6, n)};
  se.frequency_hz = Eigen::VectorXd::Ones(2);

  NastranExportOptions options;
  options.first_grid = 700;
  options.first_spoint = 50;
  options.grid_ids = {{"tip", 42}};
  options.name_suffix = "crk";
  const fs::path pch =
      fs::temp_directory_path() / ("nvh_dmig_synthetic_" + std::to_string(::getpid()) + ".pch");
  {
    std::ofstream out(pch);
    write_nastran_dmig(out, se, options);
  }
  const Deck deck = parse_deck(pch);
  fs::remove(pch);
  EXPECT_EQ(deck.lines_over_80, 0);
  EXPECT_FALSE(deck.dmig.contains("BCRK"));
  for (const char* name : {"KCRK", "MCRK", "GXXCRK", "GYYCRK", "GZZCRK", "GXYCRK", "GYZCRK", "GZXCRK"})
    EXPECT_TRUE(deck.dmig.contains(name)) << name;
  const std::vector<Dof> dofs = documented_dofs(se, 700, 50, options.grid_ids);
  EXPECT_EQ(dofs, (std::vector<Dof>{{700, 1}, {700, 6}, {42, 2}, {50, 0}, {51, 0}}));
  EXPECT_LE(max_relative_error(assemble(deck.dmig.at("KCRK"), dofs), se.stiffness), kEntryTolerance);
  EXPECT_EQ(assemble(deck.dmig.at("GZXCRK"), dofs), se.geometric_stiffness[5]);
  EXPECT_EQ(deck.grids.size(), 2u);
  EXPECT_EQ(deck.spoints, (std::vector<int>{50, 51}));

  // Bad requests are errors that say what is wrong.
  auto message = [&](NastranExportOptions o, SuperelementFile s) {
    try {
      std::ostringstream out;
      write_nastran_dmig(out, s, o);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  NastranExportOptions unknown = options;
  unknown.grid_ids = {{"rim", 3}};
  EXPECT_NE(message(unknown, se).find("no interface 'rim' (its interfaces: hub, tip)"), std::string::npos);
  NastranExportOptions clash = options;
  clash.grid_ids = {{"tip", 700}};
  EXPECT_NE(message(clash, se).find("id 700 is given to both"), std::string::npos);
  NastranExportOptions overlap = options;
  overlap.first_spoint = 42;
  EXPECT_NE(message(overlap, se).find("id 42 is given to both"), std::string::npos);
  NastranExportOptions suffix = options;
  suffix.name_suffix = "TOOLONG";
  EXPECT_NE(message(suffix, se).find("expected 1 to 5 letters or digits"), std::string::npos);
  SuperelementFile skew = se;
  skew.stiffness(0, 1) += 1.0;
  EXPECT_NE(message(options, skew).find("KCRK (stiffness K_r, /reduced/stiffness): not symmetric"),
            std::string::npos);
}

// ---------------------------------------------------------------------------------------------------------
// The command line: `condense export`.

struct CliRun {
  int exit_code = 0;
  std::string output;
};

CliRun run(const std::string& arguments) {
  const std::string command = std::string(NVH_CONDENSE_EXE) + " " + arguments + " 2>&1";
  CliRun r;
  FILE* pipe = popen(command.c_str(), "r");
  std::array<char, 512> buffer;
  while (fgets(buffer.data(), buffer.size(), pipe)) r.output += buffer.data();
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

TEST(ExportCli, WritesTheDeckAndRefusesBadInputNamingTheFile) {
  const fs::path dir = fs::temp_directory_path() / ("nvh_export_cli_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const Superelement made =
      condense_component(raw_craig_bampton_frame(), EigenBackend::kBlockLanczos, kQuiet);
  write_superelement(dir / "frame.h5", made, make_provenance("test", 0, nullptr, {}));

  const CliRun good = run("export " + (dir / "frame.h5").string() + " -o " + (dir / "frame.pch").string() +
                          " --first-grid 11 --grid b=501");
  EXPECT_EQ(good.exit_code, 0) << good.output;
  EXPECT_NE(good.output.find("GRID a=11 b=501"), std::string::npos) << good.output;
  const Deck deck = parse_deck(dir / "frame.pch");
  EXPECT_TRUE(deck.grids.contains(11) && deck.grids.contains(501));

  const CliRun help = run("export --help");
  EXPECT_EQ(help.exit_code, 0);
  for (const char* taught : {"SPOINT", "GRID", "SI", "K2GG = KAAX", "--first-grid", "docs/matrix-export.md"})
    EXPECT_NE(help.output.find(taught), std::string::npos) << taught;

  // Not a superelement (a text file), a missing file: exit 1, the file named, nothing written.
  std::ofstream(dir / "notes.txt") << "not HDF5\n";
  for (const std::string& input : {(dir / "notes.txt").string(), (dir / "missing.h5").string()}) {
    const CliRun bad = run("export " + input + " -o " + (dir / "bad.pch").string());
    EXPECT_EQ(bad.exit_code, 1) << bad.output;
    EXPECT_NE(bad.output.find(input), std::string::npos) << bad.output;
    EXPECT_FALSE(fs::exists(dir / "bad.pch"));
  }
  const CliRun unknown =
      run("export " + (dir / "frame.h5").string() + " -o " + (dir / "bad.pch").string() + " --grid rim=3");
  EXPECT_EQ(unknown.exit_code, 1);
  EXPECT_NE(unknown.output.find("no interface 'rim'"), std::string::npos) << unknown.output;
  const CliRun usage =
      run("export " + (dir / "frame.h5").string() + " -o " + (dir / "bad.pch").string() + " --grid rim");
  EXPECT_EQ(usage.exit_code, 2) << usage.output;
  const CliRun same = run("export " + (dir / "frame.h5").string() + " -o " + (dir / "frame.h5").string());
  EXPECT_EQ(same.exit_code, 1);
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace nvh::condense
