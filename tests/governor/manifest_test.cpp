#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "glbudget/manifest/manifest.hpp"

using namespace glbudget::manifest;

namespace {

const std::string kData = std::string(GLBUDGET_SOURCE_DIR) + "/tests/data/manifests";
const std::string kDemo = std::string(GLBUDGET_SOURCE_DIR) + "/testapps/demo";

std::string read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  REQUIRE(in);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> texts(const LoadResult& result) {
  std::vector<std::string> out;
  for (const Problem& problem : result.problems) out.push_back(problem.text);
  return out;
}

// A manifest that must load; its problems (warnings) are returned through `problems`.
Manifest load_ok(const std::string& text, std::vector<std::string>* problems = nullptr,
                 const std::string& path = "m.toml") {
  const LoadResult result = parse_manifest(text, path);
  INFO(Catch::Detail::stringify(texts(result)));
  REQUIRE(result.manifest);
  for (const Problem& problem : result.problems) CHECK_FALSE(problem.fatal);
  if (problems)
    *problems = texts(result);
  else
    CHECK(result.problems.empty());
  return *result.manifest;
}

Target target(Target::Kind kind, std::string name = {}, uint32_t id = 0) {
  Target t;
  t.kind = kind;
  t.name = std::move(name);
  t.id = id;
  return t;
}

// A valid second pass, so that dropping the pass under test does not make the manifest fatal.
const std::string kOther = "\n[[pass]]\nname = \"other\"\n";

}  // namespace

TEST_CASE("stage names round-trip") {
  for (Stage stage :
       {Stage::vertex, Stage::tess_control, Stage::tess_evaluation, Stage::geometry, Stage::fragment, Stage::compute}) {
    CHECK(parse_stage(stage_name(stage)) == stage);
  }
  CHECK(std::string(stage_name(Stage::tess_evaluation)) == "tess_evaluation");
  CHECK_FALSE(parse_stage("pixel"));
  CHECK_FALSE(parse_stage("Fragment"));
}

TEST_CASE("every key of the schema is read") {
  const std::string text = R"toml([[pass]]
name = "base"
match = { hash = ["0123456789abcdef", "FEDCBA9876543210"], source = ["SHADING_MODEL", "u_albedo"] }
scales = ["base", "other", "base"]
[[pass.level]]
name = "best"
[[pass.level]]
name = "cheap"
defines = { Z_FIRST = 1, A_SECOND = -3, F = 1.0, G = 0.25, H = 1e-5, I = 2.5e10, B = true, C = false, S = "vec3(1.0, 2.0, 3.0)" }
replace = { fragment = "cheap.frag", vertex = "cheap.frag" }
uniforms = { u_z = 16, u_f = 0.5, u_on = true, u_off = false, u_v = [1, 2.5, 3], u_m = [[1, 0], [0, 1]] }
draws = false
scale = 0.5
targets = ["self", "pass:other", "default", "window-sized", "texture:12", "framebuffer:3", "self"]
fragment_scale = 0.3

[[pass]]
name = "other"
match.hash = "00000000000000ff"
match.source = "OTHER"
)toml";
  const Manifest m = load_ok(text, nullptr, kData + "/m.toml");
  CHECK(m.path == kData + "/m.toml");
  REQUIRE(m.passes.size() == 2);
  CHECK(m.find("base") == 0);
  CHECK(m.find("other") == 1);
  CHECK(m.find("nope") == -1);

  const Pass& base = m.passes[0];
  CHECK(base.match.hashes == std::vector<uint64_t>{0x0123456789abcdefULL, 0xfedcba9876543210ULL});
  CHECK(base.match.sources == std::vector<std::string>{"SHADING_MODEL", "u_albedo"});
  CHECK(base.scales == std::vector<std::string>{"base", "other"});
  REQUIRE(base.levels.size() == 2);

  const Level& best = base.levels[0];
  CHECK(best.name == "best");
  CHECK(best.identity());
  CHECK_FALSE(best.changes_program());

  const Level& cheap = base.levels[1];
  CHECK(cheap.name == "cheap");
  const std::vector<std::pair<std::string, std::string>> defines = {
      {"Z_FIRST", "1"}, {"A_SECOND", "-3"}, {"F", "1.0"},
      {"G", "0.25"},    {"H", "1.0e-05"},   {"I", "2.5e+10"},
      {"B", "true"},    {"C", "false"},     {"S", "vec3(1.0, 2.0, 3.0)"}};
  CHECK(cheap.defines == defines);
  const std::string frag = std::filesystem::path(kData + "/cheap.frag").lexically_normal().string();
  CHECK(cheap.replace == std::map<Stage, std::string>{{Stage::vertex, frag}, {Stage::fragment, frag}});
  CHECK(cheap.replace_source.at(Stage::fragment) == read(kData + "/cheap.frag"));
  CHECK(cheap.replace_source.at(Stage::vertex) == read(kData + "/cheap.frag"));
  const std::vector<std::pair<std::string, UniformValue>> uniforms = {{"u_z", {{16}}},        {"u_f", {{0.5}}},
                                                                      {"u_on", {{1}}},        {"u_off", {{0}}},
                                                                      {"u_v", {{1, 2.5, 3}}}, {"u_m", {{1, 0, 0, 1}}}};
  CHECK(cheap.uniforms == uniforms);
  CHECK_FALSE(cheap.draws);
  CHECK(cheap.scale == 0.5);
  CHECK(cheap.targets == std::vector<Target>{target(Target::Kind::self), target(Target::Kind::pass, "other"),
                                             target(Target::Kind::default_framebuffer),
                                             target(Target::Kind::window_sized), target(Target::Kind::texture, {}, 12),
                                             target(Target::Kind::framebuffer, {}, 3)});
  CHECK(cheap.fragment_scale == 0.3);
  CHECK(cheap.fragment_scale_or_default() == 0.3);
  CHECK(cheap.changes_program());
  CHECK_FALSE(cheap.identity());

  const Pass& other = m.passes[1];
  CHECK(other.match.hashes == std::vector<uint64_t>{0xff});
  CHECK(other.match.sources == std::vector<std::string>{"OTHER"});
  REQUIRE(other.levels.size() == 1);
  CHECK(other.levels[0].identity());
  CHECK(other.scales.empty());
}

