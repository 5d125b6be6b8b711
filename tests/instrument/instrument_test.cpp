// GL-free tests of the instrumenter: static figures of a hand-counted corpus, the counting
// rule on small cases, the inserted counters, and that glslang accepts what we produce.
#include "glbudget/instrument/app_space.hpp"
#include "glbudget/instrument/instrument.hpp"
#include "shader_files.hpp"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <thread>
#include <vector>

using namespace glbudget::instrument;
using glbudget::test::shader_file;

namespace {

InstrumentResult instrument(const std::string& source, Stage stage = Stage::fragment, int binding = 7) {
  return instrument_shader({{source}, stage, binding});
}

EShLanguage glslang_stage(Stage stage) {
  switch (stage) {
    case Stage::vertex:
      return EShLangVertex;
    case Stage::compute:
      return EShLangCompute;
    case Stage::geometry:
      return EShLangGeometry;
    case Stage::tess_control:
      return EShLangTessControl;
    case Stage::tess_evaluation:
      return EShLangTessEvaluation;
    case Stage::fragment:
      return EShLangFragment;
  }
  return EShLangFragment;
}

// glslang knows storage-buffer atomics only from GLSL 4.30 (and ES 3.10) on, not through
// the extensions we enable for older versions; Mesa accepts those (gl_instrument_test).
// To check our rewrite of an older shader with glslang, raise it to 4.30 compatibility.
std::string as_glsl430(std::string source) {
  const std::size_t version_end = source.find('\n');
  const int version = std::atoi(source.c_str() + std::string("#version ").size());
  if (source.rfind("#version ", 0) != 0 || version >= 430 || source.find(" es", 0) < version_end) return source;
  source.replace(0, version_end, "#version 430 compatibility");
  for (const char* ours :
       {"#extension GL_ARB_shader_storage_buffer_object : require", "#extension GL_ARB_uniform_buffer_object : enable",
        "#extension GL_EXT_gpu_shader4 : enable"}) {
    const std::size_t at = source.find(ours);
    if (at != std::string::npos) source.erase(at, std::string(ours).size());
  }
  return source;
}

// glslang's verdict on a shader: empty when it compiles, else its log.
std::string glslang_errors(const std::string& original, Stage stage) {
  static const bool initialised = glslang::InitializeProcess();
  (void)initialised;
  glslang::TShader shader(glslang_stage(stage));
  const std::string source = as_glsl430(original);
  const char* text = source.c_str();
  shader.setStrings(&text, 1);
  if (shader.parse(GetDefaultResources(), 110, false, EShMsgDefault)) return {};
  return shader.getInfoLog();
}

// The operation count inserted at the start of `main` (its entry block).
std::uint64_t main_entry_count(const InstrumentResult& r) {
  const std::string entry = "void main(){glbudget_ins += ";
  const std::size_t at = r.instrumented_source.find(entry);
  if (at == std::string::npos) return 0;
  return std::stoull(r.instrumented_source.substr(at + entry.size()));
}

std::uint64_t entry_ops(const std::string& body, const std::string& globals = "") {
  const auto r = instrument(
      "#version 430\nuniform vec4 v; uniform int k; uniform float a[4];\n"
      "uniform sampler2D s;\nout vec4 o;\n" +
      globals + "void main() {" + body + "}\n");
  INFO(r.error << "\n" << r.instrumented_source);
  REQUIRE(r.ok);
  return main_entry_count(r);
}

}  // namespace

TEST_CASE("static figures of the hand-counted corpus", "[instrument]") {
  struct Case {
    const char* file;
    Stage stage;
    int blocks;
    std::uint64_t instructions;
    int texture_calls;
    bool binding_in_source;
  };
  const Case cases[] = {
      {"loops.frag", Stage::fragment, 9, 16, 1, false},  {"jumps.frag", Stage::fragment, 24, 32, 1, true},
      {"compat.frag", Stage::fragment, 4, 10, 1, false}, {"quad.vert", Stage::vertex, 1, 5, 0, false},
      {"quad_es.vert", Stage::vertex, 1, 5, 0, true},    {"quad_compat.vert", Stage::vertex, 1, 5, 0, false},
  };
  for (const Case& c : cases) {
    SECTION(c.file) {
      const auto r = instrument(shader_file(c.file), c.stage);
      INFO(r.error);
      REQUIRE(r.ok);
      REQUIRE(r.figures);
      CHECK(r.figures->blocks == c.blocks);
      CHECK(r.figures->instructions == c.instructions);
      CHECK(r.figures->texture_calls == c.texture_calls);
      CHECK(r.binding_in_source == c.binding_in_source);
      INFO(r.instrumented_source);
      CHECK(glslang_errors(r.instrumented_source, c.stage) == "");
    }
  }
}

