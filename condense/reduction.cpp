#include "condense/reduction.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "common/error.hpp"
#include "condense/block_pcg.hpp"
#include "condense/static_solve.hpp"

namespace nvh::condense {
namespace {

constexpr double kTwoPi = 6.283185307179586;

std::string hz(double f) {
  std::ostringstream s;
  s.precision(5);
  s << f << " Hz";
  return s.str();
}

/// The request for the lowest modes: `modes` elastic ones (plus the rigid ones), or up to fmax.
EigenRequest request_for(const ReductionSettings& s, int rigid, const ReductionInput& in) {
  EigenRequest r;
  r.backend = in.backend;
  r.progress = in.progress;
  r.ordering = in.ordering;
  r.lower_triangles = in.lower_triangles;
  r.coarse_space = in.coarse_space;
  if (s.modes > 0) {
    r.modes = s.modes + rigid;
  } else {
    r.fmax_hz = s.fmax_hz;
  }
  return r;
}

/// A mode count that ends inside a group of equal frequencies (EigenResult::split_first) keeps an
/// arbitrary part of the group's eigenspace: a warning naming the group and what to ask for instead.
/// `rigid`: the rigid-body modes counted in eig before the elastic ones; `what`: "modes" or
/// "fixed-interface modes".
void warn_if_split(const EigenResult& eig, int rigid, const std::string& what, const Logger& log) {
  if (eig.split_first < 0) return;
  const int last = static_cast<int>(eig.eigenvalues.size()) - rigid;  // the count asked for
  const int first = eig.split_first - rigid + 1;                      // 1-based, elastic
  log.warning("modes = " + std::to_string(last) + " ends inside a group of equal frequencies: " + what + " " +
              std::to_string(first) + ".." + std::to_string(last) + " at " +
              hz(frequency_hz(eig.eigenvalues[eig.eigenvalues.size() - 1])) +
              " and at least one more; the modes kept of the group are an arbitrary part of its space (the "
              "eigensolver's choice: a round shaft's other bending plane, a repeated part's partners may be "
              "missing). Ask for more modes, or by fmax, to keep whole groups");
}

/// Modal damping 2 zeta omega on the elastic modes X_e (M_r-orthonormal) of a reduced basis:
/// D = M_r X_e diag(2 zeta omega) X_e^T M_r, so that X_e^T D X_e = diag(2 zeta omega).
Eigen::MatrixXd modal_damping(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& elastic_vectors,
                              const Eigen::VectorXd& omega, double zeta) {
  const Eigen::MatrixXd mx = mass * elastic_vectors;
  return mx * (2.0 * zeta * omega).asDiagonal() * mx.transpose();
}

/// The deflation of the error estimate (frf_error.hpp) must hold every mode up to 5 % above the band.
constexpr double kDeflationMargin = 1.05 * 1.05;

double square(double x) {
  return x * x;
}
double band_omega2(const ReductionSettings& s) {
  return square(kTwoPi * s.band_hz);
}

/// The eigenvalue below which `eig` holds every eigenpair: the next one above fmax (fmax requests; none
/// found: all of them), or its highest (count requests: the next lies at or above it).
double deflation_bound(const EigenResult& eig, bool fmax_request) {
  if (fmax_request)
    return std::isnan(eig.next_eigenvalue) ? std::numeric_limits<double>::infinity() : eig.next_eigenvalue;
  return eig.eigenvalues.size() ? eig.eigenvalues(eig.eigenvalues.size() - 1) : 0.0;
}

/// The rows `rows` of x.
Eigen::MatrixXd rows_of(const Eigen::MatrixXd& x, const std::vector<int>& rows) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(rows.size()), x.cols());
  for (std::size_t i = 0; i < rows.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = x.row(rows[i]);
  return out;
}

/// Phi diag(1 / (lambda - w^2)) Phi^T: the receptance of the modes Phi (rows: the interface DOF).
Eigen::MatrixXd modal_receptance(const Eigen::MatrixXd& phi, const Eigen::VectorXd& lambda, double omega2) {
  const Eigen::VectorXd inverse = (lambda.array() - omega2).inverse().matrix();
  return phi * inverse.asDiagonal() * phi.transpose();
}

/// The deflated solves of all samples, several frequencies per block (at most 256 right-hand sides): the
/// right-hand side of sample k (nb columns) is filled by rhs(w_k^2, block); the solutions in sample order.
/// `iterations` gets the sum over the blocks of their iterations.
template <class FillRhs>
std::vector<Eigen::MatrixXd> solve_in_blocks(DeflatedShiftedSolver& solver,
                                             const std::vector<double>& samples, int nb, FillRhs rhs,
                                             int* iterations) {
  const int per_block = std::max(1, 256 / std::max(nb, 1));
  std::vector<Eigen::MatrixXd> out;
  for (std::size_t first = 0; first < samples.size(); first += per_block) {
    const int count = static_cast<int>(std::min<std::size_t>(per_block, samples.size() - first));
    Eigen::MatrixXd block(solver.rows(), count * nb);
    Eigen::VectorXd w2(count * nb);
    for (int k = 0; k < count; ++k) {
      const double omega2 = square(kTwoPi * samples[first + k]);
      w2.segment(k * nb, nb).setConstant(omega2);
      rhs(omega2, block.middleCols(k * nb, nb));
    }
    const Eigen::MatrixXd x = solver.solve(w2, block);
    *iterations += solver.iterations();
    for (int k = 0; k < count; ++k) out.push_back(x.middleCols(k * nb, nb));
  }
  return out;
}

/// The error estimate of a modal reduction (frf_error.hpp): the full model's receptance at the interface
/// DOF from deflated solves with its own modes `eig` (rigid ones first), against r's (rigid-body part
/// exact in both). K and M as the reduction had them.
FrfErrorEstimate modal_frf_error(const SparseMatrix& K, const SparseMatrix& M, const ReductionInput& in,
                                 const EigenResult& eig, const ReducedModel& r) {
  const auto start = std::chrono::steady_clock::now();
  const ReductionSettings& s = in.settings;
  const int rigid = in.rigid_body_modes;
  const double top2 = band_omega2(s);
  // The modes of the reduction reach above the band, or a second eigen-solve gets those that do.
  const EigenResult* deflation = &eig;
  EigenResult extra;
  if (deflation_bound(eig, s.modes <= 0) < kDeflationMargin * top2) {
    EigenRequest request = request_for(s, rigid, in);
    request.modes = 0;
    request.fmax_hz = 1.25 * s.band_hz;
    request.progress = {};
    // An fmax request: LOBPCG takes counts only, and the estimate factorizes K - sigma M anyway (below).
    if (request.backend == EigenBackend::kLobpcg) request.backend = EigenBackend::kBlockLanczos;
    extra = solve_eigenproblem(SparseMatrix(K), SparseMatrix(M), request);
    deflation = &extra;
  }
  const double bound = deflation_bound(*deflation, deflation != &eig || s.modes <= 0);
  // Preconditioner: K - sigma M, positive definite for a free part too.
  const double sigma = -square(kTwoPi * s.band_hz / 10.0);
  ConstrainedFactor preconditioner(in.ordering);
  if (!preconditioner.factorize(SparseMatrix(K - sigma * M)))
    throw Error("the error estimate could not factorize K - sigma M (M not positive definite?)");
  DeflatedShiftedSolver solver(K, M, in.lower_triangles, deflation->vectors, deflation->eigenvalues, bound,
                               preconditioner);
  const int n = static_cast<int>(K.rows());
  const int nb = static_cast<int>(in.boundary_dofs.size());
  Eigen::MatrixXd unit = Eigen::MatrixXd::Zero(n, nb);
  for (int j = 0; j < nb; ++j) unit(in.boundary_dofs[j], j) = 1.0;
  const Eigen::MatrixXd basis_b = rows_of(r.basis, in.boundary_dofs);
  const Eigen::VectorXd lambda_r = r.stiffness.diagonal();  // M_r = I, K_r diagonal
  const Eigen::MatrixXd rigid_b = rows_of(eig.vectors.leftCols(rigid), in.boundary_dofs);
  const Eigen::VectorXd lambda_rigid = eig.eigenvalues.head(rigid);

  const std::vector<double> samples = frf_sample_frequencies(s.band_hz, r.frequency_hz, s.error_samples);
  std::vector<Eigen::MatrixXd> full, reduced, rigid_part;
  int iterations = 0;
  const std::vector<Eigen::MatrixXd> solved = solve_in_blocks(
      solver, samples, nb, [&](double, Eigen::Ref<Eigen::MatrixXd> rhs) { rhs = unit; }, &iterations);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const double w2 = square(kTwoPi * samples[k]);
    const Eigen::MatrixXd g = rows_of(solved[k], in.boundary_dofs);
    full.push_back(0.5 * (g + g.transpose()));
    rigid_part.push_back(modal_receptance(rigid_b, lambda_rigid, w2));
    reduced.push_back(rigid_part.back() + modal_receptance(basis_b, lambda_r, w2));
  }
  FrfErrorEstimate e =
      compare_receptances(s.band_hz, samples, full, reduced, rigid_part, in.boundary_names, in.length_scale);
  e.solver_iterations = iterations;
  e.cost_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return e;
}