TEST_CASE("levels: missing or empty gives one identity level") {
  const Manifest m = load_ok("[[pass]]\nname = \"a\"\n[[pass]]\nname = \"b\"\nlevel = []\n");
  REQUIRE(m.passes.size() == 2);
  for (const Pass& pass : m.passes) {
    REQUIRE(pass.levels.size() == 1);
    CHECK(pass.levels[0].identity());
    CHECK(pass.levels[0].name.empty());
    CHECK(pass.scales.empty());
    CHECK(pass.match.empty());
  }
}

TEST_CASE("level flags: identity and changes_program") {
  const Manifest m = load_ok(R"toml([[pass]]
name = "a"
match.source = "A"
[[pass.level]]
[[pass.level]]
draws = false
[[pass.level]]
uniforms = { u = 1 }
[[pass.level]]
scale = 0.5
)toml");
  const auto& levels = m.passes[0].levels;
  REQUIRE(levels.size() == 4);
  CHECK(levels[0].identity());
  CHECK_FALSE(levels[1].identity());
  CHECK_FALSE(levels[1].changes_program());
  CHECK(levels[2].changes_program());
  CHECK_FALSE(levels[3].identity());
  CHECK_FALSE(levels[3].changes_program());
  CHECK(levels[3].fragment_scale_or_default() == 0.25);
  CHECK(levels[0].fragment_scale_or_default() == 1.0);
}

TEST_CASE("derived defaults: targets of a scaling level and the scales of a pass") {
  const Manifest m = load_ok(R"toml([[pass]]
name = "window"
[[pass.level]]
[[pass.level]]
scale = 0.5

[[pass]]
name = "shadows"
match.source = "depth"
[[pass.level]]
[[pass.level]]
scale = 0.5

[[pass]]
name = "scene"
match.source = "scene"
[[pass.level]]
[[pass.level]]
scale = 0.8
targets = ["pass:shadows", "texture:4"]

[[pass]]
name = "textures"
[[pass.level]]
[[pass.level]]
scale = 0.8
targets = ["framebuffer:2"]

[[pass]]
name = "plain"
match.source = "plain"

[[pass]]
name = "offscreen"
[[pass.level]]
[[pass.level]]
scale = 0.5
targets = ["window-sized"]
)toml");
  REQUIRE(m.passes.size() == 6);
  // No match: the default framebuffer; it scales every pass that has a match.
  CHECK(m.passes[0].levels[1].targets == std::vector<Target>{target(Target::Kind::default_framebuffer)});
  CHECK(m.passes[0].scales == std::vector<std::string>{"shadows", "scene", "plain"});
  // A match: its own framebuffers.
  CHECK(m.passes[1].levels[1].targets == std::vector<Target>{target(Target::Kind::self)});
  CHECK(m.passes[1].scales == std::vector<std::string>{"shadows"});
  CHECK(m.passes[2].scales == std::vector<std::string>{"shadows"});
  // Texture and framebuffer names say nothing about passes.
  CHECK(m.passes[3].scales.empty());
  CHECK(m.passes[4].scales.empty());
  // The window-sized framebuffers may hold any pass's image: every pass that has a match.
  CHECK(m.passes[5].scales == std::vector<std::string>{"shadows", "scene", "plain"});
}

TEST_CASE("a TOML syntax error is fatal, with the parser's line and column") {
  const LoadResult result = parse_manifest("[[pass]]\nname = \"a\"\nscale = = 3\n", "dir/m.toml");
  CHECK_FALSE(result.manifest);
  REQUIRE(result.problems.size() == 1);
  CHECK(result.problems[0].fatal);
  CHECK_THAT(result.problems[0].text, Catch::StartsWith("dir/m.toml:3:9: "));
  CHECK(result.problems[0].text.size() > std::string("dir/m.toml:3:9: ").size());

  const LoadResult unterminated = parse_manifest("[[pass]]\nname = \"a\n", "m.toml");
  REQUIRE(unterminated.problems.size() == 1);
  CHECK(unterminated.problems[0].fatal);
  CHECK_THAT(unterminated.problems[0].text, Catch::StartsWith("m.toml:2:"));
}

TEST_CASE("unknown keys are warnings with their place, and are ignored") {
  std::vector<std::string> problems;
  const Manifest m = load_ok(R"toml(version = 2
[[pass]]
name = "a"
colour = "red"
match = { source = "A", regex = "A+" }
[[pass.level]]
nmae = "typo"
[[pass.level]]
scale = 0.5
target = ["self"]
)toml",
                             &problems);
  CHECK(problems == std::vector<std::string>{
                        "m.toml:1:1: unknown key 'version' in the manifest (ignored)",
                        "m.toml:4:1: unknown key 'colour' in pass 'a' (ignored)",
                        "m.toml:5:25: unknown key 'regex' in the match of pass 'a' (ignored)",
                        "m.toml:7:1: unknown key 'nmae' in level 0 of pass 'a' (ignored)",
                        "m.toml:10:1: unknown key 'target' in level 1 of pass 'a' (ignored)",
                    });
  REQUIRE(m.passes.size() == 1);
  CHECK(m.passes[0].levels.size() == 2);
  CHECK(m.passes[0].levels[0].identity());
  CHECK(m.passes[0].levels[1].targets == std::vector<Target>{target(Target::Kind::self)});
}

