#include <catch2/catch.hpp>

#include "glbudget/model/temporal_filter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

using namespace glbudget::model;

TEST_CASE("temporal filter moves from the old to the new configuration over T", "[model][filter]") {
  const Configuration old_c{0, 0, 2, 1};
  const Configuration new_c{2, 1, 0, 1};
  CHECK(blend_configurations(old_c, new_c, 0.0, 2.0) == old_c);
  CHECK(blend_configurations(old_c, new_c, 2.0, 2.0) == new_c);
  CHECK(blend_configurations(old_c, new_c, 0.5, 2.0) == Configuration{1, 0, 2, 1});  // 0.5 -> 1, 0.25 -> 0
  CHECK(blend_configurations(old_c, new_c, 1.0, 2.0) == Configuration{1, 1, 1, 1});  // halves round up
  CHECK(blend_configurations(old_c, new_c, 1.6, 2.0) == Configuration{2, 1, 0, 1});
}

TEST_CASE("temporal filter extremes", "[model][filter][extremes]") {
  const Configuration old_c{0, 2};
  const Configuration new_c{2, 0};
  CHECK(blend_configurations(old_c, new_c, -1.0, 2.0) == old_c);
  CHECK(blend_configurations(old_c, new_c, 99.0, 2.0) == new_c);
  CHECK(blend_configurations(old_c, new_c, 0.0, 0.0) == new_c);
  CHECK(blend_configurations(old_c, new_c, std::nan(""), 2.0) == new_c);
  CHECK(blend_configurations(old_c, Configuration{1}, 1.0, 2.0) == Configuration{1});
}

namespace {

// Power as additive per pass and level: watts[pass][level] (level 0 of every pass at 10 W).
double additive_w(const Configuration& c, const std::vector<std::vector<double>>& watts) {
  double w = 0.0;
  for (std::size_t i = 0; i < c.size(); ++i) w += watts[i][static_cast<std::size_t>(c[i])];
  return w;
}

// Levels changed from one configuration to another, summed over the passes.
int levels_between(const Configuration& a, const Configuration& b) {
  int moved = 0;
  for (std::size_t i = 0; i < a.size(); ++i) moved += std::abs(a[i] - b[i]);
  return moved;
}

}  // namespace

TEST_CASE("an ordered transition takes the blend's steps at its moments, cheapest first", "[model][filter]") {
  // Pass 0 moves 2 -> 0 (dearer: 3 W, then 4 W more), pass 1 0 -> 2 (saves 5 W, then 1 W), pass
  // 2 1 -> 0 (dearer by 0.5 W).
  const std::vector<std::vector<double>> watts{{10.0, 6.0, 3.0}, {10.0, 5.0, 4.0}, {10.0, 9.5, 9.0}};
  const auto power = [&](const Configuration& c) { return additive_w(c, watts); };
  const Configuration from{2, 0, 1}, to{0, 2, 0};
  const TransitionPath ordered = ordered_transition(from, to, power);
  const std::vector<Configuration>& path = ordered.configurations;
  REQUIRE(path.size() == 6);  // five one-level steps
  CHECK(path.front() == from);
  CHECK(path.back() == to);
  // The savings first (pass 1 twice), then the cheapest of what spends (pass 2's 0.5 W, then
  // pass 0's 3 W and 4 W).
  CHECK(path[1] == Configuration{2, 1, 1});
  CHECK(path[2] == Configuration{2, 2, 1});
  CHECK(path[3] == Configuration{2, 2, 0});
  CHECK(path[4] == Configuration{1, 2, 0});
  for (std::size_t k = 1; k < path.size(); ++k) CHECK(levels_between(path[k], path[k - 1]) == 1);
  // At every moment as many levels changed as the blend has changed, and (additive power,
  // here) never a dearer configuration than the blend's, nor one dearer than the dearer end.
  REQUIRE(ordered.progress.size() == 5);
  CHECK(std::is_sorted(ordered.progress.begin(), ordered.progress.end()));
  CHECK(power(from) == 22.5);
  CHECK(power(to) == 24.0);
  const auto levels_from = [&](const Configuration& c) { return levels_between(c, from); };
  for (int k = 0; k <= 400; ++k) {
    const double t = 0.005 * k;
    INFO("t " << t);
    const Configuration at = along_path(ordered, t, 2.0);
    const Configuration blended = blend_configurations(from, to, t, 2.0);
    CHECK(levels_from(at) == levels_from(blended));
    CHECK(power(at) <= power(blended));
    CHECK(power(at) <= std::max(power(from), power(to)));
  }
  // The blend's own moments, a level falling just after them: t / T = 1/4, 1/2 and 3/4.
  for (const double t : {0.5, 1.0, 1.5}) {
    INFO("t " << t);
    CHECK(levels_from(along_path(ordered, t, 2.0)) == levels_from(blend_configurations(from, to, t, 2.0)));
  }
}

TEST_CASE("transition path extremes", "[model][filter][extremes]") {
  const auto flat = [](const Configuration&) { return 1.0; };
  // From where it is: the path is that configuration alone, whatever t.
  const TransitionPath still = ordered_transition({1, 2}, {1, 2}, flat);
  CHECK(still.configurations == std::vector<Configuration>{{1, 2}});
  CHECK(still.progress.empty());
  CHECK(along_path(still, 5.0, 2.0) == Configuration{1, 2});
  // Equal weights: the lower pass first; none finite, or no weight at all, the same.
  const std::vector<Configuration> by_pass{{0, 0}, {1, 0}, {1, 1}};
  CHECK(ordered_transition({0, 0}, {1, 1}, flat).configurations == by_pass);
  CHECK(ordered_transition({0, 0}, {1, 1}, [](const Configuration&) { return std::nan(""); }).configurations ==
        by_pass);
  CHECK(ordered_transition({0, 0}, {1, 1}, {}).configurations == by_pass);
  // A finite weight before any that is not; infinity is not finite.
  const auto pass0_unknown = [](const Configuration& c) {
    return c[0] > 0 ? std::numeric_limits<double>::infinity() : 5.0;
  };
  CHECK(ordered_transition({0, 0}, {1, 1}, pass0_unknown).configurations[1] == Configuration{0, 1});
  // Lengths that differ: the target alone, at once.
  const TransitionPath other = ordered_transition({0, 0}, {1}, flat);
  CHECK(other.configurations == std::vector<Configuration>{{1}});
  CHECK(along_path(other, 0.0, 2.0) == Configuration{1});
  // Time outside [0, T], T not positive, t not a number; an empty path.
  const TransitionPath both = ordered_transition({0, 0}, {1, 1}, flat);
  CHECK(along_path(both, -1.0, 2.0) == Configuration{0, 0});
  CHECK(along_path(both, 0.99, 2.0) == Configuration{0, 0});
  CHECK(along_path(both, 1.0, 2.0) == Configuration{1, 1});  // both rise at half of T, as blended
  CHECK(along_path(both, 99.0, 2.0) == Configuration{1, 1});
  CHECK(along_path(both, 1.0, 0.0) == Configuration{1, 1});
  CHECK(along_path(both, std::nan(""), 2.0) == Configuration{1, 1});
  CHECK(along_path(TransitionPath{}, 1.0, 2.0).empty());
}