struct ResidualModes {
  Eigen::MatrixXd vectors;  ///< n x k, M-orthonormal, K-orthogonal, M-orthogonal to Phi_r and Phi_e
  Eigen::VectorXd lambda;   ///< their Rayleigh quotients omega^2 (ascending), rad^2/s^2
  int dropped = 0;          ///< load directions already represented by the kept modes (dependent)
  FactorStats factor;
};

/// Inertia-relief residual attachment modes of the unit loads F (n x nb, columns e_j at the interface
/// DOF), after Craig and Kurdila, Fundamentals of Structural Dynamics, 2nd ed. 2006, ch. 17 (attachment
/// modes of a free component, inertia relief, residual flexibility); MacNeal (1971) for the residual
/// flexibility. Phi_r: the rigid-body modes (M-orthonormal, may be empty for a supported component),
/// Phi_e: the kept elastic modes (M-orthonormal), Lambda_e their eigenvalues.
///
///  (1) inertia-relief projector      P = I - M Phi_r Phi_r^T     (P F is self-equilibrated: Phi_r^T P F = 0)
///  (2) elastic flexibility           G_e = P^T K_c^-1 P          with K_c = K with r statically determinate
///                                    DOF held (r = number of rigid-body modes; K_c^-1 padded with zeros
///                                    on them). G_e = Phi_all,e Lambda_all,e^-1 Phi_all,e^T, independent
///                                    of which determinate DOF are held.
///  (3) residual flexibility          G_res = G_e - Phi_e Lambda_e^-1 Phi_e^T, applied to F:
///                                    Psi = G_res F = (I - Phi_e Phi_e^T M) G_e F
///  (4) M-orthonormalize Psi (Gram matrix Psi^T M Psi = V D V^T, T = V D^-1/2, directions with
///      D < 1e-12 relative to the unit-normalized columns dropped as dependent) and diagonalize its
///      stiffness (T^T Psi^T K Psi T = W Lambda_res W^T): Psi <- Psi T W.
/// Then span[Phi_e, Psi] contains G_e F, so a static load at the interfaces (self-equilibrated, or
/// balanced by inertia relief) is reproduced exactly by the reduced model; Phi_e^T K Psi = Lambda_e
/// Phi_e^T M Psi = 0 keeps the reduced matrices diagonal and the kept modes' frequencies unchanged, and
/// Psi being M-orthogonal to the lowest modes puts each Lambda_res above Lambda_e's top (Rayleigh).
ResidualModes residual_attachment_modes(const SparseMatrix& K, const SparseMatrix& M, bool lower,
                                        const std::vector<int>& load_dofs, const Eigen::MatrixXd& phi_r,
                                        const Eigen::MatrixXd& phi_e, Ordering ordering) {
  const int n = static_cast<int>(K.rows());
  const int nb = static_cast<int>(load_dofs.size());
  const int rigid = static_cast<int>(phi_r.cols());
  Eigen::MatrixXd f = Eigen::MatrixXd::Zero(n, nb);
  for (int j = 0; j < nb; ++j) f(load_dofs[j], j) = 1.0;
  // (1)-(2): the attachment modes G_e F (static_solve.hpp), M-orthogonal to the rigid-body modes.
  ResidualModes out;
  Eigen::MatrixXd psi = inertia_relief_solve(K, M, lower, f, phi_r, ordering, &out.factor);

  // Unit M-norm columns, so the dependence test below does not depend on force vs moment units.
  for (int j = 0; j < nb; ++j) {
    const double norm = std::sqrt(psi.col(j).dot(symmetric_times(M, lower, psi.col(j)).col(0)));
    if (norm > 0) psi.col(j) /= norm;
  }
  // (3) Remove the kept modes (and, for round-off, the rigid ones again), twice ("twice is enough":
  // Giraud et al., Numer. Math. 101, 2005).
  Eigen::MatrixXd basis(n, rigid + phi_e.cols());
  basis << phi_r, phi_e;
  const Eigen::MatrixXd m_basis = symmetric_times(M, lower, basis);
  for (int pass = 0; pass < 2; ++pass) psi -= basis * (m_basis.transpose() * psi);

  // (4) M-orthonormalize (dropping dependent directions), then diagonalize the stiffness.
  Eigen::MatrixXd gram = psi.transpose() * symmetric_times(M, lower, psi);
  gram = 0.5 * (gram + gram.transpose()).eval();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> g(gram);
  std::vector<int> independent;
  for (int j = 0; j < nb; ++j)
    if (g.eigenvalues()(j) > 1e-12) independent.push_back(j);
  out.dropped = nb - static_cast<int>(independent.size());
  Eigen::MatrixXd t(nb, static_cast<Eigen::Index>(independent.size()));
  for (std::size_t k = 0; k < independent.size(); ++k)
    t.col(static_cast<Eigen::Index>(k)) =
        g.eigenvectors().col(independent[k]) / std::sqrt(g.eigenvalues()(independent[k]));
  psi = (psi * t).eval();
  Eigen::MatrixXd kpp = psi.transpose() * symmetric_times(K, lower, psi);
  kpp = 0.5 * (kpp + kpp.transpose()).eval();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> w(kpp);
  out.vectors = psi * w.eigenvectors();
  out.lambda = w.eigenvalues().cwiseMax(0.0);
  return out;
}

