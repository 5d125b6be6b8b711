// Levels that change how many fragments are drawn (render scale, shadow-map size) or skip a
// pass, and the variant-table and log forms that carry them.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <sstream>

#include "glbudget/analysis/resolved_frame.hpp"
#include "glbudget/model/reuse.hpp"
#include "glbudget/model/variant_table.hpp"
#include "synthetic_scene.hpp"

using namespace glbudget::model;
using namespace glbudget::analysis;
using namespace glbudget::model::testing;

namespace {

// resolution (scales scene and glass), scene, shadows (scales itself), glass (off at level 1).
ConfigurationSpace scaled_levels_space() {
  PassVariants resolution{"resolution", {}, {"scene", "glass"}};
  for (double s : {1.0, 0.64, 0.36}) {
    VariantCost level;
    level.fragment_scale = s;
    resolution.levels.push_back(level);
  }
  PassVariants scene{"scene", {{10, 200, 4}, {10, 120, 2}}, {}};
  PassVariants shadows{"shadows", {}, {"shadows"}};
  for (double s : {1.0, 0.25, 0.0625}) {
    VariantCost level{10, 0, 0};
    level.fragment_scale = s;
    shadows.levels.push_back(level);
  }
  VariantCost off;
  off.draws = false;
  PassVariants glass{"glass", {{10, 300, 8}, off}, {}};
  return ConfigurationSpace({resolution, scene, shadows, glass});
}

// The passes the hidden model knows, at their indices in `space`; those it lacks ("ui", a
// program outside every space here) after its own.
PassNames hidden_names(const ConfigurationSpace& space) {
  PassNames names(space);
  for (const char* name : {"scene", "shadows", "glass", "ui"}) names.index_of(name);
  return names;
}

PowerModel scaled_model(const ConfigurationSpace& space) {
  PassNames names = hidden_names(space);
  PowerModel model(synthetic_profile());
  model.set(names.index_of("scene"), {0.2, 0.3, 2.0});
  model.set(names.index_of("shadows"), {0.4, 0.1, 0.5});
  model.set(names.index_of("glass"), {0.1, 0.2, 3.0});
  model.set(names.index_of("ui"), {0.05, 0.0, 0.4});
  return model;
}

// A frame's counts by pass name, as the model of `space` sees them.
std::vector<PassFrame> frame_of(const ConfigurationSpace& space,
                                const std::vector<std::pair<std::string, PassCounts>>& counts) {
  PassNames names = hidden_names(space);
  std::vector<PassFrame> frame;
  for (const auto& [name, c] : counts) frame.push_back({names.index_of(name), c});
  return frame;
}

// What the hidden model draws in configuration c for a view whose reference counts are these.
std::vector<PassFrame> drawn_in(const ConfigurationSpace& space, const Configuration& c) {
  const double res = space.passes()[0].levels[c[0]].fragment_scale;
  const double shadow = space.passes()[2].levels[c[2]].fragment_scale;
  std::vector<std::pair<std::string, PassCounts>> frame{
      {"scene", {120, 3e5, 2e7 * res}}, {"shadows", {60, 2e5, 4e7 * shadow}}, {"ui", {4, 600, 1e6}}};
  if (space.passes()[3].levels[c[3]].draws) frame.push_back({"glass", {8, 2e4, 5e6 * res}});
  return frame_of(space, frame);
}

}  // namespace

TEST_CASE("render scale and shadow-map size predict every configuration from any other", "[model][reuse][scale]") {
  const ConfigurationSpace space = scaled_levels_space();
  REQUIRE(space.size() == 36);
  const PowerModel model = scaled_model(space);
  // Costs per fragment do not depend on how many are drawn: coefficients fitted in one
  // configuration stand for all levels of the scaling passes (reuse is exact here, chi and
  // psi are not involved because the shader levels are held).
  for (const Configuration& drawn : {Configuration{0, 0, 0, 0}, Configuration{2, 0, 1, 0}, Configuration{1, 0, 2, 0}}) {
    ConfigurationPredictor predictor(space, model, drawn, {});
    predictor.set_frame(drawn_in(space, drawn), drawn);
    std::vector<double> all;
    predictor.predict_all(all);
    REQUIRE(all.size() == space.size());
    for (std::size_t i = 0; i < space.size(); ++i) {
      const Configuration c = space.decode(i);
      if (c[1] != drawn[1]) continue;  // shader levels: reuse, tested elsewhere
      CAPTURE(i);
      CHECK(all[i] == Approx(predictor.predict(c)).epsilon(1e-12));
      CHECK(predictor.predict(c) == Approx(model.predict_power(drawn_in(space, c))).epsilon(1e-12));
    }
    // The render scale moves power the right way: less at lower scale, everything else equal.
    CHECK(predictor.predict({0, 0, 0, 0}) > predictor.predict({1, 0, 0, 0}));
    CHECK(predictor.predict({1, 0, 0, 0}) > predictor.predict({2, 0, 0, 0}));
    CHECK(predictor.predict({0, 0, 0, 0}) > predictor.predict({0, 0, 2, 0}));
  }
}

