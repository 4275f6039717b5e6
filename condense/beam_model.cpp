#include "condense/beam_model.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "condense/timoshenko_beam.hpp"

namespace nvh::condense {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

Eigen::Vector3d as_vector(const Vec3& v) {
  return {v[0], v[1], v[2]};
}

std::string format_point(const Vec3& p) {
  std::ostringstream s;
  s << "[" << p[0] << ", " << p[1] << ", " << p[2] << "]";
  return s.str();
}

/// Scatter a 12x12 element matrix given on the element's global DOF into triplets.
void scatter(const Matrix12& ke, const std::array<int, 12>& dofs, Triplets& out) {
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j)
      if (ke(i, j) != 0.0) out.emplace_back(dofs[i], dofs[j], ke(i, j));
}

SparseMatrix from_triplets(int n, const Triplets& t) {
  SparseMatrix m(n, n);
  m.setFromTriplets(t.begin(), t.end());
  return m;
}

/// Section integrals of a point mass with rotary inertia, treated as a small rigid body centred on its
/// node: int rho (theta x p)_A (theta x p)_B for A, B = x, y, z gives the rotational block
///   sum_{i,m} eps_{A i j} eps_{B m n} Q_{jn},  Q = int rho p p^T = tr(J)/2 I - J.
Eigen::Matrix3d point_mass_rotary_component(const Eigen::Matrix3d& J, int a, int b) {
  const Eigen::Matrix3d Q = 0.5 * J.trace() * Eigen::Matrix3d::Identity() - J;
  auto eps = [](int i, int j, int k) -> double {
    return 0.5 * (i - j) * (j - k) * (k - i);  // Levi-Civita for indices 0..2
  };
  // (theta x p)_A = eps_{A i j} theta_i p_j, so the block (i, m) is sum_{j,n} eps_{A i j} eps_{B m n} Q_{jn}.
  Eigen::Matrix3d block = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 3; ++i)
    for (int m = 0; m < 3; ++m)
      for (int j = 0; j < 3; ++j)
        for (int n = 0; n < 3; ++n) block(i, m) += eps(a, i, j) * eps(b, m, n) * Q(j, n);
  return block;
}

}  // namespace

