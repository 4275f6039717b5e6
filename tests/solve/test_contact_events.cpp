// Contact events (integrator.hpp): the integrators locate the sign changes of the contact gaps, so an onset
// or a release is a step boundary. A ball dropped from height h onto a contact plane first touches it at
// t = sqrt(2 h / g); its bounce against the Hunt-Crossley closed form (the numbers of test_dynamics.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "solve/integrator.hpp"
#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::run_text;
using testing::hunt_crossley_rebound;
using testing::signal;

constexpr double kG = 9.81, kHeight = 0.05;
const std::string kHertz = "stiffness = 1e8\nexponent = 1.5";
const std::string kLinear = "stiffness = 2e8\nexponent = 1.0";  // piston_slap.toml's skirt contact

// A 0.5 kg point mass at height h above the ground's plane, gravity -z; contact with e = 0.7 at 1 m/s, Hertz
// (k = 1e8 N/m^1.5, the ball of test_dynamics.cpp) or linear (k = 2e8 N/m, the piston-slap skirt).
std::string drop_scene(const std::string& integrator, const std::string& contact) {
  std::ostringstream s;
  s.precision(17);
  s << R"(
[scene]
gravity = [0, 0, -9.81]
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "floor"
[[body]]
name = "ball"
type = "point-mass"
mass = 0.5
position = [0, 0, )"
    << kHeight << R"(]
  [[body.marker]]
  name = "c"
[[force]]
name = "impact"
type = "contact"
i = "ball.c"
j = "ground.floor"
restitution = 0.7
reference_speed = 1.0
)" << contact << R"(
[clock]
end_time = 0.11
)" << integrator;
  return s.str();
}

struct Drop {
  std::vector<ContactEvent> events;
  IntegratorStatistics statistics;
};

// Through the integrator itself (its event log), to t = 0.11 s: the fall (0.101 s), the impact, the rebound.
Drop drop(const std::string& integrator, const std::string& contact) {
  Scene scene = parse_scene(drop_scene(integrator, contact), "drop.toml", std::filesystem::path(NVH_SOURCE_DIR) / "testdata/scenes");
  std::ostringstream sink;
  const Logger log(sink, "solve", Verbosity::kQuiet);
  Eigen::VectorXd y, yp;
  scene.model.consistent_initial_state(0.0, y, yp, log);
  auto in = make_integrator(scene.model, scene.integrator, 0.0, y, yp);
  in->advance(scene.end_time, scene.end_time);
  return {in->events(), in->statistics()};
}

void expect_first_contact(const std::string& name, const std::string& integrator, const std::string& contact,
                          double tolerance) {
  const double t_contact = std::sqrt(2 * kHeight / kG);
  const Drop on = drop(integrator, contact);
  const Drop off = drop(integrator + "events = false\n", contact);
  ASSERT_GE(on.events.size(), 2u) << name;  // onset and release
  EXPECT_TRUE(on.events[0].onset);
  EXPECT_FALSE(on.events[1].onset);
  EXPECT_EQ(on.statistics.events, static_cast<long>(on.events.size()));
  EXPECT_EQ(off.statistics.events, 0);
  EXPECT_TRUE(off.events.empty());
  std::printf("measured: %s: first contact at %.12f s, closed form %.12f s (error %.2e s); contact %.3f ms; "
              "events %ld; steps %ld / %ld, rejected steps %ld / %ld, Newton failures %ld / %ld (events on / off)\n",
              name.c_str(), on.events[0].time, t_contact, on.events[0].time - t_contact,
              1e3 * (on.events[1].time - on.events[0].time), on.statistics.events, on.statistics.steps,
              off.statistics.steps, on.statistics.rejected_steps, off.statistics.rejected_steps,
              on.statistics.nonlinear_failures, off.statistics.nonlinear_failures);
  EXPECT_NEAR(on.events[0].time, t_contact, tolerance) << name;
  // Rejected steps: IDA's error-test failures; Newton failures cut the step too (both integrators).
  EXPECT_LT(on.statistics.rejected_steps + on.statistics.nonlinear_failures,
            off.statistics.rejected_steps + off.statistics.nonlinear_failures)
      << name;
}

