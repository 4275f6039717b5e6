// The fast Jacobian of the elasto-hydrodynamic piston-liner (`liner_jacobian`, docs/bearing.md section 17.6)
// against central differences of the element's own evaluate() (a reference that uses no Jacobian code: every
// column of every marker perturbed, the film re-solved to 1e-13 each time), at the slap scene's scale (bore
// radius 43 mm, clearance 30 um, 16 x 12 cells per panel, 208 liner markers, 13 levels x 16 angles) on a
// deformed, moving liner, in the film (e = 8 um) and in mixed contact (e = 27 um, asperities carrying load),
// JFO cavitation. Steps: 3e-10 m (1e-5 c) for positions, 1e-8 rad, 1e-6 m/s, 1e-5 rad/s; their truncation
// error and the film tolerance's noise are below 1e-6 of a row. The error of an entry is |J - J_fd| over the
// largest |J_fd| of its row (or 1e-5 of the matrix's largest, for rows that vanish to round-off).
//   linearized (default): tolerance 1e-5 - the differences of the linearized film (one Newton matrix) are
//     first-order exact with the cavitated set held; cells at the cavitation boundary make the reference's
//     one-sided kinks, measured 1e-7 .. 1e-6 (printed).
//   differences: the same tolerance (the old Jacobian, for comparison).
//   none: the piston's rows hold no liner-marker columns, and the piston's own columns equal the linearized
//     ones.
// The CPU time of one Jacobian of each kind is printed (not checked: speed is in bench/).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/input.hpp"
#include "solve/element_registry.hpp"