// One invalid level 1 of pass 'a' (lines 1-5 fixed, the level's keys from line 6): the message,
// and the pass keeps its other two levels.
void check_bad_level(const std::string& level_keys, const std::string& message, const std::string& path = "m.toml") {
  const std::string text = "[[pass]]\nname = \"a\"\nmatch.source = \"A\"\n[[pass.level]]\n[[pass.level]]\n" +
                           level_keys + "\n[[pass.level]]\nname = \"last\"\n";
  const LoadResult result = parse_manifest(text, path);
  INFO(level_keys);
  CHECK(texts(result) == std::vector<std::string>{message});
  REQUIRE(result.manifest);
  REQUIRE(result.manifest->passes.size() == 1);
  const Pass& pass = result.manifest->passes[0];
  REQUIRE(pass.levels.size() == 2);
  CHECK(pass.levels[1].name == "last");
}

TEST_CASE("an invalid level is reported where it is wrong and dropped") {
  check_bad_level("scale = 1.5",
                  "m.toml:6:9: level 1 of pass 'a': scale must be a number in (0, 1], not 1.5; level dropped");
  check_bad_level("scale = 0",
                  "m.toml:6:9: level 1 of pass 'a': scale must be a number in (0, 1], not 0; level dropped");
  check_bad_level("scale = -0.5",
                  "m.toml:6:9: level 1 of pass 'a': scale must be a number in (0, 1], not -0.5; level dropped");
  check_bad_level("scale = nan",
                  "m.toml:6:9: level 1 of pass 'a': scale must be a number in (0, 1], not nan; level dropped");
  check_bad_level("scale = \"half\"",
                  "m.toml:6:9: level 1 of pass 'a': scale must be a number in (0, 1]; level dropped");
  check_bad_level("name = \"x\"\nscale = 0.5\ntargets = [\"self\", \"screen\"]",
                  "m.toml:8:20: level 1 ('x') of pass 'a': unknown target 'screen' (expected self, default, pass:NAME, "
                  "texture:N or framebuffer:N); level dropped");
  check_bad_level("scale = 0.5\ntargets = [\"texture:0\"]",
                  "m.toml:7:12: level 1 of pass 'a': unknown target 'texture:0' (expected self, default, pass:NAME, "
                  "texture:N or framebuffer:N); level dropped");
  check_bad_level("scale = 0.5\ntargets = [\"framebuffer:x\"]",
                  "m.toml:7:12: level 1 of pass 'a': unknown target 'framebuffer:x' (expected self, default, "
                  "pass:NAME, texture:N or framebuffer:N); level dropped");
  check_bad_level("scale = 0.5\ntargets = [\"pass:\"]",
                  "m.toml:7:12: level 1 of pass 'a': unknown target 'pass:' (expected self, default, pass:NAME, "
                  "texture:N or framebuffer:N); level dropped");
  check_bad_level("scale = 0.5\ntargets = [3]",
                  "m.toml:7:12: level 1 of pass 'a': unknown target (not a string) (expected self, default, "
                  "pass:NAME, texture:N or framebuffer:N); level dropped");
  check_bad_level("scale = 0.5\ntargets = \"self\"",
                  "m.toml:7:11: level 1 of pass 'a': targets must be an array of strings; level dropped");
  check_bad_level("scale = 0.5\ntargets = []",
                  "m.toml:7:11: level 1 of pass 'a': targets is empty but scale is 0.5; level dropped");
  check_bad_level("replace = { pixel = \"cheap.frag\" }",
                  "m.toml:6:21: level 1 of pass 'a': unknown stage 'pixel' in replace (expected vertex, "
                  "tess_control, tess_evaluation, geometry, fragment or compute); level dropped");
  check_bad_level("replace = { fragment = 1 }",
                  "m.toml:6:24: level 1 of pass 'a': replace fragment must be a file name; level dropped");
  check_bad_level("replace = \"cheap.frag\"",
                  "m.toml:6:11: level 1 of pass 'a': replace must be a table of stage = \"file\"; level dropped");
  check_bad_level("replace = { fragment = \"missing.frag\" }",
                  kData + "/m.toml:6:24: level 1 of pass 'a': cannot read replace file '" + kData +
                      "/missing.frag': No such file or directory; level dropped",
                  kData + "/m.toml");
  check_bad_level("replace = { fragment = \"../manifests\" }",
                  kData + "/m.toml:6:24: level 1 of pass 'a': cannot read replace file '" + kData +
                      "': not a regular file; level dropped",
                  kData + "/m.toml");
  check_bad_level("uniforms = { u_ok = 1, u_name = \"x\" }",
                  "m.toml:6:33: level 1 of pass 'a': uniform 'u_name' must be a number, a bool or an array of "
                  "numbers; level dropped");
  check_bad_level("uniforms = { u = [1, \"x\"] }",
                  "m.toml:6:18: level 1 of pass 'a': uniform 'u' must be a number, a bool or an array of numbers; "
                  "level dropped");
  check_bad_level("uniforms = { u = [] }",
                  "m.toml:6:18: level 1 of pass 'a': uniform 'u' must be a number, a bool or an array of numbers; "
                  "level dropped");
  check_bad_level("uniforms = { u = { x = 1 } }",
                  "m.toml:6:18: level 1 of pass 'a': uniform 'u' must be a number, a bool or an array of numbers; "
                  "level dropped");
  check_bad_level("uniforms = [1]",
                  "m.toml:6:12: level 1 of pass 'a': uniforms must be a table of name = value; level dropped");
  check_bad_level("defines = { N = [1] }",
                  "m.toml:6:17: level 1 of pass 'a': define 'N' must be a one-line string, an integer, a finite "
                  "float or a bool; level dropped");
  check_bad_level("defines = { N = inf }",
                  "m.toml:6:17: level 1 of pass 'a': define 'N' must be a one-line string, an integer, a finite "
                  "float or a bool; level dropped");
  check_bad_level("defines = { N = \"a\\nb\" }",
                  "m.toml:6:17: level 1 of pass 'a': define 'N' must be a one-line string, an integer, a finite "
                  "float or a bool; level dropped");
  check_bad_level("defines = { N = 1979-05-27 }",
                  "m.toml:6:17: level 1 of pass 'a': define 'N' must be a one-line string, an integer, a finite "
                  "float or a bool; level dropped");
  check_bad_level("defines = { \"NOT A NAME\" = 1 }",
                  "m.toml:6:28: level 1 of pass 'a': define name 'NOT A NAME' is not a GLSL identifier; level dropped");
  check_bad_level("defines = 3",
                  "m.toml:6:11: level 1 of pass 'a': defines must be a table of NAME = value; level dropped");
  check_bad_level("draws = 0", "m.toml:6:9: level 1 of pass 'a': draws must be a bool; level dropped");
  check_bad_level("name = 2", "m.toml:6:8: level 1 of pass 'a': name must be a string; level dropped");
  check_bad_level("fragment_scale = 0",
                  "m.toml:6:18: level 1 of pass 'a': fragment_scale must be a finite number > 0; level dropped");
  check_bad_level("fragment_scale = inf",
                  "m.toml:6:18: level 1 of pass 'a': fragment_scale must be a finite number > 0; level dropped");
}

