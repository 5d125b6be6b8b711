#include "glbudget/model/nonnegative_least_squares.hpp"

#include <Eigen/Cholesky>
#include <algorithm>

namespace glbudget::model {
namespace {

class ActiveSetSolver {
 public:
  using Matrix = Eigen::MatrixXd;
  using Vector = Eigen::VectorXd;
  using Indices = Eigen::Matrix<Eigen::Index, Eigen::Dynamic, 1>;

  ActiveSetSolver(const Eigen::Ref<const Eigen::MatrixXd>& gram, const Eigen::Ref<const Eigen::VectorXd>& rhs)
      : gram_(gram), rhs_(rhs), n_(rhs.size()), free_(n_), is_free_(n_) {}

  void solve(Eigen::Ref<Eigen::VectorXd> z) {
    z.setZero();
    if (n_ == 0) return;
    const double tolerance = 1e-12 * std::max(1.0, rhs_.cwiseAbs().maxCoeff());
    is_free_.setZero();
    Vector s(n_);

    // Warm start. Lawson & Hanson start from z = 0 and free one variable per outer
    // iteration, a factorisation each: ~n of them when most of the solution is positive,
    // as in a ridge fit with a few zero costs. Starting instead from the positive part of
    // the unconstrained solution (dropping negative entries until the rest solves to
    // positive values) gives a point the method may start from — feasible, and the
    // minimiser on its free set — from which it usually needs no or few iterations. The
    // minimiser is unique (G positive definite), so where the method starts does not
    // change what it returns beyond rounding.
    free_count_ = n_;
    for (Eigen::Index j = 0; j < n_; ++j) free_(j) = j;
    solve_on_free_set(s);
    for (;;) {
      Eigen::Index kept = 0;
      for (Eigen::Index k = 0; k < free_count_; ++k) {
        if (s(free_(k)) > 0.0) free_(kept++) = free_(k);
      }
      if (kept == free_count_) break;
      free_count_ = kept;
      solve_on_free_set(s);
    }
    for (Eigen::Index k = 0; k < free_count_; ++k) is_free_(free_(k)) = 1;
    z = s;

    for (Eigen::Index outer = 0; outer < 3 * n_; ++outer) {
      const Vector descent = rhs_ - gram_ * z;
      Eigen::Index best = -1;
      double best_value = tolerance;
      for (Eigen::Index j = 0; j < n_; ++j) {
        if (!is_free_(j) && descent(j) > best_value) best = j, best_value = descent(j);
      }
      if (best < 0) break;  // KKT conditions hold
      is_free_(best) = 1;
      free_(free_count_++) = best;

      solve_on_free_set(s);
      for (Eigen::Index inner = 0; inner < 3 * n_; ++inner) {
        double step = 1.0;
        bool feasible = true;
        for (Eigen::Index k = 0; k < free_count_; ++k) {
          const Eigen::Index j = free_(k);
          if (s(j) <= 0.0) {
            feasible = false;
            const double denominator = z(j) - s(j);
            if (denominator > 0.0) step = std::min(step, z(j) / denominator);
          }
        }
        if (feasible) break;
        z += step * (s - z);
        // Variables that reached the bound leave the free set.
        Eigen::Index kept = 0;
        for (Eigen::Index k = 0; k < free_count_; ++k) {
          const Eigen::Index j = free_(k);
          if (z(j) <= tolerance) {
            z(j) = 0.0;
            is_free_(j) = 0;
          } else {
            free_(kept++) = j;
          }
        }
        free_count_ = kept;
        solve_on_free_set(s);
      }
      z = s.cwiseMax(0.0);
    }
  }

 private:
  // Unconstrained minimiser restricted to the free set (other entries zero).
  void solve_on_free_set(Vector& s) const {
    s.setZero();
    const Eigen::Index m = free_count_;
    if (m == 0) return;
    Matrix g(m, m);
    Vector h(m);
    for (Eigen::Index r = 0; r < m; ++r) {
      h(r) = rhs_(free_(r));
      for (Eigen::Index c = 0; c < m; ++c) g(r, c) = gram_(free_(r), free_(c));
    }
    const Vector s_free = g.ldlt().solve(h);
    for (Eigen::Index r = 0; r < m; ++r) s(free_(r)) = s_free(r);
  }

  const Eigen::Ref<const Eigen::MatrixXd>& gram_;
  const Eigen::Ref<const Eigen::VectorXd>& rhs_;
  Eigen::Index n_;
  Indices free_;  // the free set (first free_count_ entries), in the order variables entered
  Eigen::Index free_count_ = 0;
  Eigen::Matrix<char, Eigen::Dynamic, 1> is_free_;
};

}  // namespace

void solve_nonnegative(const Eigen::Ref<const Eigen::MatrixXd>& gram, const Eigen::Ref<const Eigen::VectorXd>& rhs,
                       Eigen::Ref<Eigen::VectorXd> z) {
  ActiveSetSolver(gram, rhs).solve(z);
}

Eigen::VectorXd solve_nonnegative(const Eigen::MatrixXd& gram, const Eigen::VectorXd& rhs) {
  Eigen::VectorXd z(rhs.size());
  solve_nonnegative(Eigen::Ref<const Eigen::MatrixXd>(gram), Eigen::Ref<const Eigen::VectorXd>(rhs), z);
  return z;
}

Eigen::VectorXd ridge_nonnegative(Eigen::MatrixXd a, const Eigen::VectorXd& y, const Eigen::VectorXd& prior,
                                  const Eigen::VectorXd& ridge) {
  const Eigen::Index cols = a.cols();
  const Eigen::VectorXd scale = a.colwise().norm().transpose();
  for (Eigen::Index c = 0; c < cols; ++c) {
    if (scale(c) > 0.0) a.col(c) /= scale(c);
  }
  const Eigen::VectorXd scaled_prior = prior.cwiseProduct(scale);
  Eigen::MatrixXd gram = a.transpose() * a;
  gram.diagonal() += ridge;
  for (Eigen::Index c = 0; c < cols; ++c) {
    if (scale(c) == 0.0) gram(c, c) = 1.0;  // no data: its unknown is 0 and discarded below
  }
  const Eigen::VectorXd z = solve_nonnegative(gram, a.transpose() * y + ridge.cwiseProduct(scaled_prior));
  Eigen::VectorXd unknowns = prior;
  for (Eigen::Index c = 0; c < cols; ++c) {
    if (scale(c) > 0.0) unknowns(c) = z(c) / scale(c);
  }
  return unknowns;
}

}  // namespace glbudget::model
