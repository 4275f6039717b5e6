#include "condense/frf_error.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "common/error.hpp"
#include "condense/static_solve.hpp"

namespace nvh::condense {
namespace {
constexpr double kPi = 3.14159265358979323846;
/// Two resonances closer than this ratio get no sample between them (frf_sample_frequencies).
constexpr double kCloseResonances = 1.05;
}  // namespace

double FrfErrorEstimate::max_error() const {
  double worst = interface_error.size() ? interface_error.maxCoeff() : 0.0;
  if (point_error.size()) worst = std::max(worst, point_error.maxCoeff());
  return worst;
}

std::pair<double, double> FrfErrorEstimate::point_max(int p) const {
  Eigen::Index at = 0;
  const double worst = point_error.row(p).maxCoeff(&at);
  return {worst, frequency_hz(at)};
}

std::vector<double> frf_sample_frequencies(double band_hz, const Eigen::VectorXd& resonances_hz, int count) {
  std::vector<double> edges{0.0};
  for (Eigen::Index k = 0; k < resonances_hz.size(); ++k) {
    const double f = resonances_hz(k);
    if (f > edges.back() * (1.0 + 1e-9) && f < band_hz) edges.push_back(f);
  }
  edges.push_back(band_hz);
  std::vector<double> samples;
  for (std::size_t i = 0; i + 1 < edges.size(); ++i) {
    const double a = edges[i], b = edges[i + 1];
    // Closely spaced resonances (or the band's edge just above one): no frequency between them lies
    // more than 2.5 % from both, where the receptance is the resonant modes' alone.
    if (a > 0.0 && b < kCloseResonances * a) continue;
    const int n = std::max(1, static_cast<int>(std::lround(count * (b - a) / band_hz)));
    for (int j = 0; j < n; ++j) {
      // Equal steps below the first resonance, equal ratios between two (each sample as far from its
      // neighbouring resonances, relatively, as the others).
      samples.push_back(a == 0.0 ? b * (j + 0.5) / n : a * std::pow(b / a, (j + 0.5) / n));
    }
  }
  return samples;
}

DeflatedShiftedSolver::DeflatedShiftedSolver(const SparseMatrix& a, const SparseMatrix& b, bool lower,
                                             const Eigen::MatrixXd& phi, const Eigen::VectorXd& lambda,
                                             double bound, const ConstrainedFactor& preconditioner)
    : phi_(phi),
      lambda_(lambda),
      b_phi_(phi.cols() ? symmetric_times(b, lower, phi) : Eigen::MatrixXd(b.rows(), 0)),
      bound_(bound),
      preconditioner_(preconditioner) {
  if (lower) {
    a_rows_ = RowMajorSparse(SparseMatrix(a.selfadjointView<Eigen::Lower>()));
    b_rows_ = RowMajorSparse(SparseMatrix(b.selfadjointView<Eigen::Lower>()));
  } else {
    a_rows_ = RowMajorSparse(a);
    b_rows_ = RowMajorSparse(b);
  }
}

Eigen::MatrixXd DeflatedShiftedSolver::solve(double omega2, const Eigen::MatrixXd& rhs, double tolerance) {
  return solve(Eigen::VectorXd::Constant(rhs.cols(), omega2), rhs, tolerance);
}

Eigen::MatrixXd DeflatedShiftedSolver::solve(const Eigen::VectorXd& omega2, const Eigen::MatrixXd& rhs,
                                             double tolerance) {
  const Eigen::Index n = rhs.rows(), p = rhs.cols();
  if (omega2.size() != p) throw Error("internal: one w^2 per right-hand side");
  if (p == 0) return Eigen::MatrixXd(n, 0);
  if (!(omega2.maxCoeff() < bound_))
    throw Error("internal: deflated solve at or above the bound of its modes");
  auto hz = [](double w2) { return std::sqrt(w2) / (2.0 * kPi); };
  // (A - w_j^2 B) x_j for every column j at once.
  auto apply = [&](const Eigen::MatrixXd& x) -> Eigen::MatrixXd {
    const RowMajorDense xr = x;
    RowMajorDense ax = a_rows_ * xr;
    ax -= (b_rows_ * xr) * omega2.asDiagonal();
    return ax;
  };
  // Q^T r = r - B Phi Phi^T r (onto the range of the complement) and Q z = z - Phi (B Phi)^T z.
  auto project_dual = [&](Eigen::MatrixXd& r) {
    if (phi_.cols()) r -= b_phi_ * (phi_.transpose() * r);
  };
  auto project_primal = [&](Eigen::MatrixXd& z) {
    if (phi_.cols()) z -= phi_ * (b_phi_.transpose() * z);
  };
  // The deflated part: Phi (Lambda - w_j^2)^-1 Phi^T r_j.
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(n, p);
  if (phi_.cols()) {
    const Eigen::MatrixXd modal = phi_.transpose() * rhs;  // m x p
    Eigen::MatrixXd scaled(modal.rows(), p);
    for (Eigen::Index j = 0; j < p; ++j)
      scaled.col(j) = modal.col(j).cwiseQuotient((lambda_.array() - omega2(j)).matrix());
    x = phi_ * scaled;
  }
  // The complement: block PCG, one scalar recurrence per column, all solves in one multi-RHS call.
  Eigen::MatrixXd r = rhs;
  project_dual(r);
  const Eigen::VectorXd r0 = r.colwise().norm().transpose();
  std::vector<bool> done(static_cast<std::size_t>(p));
  for (Eigen::Index j = 0; j < p; ++j) done[j] = r0(j) == 0.0;
  Eigen::MatrixXd z = preconditioner_.solve(r);
  project_primal(z);
  Eigen::MatrixXd d = z;
  Eigen::VectorXd rz = (r.array() * z.array()).colwise().sum().transpose();
  iterations_ = 0;
  const int max_iterations = 500;
  for (;;) {
    bool all = true;
    for (Eigen::Index j = 0; j < p; ++j) all = all && done[j];
    if (all) break;
    if (iterations_ == max_iterations) {
      std::ostringstream s;
      s << "the full-model solve of the error estimate did not converge in " << max_iterations
        << " iterations at " << hz(omega2.maxCoeff()) << " Hz";
      throw Error(s.str());
    }
    ++iterations_;
    const Eigen::MatrixXd q = apply(d);
    for (Eigen::Index j = 0; j < p; ++j) {
      if (done[j]) continue;
      const double dq = d.col(j).dot(q.col(j));
      if (!(dq > 0.0)) {
        std::ostringstream s;
        s << "the full-model solve of the error estimate met a mode below " << hz(omega2(j))
          << " Hz that the deflation lacks (K - w^2 M not positive definite on its complement)";
        throw Error(s.str());
      }
      const double alpha = rz(j) / dq;
      x.col(j) += alpha * d.col(j);
      r.col(j) -= alpha * q.col(j);
    }
    project_dual(r);  // against the drift of round-off and of the eigenvectors' residuals
    for (Eigen::Index j = 0; j < p; ++j)
      if (!done[j] && r.col(j).norm() <= tolerance * r0(j)) done[j] = true;
    z = preconditioner_.solve(r);
    project_primal(z);
    for (Eigen::Index j = 0; j < p; ++j) {
      if (done[j]) {
        d.col(j).setZero();
        continue;
      }
      const double rz_new = r.col(j).dot(z.col(j));
      d.col(j) = z.col(j) + (rz_new / rz(j)) * d.col(j);
      rz(j) = rz_new;
    }
  }
  return x;
}

namespace {

bool is_rotation(const std::string& name) {
  const std::size_t dot = name.rfind('.');
  const std::string dof = dot == std::string::npos ? name : name.substr(dot + 1);
  return dof == "rx" || dof == "ry" || dof == "rz";
}

std::string point_of(const std::string& name) {
  const std::size_t dot = name.rfind('.');
  return dot == std::string::npos ? name : name.substr(0, dot);
}

}  // namespace

FrfErrorEstimate compare_receptances(double band_hz, const std::vector<double>& frequency_hz,
                                     const std::vector<Eigen::MatrixXd>& full,
                                     const std::vector<Eigen::MatrixXd>& reduced,
                                     const std::vector<Eigen::MatrixXd>& rigid,
                                     const std::vector<std::string>& dof_names, double length_scale) {
  FrfErrorEstimate e;
  e.band_hz = band_hz;
  e.length_scale = length_scale;
  const int ns = static_cast<int>(frequency_hz.size());
  const int nb = static_cast<int>(dof_names.size());
  e.frequency_hz = Eigen::Map<const Eigen::VectorXd>(frequency_hz.data(), ns);
  // Scaling: rotations times l, so G_scaled = S G S with S = diag(1 or l) is in m/N throughout.
  Eigen::VectorXd scale(nb);
  std::map<std::string, int> index;
  std::vector<std::vector<int>> members;
  for (int j = 0; j < nb; ++j) {
    scale(j) = is_rotation(dof_names[j]) ? length_scale : 1.0;
    const std::string point = point_of(dof_names[j]);
    auto [it, inserted] = index.emplace(point, static_cast<int>(e.points.size()));
    if (inserted) {
      e.points.push_back(point);
      members.emplace_back();
    }
    members[it->second].push_back(j);
  }
  const int np = static_cast<int>(e.points.size());
  e.point_error.resize(np, ns);
  e.interface_error.resize(ns);
  for (int s = 0; s < ns; ++s) {
    const Eigen::MatrixXd diff = scale.asDiagonal() * (reduced[s] - full[s]) * scale.asDiagonal();
    const Eigen::MatrixXd elastic = scale.asDiagonal() * (full[s] - rigid[s]) * scale.asDiagonal();
    e.interface_error(s) = diff.norm() / elastic.norm();
    for (int p = 0; p < np; ++p) {
      double num = 0.0, den = 0.0;
      for (int i : members[p])
        for (int j : members[p]) {
          num += diff(i, j) * diff(i, j);
          den += elastic(i, j) * elastic(i, j);
        }
      e.point_error(p, s) = std::sqrt(num / den);
    }
  }
  return e;
}

}  // namespace nvh::condense
