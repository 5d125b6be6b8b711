// Integration (issue 12): the default framebuffer scaled from outside, the one knob every app
// has without a manifest (GLBUDGET_FORCE=l picks the built-in render-scale pass's level:
// 100 / 80 / 60 / 50 %). The probes read their window back (glReadPixels of FBO 0): the image
// must be window-sized and look like the unscaled one; programs nobody here wrote run to the end.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "glbudget/quality/luma_image.hpp"
#include "glbudget/quality/ssim.hpp"
#include "probe_expectations.hpp"
#include "xvfb_server.hpp"

namespace {

struct Ppm {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
};

Ppm read_ppm(const std::string& path) {
  Ppm p;
  FILE* f = fopen(path.c_str(), "rb");
  if (!f) return p;
  int max = 0;
  if (fscanf(f, "P6 %d %d %d", &p.width, &p.height, &max) == 3 && fgetc(f) != EOF && max == 255) {
    p.rgb.resize(static_cast<size_t>(p.width) * p.height * 3);
    if (fread(p.rgb.data(), 1, p.rgb.size(), f) != p.rgb.size()) p.rgb.clear();
  }
  fclose(f);
  return p;
}

double ssim_of(const Ppm& a, const Ppm& b) {
  using namespace glbudget::quality;
  const LumaImage la = luma_from_8bit(a.rgb.data(), a.width, a.height, 3);
  const LumaImage lb = luma_from_8bit(b.rgb.data(), b.width, b.height, 3);
  return ssim(la.view(), lb.view());
}

// The probe without the shim, then under it at `level` of the render scale. The shim says
// nothing, or (`said` not empty) one line that holds `said`. Returns the scaled image.
Ppm check_scaled_probe(const std::string& probe, std::vector<std::string> args, const std::string& level,
                       std::map<std::string, std::string> env = {}, const std::string& said = "") {
  const std::string plain_img = temp_path(probe + "_plain.ppm"), shim_img = temp_path(probe + "_scaled.ppm");
  const std::string log = temp_path(probe + "_scaled.csv");
  unlink(log.c_str());
  std::vector<std::string> base = {probe_path(probe), "--frames", "4"};
  base.insert(base.end(), args.begin(), args.end());
  auto plain_args = base, shim_args = base;
  plain_args.insert(plain_args.end(), {"--out", plain_img});
  shim_args.insert(shim_args.end(), {"--out", shim_img});
  const ProcessResult plain = run_process(plain_args, env);
  env["LD_PRELOAD"] = shim_path();
  env["GLBUDGET_LOG"] = log;
  env["GLBUDGET_SENSOR"] = "cpu";
  env["GLBUDGET_FORCE"] = level;
  const ProcessResult shim = run_process(shim_args, env);
  INFO(probe << " at level " << level << "\nshim stderr: " << shim.err);
  REQUIRE(plain.exit_code == 0);
  REQUIRE(shim.exit_code == 0);
  if (said.empty()) {
    CHECK(shim.err.find("glbudget:") == std::string::npos);
  } else {
    CHECK(count_lines_with(shim.err, "glbudget:") == 1);
    CHECK(count_lines_with(shim.err, said) == 1);
  }
  const Ppm a = read_ppm(plain_img), b = read_ppm(shim_img);
  REQUIRE(!a.rgb.empty());
  REQUIRE(b.width == a.width);  // glReadPixels of the window: window-sized, whatever the scale
  REQUIRE(b.height == a.height);
  REQUIRE(!b.rgb.empty());
  const double s = ssim_of(a, b);
  INFO("SSIM " << s);
  CHECK(s >= 0.95);
  CHECK(a.rgb != b.rgb);  // drawn smaller, then stretched: not the same pixels
  const auto rows = read_csv_rows_by_name(log);
  REQUIRE(!rows.empty());
  for (const auto& row : rows) CHECK(row.at("configuration") == level);
  unlink(plain_img.c_str());
  unlink(shim_img.c_str());
  unlink(log.c_str());
  return b;
}

// Quality probes of a multisampled window shown at 60 %: the best stream is drawn with as many
// samples as the window, so the slanted triangle's edges come out antialiased (pixels blended
// between the triangle and what is behind it), as the app draws them into its own window.
void check_probes_of_multisampled_window(const std::string& display) {
  const std::string dir = temp_path("glx_ms_probes"), log = temp_path("glx_ms_probes.csv"),
                    plain_img = temp_path("glx_ms_plain.ppm");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::vector<std::string> args = {
      probe_path("probe_glx"), "--size", "128", "--samples", "4", "--slanted", "1", "--frames", "4"};
  auto plain_args = args;
  plain_args.insert(plain_args.end(), {"--out", plain_img});
  REQUIRE(run_process(plain_args, {{"DISPLAY", display}}).exit_code == 0);
  const ProcessResult r = run_process(args, {{"DISPLAY", display},
                                             {"LD_PRELOAD", shim_path()},
                                             {"GLBUDGET_LOG", log},
                                             {"GLBUDGET_SENSOR", "cpu"},
                                             {"GLBUDGET_FORCE", "2"},
                                             {"GLBUDGET_PROBE_PERIOD", "2"},
                                             {"GLBUDGET_DUMP_PROBES", dir}});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);  // 4: a GL error reached the app
  CHECK(r.err.find("glbudget:") == std::string::npos);
  int probe_rows = 0;
  for (const auto& row : read_csv_rows_by_name(log))
    if (!row.at("probe_error").empty()) {
      ++probe_rows;
      CHECK(std::stod(row.at("probe_error")) > 0.005);  // 60 % against the best
    }
  CHECK(probe_rows > 0);
  Ppm best = read_ppm(dir + "/probe_c0_f4_s1_0.ppm"), plain = read_ppm(plain_img);
  REQUIRE(!best.rgb.empty());
  REQUIRE(best.width == plain.width);
  // The scene's flat colours and the triangle's; anything else is a blend at an edge.
  auto flat = [&](const uint8_t* p) {
    for (size_t i = 0; i + 2 < plain.rgb.size(); i += 3)
      if (plain.rgb[i] == p[0] && plain.rgb[i + 1] == p[1] && plain.rgb[i + 2] == p[2]) return true;
    return false;
  };
  int blended = 0;
  for (size_t i = 0; i + 2 < best.rgb.size(); i += 3) blended += !flat(&best.rgb[i]);
  INFO("pixels of the best stream's image blended at an edge: " << blended);
  CHECK(blended > 50);
  std::filesystem::remove_all(dir);
  for (const std::string& path : {log, plain_img}) unlink(path.c_str());
}

}  // namespace

