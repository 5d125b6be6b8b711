#include "glslang_front.hpp"

// ShaderLang.h must come before glslang's internal headers.
#include <glslang/Public/ShaderLang.h>
#include <glslang/Public/ResourceLimits.h>
#include <glslang/MachineIndependent/localintermediate.h>

#include <mutex>
#include <sstream>

namespace glbudget::instrument {

namespace {

constexpr int kDefaultVersion = 110;  // GLSL without #version

void initialise_glslang_once() {
  // glslang keeps process-wide tables; they stay until exit (the shim may use them
  // from any thread at any time).
  static std::once_flag once;
  std::call_once(once, [] { glslang::InitializeProcess(); });
}

EShLanguage to_glslang(Stage stage) {
  switch (stage) {
    case Stage::vertex:
      return EShLangVertex;
    case Stage::tess_control:
      return EShLangTessControl;
    case Stage::tess_evaluation:
      return EShLangTessEvaluation;
    case Stage::geometry:
      return EShLangGeometry;
    case Stage::fragment:
      return EShLangFragment;
    case Stage::compute:
      return EShLangCompute;
  }
  return EShLangFragment;
}

// The first "ERROR:" line of a glslang info log, without its prefix.
std::string first_error(const char* log) {
  std::istringstream lines(log ? log : "");
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("ERROR: ", 0) == 0) return line.substr(7);
  }
  return "glslang rejected the shader";
}

}  // namespace

Preprocessed preprocess(const std::string& source, Stage stage, const std::string& preamble) {
  initialise_glslang_once();
  glslang::TShader shader(to_glslang(stage));
  const char* text = source.c_str();
  shader.setStrings(&text, 1);
  shader.setPreamble(preamble.c_str());
  glslang::TShader::ForbidIncluder no_includes;
  Preprocessed result;
  result.ok = shader.preprocess(GetDefaultResources(), kDefaultVersion, ENoProfile, false, false, EShMsgDefault,
                                &result.text, no_includes);
  if (!result.ok) result.error = first_error(shader.getInfoLog());
  return result;
}

Parsed parse_for_census(const std::string& text, Stage stage) {
  initialise_glslang_once();
  glslang::TShader shader(to_glslang(stage));
  const char* source = text.c_str();
  shader.setStrings(&source, 1);
  Parsed result;
  result.ok = shader.parse(GetDefaultResources(), kDefaultVersion, false, EShMsgDefault);
  if (!result.ok) {
    result.error = first_error(shader.getInfoLog());
    return result;
  }
  const glslang::TIntermediate& ast = *shader.getIntermediate();
  result.language.version = ast.getVersion();
  result.language.es = ast.getProfile() == EEsProfile;
  result.language.compatibility =
      ast.getProfile() == ECompatibilityProfile || (!result.language.es && ast.getVersion() < 150);
  if (ast.getTreeRoot()) result.nodes = census(*ast.getTreeRoot());
  return result;
}

}  // namespace glbudget::instrument
