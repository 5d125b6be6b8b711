#include <catch2/catch.hpp>

#include "glbudget/model/temporal_filter.hpp"

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
