#include <catch2/catch.hpp>

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