ReducedModel modal_reduction(ReductionInput& in, const Logger& log) {
  const ReductionSettings& s = in.settings;
  const int rigid = in.rigid_body_modes;
  if (s.residual_modes && in.boundary_dofs.empty()) {
    throw Error("residual_modes = true needs at least one [[interface]] point (its DOF are the load points)",
                s.where, "reduction.residual_modes");
  }
  if (s.band_hz > 0.0 && in.boundary_dofs.empty()) {
    throw Error(
        "band needs at least one [[interface]] point: the error estimate is that of the receptance "
        "at the interfaces; without one give fmax or modes",
        s.band_where, "reduction.band");
  }
  // The residual modes and the error estimate need K and M after the eigen-solve, which consumes them:
  // keep copies then.
  SparseMatrix K, M;
  if (s.residual_modes || s.band_hz > 0.0) {
    K = in.stiffness;
    M = in.mass;
  }
  EigenResult eig =
      solve_eigenproblem(std::move(in.stiffness), std::move(in.mass), request_for(s, rigid, in));
  warn_if_split(eig, rigid, "modes", log);
  const int found = static_cast<int>(eig.eigenvalues.size());
  if (found <= rigid) {
    // Nothing elastic below fmax: the eigen-solve found the first elastic mode above it.
    throw Error("fmax = " + hz(s.fmax_hz) + " is below the first elastic mode (" +
                    hz(frequency_hz(eig.next_eigenvalue)) +
                    "): no mode to keep; raise fmax or give modes = N",
                s.where, s.where_key);
  }
  const int m = found - rigid;
  ReducedModel r;
  r.rigid_body_modes_removed = rigid;
  r.basis = eig.vectors.rightCols(m);
  r.mass = Eigen::MatrixXd::Identity(m, m);
  const Eigen::VectorXd lambda = eig.eigenvalues.tail(m).cwiseMax(0.0);
  r.stiffness = lambda.asDiagonal();
  const Eigen::VectorXd omega = lambda.cwiseSqrt();
  r.damping = (2.0 * s.damping_ratio * omega).asDiagonal();
  r.frequency_hz = omega / kTwoPi;
  for (int i = 0; i < m; ++i) r.coordinates.push_back("mode " + std::to_string(i + 1));
  r.max_residual = eig.residuals.size() ? eig.residuals.maxCoeff() : 0.0;
  r.factor = eig.factor;
  r.eigen_seconds = eig.iteration_seconds;
  r.eigen_solves = eig.matrix_operations;
  r.backend = in.backend;
  log.detail("modal: " + std::to_string(m) + " elastic modes, " + hz(r.frequency_hz(0)) + " .. " +
             hz(r.frequency_hz(m - 1)));
  if (!s.residual_modes) {
    if (s.band_hz > 0.0) r.frf_error = modal_frf_error(K, M, in, eig, r);
    return r;
  }

  // Residual (attachment) modes of the interface DOF, appended after the kept modes. Both blocks are
  // M-orthonormal and K-diagonal and the residual ones lie above the band (see residual_attachment_modes),
  // so the reduced M stays I, K diagonal and the frequencies ascending, as the file requires; a sort
  // guards the order against round-off.
  const ResidualModes res = residual_attachment_modes(K, M, in.lower_triangles, in.boundary_dofs,
                                                      eig.vectors.leftCols(rigid), r.basis, in.ordering);
  r.factor.add(res.factor);
  const int k = static_cast<int>(res.lambda.size());
  r.static_correction = k;
  Eigen::MatrixXd basis(r.basis.rows(), m + k);
  basis << r.basis, res.vectors;
  Eigen::VectorXd all_lambda(m + k);
  all_lambda << lambda, res.lambda;
  std::vector<std::string> names = r.coordinates;
  for (int j = 0; j < k; ++j) names.push_back("residual mode " + std::to_string(j + 1));
  std::vector<int> order(m + k);
  for (int j = 0; j < m + k; ++j) order[j] = j;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return all_lambda(a) < all_lambda(b); });
  r.basis.resize(basis.rows(), m + k);
  Eigen::VectorXd sorted(m + k);
  r.coordinates.clear();
  for (int j = 0; j < m + k; ++j) {
    r.basis.col(j) = basis.col(order[j]);
    sorted(j) = all_lambda(order[j]);
    r.coordinates.push_back(names[order[j]]);
  }
  r.mass = Eigen::MatrixXd::Identity(m + k, m + k);
  r.stiffness = sorted.asDiagonal();
  const Eigen::VectorXd all_omega = sorted.cwiseSqrt();
  r.damping = (2.0 * s.damping_ratio * all_omega).asDiagonal();
  r.frequency_hz = all_omega / kTwoPi;
  log.detail(
      "modal: " + std::to_string(k) + " residual modes of " + std::to_string(in.boundary_dofs.size()) +
      " interface DOF (" + std::to_string(res.dropped) + " dependent dropped), " +
      (k > 0 ? hz(res.lambda.cwiseSqrt()(0) / kTwoPi) + " .. " + hz(res.lambda.cwiseSqrt()(k - 1) / kTwoPi)
             : std::string("none")));
  if (s.band_hz > 0.0) r.frf_error = modal_frf_error(K, M, in, eig, r);
  return r;
}