FeModel build_beam_model(const Component& c) {
  const BeamGeometry& beam = c.beam;
  const double tol = c.point_tolerance;
  FeModel model;
  model.element_kind = "beam elements";

  // --- nodes along the polyline: station s is node s * elements_per_segment ---
  const int per = beam.elements_per_segment;
  const int segments = static_cast<int>(beam.points.size()) - 1;
  for (int s = 0; s < segments; ++s) {
    const Eigen::Vector3d a = as_vector(beam.points[s]);
    const Eigen::Vector3d b = as_vector(beam.points[s + 1]);
    for (int e = 0; e < per; ++e) model.nodes.push_back(a + (b - a) * (static_cast<double>(e) / per));
  }
  model.nodes.push_back(as_vector(beam.points.back()));
  const int beam_nodes = static_cast<int>(model.nodes.size());
  model.master_of.resize(beam_nodes);
  for (int n = 0; n < beam_nodes; ++n) model.master_of[n] = n;

  // --- rigid links: `to` becomes a slave node of the (resolved) master at `from` ---
  for (const RigidLink& link : beam.rigid_links) {
    const int from = model.find_node(link.from, tol);
    if (from < 0) {
      throw Error("the rigid link starts at " + format_point(link.from) +
                      ", which is not a node of the model (a station, an element node, or the end of a rigid "
                      "link listed before this one)",
                  link.where, link.path + ".from");
    }
    int to = model.find_node(link.to, tol);
    if (to == from) throw Error("the rigid link has zero length", link.where, link.path + ".to");
    if (to >= 0 && model.master_of[to] != to) {
      throw Error("the point " + format_point(link.to) + " is already tied by another rigid link", link.where,
                  link.path + ".to");
    }
    if (to >= 0 && to < beam_nodes) {
      throw Error("the rigid link ends on a beam node " + format_point(link.to) +
                      "; rigid links end at points off the beam",
                  link.where, link.path + ".to");
    }
    if (to < 0) {
      model.nodes.push_back(as_vector(link.to));
      model.master_of.push_back(static_cast<int>(model.nodes.size()) - 1);
      to = static_cast<int>(model.nodes.size()) - 1;
    }
    model.master_of[to] = model.master_of[from];  // a link from a slave hangs on that slave's master
  }

  const int n_all = model.all_dofs();
  Triplets kt, mt;
  std::array<std::array<Triplets, 3>, 3> ct;
  model.position_moment_all = Eigen::MatrixXd::Zero(n_all, 9);

  // --- beam elements ---
  for (int s = 0; s < segments; ++s) {
    const BeamSection& section = beam.segment_sections[s];
    const Material& mat = c.materials.at(section.material.empty() ? beam.material : section.material);
    const Eigen::Vector3d hint = section.y_axis ? as_vector(*section.y_axis) : Eigen::Vector3d::Zero();
    for (int e = 0; e < per; ++e) {
      const int n1 = s * per + e, n2 = n1 + 1;
      const Eigen::Vector3d& p1 = model.nodes[n1];
      const Eigen::Vector3d& p2 = model.nodes[n2];
      Eigen::Matrix3d axes;
      try {
        axes = beam_axes(p1, p2, hint);
      } catch (const Error& err) {
        throw Error(err.message(), section.where, "y_axis");
      }
      BeamElementData data;
      data.L = (p2 - p1).norm();
      data.E = mat.E;
      data.G = mat.shear_modulus();
      data.rho = mat.rho;
      data.A = section.A;
      data.Iy = section.Iy;
      data.Iz = section.Iz;
      data.J = section.J;
      data.shear_factor = section.shear_factor.value_or(0.0);
      data.rotary_inertia = section.rotary_inertia;

      const Matrix12 T = local_from_global(axes);
      std::array<int, 12> dofs;
      for (int i = 0; i < 6; ++i) {
        dofs[i] = 6 * n1 + i;
        dofs[6 + i] = 6 * n2 + i;
      }
      const BeamMassIntegrals integrals = mass_integrals(data, p1, axes);
      Matrix12 me = Matrix12::Zero();
      for (int A = 0; A < 3; ++A) {
        for (int B = 0; B < 3; ++B) {
          // Global components: N_A = sum_a axes(a, A) N_a, on global DOF through T.
          Matrix12 cab = Matrix12::Zero();
          for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) cab += axes(a, A) * axes(b, B) * integrals.component[a][b];
          const Matrix12 global = T.transpose() * cab * T;
          scatter(global, dofs, ct[A][B]);
          if (A == B) me += global;
        }
        for (int k = 0; k < 3; ++k) {
          Vector12 p = Vector12::Zero();
          for (int a = 0; a < 3; ++a) p += axes(a, A) * integrals.position[k][a];
          const Vector12 global = T.transpose() * p;
          for (int i = 0; i < 12; ++i) model.position_moment_all(dofs[i], 3 * k + A) += global(i);
        }
      }
      scatter(T.transpose() * local_stiffness(data) * T, dofs, kt);
      scatter(me, dofs, mt);
      model.beam_elements.push_back({n1, n2, axes, data});
      ++model.element_count;
    }
  }

  // --- point masses (with rotary inertia about principal axes aligned with the component axes) ---
  for (const PointMass& pm : beam.masses) {
    const int n = model.find_node(pm.at, tol);
    if (n < 0) {
      throw Error("the point mass at " + format_point(pm.at) +
                      " is not on the model (not a beam node nor the end of a rigid link)",
                  pm.where, pm.path + ".at");
    }
    const Eigen::Matrix3d J = Eigen::Vector3d(pm.J[0], pm.J[1], pm.J[2]).asDiagonal();
    for (int k = 0; k < 3; ++k) {
      mt.emplace_back(6 * n + k, 6 * n + k, pm.m);
      mt.emplace_back(6 * n + 3 + k, 6 * n + 3 + k, J(k, k));
      ct[k][k].emplace_back(6 * n + k, 6 * n + k, pm.m);
    }
    for (int A = 0; A < 3; ++A) {
      for (int B = 0; B < 3; ++B) {
        const Eigen::Matrix3d block = point_mass_rotary_component(J, A, B);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            if (block(i, j) != 0.0) ct[A][B].emplace_back(6 * n + 3 + i, 6 * n + 3 + j, block(i, j));
      }
      // int rho x_k u_A over the point mass: m x_k on the translation; the rotary part integrates
      // (x_k + p_k)(theta x p)_A = eps_{A i j} theta_i Q_{kj}.
      const Eigen::Matrix3d Q = 0.5 * J.trace() * Eigen::Matrix3d::Identity() - J;
      for (int k = 0; k < 3; ++k) {
        model.position_moment_all(6 * n + A, 3 * k + A) += pm.m * model.nodes[n](k);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            const double eps = 0.5 * (A - i) * (i - j) * (j - A);
            model.position_moment_all(6 * n + 3 + i, 3 * k + A) += eps * Q(k, j);
          }
      }
    }
  }

  model.stiffness_all = from_triplets(n_all, kt);
  model.mass_all = from_triplets(n_all, mt);
  for (int A = 0; A < 3; ++A)
    for (int B = 0; B < 3; ++B) model.component_mass_all[A][B] = from_triplets(n_all, ct[A][B]);

  model.inactive_dof.assign(n_all, false);
  apply_supports(model, c.supports, tol);
  build_transform(model);
  return model;
}

}  // namespace nvh::condense
