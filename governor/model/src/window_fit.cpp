#include "glbudget/model/window_fit.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "glbudget/model/nonnegative_least_squares.hpp"
#include "glbudget/model/power_curve.hpp"

namespace glbudget::model {
namespace {

constexpr int kTerms = 3;  // batches, vertices, fragments

std::array<double, kTerms> normalised_counts(const PlatformProfile& profile, const PassCounts& c) {
    return {c.batches / profile.saturation_batches, c.vertices / profile.saturation_vertices,
            c.fragments / profile.saturation_fragments};
}

double& term(PassCoefficients& k, int t) { return t == 0 ? k.k_b : t == 1 ? k.k_v : k.k_f; }

struct Column {
    std::string pass;
    int term;
};

struct RidgeSolution {
    Eigen::VectorXd coefficients;
    // Share of each estimate owed to the prior: lambda (G^-1)_jj on the scaled problem; 1 for a
    // column the data says nothing about, ~0 for a well-identified one.
    Eigen::VectorXd prior_share;
};

// Generalised cross-validation (Golub, Heath & Wahba 1979) picks how far a window's
// estimate may move from the prior: noiseless data get the smallest ridge and an exact fit,
// noisy or barely varying counts a stronger pull instead of noise amplified into the
// coefficients. Works on the eigen-decomposition of A'A: `s2` are the squared singular values
// of A, `v_atr` = V' A' r for the residual r = y - A prior.
double choose_lambda(const Eigen::VectorXd& s2, const Eigen::VectorXd& v_atr, double residual_norm2,
                     double rows, double floor) {
    // Squared components of r along A's left singular vectors: (v_i' A' r)^2 / s_i^2.
    const double negligible = 1e-14 * std::max(s2.maxCoeff(), 1e-300);
    Eigen::VectorXd projected2(s2.size());
    for (Eigen::Index i = 0; i < s2.size(); ++i) {
        projected2(i) = s2(i) > negligible ? v_atr(i) * v_atr(i) / s2(i) : 0.0;
    }
    const double outside = std::max(0.0, residual_norm2 - projected2.sum());
    const double ceiling = std::max(floor, static_cast<double>(s2.size()));
    double best_lambda = floor, best_score = std::numeric_limits<double>::infinity();
    for (double lambda = floor; lambda <= ceiling * 1.0001; lambda *= std::sqrt(10.0)) {
        double rss = outside, dof = 0.0;
        for (Eigen::Index i = 0; i < s2.size(); ++i) {
            const double shrink = lambda / (s2(i) + lambda);
            rss += shrink * shrink * projected2(i);
            dof += s2(i) / (s2(i) + lambda);
        }
        const double denominator = rows - dof;
        if (denominator < 0.5) continue;  // as many effective parameters as samples
        const double score = rows * rss / (denominator * denominator);
        if (score < best_score * (1.0 - 1e-9)) best_score = score, best_lambda = lambda;
    }
    return best_lambda;
}

// min |A k - y|^2 + lambda |D (k - prior)|^2 subject to k >= 0, where D scales A's columns to
// unit norm (so the ridge means the same for counts of any magnitude). lambda is chosen by
// GCV, never below ridge^2 * columns: directions of A with singular values well below
// sqrt(lambda) stay at the prior. One symmetric eigen-decomposition of A'A serves the choice
// of lambda, the ridge solution and the prior shares; the active-set solver only runs when
// that solution has a negative coefficient.
RidgeSolution solve_ridge_nonnegative(Eigen::MatrixXd a, const Eigen::VectorXd& y,
                                      const Eigen::VectorXd& prior, double ridge) {
    const Eigen::Index cols = a.cols();
    const Eigen::VectorXd scale = a.colwise().norm().transpose();
    for (Eigen::Index c = 0; c < cols; ++c) {
        if (scale(c) > 0.0) a.col(c) /= scale(c);
    }
    const Eigen::VectorXd scaled_prior = prior.cwiseProduct(scale);
    const Eigen::VectorXd residual = y - a * scaled_prior;
    Eigen::MatrixXd gram = a.transpose() * a;
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram);
    const Eigen::VectorXd s2 = eigen.eigenvalues().cwiseMax(0.0);
    const Eigen::MatrixXd& v = eigen.eigenvectors();
    const Eigen::VectorXd v_atr = v.transpose() * (a.transpose() * residual);
    const double lambda = choose_lambda(s2, v_atr, residual.squaredNorm(), static_cast<double>(a.rows()),
                                        ridge * ridge * static_cast<double>(cols));
    const Eigen::VectorXd inverse_eigen = (s2.array() + lambda).inverse().matrix();

