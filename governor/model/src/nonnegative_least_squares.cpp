#include "glbudget/model/nonnegative_least_squares.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <vector>

namespace glbudget::model {
namespace {

// Unconstrained minimiser restricted to the free set (other entries zero).
Eigen::VectorXd solve_on_free_set(const Eigen::MatrixXd& gram, const Eigen::VectorXd& rhs,
                                  const std::vector<Eigen::Index>& free) {
    const auto m = static_cast<Eigen::Index>(free.size());
    Eigen::MatrixXd g(m, m);
    Eigen::VectorXd h(m);
    for (Eigen::Index r = 0; r < m; ++r) {
        h(r) = rhs(free[r]);
        for (Eigen::Index c = 0; c < m; ++c) g(r, c) = gram(free[r], free[c]);
    }
    const Eigen::VectorXd s_free = g.ldlt().solve(h);
    Eigen::VectorXd s = Eigen::VectorXd::Zero(rhs.size());
    for (Eigen::Index r = 0; r < m; ++r) s(free[r]) = s_free(r);
    return s;
}

}  // namespace

Eigen::VectorXd solve_nonnegative(const Eigen::MatrixXd& gram, const Eigen::VectorXd& rhs) {
    const Eigen::Index n = rhs.size();
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
    if (n == 0) return z;
    const double tolerance = 1e-12 * std::max(1.0, rhs.cwiseAbs().maxCoeff());
    std::vector<bool> is_free(n, false);
    std::vector<Eigen::Index> free;

    for (Eigen::Index outer = 0; outer < 3 * n; ++outer) {
        const Eigen::VectorXd descent = rhs - gram * z;
        Eigen::Index best = -1;
        double best_value = tolerance;
        for (Eigen::Index j = 0; j < n; ++j) {
            if (!is_free[j] && descent(j) > best_value) best = j, best_value = descent(j);
        }
        if (best < 0) break;  // KKT conditions hold
        is_free[best] = true;
        free.push_back(best);

        Eigen::VectorXd s = solve_on_free_set(gram, rhs, free);
        for (Eigen::Index inner = 0; inner < 3 * n; ++inner) {
            double step = 1.0;
            bool feasible = true;
            for (Eigen::Index j : free) {
                if (s(j) <= 0.0) {
                    feasible = false;
                    const double denominator = z(j) - s(j);
                    if (denominator > 0.0) step = std::min(step, z(j) / denominator);
                }
            }
            if (feasible) break;
            z += step * (s - z);
            // Variables that reached the bound leave the free set.
            std::vector<Eigen::Index> kept;
            for (Eigen::Index j : free) {
                if (z(j) <= tolerance) {
                    z(j) = 0.0;
                    is_free[j] = false;
                } else {
                    kept.push_back(j);
                }
            }
            free.swap(kept);
            s = free.empty() ? Eigen::VectorXd::Zero(n) : solve_on_free_set(gram, rhs, free);
        }
        z = s.cwiseMax(0.0);
    }
    return z;
}

}  // namespace glbudget::model