TEST_CASE("the counting rule on single statements", "[instrument]") {
  CHECK(entry_ops("o = v;") == 1);                               // assignment
  CHECK(entry_ops("o = v * 2.0 + v;") == 3);                     // two operators and the assignment
  CHECK(entry_ops("o = vec4(v.x, v.yz, a[2]);") == 2);           // swizzles, constant index free
  CHECK(entry_ops("o = vec4(a[k]);") == 3);                      // dynamic index, constructor, =
  CHECK(entry_ops("o = vec4(1.0, 2.0, 3.0, 4.0) * 2.0;") == 1);  // folded by glslang
  CHECK(entry_ops("o = vec4(float(k));") == 3);                  // conversion, constructor, =
  CHECK(entry_ops("o = normalize(v) + max(v, v);") == 4);        // built-ins count one each
  CHECK(entry_ops("o = k > 0 ? v : -v;") == 4);                  // >, unary -, ?:, =
  CHECK(entry_ops("o = v; o.x += 1.0; o.y++;") == 3);
  CHECK(entry_ops("o = vec4(f(v.x));", "float f(float x) { return x; }\n") == 3);  // call, ctor, =
  CHECK(entry_ops("o = v;", "float g = gl_FragCoord.x * 2.0;\n") == 3);            // global initialiser
}

TEST_CASE("texel accesses: one per sampling call, none for queries", "[instrument]") {
  const auto r = instrument(
      "#version 430\nuniform sampler2D s; out vec4 o;\n"
      "void main() { o = texture(s, vec2(0.5)) + texelFetch(s, ivec2(0), 0)"
      " + textureGather(s, vec2(0.5)) + vec4(textureSize(s, 0), 0, 0); }\n");
  REQUIRE(r.ok);
  CHECK(r.figures->texture_calls == 3);
  CHECK(r.instrumented_source.find("glbudget_tex += 3u;") != std::string::npos);
}

TEST_CASE("counters sit where the blocks start", "[instrument]") {
  const auto r = instrument(shader_file("loops.frag"));
  REQUIRE(r.ok);
  const std::string& s = r.instrumented_source;
  // loop condition and step count each evaluation; the unbraced body gets braces
  CHECK(s.find("(glbudget_ins += 1u, i < trips)") != std::string::npos);
  CHECK(s.find("(glbudget_ins += 1u, ++ i)") != std::string::npos);
  CHECK(s.find("{ glbudget_ins += 5u; sum += fetch(") != std::string::npos);
  // the called function counts its own body, texel access included
  CHECK(s.find("{glbudget_ins += 2u; glbudget_tex += 1u;  return texture(image, at)") != std::string::npos);
  // main flushes once at its end
  CHECK(s.find("glbudget_flush(); }") != std::string::npos);
}

TEST_CASE("discard and early return flush the invocation first", "[instrument]") {
  const auto r = instrument(shader_file("jumps.frag"));
  REQUIRE(r.ok);
  CHECK(r.instrumented_source.find("{ glbudget_flush(); discard; }") != std::string::npos);
  CHECK(r.instrumented_source.find("glbudget_flush(); return;") != std::string::npos);
  // return in another function does not flush
  CHECK(r.instrumented_source.find("{ return 0.0; }") != std::string::npos);
}

TEST_CASE("the counter block has the binding and the stage's words", "[instrument]") {
  const auto r = instrument(shader_file("quad_es.vert"), Stage::vertex, 31);
  REQUIRE(r.ok);
  CHECK(r.instrumented_source.find("#version 310 es") == 0);  // 3.00 has no storage buffers
  CHECK(r.instrumented_source.find("layout(std430, binding = 31) buffer glbudget_Counters") != std::string::npos);
  CHECK(r.instrumented_source.find("highp uint glbudget_ins") != std::string::npos);
  CHECK(r.instrumented_source.find("glbudget_add64(0, glbudget_ins)") != std::string::npos);
  const auto old = instrument(shader_file("quad_compat.vert"), Stage::vertex, 31);
  REQUIRE(old.ok);
  CHECK(old.instrumented_source.find("#extension GL_EXT_gpu_shader4 : enable") != std::string::npos);
  CHECK(old.instrumented_source.find("binding") == std::string::npos);
}

