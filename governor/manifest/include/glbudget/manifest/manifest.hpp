#pragma once
// The variant manifest (TOML): which programs form which pass, and the pass's quality levels,
// best first. Read by the shim (to build and apply variants) and by the model (its
// configuration space). GL-free: stages and targets are named, never GL enums.
//
//   [[pass]]
//   name = "base"
//   match = { source = "SHADING_MODEL" }          # or hash = ["542f5c2146c2220b", ...]
//   [[pass.level]]                                 # level 0: the app's own program
//   name = "microfacet"
//   [[pass.level]]
//   defines = { SHADING_MODEL = 1 }                # set (or add) a #define
//   [[pass.level]]
//   replace = { fragment = "cheap_base.frag" }     # a file beside the manifest
//   uniforms = { u_samples = 16 }                  # held at this value
//   draws = false                                  # the pass's draws are skipped
//   scale = 0.5                                    # render targets at half width and height
//   targets = ["self", "pass:metals", "default", "window-sized", "texture:12", "framebuffer:3"]
//
// Schema. Top level: `pass`, an array of tables, in the order of GLBUDGET_FORCE;
// `shader_coordinates`, "app" (default) or "scaled" (Manifest::app_coordinates).
//   pass.name     string, required, unique.
//   pass.match    table: `hash` (string or array of strings of 16 hex digits, the frame log's
//                 program hash) and/or `source` (string or array of non-empty strings, each a
//                 substring of a shader source). Absent: the pass owns no programs.
//   pass.level    array of tables, best first. Absent or empty: one identity level.
//   pass.scales   array of pass names. Absent: derived from the levels' targets ("self": this
//                 pass, "pass:X": X, "default" and "window-sized": every pass with a match;
//                 texture/framebuffer targets name no pass).
// Level keys:
//   name            string.
//   defines         table NAME -> string | integer | float | bool (finite), in manifest order;
//                   the value is kept as GLSL text: 3, 1.0, 0.25, true, strings verbatim.
//   replace         table stage -> file (relative to the manifest's directory): the stage's
//                   complete source, #version line included. Read at load.
//   uniforms        table name -> number | bool (1 / 0) | array of numbers (and bools; nested
//                   arrays are flattened).
//   draws           bool (default true).
//   scale           number in (0, 1] (default 1).
//   targets         array of "self", "default", "window-sized", "pass:NAME", "texture:N",
//                   "framebuffer:N" (N >= 1); "window-sized": every app framebuffer whose
//                   images all have the window's size, whichever pass draws into it. Only with scale < 1 (ignored with
//                   a warning at scale 1); absent: "self" when the pass has a match, else "default"; "self" needs a
//                   match. A "pass:NAME" naming no pass is dropped with a warning, and a level left with no target is
//                   dropped.
//   fragment_scale  number > 0 (default scale * scale).
//   error           number in [0, 1]: the level's error (1 - SSIM against the best configuration)
//                   with every other pass at its best, measured or guessed; the governor's error
//                   estimates add these up (paper §6.2). Level 0 is the reference: its error
//                   is 0 (a different value is ignored with a warning). Absent: the governor
//                   uses a stand-in (governor/loop/error_table.hpp).
// Stages: vertex, tess_control, tess_evaluation, geometry, fragment, compute.
//
// Problems never throw. A TOML syntax error is fatal. An unknown key is a warning and is
// ignored. An invalid value drops its level (level 0: its pass); a pass without a name, a
// duplicate name or an invalid match is dropped; no usable pass left is fatal.
//
// A pass named "resolution" with no match is the paper's render scale. When the manifest has
// no pass named "resolution", the shim puts its own first: the default framebuffer and every
// window-sized framebuffer at 100 / 80 / 60 / 50 % (builtin_resolution_pass()).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace glbudget::manifest {

enum class Stage { vertex, tess_control, tess_evaluation, geometry, fragment, compute };
const char* stage_name(Stage stage);  // "vertex", ..., as in the manifest
std::optional<Stage> parse_stage(const std::string& name);

// Which render targets a level scales.
struct Target {
  enum class Kind {
    self,                 // the framebuffers this pass's draws go to
    pass,                 // the framebuffers another pass's draws go to (`name`)
    default_framebuffer,  // the window ("default")
    window_sized,         // every app framebuffer whose images are the window's size ("window-sized")
    texture,              // an app texture by GL name (`id`)
    framebuffer,          // an app framebuffer object by GL name (`id`): all its attachments
  };
  Kind kind = Kind::self;
  std::string name;  // Kind::pass
  uint32_t id = 0;   // Kind::texture, Kind::framebuffer
  bool operator==(const Target&) const = default;
};

