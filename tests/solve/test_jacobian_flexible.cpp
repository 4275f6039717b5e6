// The closed-form derivatives of flexible bodies (flexible_body.cpp, issue 12 item 3) against differences:
//   1. the model's analytic Jacobian (Model::jacobian) of a flexible beam (modal and raw Craig-Bampton
//      superelements, full and linear coupling) joined to a rigid body by a revolute joint and a
//      spring-damper, loaded by a torque on the beam, against central differences of Model::residual at
//      random states (the oracle of test_jacobian.cpp, its `compare` helper copied);
//   2. each of FlexibleBody's five derivative functions against the Body base class' local-difference
//      defaults (qualified calls), at random states with modal rotations up to ~0.3 rad;
//   3. add_wrench, marker_sensitivity, add_wrench_derivative, kinematic_jacobian, inertia_jacobian,
//      inertia_residual and dissipated_power do not allocate, mass_matrix only its result (glibc: malloc
//      counted);
//   4. the time of Model::jacobian for a beam of 30 modes, with the closed forms and with the defaults
//      (a forwarding body that inherits them), printed.
#include <gtest/gtest.h>

#include <unistd.h>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <random>
#include <sstream>

#include "common/log.hpp"
#include "common/provenance.hpp"
#include "condense/condense.hpp"
#include "jacobian_check.hpp"
#include "solve/flexible_body.hpp"
#include "solve/scene.hpp"
#include "tests/condense/beam_fixtures.hpp"

// Not under AddressSanitizer (check-sanitize), whose own malloc must be the only one: the test is skipped
// there.
#if defined(__SANITIZE_ADDRESS__)
#define NVH_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define NVH_SANITIZED 1
#endif
#endif
#if defined(__GLIBC__) && !defined(NVH_SANITIZED)
// Count heap allocations in a window (the library's Eigen allocations go through malloc; so does operator
// new).
extern "C" void* __libc_malloc(std::size_t);
namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
}  // namespace
extern "C" void* malloc(std::size_t n) noexcept {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(n);
}
#define NVH_COUNT_ALLOCATIONS 1
#endif

