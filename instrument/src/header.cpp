#include "header.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

namespace glbudget::instrument {

namespace {

using syntax::Directive;

// The line number the driver gives the line starting at `offset`.
long logical_line(std::string_view text, const std::vector<Directive>& directives, std::size_t offset,
                  const LanguageVersion& language) {
  auto physical = [&](std::size_t at) { return 1 + std::count(text.begin(), text.begin() + at, '\n'); };
  long line = physical(offset);
  for (const Directive& d : directives) {
    if (d.name != "line" || d.whole.begin >= offset) continue;
    const std::string body(text.substr(d.whole.begin, d.whole.end - d.whole.begin));
    const long named = std::strtol(body.c_str() + body.find("line") + 4, nullptr, 0);
    const long first_after = line_names_next_line(language) ? named : named + 1;
    line = first_after + (physical(offset) - physical(d.whole.begin) - 1);
  }
  return line;
}

// Offset of the line after a directive (the directive's newline is kept).
std::size_t after(const Directive& d, std::string& text) {
  if (d.whole.end >= text.size()) text += '\n';
  return d.whole.end + 1;
}

std::vector<std::string> extensions_needed(const LanguageVersion& language) {
  if (language.es || language.version >= 430) return {};
  std::vector<std::string> needed{"GL_ARB_shader_storage_buffer_object : require"};
  if (language.version < 140) needed.push_back("GL_ARB_uniform_buffer_object : enable");  // layout()
  if (language.version < 130) needed.push_back("GL_EXT_gpu_shader4 : enable");            // uint
  return needed;
}

std::string declarations(const LanguageVersion& language, Stage stage, int binding, bool with_binding) {
  const std::string p = language.es ? "highp " : "";
  const std::string layout =
      with_binding ? "layout(std430, binding = " + std::to_string(binding) + ")" : "layout(std430)";
  auto word = [&](Quantity q) { return std::to_string(word_index(stage, q)); };
  return layout + " buffer " + kCounterBlockName + " { " + p + "uint glbudget_counter[" +
         std::to_string(kCounterWords) + "]; };\n" + p + "uint " + std::string(kInstructionVariable) + " = 0u;\n" + p +
         "uint " + std::string(kTexelVariable) + " = 0u;\n" + "void glbudget_add64(int low, " + p +
         "uint amount) {\n"
         "    if (amount == 0u) return;  // atomics are the cost of instrumentation\n"
         "    " +
         p +
         "uint before = atomicAdd(glbudget_counter[low], amount);\n"
         "    if (before > 0xFFFFFFFFu - amount) atomicAdd(glbudget_counter[low + 1], 1u);  // carry\n"
         "}\n"
         "void " +
         std::string(kFlushFunction) +
         "() {\n"
         "    glbudget_add64(" +
         word(Quantity::instructions) + ", " + std::string(kInstructionVariable) +
         ");\n"
         "    glbudget_add64(" +
         word(Quantity::texel_accesses) + ", " + std::string(kTexelVariable) +
         ");\n"
         "    glbudget_add64(" +
         word(Quantity::invocations) +
         ", 1u);\n"
         "}\n";
}

}  // namespace

HeaderPoints header_points(std::string& text, const syntax::Unit& unit) {
  const std::size_t first_function = unit.functions.empty() ? text.size() : unit.functions.front().whole.begin;
  const Directive* version = nullptr;
  const Directive* last_extension = nullptr;
  for (const Directive& d : unit.directives) {
    if (d.whole.begin > first_function) break;
    if (d.name == "version") version = &d;
    if (d.name == "extension") last_extension = &d;
  }
  HeaderPoints points;
  points.version = version;
  points.extension = version ? after(*version, text) : 0;
  points.declaration = last_extension ? after(*last_extension, text) : points.extension;
  if (points.declaration > first_function)
    throw std::runtime_error("an #extension directive follows the first function");
  return points;
}

std::string line_fixup(std::string_view text, const syntax::Unit& unit, std::size_t offset,
                       const LanguageVersion& language) {
  const long next = logical_line(text, unit.directives, offset, language);
  return "#line " + std::to_string(line_names_next_line(language) ? next : next - 1) + "\n";
}

HeaderPlan plan_header(std::string& text, const syntax::Unit& unit, const LanguageVersion& language, Stage stage,
                       int binding) {
  if (language.es && language.version < 300)
    throw std::runtime_error("GLSL ES 1.00 has no shader storage buffers to count into");
  HeaderPlan plan;
  plan.binding_in_source = language.es ? language.version >= 300 : language.version >= 420;

  const HeaderPoints points = header_points(text, unit);
  if (language.es && language.version == 300 && points.version) {
    const std::size_t digits = text.find("300", points.version->whole.begin);
    if (digits < points.version->whole.end) text.replace(digits, 3, "310");
  }

  std::string extension_lines;
  for (const std::string& e : extensions_needed(language)) extension_lines += "#extension " + e + "\n";
  const std::string decls = declarations(language, stage, binding, plan.binding_in_source);
  if (points.extension == points.declaration) {
    plan.insertions.push_back(
        {points.extension, extension_lines + decls + line_fixup(text, unit, points.extension, language)});
  } else {
    if (!extension_lines.empty())
      plan.insertions.push_back(
          {points.extension, extension_lines + line_fixup(text, unit, points.extension, language)});
    plan.insertions.push_back({points.declaration, decls + line_fixup(text, unit, points.declaration, language)});
  }
  return plan;
}

}  // namespace glbudget::instrument
