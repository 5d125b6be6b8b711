// instrument_shader(): preprocess → census of the AST → statement structure → insertions.
#include "glbudget/instrument/instrument.hpp"

#include "driver_macros.hpp"
#include "glslang_front.hpp"
#include "header.hpp"
#include "rewrite.hpp"
#include "syntax.hpp"

#include <stdexcept>

namespace glbudget::instrument {

namespace {

// A copy of preprocessed text whose #line directives are spaces, so that glslang reports
// physical lines (offsets and columns are unchanged).
std::string without_line_directives(std::string text, const syntax::Unit& unit) {
  for (const syntax::Directive& d : unit.directives)
    if (d.name == "line") text.replace(d.whole.begin, d.whole.end - d.whole.begin, d.whole.end - d.whole.begin, ' ');
  return text;
}

}  // namespace

const char* stage_name(Stage stage) {
  switch (stage) {
    case Stage::vertex:
      return "vertex";
    case Stage::tess_control:
      return "tess_control";
    case Stage::tess_evaluation:
      return "tess_evaluation";
    case Stage::geometry:
      return "geometry";
    case Stage::fragment:
      return "fragment";
    case Stage::compute:
      return "compute";
  }
  return "unknown";
}

InstrumentResult instrument_shader(const InstrumentRequest& request) {
  InstrumentResult result;
  std::string source;  // GL concatenates the strings of glShaderSource; so do we
  for (const std::string& s : request.sources) source += s;

  std::string preamble;
  if (request.driver_extensions) {
    DriverMacroSource driver = with_driver_extension_macros(source, *request.driver_extensions);
    source = std::move(driver.source);
    preamble = std::move(driver.preamble);
  }
  Preprocessed pre = preprocess(source, request.stage, preamble);
  if (!pre.ok) {
    result.error = "glslang cannot preprocess the shader: " + pre.error;
    return result;
  }
  try {
    syntax::Unit unit = syntax::parse(pre.text);
    const Parsed parsed = parse_for_census(without_line_directives(pre.text, unit), request.stage);
    if (!parsed.ok) {
      result.error = "glslang cannot parse the shader: " + parsed.error;
      return result;
    }
    BodyPlan body = plan_body(pre.text, unit, parsed.nodes);
    result.figures = body.figures;
    HeaderPlan header = plan_header(pre.text, unit, parsed.language, request.stage, request.ssbo_binding);
    std::vector<Insertion> insertions = std::move(header.insertions);
    insertions.insert(insertions.end(), body.insertions.begin(), body.insertions.end());
    result.instrumented_source = apply_insertions(pre.text, std::move(insertions));
    result.binding_in_source = header.binding_in_source;
    result.ok = true;
  } catch (const std::exception& e) {
    result.error = e.what();
  }
  return result;
}

}  // namespace glbudget::instrument