TEST_CASE("several source strings are one shader", "[instrument]") {
  const auto r = instrument_shader({{"#version 330\n", "out vec4 o;\n", "void main() { o = vec4(1.0) * 2.0 + o; }\n"},
                                    Stage::fragment,
                                    3});  // folded product, +, =
  REQUIRE(r.ok);
  CHECK(r.figures->instructions == 2);
}

TEST_CASE("shaders that cannot be instrumented say why", "[instrument]") {
  SECTION("GLSL ES 1.00 has no storage buffers, but has static figures") {
    const auto r = instrument(
        "#version 100\nprecision mediump float;\nuniform sampler2D s;\n"
        "void main() { gl_FragColor = texture2D(s, vec2(0.5)); }\n");
    CHECK_FALSE(r.ok);
    CHECK(r.error.find("storage buffers") != std::string::npos);
    REQUIRE(r.figures);
    CHECK(r.figures->texture_calls == 1);
    CHECK(r.figures->instructions == 2);
  }
  SECTION("syntax error") {
    const auto r = instrument("#version 330\nvoid main() { o = ; }\n");
    CHECK_FALSE(r.ok);
    CHECK(r.error.rfind("glslang cannot parse the shader:", 0) == 0);
    CHECK(r.error.find('\n') == std::string::npos);
  }
  SECTION("preprocessor error") {
    const auto r = instrument("#version 330\n#error nope\nvoid main() {}\n");
    CHECK_FALSE(r.ok);
    CHECK(r.error.rfind("glslang cannot preprocess the shader:", 0) == 0);
  }
  SECTION("empty source") {
    const auto r = instrument("");
    CHECK_FALSE(r.ok);
    CHECK_FALSE(r.error.empty());
  }
}

TEST_CASE("awkward but valid structure instruments and stays valid GLSL", "[instrument]") {
  struct Case {
    const char* name;
    Stage stage;
    const char* source;
    std::uint64_t instructions;  // static, by the counting rule
  };
  const Case cases[] = {
      {"else-if chain, unbraced", Stage::fragment,
       "#version 430\nuniform int k; out vec4 o;\nvoid main() {\n"
       "  if (k == 0) o = vec4(0.0); else if (k == 1) o = vec4(1.0); else o = vec4(2.0);\n}\n",
       5},  // ==, =, ==, =, =
      {"nested unbraced loops with break and continue", Stage::fragment,
       "#version 430\nuniform int k; out vec4 o;\nvoid main() {\n  o = vec4(0.0);\n"
       "  for (int i = 0; i < k; ++i) for (int j = 0; j < i; j++) if (j == 2) break; else if (j == 1) continue; else "
       "o.x += 1.0;\n"
       "  for (;;) { if (o.x > 3.0) break; o.x += 1.0; }\n}\n",
       12},  // o=; i=0, <, ++; j=0, <, ++; ==; ==; +=; >; +=
      {"switch with fallthrough and a do-while without braces", Stage::fragment,
       "#version 430\nuniform int k; out vec4 o;\nvoid main() {\n  int n = k;\n"
       "  switch (k) { case 0: case 1: n += 1; case 2: { n *= 2; break; } default: n = 0; }\n"
       "  do n--; while (n > 0);\n  o = vec4(n);\n}\n",
       9},  // n=k; +=; *=; =0; --; >; vec4(n): int→float conversion, constructor; =
      {"prototypes, structs, arrays, dead code after return", Stage::vertex,
       "#version 430\nstruct S { float a[2]; };\nfloat f(S s);\nin vec2 p;\n"
       "void main() {\n  S s = S(float[2](p.x, p.y));\n  gl_Position = vec4(f(s));\n  return;\n  gl_Position = "
       "vec4(1.0);\n}\n"
       "float f(S s) { return s.a[0] + s.a[1]; }\n",
       8},  // S(), float[2](), =; f(), vec4(), =; =; +
      {"#line with a source string number", Stage::fragment,
       "#version 430\n#line 7 3\nout vec4 o;\nvoid main() { o = vec4(1.0); }\n", 1},
      {"compute shader", Stage::compute,
       "#version 430\nlayout(local_size_x = 8) in;\nlayout(std430, binding = 0) buffer Data { float d[]; };\n"
       "void main() { d[gl_GlobalInvocationID.x] *= 2.0; }\n",
       2},  // dynamic index, *=
      {"geometry shader emitting in a loop", Stage::geometry,
       "#version 430\nlayout(triangles) in;\nlayout(triangle_strip, max_vertices = 3) out;\n"
       "void main() { for (int i = 0; i < 3; ++i) { gl_Position = gl_in[i].gl_Position; EmitVertex(); } "
       "EndPrimitive(); }\n",
       7},  // i=0, <, ++; gl_in[i] dynamic index, =; EmitVertex; EndPrimitive
      {"tessellation control shader", Stage::tess_control,
       "#version 430\nlayout(vertices = 3) out;\n"
       "void main() { gl_out[gl_InvocationID].gl_Position = gl_in[gl_InvocationID].gl_Position;\n"
       "  if (gl_InvocationID == 0) { gl_TessLevelInner[0] = 1.0; gl_TessLevelOuter[0] = 1.0; } barrier(); }\n",
       7},  // gl_out[id], gl_in[id] dynamic indices, =; ==; =; =; barrier
  };
  for (const Case& c : cases) {
    SECTION(c.name) {
      const auto r = instrument(c.source, c.stage);
      INFO(r.error << "\n" << r.instrumented_source);
      REQUIRE(r.ok);
      CHECK(r.figures->instructions == c.instructions);
      CHECK(glslang_errors(r.instrumented_source, c.stage) == "");
    }
  }
}