TEST_CASE("a level's error (1 - SSIM) for the governor's estimates") {
  std::vector<std::string> problems;
  const Manifest m = load_ok(R"toml([[pass]]
name = "a"
match.source = "A"
[[pass.level]]
error = 0
[[pass.level]]
error = 0.02
[[pass.level]]
error = 1
[[pass.level]]
[[pass]]
name = "b"
[[pass.level]]
error = 0.1
)toml",
                             &problems);
  const auto& levels = m.passes[0].levels;
  REQUIRE(levels.size() == 4);
  CHECK(levels[0].error == 0.0);
  CHECK(levels[1].error == 0.02);
  CHECK(levels[2].error == 1.0);
  CHECK_FALSE(levels[3].error);
  // Level 0 is the reference: another value is ignored with a warning, the pass kept.
  REQUIRE(m.passes[1].levels.size() == 1);
  CHECK_FALSE(m.passes[1].levels[0].error);
  CHECK(problems == std::vector<std::string>{
                        "m.toml:14:9: level 0 of pass 'b': error ignored: level 0 is the reference, its error is 0"});

  check_bad_level(
      "error = 1.5",
      "m.toml:6:9: level 1 of pass 'a': error must be a number in [0, 1] (1 - SSIM), not 1.5; level dropped");
  check_bad_level("error = -0.01",
                  "m.toml:6:9: level 1 of pass 'a': error must be a number in [0, 1] (1 - SSIM), not -0.01; level "
                  "dropped");
  check_bad_level(
      "error = nan",
      "m.toml:6:9: level 1 of pass 'a': error must be a number in [0, 1] (1 - SSIM), not nan; level dropped");
  check_bad_level("error = \"low\"",
                  "m.toml:6:9: level 1 of pass 'a': error must be a number in [0, 1] (1 - SSIM); level dropped");
}

TEST_CASE("a level may have several problems, each reported") {
  const LoadResult result =
      parse_manifest("[[pass]]\nname = \"a\"\n[[pass.level]]\n[[pass.level]]\nscale = 2\ndraws = 1\n", "m.toml");
  CHECK(texts(result) == std::vector<std::string>{
                             "m.toml:5:9: level 1 of pass 'a': scale must be a number in (0, 1], not 2; level dropped",
                             "m.toml:6:9: level 1 of pass 'a': draws must be a bool; level dropped"});
  // In the order they are written.
  const LoadResult reversed =
      parse_manifest("[[pass]]\nname = \"a\"\n[[pass.level]]\n[[pass.level]]\ndraws = 1\nscale = 2\n", "m.toml");
  CHECK(texts(reversed) ==
        std::vector<std::string>{
            "m.toml:5:9: level 1 of pass 'a': draws must be a bool; level dropped",
            "m.toml:6:9: level 1 of pass 'a': scale must be a number in (0, 1], not 2; level dropped"});
  REQUIRE(result.manifest);
  CHECK(result.manifest->passes[0].levels.size() == 1);
}

TEST_CASE("'self' needs a pass with a match") {
  const LoadResult result = parse_manifest(
      "[[pass]]\nname = \"a\"\n[[pass.level]]\n[[pass.level]]\nscale = 0.5\ntargets = [\"self\"]\n", "m.toml");
  CHECK(texts(result) ==
        std::vector<std::string>{"m.toml:6:12: level 1 of pass 'a': target 'self' needs a pass with a match (this pass "
                                 "owns no programs); level dropped"});
  REQUIRE(result.manifest);
  CHECK(result.manifest->passes[0].levels.size() == 1);
}

TEST_CASE("targets with scale 1 are ignored with a warning") {
  std::vector<std::string> problems;
  const Manifest m = load_ok("[[pass]]\nname = \"a\"\n[[pass.level]]\ntargets = [\"default\"]\n", &problems);
  CHECK(problems ==
        std::vector<std::string>{"m.toml:4:11: level 0 of pass 'a': targets ignored: the level's scale is 1"});
  CHECK(m.passes[0].levels[0].targets.empty());
  CHECK(m.passes[0].levels[0].identity());
}

TEST_CASE("an invalid level 0 drops its pass") {
  const LoadResult result =
      parse_manifest("[[pass]]\nname = \"a\"\n[[pass.level]]\nscale = 3\n[[pass.level]]\n" + kOther, "m.toml");
  CHECK(texts(result) == std::vector<std::string>{
                             "m.toml:4:9: level 0 of pass 'a': scale must be a number in (0, 1], not 3; pass dropped"});
  REQUIRE(result.manifest);
  REQUIRE(result.manifest->passes.size() == 1);
  CHECK(result.manifest->passes[0].name == "other");

  const LoadResult not_a_table = parse_manifest("[[pass]]\nname = \"a\"\nlevel = [1, {}]\n" + kOther, "m.toml");
  CHECK(texts(not_a_table) == std::vector<std::string>{"m.toml:3:10: level 0 of pass 'a': not a table; pass dropped"});
  REQUIRE(not_a_table.manifest);
  CHECK(not_a_table.manifest->passes.size() == 1);
}