/// The error estimate of a Craig-Bampton or Guyan reduction (frf_error.hpp). The full model's receptance
/// at the boundary is the inverse of its dynamic Schur complement,
///     S(w) = D_bb - D_bi D_ii^-1 D_ib,   D = K - w^2 M,
/// with D_ii^-1 D_ib from deflated solves with the fixed-interface modes phi (eigenvalues lambda, all of
/// them below `bound`) and the interior factor `kii_factor`; the reduced one is the boundary block of
/// (K_r - w^2 M_r)^-1, the first nb coordinates being the boundary DOF. The rigid-body part (free parts)
/// comes from the reduced eigenproblem, whose basis holds the rigid motion exactly.
FrfErrorEstimate craig_bampton_frf_error(const ReductionInput& in, const std::vector<int>& b,
                                         const std::vector<int>& i_dofs, const SparseMatrix& Kib,
                                         std::shared_ptr<ConstrainedFactor> kii_factor, Eigen::MatrixXd phi,
                                         Eigen::VectorXd lambda, double bound, const ReducedModel& r) {
  const auto start = std::chrono::steady_clock::now();
  const ReductionSettings& s = in.settings;
  const SparseMatrix& K = in.stiffness;
  const SparseMatrix& M = in.mass;
  const double top2 = band_omega2(s);
  const SparseMatrix Kii = submatrix(K, i_dofs, i_dofs);
  const SparseMatrix Mii = submatrix(M, i_dofs, i_dofs);
  if (bound < kDeflationMargin * top2) {
    // Guyan, or a cut-off below the band: the fixed-interface modes up to 1.25 band, for the estimate.
    EigenRequest request = request_for(s, 0, in);
    request.modes = 0;
    request.fmax_hz = 1.25 * s.band_hz;
    request.progress = {};
    // An fmax request: LOBPCG takes counts only, and the estimate factorizes K - sigma M anyway (below).
    if (request.backend == EigenBackend::kLobpcg) request.backend = EigenBackend::kBlockLanczos;
    request.stiffness_factor = kii_factor;
    EigenResult eig = solve_eigenproblem(SparseMatrix(Kii), SparseMatrix(Mii), request);
    bound = deflation_bound(eig, true);
    phi = std::move(eig.vectors);
    lambda = std::move(eig.eigenvalues);
  }
  DeflatedShiftedSolver solver(Kii, Mii, false, phi, lambda, bound, *kii_factor);
  const SparseMatrix Mib = submatrix(M, i_dofs, b);
  const Eigen::MatrixXd Kbb = Eigen::MatrixXd(submatrix(K, b, b)), Mbb = Eigen::MatrixXd(submatrix(M, b, b));
  const int nb = static_cast<int>(b.size()), rigid = in.rigid_body_modes;

  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> reduced_modes(r.stiffness, r.mass);
  const Eigen::VectorXd reduced_lambda = reduced_modes.eigenvalues();
  const Eigen::MatrixXd rigid_b = reduced_modes.eigenvectors().topLeftCorner(nb, rigid);
  const Eigen::VectorXd lambda_rigid = reduced_lambda.head(rigid);
  const Eigen::VectorXd resonances =
      reduced_lambda.tail(reduced_lambda.size() - rigid).cwiseMax(0.0).cwiseSqrt() / kTwoPi;

  const std::vector<double> samples = frf_sample_frequencies(s.band_hz, resonances, s.error_samples);
  std::vector<Eigen::MatrixXd> full, reduced, rigid_part;
  int iterations = 0;
  // D_ii^-1 (-D_ib) at every sample.
  const std::vector<Eigen::MatrixXd> solved = solve_in_blocks(
      solver, samples, nb,
      [&](double w2, Eigen::Ref<Eigen::MatrixXd> rhs) { rhs = -Eigen::MatrixXd(Kib - w2 * Mib); },
      &iterations);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const double w2 = square(kTwoPi * samples[k]);
    const Eigen::MatrixXd& x = solved[k];
    Eigen::MatrixXd schur = Kbb - w2 * Mbb + Kib.transpose() * x - w2 * (Mib.transpose() * x);
    schur = 0.5 * (schur + schur.transpose()).eval();
    const Eigen::MatrixXd g = schur.fullPivLu().inverse();
    full.push_back(0.5 * (g + g.transpose()));
    // The boundary block of (K_r - w^2 M_r)^-1: nb columns solved, not the whole inverse.
    const Eigen::MatrixXd d_r = r.stiffness - w2 * r.mass;
    const Eigen::MatrixXd g_r = d_r.fullPivLu().solve(Eigen::MatrixXd::Identity(d_r.rows(), nb)).topRows(nb);
    reduced.push_back(0.5 * (g_r + g_r.transpose()));
    rigid_part.push_back(modal_receptance(rigid_b, lambda_rigid, w2));
  }
  FrfErrorEstimate e =
      compare_receptances(s.band_hz, samples, full, reduced, rigid_part, in.boundary_names, in.length_scale);
  e.solver_iterations = iterations;
  e.cost_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return e;
}