namespace nvh::solve {
namespace {

namespace fs = std::filesystem;
using condense::testing::circle;
using condense::testing::point;
using condense::testing::Steel;
using condense::testing::straight_beam;

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("nvh_flexjac_" + std::to_string(::getpid()) + "_" + name);
  fs::create_directories(d);
  return d;
}

/// A steel beam, L = 1 m, d = 20 mm, interfaces "a" at x = 0 and "b" at x = L (as test_flexible.cpp).
/// `stiffening`: with the centrifugal geometric stiffness, reduced at a spin of (0.3, -0.2, 0.5) rad/s (so
/// that both K_G(omega) and the reference's subtraction are exercised).
void write_beam(const fs::path& file, condense::ReductionMethod method, bool orthonormalize, int modes,
                bool stiffening = false) {
  condense::BeamSection s = circle(0.02);
  s.rotary_inertia = false;
  condense::Component c = straight_beam(1.0, s, 16, Steel{});
  c.interfaces = {point("a", {0, 0, 0}), point("b", {1.0, 0, 0})};
  c.reduction.method = method;
  c.reduction.orthonormalize = orthonormalize;
  c.reduction.damping_ratio = 0.02;
  c.reduction.modes = modes;
  if (stiffening) {
    c.reduction.geometric_stiffening = true;
    c.reduction.spin = {0.3, -0.2, 0.5};
  }
  std::ostringstream quiet;
  const Logger log(quiet, "test", Verbosity::kQuiet);
  const condense::Superelement se =
      condense::condense_component(c, condense::EigenBackend::kBlockLanczos, log);
  condense::write_superelement(file, se, make_provenance("test", 0, nullptr, {}));
}

// ---------------------------------------------------------------- 1. the model's Jacobian
using testing::compare;  // jacobian_check.hpp; `modal` sets the amplitude of the random modal coordinates
using testing::Comparison;

/// The beam (markers a, b of the superelement and "end" on b with its own axes) pinned at its tip to a rigid
/// body by a revolute joint, a spring-damper from its root to the rigid body, a torque on its root, gravity.
std::string flexible_scene(const std::string& coupling, int modes) {
  std::ostringstream s;
  s << R"(
[scene]
gravity = [0, -9.81, 0]
[[body]]
name = "beam"
type = "flexible"
superelement = "beam.h5"
coupling = ")"
    << coupling << "\"\n";
  if (modes > 0) s << "modes = " << modes << "\n";
  s << R"(angular_velocity = [0.5, -1.0, 2.0]
[[body.marker]]
name = "end"
point = "b"
z = [0.0, 0.3, 1.0]
x = [1.0, 0.0, 0.0]
[[body]]
name = "r"
type = "rigid"
mass = 3.0
inertia = [0.05, 0.04, 0.06, 0.001, 0.002, 0.003]
position = [1.0, 0.05, 0.0]
[[body.marker]]
name = "m"
at = [0.0, -0.05, 0.0]
z = [0.0, 0.3, 1.0]
x = [1.0, 0.0, 0.0]
[[body.marker]]
name = "m2"
at = [0.0, 0.1, 0.02]
[[joint]]
name = "pin"
type = "revolute"
i = "beam.end"
j = "r.m"
[[force]]
name = "s"
type = "spring-damper"
i = "beam.a"
j = "r.m2"
k = 1.0e5
d = 300.0
free_length = 0.9
[[load]]
name = "tq"
type = "torque"
at = "beam.a"
direction = [0.3, 0.2, 1.0]
axes = "marker"
table = [[0.0, 50.0], [1.0, 50.0]]
[clock]
end_time = 0.01
)";
  return s.str();
}

struct Basis {
  const char* name;
  condense::ReductionMethod method;
  bool orthonormalize;
  int modes;
  bool stiffening = false;
};
const Basis kModal{"modal", condense::ReductionMethod::kModal, true, 6};
const Basis kCraigBampton{"craig_bampton", condense::ReductionMethod::kCraigBampton, false, 4};
const Basis kStiffened{"modal_stiffened", condense::ReductionMethod::kModal, true, 6, true};

struct JacobianCase {
  Basis basis;
  const char* coupling;
};
class FlexibleJacobian : public ::testing::TestWithParam<JacobianCase> {};

TEST_P(FlexibleJacobian, ModelJacobianMatchesDifferencesOfTheResidual) {
  const auto& c = GetParam();
  const fs::path dir = temp_dir(std::string("model_") + c.basis.name + "_" + c.coupling);
  write_beam(dir / "beam.h5", c.basis.method, c.basis.orthonormalize, c.basis.modes, c.basis.stiffening);
  double worst = 0;
  for (unsigned seed : {1u, 2u, 3u}) {
    Scene s = parse_scene(flexible_scene(c.coupling, 0), "flexible_jacobian.toml", dir);
    // modal coordinates up to 1e-2: modal rotations of the points up to ~0.05 rad
    const Comparison r = compare(s, seed, 1.0, 1e-2);
    worst = std::max(worst, r.worst);
    EXPECT_LT(r.worst, 1e-6) << c.basis.name << ", " << c.coupling << " (seed " << seed << "): worst at "
                             << r.where;
    EXPECT_LT(r.outside, 1e-9) << "the differences have entries outside the sparsity pattern";
  }
  std::printf("  %s, %s coupling: worst relative error of the model's Jacobian %.2e\n", c.basis.name,
              c.coupling, worst);
  fs::remove_all(dir);
}

