// Joint primitives and the joints built from them (see constraint.hpp).
#include "solve/constraint.hpp"

#include <cmath>

namespace nvh::solve {
namespace {

// Rows of the primitives, written into `out` from row `r`.
void point(const MarkerMotion& i, const MarkerMotion& j, ConstraintEquations& out, int r) {
  out.phi.segment<3>(r) = i.position - j.position;
  out.di.block<3, 3>(r, 0) = Mat3::Identity();
  out.dj.block<3, 3>(r, 0) = -Mat3::Identity();
}

// a_i . b_j = 0: d/dt = omega_i . (a_i x b_j) + omega_j . (b_j x a_i).
void dot1(const Vec3& a_i, const Vec3& b_j, ConstraintEquations& out, int r) {
  out.phi[r] = a_i.dot(b_j);
  out.di.block<1, 3>(r, 3) = a_i.cross(b_j).transpose();
  out.dj.block<1, 3>(r, 3) = b_j.cross(a_i).transpose();
}

// b_j . d = 0 with d = p_i - p_j: d/dt = b_j . (v_i - v_j) + omega_j . (b_j x d).
void dot2(const MarkerMotion& i, const MarkerMotion& j, const Vec3& b_j, ConstraintEquations& out, int r) {
  const Vec3 d = i.position - j.position;
  out.phi[r] = b_j.dot(d);
  out.di.block<1, 3>(r, 0) = b_j.transpose();
  out.dj.block<1, 3>(r, 0) = -b_j.transpose();
  out.dj.block<1, 3>(r, 3) = b_j.cross(d).transpose();
}

class Joint final : public Constraint {
 public:
  explicit Joint(JointType t) : type_(t), size_(static_cast<int>(equation_names().size())) {}
  std::string type() const override {
    switch (type_) {
      case JointType::kFixed: return "fixed";
      case JointType::kRevolute: return "revolute";
      case JointType::kSpherical: return "spherical";
      case JointType::kPrismatic: return "prismatic";
      case JointType::kCylindrical: return "cylindrical";
      case JointType::kInLine:
        return "in-line";
    }
    return "?";
  }
  int size() const override { return size_; }
  std::vector<std::string> equation_names() const override {
    const std::vector<std::string> pt = {"point-x", "point-y", "point-z"};
    const std::vector<std::string> axis = {"z_i.x_j", "z_i.y_j"};
    const std::vector<std::string> line = {"x_j.d", "y_j.d"};
    auto cat = [](std::vector<std::string> a, const std::vector<std::string>& b) {
      a.insert(a.end(), b.begin(), b.end());
      return a;
    };
    switch (type_) {
      case JointType::kSpherical: return pt;
      case JointType::kRevolute: return cat(pt, axis);
      case JointType::kFixed: return cat(cat(pt, axis), {"x_i.y_j"});
      case JointType::kCylindrical: return cat(axis, line);
      case JointType::kPrismatic: return cat(cat(axis, line), {"x_i.y_j"});
      case JointType::kInLine:
        return line;
    }
    return {};
  }
  void evaluate(double, const MarkerMotion& i, const MarkerMotion& j, ConstraintEquations& out) const override {
    const Vec3 xi = i.axes.col(0), zi = i.axes.col(2);
    const Vec3 xj = j.axes.col(0), yj = j.axes.col(1);
    switch (type_) {
      case JointType::kSpherical: point(i, j, out, 0); break;
      case JointType::kRevolute:
        point(i, j, out, 0);
        dot1(zi, xj, out, 3);
        dot1(zi, yj, out, 4);
        break;
      case JointType::kFixed:
        point(i, j, out, 0);
        dot1(zi, xj, out, 3);
        dot1(zi, yj, out, 4);
        dot1(xi, yj, out, 5);
        break;
      case JointType::kCylindrical:
        dot1(zi, xj, out, 0);
        dot1(zi, yj, out, 1);
        dot2(i, j, xj, out, 2);
        dot2(i, j, yj, out, 3);
        break;
      case JointType::kPrismatic:
        dot1(zi, xj, out, 0);
        dot1(zi, yj, out, 1);
        dot2(i, j, xj, out, 2);
        dot2(i, j, yj, out, 3);
        dot1(xi, yj, out, 4);
        break;
      case JointType::kInLine:  // point on line: the two dot-2 rows of the cylindrical joint
        dot2(i, j, xj, out, 0);
        dot2(i, j, yj, out, 1);
        break;
    }
  }