    Eigen::VectorXd z = scaled_prior + v * inverse_eigen.cwiseProduct(v_atr);
    if (z.minCoeff() < 0.0) {
        gram.diagonal().array() += lambda;
        z = solve_nonnegative(gram, a.transpose() * y + lambda * scaled_prior);
    }

    RidgeSolution solution;
    // Share of each estimate owed to the prior: lambda (G^-1)_jj, G = A'A + lambda I.
    solution.prior_share = lambda * (v.array().square().matrix() * inverse_eigen);
    solution.coefficients = prior;  // an all-zero column keeps its prior
    for (Eigen::Index c = 0; c < cols; ++c) {
        if (scale(c) > 0.0) solution.coefficients(c) = z(c) / scale(c);
    }
    return solution;
}

}  // namespace

WindowFitResult fit_window(std::span<const FrameSample> window, const PowerModel& previous,
                           const WindowFitSettings& settings) {
    WindowFitResult result{previous};
    const PlatformProfile& profile = previous.profile();

    std::vector<const FrameSample*> usable;
    for (const FrameSample& sample : window) {
        if (is_usable(sample)) usable.push_back(&sample);
        else ++result.samples_rejected;
    }
    result.samples_used = usable.size();
    if (usable.empty() || !(profile.range_w() > 0.0)) return result;  // nothing to learn

    // One column per (pass, term) with any non-zero count in the window.
    std::map<std::string, std::array<int, kTerms>> column_of;  // -1: no column
    for (const FrameSample* sample : usable) {
        for (const PassFrame& pass : sample->passes) {
            auto [it, inserted] = column_of.try_emplace(pass.pass);
            if (inserted) it->second.fill(-1);
            const auto x = normalised_counts(profile, pass.counts);
            for (int t = 0; t < kTerms; ++t) {
                if (x[t] > 0.0 && it->second[t] < 0) it->second[t] = 0;  // mark, numbered below
            }
        }
    }
    std::vector<Column> columns;
    for (auto& [pass, indices] : column_of) {
        for (int t = 0; t < kTerms; ++t) {
            if (indices[t] >= 0) {
                indices[t] = static_cast<int>(columns.size());
                columns.push_back({pass, t});
            }
        }
    }
    result.columns = columns.size();
    if (columns.empty()) return result;

    const auto rows = static_cast<Eigen::Index>(usable.size());
    const auto cols = static_cast<Eigen::Index>(columns.size());
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(rows, cols);
    Eigen::VectorXd y(rows);
    for (Eigen::Index r = 0; r < rows; ++r) {
        const LinearisedPower target = linearise_power(profile, usable[r]->power_w);
        y(r) = target.weight * target.alpha;
        for (const PassFrame& pass : usable[r]->passes) {
            const auto& indices = column_of.at(pass.pass);
            const auto x = normalised_counts(profile, pass.counts);
            for (int t = 0; t < kTerms; ++t) {
                if (indices[t] >= 0) a(r, indices[t]) += target.weight * x[t];
            }
        }
    }

    // Prior for each column: the previous coefficient where the pass has one; for a pass seen
    // for the first time, the pooled fit below (one k_b, k_v, k_f shared by all passes, which
    // a window identifies far better than per-pass values).
    Eigen::VectorXd prior(cols);
    std::vector<bool> has_previous(static_cast<std::size_t>(cols));
    for (Eigen::Index c = 0; c < cols; ++c) {
        const PassCoefficients* found = previous.find(columns[c].pass);
        has_previous[c] = found != nullptr;
        PassCoefficients k = found ? *found : PassCoefficients{};
        prior(c) = term(k, columns[c].term);
    }
    if (std::find(has_previous.begin(), has_previous.end(), false) != has_previous.end()) {
        Eigen::MatrixXd pooled = Eigen::MatrixXd::Zero(rows, kTerms);
        for (Eigen::Index c = 0; c < cols; ++c) pooled.col(columns[c].term) += a.col(c);
        const RidgeSolution shared = solve_ridge_nonnegative(pooled, y, Eigen::VectorXd::Zero(kTerms), settings.ridge);
        for (Eigen::Index c = 0; c < cols; ++c) {
            if (!has_previous[c]) prior(c) = shared.coefficients(columns[c].term);
        }
    }
    const RidgeSolution solution = solve_ridge_nonnegative(a, y, prior, settings.ridge);
    const Eigen::VectorXd& prior_share = solution.prior_share;

    for (Eigen::Index c = 0; c < cols; ++c) {
        if (prior_share(c) > settings.held_share) ++result.held_terms;
        PassCoefficients k;
        if (const PassCoefficients* found = result.model.find(columns[c].pass)) k = *found;
        term(k, columns[c].term) = solution.coefficients(c);
        result.model.set(columns[c].pass, k);
    }
    return result;
}

}  // namespace glbudget::model
