// Same arguments, same frames: in one process (whatever was drawn before) and across runs of
// the demo program.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <unistd.h>

#include "render_fixture.hpp"
#include "scenes/registry.hpp"

TEST_CASE("a frame renders bit-identically when repeated", "[demo][determinism]") {
  demo_test::gl_context();
  const demo::Scene scene = *demo::make_scene("subway", 0.03f);
  demo::Renderer renderer(scene, demo_test::kWidth, demo_test::kHeight);
  const demo::Config config = *demo::parse_config("1,0,1,2,0,1");
  renderer.render(config, 2.5);
  const auto first = renderer.read_pixels();
  renderer.render(demo::Config::cheapest(), 7.0);  // disturb: other sizes, programs, time
  renderer.render(demo::Config::best(), 0.0);
  renderer.render(config, 2.5);
  CHECK(renderer.read_pixels() == first);
  renderer.render(config, 2.6);  // and time does move the scene
  CHECK(renderer.read_pixels() != first);
}

namespace {
std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
}  // namespace

TEST_CASE("two runs of the demo program dump identical images", "[demo][determinism]") {
  const std::filesystem::path program = GLBUDGET_BINARY_DIR "/testapps/demo/demo";
  REQUIRE(std::filesystem::exists(program));
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("demo_determinism_" + std::to_string(::getpid()));
  std::filesystem::remove_all(root);
  for (const char* run : {"a", "b"}) {
    const std::string command = program.string() +
                                " --scene hall --detail 0.02 --width 96 --height 54 --frames 3 --start-frame 10"
                                " --config 0,1,0,1,0,0 --dump " +
                                (root / run).string() + " 2>/dev/null";
    REQUIRE(std::system(command.c_str()) == 0);
  }
  int compared = 0;
  for (const auto& entry : std::filesystem::directory_iterator(root / "a")) {
    const auto twin = root / "b" / entry.path().filename();
    INFO(entry.path().filename().string());
    REQUIRE(std::filesystem::exists(twin));
    CHECK(slurp(entry.path()) == slurp(twin));
    ++compared;
  }
  CHECK(compared == 3);
  CHECK(std::filesystem::exists(root / "a" / "hall_c010100_f00010.png"));
  std::filesystem::remove_all(root);
}

TEST_CASE("--all-configs dumps each configuration's frame as a run at that configuration does", "[demo][determinism]") {
  // The ground truth of the error estimates over the whole space (bench/evaluation/error_estimates.py)
  // comes from one process rendering every configuration in turn: nothing may carry over.
  const std::filesystem::path program = GLBUDGET_BINARY_DIR "/testapps/demo/demo";
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("demo_all_configs_" + std::to_string(::getpid()));
  std::filesystem::remove_all(root);
  const std::string common = program.string() +
                             " --scene subway --detail 0.02 --width 96 --height 54 --start-frame 25"
                             " --shadow-size 512";  // a quarter of its side: half the time
  REQUIRE(std::system((common + " --all-configs --dump " + (root / "all").string() + " 2>/dev/null").c_str()) == 0);
  int files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(root / "all")) ++files;
  CHECK(files == 729);
  // Either side of configurations whose passes leave state behind (the reflections' and the
  // antialiasing's passes switched off, the render scale back up).
  for (const char* config : {"0,1,0,1,0,0", "2,2,2,2,2,2", "1,0,2,0,1,2", "0,0,0,0,0,0"}) {
    const std::string dir = (root / config).string();
    REQUIRE(std::system((common + " --frames 1 --config " + config + " --dump " + dir + " 2>/dev/null").c_str()) == 0);
    std::string name = "subway_c" + std::string(config) + "_f00025.png";
    name.erase(std::remove(name.begin(), name.end(), ','), name.end());
    INFO(name);
    REQUIRE(std::filesystem::exists(root / config / name));
    CHECK(slurp(root / "all" / name) == slurp(root / config / name));
  }
  CHECK(std::system((program.string() + " --all-configs 2>/dev/null").c_str()) != 0);  // no --dump: said, not run
  std::filesystem::remove_all(root);
}

TEST_CASE("a GLX window under Xvfb renders the same frames as EGL surfaceless", "[demo][determinism]") {
  REQUIRE(std::system("command -v xvfb-run >/dev/null") == 0);  // xvfb is in scripts/packages.txt
  const std::filesystem::path program = GLBUDGET_BINARY_DIR "/testapps/demo/demo";
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("demo_glx_" + std::to_string(::getpid()));
  std::filesystem::remove_all(root);
  const std::string args = " --scene valley --detail 0.02 --width 96 --height 54 --frames 2 --start-frame 5 --dump ";
  const std::string egl = program.string() + args + (root / "egl").string() + " 2>/dev/null";
  const std::string glx = "xvfb-run -a -s '-screen 0 320x240x24' " + program.string() + " --glx" + args +
                          (root / "glx").string() + " 2>/dev/null";
  REQUIRE(std::system(egl.c_str()) == 0);
  REQUIRE(std::system(glx.c_str()) == 0);
  for (const char* name : {"valley_c000000_f00005.png", "valley_c000000_f00006.png"}) {
    INFO(name);
    REQUIRE(std::filesystem::exists(root / "glx" / name));
    CHECK(slurp(root / "egl" / name) == slurp(root / "glx" / name));
  }
  std::filesystem::remove_all(root);
}