 private:
  JointType type_;
  int size_;  // equation_names() builds strings: not for the residual's loops
};

// |d| = L as (d.d - L^2) / (2 L): d/dt = d . (v_i - v_j) / L.
class DistanceJoint final : public Constraint {
 public:
  explicit DistanceJoint(double length) : length_(length) {}
  std::string type() const override { return "distance"; }
  int size() const override { return 1; }
  std::vector<std::string> equation_names() const override { return {"|d|-L"}; }
  void evaluate(double, const MarkerMotion& i, const MarkerMotion& j, ConstraintEquations& out) const override {
    const Vec3 d = i.position - j.position;
    out.phi[0] = (d.squaredNorm() - length_ * length_) / (2.0 * length_);
    out.di.block<1, 3>(0, 0) = d.transpose() / length_;
    out.dj.block<1, 3>(0, 0) = -d.transpose() / length_;
  }

 private:
  double length_;
};

class InPlaneJoint final : public Constraint {
 public:
  explicit InPlaneJoint(double offset) : offset_(offset) {}
  std::string type() const override { return "in-plane"; }
  int size() const override { return 1; }
  std::vector<std::string> equation_names() const override { return {"z_j.d"}; }
  void evaluate(double, const MarkerMotion& i, const MarkerMotion& j, ConstraintEquations& out) const override {
    dot2(i, j, j.axes.col(2), out, 0);
    out.phi[0] -= offset_;
  }

 private:
  double offset_;
};

}  // namespace

std::unique_ptr<Constraint> make_joint(JointType type) { return std::make_unique<Joint>(type); }
std::unique_ptr<Constraint> make_distance_joint(double length) { return std::make_unique<DistanceJoint>(length); }
std::unique_ptr<Constraint> make_in_plane_joint(double offset) { return std::make_unique<InPlaneJoint>(offset); }

double relative_angle(const MarkerMotion& i, const MarkerMotion& j) {
  const Vec3 xi = i.axes.col(0);
  return std::atan2(xi.dot(j.axes.col(1)), xi.dot(j.axes.col(0)));
}

// Phi = x_i . b with b = cos(theta) y_j - sin(theta) x_j, i.e. sin(angle - theta) for a revolute pair.
void AngleDriver::evaluate(double t, const MarkerMotion& i, const MarkerMotion& j,
                           ConstraintEquations& out) const {
  const double th = theta_(t), c = std::cos(th), s = std::sin(th);
  const Vec3 xi = i.axes.col(0), xj = j.axes.col(0), yj = j.axes.col(1);
  const Vec3 b = c * yj - s * xj;
  out.phi[0] = xi.dot(b);
  out.di.block<1, 3>(0, 3) = xi.cross(b).transpose();
  out.dj.block<1, 3>(0, 3) = b.cross(xi).transpose();
  out.phi_t[0] = xi.dot(-s * yj - c * xj) * rate_(t);
}


// phi = z_j . d - offset - s(theta(t)), d = p_i - p_j. Rates: d' = v_i - v_j, z_j' = omega_j x z_j, so
// (z_j . d)' = z_j . (v_i - v_j) + omega_j . (z_j x d); phi_t = -s'(theta) theta'.
void LiftDriver::evaluate(double t, const MarkerMotion& i, const MarkerMotion& j, ConstraintEquations& out) const {
  const Vec3 z = j.axes.col(2), d = i.position - j.position;
  const auto [s, ds] = lift_(theta_(t));
  out.phi[0] = z.dot(d) - offset_ - s;
  out.di.block<1, 3>(0, 0) = z.transpose();
  out.dj.block<1, 3>(0, 0) = -z.transpose();
  out.dj.block<1, 3>(0, 3) = z.cross(d).transpose();
  out.phi_t[0] = -ds * rate_(t);
}

namespace {
double time_itself(double t) {
  return t;
}
double unit_rate(double) {
  return 1.0;
}

// (D1): a LiftDriver whose "cam angle" is the time itself (theta = t, theta' = 1).
class DisplacementDriver final : public Constraint {
 public:
  DisplacementDriver(std::function<std::pair<double, double>(double)> motion, double offset)
      : lift_(std::move(motion), time_itself, unit_rate, offset) {}
  std::string type() const override { return "displacement-driver"; }
  bool is_driver() const override { return true; }
  int size() const override { return 1; }
  std::vector<std::string> equation_names() const override { return {"displacement"}; }
  void evaluate(double t, const MarkerMotion& i, const MarkerMotion& j,
                ConstraintEquations& out) const override {
    lift_.evaluate(t, i, j, out);
  }

 private:
  LiftDriver lift_;
};
}  // namespace

std::unique_ptr<Constraint> make_displacement_driver(std::function<std::pair<double, double>(double)> motion,
                                                     double offset) {
  return std::make_unique<DisplacementDriver>(std::move(motion), offset);
}

}  // namespace nvh::solve
