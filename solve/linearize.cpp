#include "solve/linearize.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "common/error.hpp"
#include "solve/flexible_body.hpp"
#include "solve/flexible_rotor_body.hpp"

namespace nvh::solve {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double kRankTolerance = 1e-10;  // singular values below this x the largest count as zero

/// Dense dF/dy + cj dF/dy' from the model's sparse analytic Jacobian.
MatrixXd dense_jacobian(const Model& model, const SparsityPattern& pattern, double t, const VectorXd& y,
                        const VectorXd& yp, double cj) {
  std::vector<double> values;
  model.jacobian(t, y.data(), yp.data(), cj, values);
  MatrixXd m = MatrixXd::Zero(pattern.n, pattern.n);
  for (int c = 0; c < pattern.n; ++c)
    for (int k = pattern.column_start[c]; k < pattern.column_start[c + 1]; ++k)
      m(pattern.rows[k], c) = values[k];
  return m;
}

/// Orthonormal bases of the null space of `m` and of its orthogonal complement (the row space), by SVD. Rows
/// are scaled to unit length first (the null space is unchanged; rank decisions then do not depend on units).
std::pair<MatrixXd, MatrixXd> null_and_row_space(MatrixXd m) {
  const Eigen::Index cols = m.cols();
  if (m.rows() == 0) return {MatrixXd::Identity(cols, cols), MatrixXd(cols, 0)};
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    if (const double norm = m.row(r).norm(); norm > 0) m.row(r) /= norm;
  Eigen::BDCSVD<MatrixXd> svd(m, Eigen::ComputeFullV);
  const VectorXd& s = svd.singularValues();
  Eigen::Index rank = 0;
  while (rank < s.size() && s[rank] > kRankTolerance * std::max(s[0], 1e-300)) ++rank;
  return {svd.matrixV().rightCols(cols - rank), svd.matrixV().leftCols(rank)};
}

/// Small rotation (global axes) taking frame `a` to frame `b`: vee of the skew part of b a^T.
Vec3 rotation_between(const Mat3& a, const Mat3& b) {
  const Mat3 r = b * a.transpose();
  return 0.5 * Vec3(r(2, 1) - r(1, 2), r(0, 2) - r(2, 0), r(1, 0) - r(0, 1));
}

/// d^T K_e d of every force element along the real direction `d` (positions and element states), by central
/// differences of its wrenches: -(dF . dp + dT . dtheta) summed over its markers, / (2 eps)^2.
std::vector<double> element_energies(const Model& model, double t, const VectorXd& y, const VectorXd& yp,
                                     const VectorXd& d) {
  std::vector<double> energy(model.forces.size(), 0.0);
  const double scale = d.cwiseAbs().maxCoeff();
  if (!(scale > 0)) return energy;
  const double eps = 1e-7 / scale;
  const VectorXd y_plus = y + eps * d, y_minus = y - eps * d;
  std::vector<MarkerMotion> mp, mm;
  for (std::size_t f = 0; f < model.forces.size(); ++f) {
    const ForceEntry& fe = model.forces[f];
    if (fe.element->is_source()) continue;  // loads and motors do work; they store none
    const std::size_t nm = fe.markers.size();
    std::vector<Wrench> wp(nm), wm(nm);
    std::vector<double> rows(static_cast<std::size_t>(fe.state_count));
    const ElementInput in_p = model.element_input(fe, t, y_plus.data(), yp.data(), mp);
    ElementOutput out_p{wp, rows};
    fe.element->evaluate(in_p, out_p);
    const ElementInput in_m = model.element_input(fe, t, y_minus.data(), yp.data(), mm);
    ElementOutput out_m{wm, rows};
    fe.element->evaluate(in_m, out_m);
    double work = 0;
    for (std::size_t k = 0; k < nm; ++k) {
      const Vec3 dp = mp[k].position - mm[k].position;
      const Vec3 dtheta = rotation_between(mm[k].axes, mp[k].axes);
      work -= (wp[k].force - wm[k].force).dot(dp) + (wp[k].torque - wm[k].torque).dot(dtheta);
    }
    energy[f] = work / (4 * eps * eps);
  }
  return energy;
}

std::vector<std::pair<std::string, double>> shares(std::vector<std::pair<std::string, double>> parts) {
  double total = 0;
  for (const auto& p : parts) total += std::max(p.second, 0.0);
  std::vector<std::pair<std::string, double>> out;
  if (!(total > 0)) return out;
  for (auto& p : parts)
    if (std::abs(p.second) >= 1e-4 * total) out.emplace_back(p.first, p.second / total);
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  return out;
}

}  // namespace

double LinearMode::frequency_hz() const {
  return omega / (2 * std::numbers::pi);
}