TEST_CASE("predict-all agrees with predict for every configuration with shader levels, scales and skips",
          "[model][reuse][scale]") {
  const ConfigurationSpace space = scaled_levels_space();
  ConfigurationPredictor predictor(space, scaled_model(space), {0, 0, 0, 0}, {0.01, 0.2});
  predictor.set_frame(drawn_in(space, {1, 1, 1, 0}), {1, 1, 1, 0});
  std::vector<double> all;
  predictor.predict_all(all);
  for (std::size_t i = 0; i < space.size(); ++i) {
    CAPTURE(i);
    CHECK(all[i] == Approx(predictor.predict(space.decode(i))).epsilon(1e-12));
  }
}

TEST_CASE("a skipped pass is predicted from what it drew when it was last on", "[model][reuse][scale]") {
  const ConfigurationSpace space = scaled_levels_space();
  const PowerModel model = scaled_model(space);
  ConfigurationPredictor predictor(space, model, {0, 0, 0, 0}, {});
  // Never seen on: glass adds nothing, whatever its level.
  predictor.set_frame(drawn_in(space, {0, 0, 0, 1}), {0, 0, 0, 1});
  CHECK(predictor.predict({0, 0, 0, 0}) == Approx(predictor.predict({0, 0, 0, 1})));
  CHECK(predictor.predict({0, 0, 0, 1}) == Approx(model.predict_power(drawn_in(space, {0, 0, 0, 1}))));
  // Seen on at render scale 0.6; then off at full scale: on is predicted at full scale.
  predictor.set_frame(drawn_in(space, {2, 0, 0, 0}), {2, 0, 0, 0});
  predictor.set_frame(drawn_in(space, {0, 0, 0, 1}), {0, 0, 0, 1});
  CHECK(predictor.predict({0, 0, 0, 0}) == Approx(model.predict_power(drawn_in(space, {0, 0, 0, 0}))).epsilon(1e-12));
  CHECK(predictor.predict({0, 0, 0, 1}) == Approx(model.predict_power(drawn_in(space, {0, 0, 0, 1}))).epsilon(1e-12));
  // A refit keeps what was remembered.
  predictor.refit(model, {0, 0, 0, 1}, {});
  predictor.set_frame(drawn_in(space, {0, 0, 0, 1}), {0, 0, 0, 1});
  CHECK(predictor.predict({0, 0, 0, 0}) == Approx(model.predict_power(drawn_in(space, {0, 0, 0, 0}))).epsilon(1e-12));
}

TEST_CASE("a fragment scale of 0 and unknown frame configurations stay finite", "[model][reuse][scale][extremes]") {
  PassVariants scale{"scale", {}, {"scene"}};
  for (double s : {1.0, 0.0}) {
    VariantCost level;
    level.fragment_scale = s;
    scale.levels.push_back(level);
  }
  const ConfigurationSpace space({scale, PassVariants{"scene", {{1, 1, 0}}, {}}});
  ConfigurationPredictor predictor(space, scaled_model(space), {0, 0}, {});
  predictor.set_frame(frame_of(space, {{"scene", {10, 100, 0}}}), {1, 0});  // drew no fragments at scale 0
  CHECK(std::isfinite(predictor.predict({0, 0})));
  CHECK(predictor.predict({0, 0}) >= synthetic_profile().p_min_w);
  predictor.set_frame(frame_of(space, {{"scene", {10, 100, 1e6}}}), {7, 7});  // not a configuration: taken as fitted
  CHECK(predictor.predict({1, 0}) < predictor.predict({0, 0}));
  CHECK(std::isnan(predictor.predict({7, 7})));
  CHECK(std::isnan(predictor.predict({0})));
}