TEST_CASE("invalid passes are dropped") {
  const auto problems_of = [](const std::string& text) {
    const LoadResult result = parse_manifest(text + kOther, "m.toml");
    REQUIRE(result.manifest);
    CHECK(result.manifest->passes.back().name == "other");
    return texts(result);
  };
  CHECK(problems_of("[[pass]]\nmatch.source = \"A\"\n") ==
        std::vector<std::string>{"m.toml:1:1: pass without a name; pass dropped"});
  CHECK(problems_of("[[pass]]\nname = 3\n") ==
        std::vector<std::string>{"m.toml:2:8: pass name must be a non-empty string; pass dropped"});
  CHECK(problems_of("[[pass]]\nname = \"\"\n") ==
        std::vector<std::string>{"m.toml:2:8: pass name must be a non-empty string; pass dropped"});
  CHECK(problems_of("[[pass]]\nname = \"other\"\nmatch.source = \"A\"\n") ==
        std::vector<std::string>{"m.toml:6:8: duplicate pass name 'other' (first at m.toml:2:8); pass dropped"});
  CHECK(
      problems_of("[[pass]]\nname = \"a\"\nmatch.hash = [\"0123\"]\n") ==
      std::vector<std::string>{"m.toml:3:15: pass 'a': match hash '0123' is not 16 hexadecimal digits; pass dropped"});
  CHECK(problems_of("[[pass]]\nname = \"a\"\nmatch.hash = \"0123456789abcdeg\"\n") ==
        std::vector<std::string>{
            "m.toml:3:14: pass 'a': match hash '0123456789abcdeg' is not 16 hexadecimal digits; pass dropped"});
  CHECK(problems_of("[[pass]]\nname = \"a\"\nmatch.hash = 5\n") ==
        std::vector<std::string>{
            "m.toml:3:14: pass 'a': match hash must be a string or an array of strings; pass dropped"});
  CHECK(problems_of("[[pass]]\nname = \"a\"\nmatch.source = [\"A\", \"\"]\n") ==
        std::vector<std::string>{
            "m.toml:3:22: pass 'a': match source must not be empty (it would match every program); pass dropped"});
  CHECK(problems_of("[[pass]]\nname = \"a\"\nmatch = {}\n") ==
        std::vector<std::string>{"m.toml:3:9: pass 'a': match has neither hash nor source; pass dropped"});
  CHECK(problems_of("[[pass]]\nname = \"a\"\nmatch = \"A\"\n") ==
        std::vector<std::string>{"m.toml:3:9: pass 'a': match must be a table with hash and/or source; pass dropped"});
  CHECK(problems_of("[[pass]]\nname = \"a\"\nlevel = { scale = 0.5 }\n") ==
        std::vector<std::string>{
            "m.toml:3:9: pass 'a': level must be an array of tables ([[pass.level]]); pass dropped"});
  CHECK(problems_of("[[pass]]\nname = \"a\"\nscales = \"b\"\n") ==
        std::vector<std::string>{"m.toml:3:10: pass 'a': scales must be an array of pass names; pass dropped"});
  CHECK(texts(parse_manifest("pass = [3, { name = \"other\" }]\n", "m.toml")) ==
        std::vector<std::string>{"m.toml:1:9: pass 0 is not a table; pass dropped"});
}

TEST_CASE("a manifest without a usable pass is fatal") {
  for (const std::string text : {"", "# nothing\n", "[[pass]]\nname = 1\n", "pass = 3\n"}) {
    const LoadResult result = parse_manifest(text, "m.toml");
    INFO(text);
    CHECK_FALSE(result.manifest);
    REQUIRE_FALSE(result.problems.empty());
    CHECK(result.problems.back().fatal);
    CHECK_THAT(result.problems.back().text,
               Catch::EndsWith(": no passes: the manifest needs at least one usable [[pass]]"));
  }
  CHECK(texts(parse_manifest("", "m.toml")) ==
        std::vector<std::string>{"m.toml:1:1: no passes: the manifest needs at least one usable [[pass]]"});
  CHECK(texts(parse_manifest("pass = 3\n", "m.toml")) ==
        std::vector<std::string>{"m.toml:1:8: pass must be an array of tables ([[pass]])",
                                 "m.toml:1:8: no passes: the manifest needs at least one usable [[pass]]"});
}

TEST_CASE("a pass:NAME target naming no pass is dropped, then a level left with nothing to scale") {
  const LoadResult result = parse_manifest(R"toml([[pass]]
name = "res"
[[pass.level]]
[[pass.level]]
scale = 0.8
targets = ["pass:scene", "pass:gone"]
[[pass.level]]
scale = 0.6
targets = ["pass:gone"]

[[pass]]
name = "scene"
match.source = "S"

[[pass]]
name = "gone"
match.source = ""
)toml",
                                           "m.toml");
  CHECK(texts(result) ==
        std::vector<std::string>{"m.toml:17:16: pass 'gone': match source must not be empty (it would match every "
                                 "program); pass dropped",
                                 "m.toml:6:26: level 1 of pass 'res': target 'pass:gone' names no pass of the manifest "
                                 "(ignored)",
                                 "m.toml:9:12: level 2 of pass 'res': target 'pass:gone' names no pass of the manifest "
                                 "(ignored)",
                                 "m.toml:7:1: level 2 of pass 'res': no target left to scale; level dropped"});
  REQUIRE(result.manifest);
  const Pass& res = result.manifest->passes[0];
  REQUIRE(res.levels.size() == 2);
  CHECK(res.levels[1].targets == std::vector<Target>{target(Target::Kind::pass, "scene")});
  CHECK(res.scales == std::vector<std::string>{"scene"});
}