/// The constraint modes Psi = -K_ii^-1 K_ib without a factor of K_ii: block PCG (block_pcg.hpp) to a
/// relative residual of 1e-10 per column, preconditioned by the two-grid cycle (p_multigrid.hpp) on the
/// interior's coarse space `space`, in its Z-order numbering. `factor`: the coarse factor's costs.
Eigen::MatrixXd iterative_constraint_modes(const SparseMatrix& kii, const SparseMatrix& kib,
                                           const CoarseSpace& space, Ordering ordering, FactorStats& factor,
                                           int& iterations) {
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> renumbering(kii.rows());
  std::copy(space.new_index.begin(), space.new_index.end(), renumbering.indices().data());
  const SparseMatrix whole = renumbered_whole(SparseMatrix(kii), space.new_index);
  const PMultigrid preconditioner(whole, space.prolongation, PMultigrid::kDegree, ordering,
                                  space.coarse_only);
  const Block rhs = -(renumbering * Eigen::MatrixXd(kib));
  const BlockPcgResult x = block_pcg(whole, preconditioner, rhs, 1e-10);
  factor = preconditioner.coarse_factor_stats();
  iterations = x.iterations;
  return renumbering.inverse() * Eigen::MatrixXd(x.x);
}

/// Residual vectors of load points for Craig-Bampton (Nastran's RESVEC; Craig & Kurdila, Fundamentals of
/// Structural Dynamics, 2nd ed. 2006, sec. 17.4, the residual flexibility of attachment modes, here with the
/// interface held):
///  (1) the interior's static response to each unit load with the interface held, X = K_ii^-1 F_i (on
///      C_i u_i = 0 in multiplier form);
///  (2) less its part in the kept fixed-interface modes phi (M_ii-orthonormal): X <- (I - phi phi^T M_ii) X,
///      twice for round-off - the residual flexibility G_res F_i = (K_ii^-1 - phi Lambda^-1 phi^T) F_i;
///  (3) compressed to the load space's directions of residual flexibility: F_i^T X = V D V^T (k x k,
///      symmetric positive semi-definite), the columns X v_j with d_j > tolerance d_max kept - a film's
///      smooth pressure needs a few of them, not one per point;
///  (4) M_ii-orthonormalized (directions with a Gram eigenvalue below 1e-12 of unit-normalized columns
///      dropped as dependent).
/// span[Psi, phi, X] then holds u_i = Psi u_b + K_ii^-1 F_i f (to the dropped flexibility) for any interface
/// motion u_b and loads f at the points: the static response to loads there is exact, as the constraint
/// modes make it for loads at the interface.
struct LoadResiduals {
  Eigen::MatrixXd vectors;      // ni x kept
  Eigen::VectorXd flexibility;  // d_j of (3), descending (m/N for unit forces)
  int kept = 0;
};
LoadResiduals load_residual_vectors(const ConstrainedFactor& chol, const SparseMatrix& Mii,
                                    const Eigen::MatrixXd& Fi, const Eigen::MatrixXd& phi, double tolerance) {
  const int k = static_cast<int>(Fi.cols());
  Eigen::MatrixXd x = chol.solve(Fi);  // with C_i u_i = 0 when the factor holds constraints
  if (phi.cols() > 0)
    for (int pass = 0; pass < 2; ++pass) x -= phi * (phi.transpose() * (Mii * x));
  Eigen::MatrixXd flex = Fi.transpose() * x;
  flex = 0.5 * (flex + flex.transpose()).eval();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> d(flex);
  LoadResiduals out;
  out.flexibility = d.eigenvalues().reverse();
  const double largest = out.flexibility.size() ? std::max(out.flexibility(0), 0.0) : 0.0;
  std::vector<int> keep;
  for (int j = k - 1; j >= 0; --j)
    if (largest > 0 && d.eigenvalues()(j) > tolerance * largest) keep.push_back(j);
  Eigen::MatrixXd y(x.rows(), static_cast<Eigen::Index>(keep.size()));
  for (std::size_t c = 0; c < keep.size(); ++c)
    y.col(static_cast<Eigen::Index>(c)) = x * d.eigenvectors().col(keep[c]);
  for (Eigen::Index c = 0; c < y.cols(); ++c) {
    const double norm = std::sqrt(y.col(c).dot(Mii * y.col(c)));
    if (norm > 0) y.col(c) /= norm;
  }
  Eigen::MatrixXd gram = y.transpose() * (Mii * y);
  gram = 0.5 * (gram + gram.transpose()).eval();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> g(gram);
  std::vector<int> independent;
  for (Eigen::Index j = 0; j < gram.rows(); ++j)
    if (g.eigenvalues()(j) > 1e-12) independent.push_back(static_cast<int>(j));
  out.vectors.resize(y.rows(), static_cast<Eigen::Index>(independent.size()));
  for (std::size_t c = 0; c < independent.size(); ++c)
    out.vectors.col(static_cast<Eigen::Index>(c)) =
        y * g.eigenvectors().col(independent[c]) / std::sqrt(g.eigenvalues()(independent[c]));
  out.kept = static_cast<int>(out.vectors.cols());
  return out;
}