Linearization linearize(const Model& model, double t, const VectorXd& y, const VectorXd& yp) {
  const SparsityPattern pattern = model.jacobian_pattern();
  const MatrixXd a = dense_jacobian(model, pattern, t, y, yp, 0.0);
  const MatrixXd b = dense_jacobian(model, pattern, t, y, yp, 1.0) - a;
  const int n = model.size();
  // Differential rows and columns: those where dF/dy' has an entry.
  std::vector<int> rows_d, rows_a, cols_d;
  for (int k = 0; k < n; ++k) {
    (b.row(k).cwiseAbs().maxCoeff() > 0 ? rows_d : rows_a).push_back(k);
    if (b.col(k).cwiseAbs().maxCoeff() > 0) cols_d.push_back(k);
  }
  // 1. dy = N s on the algebraic rows' null space.
  const MatrixXd n_space = null_and_row_space(a(rows_a, Eigen::all)).first;
  // 2. Z1: directions of s that move no differential variable (multipliers); Z2 the rest.
  const auto [z1, z2] = null_and_row_space(n_space(cols_d, Eigen::all));
  const MatrixXd a_n = a(rows_d, Eigen::all) * n_space;
  const MatrixXd left = null_and_row_space((a_n * z1).transpose()).first;  // L: L^T A N Z1 = 0
  if (left.cols() != z2.cols())
    throw Error("cannot linearise the model at its initial state: " + std::to_string(left.cols()) +
                " equations for " + std::to_string(z2.cols()) +
                " unknowns once the constraints are removed (dependent constraints, or an algebraic part of "
                "index above 2)");
  const MatrixXd basis = n_space * z2;  // the state directions of u
  const MatrixXd bh = left.transpose() * b(rows_d, Eigen::all) * basis;
  const MatrixXd ah = left.transpose() * a_n * z2;
  Linearization out;
  out.size = static_cast<int>(bh.rows());
  if (out.size == 0) return out;
  const Eigen::FullPivLU<MatrixXd> lu(bh);
  if (!lu.isInvertible())
    throw Error("cannot linearise the model at its initial state: the mass of " +
                std::to_string(out.size - lu.rank()) +
                " direction(s) is zero on the constraint manifold (a body without mass or inertia that no "
                "joint holds)");
  const Eigen::EigenSolver<MatrixXd> es(-lu.solve(ah), true);
  const Eigen::VectorXcd lambda = es.eigenvalues();
  const double largest = lambda.cwiseAbs().maxCoeff();
  const double zero =
      std::max(0.1, 1e-10 * largest);  // rad/s (0.016 Hz): rigid motion, clock, energy integrals

  // Participation: the bodies' mass matrices and the positional part of a direction.
  std::vector<MatrixXd> mass(model.bodies.size());
  for (std::size_t bi = 0; bi < model.bodies.size(); ++bi)
    mass[bi] = model.bodies[bi]->mass_matrix(model.positions(static_cast<int>(bi), y.data()));
  VectorXd positional = model.differential_mask() - model.velocity_mask();
  positional[model.energy_offset()] = positional[model.energy_offset() + 1] = 0;

  for (Eigen::Index e = 0; e < lambda.size(); ++e) {
    const std::complex<double> l = lambda[e];
    const double mag = std::abs(l);
    if (mag <= zero) continue;
    if (std::abs(l.imag()) <= 1e-9 * mag) {
      (l.real() < 0 ? out.relaxation_rates : out.growth_rates).push_back(std::abs(l.real()));
      continue;
    }
    if (l.imag() < 0) continue;  // one of each conjugate pair
    LinearMode mode;
    mode.omega = mag;
    mode.damping_ratio = -l.real() / mag;
    const Eigen::VectorXcd x = basis * es.eigenvectors().col(e);
    std::vector<std::pair<std::string, double>> kinetic, elastic;
    for (std::size_t bi = 0; bi < model.bodies.size(); ++bi) {
      const Body& body = *model.bodies[bi];
      if (body.velocity_count() == 0) continue;
      const int o = model.body_offset(static_cast<int>(bi));
      const Eigen::VectorXcd w = x.segment(o + body.position_count(), body.velocity_count());
      kinetic.emplace_back(body.name(), (w.adjoint() * mass[bi] * w)(0).real());
      if (const FlexibleBody* flex = flexible_part(body)) {  // its modal coordinates end its positions
        const Eigen::VectorXcd eta = x.segment(o + body.position_count() - flex->modes(), flex->modes());
        elastic.emplace_back(body.name() + " (elastic)",
                             (eta.adjoint() * flex->data().stiffness * eta)(0).real());
      }
    }
    std::vector<double> energy(model.forces.size(), 0.0);
    for (const VectorXd& part : {VectorXd(x.real()), VectorXd(x.imag())}) {
      const std::vector<double> e_part = element_energies(model, t, y, yp, part.cwiseProduct(positional));
      for (std::size_t f = 0; f < energy.size(); ++f) energy[f] += e_part[f];
    }
    for (std::size_t f = 0; f < model.forces.size(); ++f)
      if (energy[f] != 0) elastic.emplace_back(model.forces[f].name, energy[f]);
    mode.kinetic = shares(std::move(kinetic));
    mode.elastic = shares(std::move(elastic));
    out.modes.push_back(std::move(mode));
  }
  std::sort(out.modes.begin(), out.modes.end(),
            [](const auto& p, const auto& q) { return p.omega < q.omega; });
  std::sort(out.relaxation_rates.begin(), out.relaxation_rates.end());
  std::sort(out.growth_rates.begin(), out.growth_rates.end());
  return out;
}

}  // namespace nvh::solve
