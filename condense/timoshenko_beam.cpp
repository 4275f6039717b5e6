#include "condense/timoshenko_beam.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "common/error.hpp"

namespace nvh::condense {
namespace {

using Row12 = Eigen::Matrix<double, 1, 12>;

// Local DOF indices.
constexpr int kU[2] = {0, 6};
constexpr int kRx[2] = {3, 9};
constexpr int kPlaneXY[4] = {1, 5, 7, 11};  // v1, rz1, v2, rz2
constexpr int kPlaneXZ[4] = {2, 4, 8, 10};  // w1, ry1, w2, ry2
// In the x-z plane ry = -dw/dx, so (w, -ry) behaves as (v, rz): flip the sign of the rotation DOF.
constexpr double kSignXZ[4] = {1.0, -1.0, 1.0, -1.0};

/// 4x4 Timoshenko bending stiffness for (v1, rz1, v2, rz2) (Przemieniecki 1968, eq. 5.118).
Eigen::Matrix4d bending_stiffness(double EI, double L, double phi) {
  const double c = EI / ((1.0 + phi) * L * L * L);
  const double L2 = L * L;
  Eigen::Matrix4d k;
  k << 12.0, 6.0 * L, -12.0, 6.0 * L,                         //
      6.0 * L, (4.0 + phi) * L2, -6.0 * L, (2.0 - phi) * L2,  //
      -12.0, -6.0 * L, 12.0, -6.0 * L,                        //
      6.0 * L, (2.0 - phi) * L2, -6.0 * L, (4.0 + phi) * L2;
  return c * k;
}

/// Interdependent interpolation of deflection and section rotation for (v1, rz1, v2, rz2) at xi = x/L
/// (Friedman and Kosmatka 1993, eq. 15-16). Exact for a Timoshenko beam without distributed load.
struct BendingShape {
  Eigen::RowVector4d deflection;  // N_v
  Eigen::RowVector4d rotation;    // N_theta
};
BendingShape bending_shape(double xi, double L, double phi) {
  const double c = 1.0 / (1.0 + phi);
  const double x2 = xi * xi, x3 = x2 * xi;
  BendingShape s;
  s.deflection << c * (2.0 * x3 - 3.0 * x2 - phi * xi + 1.0 + phi),
      c * L * (x3 - (2.0 + 0.5 * phi) * x2 + (1.0 + 0.5 * phi) * xi), c * (-2.0 * x3 + 3.0 * x2 + phi * xi),
      c * L * (x3 - (1.0 - 0.5 * phi) * x2 - 0.5 * phi * xi);
  s.rotation << c * 6.0 / L * (x2 - xi), c * (3.0 * x2 - (4.0 + phi) * xi + 1.0 + phi),
      -c * 6.0 / L * (x2 - xi), c * (3.0 * x2 - (2.0 - phi) * xi);
  return s;
}

/// d/dx of the deflection interpolation above (the slope of the centre line), for the geometric stiffness.
Eigen::RowVector4d deflection_slope(double xi, double L, double phi) {
  const double c = 1.0 / (1.0 + phi);
  const double x2 = xi * xi;
  Eigen::RowVector4d d;
  d << c * (6.0 * x2 - 6.0 * xi - phi) / L, c * (3.0 * x2 - (4.0 + phi) * xi + 1.0 + 0.5 * phi),
      c * (-6.0 * x2 + 6.0 * xi + phi) / L, c * (3.0 * x2 - (2.0 - phi) * xi - 0.5 * phi);
  return d;
}

/// The centre-line fields at xi as rows over the 12 local DOF.
struct CentreLine {
  Row12 u, v, w, rx, ry, rz;
};
CentreLine centre_line(const BeamElementData& e, double xi) {
  CentreLine n;
  n.u.setZero();
  n.v.setZero();
  n.w.setZero();
  n.rx.setZero();
  n.ry.setZero();
  n.rz.setZero();
  n.u(kU[0]) = 1.0 - xi;
  n.u(kU[1]) = xi;
  n.rx(kRx[0]) = 1.0 - xi;
  n.rx(kRx[1]) = xi;
  const BendingShape xy = bending_shape(xi, e.L, e.phi_z());
  const BendingShape xz = bending_shape(xi, e.L, e.phi_y());
  for (int i = 0; i < 4; ++i) {
    n.v(kPlaneXY[i]) = xy.deflection(i);
    n.rz(kPlaneXY[i]) = xy.rotation(i);
    // w = N_v (w1, -ry1, w2, -ry2) and ry = -N_theta (w1, -ry1, w2, -ry2).
    n.w(kPlaneXZ[i]) = kSignXZ[i] * xz.deflection(i);
    n.ry(kPlaneXZ[i]) = -kSignXZ[i] * xz.rotation(i);
  }
  return n;
}

// 4-point Gauss-Legendre rule on [0, 1]: exact for the degree-6 products of cubic shape functions.
constexpr double kGaussPoint[4] = {0.5 * (1.0 - 0.8611363115940526), 0.5 * (1.0 - 0.3399810435848563),
                                   0.5 * (1.0 + 0.3399810435848563), 0.5 * (1.0 + 0.8611363115940526)};
constexpr double kGaussWeight[4] = {0.5 * 0.3478548451374538, 0.5 * 0.6521451548625461,
                                    0.5 * 0.6521451548625461, 0.5 * 0.3478548451374538};

}  // namespace

double BeamElementData::phi_y() const {
  if (shear_factor <= 0.0) return 0.0;
  return 12.0 * E * Iy / (shear_factor * G * A * L * L);
}

double BeamElementData::phi_z() const {
  if (shear_factor <= 0.0) return 0.0;
  return 12.0 * E * Iz / (shear_factor * G * A * L * L);
}

Matrix12 local_stiffness(const BeamElementData& e) {
  Matrix12 k = Matrix12::Zero();
  const double axial = e.E * e.A / e.L;
  const double torsion = e.G * e.J / e.L;
  k(kU[0], kU[0]) = k(kU[1], kU[1]) = axial;
  k(kU[0], kU[1]) = k(kU[1], kU[0]) = -axial;
  k(kRx[0], kRx[0]) = k(kRx[1], kRx[1]) = torsion;
  k(kRx[0], kRx[1]) = k(kRx[1], kRx[0]) = -torsion;
  const Eigen::Matrix4d kxy = bending_stiffness(e.E * e.Iz, e.L, e.phi_z());
  const Eigen::Matrix4d kxz = bending_stiffness(e.E * e.Iy, e.L, e.phi_y());
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      k(kPlaneXY[i], kPlaneXY[j]) = kxy(i, j);
      k(kPlaneXZ[i], kPlaneXZ[j]) = kSignXZ[i] * kSignXZ[j] * kxz(i, j);
    }
  }
  return k;
}