// A uniform value: numbers in the order GL stores them (vectors, then matrices column-major).
// The GL type comes from the program at run time; the count must fit it.
struct UniformValue {
  std::vector<double> values;
  bool operator==(const UniformValue&) const = default;
};

struct Level {
  std::string name;                                          // may be empty
  std::vector<std::pair<std::string, std::string>> defines;  // in manifest order
  std::map<Stage, std::string> replace;                      // stage -> absolute path of the file
  std::map<Stage, std::string> replace_source;               // stage -> its contents (read at load)
  std::vector<std::pair<std::string, UniformValue>> uniforms;
  bool draws = true;
  double scale = 1.0;                    // (0, 1]: linear factor on width and height
  std::vector<Target> targets;           // what `scale` applies to (empty when scale == 1)
  std::optional<double> fragment_scale;  // for the model; default scale * scale
  std::optional<double> error;           // 1 - SSIM of this level alone, in [0, 1]; absent: unknown

  double fragment_scale_or_default() const { return fragment_scale.value_or(scale * scale); }

  // True when the level changes the program (a variant program must be built for it).
  bool changes_program() const { return !defines.empty() || !replace_source.empty() || !uniforms.empty(); }
  // True when the level is the app's own rendering unchanged.
  bool identity() const { return !changes_program() && draws && scale == 1.0; }
};

struct Match {
  std::vector<uint64_t> hashes;      // program hashes, as in the frame log's pass column
  std::vector<std::string> sources;  // substrings of any one of the program's shader sources
  bool empty() const { return hashes.empty() && sources.empty(); }
};

struct Pass {
  std::string name;
  Match match;                      // empty: the pass owns no programs (a render scale)
  std::vector<Level> levels;        // best first; never empty
  std::vector<std::string> scales;  // for the model: passes whose fragments `scale` multiplies
                                    // (names of this manifest's passes, in manifest order
                                    // when derived)
  // Some level scales render targets: the pass changes the image whether or not its own
  // programs draw.
  bool scales_targets() const;
};

struct Manifest {
  std::string path;  // where it was read from ("" for the built-in one)
  std::vector<Pass> passes;
  // `shader_coordinates`: "app" (the default) rewrites the fragment shaders that read
  // gl_FragCoord, texelFetch or textureSize so that, drawing into a scaled target, they see
  // the app's pixels (instrument/app_space.hpp): right for shaders written for one resolution.
  // "scaled" leaves them as they are: right for an app whose shaders follow its own render
  // scale, as a manifest reproducing that scale from outside does.
  bool app_coordinates = true;
  // Index of the pass of this name, or -1.
  int find(const std::string& name) const;
};

// One problem with the manifest, in the form `file:line:column: what` (without "glbudget: ").
struct Problem {
  std::string text;
  bool fatal = false;  // the manifest cannot be used at all
};

struct LoadResult {
  std::optional<Manifest> manifest;  // present unless a fatal problem
  std::vector<Problem> problems;     // warnings (unknown keys, bad levels dropped) and errors
};

// Parses TOML text; `path` names it in messages and anchors relative `replace` files.
LoadResult parse_manifest(const std::string& toml_text, const std::string& path);
LoadResult load_manifest(const std::string& path);

// Where an app's manifest is looked for when GLBUDGET_CONFIG names none:
// $XDG_CONFIG_HOME/glbudget/<executable>.toml (~/.config when unset), if that file exists;
// else empty. `executable` is the program's file name, without its directory.
std::string default_manifest_path(const std::string& executable);

// The default framebuffer at 100 / 80 / 60 / 50 %: the knob every app has. Its `scales` is
// empty: which passes draw into the default framebuffer is known only with a manifest (see
// with_resolution_pass()) or at run time.
Pass builtin_resolution_pass();
// The manifest the shim applies: `m` with builtin_resolution_pass() first unless it has a
// pass named "resolution"; the built-in pass alone without a manifest. The inserted pass
// scales every pass of `m` that has a match, as a "default" target does.
Manifest with_resolution_pass(std::optional<Manifest> m);

// GLBUDGET_FORCE: "1,0,2" -> one level per pass in manifest order (spaces allowed around the
// numbers). nullopt and `error` (when not null) set when the count is wrong, a field is not
// an integer or a level is out of range.
std::optional<std::vector<int>> parse_force(const std::string& text, const Manifest& m, std::string* error);

// Pass-name matching of a program: `hash` is the program's hash, `sources` its shaders' sources.
// True when the hash is listed or any source contains any of the substrings (case-sensitive);
// false for an empty match.
bool matches(const Match& match, uint64_t hash, const std::vector<std::string>& sources);

}  // namespace glbudget::manifest