ReducedModel craig_bampton(const ReductionInput& in, bool with_fixed_interface_modes, const Logger& log) {
  const ReductionSettings& s = in.settings;
  const SparseMatrix& K = in.stiffness;
  const SparseMatrix& M = in.mass;
  const int n = static_cast<int>(K.rows());
  if (in.boundary_dofs.empty()) {
    throw Error(to_string(s.method) +
                    " reduction needs at least one [[interface]] point (its DOF are kept); "
                    "add one, or use method = \"modal\"",
                s.where, "reduction.method");
  }
  std::vector<int> b = in.boundary_dofs;
  std::vector<bool> is_boundary(n, false);
  for (int d : b) is_boundary[d] = true;
  std::vector<int> i_dofs;
  for (int d = 0; d < n; ++d)
    if (!is_boundary[d]) i_dofs.push_back(d);
  const int nb = static_cast<int>(b.size()), ni = static_cast<int>(i_dofs.size());

  // Constraint modes: K_ii Psi = -K_ib, one factorization, nb right-hand sides. K_ii is positive
  // definite when the interface restrains the interior, so the fixed-interface eigen-solve runs on the
  // same factorization (shift 0): one factorization for both.
  // With linear constraints C u = 0 (distributing couplings in multiplier form, fe_model.hpp), split
  // C u = C_i u_i + C_b u_b: a constraint mode is the interior's least-energy motion with C_i Psi = -C_b
  // for a unit boundary motion, [K_ii C_i^T; C_i 0] [Psi; Lambda] = [-K_ib; -C_b], and the fixed-interface
  // modes are those of (K_ii, M_ii) on C_i u_i = 0 (Craig & Kurdila, Fundamentals of Structural
  // Dynamics, 2nd ed. 2006, sec. 18.3 with constraints: the same definitions on the constrained space);
  // both on one ConstrainedFactor (constrained_factor.hpp). K_ii must be positive definite on its own.
  SparseMatrix Kii = submatrix(K, i_dofs, i_dofs);
  const SparseMatrix Kib = submatrix(K, i_dofs, b);
  const bool constrained = in.constraints.rows() > 0;
  Eigen::MatrixXd psi(ni, nb);
  FactorStats factor;
  std::shared_ptr<ConstrainedFactor> chol;
  // --eigensolver lobpcg: no factor of K_ii. The constraint modes by block PCG and the fixed-interface modes
  // by LOBPCG, both preconditioned by the two-grid cycle on the interior's coarse space (the boundary DOF
  // held). The error estimate (band) and the residual vectors of load points solve with K_ii many times:
  // with them K_ii is factored as for the other eigensolvers.
  const bool wants_factor = s.band_hz > 0.0 || in.residual_loads.cols() > 0;
  const bool iterative = in.backend == EigenBackend::kLobpcg && ni > 0 && !wants_factor;
  std::shared_ptr<const CoarseSpace> interior_space;
  int pcg_iterations = 0;
  if (iterative) {
    if (constrained || !in.coarse_space)
      throw Error("internal: the lobpcg eigensolver needs a coarse space and couplings in elimination form");
    interior_space = std::make_shared<const CoarseSpace>(restricted_space(*in.coarse_space, i_dofs));
    psi = iterative_constraint_modes(Kii, Kib, *interior_space, in.ordering, factor, pcg_iterations);
    log.detail(to_string(s.method) + ": " + std::to_string(nb) + " constraint modes by PCG in " +
               std::to_string(pcg_iterations) + " iterations");
  } else if (ni > 0) {
    if (in.backend == EigenBackend::kLobpcg)
      log.info(to_string(s.method) + ": " +
               (s.band_hz > 0.0 ? "the error estimate (band)" : "residual vectors") +
               " factor K_ii: the fixed-interface modes by shift-invert Lanczos on that factor, not lobpcg");
    chol = std::make_shared<ConstrainedFactor>(in.ordering);
    std::vector<int> rows(static_cast<std::size_t>(in.constraints.rows()));
    for (std::size_t k = 0; k < rows.size(); ++k) rows[k] = static_cast<int>(k);
    if (constrained) chol->set_constraints(submatrix(in.constraints, rows, i_dofs));
    if (!chol->factorize(Kii)) {
      throw Error(
          std::string("the interior of the model is not restrained by the interface points and supports (the "
                      "stiffness with the interface DOF held is singular): add an interface or a support, or "
                      "check that the beam is connected") +
          (constrained ? "; distributing (RBE3) couplings in multiplier form do not restrain it: "
                         "set [volume] rbe3_form = \"elimination\""
                       : ""));
    }
    psi = constrained
              ? chol->solve(-Eigen::MatrixXd(Kib), -Eigen::MatrixXd(submatrix(in.constraints, rows, b)))
              : Eigen::MatrixXd(-chol->solve(Eigen::MatrixXd(Kib)));
    factor = chol->stats();
  }

  // Fixed-interface modes.
  Eigen::MatrixXd phi(ni, 0);
  Eigen::VectorXd fixed_hz;
  double max_residual = 0.0;
  double eigen_seconds = 0.0;
  int eigen_solves = 0;
  double bound = 0.0;  // every fixed-interface eigenvalue below it is in phi (the error estimate)
  Eigen::VectorXd fixed_lambda;
  if (with_fixed_interface_modes && ni > 0) {
    EigenRequest request = request_for(s, 0, in);
    if (iterative) {
      request.coarse_space = interior_space;
    } else {
      request.stiffness_factor = chol;
      if (request.backend == EigenBackend::kLobpcg) request.backend = EigenBackend::kBlockLanczos;
    }
    const EigenResult eig = solve_eigenproblem(std::move(Kii), submatrix(M, i_dofs, i_dofs), request);
    warn_if_split(eig, 0, "fixed-interface modes", log);
    if (eig.eigenvalues.size() == 0) {
      throw Error("fmax = " + hz(s.fmax_hz) + " is below the first fixed-interface mode (" +
                      hz(frequency_hz(eig.next_eigenvalue)) +
                      "): no mode to keep; raise fmax, give modes = N, or use method = \"guyan\"",
                  s.where, s.where_key);
    }
    phi = eig.vectors;
    bound = deflation_bound(eig, s.modes <= 0);
    fixed_lambda = eig.eigenvalues;
    fixed_hz = eig.eigenvalues.unaryExpr([](double l) { return frequency_hz(l); });
    max_residual = eig.residuals.size() ? eig.residuals.maxCoeff() : 0.0;
    factor.add(eig.factor);
    eigen_seconds = eig.iteration_seconds;
    eigen_solves = eig.matrix_operations;
  }
  // Residual vectors of load points (load_residual_vectors above): after the fixed-interface modes.
  Eigen::MatrixXd extra(ni, 0);
  if (in.residual_loads.cols() > 0 && ni > 0) {
    const Eigen::MatrixXd fi = rows_of(in.residual_loads, i_dofs);
    const LoadResiduals res =
        load_residual_vectors(*chol, submatrix(M, i_dofs, i_dofs), fi, phi, s.residual_tolerance);
    extra = res.vectors;
    std::ostringstream msg;
    msg.precision(3);
    msg << to_string(s.method) << ": " << res.kept << " residual vectors of " << fi.cols()
        << " load points (residual flexibility " << (res.flexibility.size() ? res.flexibility(0) : 0.0)
        << " m/N at most, kept down to " << s.residual_tolerance << " of it)";
    log.info(msg.str());
  }
  if (!(s.band_hz > 0.0)) chol.reset();  // the error estimate needs it; else free it before the basis
  const int nm = static_cast<int>(phi.cols()), nx = static_cast<int>(extra.cols());

  ReducedModel r;
  r.fixed_interface_hz = fixed_hz;
  r.max_residual = max_residual;
  r.factor = factor;
  r.eigen_seconds = eigen_seconds;
  r.eigen_solves = eigen_solves;
  r.backend = in.backend == EigenBackend::kLobpcg && !iterative ? EigenBackend::kBlockLanczos : in.backend;
  r.basis = Eigen::MatrixXd::Zero(n, nb + nm + nx);
  for (int j = 0; j < nb; ++j) r.basis(b[j], j) = 1.0;
  for (int i = 0; i < ni; ++i) {
    r.basis.row(i_dofs[i]).head(nb) = psi.row(i);
    r.basis.row(i_dofs[i]).segment(nb, nm) = phi.row(i);
    r.basis.row(i_dofs[i]).tail(nx) = extra.row(i);
  }
  r.coordinates = in.boundary_names;
  r.static_correction = nx;
  for (int j = 0; j < nm; ++j) r.coordinates.push_back("fixed-interface mode " + std::to_string(j + 1));
  for (int j = 0; j < nx; ++j) r.coordinates.push_back("residual vector " + std::to_string(j + 1));
  r.stiffness = r.basis.transpose() * (K * r.basis);
  r.mass = r.basis.transpose() * (M * r.basis);
  r.stiffness = 0.5 * (r.stiffness + r.stiffness.transpose()).eval();
  r.mass = 0.5 * (r.mass + r.mass.transpose()).eval();
  if (s.band_hz > 0.0 && ni > 0) {
    if (constrained)
      throw Error(
          "internal: the error estimate (band) does not handle linear constraints (rbe3_form = multiplier)");
    r.frf_error = craig_bampton_frf_error(in, b, i_dofs, Kib, chol, phi, fixed_lambda, bound, r);
  }
  log.detail(to_string(s.method) + ": " + std::to_string(nb) + " boundary DOF, " + std::to_string(nm) +
             " fixed-interface modes");
  return r;
}