TEST_CASE("dropping a pass can drop the passes that scale only it") {
  const LoadResult result = parse_manifest(R"toml([[pass]]
name = "a"
[[pass.level]]
scale = 0.5
targets = ["pass:b"]

[[pass]]
name = "b"
match.source = "B"
[[pass.level]]
scale = 0.5
targets = ["pass:c"]

[[pass]]
name = "c"
match.hash = "x"

[[pass]]
name = "d"
match.source = "D"
)toml",
                                           "m.toml");
  CHECK(texts(result) ==
        std::vector<std::string>{
            "m.toml:16:14: pass 'c': match hash 'x' is not 16 hexadecimal digits; pass dropped",
            "m.toml:12:12: level 0 of pass 'b': target 'pass:c' names no pass of the manifest (ignored)",
            "m.toml:10:1: level 0 of pass 'b': no target left to scale; pass dropped",
            "m.toml:5:12: level 0 of pass 'a': target 'pass:b' names no pass of the manifest (ignored)",
            "m.toml:3:1: level 0 of pass 'a': no target left to scale; pass dropped"});
  REQUIRE(result.manifest);
  REQUIRE(result.manifest->passes.size() == 1);
  CHECK(result.manifest->passes[0].name == "d");
}

TEST_CASE("scales: entries naming no pass, and entries that are not names") {
  const LoadResult unknown = parse_manifest("[[pass]]\nname = \"a\"\nscales = [\"a\", \"zz\"]\n", "m.toml");
  CHECK(texts(unknown) ==
        std::vector<std::string>{"m.toml:3:16: pass 'a': 'zz' in scales names no pass of the manifest (ignored)"});
  REQUIRE(unknown.manifest);
  CHECK(unknown.manifest->passes[0].scales == std::vector<std::string>{"a"});

  const LoadResult not_names = parse_manifest("[[pass]]\nname = \"a\"\nscales = [3]\n" + kOther, "m.toml");
  CHECK(texts(not_names) ==
        std::vector<std::string>{"m.toml:3:11: pass 'a': scales must be an array of pass names; pass dropped"});
}

TEST_CASE("load_manifest reads a file, and names one it cannot read") {
  const LoadResult demo = load_manifest(kDemo + "/glbudget.toml");
  CHECK(demo.manifest);
  CHECK(demo.manifest->path == kDemo + "/glbudget.toml");

  const LoadResult missing = load_manifest(kData + "/no-such.toml");
  CHECK_FALSE(missing.manifest);
  CHECK(texts(missing) ==
        std::vector<std::string>{kData + "/no-such.toml: cannot read the manifest: No such file or directory"});
  CHECK(missing.problems[0].fatal);
}

TEST_CASE("the built-in resolution pass") {
  const Pass pass = builtin_resolution_pass();
  CHECK(pass.name == "resolution");
  CHECK(pass.match.empty());
  CHECK(pass.scales.empty());
  REQUIRE(pass.levels.size() == 4);
  const std::vector<std::string> names = {"100%", "80%", "60%", "50%"};
  const std::vector<double> scales = {1.0, 0.8, 0.6, 0.5};
  for (std::size_t i = 0; i < 4; ++i) {
    CHECK(pass.levels[i].name == names[i]);
    CHECK(pass.levels[i].scale == scales[i]);
    CHECK_FALSE(pass.levels[i].changes_program());
    CHECK(pass.levels[i].draws);
    if (i == 0)
      CHECK(pass.levels[i].targets.empty());
    else
      CHECK(pass.levels[i].targets ==
            std::vector<Target>{target(Target::Kind::default_framebuffer), target(Target::Kind::window_sized)});
  }
  CHECK(pass.levels[0].identity());
}

TEST_CASE("with_resolution_pass puts the built-in pass first unless the manifest has one") {
  const Manifest alone = with_resolution_pass(std::nullopt);
  REQUIRE(alone.passes.size() == 1);
  CHECK(alone.passes[0].name == "resolution");
  CHECK(alone.path.empty());

  const Manifest m =
      with_resolution_pass(load_ok("[[pass]]\nname = \"a\"\nmatch.source = \"A\"\n[[pass]]\nname = "
                                   "\"b\"\n[[pass]]\nname = \"c\"\nmatch.source = \"C\"\n"));
  REQUIRE(m.passes.size() == 4);
  CHECK(m.path == "m.toml");
  CHECK(m.passes[0].name == "resolution");
  CHECK(m.passes[0].levels.size() == 4);
  CHECK(m.passes[0].scales == std::vector<std::string>{"a", "c"});
  CHECK(m.passes[1].name == "a");

  const Manifest own = with_resolution_pass(load_ok(
      "[[pass]]\nname = \"a\"\nmatch.source = \"A\"\n[[pass]]\nname = \"resolution\"\n[[pass.level]]\n[[pass.level]]\n"
      "scale = 0.7\n"));
  REQUIRE(own.passes.size() == 2);
  CHECK(own.passes[1].name == "resolution");
  CHECK(own.passes[1].levels.size() == 2);
}

