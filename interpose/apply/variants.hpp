// Program shadowing: the variant programs of a program the manifest matches, one per level of
// its pass that changes the program (#defines, a replaced stage, held uniforms). Built when the
// app links its program, in the same share group, with the app's attribute and output
// locations and separable flag; then every uniform and block binding the app sets reaches
// each variant too, through per-variant location tables (a location a variant lacks is
// dropped, never passed to the driver), and so do its subroutine selections (per-variant
// subroutine tables, apply/subroutines.hpp). The app only ever sees its own program.
#pragma once
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "configuration.hpp"
#include "frame_row.hpp"
#include "gl_types.hpp"
#include "pass_counter.hpp"

namespace glbudget {

class Instrumentation;

// Subroutine uniforms (GL 4.0): their indices and locations belong to a program, as uniform
// locations do (apply/subroutines.hpp). Stages are slotted 0..5: vertex, tess control, tess
// evaluation, geometry, fragment, compute; -1 for anything else.
constexpr int kShaderStages = 6;
int shader_stage_slot(GLenum stage);
// One stage of one program, in its own terms.
struct SubroutineStage {
  GLint locations = -1;                         // GL_ACTIVE_SUBROUTINE_UNIFORM_LOCATIONS; -1: not tracked (the program
                                                // has no such stage, or the context no GL 4.0)
  GLuint subroutines = 0;                       // 1 + the highest subroutine index
  std::vector<std::vector<GLuint>> compatible;  // per location (empty: no uniform there)
};
// How the app's selection of one stage reaches a variant: built with it, matched by name.
struct SubroutineMap {
  SubroutineStage own;              // the variant's
  std::vector<GLuint> index;        // app subroutine index -> the variant's (GL_INVALID_INDEX: lacks it)
  std::vector<GLint> app_location;  // variant location -> the app's (-1: the app has no such uniform)
};

// The uniforms of a variant whose fragment shader was rewritten to see the app's pixels in
// scaled targets (instrument/app_space.hpp), set before its draws (apply/app_space.hpp). The
// values last given (uniforms are the program's state) are shared by the levels that draw the
// same program, and skip repeating them.
struct AppSpaceUniforms {
  GLint frag_ratio = -1;  // glbudget_frag_ratio (-1: the shader does not read gl_FragCoord)
  struct Sampler {
    GLint sampler = -1;  // the sampler uniform (its value: the texture unit)
    GLint size = -1;     // its glbudget_size_<name>
  };
  std::vector<Sampler> samplers;
  struct Given {
    std::array<float, 2> ratio{1.0f, 1.0f};
    std::vector<std::array<GLint, 3>> sizes;  // per sampler
  };
  std::shared_ptr<Given> given;
  bool any() const { return frag_ratio >= 0 || !samplers.empty(); }
};

struct Variant {
  GLuint program = 0;         // 0: the level draws with the app's program
  PassId pass_hash = 0;       // the program's name in the frame log (as if the app had built it)
  bool draws = true;          // false: the level skips the pass's draws
  bool instrumented = false;  // built from instrumented sources (GLBUDGET_INSTRUMENT, GLBUDGET_DUMP)
  // Its name in the dump: hash_text(pass_hash), with "-level<l>" added when only held
  // uniforms set it apart (its sources, hence its log name, are the app program's).
  std::string dump_name;
  // App location -> variant location (-1: absent, or held by the level).
  std::vector<GLint> location;
  std::vector<GLint> uniform_block;  // app block index -> variant index (-1: absent)
  std::vector<GLint> storage_block;
  std::array<SubroutineMap, kShaderStages> subroutines;  // per stage slot
  AppSpaceUniforms app_space;
};

struct VariantSet {
  GLuint app_program = 0;
  int pass = -1;                 // manifest pass; -1: no pass, one level (the app's program in app coordinates)
  std::vector<Variant> levels;   // one per level of the pass
  std::vector<GLuint> programs;  // distinct variant programs (not the app's)
  std::array<SubroutineStage, kShaderStages> app_subroutines;  // the app program's, per stage slot

  const Variant& at(const Levels& config) const {
    const int l = pass < 0 ? 0 : config[pass];
    return levels[static_cast<size_t>(l < static_cast<int>(levels.size()) ? l : 0)];
  }
  GLuint program_for(const Levels& config) const {
    const Variant& v = at(config);
    return v.program ? v.program : app_program;
  }
};

struct ShaderSource {
  GLenum stage = 0;
  std::string source;
};

// The manifest pass that claims a linked program, or -1.
int match_pass(PassId hash, const std::vector<ShaderSource>& sources);

// Builds the variants of `program` (linked successfully by the app) for manifest pass `pass`
// (-1: one level, the app's program unchanged). With `app_coordinates`, every level whose
// fragment shader reads pixel coordinates is built rewritten to see the app's pixels in
// scaled targets (instrument/app_space.hpp), the app's own level too; where the rewrite cannot
// follow a use, `refused` gets why (the first one) and the level is built as it is.
// Levels whose variant does not compile or link are reported once and fall back to the app's
// program. Null when the pass needs no variant program (only draws/scale levels) and skips
// nothing, or when the driver lacks glProgramUniform*.
struct NameBindings {
  std::vector<std::pair<std::string, GLuint>> attributes;
  std::vector<std::pair<std::string, std::pair<GLuint, GLuint>>> frag_data;  // colour, index
};
// With `inst` (instrumentation on in this context) each variant is instrumented too, counting
// under its own program hash; one that does not build instrumented is built plainly.
// The caller has moved the app's pending GL errors aside (state/gl_errors.hpp, OwnGlWork): a
// level whose build raises an error is dropped with one glbudget: line, and after a
// GL_OUT_OF_MEMORY no variant is built again in the process.
std::shared_ptr<VariantSet> build_variants(GLuint program, PassId app_hash, int pass,
                                           const std::vector<ShaderSource>& sources, const GlCaps& caps,
                                           const NameBindings& bindings, Instrumentation* inst, bool app_coordinates,
                                           const std::optional<std::vector<std::string>>& driver_extensions,
                                           std::string* refused);
void delete_variants(const VariantSet& set);

// The app's last glUniformSubroutinesuiv of one stage, in its program's indices, and the
// variant set (of that program, at that link) it was made under (apply/subroutines.hpp).
struct SubroutineSelection {
  std::shared_ptr<const VariantSet> set;
  std::vector<GLuint> indices;
};

// Where one of the app's uniform calls goes: each (program, location) pair.
struct UniformTargets {
  int count = 0;
  GLuint program[kMaxPasses + 1];
  GLint location[kMaxPasses + 1];
};
void uniform_targets(const VariantSet& set, GLint app_location, UniformTargets* out);

// glUniformBlockBinding / glShaderStorageBlockBinding for each variant.
void forward_block_binding(const VariantSet& set, GLuint index, GLuint binding, bool storage);

}  // namespace glbudget
