#pragma once
// Non-negative least squares in normal-equation form: minimise 1/2 z'Gz - h'z subject to
// z >= 0, for a symmetric positive definite G (Lawson & Hanson's active-set method).
// Eigen 3.4 has no NNLS module, so this small solver lives here.
#include <Eigen/Core>

namespace glbudget::model {

Eigen::VectorXd solve_nonnegative(const Eigen::MatrixXd& gram, const Eigen::VectorXd& rhs);

// The same, writing into `z` (sized like rhs), taking any column-major storage without a copy.
void solve_nonnegative(const Eigen::Ref<const Eigen::MatrixXd>& gram, const Eigen::Ref<const Eigen::VectorXd>& rhs,
                       Eigen::Ref<Eigen::VectorXd> z);

// The regression every fit of the model runs (the window fit, which picks its ridge by
// cross-validation on an eigen-decomposition, reaches solve_nonnegative itself):
//   min |A z - y|^2 + sum_j ridge_j |A_j|^2 (z_j - prior_j)^2  subject to z >= 0,
// i.e. each column scaled to unit norm first, so that a ridge means the same for counts of any
// magnitude. ridge_j = 0 leaves a column free; a column with no data (all zero) keeps its prior.
Eigen::VectorXd ridge_nonnegative(Eigen::MatrixXd a, const Eigen::VectorXd& y, const Eigen::VectorXd& prior,
                                  const Eigen::VectorXd& ridge);

}  // namespace glbudget::model
