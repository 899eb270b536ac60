#pragma once
/// \file sparse_solver.h
/// The sparse symmetric positive (semi-)definite solver of the fits: Eigen's SimplicialLDLT for
/// systems below kCholmodMinUnknowns, CHOLMOD's supernodal Cholesky (SuiteSparse, through Eigen's
/// CholmodSupport) above when the build found it. A CHOLMOD factorization that fails (a matrix
/// that is only semidefinite in floating point) is redone with SimplicialLDLT, so the two builds
/// fail on the same systems. Why (docs/fit.md "Sparse solver"): the tangent-distance fit
/// refactorizes its 3n x 3n system every iteration; at 3 000 patches (9 000 unknowns) on bunny00
/// SimplicialLDLT took 7.5 of the fit's 8.4 s, CHOLMOD 1.9 of 2.8 s. Below ~1 500 control vertices
/// neither is clearly faster, and the fit amplifies the solvers' different rounding into
/// different iterates (RMS limit within ±10 %, RMS displaced up to +28 % on one of 9 meshes):
/// small systems keep SimplicialLDLT and today's results bit for bit.

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#ifdef FITMAP_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif
#ifdef _OPENMP
#include <omp.h>
#endif

namespace vcgext {
namespace fitdetail {

/// OpenMP's thread count set to 1 for the scope (the calling thread's setting only). Measured
/// 2026-12-03 on bunny00 at 3 000 patches: CHOLMOD's factorizations through OpenMP-threaded
/// OpenBLAS took 9.4 s with 2 threads (libgomp spinning between small BLAS calls) and 2.1 s
/// with 1.
struct OneThread {
#ifdef _OPENMP
  int saved = omp_get_max_threads();
  OneThread() { omp_set_num_threads(1); }
  ~OneThread() { omp_set_num_threads(saved); }
#endif
};

class SpdSolver {
 public:
  using SpMat = Eigen::SparseMatrix<double>;
  /// Systems with at least this many unknowns use CHOLMOD (when compiled in).
  static constexpr int kCholmodMinUnknowns = 4500;
  /// `unknowns`: the matrix's dimension (chooses the solver; see kCholmodMinUnknowns).
  explicit SpdSolver(int unknowns) : useLdlt_(!kCholmod || unknowns < kCholmodMinUnknowns) {
#ifdef FITMAP_HAVE_CHOLMOD
    cholmod_.cholmod().print = 0;  // a refused factorization is handled here, not printed
#endif
  }
  /// true when CHOLMOD is compiled in (the build's choice, see CMakeLists.txt)
  static constexpr bool kCholmod =
#ifdef FITMAP_HAVE_CHOLMOD
      true;
#else
      false;
#endif
  /// Symbolic analysis of the pattern (reused by factorize for matrices of the same pattern).
  void analyzePattern(const SpMat& a) {
#ifdef FITMAP_HAVE_CHOLMOD
    if (!useLdlt_) {
      cholmod_.analyzePattern(a);
      useLdlt_ = cholmod_.info() != Eigen::Success;
      if (!useLdlt_) return;
    }
#endif
    ldlt_.analyzePattern(a);
    ldltAnalyzed_ = true;
  }
  void factorize(const SpMat& a) {
#ifdef FITMAP_HAVE_CHOLMOD
    if (!useLdlt_) {
      {
        OneThread one;  // CHOLMOD's BLAS calls: small supernodes, threads only spin (see below)
        cholmod_.factorize(a);
      }
      if (cholmod_.info() == Eigen::Success) return;
      useLdlt_ = true;  // not positive definite in floating point: LDLT from here on
      ++fallbacks_;
    }
#endif
    if (!ldltAnalyzed_) {
      ldlt_.analyzePattern(a);
      ldltAnalyzed_ = true;
    }
    ldlt_.factorize(a);
  }
  void compute(const SpMat& a) {
    analyzePattern(a);
    factorize(a);
  }
  Eigen::ComputationInfo info() const {
#ifdef FITMAP_HAVE_CHOLMOD
    if (!useLdlt_) return cholmod_.info();
#endif
    return ldlt_.info();
  }
  template <typename Rhs>
  Eigen::MatrixXd solve(const Rhs& b) const {
#ifdef FITMAP_HAVE_CHOLMOD
    if (!useLdlt_) return cholmod_.solve(b);
#endif
    return ldlt_.solve(b);
  }
  /// Factorizations that CHOLMOD refused and SimplicialLDLT redid.
  int Fallbacks() const { return fallbacks_; }
  /// The solver of the latest factorization: true = CHOLMOD.
  bool UsesCholmod() const { return !useLdlt_; }

 private:
#ifdef FITMAP_HAVE_CHOLMOD
  Eigen::CholmodSupernodalLLT<SpMat> cholmod_;
#endif
  Eigen::SimplicialLDLT<SpMat> ldlt_;
  bool useLdlt_, ldltAnalyzed_ = false;
  int fallbacks_ = 0;
};

/// An SpdSolver's factorization (of an earlier matrix) as the preconditioner of Eigen's
/// ConjugateGradient: the tangent-distance fit's later systems differ from the first only by the
/// rows' normals and foot points, so a few conjugate-gradient steps preconditioned with the first
/// factorization replace a refactorization (FitParams::reuseFactorizationFrom). `Use` it before
/// the solver's compute(); compute() itself does nothing.
class FactorPreconditioner {
 public:
  using StorageIndex = int;
  enum { ColsAtCompileTime = Eigen::Dynamic, MaxColsAtCompileTime = Eigen::Dynamic };
  FactorPreconditioner() = default;
  void Use(const SpdSolver* s, Eigen::Index n) { s_ = s; n_ = n; }
  template <typename M> FactorPreconditioner& analyzePattern(const M&) { return *this; }
  template <typename M> FactorPreconditioner& factorize(const M&) { return *this; }
  template <typename M> FactorPreconditioner& compute(const M&) { return *this; }
  /// One OpenMP thread, as for the factorizations (OneThread): the triangular solves' BLAS
  /// calls are as small, and a second thread would only spin while the machine is shared.
  template <typename Rhs> Eigen::VectorXd solve(const Rhs& b) const {
    OneThread one;
    return s_->solve(b);
  }
  Eigen::ComputationInfo info() const { return s_ ? s_->info() : Eigen::InvalidInput; }
  Eigen::Index rows() const { return n_; }
  Eigen::Index cols() const { return n_; }

 private:
  const SpdSolver* s_ = nullptr;
  Eigen::Index n_ = 0;
};

}  // namespace fitdetail
}  // namespace vcgext