// ---------------------------------------------------------------- 2. each function against the defaults
/// Largest |a - b| / (largest |b| of that row + 1e-4 of the largest |b| of the block): relative by rows. The
/// floor keeps rows that vanish in exact arithmetic from comparing the defaults' round-off (~1e-11 of the
/// block) with zero: in linear coupling the omega_x row of d/domega of the beam is 0 (its elastic modes are
/// mass-orthogonal to the rigid ones, so I_tilde_xy . eta = 0; a line beam has no I_yy, I_zz terms); entries
/// below 1e-4 of the block are so held to 1e-10 of it.
double row_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, std::string& where) {
  const double floor = 1e-4 * std::max(b.cwiseAbs().maxCoeff(), 1e-300);
  double worst = 0;
  for (int r = 0; r < b.rows(); ++r) {
    const double scale = b.row(r).cwiseAbs().maxCoeff() + floor;
    for (int c = 0; c < b.cols(); ++c) {
      const double e = std::abs(a(r, c) - b(r, c)) / scale;
      if (e > worst) {
        worst = e;
        where = "(" + std::to_string(r) + ", " + std::to_string(c) + "): closed form " +
                std::to_string(a(r, c)) + ", default " + std::to_string(b(r, c));
      }
    }
  }
  return worst;
}

struct RandomState {
  Eigen::VectorXd q, w, wdot;
  Vec3 force, torque;
};
RandomState random_state(const Body& body, std::mt19937& rng, double modal) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int nq = body.position_count(), nw = body.velocity_count();
  RandomState s;
  s.q.resize(nq);
  for (int k = 0; k < nq; ++k) s.q[k] = u(rng);
  s.q.segment<4>(3).normalize();
  s.q.tail(nq - 7) *= modal;
  s.w = 3.0 * Eigen::VectorXd::NullaryExpr(nw, [&] { return u(rng); });
  s.wdot = 30.0 * Eigen::VectorXd::NullaryExpr(nw, [&] { return u(rng); });
  s.force = 100.0 * Vec3(u(rng), u(rng), u(rng));
  s.torque = 10.0 * Vec3(u(rng), u(rng), u(rng));
  return s;
}

std::span<const double> span_of(const Eigen::VectorXd& v) {
  return {v.data(), std::size_t(v.size())};
}

/// The q columns of a derivative restricted to changes of p tangent to |p| = 1: the closed forms are exact
/// there; the radial direction (which scales A(p)) is the model's directional difference (model.cpp).
Eigen::MatrixXd tangent(Eigen::MatrixXd m, const Eigen::VectorXd& q) {
  const Eigen::Vector4d p = q.segment<4>(3);
  m.middleCols<4>(3) = (m.middleCols<4>(3) * (Eigen::Matrix4d::Identity() - p * p.transpose())).eval();
  return m;
}