TEST_CASE("instrumenting from several threads at once gives the same result", "[instrument]") {
  // The shim instruments on whichever thread the app compiles shaders on.
  const std::string loops = shader_file("loops.frag"), jumps = shader_file("jumps.frag");
  const auto expected_loops = instrument(loops), expected_jumps = instrument(jumps);
  std::vector<std::thread> threads;
  std::atomic<int> mismatches{0};
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int i = 0; i < 5; ++i) {
        const auto r = instrument(t % 2 ? loops : jumps);
        const auto& expected = t % 2 ? expected_loops : expected_jumps;
        if (!r.ok || r.instrumented_source != expected.instrumented_source) ++mismatches;
      }
    });
  for (auto& thread : threads) thread.join();
  CHECK(mismatches == 0);
}

TEST_CASE("extension conditionals follow the driver's extensions when they are given", "[instrument]") {
  const std::string source =
      "#version 430\nout vec4 o;\n"
      "#if defined(GL_ARB_gpu_shader_fp64) && defined GL_NV_glbudget_imaginary\n#define PATH 2.0\n"
      "#elif defined(GL_NV_glbudget_imaginary) || GL_ES\n#define PATH 3.0\n"
      "#else\n#define PATH 4.0\n#endif\n"
      "void main() { o = vec4(PATH); }\n";
  auto with = [&](std::optional<std::vector<std::string>> extensions) {
    InstrumentRequest request{{source}, Stage::fragment, 1};
    request.driver_extensions = std::move(extensions);
    const auto r = instrument_shader(request);
    INFO(r.error);
    REQUIRE(r.ok);
    return r.instrumented_source;
  };
  // glslang's own view: it knows fp64, not the imaginary extension
  CHECK(with(std::nullopt).find("vec4(4.0)") != std::string::npos);
  CHECK(with(std::vector<std::string>{"GL_NV_glbudget_imaginary", "GL_ARB_gpu_shader_fp64"}).find("vec4(2.0)") !=
        std::string::npos);
  CHECK(with(std::vector<std::string>{"GL_NV_glbudget_imaginary"}).find("vec4(3.0)") != std::string::npos);
  CHECK(with(std::vector<std::string>{}).find("vec4(4.0)") != std::string::npos);
  // the rewrite keeps the lines: main stays on line 10
  const std::string out = with(std::vector<std::string>{});
  CHECK(out.find("#line 2\n") != std::string::npos);
  const std::size_t after_line = out.find("#line 2\n") + 8;
  CHECK(std::count(out.begin() + static_cast<std::ptrdiff_t>(after_line),
                   out.begin() + static_cast<std::ptrdiff_t>(out.find("void main")), '\n') == 8);
}

TEST_CASE("truncated and mangled shaders fail cleanly, never crash", "[instrument]") {
  // The shim runs inside the app: whatever the app passes must give a result, not a crash.
  int ok = 0, failed = 0;
  for (const char* file : {"loops.frag", "jumps.frag", "compat.frag"}) {
    const std::string source = shader_file(file);
    for (std::size_t length = 0; length < source.size(); length += 11) {
      for (const std::string& variant :
           {source.substr(0, length), source.substr(0, length) + "}}})){{;", source.substr(length)}) {
        InstrumentResult r;
        REQUIRE_NOTHROW(r = instrument(variant));
        (r.ok ? ok : failed)++;
        if (!r.ok) CHECK_FALSE(r.error.empty());
      }
    }
  }
  INFO(ok << " variants instrumented, " << failed << " refused");
  CHECK(failed > 0);
  CHECK(ok > 0);
}