TEST_CASE("the window at 60 %: probes read back a window-sized image that looks the same", "[integration]") {
  for (const char* probe : {"probe_direct", "probe_getproc", "probe_dlopen", "probe_glew", "probe_compat"})
    check_scaled_probe(probe, {"--size", "128"}, "2");
  check_scaled_probe("probe_getproc", {"--es", "3", "--size", "128"}, "2");
}

// OpenGL ES 2.0 (Mali-400, VideoCore IV, PowerVR SGX) has framebuffer objects but no blits and
// one framebuffer binding: the stand-in's colour is a texture, drawn into the window at each
// swap and into a window-sized copy for glReadPixels. Mesa gives an ES 2.0 context when asked
// for it (MESA_GLES_VERSION_OVERRIDE), without glBlitFramebuffer as such a driver is. The probe
// sets its vertex array, buffer, program and viewport once, so a copy that left any of them
// changed would spoil the frames after the first swap.
TEST_CASE("a GLES 2.0 context, without blits: the window scaled, drawn into the back buffer at the swap",
          "[integration]") {
  const std::map<std::string, std::string> es2 = {{"MESA_GLES_VERSION_OVERRIDE", "2.0"}};
  const std::string said = "this context is OpenGL ES 2.0, without blits: the window's resolution is scaled";
  // Sanitized: one size and one level, the path alike.
  for (const char* size : {"128", "160"}) {
    if (kSanitizedRun && std::string(size) != "128") continue;
    INFO("size " << size);
    const Ppm drawn = check_scaled_probe("probe_getproc", {"--es", "2", "--size", size}, "2", es2, said);
    // The same picture as a GLES 3 context's blit: the copy samples as the blit filters.
    const Ppm blitted = check_scaled_probe("probe_getproc", {"--es", "3", "--size", size}, "2");
    CHECK(drawn.rgb == blitted.rgb);
  }
  if (kSanitizedRun) return;
  for (const char* level : {"1", "3"})
    check_scaled_probe("probe_getproc", {"--es", "2", "--size", "160"}, level, es2, said);
}

// A desktop GL 2.1 context (a driver without GL 3: vc4, lima and i915g give one) has framebuffer
// objects and blits through ARB_framebuffer_object, under the core names: there it is scaled as
// GL 3 is. Without the extension (EXT_framebuffer_object alone) it draws at full size, and says
// so once, so that the log's configuration column is not taken for what drew.
TEST_CASE("a desktop GL 2.1 context: scaled with ARB_framebuffer_object, else drawn at full size and said once",
          "[integration]") {
  check_scaled_probe("probe_compat", {"--size", "128"}, "2", {{"MESA_GL_VERSION_OVERRIDE", "2.1"}});
  check_scaled_probe("probe_compat", {"--size", "128", "--push-attrib", "1", "--frames", "5"}, "2",
                     {{"MESA_GL_VERSION_OVERRIDE", "2.1"}});
  const std::string plain_img = temp_path("gl21_plain.ppm"), shim_img = temp_path("gl21_shim.ppm");
  const std::vector<std::string> args = {probe_path("probe_compat"), "--size", "128", "--frames", "4", "--out"};
  auto plain_args = args, shim_args = args;
  plain_args.push_back(plain_img);
  shim_args.push_back(shim_img);
  REQUIRE(run_process(plain_args, {{"MESA_GL_VERSION_OVERRIDE", "2.1"}}).exit_code == 0);
  const ProcessResult r = run_process(shim_args, {{"MESA_GL_VERSION_OVERRIDE", "2.1"},
                                                  {"LD_PRELOAD", shim_path()},
                                                  {"GLBUDGET_SENSOR", "cpu"},
                                                  {"GLBUDGET_FORCE", "2"},
                                                  {"GLBUDGET_TEST_HIDE_EXTENSIONS", "GL_ARB_framebuffer_object"}});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(count_lines_with(r.err, "glbudget:") == 1);
  CHECK(count_lines_with(r.err,
                         "this context is OpenGL 2.1, without framebuffer objects and blits (GL 3.0 or "
                         "GL_ARB_framebuffer_object): nothing is scaled") == 1);
  const Ppm a = read_ppm(plain_img), b = read_ppm(shim_img);
  REQUIRE(!a.rgb.empty());
  CHECK(a.rgb == b.rgb);
  unlink(plain_img.c_str());
  unlink(shim_img.c_str());
}

