#include "glbudget/model/window_fit.hpp"

#include <Eigen/Cholesky>
#include <array>
#include <cmath>
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

    // Unit-norm columns; z = scale .* k are the unknowns actually solved for. A column can be
    // all zero after weighting (only saturated samples saw it): it is then held entirely.
    Eigen::VectorXd scale = a.colwise().norm().transpose();
    for (Eigen::Index c = 0; c < cols; ++c) {
        if (scale(c) > 0.0) a.col(c) /= scale(c);
    }
    Eigen::VectorXd z_previous(cols);
    for (Eigen::Index c = 0; c < cols; ++c) {
        PassCoefficients k;
        if (const PassCoefficients* found = previous.find(columns[c].pass)) k = *found;
        z_previous(c) = term(k, columns[c].term) * scale(c);
    }

    const double lambda = settings.ridge * settings.ridge * static_cast<double>(cols);
    Eigen::MatrixXd gram = a.transpose() * a;
    gram.diagonal().array() += lambda;
    const Eigen::VectorXd rhs = a.transpose() * y + lambda * z_previous;
    const Eigen::VectorXd z = solve_nonnegative(gram, rhs);

    // Share of each estimate owed to the prior: lambda * (G^-1)_jj, 1 for a column the window
    // says nothing about, ~0 for a well-identified one.
    const Eigen::VectorXd prior_share =
        lambda * gram.ldlt().solve(Eigen::MatrixXd::Identity(cols, cols)).diagonal();

    for (Eigen::Index c = 0; c < cols; ++c) {
        if (prior_share(c) > settings.held_share) ++result.held_terms;
        PassCoefficients k;
        if (const PassCoefficients* found = result.model.find(columns[c].pass)) k = *found;
        if (scale(c) > 0.0) term(k, columns[c].term) = z(c) / scale(c);
        result.model.set(columns[c].pass, k);
    }
    return result;
}

}  // namespace glbudget::model
