// Integration (issue 12): program shadowing, one probe per case (testapps/probes/probe_*.cpp,
// see probe_shadowing.hpp), each under a manifest of its own (tests/data/manifests/probes/).
// Every probe checks what its shader received against what it set, after every draw, and
// glGetError; it exits 1 on any mismatch, printing it. Here each runs three ways: without the
// shim, under the shim without a manifest, and under the shim with its manifest and forced
// levels (GLBUDGET_FORCE="a;b;..." with GLBUDGET_FORCE_EVERY=1: frame f, counted from 0, draws
// configuration f % n). All must exit 0; each draw prints "frame F draw D mark M ...", M being
// the VARIANT_MARK of the program that drew (0 in the app's source, redefined by a level), so
// the tests know which program the driver ran. Cases tagged [!shouldfail] / [!mayfail] pin
// down shim bugs found by these probes; each says what goes wrong and where.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "probe_expectations.hpp"

namespace {

std::string manifest(const std::string& name) {
  return std::string(GLBUDGET_SOURCE_DIR) + "/tests/data/manifests/probes/" + name + ".toml";
}

struct Draw {
  int frame = -1, draw = -1;
  unsigned mark = 0;
  std::string rest;  // what the probe printed after the mark
};

std::vector<Draw> draws_of(const std::string& out) {
  std::vector<Draw> draws;
  std::istringstream in(out);
  std::string line;
  while (std::getline(in, line)) {
    Draw d;
    char rest[512] = {};
    if (std::sscanf(line.c_str(), "frame %d draw %d mark %u %511[^\n]", &d.frame, &d.draw, &d.mark, rest) >= 3) {
      d.rest = rest;
      draws.push_back(d);
    }
  }
  return draws;
}

// The probe's own value of `key` in a draw's line ("... u_x 3.5 ..."), or "".
std::string field(const Draw& d, const std::string& key) {
  std::istringstream in(d.rest);
  std::string word, value;
  while (in >> word)
    if (word == key && in >> value) return value;
  return {};
}

struct Run {
  ProcessResult result;
  std::vector<Draw> draws;
  std::string log;  // the shim's frame log, when it had one
};

enum class Mode { plain, shim, shadowed };

// Levels of the manifest's one pass, frame by frame (the render-scale pass stays at 0).
struct Forced {
  std::vector<int> levels;
  std::string force() const {
    std::string s;
    for (size_t i = 0; i < levels.size(); ++i) s += (i ? ";0," : "0,") + std::to_string(levels[i]);
    return s;
  }
  int level(int frame) const { return levels[static_cast<size_t>(frame) % levels.size()]; }
};

Run run_probe(const std::string& probe, Mode mode, const std::string& manifest_name, const Forced& forced, int frames,
              const std::vector<std::string>& extra_args = {}, std::map<std::string, std::string> env = {}) {
  std::vector<std::string> args = {probe_path(probe), "--frames", std::to_string(frames)};
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  Run run;
  if (mode != Mode::plain) {
    env["LD_PRELOAD"] = shim_path();
    env["GLBUDGET_SENSOR"] = "cpu";  // named: the shim has nothing to announce
    run.log = temp_path(probe + (mode == Mode::shim ? "_shim.csv" : "_shadowed.csv"));
    unlink(run.log.c_str());
    env["GLBUDGET_LOG"] = run.log;
  }
  if (mode == Mode::shadowed) {
    env["GLBUDGET_CONFIG"] = manifest(manifest_name);
    env["GLBUDGET_FORCE"] = forced.force();
    env["GLBUDGET_FORCE_EVERY"] = "1";
  }
  run.result = run_process(args, env);
  run.draws = draws_of(run.result.out);
  return run;
}

// `draws` draws, each with the mark `mark_of(draw)` says.
void check_marks(const Run& run, size_t draws, const std::function<unsigned(const Draw&)>& mark_of) {
  REQUIRE(run.draws.size() == draws);
  for (const Draw& d : run.draws) {
    INFO("frame " << d.frame << " draw " << d.draw << ": " << d.rest);
    CHECK(d.mark == mark_of(d));
  }
}

// The shim's log: one configuration per frame, as forced; returns the pass column per frame
// (each frame's passes, in the order logged).
std::map<int, std::vector<std::string>> check_log_configurations(const Run& run, const Forced& forced, int frames) {
  const auto rows = read_csv_rows_by_name(run.log);
  std::map<int, std::vector<std::string>> passes;
  for (const auto& row : rows) {
    const int frame = std::stoi(row.at("frame")) - 1;  // the log counts from 1
    INFO("log frame " << frame + 1);
    CHECK(row.at("configuration") == "0:" + std::to_string(forced.level(frame)));
    passes[frame].push_back(row.at("pass"));
  }
  CHECK(passes.size() == static_cast<size_t>(frames));
  unlink(run.log.c_str());
  return passes;
}

// The mark a draw must show at a level.
using MarkOf = std::function<unsigned(const Draw&, int level)>;
unsigned level_is_mark(const Draw&, int level) { return static_cast<unsigned>(level); }

// Runs a probe the three ways: all exit 0 with no `glbudget:` line and `draws` draws; without
// a manifest every mark is 0, with it `mark_of(draw, level)`. Returns the shadowed run.
Run run_three_ways(const std::string& probe, const std::string& manifest_name, const Forced& forced, int frames,
                   size_t draws, const MarkOf& mark_of, const std::vector<std::string>& extra_args = {}) {
  for (Mode mode : {Mode::plain, Mode::shim}) {
    const Run r = run_probe(probe, mode, manifest_name, forced, frames, extra_args);
    INFO(probe << (mode == Mode::plain ? " without the shim" : " under the shim, no manifest") << "\nstdout:\n"
               << r.result.out << "stderr:\n"
               << r.result.err);
    REQUIRE(r.result.exit_code == 0);
    CHECK(count_lines_with(r.result.err, "glbudget:") == 0);
    check_marks(r, draws, [](const Draw&) { return 0u; });
    if (!r.log.empty()) unlink(r.log.c_str());
  }
  Run r = run_probe(probe, Mode::shadowed, manifest_name, forced, frames, extra_args);
  INFO(probe << " under the shim with " << manifest_name << ".toml, GLBUDGET_FORCE=" << forced.force() << "\nstdout:\n"
             << r.result.out << "stderr:\n"
             << r.result.err);
  CHECK(r.result.exit_code == 0);
  check_marks(r, draws, [&](const Draw& d) { return mark_of(d, forced.level(d.frame)); });
  return r;
}

}  // namespace