// Fixed-function HUDs and SFML's pushGLStates keep the viewport on glPushAttrib's stack, and
// apps save theirs with glGetIntegerv(GL_VIEWPORT) to set it again: both must see the app's
// own box, never the scaled one the driver holds (set again, it would be scaled twice). The
// probe exits 5 when GL_VIEWPORT after a pop is not its own, 4 on a GL error; every other frame
// its push is made before the swap and popped after it, with the window bound after the frame
// drew into it, while the scale switches each frame: the read and draw buffers pushed name the
// window as it was (GL_COLOR_ATTACHMENT0 of the stand-in, popped onto the unscaled window, was
// a GL error; extremetuxracer under a governor hit the reverse, GL_BACK onto the stand-in).
TEST_CASE("an app's viewport across glPushAttrib/glPopAttrib and glGetIntegerv, scaled window", "[integration]") {
  check_scaled_probe("probe_compat", {"--size", "128", "--push-attrib", "1", "--frames", "5"}, "2");
  for (const char* force : {"0;2", "2;0"}) {
    if (kSanitizedRun && std::string(force) != "0;2") continue;
    INFO("GLBUDGET_FORCE=" << force << ", a switch at every frame");
    const ProcessResult r = run_process({probe_path("probe_compat"), "--size", "128", "--push-attrib", "1", "--frames",
                                         "6", "--out", temp_path("push_attrib.ppm")},
                                        {{"LD_PRELOAD", shim_path()},
                                         {"GLBUDGET_SENSOR", "cpu"},
                                         {"GLBUDGET_FORCE", force},
                                         {"GLBUDGET_FORCE_EVERY", "1"},
                                         {"MESA_DEBUG", "1"}});
    INFO(r.err);
    CHECK(r.exit_code == 0);
    CHECK(count_lines_with(r.err, "glbudget:") == 0);
    CHECK(count_lines_with(r.err, "Mesa: User error") == 0);
  }
  unlink(temp_path("push_attrib.ppm").c_str());
}

// glTextureView needs immutable storage, and the scaler makes window-sized glTexStorage2D
// textures mutable so that it can resize them: such a view failed (GL_INVALID_OPERATION) under
// the shim even with nothing scaled. The viewed texture now gets the driver's immutable storage
// back at the app's size, keeps it, and so does its framebuffer; the window still scales.
TEST_CASE("a texture the app views through glTextureView keeps its size and its view works", "[integration]") {
  for (const char* format : {"immutable", "dsa", "mipmapped"}) {
    if (kSanitizedRun && std::string(format) != "mipmapped") continue;  // the one with levels to keep
    INFO("--format " << format);
    check_scaled_probe("probe_offscreen", {"--size", "128", "--format", format, "--view", "1"}, "2", {},
                       "is viewed through glTextureView, which needs immutable storage");
  }
}

// Viewport arrays (GL 4.1): Wine's wined3d sets its viewport and scissor boxes through
// glViewportIndexedf and glScissorIndexed where the driver has them. They scale as glViewport and
// glScissor do (the same pixels at 60 %), and glGetFloati_v answers the app's box (the probe
// exits 5 if not; before, the unscaled viewport drew a corner of the scaled window).
TEST_CASE("viewport arrays scale as glViewport does: glViewportIndexedf, glScissorIndexed", "[integration]") {
  for (const char* twice : {"0", "1"}) {
    if (kSanitizedRun && std::string(twice) != "1") continue;  // the one with scissor boxes
    INFO("--twice " << twice);
    const Ppm indexed =
        check_scaled_probe("probe_offscreen", {"--size", "128", "--viewport-indexed", "1", "--twice", twice}, "2");
    const Ppm plain = check_scaled_probe("probe_offscreen", {"--size", "128", "--twice", twice}, "2");
    CHECK(indexed.rgb == plain.rgb);
  }
}

TEST_CASE("every level of the built-in render scale", "[integration]") {
  for (const char* level : {"1", "2", "3"}) check_scaled_probe("probe_direct", {"--size", "160"}, level);
}