/// The worst relative error of each of the five functions over `states` random states and all markers.
struct FunctionErrors {
  double wrench = 0, sensitivity = 0, wrench_derivative = 0, kinematic = 0, inertia = 0;
};
FunctionErrors check_functions(const FlexibleBody& body, unsigned seed, int states, double modal) {
  std::mt19937 rng(seed);
  const int nq = body.position_count(), nw = body.velocity_count();
  const Vec3 g(0.0, -9.81, 2.0);
  FunctionErrors worst;
  std::string where;
  for (int k = 0; k < states; ++k) {
    const RandomState s = random_state(body, rng, modal);
    const auto q = span_of(s.q), w = span_of(s.w), wd = span_of(s.wdot);
    for (int m = 0; m < static_cast<int>(body.markers().size()); ++m) {
      Eigen::VectorXd qa = Eigen::VectorXd::Zero(nw), qb = qa;
      body.add_wrench(m, q, s.force, s.torque, {qa.data(), std::size_t(nw)});
      body.Body::add_wrench(m, q, s.force, s.torque, {qb.data(), std::size_t(nw)});
      double e = row_error(qa, qb, where);
      EXPECT_LT(e, 1e-12) << "add_wrench, marker " << m << " " << where;
      worst.wrench = std::max(worst.wrench, e);

      Eigen::MatrixXd sa(12, nq), sb(12, nq);
      body.marker_sensitivity(m, q, w, sa);
      body.Body::marker_sensitivity(m, q, w, sb);
      e = row_error(tangent(sa, s.q), tangent(sb, s.q), where);
      EXPECT_LT(e, 1e-6) << "marker_sensitivity, marker " << m << " " << where;
      worst.sensitivity = std::max(worst.sensitivity, e);

      Eigen::MatrixXd da = Eigen::MatrixXd::Zero(nw, nq), db = da;
      body.add_wrench_derivative(m, q, s.force, s.torque, da);
      body.Body::add_wrench_derivative(m, q, s.force, s.torque, db);
      e = row_error(tangent(da, s.q), tangent(db, s.q), where);
      EXPECT_LT(e, 1e-6) << "add_wrench_derivative, marker " << m << " " << where;
      worst.wrench_derivative = std::max(worst.wrench_derivative, e);
    }
    Eigen::MatrixXd kqa(nq, nq), kwa(nq, nw), kqb(nq, nq), kwb(nq, nw);
    body.kinematic_jacobian(q, w, kqa, kwa);
    body.Body::kinematic_jacobian(q, w, kqb, kwb);
    double e = std::max(row_error(tangent(kqa, s.q), tangent(kqb, s.q), where), row_error(kwa, kwb, where));
    EXPECT_LT(e, 1e-6) << "kinematic_jacobian " << where;
    worst.kinematic = std::max(worst.kinematic, e);

    Eigen::MatrixXd iqa(nw, nq), iwa(nw, nw), iqb(nw, nq), iwb(nw, nw);
    body.inertia_jacobian(q, w, wd, g, iqa, iwa);
    body.Body::inertia_jacobian(q, w, wd, g, iqb, iwb);
    e = row_error(tangent(iqa, s.q), tangent(iqb, s.q), where);
    EXPECT_LT(e, 1e-6) << "inertia_jacobian d/dq " << where;
    const double ew = row_error(iwa, iwb, where);
    EXPECT_LT(ew, 1e-6) << "inertia_jacobian d/dw " << where;
    worst.inertia = std::max({worst.inertia, e, ew});
  }
  return worst;
}

TEST_P(FlexibleJacobian, EachDerivativeMatchesTheBaseClassDifferences) {
  const auto& c = GetParam();
  const fs::path dir = temp_dir(std::string("direct_") + c.basis.name + "_" + c.coupling);
  write_beam(dir / "beam.h5", c.basis.method, c.basis.orthonormalize, c.basis.modes, c.basis.stiffening);
  // The defaults' central differences (step 1e-7) carry a round-off of about eps |R| / 1e-7; at modal
  // coordinates of 0.1 the elastic forces K eta (up to 1e6 N) would drown them, so the body's stiffness is
  // scaled by 1e-3 here (K enters the derivatives as the block K alone; every other term is unchanged).
  FlexibleData data = load_flexible_data(dir / "beam.h5");
  data.stiffness *= 1e-3;
  const int tip = data.points[0].name == "b" ? 0 : 1;
  const Vec3 tip_at = data.points[tip].position;
  FlexibleBody body("beam", std::move(data),
                    std::string(c.coupling) == "full" ? Coupling::kFull : Coupling::kLinear, InitialState{},
                    {}, {}, {tip});
  body.add_marker({"end", tip_at, frame_from_z(Vec3(0.0, 0.3, 1.0), Vec3::UnitX()), -1});
  // modal coordinates up to 0.1: modal rotations of the points up to ~0.3 rad (T(theta) far from 1)
  for (double modal : {1e-3, 0.1}) {
    const FunctionErrors e = check_functions(body, 7u, 4, modal);
    std::printf(
        "  %s, %s, |eta| <= %g: add_wrench %.1e, marker_sensitivity %.1e, add_wrench_derivative %.1e, "
        "kinematic_jacobian %.1e, inertia_jacobian %.1e\n",
        c.basis.name, c.coupling, modal, e.wrench, e.sensitivity, e.wrench_derivative, e.kinematic,
        e.inertia);
  }
  fs::remove_all(dir);
}