TEST_CASE("shadowing 1: uniforms of every type reach the variant, before and after each switch",
          "[integration][shadowing]") {
  // Scalars, vectors, matrices (square, non-square, transposed), doubles, arrays set whole,
  // element by element at loc + i and in two calls, structs, arrays of structs, a struct in a
  // struct, initialisers; glUniform* and glProgramUniform*. Level 1's variant declares three
  // uniforms ahead of the app's, so all its locations differ from the app's.
  // Frame 0 draws once (nothing was set before it), the others twice: the previous frame's
  // values, then new ones.
  const Forced forced{{0, 1}};
  Run r = run_three_ways("probe_uniforms", "uniforms", forced, 6, 11, level_is_mark);
  CHECK(count_lines_with(r.result.err, "glbudget:") == 0);
  const auto passes = check_log_configurations(r, forced, 6);
  std::set<std::string> level0, level1;
  for (const auto& [frame, names] : passes) {
    REQUIRE(names.size() == 1);
    (forced.level(frame) ? level1 : level0).insert(names[0]);
  }
  CHECK(level0.size() == 1);
  CHECK(level1.size() == 1);
  CHECK(level0 != level1);  // a variant is logged under its own sources' hash
}

TEST_CASE("shadowing 1b: uniforms set only while the variant is bound (level 1 from the first frame)",
          "[integration][shadowing]") {
  const Forced always{{1}};
  Run v = run_probe("probe_uniforms", Mode::shadowed, "uniforms", always, 4);
  INFO(v.result.err);
  CHECK(v.result.exit_code == 0);
  CHECK(count_lines_with(v.result.err, "glbudget:") == 0);
  check_marks(v, 7, [](const Draw&) { return 1u; });
  check_log_configurations(v, always, 4);

  // Subroutine selections made while a variant with the app's subroutine indices is bound
  // (probe_subroutines, level 2), with no switch: they reach it.
  const Forced level2{{2}};
  Run s = run_probe("probe_subroutines", Mode::shadowed, "subroutines", level2, 6);
  INFO(s.result.out << s.result.err);
  CHECK(s.result.exit_code == 0);
  CHECK(count_lines_with(s.result.err, "glbudget:") == 0);
  check_marks(s, 6, [](const Draw&) { return 2u; });
  check_log_configurations(s, level2, 6);
}