namespace nvh::solve {
namespace {

constexpr double kPi = std::numbers::pi;

const std::string kKeys =
    "bore_radius = 0.043\nradial_clearance = 30e-6\nskirt_length = 0.04\nskirt_top = 0.012\nviscosity = "
    "0.007\n"
    "barrel = [[-0.028, 12e-6], [-0.006, 0.0], [0.012, 8e-6]]\ncells_axial = 16\ncells_around = 12\n"
    "arcs_deg = [[-60, 60], [120, 240]]\noil_layer = 8e-6\nfill_bottom = 0.2\nfill_top = 0.2\n"
    "sigma = 1e-6\nK = 2.4e-4\nmodulus = 1.1e11\nmu_asperity = 0.1\nfilm_tolerance = 1e-13\n";

struct Built {
  input::Document doc;
  std::unique_ptr<ForceElement> element;
};

Built build(const std::string& keys, const std::vector<Vec3>& ring) {
  Built b{input::Document::parse(keys, "piston-liner.toml"), nullptr};
  const input::Table t = b.doc.root();
  std::vector<std::filesystem::path> files;
  std::vector<MarkerMotion> initial(2);
  std::vector<std::string> bodies = {"piston", "block"};
  for (const Vec3& p : ring) {
    MarkerMotion m;
    m.position = p;
    initial.push_back(m), bodies.push_back("block");
  }
  ElementContext c{t, ".", files, initial, bodies};
  b.element = builtin_elements().find("force", "piston-liner")->make(c);
  t.finish();
  return b;
}

Eigen::VectorXd rows_of(const ForceElement& e, const std::vector<MarkerMotion>& m) {
  const int nm = static_cast<int>(m.size());
  std::vector<Wrench> w(nm);
  const ElementInput in{0.0, 0.0, m, {}, {}};
  ElementOutput out{w, {}};
  e.evaluate(in, out);
  Eigen::VectorXd v(6 * nm);
  for (int k = 0; k < nm; ++k) v.segment<3>(6 * k) = w[k].force, v.segment<3>(6 * k + 3) = w[k].torque;
  return v;
}

/// Central differences of evaluate() in every marker column (dp, dtheta, dv, domega as model.cpp perturbs).
Eigen::MatrixXd differences(const ForceElement& e, const std::vector<MarkerMotion>& m) {
  const int nm = static_cast<int>(m.size());
  Eigen::MatrixXd jf = Eigen::MatrixXd::Zero(6 * nm, 12 * nm + 1);
  const double steps[] = {3e-10, 1e-8, 1e-6, 1e-5};
  for (int c = 0; c < 12 * nm; ++c) {
    const int k = c / 12, kind = (c % 12) / 3, axis = c % 3;
    const double h = steps[kind];
    std::vector<MarkerMotion> plus = m, minus = m;
    for (auto [mm, s] : {std::pair{&plus[k], h}, std::pair{&minus[k], -h}}) {
      if (kind == 0) mm->position[axis] += s;
      if (kind == 1) mm->axes = Eigen::AngleAxisd(s, Vec3::Unit(axis)).toRotationMatrix() * mm->axes;
      if (kind == 2) mm->velocity[axis] += s;
      if (kind == 3) mm->angular_velocity[axis] += s;
    }
    jf.col(c) = (rows_of(e, plus) - rows_of(e, minus)) / (2 * h);
  }
  return jf;
}

Eigen::MatrixXd jacobian(const ForceElement& e, const std::vector<MarkerMotion>& m, double& ms) {
  const int nm = static_cast<int>(m.size());
  Eigen::MatrixXd ja = Eigen::MatrixXd::Zero(6 * nm, 12 * nm + 1);
  const ElementInput in{0.0, 0.0, m, {}, {}};
  ElementJacobian jac{1.0, ja};
  rows_of(e, m);                         // the state evaluated first, as in a model's Newton iteration
  const std::clock_t t0 = std::clock();  // process CPU time (the machine is shared)
  constexpr int kRepeat = 3;
  for (int r = 0; r < kRepeat; ++r) {
    ja.setZero();
    EXPECT_TRUE(e.jacobian(in, jac));
  }
  ms = 1e3 * double(std::clock() - t0) / CLOCKS_PER_SEC / kRepeat;
  return ja;
}

/// Largest |J - J_ref| over the row scale (see the top), and the overall scale.
double worst(const Eigen::MatrixXd& ja, const Eigen::MatrixXd& jf) {
  const double overall = jf.cwiseAbs().maxCoeff();
  double w = 0;
  for (int r = 0; r < jf.rows(); ++r) {
    const double scale = std::max(jf.row(r).cwiseAbs().maxCoeff(), 1e-5 * overall);
    w = std::max(w, (ja.row(r) - jf.row(r)).cwiseAbs().maxCoeff() / scale);
  }
  return w;
}

TEST(PistonLinerEhlJacobian, LinearizedFilmAgainstDifferencesOfTheElement) {
  std::vector<Vec3> ring;  // 13 levels x 16 angles on the bore, j at the origin
  for (int b = 0; b < 16; ++b) {
    const double th = -kPi + 2 * kPi * (b + 0.5) / 16;
    for (int a = 0; a < 13; ++a)
      ring.emplace_back(0.043 * std::cos(th), -0.043 * std::sin(th), -0.05 + 0.01 * a);
  }
  const Built linearized = build(kKeys, ring);
  const Built diff = build(kKeys + "liner_jacobian = \"differences\"\n", ring);
  const Built none = build(kKeys + "liner_jacobian = \"none\"\n", ring);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const double e : {8e-6, 27e-6}) {
    std::vector<MarkerMotion> m(2);
    MarkerMotion &i = m[0], &j = m[1];
    j.velocity = Vec3(0.01, -0.02, 0.005), j.angular_velocity = Vec3(0.5, -0.3, 0.2);
    i.axes = Eigen::AngleAxisd(3e-4, -Vec3::UnitY()).toRotationMatrix();
    i.position = Vec3(e, 0, 0.004);
    i.velocity = j.velocity + j.angular_velocity.cross(i.position) + Vec3(0.03, 0, 7.0);
    i.angular_velocity = j.angular_velocity + Vec3(0, 0.8, 0);
    for (const Vec3& p : ring) {  // displaced up to 3 um radially, moving up to 0.02 m/s
      const Vec3 radial = Vec3(p.x(), p.y(), 0).normalized();
      MarkerMotion q;
      q.position = p + 3e-6 * u(rng) * radial;
      q.velocity = j.velocity + j.angular_velocity.cross(q.position) + 0.02 * u(rng) * radial;
      m.push_back(q);
    }
    double ms_lin = 0, ms_diff = 0, ms_none = 0;
    const Eigen::MatrixXd jl = jacobian(*linearized.element, m, ms_lin);
    const Eigen::MatrixXd jd = jacobian(*diff.element, m, ms_diff);
    const Eigen::MatrixXd jn = jacobian(*none.element, m, ms_none);
    const Eigen::MatrixXd jf = differences(*linearized.element, m);
    const double err_lin = worst(jl, jf), err_diff = worst(jd, jf);
    EXPECT_LT(err_lin, 1e-5) << "linearized, e = " << e;
    EXPECT_LT(err_diff, 1e-5) << "differences, e = " << e;
    // the liner columns matter here (else the test could not tell the kinds apart)
    const int liner_cols = 12 * static_cast<int>(ring.size());
    const double liner_part = jf.block(0, 24, 6, liner_cols).cwiseAbs().maxCoeff();
    EXPECT_GT(liner_part, 1e-2 * jf.block(0, 0, 6, 24).cwiseAbs().maxCoeff());
    EXPECT_EQ(jn.block(0, 24, 6, liner_cols).cwiseAbs().maxCoeff(), 0.0)
        << "none: piston rows, liner columns";
    // (j's columns differ: moving j changes every u_k, which `none` leaves out)
    const double err_none = (jn.block(0, 0, 6, 12) - jl.block(0, 0, 6, 12)).cwiseAbs().maxCoeff() /
                            jl.block(0, 0, 6, 12).cwiseAbs().maxCoeff();
    EXPECT_LT(err_none, 1e-5) << "none: the piston's columns";
    std::printf(
        "measured: e = %.0f um, %zu liner markers: worst row-relative error against differences of "
        "evaluate(): "
        "linearized %.2e, film differences %.2e (tolerance 1e-5); one Jacobian: linearized %.1f ms, "
        "differences %.1f ms, none %.1f ms; liner columns' largest %.3g against the piston's %.3g\n",
        e * 1e6, ring.size(), err_lin, err_diff, ms_lin, ms_diff, ms_none, liner_part,
        jf.block(0, 0, 6, 24).cwiseAbs().maxCoeff());
  }
}

}  // namespace
}  // namespace nvh::solve
