// Solid models against beam theory, and the node selectors of bearing bores.
//
// 1. A solid cantilever bar (C3D20) against Timoshenko beam theory: the frequency equation of the
//    clamped-free Timoshenko beam is solved here independently (transfer matrix of the governing ODEs,
//    root bracketing), not with condense's beam element.
// 2. Cylinder selectors on a gmsh-meshed block with a bore: they take exactly the nodes gmsh puts on
//    the bore's face, a [[fix]] on the cylinder equals one on the face's physical group, and a
//    selector that catches no node is an error naming the entry.
#include <gtest/gtest.h>

#include <unistd.h>
#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <unsupported/Eigen/MatrixFunctions>

#include "common/log.hpp"
#include "condense/component_reader.hpp"
#include "condense/condense.hpp"
#include "condense/gmsh_mesh.hpp"
#include "condense/node_selector.hpp"
#include "condense/surface.hpp"
#include "structured_mesh.hpp"

namespace nvh::condense {
namespace {

namespace fs = std::filesystem;
const Logger kQuiet(std::cerr, "test", Verbosity::kQuiet);

// ---------------------------------------------------------------------------------------------
// Timoshenko beam theory (Timoshenko 1921; frequency equation of the clamped-free beam e.g. Huang,
// J. Appl. Mech. 28, 1961), harmonic motion at omega, deflection w(x) and section rotation psi(x):
//   kappa G A (w'' - psi') + rho A omega^2 w = 0
//   E I psi'' + kappa G A (w' - psi) + rho I omega^2 psi = 0
// State y = [w, w', psi, psi'], y' = A y. Clamped at x = 0 (w = psi = 0); free at x = L (bending
// moment E I psi' = 0, shear force kappa G A (w' - psi) = 0). With Y = exp(A L) the 2 x 2 determinant
// of the free-end conditions on the two unknown initial slopes vanishes at the natural frequencies.
struct Beam {
  double E, G, rho, A, I, kappa, L;
};

double clamped_free_determinant(const Beam& b, double omega) {
  const double w2 = omega * omega;
  Eigen::Matrix4d a = Eigen::Matrix4d::Zero();
  a(0, 1) = 1.0;
  a(1, 0) = -b.rho * w2 / (b.kappa * b.G);  // w'' = psi' - rho omega^2 / (kappa G) w
  a(1, 3) = 1.0;
  a(2, 3) = 1.0;
  const double s = b.kappa * b.G * b.A / (b.E * b.I);
  a(3, 1) = -s;  // psi'' = -kappa G A / (E I) (w' - psi) - rho omega^2 / E psi
  a(3, 2) = s - b.rho * w2 / b.E;
  const Eigen::Matrix4d y = (a * b.L).exp();
  // Initial states: [0, 1, 0, 0] (w' = 1) and [0, 0, 0, 1] (psi' = 1).
  Eigen::Matrix2d d;
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector4d end = y.col(k == 0 ? 1 : 3);
    d(0, k) = end(3);           // psi'(L)
    d(1, k) = end(1) - end(2);  // w'(L) - psi(L)
  }
  return d.determinant();
}

/// The lowest `count` natural frequencies (Hz): scan omega for sign changes, then bisect.
std::vector<double> timoshenko_cantilever_hz(const Beam& b, int count, double f_max) {
  std::vector<double> roots;
  const double step = 2 * std::numbers::pi * f_max / 20000.0;
  double lo = step, d_lo = clamped_free_determinant(b, lo);
  for (double hi = 2 * step; hi <= 2 * std::numbers::pi * f_max && static_cast<int>(roots.size()) < count;
       hi += step) {
    const double d_hi = clamped_free_determinant(b, hi);
    if ((d_lo < 0) != (d_hi < 0)) {
      double a = lo, c = hi, fa = d_lo;
      for (int it = 0; it < 100; ++it) {
        const double m = 0.5 * (a + c), fm = clamped_free_determinant(b, m);
        if ((fm < 0) == (fa < 0)) {
          a = m;
          fa = fm;
        } else {
          c = m;
        }
      }
      roots.push_back(0.5 * (a + c) / (2 * std::numbers::pi));
    }
    lo = hi;
    d_lo = d_hi;
  }
  return roots;
}

// Steel bar 1.0 x 0.1 x 0.1 m (L / h = 10, where shear and rotary inertia lower the second bending
// mode by about 10 % against Euler-Bernoulli), clamped over its whole end face x = 0, C3D20 40 x 4 x 4.
// Reference: Timoshenko theory with Cowper's shear coefficient of the square, kappa = 10 (1 + nu) /
// (12 + 11 nu) (Cowper, J. Appl. Mech. 33, 1966). Tolerance 1 %: the 3D clamp also holds the root
// section's Poisson contraction and warping (stiffer than the beam's clamp, which only sets w = psi =
// 0), and Timoshenko theory itself is an approximation of 3D elasticity of order (h / L)^2 in its
// shear term; the beam-theory and 3D values differ by a few tenths of a percent at L / h = 10.
TEST(TimoshenkoCantilever, SolidBarBendingFrequenciesWithinOnePercent) {
  const double E = 210e9, nu = 0.3, rho = 7850.0, h = 0.1, L = 1.0;
  const fs::path dir = fs::temp_directory_path() / ("nvh_timoshenko_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  testing::BoxMesher mesher({L, h, h}, {40, 4, 4});
  {
    std::ofstream out(dir / "bar.inp");
    write_abaqus_mesh(mesher.hex20(), out);
  }
  Component c;
  c.name = "bar";
  c.kind = "volume";
  c.materials["steel"] = Material{"steel", E, nu, rho};
  c.volume.mesh = dir / "bar.inp";
  c.volume.material = "steel";
  Support clamp;
  clamp.box = std::array<double, 6>{-1e-9, -1, -1, 1e-9, 1, 1};
  clamp.dofs = {true, true, true, false, false, false};
  c.supports = {clamp};
  c.reduction.method = ReductionMethod::kModal;
  c.reduction.modes = 6;
  const Superelement se = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
  fs::remove_all(dir);

  const Beam beam{E, E / (2 * (1 + nu)), rho, h * h, std::pow(h, 4) / 12.0, 10 * (1 + nu) / (12 + 11 * nu),
                  L};
  const std::vector<double> reference = timoshenko_cantilever_hz(beam, 2, 2000.0);
  ASSERT_EQ(reference.size(), 2u);
  // Euler-Bernoulli for scale: 1.8751^2 / (2 pi L^2) sqrt(E I / (rho A)) = 83.55 Hz; Timoshenko lower.
  EXPECT_LT(reference[0], 83.55);
  EXPECT_GT(reference[0], 82.0);
  // The solid's modes by frequency: 1, 2 first bending (y and z, equal for the square section); 3, 4
  // second bending (about 500 Hz); torsion lies higher (1 / (4 L) sqrt(G J / (rho I_p)) = 737 Hz).
  ASSERT_GE(se.frequency_hz.size(), 4);
  for (int k = 0; k < 2; ++k) {
    for (int pair = 0; pair < 2; ++pair) {
      const double f = se.frequency_hz(2 * k + pair);
      EXPECT_NEAR(f / reference[k], 1.0, 0.01)
          << "bending mode " << k + 1 << ": solid " << f << " Hz, Timoshenko " << reference[k] << " Hz";
    }
    std::printf("bending %d: solid %.3f Hz, Timoshenko %.3f Hz (%+.3f %%)\n", k + 1, se.frequency_hz(2 * k),
                reference[k], 100 * (se.frequency_hz(2 * k) / reference[k] - 1));
  }
}

// ---------------------------------------------------------------------------------------------
// A block 0.12 x 0.08 x 0.04 m with a bore of radius 20 mm along x through it, meshed by gmsh with
// curved second-order tetrahedra (mid-edge nodes on the bore). BORE is the bore face's physical group.
class Bore : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nvh_bore_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    std::ofstream(dir_ / "block.geo")
        << "SetFactory(\"OpenCASCADE\");\n"
           "Box(1) = {0, -0.04, -0.04, 0.12, 0.08, 0.08};\n"
           "Cylinder(2) = {-0.01, 0, 0, 0.14, 0, 0, 0.02};\n"
           "v() = BooleanDifference{ Volume{1}; Delete; }{ Volume{2}; Delete; };\n"
           "Physical Surface(\"BORE\") = Surface In BoundingBox{-0.001, -0.021, -0.021, 0.121, 0.021, "
           "0.021};\n"
           "Physical Volume(\"BLOCK\") = v();\n"
           "Mesh.MeshSizeMax = 0.012;\n";
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string component(const std::string& extra) const {
    return "[component]\nname = \"block\"\nkind = \"volume\"\n[material.steel]\nE = 210e9\nnu = 0.3\n"
           "rho = 7850.0\n[volume]\nmesh = \"block.geo\"\nmaterial = \"steel\"\n" +
           extra + "[reduction]\nmethod = \"modal\"\nmodes = 6\n";
  }
  Superelement condense(const std::string& text) const {
    return condense_component(parse_component(text, (dir_ / "block.toml").string()),
                              EigenBackend::kBlockLanczos, kQuiet);
  }
  Error error_of(const std::string& text) const {
    try {
      condense(text);
    } catch (const Error& e) {
      return e;
    }
    ADD_FAILURE() << "expected an error";
    return Error("none");
  }
  fs::path dir_;
};

TEST_F(Bore, CylinderSelectorTakesExactlyTheBoreNodes) {
  const Mesh mesh = mesh_with_gmsh(GmshRequest{dir_ / "block.geo", 2, 0.0, 1});
  ASSERT_TRUE(mesh.node_sets.count("BORE"));
  const std::vector<int>& bore = mesh.node_sets.at("BORE");
  std::vector<bool> on_surface(mesh.nodes.size(), false);  // cylinders take surface nodes
  for (int n : extract_surface(mesh).nodes) on_surface[n] = true;
  NodeSelector selector;
  selector.cylinder = CylinderSelector{{0.06, 0, 0}, {2, 0, 0}, 0.0199, 0.0201, -0.07, 0.07};
  selector.path = "interface[1]";
  selector.what = "test";
  EXPECT_EQ(select_nodes(mesh, on_surface, selector), bore);  // same nodes, both sorted
  EXPECT_GT(bore.size(), 100u);
  // An axial range takes the ring of nodes within it only: here the half x < 0.06.
  selector.cylinder->s_max = 0.0;
  const std::vector<int> half = select_nodes(mesh, on_surface, selector);
  std::size_t expected = 0;
  for (int n : bore) expected += mesh.nodes[n].x() <= 0.06 + kSelectorTolerance;
  EXPECT_EQ(half.size(), expected);
  EXPECT_LT(half.size(), bore.size());
}

TEST_F(Bore, FixOnACylinderEqualsFixOnTheBoreFace) {
  const Superelement by_face = condense(component("[[fix]]\nsurface = \"bore\"\ndofs = \"x y z\"\n"));
  const Superelement by_cylinder = condense(
      component("[[fix]]\ncylinder = { point = [0, 0, 0], axis = [1, 0, 0], radius = [0.0199, 0.0201] }\n"
                "dofs = \"x y z\"\n"));
  ASSERT_EQ(by_face.frequency_hz.size(), 6);
  ASSERT_EQ(by_cylinder.frequency_hz.size(), 6);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(by_cylinder.frequency_hz(i), by_face.frequency_hz(i)) << i;
  EXPECT_GT(by_face.frequency_hz(0), 1000.0);  // held: no rigid-body modes
}

TEST_F(Bore, BearingCentreCoupledToTheBore) {
  // RBE2 to the bore: the free block keeps its 6 rigid-body modes; the coupling point sits on the axis.
  // (RBE3 works too, but makes the 700 bore nodes one dense block of the factor: 20 s here.)
  const Superelement se =
      condense(component("[[interface]]\nname = \"bearing\"\nat = [0.06, 0, 0]\ncoupling = \"rbe2\"\n"
                         "cylinder = { point = [0.06, 0, 0], axis = [1, 0, 0], radius = [0.0199, 0.0201], "
                         "length = [-0.1, 0.1] }\n"));
  EXPECT_EQ(se.rigid_body_modes_removed, 6);
  EXPECT_EQ(se.interfaces.names, std::vector<std::string>{"bearing"});
}

TEST_F(Bore, CylinderThatCatchesNoNodeIsAnError) {
  const Error e =
      error_of(component("[[interface]]\nname = \"bearing\"\nat = [0.06, 0, 0]\n"
                         "cylinder = { point = [0.06, 0, 0], axis = [1, 0, 0], radius = [0.0249, 0.0251], "
                         "length = [-0.05, 0.05] }\n"));
  EXPECT_EQ(e.key(), "interface[1].cylinder") << e.what();
  EXPECT_GT(e.where().line, 10) << e.what();  // the [[interface]] entry (toml11 places inline tables loosely)
  EXPECT_NE(e.where().file.find("block.toml"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("catches no node"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("nearest node lies at radius 0.02"), std::string::npos) << e.what();
}

TEST_F(Bore, SupportCylinderOutsideTheAxialRangeIsAnError) {
  const Error e =
      error_of(component("[[fix]]\ncylinder = { point = [0, 0, 0], axis = [1, 0, 0], radius = [0.0199, "
                         "0.0201], length = [0.2, 0.3] }\n"
                         "dofs = \"x y z\"\n"));
  EXPECT_EQ(e.key(), "fix[1].cylinder") << e.what();
  EXPECT_NE(std::string(e.what()).find("no node lies in its axial range"), std::string::npos) << e.what();
}

TEST_F(Bore, UnknownPhysicalGroupListsTheGroups) {
  const Error e =
      error_of(component("[[interface]]\nname = \"bearing\"\nat = [0.06, 0, 0]\nsurface = \"bore2\"\n"));
  EXPECT_EQ(e.key(), "interface[1].surface") << e.what();
  EXPECT_NE(std::string(e.what()).find("\"BORE2\" is not in the mesh"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("BLOCK, BORE"), std::string::npos) << e.what();
}

TEST_F(Bore, ConnectionPointFarFromItsSurfaceIsAnError) {
  // 60 mm typed as 60 m.
  const Error e =
      error_of(component("[[interface]]\nname = \"bearing\"\nat = [60, 0, 0]\nsurface = \"BORE\"\n"));
  EXPECT_EQ(e.key(), "interface[1].at") << e.what();
  EXPECT_NE(std::string(e.what()).find("farther than the size of the surface"), std::string::npos)
      << e.what();
  // ... unless the lever is intended.
  const Superelement se = condense(component(
      "[[interface]]\nname = \"bearing\"\nat = [0.3, 0, 0]\nsurface = \"BORE\"\nmax_distance = 0.5\n"));
  EXPECT_EQ(se.interfaces.names.size(), 1u);
}

}  // namespace
}  // namespace nvh::condense
