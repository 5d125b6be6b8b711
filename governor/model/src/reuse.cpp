#include "glbudget/model/reuse.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "glbudget/model/nonnegative_least_squares.hpp"
#include "glbudget/model/power_curve.hpp"

namespace glbudget::model {
namespace {

const PassCounts* find_counts(const std::vector<PassFrame>& frame, PassIndex pass) {
  for (const PassFrame& p : frame) {
    if (p.pass == pass) return &p.counts;
  }
  return nullptr;
}

}  // namespace

VariantCost cheapest_drawing_level(const PassVariants& pass) {
  VariantCost least{0.0, 0.0, 0.0};
  bool any = false;
  for (const VariantCost& cost : pass.levels) {
    if (!cost.draws) continue;
    least.ins_v = any ? std::min(least.ins_v, cost.ins_v) : cost.ins_v;
    least.ins_f = any ? std::min(least.ins_f, cost.ins_f) : cost.ins_f;
    least.tex_f = any ? std::min(least.tex_f, cost.tex_f) : cost.tex_f;
    any = true;
  }
  return least;
}

ReuseCoefficients solve_reuse(const PowerModel& fitted, const ConfigurationSpace& space,
                              const Configuration& fitted_configuration, const std::vector<PassFrame>& window_mean,
                              ReuseCoefficients previous) {
  if (!space.contains(fitted_configuration)) return previous;
  const PlatformProfile& profile = fitted.profile();
  // Rows: weight * [Ins, Tex] . [chi, psi] = weight * k, two per pass.
  std::vector<std::array<double, 3>> rows;
  for (std::size_t i = 0; i < space.pass_count(); ++i) {
    const PassVariants& pass = space.passes()[i];
    const PassCoefficients* k = fitted.find(static_cast<PassIndex>(i));
    const PassCounts* mean = find_counts(window_mean, static_cast<PassIndex>(i));
    if (k == nullptr || mean == nullptr) continue;  // pass drew nothing: says nothing
    const VariantCost& cost = pass.levels[static_cast<std::size_t>(fitted_configuration[i])];
    const double vertex_weight = mean->vertices / profile.saturation_vertices;
    const double fragment_weight = mean->fragments / profile.saturation_fragments;
    if (vertex_weight > 0.0) rows.push_back({vertex_weight * cost.ins_v, 0.0, vertex_weight * k->k_v});
    if (fragment_weight > 0.0) {
      rows.push_back({fragment_weight * cost.ins_f, fragment_weight * cost.tex_f, fragment_weight * k->k_f});
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
  // A small ridge towards the previous values holds what the data cannot identify, both costs
  // non-negative (ridge_nonnegative, as the other fits).
  const Eigen::VectorXd z = ridge_nonnegative(std::move(a), y, Eigen::Vector2d(previous.chi, previous.psi),
                                              Eigen::VectorXd::Constant(2, 1e-6 * 2.0));
  return {z(0), z(1)};
}

ConfigurationPredictor::ConfigurationPredictor(const ConfigurationSpace& space, const PowerModel& fitted,
                                               const Configuration& fitted_configuration, ReuseCoefficients reuse)
    : space_(space), fitted_(fitted), scales_(space) {
  const std::size_t passes = space.pass_count();
  scalers_of_.resize(passes);
  for (std::size_t j = 0; j < passes; ++j) scalers_of_[j] = space.scalers_of(j);
  for (std::size_t p = 0; p < passes; ++p) {
    const std::vector<std::size_t>& scaled = space.scaled_by(p);
    if (std::any_of(scaled.begin(), scaled.end(), [p](std::size_t j) { return j != p; })) outer_.push_back(p);
  }
  scaled_by_outer_.assign(passes, false);
  for (std::size_t j = 0; j < passes; ++j) {
    for (std::size_t p : scalers_of_[j]) {
      if (std::find(outer_.begin(), outer_.end(), p) != outer_.end()) scaled_by_outer_[j] = true;
    }
  }
  // When the passes that scale others come first (the render scale is the paper's first
  // "pass"), each table fills one contiguous block of configurations.
  outer_is_prefix_ = true;
  for (std::size_t n = 0; n < outer_.size(); ++n) outer_is_prefix_ = outer_is_prefix_ && outer_[n] == n;
  strides_.assign(passes, 1);
  for (std::size_t i = passes; i-- > 1;) strides_[i - 1] = strides_[i] * space.passes()[i].levels.size();
  reference_.resize(passes);
  remembered_.resize(passes);
  refit(fitted, fitted_configuration, reuse);
}

void ConfigurationPredictor::refit(const PowerModel& fitted, const Configuration& fitted_configuration,
                                   ReuseCoefficients reuse) {
  fitted_ = fitted;
  fitted_configuration_ =
      space_.contains(fitted_configuration) ? fitted_configuration : Configuration(space_.pass_count(), 0);
  const bool have_fitted_levels = space_.contains(fitted_configuration);
  coefficients_.assign(space_.pass_count(), {});
  for (std::size_t i = 0; i < space_.pass_count(); ++i) {
    const PassVariants& pass = space_.passes()[i];
    const PassCoefficients* k = fitted.find(static_cast<PassIndex>(i));
    if (k == nullptr) {
      coefficients_[i].assign(pass.levels.size(), PassCoefficients{});  // never drew
      continue;
    }
    VariantCost base =
        have_fitted_levels ? pass.levels[static_cast<std::size_t>(fitted_configuration[i])] : VariantCost{};
    // Fitted while the pass was skipped: its coefficients (remembered from when it drew,
    // or from a fit over several configurations) are those of its cheapest drawing level.
    if (!base.draws) base = cheapest_drawing_level(pass);
    for (const VariantCost& cost : pass.levels) {
      coefficients_[i].push_back(
          {k->k_b, std::max(0.0, k->k_v + reuse.chi * (cost.ins_v - base.ins_v)),
           std::max(0.0, k->k_f + reuse.chi * (cost.ins_f - base.ins_f) + reuse.psi * (cost.tex_f - base.tex_f))});
    }
  }
}

PassCoefficients ConfigurationPredictor::coefficients(std::size_t pass, int level) const {
  return coefficients_[pass][static_cast<std::size_t>(level)];
}

double ConfigurationPredictor::fragment_scale(std::size_t pass, const Configuration& configuration) const {
  double scale = 1.0;
  for (std::size_t p : scalers_of_[pass]) {
    scale *= scales_.at(pass, p, configuration[p]);
  }
  return scale;
}

std::size_t ConfigurationPredictor::outer_combination(const Configuration& configuration) const {
  std::size_t combination = 0;
  for (std::size_t p : outer_) {
    combination = combination * space_.passes()[p].levels.size() + static_cast<std::size_t>(configuration[p]);
  }
  return combination;
}

void ConfigurationPredictor::set_frame(const std::vector<PassFrame>& frame, const Configuration& frame_configuration) {
  const PlatformProfile& profile = fitted_.profile();
  const std::size_t passes = space_.pass_count();
  const Configuration& drawn = space_.contains(frame_configuration) ? frame_configuration : fitted_configuration_;

  // Reference counts of the space's passes; the rest load every configuration alike.
  for (ReferenceCounts& r : reference_) r = ReferenceCounts{{}, true};
  alpha_outside_space_ = fitted_.frame_alpha();
  for (const PassFrame& p : frame) {
    if (p.pass < passes) {
      const std::size_t i = p.pass;
      const double scale = fragment_scale(i, drawn);
      PassCounts& counts = reference_[i].counts;
      counts.batches += p.counts.batches;
      counts.vertices += p.counts.vertices;
      // A scale of 0 drew no fragments: nothing to learn about them.
      if (scale > 0.0) counts.fragments += p.counts.fragments / scale;
    } else if (const PassCoefficients* k = fitted_.find(p.pass)) {
      alpha_outside_space_ += pass_alpha(profile, *k, p.counts);
    }
  }
  for (std::size_t i = 0; i < passes; ++i) {
    const bool drew = space_.passes()[i].levels[static_cast<std::size_t>(drawn[i])].draws;
    if (drew)
      remembered_[i] = reference_[i];
    else
      reference_[i] = remembered_[i];  // skipped now: what it drew when last on, if ever
  }

  std::size_t combinations = 1;
  for (std::size_t p : outer_) combinations *= space_.passes()[p].levels.size();
  tables_.resize(combinations);
  Configuration levels(passes, 0);
  for (std::size_t o = 0; o < combinations; ++o) {
    // The outer passes' levels of combination o (the last outer pass changes fastest).
    std::size_t rest = o;
    for (std::size_t n = outer_.size(); n-- > 0;) {
      const std::size_t count = space_.passes()[outer_[n]].levels.size();
      levels[outer_[n]] = static_cast<int>(rest % count);
      rest /= count;
    }
    tables_[o].resize(passes);
    for (std::size_t i = 0; i < passes; ++i) {
      const PassVariants& pass = space_.passes()[i];
      std::vector<LevelTerm>& terms = tables_[o][i];
      // Only passes whose fragments an outer pass scales differ between the tables.
      if (o > 0 && !scaled_by_outer_[i]) {
        terms = tables_[0][i];
        continue;
      }
      terms.resize(pass.levels.size());
      const int held = levels[i];  // an outer pass's level in this combination
      for (std::size_t l = 0; l < pass.levels.size(); ++l) {
        levels[i] = static_cast<int>(l);
        double alpha = 0.0;
        if (pass.levels[l].draws && reference_[i].known) {
          PassCounts counts = reference_[i].counts;
          counts.fragments *= fragment_scale(i, levels);
          alpha = pass_alpha(profile, coefficients_[i][l], counts);
        }
        terms[l] = {alpha, std::expm1(-alpha), std::exp(-alpha), l * strides_[i]};
      }
      levels[i] = held;
    }
  }
}

double ConfigurationPredictor::predict(const Configuration& configuration) const {
  if (!space_.contains(configuration)) return std::numeric_limits<double>::quiet_NaN();
  if (tables_.empty()) return fitted_.profile().p_min_w;  // no frame given yet
  const std::vector<std::vector<LevelTerm>>& table = tables_[outer_combination(configuration)];
  double alpha = alpha_outside_space_;
  for (std::size_t i = 0; i < table.size(); ++i) {
    alpha += table[i][static_cast<std::size_t>(configuration[i])].alpha;
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
// paper's 729), a loop the compiler vectorises. A pass that scales other passes' fragments
// (the render scale) makes their loads depend on its level: each of its levels is then a
// table of its own, with that pass held at the level.
void ConfigurationPredictor::enumerate(const std::vector<std::vector<LevelTerm>>& passes, const std::vector<int>& held,
                                       std::size_t first, std::size_t last, double q0, Enumeration& out) {
  out.q.assign(1, q0);
  out.offsets.assign(1, 0);
  out.e.assign(1, 1.0);
  for (std::size_t pass = first; pass < last; ++pass) {
    const std::vector<LevelTerm>& all = passes[pass];
    // A held pass (one that scales others, in this table) contributes its one level.
    const LevelTerm* terms = held[pass] >= 0 ? &all[static_cast<std::size_t>(held[pass])] : all.data();
    const std::size_t levels = held[pass] >= 0 ? 1 : all.size();
    const std::size_t n = out.q.size();
    out.next_q.resize(n * levels);
    out.next_e.resize(n * levels);
    out.next_offsets.resize(n * levels);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t l = 0; l < levels; ++l) {
        out.next_q[i * levels + l] = out.q[i] * terms[l].e + terms[l].m;
        out.next_e[i * levels + l] = out.e[i] * terms[l].e;
        out.next_offsets[i * levels + l] = out.offsets[i] + terms[l].offset;
      }
    }
    out.q.swap(out.next_q);
    out.e.swap(out.next_e);
    out.offsets.swap(out.next_offsets);
  }
}

void ConfigurationPredictor::predict_all(std::vector<double>& out) const {
  const std::size_t passes = space_.pass_count();
  const double p_min = fitted_.profile().p_min_w, range = fitted_.profile().range_w();
  out.assign(space_.size(), p_min);  // stays P_m when no frame has been given yet
  std::vector<int>& held = held_scratch_;
  held.assign(passes, -1);
  // Contiguous: enumerate the passes after the outer ones and write each table's block in
  // order. Otherwise every configuration's index is assembled from the passes' offsets.
  const std::size_t first = outer_is_prefix_ ? outer_.size() : 0;
  const std::size_t split = first + (passes - first) / 2;
  for (std::size_t o = 0; o < tables_.size(); ++o) {
    std::size_t rest = o, block = 0;
    for (std::size_t n = outer_.size(); n-- > 0;) {
      const std::size_t count = space_.passes()[outer_[n]].levels.size();
      held[outer_[n]] = static_cast<int>(rest % count);
      block += static_cast<std::size_t>(held[outer_[n]]) * strides_[outer_[n]];
      rest /= count;
    }
    // The outer passes' own loads, at their held levels, start the product.
    double q0 = std::expm1(-alpha_outside_space_);
    for (std::size_t n = 0; n < first; ++n) {
      const LevelTerm& t = tables_[o][n][static_cast<std::size_t>(held[n])];
      q0 = q0 * t.e + t.m;
    }
    enumerate(tables_[o], held, first, split, q0, front_);
    enumerate(tables_[o], held, split, passes, 0.0, back_);
    const std::size_t back = back_.q.size();
    for (std::size_t i = 0; i < front_.q.size(); ++i) {
      const double q = front_.q[i];
      if (outer_is_prefix_) {
        double* row = out.data() + block + i * back;
        for (std::size_t j = 0; j < back; ++j) row[j] = p_min - range * (q * back_.e[j] + back_.q[j]);
      } else {
        for (std::size_t j = 0; j < back; ++j) {
          out[front_.offsets[i] + back_.offsets[j]] = p_min - range * (q * back_.e[j] + back_.q[j]);
        }
      }
    }
  }
}

}  // namespace glbudget::model
