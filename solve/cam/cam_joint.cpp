// The ideal cam joint: the roller's centre on the cam's pitch curve (cam_joint.hpp, eqs. CJ1-CJ2).
#include "solve/cam/cam_joint.hpp"

#include "solve/rotation.hpp"

namespace nvh::solve {
namespace {

class CamJoint final : public Constraint {
 public:
  explicit CamJoint(std::shared_ptr<const cam::CamProfile> profile) : profile_(std::move(profile)) {}
  std::string type() const override { return "cam"; }
  int size() const override { return 1; }
  std::vector<std::string> equation_names() const override { return {"pitch-gap"}; }

  void evaluate(double, const MarkerMotion& i, const MarkerMotion& j,
                ConstraintEquations& out) const override {
    const Vec3 r = i.position - j.position;
    // The cam's frame orthonormalized (rotation.hpp): with the raw axes the position-level equation followed
    // the Euler parameters' norm drift at the lobe's radius and fought the normalization: IDA took 0.4 us
    // steps at order 1 on the base circle of the kinematic valvetrains (270,000 steps against 4,500 with
    // this; the camshaft's Euler parameters held the error test).
    const Mat3 a = orthonormalized(j.axes);
    const Vec3 c = a.transpose() * r;
    const cam::PitchFoot foot = cam::pitch_foot(*profile_, c.x(), c.y());
    const Vec3 n = a * Vec3(foot.point.nx, foot.point.ny, 0.0);
    out.phi[0] = foot.gap;                     // (CJ1)
    out.di.block<1, 3>(0, 0) = n.transpose();  // (CJ2)
    out.dj.block<1, 3>(0, 0) = -n.transpose();
    out.dj.block<1, 3>(0, 3) = -r.cross(n).transpose();
  }

 private:
  std::shared_ptr<const cam::CamProfile> profile_;
};

}  // namespace

std::unique_ptr<Constraint> make_cam_joint(std::shared_ptr<const cam::CamProfile> profile) {
  return std::make_unique<CamJoint>(std::move(profile));
}

}  // namespace nvh::solve
