#include <catch2/catch.hpp>

#include <Eigen/Cholesky>
#include <algorithm>
#include <random>
#include <vector>

#include "glbudget/model/nonnegative_least_squares.hpp"

using namespace glbudget::model;

TEST_CASE("NNLS equals the unconstrained solution when it is non-negative", "[model][nnls]") {
  Eigen::MatrixXd a(4, 2);
  a << 1, 0, 0, 1, 1, 1, 2, 1;
  const Eigen::Vector2d truth(0.5, 2.0);
  const Eigen::VectorXd y = a * truth;
  const Eigen::VectorXd z = solve_nonnegative(a.transpose() * a, a.transpose() * y);
  CHECK(z(0) == Approx(0.5));
  CHECK(z(1) == Approx(2.0));
}

TEST_CASE("NNLS clamps a coefficient that wants to be negative", "[model][nnls]") {
  // y = 2 x0 - 1 x1 exactly; with x1 >= 0 the best is x1 = 0 and x0 the 1-D fit.
  Eigen::MatrixXd a(3, 2);
  a << 1, 1, 2, 1, 3, 2;
  const Eigen::VectorXd y = a * Eigen::Vector2d(2.0, -1.0);
  const Eigen::VectorXd z = solve_nonnegative(a.transpose() * a, a.transpose() * y);
  CHECK(z(1) == 0.0);
  CHECK(z(0) == Approx(a.col(0).dot(y) / a.col(0).squaredNorm()));
  CHECK((z.array() >= 0.0).all());
}

TEST_CASE("NNLS of an all-negative target is zero, of nothing is empty", "[model][nnls]") {
  Eigen::MatrixXd g = Eigen::MatrixXd::Identity(3, 3);
  CHECK(solve_nonnegative(g, Eigen::Vector3d(-1, -2, -3)).isZero());
  CHECK(solve_nonnegative(Eigen::MatrixXd(0, 0), Eigen::VectorXd(0)).size() == 0);
}

TEST_CASE("NNLS matches the best feasible active set on random problems", "[model][nnls]") {
  // The minimiser is unique for a positive definite G: enumerate all 2^n free sets, keep
  // the best feasible subspace minimiser, and require the solver to find the same point
  // (whatever set it starts from).
  std::mt19937_64 random(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + trial % 7;
    Eigen::MatrixXd a(n + 3, n);
    for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = normal(random);
    const Eigen::MatrixXd gram = a.transpose() * a + 1e-3 * Eigen::MatrixXd::Identity(n, n);
    Eigen::VectorXd rhs(n);
    for (int i = 0; i < n; ++i) rhs(i) = normal(random);
    auto objective = [&](const Eigen::VectorXd& z) { return 0.5 * z.dot(gram * z) - rhs.dot(z); };

    Eigen::VectorXd best = Eigen::VectorXd::Zero(n);
    for (int set = 1; set < (1 << n); ++set) {
      std::vector<int> free;
      for (int j = 0; j < n; ++j) {
        if (set & (1 << j)) free.push_back(j);
      }
      const auto m = static_cast<Eigen::Index>(free.size());
      Eigen::MatrixXd g(m, m);
      Eigen::VectorXd h(m);
      for (Eigen::Index r = 0; r < m; ++r) {
        h(r) = rhs(free[r]);
        for (Eigen::Index c = 0; c < m; ++c) g(r, c) = gram(free[r], free[c]);
      }
      const Eigen::VectorXd s = g.llt().solve(h);
      if ((s.array() < 0.0).any()) continue;
      Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
      for (Eigen::Index r = 0; r < m; ++r) z(free[r]) = s(r);
      if (objective(z) < objective(best)) best = z;
    }
    const Eigen::VectorXd z = solve_nonnegative(gram, rhs);
    CHECK((z.array() >= 0.0).all());
    CHECK(objective(z) == Approx(objective(best)).epsilon(1e-9).margin(1e-12));
    CHECK((z - best).norm() <= 1e-7 * std::max(1.0, best.norm()));
  }
}