/// Solve the reduced eigenproblem; either rotate the basis onto its elastic modes (orthonormalize) or
/// keep the basis and only record the frequencies and the modal damping.
void finish_reduced(ReducedModel& r, const ReductionInput& in) {
  const int rigid = in.rigid_body_modes;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(r.stiffness, r.mass);
  if (eig.info() != Eigen::Success) throw Error("the reduced eigenproblem could not be solved");
  const int m = static_cast<int>(r.mass.rows());
  const int elastic = m - rigid;
  if (elastic <= 0) {
    throw Error("the reduced basis holds only rigid-body motion; add fixed-interface modes or interfaces",
                in.settings.where, "reduction");
  }
  const Eigen::VectorXd lambda = eig.eigenvalues().tail(elastic).cwiseMax(0.0);
  const Eigen::MatrixXd x = eig.eigenvectors().rightCols(elastic);  // M_r-orthonormal
  const Eigen::VectorXd omega = lambda.cwiseSqrt();
  r.frequency_hz = omega / kTwoPi;
  const double zeta = in.settings.damping_ratio;
  if (in.settings.orthonormalize) {
    r.basis = r.basis * x;
    r.mass = Eigen::MatrixXd::Identity(elastic, elastic);
    r.stiffness = lambda.asDiagonal();
    r.damping = (2.0 * zeta * omega).asDiagonal();
    r.coordinates.clear();
    for (int i = 0; i < elastic; ++i) r.coordinates.push_back("mode " + std::to_string(i + 1));
    r.rigid_body_modes_removed = rigid;
  } else {
    r.damping = modal_damping(r.mass, x, omega, zeta);
    r.rigid_body_modes_contained = rigid;
  }
}

}  // namespace