TEST_CASE("variant tables carry several programs per level, shared programs, scales and skipped levels",
          "[model][variants]") {
  const auto table = parse_variant_table(R"({"passes": [
        {"name": "resolution", "scales": ["base"], "levels": [{"fragment_scale": 1}, {"fragment_scale": 0.64}]},
        {"name": "base", "levels": [{"hashes": ["a", "a-skinned"], "ins_f": 100, "tex_f": 2},
                                   {"hash": "b", "ins_f": 60}]},
        {"name": "reflections", "levels": [{"hash": "r", "ins_f": 700}, {"hash": "r", "ins_f": 200}, {"draws": false}]}
    ]})",
                                         "inline");
  REQUIRE(table);
  REQUIRE(table->space.size() == 12);
  CHECK(table->space.passes()[0].scales == std::vector<std::string>{"base"});
  CHECK(table->space.passes()[0].levels[1].fragment_scale == 0.64);
  CHECK(table->by_hash.at("a-skinned").level == 0);
  CHECK(table->by_hash.at("b").level == 1);
  CHECK(table->by_hash.at("r").level == -1);  // the same program at two levels: ambiguous
  CHECK(!table->space.passes()[2].levels[2].draws);

  // Without a configuration column, programs set the levels they identify...
  LoggedFrame frame;
  frame.power_w = 30;
  frame.passes = {{"a", {1, 10, 100}, 4}, {"a-skinned", {1, 10, 50}, 4}, {"r", {1, 3, 80}, 1}};
  PassNames names(table->space);
  ResolvedFrame resolved = resolve_frame(frame, *table, {1, 1, 1}, names);
  CHECK(resolved.configuration == Configuration{1, 0, 1});
  REQUIRE(resolved.sample.passes.size() == 2);
  CHECK(resolved.sample.passes[0].counts.fragments == 150);  // two programs, one pass
  CHECK(resolved.primitives[0] == 8);
  // ... and the logged configuration wins where there is one.
  frame.configuration = "0:0:0";
  resolved = resolve_frame(frame, *table, {1, 1, 1}, names);
  CHECK(resolved.configuration == Configuration{0, 0, 0});
  CHECK(resolved.totals.texels == Approx(150 * 2));  // reflections level 0 lists no texels
  // The baseline's totals for another configuration follow scales and skipped passes.
  const FrameTotals at_scale = totals_in(resolved, *table, {1, 0, 2});
  CHECK(at_scale.texels == Approx(150 * 0.64 * 2));
  CHECK(at_scale.triangles == 8);  // reflections off
}

TEST_CASE("configurations read from the log's column are checked against the space", "[model][variants][extremes]") {
  const ConfigurationSpace space({{"a", {{}, {}, {}}, {}}, {"b", {{}, {}}, {}}});
  CHECK(parse_configuration("2:1", space) == Configuration{2, 1});
  CHECK(parse_configuration("0:0", space) == Configuration{0, 0});
  for (const char* bad : {"", "2", "2:1:0", "3:0", "-1:0", "a:b", "1:", ":1", "1;1", "1:1 "}) {
    CAPTURE(bad);
    CHECK(!parse_configuration(bad, space));
  }
  // A bad column value falls back to the programs' levels instead of failing the frame.
  VariantTable table{space, {}, std::nullopt, std::nullopt, {}, {}};
  LoggedFrame frame;
  frame.configuration = "9:9";
  PassNames names(space);
  CHECK(resolve_frame(frame, table, {1, 1}, names).configuration == Configuration{1, 1});
}

