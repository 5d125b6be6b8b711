#include "glbudget/model/reuse.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>

#include "glbudget/model/nonnegative_least_squares.hpp"
#include "glbudget/model/power_curve.hpp"

namespace glbudget::model {
namespace {

const PassCounts* find_counts(const std::vector<PassFrame>& frame, const std::string& pass) {
    for (const PassFrame& p : frame) {
        if (p.pass == pass) return &p.counts;
    }
    return nullptr;
}

}  // namespace

ReuseCoefficients solve_reuse(const PowerModel& fitted, const ConfigurationSpace& space,
                              const Configuration& fitted_configuration,
                              const std::vector<PassFrame>& window_mean,
                              ReuseCoefficients previous) {
    if (!space.contains(fitted_configuration)) return previous;
    const PlatformProfile& profile = fitted.profile();
    // Rows: weight * [Ins, Tex] . [chi, psi] = weight * k, two per pass.
    std::vector<std::array<double, 3>> rows;
    for (std::size_t i = 0; i < space.pass_count(); ++i) {
        const PassVariants& pass = space.passes()[i];
        const PassCoefficients* k = fitted.find(pass.pass);
        const PassCounts* mean = find_counts(window_mean, pass.pass);
        if (k == nullptr || mean == nullptr) continue;  // pass drew nothing: says nothing
        const VariantCost& cost = pass.levels[static_cast<std::size_t>(fitted_configuration[i])];
        const double vertex_weight = mean->vertices / profile.saturation_vertices;
        const double fragment_weight = mean->fragments / profile.saturation_fragments;
        if (vertex_weight > 0.0) rows.push_back({vertex_weight * cost.ins_v, 0.0, vertex_weight * k->k_v});
        if (fragment_weight > 0.0) {
            rows.push_back({fragment_weight * cost.ins_f, fragment_weight * cost.tex_f,
                            fragment_weight * k->k_f});
        }
    }
    if (rows.empty()) return previous;

    Eigen::MatrixXd a(static_cast<Eigen::Index>(rows.size()), 2);
    Eigen::VectorXd y(a.rows());
    for (Eigen::Index r = 0; r < a.rows(); ++r) {
        a(r, 0) = rows[r][0];
        a(r, 1) = rows[r][1];
        y(r) = rows[r][2];
    }
    // Same scheme as the window fit: unit columns, a small ridge towards the previous values
    // holds what the data cannot identify, both costs non-negative.
    Eigen::Vector2d scale = a.colwise().norm().transpose();
    for (int c = 0; c < 2; ++c) {
        if (scale(c) > 0.0) a.col(c) /= scale(c);
    }
    const double lambda = 1e-6 * 2.0;
    Eigen::MatrixXd gram = a.transpose() * a;
    gram.diagonal().array() += lambda;
    const Eigen::Vector2d z_previous(previous.chi * scale(0), previous.psi * scale(1));
    const Eigen::VectorXd z = solve_nonnegative(gram, a.transpose() * y + lambda * z_previous);
    return {scale(0) > 0.0 ? z(0) / scale(0) : previous.chi,
            scale(1) > 0.0 ? z(1) / scale(1) : previous.psi};
}

ConfigurationPredictor::ConfigurationPredictor(const ConfigurationSpace& space,
                                               const PowerModel& fitted,
                                               const Configuration& fitted_configuration,
                                               ReuseCoefficients reuse)
    : space_(space), fitted_(fitted) {
    const bool have_fitted_levels = space.contains(fitted_configuration);
    coefficients_.resize(space.pass_count());
    alpha_.resize(space.pass_count());
    decay_.resize(space.pass_count());
    decay_minus_one_.resize(space.pass_count());
    for (std::size_t i = 0; i < space.pass_count(); ++i) {
        const PassVariants& pass = space.passes()[i];
        alpha_[i].assign(pass.levels.size(), 0.0);
        decay_[i].assign(pass.levels.size(), 1.0);
        decay_minus_one_[i].assign(pass.levels.size(), 0.0);
        const PassCoefficients* k = fitted.find(pass.pass);
        if (k == nullptr) {
            coefficients_[i].assign(pass.levels.size(), PassCoefficients{});  // never drew
            continue;
        }
        const VariantCost base =
            have_fitted_levels ? pass.levels[static_cast<std::size_t>(fitted_configuration[i])]
                               : VariantCost{};
        for (const VariantCost& cost : pass.levels) {
            coefficients_[i].push_back(
                {k->k_b, std::max(0.0, k->k_v + reuse.chi * (cost.ins_v - base.ins_v)),
                 std::max(0.0, k->k_f + reuse.chi * (cost.ins_f - base.ins_f) +
                                   reuse.psi * (cost.tex_f - base.tex_f))});
        }
    }
}

PassCoefficients ConfigurationPredictor::coefficients(std::size_t pass, int level) const {
    return coefficients_[pass][static_cast<std::size_t>(level)];
}

void ConfigurationPredictor::set_frame(const std::vector<PassFrame>& frame) {
    const PlatformProfile& profile = fitted_.profile();
    for (auto& levels : alpha_) std::fill(levels.begin(), levels.end(), 0.0);
    alpha_outside_space_ = 0.0;
    for (const PassFrame& p : frame) {
        bool in_space = false;
        for (std::size_t i = 0; i < space_.pass_count(); ++i) {
            if (space_.passes()[i].pass != p.pass) continue;
            in_space = true;
            for (std::size_t l = 0; l < alpha_[i].size(); ++l) {
                alpha_[i][l] += pass_alpha(profile, coefficients_[i][l], p.counts);
            }
            break;
        }
        if (!in_space) {
            if (const PassCoefficients* k = fitted_.find(p.pass)) {
                alpha_outside_space_ += pass_alpha(profile, *k, p.counts);
            }
        }
    }
    for (std::size_t i = 0; i < alpha_.size(); ++i) {
        for (std::size_t l = 0; l < alpha_[i].size(); ++l) {
            decay_[i][l] = std::exp(-alpha_[i][l]);
            decay_minus_one_[i][l] = std::expm1(-alpha_[i][l]);
        }
    }
}

double ConfigurationPredictor::predict(const Configuration& configuration) const {
    double alpha = alpha_outside_space_;
    for (std::size_t i = 0; i < alpha_.size(); ++i) {
        alpha += alpha_[i][static_cast<std::size_t>(configuration[i])];
    }
    return power_from_alpha(fitted_.profile(), alpha);
}

// Predicting all configurations needs no transcendental per configuration: with
// m_i = expm1(-alpha_i), e_i = exp(-alpha_i) and q = prod(1 + m_i) - 1 = -(1 - exp(-sum alpha)),
// appending a pass updates q <- q e_i + m_i. Both terms are <= 0, so nothing cancels and tiny
// loads keep their relative precision, as with expm1 of the sum.
//
// The passes are split in two halves; each half's combinations are enumerated once, and every
// configuration is then one multiply-add of a front entry with a back entry (27 x 27 for the
// paper's 729), a loop the compiler vectorises.
void ConfigurationPredictor::enumerate(std::size_t first, std::size_t last, double q0,
                                       std::vector<double>& q, std::vector<double>* e) const {
    q.assign(1, q0);
    if (e) e->assign(1, 1.0);
    std::vector<double> next_q, next_e;
    for (std::size_t pass = first; pass < last; ++pass) {
        const std::vector<double>& m_pass = decay_minus_one_[pass];
        const std::vector<double>& e_pass = decay_[pass];
        const std::size_t levels = m_pass.size();
        next_q.resize(q.size() * levels);
        for (std::size_t i = 0; i < q.size(); ++i) {
            for (std::size_t l = 0; l < levels; ++l) next_q[i * levels + l] = q[i] * e_pass[l] + m_pass[l];
        }
        q.swap(next_q);
        if (e) {
            next_e.resize(e->size() * levels);
            for (std::size_t i = 0; i < e->size(); ++i) {
                for (std::size_t l = 0; l < levels; ++l) next_e[i * levels + l] = (*e)[i] * e_pass[l];
            }
            e->swap(next_e);
        }
    }
}

void ConfigurationPredictor::predict_all(std::vector<double>& out) const {
    const std::size_t split = decay_.size() / 2;
    std::vector<double> front_q, back_q, back_e;
    enumerate(0, split, std::expm1(-alpha_outside_space_), front_q, nullptr);
    enumerate(split, decay_.size(), 0.0, back_q, &back_e);
    const double p_min = fitted_.profile().p_min_w, range = fitted_.profile().range_w();
    const std::size_t back = back_q.size();
    out.resize(front_q.size() * back);
    for (std::size_t i = 0; i < front_q.size(); ++i) {
        double* row = out.data() + i * back;
        const double q = front_q[i];
        for (std::size_t j = 0; j < back; ++j) row[j] = p_min - range * (q * back_e[j] + back_q[j]);
    }
}

}  // namespace glbudget::model