TEST_CASE("shadowing 1c: subroutine selections survive a switch of variant", "[integration][shadowing]") {
  // GL resets subroutine uniforms at glUseProgram, so an app selects after binding and may then
  // draw for frames without either call. A switch of configuration at a swap rebinds the
  // program through glUseProgram (interpose/state/contexts.cpp apply_configuration ->
  // gl_programs.cpp bind_program); the shim keeps the app's last selection per context and
  // stage and re-applies it right after (interpose/apply/subroutines.cpp), so the variant, and
  // the app's program after a switch back, run the function the app selected, and
  // glGetUniformSubroutineuiv answers the app's index. Level 2's variant has the app's
  // subroutine indices: only the reset is at stake here.
  const Forced forced{{0, 2}};
  const Run r = run_three_ways("probe_subroutines", "subroutines", forced, 6, 6, level_is_mark);
  CHECK(count_lines_with(r.result.err, "glbudget:") == 0);
  check_log_configurations(r, forced, 6);
}

TEST_CASE("shadowing 1d: subroutine indices the app selects reach a variant whose indices differ",
          "[integration][shadowing]") {
  // Subroutine indices, like uniform locations, belong to a program; level 1's variant declares
  // one more subroutine function, so its indices differ from the app's. With the variant bound
  // from the first frame, the app's glUniformSubroutinesuiv reaches it translated by name
  // (tables built with the variant, interpose/apply/variants.cpp): the app's "pick_b" (index 1)
  // selects the variant's pick_b (index 2), and glGetUniformSubroutineuiv answers the app's
  // indices.
  const Forced forced{{1}};
  const Run r = run_probe("probe_subroutines", Mode::shadowed, "subroutines", forced, 6);
  INFO(r.result.out << r.result.err);
  CHECK(r.result.exit_code == 0);
  CHECK(count_lines_with(r.result.err, "glbudget:") == 0);
  check_marks(r, 6, [](const Draw&) { return 1u; });
  if (!r.log.empty()) unlink(r.log.c_str());
}

TEST_CASE("shadowing 2: sampler units follow the app; held uniforms keep the level's values",
          "[integration][shadowing]") {
  // Level 1 holds u_x = 3; level 2 redefines VARIANT_MARK (a sampler and a uniform array more,
  // ahead of the app's) and holds u_x = 3.5, u_hv = (1, 2, 3), u_xa = (4, 5) and sampler s_b on
  // unit 4. The probe checks the other samplers and uniforms itself; here the held ones.
  const Forced forced{{0, 1, 2}};
  const Run r = run_three_ways("probe_samplers", "samplers", forced, 6, 11,
                               [](const Draw&, int level) { return level == 2 ? 2u : 0u; });
  CHECK(count_lines_with(r.result.err, "glbudget:") == 0);
  for (const Draw& d : r.draws) {
    const int level = forced.level(d.frame);
    const int p = std::stoi(field(d, "phase"));
    INFO("frame " << d.frame << " draw " << d.draw << " level " << level << ": " << d.rest);
    char app_hv[64], app_xa[64];
    std::snprintf(app_hv, sizeof app_hv, "%.9g,%.9g,%.9g", double(p), p + 0.5, p + 0.25);
    std::snprintf(app_xa, sizeof app_xa, "%.9g,%.9g", 10.0 + p, 20.0 + p);
    const std::string app_x = [&] {
      char s[32];
      std::snprintf(s, sizeof s, "%.9g", 100.5 + p);
      return std::string(s);
    }();
    CHECK(field(d, "u_x") == (level == 0 ? app_x : level == 1 ? "3" : "3.5"));
    CHECK(field(d, "u_hv") == (level == 2 ? std::string("1,2,3") : std::string(app_hv)));
    CHECK(field(d, "u_xa") == (level == 2 ? std::string("4,5") : std::string(app_xa)));
    CHECK(field(d, "s_b") == std::to_string(level == 2 ? 4 : (p + 1) % 6));
  }
  check_log_configurations(r, forced, 6);
}