// inertia_residual works by blocks without forming M(q): its w'-dependence must be mass_matrix (the model's
// Jacobian adds cj M), and M symmetric. Both are linear in w', so the difference is round-off only.
TEST_P(FlexibleJacobian, InertiaResidualIsLinearInTheAccelerationsWithTheMassMatrix) {
  const auto& c = GetParam();
  const fs::path dir = temp_dir(std::string("mass_") + c.basis.name + "_" + c.coupling);
  write_beam(dir / "beam.h5", c.basis.method, c.basis.orthonormalize, c.basis.modes, c.basis.stiffening);
  const FlexibleBody body("beam", load_flexible_data(dir / "beam.h5"),
                          std::string(c.coupling) == "full" ? Coupling::kFull : Coupling::kLinear,
                          InitialState{}, {}, {});
  std::mt19937 rng(11);
  const int nw = body.velocity_count();
  const Vec3 g(0.0, -9.81, 2.0);
  for (int k = 0; k < 4; ++k) {
    const RandomState s = random_state(body, rng, 0.1);
    const auto q = span_of(s.q), w = span_of(s.w);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(nw);
    Eigen::VectorXd r1(nw), r0(nw);
    body.inertia_residual(q, w, span_of(s.wdot), g, {r1.data(), std::size_t(nw)});
    body.inertia_residual(q, w, span_of(zero), g, {r0.data(), std::size_t(nw)});
    const Eigen::MatrixXd m = body.mass_matrix(q);
    const Eigen::VectorXd mw = m * s.wdot;
    const double scale = std::max(r1.cwiseAbs().maxCoeff(), r0.cwiseAbs().maxCoeff());
    EXPECT_LT((r1 - r0 - mw).cwiseAbs().maxCoeff(), 1e-12 * scale) << c.basis.name << ", " << c.coupling;
    EXPECT_LT((m - m.transpose()).cwiseAbs().maxCoeff(), 1e-14 * m.cwiseAbs().maxCoeff());
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(
    Superelements, FlexibleJacobian,
    ::testing::Values(JacobianCase{kModal, "full"}, JacobianCase{kModal, "linear"},
                      JacobianCase{kCraigBampton, "full"}, JacobianCase{kCraigBampton, "linear"},
                      JacobianCase{kStiffened, "full"}, JacobianCase{kStiffened, "linear"}),
    [](const auto& info) { return std::string(info.param.basis.name) + "_" + info.param.coupling; });

// ---------------------------------------------------------------- 3. no heap allocation
std::string dir_hint() {
  return fs::temp_directory_path().string();
}
TEST(FlexibleJacobianFunctions, DoNotAllocate) {
#if defined(NVH_COUNT_ALLOCATIONS)
  {  // the counter sees an allocation (Eigen's, through malloc)
    g_allocations = 0;
    g_counting = true;
    Eigen::VectorXd probe(static_cast<int>(dir_hint().size()) + 17);
    probe.setConstant(1.0);
    g_counting = false;
    ASSERT_GT(g_allocations.load(), 0) << "allocation counting does not work here";
    EXPECT_EQ(probe.sum(), probe.size());
  }
  const fs::path dir = temp_dir("alloc");
  write_beam(dir / "beam.h5", condense::ReductionMethod::kModal, true, 30);
  for (const char* coupling : {"full", "linear"}) {
    Scene s = parse_scene(flexible_scene(coupling, 0), "flexible_jacobian.toml", dir);
    const auto& body = dynamic_cast<const FlexibleBody&>(*s.model.bodies[0]);
    std::mt19937 rng(3);
    const RandomState st = random_state(body, rng, 0.05);
    const int nq = body.position_count(), nw = body.velocity_count();
    Eigen::VectorXd gen = Eigen::VectorXd::Zero(nw);
    Eigen::MatrixXd sens(12, nq), dq(nw, nq), kq(nq, nq), kw(nq, nw), iq(nw, nq), iw(nw, nw);
    dq.setZero();
    const auto q = span_of(st.q), w = span_of(st.w), wd = span_of(st.wdot);
    const Vec3 g(0, 0, -9.81);
    g_allocations = 0;
    g_counting = true;
    for (int m = 0; m < static_cast<int>(body.markers().size()); ++m) {
      body.add_wrench(m, q, st.force, st.torque, {gen.data(), std::size_t(nw)});
      body.marker_sensitivity(m, q, w, sens);
      body.add_wrench_derivative(m, q, st.force, st.torque, dq);
    }
    body.kinematic_jacobian(q, w, kq, kw);
    body.inertia_jacobian(q, w, wd, g, iq, iw);
    g_counting = false;
    EXPECT_EQ(g_allocations.load(), 0) << coupling << " coupling: heap allocations in the derivatives";

    // the inertial rows and the damping power (called by every residual) do not allocate; the mass matrix
    // (the Jacobian's) only its result
    Eigen::VectorXd rows(nw);
    g_allocations = 0;
    g_counting = true;
    body.inertia_residual(q, w, wd, g, {rows.data(), std::size_t(nw)});
    const double power = body.dissipated_power(q, w);
    g_counting = false;
    EXPECT_EQ(g_allocations.load(), 0)
        << coupling << " coupling: heap allocations in the residual's functions";
    EXPECT_GE(power, 0.0);
    g_allocations = 0;
    g_counting = true;
    const Eigen::MatrixXd mass = body.mass_matrix(q);
    g_counting = false;
    EXPECT_EQ(g_allocations.load(), 1) << coupling << " coupling: mass_matrix allocates more than its result";
    EXPECT_EQ(mass.rows(), nw);
  }
  fs::remove_all(dir);
#else
  GTEST_SKIP() << "allocation counting needs glibc and no AddressSanitizer (its malloc comes first)";
#endif
}

#if defined(NVH_COUNT_ALLOCATIONS)
/// Heap allocations of one Model::residual and one Model::jacobian at the consistent start, once the
/// workspace is warm.
std::pair<long, long> allocations_of(Model& m) {
  std::ostringstream sink;
  const Logger log(sink, "test", Verbosity::kQuiet);
  Eigen::VectorXd y, yp;
  m.consistent_initial_state(0.0, y, yp, log);
  Eigen::VectorXd f(m.size());
  std::vector<double> values;
  m.residual(0.0, y.data(), yp.data(), f.data());
  m.jacobian(0.0, y.data(), yp.data(), 100.0, values);  // warm: the workspace and `values` get their sizes
  g_allocations = 0;
  g_counting = true;
  m.residual(0.001, y.data(), yp.data(), f.data());
  g_counting = false;
  const long residual = g_allocations.load();
  g_allocations = 0;
  g_counting = true;
  m.jacobian(0.001, y.data(), yp.data(), 200.0, values);
  g_counting = false;
  return {residual, g_allocations.load()};
}
#endif

// The whole model: a flexible and a rigid body, a revolute joint, a spring-damper and a load. The residual
// (called once per Newton iteration) and the Jacobian allocate nothing once the workspace is warm.
TEST(ModelResidualAndJacobian, DoNotAllocate) {
#if defined(NVH_COUNT_ALLOCATIONS)
  const fs::path dir = temp_dir("alloc_model");
  write_beam(dir / "beam.h5", condense::ReductionMethod::kModal, true, 30);
  for (const char* coupling : {"full", "linear"}) {
    Scene s = parse_scene(flexible_scene(coupling, 0), "flexible_jacobian.toml", dir);
    const auto [residual, jacobian] = allocations_of(s.model);
    std::printf("measured: %s coupling: heap allocations per residual %ld, per Jacobian %ld\n", coupling,
                residual, jacobian);
    EXPECT_EQ(residual, 0) << coupling;
    EXPECT_EQ(jacobian, 0) << coupling;
  }
  fs::remove_all(dir);
#else
  GTEST_SKIP() << "allocation counting needs glibc and no AddressSanitizer (its malloc comes first)";
#endif
}

// The same for a flexible body on a fixed axis (solve/flexible_rotor_body.hpp): the beam clamped at its root,
// turning on the axis z there, a spring from its tip to a rigid body, a torque at the tip, gravity.
TEST(ModelResidualAndJacobian, DoNotAllocateOnAFixedAxis) {
#if defined(NVH_COUNT_ALLOCATIONS)
  const fs::path dir = temp_dir("alloc_rotor");
  {
    condense::BeamSection sec = circle(0.02);
    condense::Component c = straight_beam(1.0, sec, 16, Steel{});
    condense::Support root;
    root.dofs.fill(true);
    c.supports = {root};
    c.interfaces = {point("b", {1.0, 0, 0})};
    c.reduction.method = condense::ReductionMethod::kCraigBampton;
    c.reduction.modes = 6;
    c.reduction.damping_ratio = 0.02;
    std::ostringstream quiet;
    const Logger log(quiet, "test", Verbosity::kQuiet);
    condense::write_superelement(dir / "clamped.h5",
                                 condense::condense_component(c, condense::EigenBackend::kBlockLanczos, log),
                                 make_provenance("test", 0, nullptr, {}));
  }
  Scene s = parse_scene(R"([scene]
gravity = [0, -9.81, 2.0]
[[body]]
name = "beam"
type = "flexible"
superelement = "clamped.h5"
axis = [0, 0, 1]
speed = 3.0
[[body]]
name = "r"
type = "rigid"
mass = 2.0
inertia = [0.05, 0.04, 0.06]
position = [1.05, 0.1, 0.02]
[[body.marker]]
name = "m"
[[force]]
name = "s"
type = "spring-damper"
i = "beam.b"
j = "r.m"
k = 1.0e4
d = 30.0
free_length = 0.1
[[load]]
name = "tq"
type = "torque"
at = "beam.b"
direction = [0.3, 0.2, 1.0]
axes = "marker"
table = [[0.0, 5.0], [1.0, 5.0]]
[clock]
end_time = 0.01
)",
                        "rotor_alloc.toml", dir);
  ASSERT_EQ(s.model.bodies[0]->kind(), "flexible-rotor");
  const auto [residual, jacobian] = allocations_of(s.model);
  std::printf("measured: on a fixed axis: heap allocations per residual %ld, per Jacobian %ld\n", residual,
              jacobian);
  EXPECT_EQ(residual, 0);
  EXPECT_EQ(jacobian, 0);
  fs::remove_all(dir);
#else
  GTEST_SKIP() << "allocation counting needs glibc and no AddressSanitizer (its malloc comes first)";
#endif
}

// ---------------------------------------------------------------- 4. time of the model's Jacobian
/// A body that forwards everything to a flexible body but its derivatives: it inherits Body's defaults
/// (local differences, add_wrench through marker_jacobian) - the state before the closed forms.
class WithDefaultDerivatives final : public Body {
 public:
  explicit WithDefaultDerivatives(std::unique_ptr<Body> inner) : Body(inner->name()), b_(std::move(inner)) {
    for (const auto& m : b_->markers()) add_marker(m);
  }
  std::string kind() const override { return b_->kind(); }
  int position_count() const override { return b_->position_count(); }
  int velocity_count() const override { return b_->velocity_count(); }
  Eigen::VectorXd initial_positions() const override { return b_->initial_positions(); }
  Eigen::VectorXd initial_velocities() const override { return b_->initial_velocities(); }
  void kinematic_residual(std::span<const double> q, std::span<const double> qdot,
                          std::span<const double> w_eff, std::span<const double> alg, std::span<double> rows,
                          std::span<double> alg_rows) const override {
    b_->kinematic_residual(q, qdot, w_eff, alg, rows, alg_rows);
  }
  Eigen::VectorXd position_rates(std::span<const double> q, std::span<const double> w) const override {
    return b_->position_rates(q, w);
  }
  void inertia_residual(std::span<const double> q, std::span<const double> w, std::span<const double> wdot,
                        const Vec3& gravity, std::span<double> rows) const override {
    b_->inertia_residual(q, w, wdot, gravity, rows);
  }
  using Body::marker_jacobian;
  using Body::mass_matrix;
  void mass_matrix(std::span<const double> q, Eigen::Ref<Eigen::MatrixXd> m) const override {
    b_->mass_matrix(q, m);
  }
  MarkerMotion marker_motion(int marker, std::span<const double> q,
                             std::span<const double> w) const override {
    return b_->marker_motion(marker, q, w);
  }
  void marker_jacobian(int marker, std::span<const double> q, Eigen::Ref<Mat3X> jv,
                       Eigen::Ref<Mat3X> jw) const override {
    b_->marker_jacobian(marker, q, jv, jw);
  }
  Vec3 reference_position(std::span<const double> q) const override { return b_->reference_position(q); }
  Mat3 rotation(std::span<const double> q) const override { return b_->rotation(q); }
  double kinetic_energy(std::span<const double> q, std::span<const double> w) const override {
    return b_->kinetic_energy(q, w);
  }
  double potential_energy(std::span<const double> q, const Vec3& gravity) const override {
    return b_->potential_energy(q, gravity);
  }
  double dissipated_power(std::span<const double> q, std::span<const double> w) const override {
    return b_->dissipated_power(q, w);
  }

 private:
  std::unique_ptr<Body> b_;
};

TEST(FlexibleJacobianTiming, ThirtyModes) {
  const fs::path dir = temp_dir("timing");
  write_beam(dir / "beam.h5", condense::ReductionMethod::kModal, true, 30);
  Scene s = parse_scene(flexible_scene("full", 30), "flexible_jacobian.toml", dir);
  Model& m = s.model;
  ASSERT_EQ(m.bodies[0]->velocity_count(), 36);
  std::ostringstream sink;
  const Logger log(sink, "test", Verbosity::kQuiet);
  Eigen::VectorXd y, yp;
  m.consistent_initial_state(0.0, y, yp, log);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < m.lambda_offset(); ++k) yp[k] += u(rng);
  std::vector<double> closed, defaults;
  auto time_of = [&](std::vector<double>& values, int repeat) {
    m.jacobian(0.0, y.data(), yp.data(), 100.0, values);  // warm-up
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < repeat; ++k) m.jacobian(0.0, y.data(), yp.data(), 100.0, values);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / repeat;
  };
  const double t_closed = time_of(closed, 200);
  m.bodies[0] = std::make_unique<WithDefaultDerivatives>(std::move(m.bodies[0]));
  const double t_defaults = time_of(defaults, 20);
  std::printf(
      "  Model::jacobian, beam of 30 modes + rigid body (n = %d): closed forms %.3f ms, defaults %.3f ms "
      "(%.1fx)\n",
      m.size(), 1e3 * t_closed, 1e3 * t_defaults, t_defaults / t_closed);
  ASSERT_EQ(closed.size(), defaults.size());
  double worst = 0, scale = 0;
  for (std::size_t k = 0; k < closed.size(); ++k) {
    worst = std::max(worst, std::abs(closed[k] - defaults[k]));
    scale = std::max(scale, std::abs(defaults[k]));
  }
  EXPECT_LT(worst, 1e-6 * scale) << "the two Jacobians differ";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace nvh::solve
