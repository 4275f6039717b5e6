#include "condense/sparse_cholesky.hpp"

#include <Eigen/CholmodSupport>
#include <chrono>

#include "common/error.hpp"

namespace nvh::condense {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string ordering_name(int cholmod_ordering) {
  switch (cholmod_ordering) {
    case CHOLMOD_NATURAL:
      return "natural";
    case CHOLMOD_GIVEN:
      return "given";
    case CHOLMOD_AMD:
      return "AMD";
    case CHOLMOD_METIS:
      return "METIS";
    case CHOLMOD_NESDIS:
      return "NESDIS";
    case CHOLMOD_COLAMD:
      return "COLAMD";
    case CHOLMOD_POSTORDERED:
      return "natural (postordered)";
  }
  return "unknown";
}

}  // namespace

Ordering parse_ordering(const std::string& name) {
  if (name == "auto") return Ordering::kAuto;
  if (name == "amd") return Ordering::kAmd;
  if (name == "metis") return Ordering::kMetis;
  if (name == "nesdis") return Ordering::kNesdis;
  throw Error("unknown ordering '" + name + "' (expected one of: auto, amd, metis, nesdis)");
}

std::string to_string(Ordering ordering) {
  switch (ordering) {
    case Ordering::kAuto:
      return "auto";
    case Ordering::kAmd:
      return "amd";
    case Ordering::kMetis:
      return "metis";
    case Ordering::kNesdis:
      return "nesdis";
  }
  return "unknown";
}

void FactorStats::add(const FactorStats& other) {
  if (other.factor_nonzeros > factor_nonzeros) {
    ordering = other.ordering;
    matrix_nonzeros = other.matrix_nonzeros;
    factor_nonzeros = other.factor_nonzeros;
    flops = other.flops;
  }
  order_seconds += other.order_seconds;
  factor_seconds += other.factor_seconds;
  factorizations += other.factorizations;
}

/// Eigen's CHOLMOD wrapper, opened up for CHOLMOD's factor (the failing column, L->minor; solves with
/// parts of the factorization).
struct SparseCholesky::Impl : Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> {
  bool analysed = false;
  /// x = the solution of CHOLMOD system `sys` (CHOLMOD_L: L x = b, CHOLMOD_Lt: L^T x = b, CHOLMOD_P:
  /// x = P b, CHOLMOD_Pt: x = P^T b) for the columns of b.
  Eigen::MatrixXd solve_system(int sys, const Eigen::MatrixXd& b) {
    Eigen::MatrixXd& input = const_cast<Eigen::MatrixXd&>(b);  // CHOLMOD's view is non-const; not written
    cholmod_dense view = Eigen::viewAsCholmod(input);
    cholmod_dense* x = cholmod_solve(sys, m_cholmodFactor, &view, &cholmod());
    if (x == nullptr) throw Error("CHOLMOD could not solve with the factor (out of memory?)");
    Eigen::MatrixXd result = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(x->x), b.rows(), b.cols());
    cholmod_free_dense(&x, &cholmod());
    return result;
  }
  Eigen::Index failed_dof() const {
    if (m_cholmodFactor == nullptr) return -1;
    const auto minor = static_cast<Eigen::Index>(m_cholmodFactor->minor);
    if (minor < 0 || minor >= static_cast<Eigen::Index>(m_cholmodFactor->n)) return -1;
    if (m_cholmodFactor->Perm == nullptr) return minor;
    return static_cast<const int*>(m_cholmodFactor->Perm)[minor];
  }
};

SparseCholesky::SparseCholesky(Ordering ordering) : impl_(std::make_unique<Impl>()) {
  cholmod_common& c = impl_->cholmod();
  c.print = 0;  // CHOLMOD's own "not positive definite" warning: the caller reports it
  if (ordering != Ordering::kAuto) {
    c.nmethods = 1;
    c.method[0].ordering = ordering == Ordering::kAmd     ? CHOLMOD_AMD
                           : ordering == Ordering::kMetis ? CHOLMOD_METIS
                                                          : CHOLMOD_NESDIS;
    c.postorder = 1;
  }
}

SparseCholesky::~SparseCholesky() = default;

bool SparseCholesky::factorize(const SparseMatrix& a) {
  cholmod_common& c = impl_->cholmod();
  if (!impl_->analysed) {
    const auto start = std::chrono::steady_clock::now();
    impl_->analyzePattern(a);
    stats_.order_seconds += seconds_since(start);
    const int selected = c.selected >= 0 && c.selected < CHOLMOD_MAXMETHODS ? c.selected : 0;
    stats_.ordering = ordering_name(c.method[selected].ordering);
    stats_.factor_nonzeros = c.method[selected].lnz;
    stats_.flops = c.method[selected].fl;
    double lower = 0;  // entries on and below the diagonal (a may hold both triangles or the lower one)
    for (Eigen::Index col = 0; col < a.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(a, col); it; ++it) lower += it.row() >= col;
    stats_.matrix_nonzeros = lower;
    impl_->analysed = true;
  }
  const auto start = std::chrono::steady_clock::now();
  impl_->factorize(a);
  stats_.factor_seconds += seconds_since(start);
  ++stats_.factorizations;
  return impl_->info() == Eigen::Success;
}

void SparseCholesky::solve(const double* b, double* x) const {
  const Eigen::Index n = impl_->rows();
  Eigen::Map<Eigen::VectorXd>(x, n) = impl_->solve(Eigen::Map<const Eigen::VectorXd>(b, n));
}

Eigen::MatrixXd SparseCholesky::solve(const Eigen::MatrixXd& b) const {
  return impl_->solve(b);
}

Eigen::MatrixXd SparseCholesky::forward(const Eigen::MatrixXd& b) const {
  return impl_->solve_system(CHOLMOD_L, impl_->solve_system(CHOLMOD_P, b));
}

Eigen::MatrixXd SparseCholesky::backward(const Eigen::MatrixXd& b) const {
  return impl_->solve_system(CHOLMOD_Pt, impl_->solve_system(CHOLMOD_Lt, b));
}

Eigen::Index SparseCholesky::failed_dof() const {
  return impl_->failed_dof();
}

}  // namespace nvh::condense
