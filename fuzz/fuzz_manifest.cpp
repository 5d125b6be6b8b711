// Fuzz target: the variant manifest parser (GLBUDGET_CONFIG), TOML text in, Manifest out,
// then what the shim does with it (the built-in resolution pass, GLBUDGET_FORCE of its levels).
// Input: the manifest's text. It is parsed as the file DIR/glbudget.toml, DIR a directory of the
// temp dir holding a few shader files, so `replace = { fragment = "a.frag" }` reads one. So that
// no input can name a file outside DIR, each '/' becomes '|', and the escapes \u002F and
// \U0000002f (any case) become \u0021 and \U00000021, before parsing.
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include <unistd.h>

#include "glbudget/manifest/manifest.hpp"

namespace {

namespace fs = std::filesystem;
namespace manifest = glbudget::manifest;

// DIR: one per user, reused by every run (a fuzzer may end without running atexit handlers).
const std::string& manifest_path() {
  static const std::string path = [] {
    const fs::path dir = fs::temp_directory_path() / ("glbudget-fuzz-manifest-" + std::to_string(getuid()));
    fs::create_directories(dir);
    const std::pair<const char*, const char*> files[] = {
        {"a.frag", "#version 330 core\nout vec4 c;\nvoid main() { c = vec4(1.0); }\n"},
        {"b.vert", "#version 330 core\nvoid main() { gl_Position = vec4(0.0); }\n"},
        {"empty.frag", ""},
    };
    for (const auto& [name, text] : files) std::ofstream(dir / name) << text;
    fs::create_directory(dir / "sub");
    return (dir / "glbudget.toml").string();
  }();
  return path;
}

// No '/' left, literal or escaped: every `replace` file is DIR/NAME, in DIR or absent.
std::string confined(std::string text) {
  for (char& c : text) {
    if (c == '/') c = '|';
  }
  for (std::size_t at = text.find("002"); at != std::string::npos; at = text.find("002", at + 1)) {
    if (at + 3 < text.size() && (text[at + 3] == 'f' || text[at + 3] == 'F')) text[at + 3] = '1';
  }
  return text;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = confined(std::string(reinterpret_cast<const char*>(data), size));
  manifest::LoadResult result = manifest::parse_manifest(text, manifest_path());
  if (!result.manifest) return 0;
  const manifest::Manifest applied = manifest::with_resolution_pass(std::move(result.manifest));
  std::string levels, error;
  for (const manifest::Pass& pass : applied.passes)
    levels += (levels.empty() ? "" : ",") + std::to_string(pass.levels.size() - 1);
  // Every pass has a level, and its last one can be forced.
  if (!manifest::parse_force(levels, applied, &error)) std::abort();
  return 0;
}
