// GLBUDGET_DUMP files: names, JSON content, failures reported as one line.
#include "glbudget/instrument/dump.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>
#include <unistd.h>

using namespace glbudget::instrument;
namespace fs = std::filesystem;

namespace {

fs::path fresh_dir() {
  const fs::path dir = fs::temp_directory_path() / ("glbudget-dump-test-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

std::string read(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST_CASE("a shader and its program are dumped with their figures", "[dump]") {
  const fs::path dir = fresh_dir();
  const std::string source = "#version 330\nout vec4 o;\nvoid main() { o = vec4(1.0); }\n";
  ShaderDump shader{"00000000000000aa", Stage::fragment, source, instrument_shader({{source}, Stage::fragment, 5})};
  REQUIRE(shader.instrumentation.ok);
  REQUIRE(write_shader_dump(dir, shader).empty());
  CHECK(read(dir / "shader-00000000000000aa.fragment.glsl") == source);
  CHECK(read(dir / "shader-00000000000000aa.fragment.instrumented.glsl") == shader.instrumentation.instrumented_source);
  const auto sj = nlohmann::json::parse(read(dir / "shader-00000000000000aa.fragment.json"));
  CHECK(sj["instrumented"] == true);
  CHECK(sj["static"]["instructions"] == 1);
  CHECK(sj["static"]["blocks"] == 1);

  ProgramDump program{"0123456789abcdef",
                      {{Stage::fragment, shader.hash, shader.instrumentation.figures, averages({30, 4, 4})},
                       {Stage::vertex, "00000000000000bb", std::nullopt, std::nullopt}}};
  REQUIRE(write_program_dump(dir, program).empty());
  REQUIRE(write_index(dir, {program}).empty());
  const auto pj = nlohmann::json::parse(read(dir / "program-0123456789abcdef.json"));
  CHECK(pj["stages"][0]["measured"]["instructions_per_invocation"] == 7.5);
  CHECK(pj["stages"][0]["measured"]["texel_accesses_per_invocation"] == 1.0);
  CHECK(pj["stages"][0]["measured"]["invocations"] == 4);
  CHECK(pj["stages"][1]["measured"].is_null());
  const auto ij = nlohmann::json::parse(read(dir / "index.json"));
  CHECK(ij["programs"][0]["hash"] == "0123456789abcdef");
  CHECK(ij["programs"][0]["shaders"][1]["stage"] == "vertex");
  for (const auto& entry : fs::directory_iterator(dir))
    CHECK(entry.path().filename().string().front() != '.');  // no temporary left behind
  fs::remove_all(dir);
}

TEST_CASE("a failed instrumentation is dumped with its reason", "[dump]") {
  const fs::path dir = fresh_dir();
  const std::string source = "#version 100\nvoid main() { gl_FragColor = vec4(1.0); }\n";
  ShaderDump shader{"00000000000000cc", Stage::fragment, source, instrument_shader({{source}, Stage::fragment, 5})};
  REQUIRE(write_shader_dump(dir, shader).empty());
  CHECK_FALSE(fs::exists(dir / "shader-00000000000000cc.fragment.instrumented.glsl"));
  const auto sj = nlohmann::json::parse(read(dir / "shader-00000000000000cc.fragment.json"));
  CHECK(sj["instrumented"] == false);
  CHECK(sj["error"].get<std::string>().find("storage buffers") != std::string::npos);
  const auto pj =
      nlohmann::json::parse(program_json({"ff", {{Stage::fragment, "cc", std::nullopt, averages({0, 0, 0})}}}));
  CHECK(pj["stages"][0]["measured"]["instructions_per_invocation"].is_null());
  fs::remove_all(dir);
}

TEST_CASE("an unwritable dump directory is reported, not thrown", "[dump]") {
  const fs::path file = fresh_dir();
  std::ofstream(file) << "not a directory";
  const std::string error = write_index(file / "sub", {});
  CHECK_FALSE(error.empty());
  CHECK(error.find('\n') == std::string::npos);
  fs::remove(file);
}