TEST_CASE("the window at 60 % through GLX under Xvfb", "[integration]") {
  const XvfbServer xvfb(100 + (getpid() + 7) % 400, "256x256x24");
  REQUIRE(xvfb.running());
  const std::string display = xvfb.display();
  check_scaled_probe("probe_glx", {"--size", "128"}, "2", {{"DISPLAY", display}});
  // The window's GL_DOUBLEBUFFER is the window's, not the stand-in's (an FBO: 0), or the probe
  // exits 5. A multisampled window (4 samples): its stand-in has as many, the app's GL_SAMPLES
  // query answers them (the probe exits 5 if not, 4 on any GL error), and the swap resolves it.
  check_scaled_probe("probe_glx", {"--size", "128", "--samples", "4"}, "2", {{"DISPLAY", display}});
  check_probes_of_multisampled_window(display);
  // A framebuffer of the app's kept at its size (a manifest whose render scale is the window's
  // alone) blitted from and back to the 4-sample window: the stand-in's rectangle and the app
  // framebuffer's differ in size, which a multisampled framebuffer does not take in a blit;
  // the shim goes through the resolve image (a GL error reached the app before: exit 4).
  const std::string manifest = temp_path("window_only.toml");
  {
    std::ofstream m(manifest);
    m << "[[pass]]\nname = \"resolution\"\n[[pass.level]]\nname = \"100%\"\n[[pass.level]]\nname = \"60%\"\n"
         "scale = 0.6\ntargets = [\"default\"]\n";
  }
  check_scaled_probe("probe_glx", {"--size", "128", "--samples", "4", "--blit-through", "1"}, "1",
                     {{"DISPLAY", display}, {"GLBUDGET_CONFIG", manifest}});
  unlink(manifest.c_str());
}

// Where the configuration can change at run time, the present's stretch is blitted once at the
// first swap, before any switch (blit_warmup.cpp), over a corner of the back buffer whose pixels
// are kept aside and put back: what is swapped must be what the app drew. llvmpipe's GLX keeps
// the back buffer after a swap, so the probe reads what it swapped (--swapped-out). A
// multisampled window is not warmed: it must come out whole too.
TEST_CASE("blits warmed ahead of a switch leave what the window shows as the app drew it", "[integration]") {
  const XvfbServer xvfb(100 + (getpid() + 11) % 400, "256x256x24");
  REQUIRE(xvfb.running());
  for (const char* samples : {"0", "4"}) {
    const std::string plain_img = temp_path("warm_plain.ppm"), shim_img = temp_path("warm_shim.ppm");
    const std::vector<std::string> base = {
        probe_path("probe_glx"), "--size", "128", "--frames", "1", "--samples", samples};
    auto plain_args = base, shim_args = base;
    plain_args.insert(plain_args.end(), {"--swapped-out", plain_img});
    shim_args.insert(shim_args.end(), {"--swapped-out", shim_img});
    const ProcessResult plain = run_process(plain_args, {{"DISPLAY", xvfb.display()}});
    INFO("plain run: " << plain.err);  // once under a parallel CI: exit 2, no stderr kept
    REQUIRE(plain.exit_code == 0);
    // Level 0 (100 %) for the whole run, a switch to 60 % possible: the blits are warmed.
    const ProcessResult r = run_process(shim_args, {{"DISPLAY", xvfb.display()},
                                                    {"LD_PRELOAD", shim_path()},
                                                    {"GLBUDGET_SENSOR", "cpu"},
                                                    {"GLBUDGET_FORCE", "0;2"},
                                                    {"GLBUDGET_FORCE_EVERY", "100"}});
    INFO("samples " << samples << "\n" << r.err);
    REQUIRE(r.exit_code == 0);  // 4: a GL error reached the app
    CHECK(r.err.find("glbudget:") == std::string::npos);
    const Ppm a = read_ppm(plain_img), b = read_ppm(shim_img);
    REQUIRE(!a.rgb.empty());
    CHECK(a.rgb == b.rgb);
    unlink(plain_img.c_str());
    unlink(shim_img.c_str());
  }
}