// --- The app-space rewrite (app_space.hpp) ----------------------------------------------------

namespace {
AppSpaceResult app_space(const std::string& source) { return to_app_space(source, std::nullopt); }
}  // namespace

TEST_CASE("a shader without pixel coordinates is not rewritten", "[app_space]") {
  const AppSpaceResult r = app_space(
      "#version 330\nin vec2 uv; uniform sampler2D t; out vec4 o;\n"
      "void main() { o = texture(t, uv); }\n");
  CHECK_FALSE(r.needed);
  CHECK_FALSE(r.ok);
}

TEST_CASE("gl_FragCoord is read in the app's pixels, its redeclaration kept", "[app_space]") {
  const std::string source =
      "#version 330 core\n#extension GL_ARB_fragment_coord_conventions : enable\n"
      "layout(origin_upper_left) in vec4 gl_FragCoord;\nuniform vec2 u_res; uniform sampler2D t; out vec4 o;\n"
      "#define UV (gl_FragCoord.xy / u_res)\n"
      "void main() {\n  o = texture(t, UV) * gl_FragCoord.z;\n}\n";
  const AppSpaceResult r = app_space(source);
  REQUIRE(r.ok);
  INFO(r.source);
  CHECK(r.frag_coord);
  CHECK(r.samplers.empty());
  CHECK(r.source.find("in vec4 gl_FragCoord;") != std::string::npos);
  CHECK(r.source.find("uniform highp vec2 glbudget_frag_ratio;") != std::string::npos);
  // Each read is rewritten, also one a macro made: UV's and the one for .z.
  std::size_t reads = 0;
  for (std::size_t at = 0; (at = r.source.find("gl_FragCoord.xy * glbudget_frag_ratio", at)) != std::string::npos; ++at)
    ++reads;
  CHECK(reads == 2);
  // The declarations come after the #extension line, and the app's lines keep their numbers.
  CHECK(r.source.find("glbudget_frag_ratio") > r.source.find("#extension"));
  CHECK(r.source.find("#line 3\n") != std::string::npos);
  CHECK(glslang_errors(r.source, Stage::fragment).empty());
}

TEST_CASE("texelFetch and textureSize of uniform 2D samplers take and give the app's texels", "[app_space]") {
  const std::string source =
      "#version 330 core\nuniform sampler2D scene; uniform isampler2D ids; uniform usampler2D mask;\n"
      "uniform sampler2DShadow shadow; uniform sampler3D volume; out vec4 o;\n"
      "void main() {\n"
      "  ivec2 p = ivec2(gl_FragCoord.xy);\n"
      "  vec4 c = texelFetch(scene, p, 0) + texelFetchOffset(scene, p, 0, ivec2(1, 0));\n"
      "  c += vec4(texelFetch(ids, p / 2, 1)) + vec4(texelFetch(mask, textureSize(scene, 0) - 1, 0));\n"
      "  c += vec4(vec2(textureSize(shadow, 0)), vec2(textureSize(volume, 0).xy));\n"
      "  o = c + texelFetch(volume, ivec3(p, 0), 0);\n"
      "}\n";
  const AppSpaceResult r = app_space(source);
  REQUIRE(r.ok);
  INFO(r.source);
  CHECK(r.samplers == std::vector<AppSpaceSampler>{{"ids"}, {"mask"}, {"scene"}, {"shadow"}});  // not the 3D one
  std::string body = r.source.substr(r.source.find("void main"));
  body.erase(std::remove(body.begin(), body.end(), ' '), body.end());
  INFO(body);
  CHECK(body.find("glbudget_texelFetch(scene,p,0,glbudget_size_scene)") != std::string::npos);
  CHECK(body.find("glbudget_texelFetchOffset(scene,p,0,ivec2(1,0),glbudget_size_scene)") != std::string::npos);
  CHECK(
      body.find("glbudget_texelFetch(mask,glbudget_textureSize(scene,0,glbudget_size_scene)-1,0,glbudget_size_mask)") !=
      std::string::npos);
  CHECK(body.find("glbudget_texelFetch(ids,p/2,1,glbudget_size_ids)") != std::string::npos);
  CHECK(body.find("texelFetch(volume,ivec3(") != std::string::npos);
  CHECK(body.find("textureSize(volume,0)") != std::string::npos);
  CHECK(glslang_errors(r.source, Stage::fragment).empty());
}

