// Residual vectors of load points for Craig-Bampton ([reduction] residual_vectors, reduction.cpp
// load_residual_vectors), against the full finite-element model's static solution.
//
// The component: a steel bar 0.4 x 0.04 x 0.04 m (C3D20, 10 x 2 x 2 cells) clamped by a rigid coupling on its
// left face (the one interface), observation points on its top face (z = h, normal +z): "p_mid" at x = 0.2,
// "p_tip" at x = 0.36, and the two nodes either side of p_mid across the width ("q_1", "q_2", 10 mm off).
// Two fixed-interface modes only (the bar's first bending pair), so that the modes alone miss much of the
// static deflection under a load on the top face.
//
// The reference: the full model's static deflection with the interface's coupling node held,
// K_ii u = f (Eigen's sparse LDL^T on the free DOF, independent of the reduction's factor and basis). The
// reduced model is used as solve uses the file (orthonormalize = false: the first 6 coordinates are the
// interface's DOF, held): u_p = S_p K_ff^-1 S^T f.
// 1. Point loads (residual_patch = 0): unit forces -z at p_mid and at p_tip, the deflection at both: the
//    reduced model with residual vectors equals the full model to 1e-8; without them it is off by more than
//    1 %.
// 2. A patch load (residual_patch = 12 mm around p_mid: p_mid and q_1, q_2, 1/3 N each): the deflection at
//    all four points under that load, the residual vector of p_mid's patch alone: to 1e-8; the point load's
//    vector instead misses the patch's shape (more than 1e-4 at q_1, q_2).
#include <gtest/gtest.h>

#include <unistd.h>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/log.hpp"
#include "condense/condense.hpp"
#include "condense/volume_model.hpp"
#include "structured_mesh.hpp"

namespace fs = std::filesystem;

namespace nvh::condense {
namespace {

const Logger kQuiet{std::cerr, "test", Verbosity::kQuiet};

class ResidualVectorBar : public ::testing::Test {
 protected:
  static constexpr double L = 0.4, h = 0.04, E = 210e9, nu = 0.3, rho = 7850.0;
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nvh_residual_vectors_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    Mesh mesh = testing::BoxMesher({L, h, h}, {10, 2, 2}).hex20();
    for (int n = 0; n < static_cast<int>(mesh.nodes.size()); ++n)
      if (mesh.nodes[n].x() < 1e-12) mesh.node_sets["LEFT"].push_back(n);
    std::ofstream out(dir_ / "bar.inp");
    write_abaqus_mesh(mesh, out);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static NamedPoint point(const std::string& name, double x, double y, double z) {
    NamedPoint p;
    p.name = name;
    p.at = {x, y, z};
    return p;
  }
  Component bar(std::vector<std::string> residual, double patch) const {
    Component c;
    c.name = "bar";
    c.kind = "volume";
    c.materials["steel"] = Material{"steel", E, nu, rho};
    c.volume.mesh = dir_ / "bar.inp";
    c.volume.material = "steel";
    NamedPoint clamp = point("left", -0.01, h / 2, h / 2);
    clamp.surface = "LEFT";
    c.interfaces = {clamp};
    c.observers = {point("p_mid", 0.2, h / 2, h), point("p_tip", 0.36, h / 2, h),
                   point("q_1", 0.2, h / 2 - 0.01, h), point("q_2", 0.2, h / 2 + 0.01, h)};
    c.reduction.method = ReductionMethod::kCraigBampton;
    c.reduction.modes = 2;
    c.reduction.orthonormalize = false;
    c.reduction.residual_vectors = std::move(residual);
    c.reduction.residual_patch = patch;
    return c;
  }

  /// The full model's static deflection along z at the observation points (p_mid, p_tip, q_1, q_2) under
  /// forces along z (N) at them, the interface's coupling node held.
  Eigen::Vector4d full(const Eigen::Vector4d& fz) const {
    const Component c = bar({}, 0.0);
    const FeModel model = build_volume_model(c);
    const SparseMatrix K = model.stiffness();
    const std::vector<int> free_of = model.free_index();
    std::vector<bool> held(K.rows(), false);
    for (int a = 0; a < 6; ++a) held[free_of[6 * model.coupling_nodes[0] + a]] = true;
    std::vector<int> keep, map(K.rows(), -1);
    for (int d = 0; d < K.rows(); ++d)
      if (!held[d]) map[d] = static_cast<int>(keep.size()), keep.push_back(d);
    std::vector<Eigen::Triplet<double>> t;
    for (int col = 0; col < K.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(K, col); it; ++it)
        if (map[it.row()] >= 0 && map[it.col()] >= 0)
          t.emplace_back(map[it.row()], map[it.col()], it.value());
    SparseMatrix kii(static_cast<Eigen::Index>(keep.size()), static_cast<Eigen::Index>(keep.size()));
    kii.setFromTriplets(t.begin(), t.end());
    Eigen::SimplicialLDLT<SparseMatrix> ldlt(kii);
    EXPECT_EQ(ldlt.info(), Eigen::Success);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(kii.rows());
    std::vector<int> dof(4);
    for (int k = 0; k < 4; ++k) {
      const int node = model.find_node(c.observers[k].at, 1e-9);
      EXPECT_GE(node, 0) << c.observers[k].name << " is not a node";
      dof[k] = map[free_of[6 * node + 2]];
      f(dof[k]) += fz(k);
    }
    const Eigen::VectorXd u = ldlt.solve(f);
    return {u(dof[0]), u(dof[1]), u(dof[2]), u(dof[3])};
  }