TEST_CASE("an app's window-sized framebuffers follow the window's scale, smaller ones keep their size",
          "[integration]") {
  // probe_offscreen draws the known scene into a window-sized framebuffer, a quarter-sized
  // copy of it, and composes both into the window: at 60 % the scene and the window are drawn
  // at 60 % (about 0.36 of the fragments), the quarter-sized pass as the app made it. Its
  // textures made by glTexImage2D with a depth-stencil renderbuffer, or all by glTexStorage2D
  // (immutable storage, as GL 4.2+ engines make theirs), or so by name (GL 4.5 direct state
  // access: glTextureStorage2D, glNamedFramebufferTexture, the queries by name), where each
  // must still answer as the app made it (size, immutable format and levels: exit 5 if not), or
  // with the scene's colour a full mip chain of immutable storage that glGenerateMipmap fills, or
  // with the scene drawn into 4-sample textures and resolved by a blit into its texture (the
  // resolve's target, which no draw reaches, is scaled at the blit: a multisampled blit takes
  // rectangles of one size only).
  const std::string format = GENERATE("sized", "immutable", "dsa", "mipmapped", "multisample");
  // Immutable colour of a 16-bit normalised format or an HDR one, too.
  const std::string color = GENERATE("rgba8", "rg16", "r11f_g11f_b10f");
  if (color != "rgba8" && (format != "immutable" || kSanitizedRun)) return;
  INFO("textures: " << format << ", colour " << color);
  const std::string plain_img = temp_path("offscreen_plain.ppm");
  REQUIRE(run_process({probe_path("probe_offscreen"), "--frames", "3", "--size", "128", "--format", format, "--color",
                       color, "--out", plain_img},
                      {})
              .exit_code == 0);
  std::map<std::string, std::map<std::string, double>> fragments;  // level -> pass -> fragments of frame 2
  std::map<std::string, std::string> images;
  for (const std::string level : {"0", "2"}) {
    const std::string log = temp_path("offscreen_" + level + ".csv"), img = temp_path("offscreen_" + level + ".ppm");
    unlink(log.c_str());
    const ProcessResult r = run_process(
        {probe_path("probe_offscreen"), "--frames", "3", "--size", "128", "--format", format, "--color", color, "--out",
         img},
        {{"LD_PRELOAD", shim_path()}, {"GLBUDGET_LOG", log}, {"GLBUDGET_SENSOR", "cpu"}, {"GLBUDGET_FORCE", level}});
    INFO("level " << level << "\n" << r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(r.err.find("glbudget:") == std::string::npos);
    for (const auto& row : read_csv_rows_by_name(log)) {
      CHECK(row.at("configuration") == level);
      // Frame 2: the last frame also copies the window for the app's glReadPixels.
      if (row.at("frame") == "2") fragments[level][row.at("pass")] = std::stod(row.at("fragments"));
    }
    images[level] = img;
    unlink(log.c_str());
  }
  REQUIRE(fragments["0"].size() == 4);
  REQUIRE(fragments["2"].size() == 4);
  int scaled = 0, kept = 0;
  for (const auto& [pass, full] : fragments["0"]) {
    const double ratio = fragments["2"].at(pass) / full;
    INFO("pass " << pass << ": " << full << " fragments at 100 %, ratio " << ratio << " at 60 %");
    if (full <= 32 * 32 * 1.25) {  // the quarter-sized pass: 32 x 32 at 128 x 128
      CHECK(ratio == 1.0);
      ++kept;
    } else {
      CHECK(ratio > 0.3);
      CHECK(ratio < 0.65);  // 0.36 of the area; small quads shade proportionally more helper pixels
      ++scaled;
    }
  }
  CHECK(kept == 1);
  CHECK(scaled == 3);
  const Ppm plain = read_ppm(plain_img), full = read_ppm(images["0"]), small = read_ppm(images["2"]);
  REQUIRE(!plain.rgb.empty());
  CHECK(full.rgb == plain.rgb);  // at 100 % nothing the app draws changes
  REQUIRE(small.width == plain.width);
  REQUIRE(small.height == plain.height);
  CHECK(small.rgb != plain.rgb);
  CHECK(ssim_of(plain, small) >= 0.95);
  for (const std::string& path : {plain_img, images["0"], images["2"]}) unlink(path.c_str());
}

TEST_CASE("a pass that finds its texels from gl_FragCoord sees the app's pixels in scaled targets", "[integration]") {
  // probe_offscreen's compose pass, drawn into the scaled window, finds the scene's and the
  // quarter's texels from gl_FragCoord: divided by the window's size the app set in a uniform,
  // by texelFetch at it, or divided by textureSize. Drawn as written, at 60 % its gl_FragCoord
  // counts the stand-in's pixels: the first puts the image in a corner, the others read the
  // quarter-sized (unscaled) texture at the wrong place (also through a sampler array's
  // elements). Rewritten (manifest
  // shader_coordinates = "app", the default) each looks like the unscaled image; at 100 % it
  // is the unscaled image, bit for bit.
  // Drawn by a program, or by a program pipeline of separable programs; in GLSL 3.30 or in an
  // OpenGL ES 3 context, GLSL ES 3.00.
  const std::string mode = GENERATE("fragcoord", "fetch", "size", "array");
  const std::string pipeline = GENERATE("0", "1");
  const std::string profile = GENERATE("core", "gles3");
  if (profile == "gles3" && pipeline == "1") return;  // the probe's pipeline is desktop GLSL 4.50
  // Drawn once, or in two halves with the textures swapped between the units for the first:
  // each draw takes the sizes of its own textures.
  const std::string twice = GENERATE("0", "1");
  if (twice == "1" && (profile == "gles3" || pipeline == "1")) return;  // enough with a program
  INFO("compose: " << mode << ", pipeline " << pipeline << ", profile " << profile << ", twice " << twice);
  // The probe's command for `frames` frames, its image into the path appended last.
  auto command = [&](const char* frames) {
    return std::vector<std::string>{probe_path("probe_offscreen"),
                                    "--frames",
                                    frames,
                                    "--size",
                                    "128",
                                    "--compose",
                                    mode,
                                    "--pipeline",
                                    pipeline,
                                    "--profile",
                                    profile,
                                    "--twice",
                                    twice,
                                    "--out"};
  };
  const std::vector<std::string> args = command("3");
  const std::string manifest = temp_path("coordinates_scaled.toml");
  {
    std::ofstream m(manifest);
    m << "shader_coordinates = \"scaled\"\n[[pass]]\nname = \"other\"\n";
  }
  std::map<std::string, Ppm> images;
  const std::map<std::string, std::map<std::string, std::string>> runs = {
      {"plain", {}},
      {"100", {{"GLBUDGET_FORCE", "0"}}},
      {"60", {{"GLBUDGET_FORCE", "2"}}},
      {"60 as written", {{"GLBUDGET_FORCE", "2,0"}, {"GLBUDGET_CONFIG", manifest}}}};
  for (const auto& [name, settings] : runs) {
    const std::string img = temp_path("coordinates.ppm");
    std::map<std::string, std::string> env = settings;
    if (name != "plain") {
      env["LD_PRELOAD"] = shim_path();
      env["GLBUDGET_SENSOR"] = "cpu";
    }
    std::vector<std::string> argv = args;
    argv.push_back(img);
    const ProcessResult r = run_process(argv, env);
    INFO(name << "\n" << r.err);
    REQUIRE(r.exit_code == 0);  // 4: a GL error reached the app
    CHECK(r.err.find("glbudget:") == std::string::npos);
    images[name] = read_ppm(img);
    unlink(img.c_str());
  }
  unlink(manifest.c_str());
  const Ppm& plain = images["plain"];
  REQUIRE(!plain.rgb.empty());
  CHECK(images["100"].rgb == plain.rgb);
  REQUIRE(images["60"].width == plain.width);
  const double rewritten = ssim_of(plain, images["60"]), as_written = ssim_of(plain, images["60 as written"]);
  INFO("SSIM at 60 %: " << rewritten << " rewritten, " << as_written << " as written");
  CHECK(rewritten >= 0.95);
  CHECK(as_written < 0.9);

  // Quality probes at 60 %: the best stream draws the pass into its own window-sized shadows,
  // where the pass must see ratio 1 and the scene's shadow at its own size: its image of frame
  // 4 is the unscaled run's frame 4, bit for bit.
  const std::string dir = temp_path("coordinates_probes"), plain4 = temp_path("coordinates_plain4.ppm"),
                    img = temp_path("coordinates_probed.ppm");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::vector<std::string> plain_command = command("4"), probed_command = command("5");
  plain_command.push_back(plain4);
  probed_command.push_back(img);
  REQUIRE(run_process(plain_command, {}).exit_code == 0);
  const ProcessResult probed = run_process(probed_command, {{"LD_PRELOAD", shim_path()},
                                                            {"GLBUDGET_SENSOR", "cpu"},
                                                            {"GLBUDGET_FORCE", "2"},
                                                            {"GLBUDGET_PROBE_PERIOD", "2"},
                                                            {"GLBUDGET_DUMP_PROBES", dir}});
  INFO(probed.err);
  REQUIRE(probed.exit_code == 0);
  const Ppm best = read_ppm(dir + "/probe_c0_f4_s1_0.ppm"), unscaled = read_ppm(plain4);
  REQUIRE(!best.rgb.empty());
  REQUIRE(best.width == unscaled.width);
  const size_t row = static_cast<size_t>(best.width) * 3;  // probe images are stored bottom-up
  bool same = best.rgb.size() == unscaled.rgb.size();
  for (size_t y = 0; same && y < static_cast<size_t>(best.height); ++y)
    same = std::equal(best.rgb.begin() + y * row, best.rgb.begin() + (y + 1) * row,
                      unscaled.rgb.begin() + (best.height - 1 - y) * row);
  CHECK(same);
  std::filesystem::remove_all(dir);
  for (const std::string& path : {plain4, img}) unlink(path.c_str());
}

TEST_CASE("a pass whose texels cannot be followed is said once, when it draws into a scaled target", "[integration]") {
  // The compose pass reads its textures with texelFetch in a function taking the sampler:
  // which texture a parameter is, the rewrite cannot know. At 100 % nothing is said; at 60 %
  // one line.
  for (const std::string level : {"0", "2"}) {
    const std::string img = temp_path("coordinates_array.ppm");
    const ProcessResult r = run_process(
        {probe_path("probe_offscreen"), "--frames", "3", "--size", "64", "--compose", "parameter", "--out", img},
        {{"LD_PRELOAD", shim_path()}, {"GLBUDGET_FORCE", level}});
    INFO(level << "\n" << r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(count_lines_with(r.err, "glbudget:") == (level == "0" ? 0 : 1));
    if (level == "2")
      CHECK(r.err.find("in their pixel coordinates (texelFetch of 's', not a uniform sampler or an element of one)") !=
            std::string::npos);
    unlink(img.c_str());
  }
}

TEST_CASE("an app reading its scaled framebuffer back reads it at its own size: screenshots and picking",
          "[integration]") {
  // probe_offscreen --read-fbo: at the last frame it reads its window-sized scene framebuffer
  // back whole (glReadPixels), one pixel of it under a "cursor" (picking), and the same pixel
  // through glCopyTexSubImage2D. At 60 % the framebuffer is stored scaled; what the app reads
  // must be its own size and place: the whole image like the unscaled one, the picked pixel
  // exactly the unscaled run's (the centre of a flat quad, read through nearest texels).
  std::map<std::string, std::string> picks, copies;
  std::map<std::string, Ppm> images;
  for (const std::string level : {"plain", "2"}) {
    const std::string img = temp_path("readback_" + level + ".ppm"),
                      fbo_img = temp_path("readback_fbo_" + level + ".ppm");
    std::map<std::string, std::string> env;
    if (level != "plain") env = {{"LD_PRELOAD", shim_path()}, {"GLBUDGET_SENSOR", "cpu"}, {"GLBUDGET_FORCE", level}};
    const ProcessResult r = run_process(
        {probe_path("probe_offscreen"), "--frames", "3", "--size", "128", "--out", img, "--read-fbo", fbo_img}, env);
    INFO(level << "\n" << r.err);
    REQUIRE(r.exit_code == 0);  // 4: a GL error reached the app
    CHECK(r.err.find("glbudget:") == std::string::npos);
    std::istringstream out(r.out);
    for (std::string line; std::getline(out, line);) {
      if (line.rfind("pick ", 0) == 0) picks[level] = line.substr(5);
      if (line.rfind("copied ", 0) == 0) copies[level] = line.substr(7);
    }
    images[level] = read_ppm(fbo_img);
    unlink(img.c_str());
    unlink(fbo_img.c_str());
  }
  REQUIRE(!picks["plain"].empty());
  CHECK(picks["2"] == picks["plain"]);
  CHECK(copies["2"] == picks["plain"]);
  CHECK(copies["plain"] == picks["plain"]);
  const Ppm &plain = images["plain"], &scaled = images["2"];
  REQUIRE(!plain.rgb.empty());
  REQUIRE(scaled.width == plain.width);
  REQUIRE(scaled.height == plain.height);
  CHECK(scaled.rgb != plain.rgb);  // drawn at 60 %: not the same pixels
  CHECK(ssim_of(plain, scaled) >= 0.95);
}

namespace {
// A manifest of one pass, the shadow pass (the occluder's fragment shader), at full size or at
// half its render targets' width and height.
std::string shadow_layers_manifest() {
  const std::string path = temp_path("shadow_layers.toml");
  std::ofstream m(path);
  m << "[[pass]]\nname = \"shadow\"\nmatch = { source = \"/* shadow */\" }\n[[pass.level]]\nname = \"full\"\n"
       "[[pass.level]]\nname = \"half\"\nscale = 0.5\ntargets = [\"self\"]\n";
  return path;
}
}  // namespace

TEST_CASE("shadow maps in the layers of an array or the faces of a cube map scale with their pass", "[integration]") {
  // probe_shadow_layers draws an occluder into each cascade of a depth 2D array (or each face of
  // a depth cube map) through one framebuffer re-attached layer by layer, then samples all of
  // them with a shadow sampler. Its manifest's one pass is the shadow pass, with a level at
  // half size ("self"): every layer is stored at 64 x 64 instead of 128 x 128 (a quarter of the
  // shadow fragments), the lit pass is drawn as before, the image keeps its shadows, and the
  // texture answers as the app made it (size, layers, immutable format and levels: exit 5 if
  // not; any GL error: exit 4). Made by glTexImage3D / glTexImage2D per face, by glTexStorage*,
  // or by name (glTextureStorage*, glNamedFramebufferTextureLayer); drawn layer by layer, or
  // attached whole and drawn once, a geometry shader choosing the layer; in a core context, or
  // an OpenGL ES 3 one (GLSL ES 3.00, layer by layer, no direct state access).
  const std::string layout = GENERATE("array", "cube");
  const std::string storage = GENERATE("mutable", "immutable", "dsa");
  const std::string attach = GENERATE("layer", "layered");
  const std::string profile = GENERATE("core", "gles3");
  if (attach == "layered" && storage == "immutable") return;
  if (profile == "gles3" && (attach == "layered" || storage == "dsa")) return;
  if (kSanitizedRun) {  // each kind, storage, attachment and profile once
    const std::string at = layout + "/" + storage + "/" + attach + "/" + profile;
    if (at != "array/mutable/layer/core" && at != "cube/immutable/layer/core" && at != "cube/dsa/layered/core" &&
        at != "array/immutable/layer/gles3")
      return;
  }
  INFO(layout << ", " << storage << ", " << attach << ", " << profile);
  const std::string manifest = shadow_layers_manifest(), plain_img = temp_path("shadow_layers_plain.ppm");
  const std::vector<std::string> args = {probe_path("probe_shadow_layers"),
                                         "--frames",
                                         "3",
                                         "--size",
                                         "96",
                                         "--layout",
                                         layout,
                                         "--storage",
                                         storage,
                                         "--attach",
                                         attach,
                                         "--profile",
                                         profile,
                                         "--out"};
  auto with_out = [&](const std::string& out) {
    auto a = args;
    a.push_back(out);
    return a;
  };
  REQUIRE(run_process(with_out(plain_img), {}).exit_code == 0);
  std::map<std::string, std::map<std::string, double>> fragments;  // configuration -> pass -> of frame 2
  std::map<std::string, Ppm> images;
  for (const std::string config : {"0,0", "0,1"}) {
    const std::string log = temp_path("shadow_layers.csv"), img = temp_path("shadow_layers.ppm");
    unlink(log.c_str());
    const ProcessResult r = run_process(with_out(img), {{"LD_PRELOAD", shim_path()},
                                                        {"GLBUDGET_CONFIG", manifest},
                                                        {"GLBUDGET_FORCE", config},
                                                        {"GLBUDGET_LOG", log},
                                                        {"GLBUDGET_SENSOR", "cpu"}});
    INFO(config << "\n" << r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(r.err.find("glbudget:") == std::string::npos);
    // GLES has no pipeline statistics: its fragments are not measured (empty), its images speak.
    for (const auto& row : read_csv_rows_by_name(log))
      if (row.at("frame") == "2" && profile == "core")
        fragments[config][row.at("pass")] = std::stod(row.at("fragments"));
    images[config] = read_ppm(img);
    unlink(log.c_str());
    unlink(img.c_str());
  }
  REQUIRE(fragments["0,0"].size() == (profile == "core" ? 2 : 0));
  REQUIRE(fragments["0,1"].size() == fragments["0,0"].size());
  int scaled = 0, kept = 0;
  for (const auto& [pass, full] : fragments["0,0"]) {
    const double ratio = fragments["0,1"].at(pass) / full;
    INFO("pass " << pass << ": " << full << " fragments at full size, ratio " << ratio << " at half");
    if (full == 96.0 * 96.0) {  // the lit pass, one fragment per window pixel
      CHECK(ratio == 1.0);
      ++kept;
    } else {
      CHECK(ratio > 0.2);
      CHECK(ratio < 0.32);  // a quarter of the texels; the occluder's edge quads shade helpers
      ++scaled;
    }
  }
  CHECK(kept == scaled);
  CHECK(kept == (profile == "core" ? 1 : 0));
  const Ppm plain = read_ppm(plain_img);
  REQUIRE(!plain.rgb.empty());
  CHECK(images["0,0"].rgb == plain.rgb);  // at full size nothing the app draws changes
  REQUIRE(images["0,1"].width == plain.width);
  CHECK(images["0,1"].rgb != plain.rgb);
  CHECK(ssim_of(plain, images["0,1"]) >= 0.9);
  unlink(plain_img.c_str());
  unlink(manifest.c_str());
}

TEST_CASE("a cached shadow map keeps its contents across switches of its scale at run time", "[integration]") {
  // probe_shadow_layers --static 1 draws its shadow map at the first frame only (static geometry's
  // shadows, cached) and samples it every frame. The configuration switches every two frames,
  // full size to half and back: each switch respecifies every layer or face at the new size and
  // carries its depths over, so the shadows stay (a layer respecified empty would shade every
  // pixel as shadowed).
  const std::string layout = GENERATE("array", "cube");
  INFO(layout);
  const std::string manifest = shadow_layers_manifest(), dir = temp_path("shadow_layers_switch");
  std::filesystem::create_directories(dir);
  auto command = [&](const std::string& each) {
    return std::vector<std::string>{probe_path("probe_shadow_layers"),
                                    "--frames",
                                    "6",
                                    "--size",
                                    "96",
                                    "--layout",
                                    layout,
                                    "--static",
                                    "1",
                                    "--each",
                                    dir + "/" + each,
                                    "--out",
                                    dir + "/" + each + "_last.ppm"};
  };
  REQUIRE(run_process(command("plain"), {}).exit_code == 0);
  const ProcessResult r = run_process(command("shim"), {{"LD_PRELOAD", shim_path()},
                                                        {"GLBUDGET_CONFIG", manifest},
                                                        {"GLBUDGET_FORCE", "0,0;0,1"},
                                                        {"GLBUDGET_FORCE_EVERY", "2"}});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.err.find("glbudget:") == std::string::npos);
  for (int f = 0; f < 6; ++f) {
    const Ppm plain = read_ppm(dir + "/plain" + std::to_string(f) + ".ppm"),
              shim = read_ppm(dir + "/shim" + std::to_string(f) + ".ppm");
    REQUIRE(!plain.rgb.empty());
    REQUIRE(shim.width == plain.width);
    INFO("frame " << f);
    if (f < 2) {
      CHECK(shim.rgb == plain.rgb);  // drawn at full size
    } else {
      // Frames 2-3 read the depths carried down to 64 x 64; frames 4-5 the same carried back up.
      CHECK(shim.rgb != plain.rgb);
      CHECK(ssim_of(plain, shim) >= 0.9);
    }
  }
  std::filesystem::remove_all(dir);
  unlink(manifest.c_str());
}
