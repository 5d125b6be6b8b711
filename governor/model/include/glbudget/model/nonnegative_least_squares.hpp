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

}  // namespace glbudget::model