TEST_CASE("the rewrite compiles in GLSL ES and old desktop GLSL", "[app_space]") {
  const char* sources[] = {
      "#version 100\nprecision mediump float;\nuniform vec2 u_res;\n"
      "void main() { gl_FragColor = vec4(gl_FragCoord.xy / u_res, 0.0, 1.0); }\n",
      "#version 300 es\nprecision mediump float;\nuniform mediump isampler2D ids; uniform sampler2D t; out vec4 o;\n"
      "void main() { o = texelFetch(t, ivec2(gl_FragCoord.xy), 0) + vec4(texelFetch(ids, ivec2(0), 0)); }\n",
      "#version 120\nuniform vec2 u_res;\nvoid main() { gl_FragColor = vec4(gl_FragCoord.xy / u_res, 0.0, 1.0); }\n",
      "varying vec2 v;\nvoid main() { gl_FragColor = vec4(gl_FragCoord.xy * v, 0.0, 1.0); }\n",
  };
  for (const char* source : sources) {
    INFO(source);
    const AppSpaceResult r = app_space(source);
    REQUIRE(r.ok);
    INFO(r.source);
    CHECK(glslang_errors(r.source, Stage::fragment).empty());
  }
}

TEST_CASE("an element of a sampler array reads the size of its own element", "[app_space]") {
  const AppSpaceResult r = app_space(
      "#version 330 core\nconst int N = 3;\nuniform sampler2D layers[N]; uniform sampler2D pair[2]; out vec4 o;\n"
      "void main() { ivec2 p = ivec2(gl_FragCoord.xy);\n"
      "  o = texelFetch(layers[1], p, 0) + texelFetch(pair[N - 2], p, 0) + vec4(textureSize(layers[2], 0), 0, 0); }\n");
  REQUIRE(r.ok);
  INFO(r.source);
  CHECK(r.samplers == std::vector<AppSpaceSampler>{{"layers", true}, {"pair", true}});
  CHECK(r.source.find("uniform sampler2D layers[N]; uniform highp ivec3 glbudget_size_layers[N];") !=
        std::string::npos);
  CHECK(r.source.find("uniform highp ivec3 glbudget_size_pair[2];") != std::string::npos);
  std::string body = r.source.substr(r.source.find("void main"));
  body.erase(std::remove(body.begin(), body.end(), ' '), body.end());
  CHECK(body.find("glbudget_texelFetch(layers[1],p,0,glbudget_size_layers[1])") != std::string::npos);
  CHECK(body.find("glbudget_texelFetch(pair[N-2],p,0,glbudget_size_pair[N-2])") != std::string::npos);
  CHECK(body.find("glbudget_textureSize(layers[2],0,glbudget_size_layers[2])") != std::string::npos);
  CHECK(glslang_errors(r.source, Stage::fragment).empty());
}

TEST_CASE("a sampler known only at run time leaves the shader as it is, saying why", "[app_space]") {
  const char* sources[] = {
      "#version 430\nuniform sampler2D t[2]; out vec4 o;\n"
      "void main() { int i = 0; o = texelFetch(t[i++], ivec2(gl_FragCoord.xy), 0); }\n",
      "#version 430\nuniform sampler2D t[2]; out vec4 o; int n = 0; int next() { return n++; }\n"
      "void main() { o = texelFetch(t[next()], ivec2(gl_FragCoord.xy), 0); }\n",
      "#version 330\nuniform sampler2D t; out vec4 o;\n"
      "vec4 at(sampler2D s, ivec2 p) { return texelFetch(s, p, 0); }\n"
      "void main() { o = at(t, ivec2(gl_FragCoord.xy)); }\n",
  };
  for (const char* source : sources) {
    const AppSpaceResult r = app_space(source);
    CHECK(r.needed);
    CHECK_FALSE(r.ok);
    CHECK(r.unsupported);
    CHECK(r.error.find("not a uniform sampler or an element of one") != std::string::npos);
  }
  const AppSpaceResult broken = app_space("#version 330\nout vec4 o; void main() { o = gl_FragCoord }\n");
  CHECK(broken.needed);
  CHECK_FALSE(broken.ok);
  CHECK_FALSE(broken.unsupported);
  CHECK_FALSE(broken.error.empty());
}
