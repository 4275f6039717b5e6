// The ideal cam joint: the roller's centre on the cam's pitch curve (cam_joint.hpp, eqs. CJ1-CJ2).
#include "solve/cam/cam_joint.hpp"

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
    // The cam's frame orthonormalized: a rigid body's axes come from Euler parameters whose norm drifts by
    // round-off (held near 1 by a stabilizing term, body.hpp), and A(p) is then not a rotation. With c = A^T
    // r the position-level equation followed that drift at the lobe's radius and fought the normalization:
    // IDA took 0.4 us steps at order 1 on the base circle of the kinematic valvetrains (270,000 steps against
    // 4,500 with this; the camshaft's Euler parameters held the error test).
    Mat3 a = j.axes;
    a.col(0).normalize();
    a.col(1) = (a.col(1) - a.col(1).dot(a.col(0)) * a.col(0)).normalized();
    a.col(2) = a.col(0).cross(a.col(1));
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
