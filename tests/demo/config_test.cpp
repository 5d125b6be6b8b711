#include <catch2/catch.hpp>

#include <set>

#include "config.hpp"

using demo::Config;
using demo::Knob;

TEST_CASE("configurations parse and format round trip", "[demo][config]") {
  const auto config = demo::parse_config("0,1,2,0,0,1");
  REQUIRE(config);
  CHECK(config->level == std::array<int, 6>{0, 1, 2, 0, 0, 1});
  CHECK(demo::format_config(*config) == "0,1,2,0,0,1");
  CHECK(demo::parse_config("2,2,2,2,2,2") == Config::cheapest());
}

TEST_CASE("malformed configurations are rejected", "[demo][config]") {
  for (const char* bad : {"", "0,1,2,0,0", "0,1,2,0,0,1,", "0,1,2,0,0,1,0", "0,1,3,0,0,1", "0,1,-1,0,0,1",
                          "0;1;2;0;0;1", "a,b,c,d,e,f", "0,1,2,0,0,", ",0,1,2,0,0", "00,1,2,0,0,1x"}) {
    INFO(bad);
    CHECK_FALSE(demo::parse_config(bad));
  }
}

TEST_CASE("the 729 configurations are distinct and span best to cheapest", "[demo][config]") {
  std::set<std::string> seen;
  for (int i = 0; i < 729; ++i) seen.insert(demo::format_config(Config::from_index(i)));
  CHECK(seen.size() == 729);
  CHECK(Config::from_index(0) == Config::best());
  CHECK(Config::from_index(728) == Config::cheapest());
  CHECK(Config::from_index(1)[Knob::Antialiasing] == 1);  // the last knob varies fastest
}

TEST_CASE("levels map to the paper's Table 2, best first", "[demo][config]") {
  const Config best = Config::best(), cheap = Config::cheapest();
  Config middle;
  middle.level.fill(1);
  CHECK(demo::render_scale(best) == 1.0f);
  CHECK(demo::render_scale(middle) == 0.8f);
  CHECK(demo::render_scale(cheap) == 0.6f);
  CHECK(demo::shading_model(best) > demo::shading_model(middle));
  CHECK(demo::shading_model(middle) > demo::shading_model(cheap));
  CHECK(demo::reflection_samples(best) == 64);
  CHECK(demo::reflection_kernel_taps(best) == 9);
  CHECK(demo::reflection_samples(middle) == 16);
  CHECK(demo::reflection_kernel_taps(middle) == 1);
  CHECK(demo::reflection_samples(cheap) == 0);
  CHECK(demo::shadow_map_size(best) == 2048);
  CHECK(demo::shadow_map_size(middle) == 1024);
  CHECK(demo::shadow_map_size(cheap) == 512);
  CHECK(demo::metal_samples(best) == 60);
  CHECK(demo::metal_samples(middle) == 6);
  CHECK(demo::metal_samples(cheap) == 2);
  CHECK(demo::fxaa_steps(best) == 32);
  CHECK(demo::fxaa_steps(middle) == 2);
  CHECK(demo::fxaa_steps(cheap) == 0);
}