  /// The reduced model's deflection along z at the observation points under forces along z at them, its
  /// first 6 coordinates (the interface) held; `coordinates`: how many it has.
  static Eigen::Vector4d reduced(const Superelement& se, const Eigen::Vector4d& fz,
                                 int* coordinates = nullptr) {
    const int n = se.size(), m = n - 6;
    if (coordinates) *coordinates = n;
    Eigen::MatrixXd s(4, m);  // z rows of the observation shapes, free coordinates
    for (int k = 0; k < 4; ++k) s.row(k) = se.observers.shapes[k].row(2).tail(m);
    const Eigen::MatrixXd kff = se.stiffness.bottomRightCorner(m, m);
    return s * kff.ldlt().solve(s.transpose() * fz);
  }

  fs::path dir_;
};

double worst(const Eigen::Vector4d& x, const Eigen::Vector4d& reference) {
  return (x - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff();
}

TEST_F(ResidualVectorBar, PointLoadsAreStaticallyExact) {
  int with_count = 0, without_count = 0;
  const Superelement with = condense_component(bar({"p_*"}, 0.0), EigenBackend::kBlockLanczos, kQuiet);
  const Superelement without = condense_component(bar({}, 0.0), EigenBackend::kBlockLanczos, kQuiet);
  EXPECT_EQ(with.static_correction, 2) << "the file counts its residual vectors (/reduced static_correction)";
  EXPECT_EQ(without.static_correction, 0);
  for (const Eigen::Vector4d& f : {Eigen::Vector4d(-1, 0, 0, 0), Eigen::Vector4d(0, -1, 0, 0)}) {
    const Eigen::Vector4d reference = full(f);
    const Eigen::Vector4d a = reduced(with, f, &with_count), b = reduced(without, f, &without_count);
    EXPECT_LT(worst(a, reference), 1e-8) << "with residual vectors";
    EXPECT_GT(worst(b, reference), 1e-2) << "without them the two modes should miss the static deflection";
    std::printf(
        "measured: unit load at %s: full model p_mid %.6e m, p_tip %.6e m; with residual vectors (%d "
        "coordinates) relative error %.2e (tolerance 1e-8), without (%d) %.2e\n",
        f(0) != 0 ? "p_mid" : "p_tip", reference(0), reference(1), with_count, worst(a, reference),
        without_count, worst(b, reference));
  }
}

TEST_F(ResidualVectorBar, PatchLoadIsStaticallyExact) {
  const Superelement se = condense_component(bar({"p_mid"}, 0.012), EigenBackend::kBlockLanczos, kQuiet);
  const Eigen::Vector4d f(-1.0 / 3, 0, -1.0 / 3, -1.0 / 3);  // p_mid's patch: p_mid, q_1, q_2
  const Eigen::Vector4d reference = full(f), a = reduced(se, f);
  EXPECT_LT(worst(a, reference), 1e-8);
  // The point load's vector holds the deflection at p_mid (reciprocity: its dual solution is in the basis)
  // but not the patch's whole deflected shape: q_1 and q_2 are off.
  const Superelement point = condense_component(bar({"p_mid"}, 0.0), EigenBackend::kBlockLanczos, kQuiet);
  const Eigen::Vector4d b = reduced(point, f);
  EXPECT_GT(worst(b, reference), 1e-4) << "a point load's vector should not hold the patch's deflection";
  std::printf(
      "measured: patch load at p_mid (3 nodes, 12 mm): full model p_mid %.6e m, q_1 %.6e m; with the patch's "
      "residual vector relative error %.2e (tolerance 1e-8); with the point load's vector %.2e\n",
      reference(0), reference(2), worst(a, reference), worst(b, reference));
}

}  // namespace
}  // namespace nvh::condense
