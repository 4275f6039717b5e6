// The free rigid slider-crank of bench/simbody/slider_crank_free.toml, modelled in Simbody (relative
// coordinates): the peer of solve in bench/run_simbody_bench.sh. Same masses, inertias, lengths, gravity
// and initial conditions; every number below is also in the scene file.
//
//   simbody_slider_crank_free ACCURACY [rkm|cpodes|rkf|rk3] [END_TIME]
//
// Tree: ground -Pin(z)-> crank -Pin(z)-> conrod;  ground -Slider(along global y)-> piston.
// Loop closure: the conrod's small end on the line through the piston pin along z (Constraint::PointOnLine,
// exactly the 2 independent equations of a planar pin: no redundant equations). Three mobilities, one
// degree of freedom. Integrates from 0 to END_TIME (default 1 s) with the given integrator (default
// Runge-Kutta-Merson, Simbody's usual choice) at the given accuracy (the constraint tolerance is left at
// Simbody's default, tied to the accuracy), and prints one line: the final crank angle (unwrapped, rad),
// crank speed, piston height, the step counts and the CPU time of the integration (std::clock; set-up and
// process start excluded - the bench script measures the whole process too).
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <string>

#include "Simbody.h"

using namespace SimTK;

int main(int argc, char** argv) {
  if (argc < 2 || argc > 4) {
    std::fprintf(stderr, "usage: simbody_slider_crank_free ACCURACY [rkm|cpodes|rkf|rk3] [END_TIME]\n");
    return 2;
  }
  const double accuracy = std::atof(argv[1]);
  const std::string method = argc > 2 ? argv[2] : "rkm";
  const double end_time = argc > 3 ? std::atof(argv[3]) : 1.0;

  // The mechanism (SI): crank radius, conrod length, initial crank speed, gravity.
  const double r = 0.05, l = 0.2, w0 = 10 * Pi, g = 9.81;

  MultibodySystem system;
  SimbodyMatterSubsystem matter(system);
  GeneralForceSubsystem forces(system);
  Force::UniformGravity gravity(forces, matter, Vec3(0, -g, 0));

  // Body frames at the centres of mass (as in solve), inertias about them in body axes.
  const Body::Rigid crank_body(MassProperties(2.0, Vec3(0), Inertia(0.002, 0.002, 0.003)));
  const Body::Rigid conrod_body(MassProperties(0.6, Vec3(0), Inertia(0.002, 0.0001, 0.002)));
  const Body::Rigid piston_body(MassProperties(0.4, Vec3(0), Inertia(0.0003, 0.0003, 0.0003)));

  // Crank about global z through the origin; at q = 0 its pin is at [0, r, 0] (top dead centre).
  MobilizedBody::Pin crank(matter.Ground(), Transform(), crank_body, Transform());
  // Conrod about z at the crank pin; its centre l/2 further along y at q = 0.
  MobilizedBody::Pin conrod(crank, Transform(Vec3(0, r, 0)), conrod_body, Transform(Vec3(0, -l / 2, 0)));
  // Piston slides along global y (a Slider moves along the x axis of its frames: turn them by 90 deg
  // about z on both sides so that the piston keeps the global orientation); q = piston height.
  const Rotation x_to_y(Pi / 2, ZAxis);
  MobilizedBody::Slider piston(matter.Ground(), Transform(x_to_y), piston_body, Transform(x_to_y));
  // Piston pin: the conrod's small end stays on the piston's z line through the pin.
  Constraint::PointOnLine pin(piston, UnitVec3(0, 0, 1), Vec3(0), conrod, Vec3(0, l / 2, 0));

  system.realizeTopology();
  State state = system.getDefaultState();
  crank.setQ(state, 0);
  conrod.setQ(state, 0);
  piston.setQ(state, r + l);
  crank.setU(state, w0);
  conrod.setU(state, -r * w0 / l - w0);  // absolute conrod rate -r w0 / l at top dead centre
  piston.setU(state, 0);
  system.realize(state, Stage::Velocity);

  std::unique_ptr<Integrator> integ;
  if (method == "rkm") integ = std::make_unique<RungeKuttaMersonIntegrator>(system);
  else if (method == "cpodes") integ = std::make_unique<CPodesIntegrator>(system);
  else if (method == "rkf") integ = std::make_unique<RungeKuttaFeldbergIntegrator>(system);
  else if (method == "rk3") integ = std::make_unique<RungeKutta3Integrator>(system);
  else {
    std::fprintf(stderr, "unknown integrator '%s' (rkm, cpodes, rkf, rk3)\n", method.c_str());
    return 2;
  }
  integ->setAccuracy(accuracy);
  integ->setInternalStepLimit(100000000);  // CPodes stops after 500 internal steps by default

  const std::clock_t start = std::clock();
  TimeStepper stepper(system, *integ);
  stepper.initialize(state);
  if (end_time > 0) stepper.stepTo(end_time);
  const double cpu = double(std::clock() - start) / CLOCKS_PER_SEC;

  const State& s = integ->getState();
  system.realize(s, Stage::Velocity);
  // Energy check: kinetic + potential (gravity), against the start.
  const double energy0 = system.calcEnergy(state), energy = system.calcEnergy(s);
  std::printf(
      "simbody method=%s accuracy=%.3g t=%.17g crank_angle_rad=%.17g crank_speed=%.17g piston_y=%.17g "
      "steps=%d attempted=%d realizations=%d projections=%d energy_drift=%.3g cpu_s=%.6f\n",
      method.c_str(), accuracy, s.getTime(), crank.getOneQ(s, 0), crank.getOneU(s, 0), piston.getOneQ(s, 0),
      integ->getNumStepsTaken(), integ->getNumStepsAttempted(), integ->getNumRealizations(),
      integ->getNumProjections(), energy - energy0, cpu);
  return 0;
}