TEST_CASE("parse_force") {
  const Manifest m = load_ok(R"toml([[pass]]
name = "resolution"
[[pass.level]]
[[pass.level]]
scale = 0.5
[[pass]]
name = "base"
[[pass]]
name = "shadows"
match.source = "S"
[[pass.level]]
[[pass.level]]
draws = false
[[pass.level]]
draws = false
)toml");
  std::string error;
  CHECK(parse_force("1,0,2", m, &error) == std::vector<int>{1, 0, 2});
  CHECK(parse_force(" 0 , 0 ,\t0 ", m, &error) == std::vector<int>{0, 0, 0});
  CHECK(parse_force("1,0,2", m, nullptr) == std::vector<int>{1, 0, 2});
  // As the log and the report write a configuration.
  CHECK(parse_force("1:0:2", m, &error) == std::vector<int>{1, 0, 2});
  CHECK(parse_force("1:0,2", m, &error) == std::vector<int>{1, 0, 2});
  CHECK_FALSE(parse_force("1::2", m, &error));
  CHECK(error == "GLBUDGET_FORCE='1::2': '' is not a level of pass 'base' (expected an integer)");

  CHECK_FALSE(parse_force("1,0", m, &error));
  CHECK(error == "GLBUDGET_FORCE='1,0' has 2 levels; the manifest has 3 passes (resolution, base, shadows)");
  CHECK_FALSE(parse_force("1,0,2,0", m, &error));
  CHECK(error == "GLBUDGET_FORCE='1,0,2,0' has 4 levels; the manifest has 3 passes (resolution, base, shadows)");
  CHECK_FALSE(parse_force("", m, &error));
  CHECK(error == "GLBUDGET_FORCE='' has 0 levels; the manifest has 3 passes (resolution, base, shadows)");
  CHECK_FALSE(parse_force("2", m, &error));
  CHECK(error == "GLBUDGET_FORCE='2' has 1 level; the manifest has 3 passes (resolution, base, shadows)");

  CHECK_FALSE(parse_force("1,0,3", m, &error));
  CHECK(error == "level 3 of pass 'shadows' is out of range 0..2");
  CHECK_FALSE(parse_force("2,0,0", m, &error));
  CHECK(error == "level 2 of pass 'resolution' is out of range 0..1");
  CHECK_FALSE(parse_force("0,1,0", m, &error));
  CHECK(error == "level 1 of pass 'base' is out of range 0..0");
  CHECK_FALSE(parse_force("0,-1,0", m, &error));
  CHECK(error == "level -1 of pass 'base' is out of range 0..0");
  CHECK_FALSE(parse_force("0,0,99999999999999999999999", m, &error));
  CHECK(error == "level 99999999999999999999999 of pass 'shadows' is out of range 0..2");

  CHECK_FALSE(parse_force("0,x,0", m, &error));
  CHECK(error == "GLBUDGET_FORCE='0,x,0': 'x' is not a level of pass 'base' (expected an integer)");
  CHECK_FALSE(parse_force("0,,0", m, &error));
  CHECK(error == "GLBUDGET_FORCE='0,,0': '' is not a level of pass 'base' (expected an integer)");
  CHECK_FALSE(parse_force("0,0,1.5", m, &error));
  CHECK(error == "GLBUDGET_FORCE='0,0,1.5': '1.5' is not a level of pass 'shadows' (expected an integer)");
  CHECK_FALSE(parse_force("0,0 1,0", m, &error));

  const Manifest one = load_ok("[[pass]]\nname = \"only\"\n");
  CHECK(parse_force("0", one, &error) == std::vector<int>{0});
  CHECK_FALSE(parse_force("0,0", one, &error));
  CHECK(error == "GLBUDGET_FORCE='0,0' has 2 levels; the manifest has 1 pass (only)");

  CHECK(parse_force("", Manifest{}, &error) == std::vector<int>{});
  CHECK_FALSE(parse_force("0", Manifest{}, &error));
  CHECK(error == "GLBUDGET_FORCE='0' has 1 level; the manifest has 0 passes ()");
}

TEST_CASE("matches: a listed hash, or a substring of any source") {
  Match match;
  CHECK_FALSE(matches(match, 0, {"anything"}));
  match.hashes = {0x10, 0x20};
  match.sources = {"FXAA_STEPS", "u_kernel"};
  CHECK(matches(match, 0x20, {}));
  CHECK_FALSE(matches(match, 0x30, {}));
  CHECK(matches(match, 0x30, {"void main() {}", "#define FXAA_STEPS 32\n"}));
  CHECK(matches(match, 0x30, {"uniform int u_kernel_taps;"}));
  CHECK_FALSE(matches(match, 0x30, {"fxaa_steps", "FXAA_STEP"}));
}

namespace {

// The demo's programs as its gl_program.cpp builds them: "#version 330 core\n", one
// "#define NAME VALUE\n" per define, then the files; both stages get the defines.
struct DemoProgram {
  std::string pass;  // the manifest pass it must belong to ("" for none)
  std::vector<std::string> sources;
};

std::string stage(const std::vector<std::pair<std::string, std::string>>& defines,
                  const std::vector<std::string>& files) {
  std::string source = "#version 330 core\n";
  for (const auto& [name, value] : defines) source += "#define " + name + " " + value + "\n";
  for (const std::string& file : files) source += read(kDemo + "/shaders/" + file);
  return source;
}

std::vector<DemoProgram> demo_programs() {
  std::vector<DemoProgram> programs;
  const auto scene = [&](const std::string& pass, const std::string& frag,
                         std::vector<std::pair<std::string, std::string>> defines) {
    for (bool skinned : {false, true}) {
      auto d = defines;
      if (skinned) d.emplace_back("SKINNED", "1");
      std::vector<std::string> fragment_files = {frag};
      if (frag != "depth.frag") fragment_files.insert(fragment_files.begin(), "lighting.glsl");
      programs.push_back({pass, {stage(d, {"scene.vert"}), stage(d, fragment_files)}});
    }
  };
  scene("shadows", "depth.frag", {});
  for (const char* model : {"0", "1", "2"}) scene("base", "base.frag", {{"SHADING_MODEL", model}});
  for (const char* samples : {"60", "6", "2"}) scene("metals", "metal.frag", {{"METAL_SAMPLES", samples}});
  const auto fullscreen = [&](const std::string& pass, const std::string& frag,
                              std::vector<std::pair<std::string, std::string>> defines) {
    programs.push_back({pass, {stage(defines, {"fullscreen.vert"}), stage(defines, {frag})}});
  };
  fullscreen("reflections", "ssr.frag", {});
  fullscreen("", "upscale.frag", {});
  for (const char* steps : {"32", "2"}) fullscreen("antialiasing", "fxaa.frag", {{"FXAA_STEPS", steps}});
  return programs;
}

}  // namespace