BeamMassIntegrals mass_integrals(const BeamElementData& e, const Eigen::Vector3d& origin,
                                 const Eigen::Matrix3d& axes) {
  BeamMassIntegrals out;
  for (auto& row : out.component)
    for (auto& m : row) m.setZero();
  for (auto& row : out.position)
    for (auto& p : row) p.setZero();

  // Section integrals about the centroid (principal axes): int dA = A, int y^2 = Iz, int z^2 = Iy,
  // int y = int z = int yz = 0. A material point at section coordinates (y, z) moves by
  //   u_x = u - y rz + z ry,   u_y = v - z rx,   u_z = w + y rx.
  // Without rotary inertia the section terms of u_x are dropped (Euler-Bernoulli mass).
  const double rot = e.rotary_inertia ? 1.0 : 0.0;
  const double A = e.A, Iy = e.Iy, Iz = e.Iz;
  for (int g = 0; g < 4; ++g) {
    const double xi = kGaussPoint[g];
    const double w = kGaussWeight[g] * e.L * e.rho;
    const CentreLine n = centre_line(e, xi);
    auto outer = [](const Row12& a, const Row12& b) -> Matrix12 { return a.transpose() * b; };

    auto& c = out.component;
    c[0][0] += w * (A * outer(n.u, n.u) + rot * (Iz * outer(n.rz, n.rz) + Iy * outer(n.ry, n.ry)));
    c[1][1] += w * (A * outer(n.v, n.v) + Iy * outer(n.rx, n.rx));
    c[2][2] += w * (A * outer(n.w, n.w) + Iz * outer(n.rx, n.rx));
    c[0][1] += w * (A * outer(n.u, n.v) - rot * Iy * outer(n.ry, n.rx));
    c[0][2] += w * (A * outer(n.u, n.w) - rot * Iz * outer(n.rz, n.rx));
    c[1][2] += w * (A * outer(n.v, n.w));

    // Position of the section centre, and the global components of the local y and z axes.
    const Eigen::Vector3d X = origin + e.L * xi * axes.row(0).transpose();
    for (int k = 0; k < 3; ++k) {
      const double yk = axes(1, k), zk = axes(2, k);
      out.position[k][0] += w * (A * X(k) * n.u + rot * (-Iz * yk * n.rz + Iy * zk * n.ry));
      out.position[k][1] += w * (A * X(k) * n.v - Iy * zk * n.rx);
      out.position[k][2] += w * (A * X(k) * n.w + Iz * yk * n.rx);
    }
  }
  out.component[1][0] = out.component[0][1].transpose();
  out.component[2][0] = out.component[0][2].transpose();
  out.component[2][1] = out.component[1][2].transpose();
  return out;
}