namespace {

ReducedModel reduce_once(ReductionInput& in, const Logger& log) {
  if (in.constraints.rows() > 0 && in.settings.method == ReductionMethod::kModal)
    throw Error("internal: the modal reduction does not handle linear constraints (rbe3_form = multiplier)");
  switch (in.settings.method) {
    case ReductionMethod::kModal:
      return modal_reduction(in, log);
    case ReductionMethod::kCraigBampton: {
      ReducedModel r = craig_bampton(in, true, log);
      finish_reduced(r, in);
      return r;
    }
    case ReductionMethod::kGuyan: {
      ReducedModel r = craig_bampton(in, false, log);
      finish_reduced(r, in);
      return r;
    }
  }
  throw Error("unknown reduction method");
}

std::string seconds(double t) {
  std::ostringstream s;
  s.precision(3);
  s << t << " s";
  return s.str();
}

std::string percent(double x) {
  std::ostringstream s;
  s.precision(3);
  s << 100.0 * x << " %";
  return s.str();
}

/// The estimate in the log: one line for the interface, one per point (verbose), a warning above the
/// tolerance.
void report_error(const ReducedModel& r, const ReductionSettings& s, const Logger& log) {
  const FrfErrorEstimate& e = r.frf_error;
  if (e.empty()) return;
  log.info("receptance error at the interfaces in 0 .. " + hz(s.band_hz) + " (" +
           std::to_string(e.frequency_hz.size()) + " frequencies, " + std::to_string(e.solver_iterations) +
           " deflated-PCG iterations, " + seconds(e.cost_seconds) + "): " + percent(e.max_error()) +
           " at most (tolerance " + percent(s.frf_tolerance) + ")");
  for (int p = 0; p < static_cast<int>(e.points.size()); ++p) {
    const auto [worst, at] = e.point_max(p);
    log.detail("  " + e.points[p] + ": " + percent(worst) + " at most, at " + hz(at));
  }
  if (e.max_error() > s.frf_tolerance)
    log.warning("the reduced model's receptance error " + percent(e.max_error()) + " exceeds frf_tolerance " +
                percent(s.frf_tolerance) + " in the band: raise fmax (or modes), or add residual modes");
}

/// The cut-off the band starts from, and the largest it may reach, as multiples of the band.
constexpr double kFirstCutoff = 1.5;
constexpr double kLastCutoff = 10.0;

}  // namespace

ReducedModel reduce(ReductionInput& in, const Logger& log) {
  if (in.lower_triangles && in.settings.method != ReductionMethod::kModal)
    throw Error("internal: only the modal reduction works on lower triangles");
  const ReductionSettings settings = in.settings;
  const bool choose = settings.band_hz > 0.0 && settings.fmax_hz <= 0.0 && settings.modes <= 0 &&
                      settings.method != ReductionMethod::kGuyan;
  if (!choose) {
    ReducedModel r = reduce_once(in, log);
    r.cutoff_hz = settings.fmax_hz;
    report_error(r, settings, log);
    return r;
  }
  // Choose the cut-off: from 1.5 band up, each pass predicting the next from the estimate, the
  // truncation error falling about as (band / cut-off)^2 (the first neglected mode's quasi-static term).
  // The modal reduction consumes K and M: keep them for the passes after the first.
  const bool consumed = settings.method == ReductionMethod::kModal;
  SparseMatrix K0, M0;
  if (consumed) {
    K0 = in.stiffness;
    M0 = in.mass;
  }
  double cutoff = kFirstCutoff * settings.band_hz;
  std::vector<std::pair<double, double>> passes;
  for (int pass = 1;; ++pass) {
    if (consumed && pass > 1) {
      in.stiffness = K0;
      in.mass = M0;
    }
    in.settings.fmax_hz = cutoff;
    in.settings.where = settings.band_where;
    in.settings.where_key = "reduction.band";
    ReducedModel r = reduce_once(in, log);
    const double error = r.frf_error.max_error();
    passes.emplace_back(cutoff, error);
    log.info("band " + hz(settings.band_hz) + ", pass " + std::to_string(pass) + ": cut-off " + hz(cutoff) +
             " (" + std::to_string(r.coordinates.size()) + " coordinates), estimated error " +
             percent(error));
    const bool last = cutoff >= kLastCutoff * settings.band_hz * (1.0 - 1e-12);
    if (error <= settings.frf_tolerance || last) {
      r.cutoff_hz = cutoff;
      r.cutoff_passes = passes;
      in.settings = settings;
      report_error(r, settings, log);
      return r;
    }
    const double factor = std::clamp(1.1 * std::sqrt(error / settings.frf_tolerance), 1.25, 3.0);
    cutoff = std::min(cutoff * factor, kLastCutoff * settings.band_hz);
  }
}

}  // namespace nvh::condense
