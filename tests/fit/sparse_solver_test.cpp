// vcg_ext/fit/sparse_solver.h: the fits' sparse SPD solver against a dense reference.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include "vcg_ext/fit/sparse_solver.h"

namespace {

using vcgext::fitdetail::SpdSolver;
using SpMat = Eigen::SparseMatrix<double>;

// A 3D grid Laplacian (7-point, Dirichlet) plus `shift` on the diagonal: SPD for shift > -min eig.
SpMat GridLaplacian(int n, double shift) {
  const int N = n * n * n;
  auto id = [n](int i, int j, int k) { return (i * n + j) * n + k; };
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const int r = id(i, j, k);
        t.emplace_back(r, r, 6.0 + shift);
        if (i + 1 < n) { t.emplace_back(r, id(i + 1, j, k), -1.0); t.emplace_back(id(i + 1, j, k), r, -1.0); }
        if (j + 1 < n) { t.emplace_back(r, id(i, j + 1, k), -1.0); t.emplace_back(id(i, j + 1, k), r, -1.0); }
        if (k + 1 < n) { t.emplace_back(r, id(i, j, k + 1), -1.0); t.emplace_back(id(i, j, k + 1), r, -1.0); }
      }
  SpMat a(N, N);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

Eigen::MatrixXd RandomRhs(int rows, int cols) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::MatrixXd b(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) b(i, j) = u(rng);
  return b;
}

double Residual(const SpMat& a, const Eigen::MatrixXd& x, const Eigen::MatrixXd& b) {
  return (a * x - b).norm() / b.norm();
}

}  // namespace

TEST(SparseSolver, SmallSystemsUseSimplicialLdltAndMatchADenseSolve) {
  const SpMat a = GridLaplacian(8, 0.1);  // 512 unknowns
  ASSERT_LT(a.rows(), SpdSolver::kCholmodMinUnknowns);
  const Eigen::MatrixXd b = RandomRhs(int(a.rows()), 3);
  SpdSolver s(int(a.rows()));
  s.compute(a);
  ASSERT_EQ(s.info(), Eigen::Success);
  EXPECT_FALSE(s.UsesCholmod());
  const Eigen::MatrixXd x = s.solve(b);
  const Eigen::MatrixXd ref = Eigen::MatrixXd(a).ldlt().solve(b);
  EXPECT_LT((x - ref).norm() / ref.norm(), 1e-10);
  EXPECT_LT(Residual(a, x, b), 1e-12);
}

TEST(SparseSolver, LargeSystemsUseCholmodWhenBuiltAndAgreeWithSimplicialLdlt) {
  const SpMat a = GridLaplacian(18, 0.05);  // 5 832 unknowns, above the threshold
  ASSERT_GE(a.rows(), SpdSolver::kCholmodMinUnknowns);
  const Eigen::MatrixXd b = RandomRhs(int(a.rows()), 3);
  SpdSolver s(int(a.rows()));
  s.analyzePattern(a);
  // refactorized with new values of the same pattern, as the tangent-distance fit does
  for (double scale : {1.0, 2.5}) {
    const SpMat as = scale * a;
    s.factorize(as);
    ASSERT_EQ(s.info(), Eigen::Success);
    EXPECT_EQ(s.UsesCholmod(), SpdSolver::kCholmod);
    const Eigen::MatrixXd x = s.solve(b);
    Eigen::SimplicialLDLT<SpMat> ldlt(as);
    const Eigen::MatrixXd ref = ldlt.solve(b);
    EXPECT_LT((x - ref).norm() / ref.norm(), 1e-9) << "scale " << scale;
    EXPECT_LT(Residual(as, x, b), 1e-10) << "scale " << scale;
  }
  EXPECT_EQ(s.Fallbacks(), 0);
}

TEST(SparseSolver, AnIndefiniteLargeSystemFallsBackToLdlt) {
  // shift -0.5: the grid Laplacian's smallest eigenvalues (~0.09 for n = 18) become negative, so
  // a Cholesky factorization fails; LDLT still solves the nonsingular system.
  const SpMat a = GridLaplacian(18, -0.5);
  const Eigen::MatrixXd b = RandomRhs(int(a.rows()), 1);
  SpdSolver s(int(a.rows()));
  s.compute(a);
  ASSERT_EQ(s.info(), Eigen::Success);
  EXPECT_FALSE(s.UsesCholmod());
  EXPECT_EQ(s.Fallbacks(), SpdSolver::kCholmod ? 1 : 0);
  EXPECT_LT(Residual(a, s.solve(b), b), 1e-8);
}