TEST_CASE("variant-table mistakes are reported and the rest is kept", "[model][variants][extremes]") {
  std::ostringstream captured;
  auto* old = std::cerr.rdbuf(captured.rdbuf());
  const auto table = parse_variant_table(R"({"passes": [
        {"name": "p", "scales": "q", "levels": [{"hashes": "x", "fragment_scale": -1, "draws": 3}, 5]}
    ]})",
                                         "inline");
  std::cerr.rdbuf(old);
  REQUIRE(table);
  REQUIRE(table->space.pass_count() == 1);
  CHECK(table->space.passes()[0].levels.size() == 1);
  CHECK(table->space.passes()[0].scales.empty());
  CHECK(table->space.passes()[0].levels[0].fragment_scale == 0.0);
  CHECK(table->space.passes()[0].levels[0].draws);
  const std::string messages = captured.str();
  CHECK(messages.find("glbudget: inline: pass p: \"scales\" must be an array") != std::string::npos);
  CHECK(messages.find("\"hashes\" must be an array") != std::string::npos);
  CHECK(messages.find("\"fragment_scale\" must be a number >= 0") != std::string::npos);
  CHECK(messages.find("\"draws\" must be true or false") != std::string::npos);
  CHECK(messages.find("a level must be an object") != std::string::npos);
}

TEST_CASE("coefficients fitted while a pass was skipped are those of its cheapest drawing level",
          "[model][reuse][scale]") {
  // Fitted with glass off: its k (say from a fit over several configurations) holds for its
  // cheapest level, and the better level adds chi and psi times its extra instructions and
  // texels, not its whole cost as if the skipped level cost nothing.
  VariantCost off;
  off.draws = false;
  const ConfigurationSpace space({PassVariants{"glass", {{10, 300, 8}, {10, 200, 5}, off}, {}}});
  PowerModel model(synthetic_profile());
  model.set(0, {0.1, 0.2, 3.0});
  const ReuseCoefficients reuse{0.01, 0.2};
  ConfigurationPredictor predictor(space, model, {2}, reuse);
  CHECK(predictor.coefficients(0, 1).k_f == Approx(3.0));
  CHECK(predictor.coefficients(0, 0).k_f == Approx(3.0 + 0.01 * 100 + 0.2 * 3));
}

TEST_CASE("predict-all is right whichever position the scaling pass has in the space", "[model][reuse][scale]") {
  // The render scale in the middle: its tables no longer fill contiguous blocks.
  PassVariants resolution{"resolution", {}, {"scene", "glass"}};
  for (double s : {1.0, 0.5}) {
    VariantCost level;
    level.fragment_scale = s;
    resolution.levels.push_back(level);
  }
  VariantCost off;
  off.draws = false;
  const ConfigurationSpace space({PassVariants{"scene", {{10, 200, 4}, {10, 120, 2}, {10, 60, 1}}, {}}, resolution,
                                  PassVariants{"glass", {{10, 300, 8}, off}, {}},
                                  PassVariants{"shadows", {{10, 0, 0}}, {}}});
  ConfigurationPredictor predictor(space, scaled_model(space), {0, 0, 0, 0}, {0.01, 0.2});
  predictor.set_frame(
      frame_of(space, {{"scene", {120, 3e5, 2e7}}, {"glass", {8, 2e4, 5e6}}, {"shadows", {60, 2e5, 4e7}}}),
      {1, 1, 0, 0});
  std::vector<double> all;
  predictor.predict_all(all);
  REQUIRE(all.size() == space.size());
  for (std::size_t i = 0; i < space.size(); ++i) {
    CAPTURE(i);
    CHECK(all[i] == Approx(predictor.predict(space.decode(i))).epsilon(1e-12));
  }
  CHECK(predictor.predict({0, 0, 0, 0}) > predictor.predict({0, 1, 0, 0}));
}