TEST_CASE("shadowing 3: uniform and storage block bindings set before and after a switch", "[integration][shadowing]") {
  // glUniformBlockBinding / glShaderStorageBlockBinding every frame, on blocks with and without
  // instance names, an array of blocks, a runtime-sized storage block, and blocks bound by
  // layout(binding); level 1's variant has a block of each kind more, so its block indices differ.
  const Forced forced{{0, 1}};
  const Run r = run_three_ways("probe_blocks", "blocks", forced, 6, 11, level_is_mark);
  CHECK(count_lines_with(r.result.err, "glbudget:") == 0);
  check_log_configurations(r, forced, 6);
}

TEST_CASE("shadowing 4: attribute and fragment-output locations the app chose hold in the variant",
          "[integration][shadowing]") {
  // glBindAttribLocation (array-fed and a current value), layout(location) attributes, an integer
  // attribute; glBindFragDataLocation (reversed) and layout(location) outputs on three
  // attachments. Level 1's variant declares two attributes and an output ahead of the app's.
  const Forced forced{{0, 1}};
  const Run r = run_three_ways("probe_attributes", "attributes", forced, 4, 7, level_is_mark);
  CHECK(count_lines_with(r.result.err, "glbudget:") == 0);
  check_log_configurations(r, forced, 4);
}

TEST_CASE("shadowing 4b: locations the app bound for names its program lacks hold in a variant that has them",
          "[integration][shadowing]") {
  // Apps that bind one fixed scheme for every program call glBindAttribLocation(p, 7,
  // "tangent") and glBindFragDataLocation(p, 4, "outD") / (p, 3, "outE") whatever p declares.
  // The app's program lacks them; level 1's variant (VARIANT_MARK = 1) declares and uses them,
  // and the app's own build of that source would have them where it bound them. glbudget
  // records those calls per program and replays them on each variant before it links.
  const Forced forced{{0, 1}};
  const Run r =
      run_three_ways("probe_attributes", "attributes", forced, 4, 7, level_is_mark, {"--scenario", "inactive"});
  CHECK(count_lines_with(r.result.err, "glbudget:") == 0);
  if (!r.log.empty()) unlink(r.log.c_str());
}

TEST_CASE("shadowing 5: program pipelines draw their stages' variants, switched with the configuration",
          "[integration][shadowing]") {
  // The manifest's pass matches all three fragment programs: A (glCreateShaderProgramv) and B
  // (a separable program the app linked) drawn in program pipelines, C with glUseProgram.
  // glbudget puts each stage's variant in the app's pipelines (glUseProgramStages with the
  // variant) and swaps them at a switch; glGetProgramPipelineiv answers the app's programs,
  // uniforms set through glActiveShaderProgram + glUniform* or glProgramUniform* reach the
  // variants, GL_CURRENT_PROGRAM stays 0 with a pipeline bound (the probe checks these).
  const Forced forced{{0, 1}};
  const Run r = run_three_ways("probe_pipeline_stages", "pipeline_stages", forced, 4, 16,
                               [](const Draw&, int level) { return static_cast<unsigned>(level); });
  CHECK(count_lines_with(r.result.err, "glbudget:") == 0);
  check_log_configurations(r, forced, 4);
}

TEST_CASE("shadowing 6: a program relinked with new sources gets variants of the new sources",
          "[integration][shadowing]") {
  // Relinks while bound at level 1 (the variant in the driver), with the program unbound, and
  // at level 0; the new sources declare their uniforms in another order and one more.
  // Frames 1, 3 and 4 draw twice, before and after their relink.
  const Forced forced{{0, 1}};
  const Run s = run_three_ways("probe_relink", "relink", forced, 6, 9, level_is_mark, {"--scenario", "matched"});
  CHECK(count_lines_with(s.result.err, "glbudget:") == 0);
  // The version each draw ran: 1, then 2 after frame 1's relink, 4 after frame 3's, 1 after
  // frame 4's.
  const std::map<std::pair<int, int>, std::string> versions = {{{0, 0}, "1"}, {{1, 0}, "1"}, {{1, 1}, "2"},
                                                               {{2, 0}, "2"}, {{3, 0}, "2"}, {{3, 1}, "4"},
                                                               {{4, 0}, "4"}, {{4, 1}, "1"}, {{5, 0}, "1"}};
  for (const Draw& d : s.draws) {
    INFO("frame " << d.frame << " draw " << d.draw);
    CHECK(field(d, "version") == versions.at({d.frame, d.draw}));
  }
  check_log_configurations(s, forced, 6);
}