TEST_CASE("the demo's manifest loads cleanly and describes its six knobs") {
  const LoadResult result = load_manifest(kDemo + "/glbudget.toml");
  INFO(Catch::Detail::stringify(texts(result)));
  CHECK(result.problems.empty());
  REQUIRE(result.manifest);
  const Manifest& m = *result.manifest;
  REQUIRE(m.passes.size() == 6);
  const std::vector<std::string> names = {"resolution", "base", "reflections", "shadows", "metals", "antialiasing"};
  for (std::size_t i = 0; i < names.size(); ++i) {
    CHECK(m.passes[i].name == names[i]);
    CHECK(m.passes[i].levels.size() == 3);
    CHECK(m.passes[i].levels[0].identity());
  }
  CHECK(with_resolution_pass(m).passes.size() == 6);
  CHECK(parse_force("2,2,2,2,2,2", m, nullptr));

  const Pass& resolution = m.passes[0];
  CHECK(resolution.match.empty());
  CHECK(resolution.scales == std::vector<std::string>{"base", "metals", "reflections"});
  const std::vector<Target> scene = {target(Target::Kind::pass, "base"), target(Target::Kind::pass, "metals"),
                                     target(Target::Kind::pass, "reflections")};
  CHECK(resolution.levels[1].scale == 0.8);
  CHECK(resolution.levels[1].targets == scene);
  CHECK(resolution.levels[2].scale == 0.6);
  CHECK(resolution.levels[2].targets == scene);

  using Defines = std::vector<std::pair<std::string, std::string>>;
  CHECK(m.passes[1].levels[1].defines == Defines{{"SHADING_MODEL", "1"}});
  CHECK(m.passes[1].levels[2].defines == Defines{{"SHADING_MODEL", "0"}});

  const Pass& reflections = m.passes[2];
  CHECK(reflections.levels[1].uniforms ==
        std::vector<std::pair<std::string, UniformValue>>{{"u_samples", {{16}}}, {"u_kernel_taps", {{1}}}});
  CHECK(reflections.levels[2].replace.at(Stage::fragment) == kDemo + "/manifest/ssr_off.frag");
  CHECK(reflections.levels[2].replace_source.at(Stage::fragment) == read(kDemo + "/manifest/ssr_off.frag"));
  CHECK(reflections.levels[2].draws);

  const Pass& shadows = m.passes[3];
  CHECK(shadows.levels[1].scale == 0.5);
  CHECK(shadows.levels[2].scale == 0.25);
  CHECK(shadows.levels[2].targets == std::vector<Target>{target(Target::Kind::self)});
  CHECK(shadows.scales == std::vector<std::string>{"shadows"});

  CHECK(m.passes[4].levels[1].defines == Defines{{"METAL_SAMPLES", "6"}});
  CHECK(m.passes[4].levels[2].defines == Defines{{"METAL_SAMPLES", "2"}});
  CHECK(m.passes[5].levels[1].defines == Defines{{"FXAA_STEPS", "2"}});
  CHECK(m.passes[5].levels[2].replace_source.at(Stage::fragment) == read(kDemo + "/manifest/fxaa_off.frag"));
  for (const Pass& pass : m.passes) {
    if (pass.name != "resolution" && pass.name != "shadows") CHECK(pass.scales.empty());
  }
}

TEST_CASE("each of the demo's programs matches exactly its own pass") {
  const Manifest m = *load_manifest(kDemo + "/glbudget.toml").manifest;
  const std::vector<DemoProgram> programs = demo_programs();
  CHECK(programs.size() == 18);
  for (const DemoProgram& program : programs) {
    std::vector<std::string> matched;
    for (const Pass& pass : m.passes) {
      if (matches(pass.match, 0, program.sources)) matched.push_back(pass.name);
    }
    INFO(program.sources[1].substr(0, 120));
    if (program.pass.empty())
      CHECK(matched.empty());
    else
      CHECK(matched == std::vector<std::string>{program.pass});
  }
}

TEST_CASE("the demo's replacement shaders keep the declarations of the shaders they replace") {
  const auto declarations = [](const std::string& source) {
    std::vector<std::string> lines;
    std::istringstream in(source);
    for (std::string line; std::getline(in, line);) {
      if (line.starts_with("uniform ") || line.starts_with("in ") || line.starts_with("out ")) lines.push_back(line);
    }
    return lines;
  };
  CHECK(declarations(read(kDemo + "/manifest/ssr_off.frag")) == declarations(read(kDemo + "/shaders/ssr.frag")));
  CHECK(declarations(read(kDemo + "/manifest/fxaa_off.frag")) == declarations(read(kDemo + "/shaders/fxaa.frag")));
  CHECK(read(kDemo + "/manifest/ssr_off.frag").starts_with("#version 330 core\n"));
  CHECK(read(kDemo + "/manifest/fxaa_off.frag").starts_with("#version 330 core\n"));
}

TEST_CASE("shader_coordinates: app by default, scaled when asked, a bad value warned") {
  CHECK(load_ok("[[pass]]\nname = \"a\"\n").app_coordinates);
  CHECK_FALSE(load_ok("shader_coordinates = \"scaled\"\n[[pass]]\nname = \"a\"\n").app_coordinates);
  CHECK(load_ok("shader_coordinates = \"app\"\n[[pass]]\nname = \"a\"\n").app_coordinates);
  std::vector<std::string> problems;
  CHECK(load_ok("shader_coordinates = \"stored\"\n[[pass]]\nname = \"a\"\n", &problems).app_coordinates);
  REQUIRE(problems.size() == 1);
  CHECK(problems[0] == "m.toml:1:22: shader_coordinates must be \"app\" or \"scaled\"; \"app\" is used");
  CHECK_FALSE(
      with_resolution_pass(load_ok("shader_coordinates = \"scaled\"\n[[pass]]\nname = \"a\"\n")).app_coordinates);
}