TEST(ContactEvents, IdaFirstContactAtTheClosedFormWithFewerRejectedSteps) {
  expect_first_contact("IDA, Hertz", "[integrator]\nrtol = 1e-8\natol = 1e-10\n", kHertz, 1e-9);
  expect_first_contact("IDA, linear", "[integrator]\nrtol = 1e-8\natol = 1e-10\n", kLinear, 1e-9);
}

TEST(ContactEvents, GeneralizedAlphaFirstContactAtTheClosedFormWithFewerRejectedSteps) {
  // GA rejects a step only when Newton fails: at 100 us on the stiff linear contact, not on the Hertz one
  // (there: 0 with and without events).
  expect_first_contact("generalized-alpha 100 us, linear",
                       "[integrator]\nmethod = \"generalized-alpha\"\nstep = 1e-4\n", kLinear, 1e-9);
}

// ------------------------------------------------------------------ the bounce
// The ball of solve_fixture.hpp (kBallOnFloor): 0.5 kg at 1 mm, -1.5 m/s, no gravity; Hunt-Crossley k = 1e8, n = 1.5,
// e = 0.7 at 1 m/s. Rebound speed from G(v_out) = G(v_in), G(v) = v / alpha - ln(1 + alpha v) / alpha^2.

struct Bounce {
  double restitution = 0;
  long events = 0, steps = 0, rejected = 0;
};

Bounce bounce(const std::string& integrator, const std::string& name) {
  const std::string text = testing::kBallOnFloor + integrator;
  RunSummary summary;
  const auto file = run_text(text, name, &summary);
  const Eigen::VectorXd v = signal(file, "markers/ball.c/velocity", 2);
  const h5::File f = h5::File::open_read(file);
  const auto written = f.root().open_group("solver/statistics").int_attribute("events");
  EXPECT_EQ(written, summary.statistics.events);
  return {v[v.size() - 1] / 1.5, summary.statistics.events, summary.statistics.steps,
          summary.statistics.rejected_steps};
}

TEST(ContactEvents, BounceRestitutionAgainstHuntCrossley) {
  const double expected = hunt_crossley_rebound(3 * (1 - 0.7) / 2.0, 1.5) / 1.5;
  struct Case {
    const char* name;
    std::string integrator;
    double tolerance;
  };
  const Case cases[] = {
      {"IDA rtol 1e-10", "[integrator]\nrtol = 1e-10\natol = 1e-12\nmax_step = 1e-5\n", 1e-5},
      {"IDA rtol 1e-6", "[integrator]\nrtol = 1e-6\natol = 1e-8\n", 1e-3},
      {"generalized-alpha 1 us", "[integrator]\nmethod = \"generalized-alpha\"\nstep = 1e-6\n", 2e-3},
      {"generalized-alpha 10 us", "[integrator]\nmethod = \"generalized-alpha\"\nstep = 1e-5\n", 2e-2},
  };
  int n = 0;
  for (const Case& c : cases) {
    const Bounce on = bounce(c.integrator, "bounce_on_" + std::to_string(n));
    const Bounce off = bounce(c.integrator + "events = false\n", "bounce_off_" + std::to_string(n++));
    std::printf("measured: %s: restitution %.8f (events on, %ld events, %ld steps, %ld rejected) / %.8f (off, %ld "
                "steps, %ld rejected); closed form %.8f\n",
                c.name, on.restitution, on.events, on.steps, on.rejected, off.restitution, off.steps, off.rejected,
                expected);
    EXPECT_EQ(on.events, 2) << c.name;
    EXPECT_EQ(off.events, 0) << c.name;
    EXPECT_NEAR(on.restitution, expected, c.tolerance) << c.name;
  }
}

}  // namespace
}  // namespace nvh::solve