TEST_CASE("shadowing 6b: relinked to sources no pass matches while a variant is bound, the app's program draws",
          "[integration][shadowing]") {
  // With level 1 in force the driver has the variant bound; the app relinks its program
  // (glShaderSource, glCompileShader, glLinkProgram on the bound program) to a source no
  // manifest pass matches. The variants go, and the app's program must be bound again: the
  // next draws run the new source and the app's glUniform* reach its program.
  const Forced forced{{0, 1}};
  const Run s = run_probe("probe_relink", Mode::shadowed, "relink", forced, 6, {"--scenario", "unmatched"});
  INFO(s.result.out << s.result.err);
  CHECK(s.result.exit_code == 0);
  // Version 3 matches no pass: the app's program draws it, mark 0, at either level.
  check_marks(s, 10, [&](const Draw& d) {
    return field(d, "version") == "3" ? 0u : static_cast<unsigned>(forced.level(d.frame));
  });
  const std::map<std::pair<int, int>, std::string> versions = {
      {{0, 0}, "1"}, {{1, 0}, "1"}, {{1, 1}, "3"}, {{2, 0}, "3"}, {{2, 1}, "2"},
      {{3, 0}, "2"}, {{4, 0}, "2"}, {{4, 1}, "3"}, {{5, 0}, "3"}, {{5, 1}, "4"}};
  for (const Draw& d : s.draws) {
    INFO("frame " << d.frame << " draw " << d.draw);
    CHECK(field(d, "version") == versions.at({d.frame, d.draw}));
  }
  unlink(s.log.c_str());
}

TEST_CASE("shadowing 6c: a program the app deletes while it is bound keeps drawing, at every level",
          "[integration][shadowing]") {
  // GL keeps a program deleted while in use until it is unbound, so an app may glDeleteProgram
  // its bound program and go on drawing with it and setting its uniforms. With a variant bound
  // in the driver instead (level 1, or a switch to it at the next swap), the driver would
  // delete the app's program at once; glbudget defers the real delete until the app binds
  // another program.
  for (const Forced& forced : {Forced{{0, 1}}, Forced{{1, 0}}}) {
    const Run r = run_three_ways("probe_relink", "relink", forced, 6, 6, level_is_mark, {"--scenario", "deleted"});
    CHECK(count_lines_with(r.result.err, "glbudget:") == 0);
    check_log_configurations(r, forced, 6);
  }
}

TEST_CASE("shadowing 7: locations, indices and GL_CURRENT_PROGRAM answer as without glbudget",
          "[integration][shadowing]") {
  // Every "query" line the probe prints (locations by every query, active resources, block
  // indices, GL_CURRENT_PROGRAM through glGetIntegerv/Integer64v/Floatv/Doublev/Booleanv with
  // the program bound, after a draw, with another bound, with none) must be the same without the
  // shim, under it without a manifest, and under it at level 0 and level 1, whose variant has
  // an attribute, uniforms and blocks more ahead of the app's.
  auto queries = [](const Run& r) {
    std::string q;
    std::istringstream in(r.result.out);
    std::string line;
    while (std::getline(in, line))
      if (line.rfind("query ", 0) == 0) q += line + "\n";
    return q;
  };
  const Forced forced{{0, 1}};
  const Run plain = run_probe("probe_locations", Mode::plain, "locations", forced, 4);
  REQUIRE(plain.result.exit_code == 0);
  const std::string expected = queries(plain);
  REQUIRE(count_lines_with(expected, "query current program") == 4 * 6);
  for (Mode mode : {Mode::shim, Mode::shadowed}) {
    for (const Forced& f : {Forced{{0, 1}}, Forced{{1, 0}}}) {
      const Run r = run_probe("probe_locations", mode, "locations", f, 4);
      INFO((mode == Mode::shim ? "no manifest" : "GLBUDGET_FORCE=" + f.force()) << "\n" << r.result.err);
      CHECK(r.result.exit_code == 0);
      CHECK(count_lines_with(r.result.err, "glbudget:") == 0);
      CHECK(queries(r) == expected);
      check_marks(r, 4,
                  [&](const Draw& d) { return mode == Mode::shim ? 0u : static_cast<unsigned>(f.level(d.frame)); });
      unlink(r.log.c_str());
      if (mode == Mode::shim) break;
    }
  }
}