TEST_CASE("a variant table's platform costs: read whole or not at all", "[model][variants][extremes]") {
  const auto good = parse_variant_table(R"({"passes": [{"name": "p", "levels": [{"ins_f": 3}]}],
        "platform_costs": {"batch": 0, "vertex": 1e-300, "fragment": 3.5, "instruction": 0.02, "texel": 1e300}})",
                                        "inline");
  REQUIRE(good);
  REQUIRE(good->platform_costs);
  CHECK(good->platform_costs->batch == 0.0);
  CHECK(good->platform_costs->vertex == 1e-300);
  CHECK(good->platform_costs->fragment == 3.5);
  CHECK(good->platform_costs->instruction == 0.02);
  CHECK(good->platform_costs->texel == 1e300);
  const auto none = parse_variant_table(R"({"passes": [{"name": "p", "levels": [{}]}]})", "inline");
  REQUIRE(none);
  CHECK_FALSE(none->platform_costs);
  for (const char* bad :
       {R"("platform_costs": {"batch": 0, "vertex": 0, "fragment": 1, "instruction": 0.1})",
        R"("platform_costs": {"batch": 0, "vertex": 0, "fragment": -1, "instruction": 0.1, "texel": 0})",
        R"("platform_costs": {"batch": 0, "vertex": 0, "fragment": "1", "instruction": 0.1, "texel": 0})",
        R"("platform_costs": [0, 0, 1, 0.1, 0])"}) {
    std::ostringstream captured;
    auto* old = std::cerr.rdbuf(captured.rdbuf());
    const auto table =
        parse_variant_table(std::string(R"({"passes": [{"name": "p", "levels": [{}]}], )") + bad + "}", "inline");
    std::cerr.rdbuf(old);
    INFO(bad);
    REQUIRE(table);  // the levels are kept
    CHECK_FALSE(table->platform_costs);
    CHECK(captured.str().find("glbudget: inline: \"platform_costs\" needs batch, vertex, fragment, instruction and "
                              "texel") != std::string::npos);
  }
}

TEST_CASE("a variant table's measured range: the best and the cheapest configuration's power, both or none",
          "[model][variants][extremes]") {
  const std::string passes =
      R"("passes": [{"name": "a", "levels": [{"ins_f": 3}, {"ins_f": 1}]},
                    {"name": "b", "levels": [{"ins_f": 3}, {"ins_f": 2}, {"ins_f": 1}]}])";
  auto parse = [&](const std::string& power) {
    return parse_variant_table("{" + passes + (power.empty() ? "" : ", \"power\": " + power) + "}", "inline");
  };
  const auto both = parse(R"({"configurations": [{"configuration": "0:0", "power_w": 30.5},
      {"configuration": "1:0", "power_w": 25}, {"configuration": "1:2", "power_w": 12.25}]})");
  REQUIRE(both);
  REQUIRE(both->measured_range);
  CHECK(both->measured_range->best_w == 30.5);
  CHECK(both->measured_range->cheapest_w == 12.25);
  for (const std::string& power :
       {std::string(), std::string(R"({"configurations": [{"configuration": "0:0", "power_w": 30}]})"),
        std::string(R"({"configurations": [{"configuration": "1:2", "power_w": 12}]})"),
        std::string(R"({"configurations": [{"configuration": "0:0", "power_w": 30},
                                           {"configuration": "1:2", "power_w": 0}]})"),
        std::string(R"({"configurations": [{"configuration": "0:0", "power_w": "30"},
                                           {"configuration": "1:2", "power_w": 12}]})"),
        std::string(R"({"configurations": {"0:0": 30, "1:2": 12}})"), std::string("[]")}) {
    CAPTURE(power);
    const auto table = parse(power);
    REQUIRE(table);
    CHECK_FALSE(table->measured_range);
  }
}

TEST_CASE("a variant table's error ratios k: numbers in [0, 1] by pass and level, others said",
          "[model][variants][extremes]") {
  std::ostringstream captured;
  auto* old = std::cerr.rdbuf(captured.rdbuf());
  const auto table = parse_variant_table(R"({"passes": [
        {"name": "shading", "levels": [{"ins_f": 9}, {"ins_f": 5, "error_ratio": 0.25}, {"ins_f": 1, "error_ratio": 1}]},
        {"name": "shadows", "levels": [{}, {"error_ratio": 0}, {"error_ratio": 1.5}, {"error_ratio": "half"}, {}]}
    ]})",
                                         "inline");
  std::cerr.rdbuf(old);
  REQUIRE(table);
  const std::map<std::pair<std::string, int>, double> expected = {
      {{"shading", 1}, 0.25}, {{"shading", 2}, 1.0}, {{"shadows", 1}, 0.0}};
  CHECK(table->error_ratios == expected);
  CHECK(table->space.passes()[1].levels.size() == 5);  // a bad ratio drops the ratio, not the level
  const std::string messages = captured.str();
  CHECK(std::count(messages.begin(), messages.end(), '\n') == 2);
  CHECK(messages.find("glbudget: inline: pass shadows: \"error_ratio\" must be a number in [0, 1]; ignored") !=
        std::string::npos);
}
