#include <catch2/catch.hpp>

#include "glbudget/model/platform_profile.hpp"

using namespace glbudget::model;

TEST_CASE("platform profile round-trips through JSON", "[model][profile]") {
  PlatformProfile written;
  written.p_min_w = 12.5;
  written.p_max_w = 88.0;
  written.saturation_batches = 4096;
  written.saturation_vertices = 2.5e7;
  written.saturation_fragments = 7.5e8;
  const PlatformProfile read = parse_platform_profile(platform_profile_to_json(written), "test");
  CHECK(read.p_min_w == written.p_min_w);
  CHECK(read.p_max_w == written.p_max_w);
  CHECK(read.saturation_batches == written.saturation_batches);
  CHECK(read.saturation_vertices == written.saturation_vertices);
  CHECK(read.saturation_fragments == written.saturation_fragments);
}

TEST_CASE("bad profile fields fall back to defaults", "[model][profile]") {
  const PlatformProfile defaults;
  const PlatformProfile read = parse_platform_profile(
      R"({"p_min_w": "cold", "p_max_w": 50, "saturation": {"batches": -1, "vertices": 0, "fragments": 9e8}})", "test");
  CHECK(read.p_min_w == defaults.p_min_w);
  CHECK(read.p_max_w == 50.0);
  CHECK(read.saturation_batches == defaults.saturation_batches);
  CHECK(read.saturation_vertices == defaults.saturation_vertices);
  CHECK(read.saturation_fragments == 9e8);

  const PlatformProfile garbage = parse_platform_profile("not json at all", "test");
  CHECK(garbage.p_max_w == defaults.p_max_w);

  const PlatformProfile inverted = parse_platform_profile(
      R"({"p_min_w": 30, "p_max_w": 10, "saturation": {"batches": 1, "vertices": 1, "fragments": 1}})", "test");
  CHECK(inverted.p_max_w == inverted.p_min_w);
  CHECK(!load_platform_profile("/nonexistent/glbudget/profile.json"));
}

TEST_CASE("a profile's calibrated costs round-trip and are all or nothing", "[model][profile][costs]") {
  PlatformProfile written;
  written.costs = PlatformCosts{0.5, 1.25, 2.0, 0.03, 0.7};
  const PlatformProfile read = parse_platform_profile(platform_profile_to_json(written), "test");
  REQUIRE(read.costs);
  CHECK(read.costs->batch == 0.5);
  CHECK(read.costs->vertex == 1.25);
  CHECK(read.costs->fragment == 2.0);
  CHECK(read.costs->instruction == 0.03);
  CHECK(read.costs->texel == 0.7);
  // Without costs none are written, and none are read.
  CHECK(platform_profile_to_json(PlatformProfile{}).find("costs") == std::string::npos);
  CHECK(!parse_platform_profile(platform_profile_to_json(PlatformProfile{}), "test").costs);

  const char* broken[] = {
      // a negative cost, a missing one, a string, not an object
      R"({"p_min_w": 1, "p_max_w": 2, "saturation": {"batches": 1, "vertices": 1, "fragments": 1},
            "costs": {"batch": -1, "vertex": 0, "fragment": 0, "instruction": 0, "texel": 0}})",
      R"({"p_min_w": 1, "p_max_w": 2, "saturation": {"batches": 1, "vertices": 1, "fragments": 1},
            "costs": {"batch": 1, "vertex": 0, "fragment": 0, "instruction": 0}})",
      R"({"p_min_w": 1, "p_max_w": 2, "saturation": {"batches": 1, "vertices": 1, "fragments": 1},
            "costs": {"batch": "1", "vertex": 0, "fragment": 0, "instruction": 0, "texel": 0}})",
      R"({"p_min_w": 1, "p_max_w": 2, "saturation": {"batches": 1, "vertices": 1, "fragments": 1},
            "costs": [1, 2, 3, 4, 5]})",
  };
  for (const char* text : broken) {
    const PlatformProfile parsed = parse_platform_profile(text, "test");
    CHECK(!parsed.costs);
    CHECK(parsed.p_max_w == 2.0);  // the rest of the profile still stands
  }
}