TEST_CASE("shadowing 8: a variant that does not compile or link: one line each, the app's program draws",
          "[integration][shadowing]") {
  // Level 1 redefines BAD to "(" (does not compile), level 3 replaces the fragment stage with
  // one that does not link, level 2 is good. Two programs of the same sources draw each frame.
  const Forced forced{{0, 1, 2, 3}};
  const int frames = 8;  // every level twice
  for (Mode mode : {Mode::plain, Mode::shim}) {
    const Run r = run_probe("probe_bad_variant", mode, "bad_variant", forced, frames);
    INFO(r.result.err);
    CHECK(r.result.exit_code == 0);
    CHECK(count_lines_with(r.result.err, "glbudget:") == 0);
    check_marks(r, 2 * frames, [](const Draw&) { return 0u; });
    if (!r.log.empty()) unlink(r.log.c_str());
  }
  const Run r = run_probe("probe_bad_variant", Mode::shadowed, "bad_variant", forced, frames);
  INFO(r.result.out << r.result.err);
  CHECK(r.result.exit_code == 0);  // every draw showed the app's values, and no GL error
  CHECK(count_lines_with(r.result.err, "glbudget:") == 2);
  CHECK(count_lines_with(r.result.err, "glbudget: pass 'fragile' level 1 (syntax error): ") == 1);
  CHECK(count_lines_with(r.result.err, "does not compile") == 1);
  CHECK(count_lines_with(r.result.err, "glbudget: pass 'fragile' level 3 (unlinkable): ") == 1);
  CHECK(count_lines_with(r.result.err, "does not link") == 1);
  CHECK(count_lines_with(r.result.err, "this level draws the app's program") == 2);
  // Levels 1 and 3 draw the app's program (mark 0), level 2 its variant.
  check_marks(r, 2 * frames, [&](const Draw& d) { return forced.level(d.frame) == 2 ? 2u : 0u; });
  check_log_configurations(r, forced, frames);
}

TEST_CASE("faults: GL_OUT_OF_MEMORY while building a variant: one line, no more variants, the app's errors its own",
          "[integration][shadowing][faults]") {
  // GLBUDGET_TEST_OUT_OF_MEMORY=fragile:2 has the shim, while it builds level 2's variant, ask
  // the driver for a buffer no machine has: a real GL_OUT_OF_MEMORY, which the shim must read
  // (the level is dropped and, the driver short of memory, no variant is built after it) and
  // the app must not: the probe raised GL_INVALID_ENUM before linking and reads exactly that
  // after, then no error to the end. Level 1 (does not compile) was built before; level 3 and
  // the second program's variants are not tried.
  const Forced forced{{0, 1, 2, 3}};
  const int frames = 8;
  const Run r = run_probe("probe_bad_variant", Mode::shadowed, "bad_variant", forced, frames, {},
                          {{"GLBUDGET_TEST_OUT_OF_MEMORY", "fragile:2"}});
  INFO(r.result.out << r.result.err);
  CHECK(r.result.exit_code == 0);
  CHECK(count_lines_with(r.result.err, "glbudget:") == 2);
  CHECK(count_lines_with(r.result.err, "glbudget: pass 'fragile' level 1 (syntax error): ") == 1);
  CHECK(count_lines_with(r.result.err,
                         "glbudget: pass 'fragile' level 2 (marked): the driver ran out of memory "
                         "(GL_OUT_OF_MEMORY) building the variant of program ") == 1);
  CHECK(count_lines_with(r.result.err, "no more variants are built") == 1);
  CHECK(count_lines_with(r.result.err, "does not link") == 0);
  check_marks(r, 2 * frames, [](const Draw&) { return 0u; });  // the app's programs at every level
  check_log_configurations(r, forced, frames);
}