double axial_force(const BeamElementData& e, const Vector12& u_local) {
  return e.E * e.A * (u_local(kU[1]) - u_local(kU[0])) / e.L;
}

Matrix12 local_geometric_stiffness(const BeamElementData& e, double N) {
  // K_G = N int_0^L (v'^T v' + w'^T w' + (Ip / A) rx'^T rx') dx, v' and w' the slopes of the element's own
  // deflection interpolation (exact by the 4-point rule: degree 4). rx is linear: rx' = (rx2 - rx1) / L.
  Matrix12 k = Matrix12::Zero();
  for (int g = 0; g < 4; ++g) {
    const double w = kGaussWeight[g] * e.L * N;
    const Eigen::RowVector4d sxy = deflection_slope(kGaussPoint[g], e.L, e.phi_z());
    const Eigen::RowVector4d sxz = deflection_slope(kGaussPoint[g], e.L, e.phi_y());
    Row12 dv = Row12::Zero(), dw = Row12::Zero();
    for (int i = 0; i < 4; ++i) {
      dv(kPlaneXY[i]) = sxy(i);
      dw(kPlaneXZ[i]) = kSignXZ[i] * sxz(i);
    }
    k += w * (dv.transpose() * dv + dw.transpose() * dw);
  }
  const double torsion = N * (e.Iy + e.Iz) / (e.A * e.L);
  k(kRx[0], kRx[0]) += torsion;
  k(kRx[1], kRx[1]) += torsion;
  k(kRx[0], kRx[1]) -= torsion;
  k(kRx[1], kRx[0]) -= torsion;
  return k;
}

Matrix12 local_mass(const BeamElementData& e) {
  const BeamMassIntegrals m = mass_integrals(e, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity());
  return m.component[0][0] + m.component[1][1] + m.component[2][2];
}

Eigen::Matrix3d beam_axes(const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                          const Eigen::Vector3d& y_hint) {
  const Eigen::Vector3d ex = (p2 - p1).normalized();
  Eigen::Vector3d hint = y_hint;
  if (hint.norm() == 0.0) {
    hint = std::abs(ex.y()) < 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
  }
  Eigen::Vector3d ey = hint - hint.dot(ex) * ex;
  if (ey.norm() < 1e-6 * hint.norm()) {
    throw Error("the section's y_axis is parallel to the beam segment; give a direction normal to it");
  }
  ey.normalize();
  Eigen::Matrix3d axes;
  axes.row(0) = ex.transpose();
  axes.row(1) = ey.transpose();
  axes.row(2) = ex.cross(ey).transpose();
  return axes;
}

Matrix12 local_from_global(const Eigen::Matrix3d& axes) {
  Matrix12 t = Matrix12::Zero();
  for (int b = 0; b < 4; ++b) t.block<3, 3>(3 * b, 3 * b) = axes;
  return t;
}

}  // namespace nvh::condense
