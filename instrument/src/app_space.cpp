// to_app_space(): preprocess, find the uniform 2D samplers and the calls and gl_FragCoord reads
// by their tokens (the text is preprocessed: no macros hide them), edit those, and declare
// what the edits use after the app's #version/#extension lines.
#include "glbudget/instrument/app_space.hpp"

#include "driver_macros.hpp"
#include "glslang_front.hpp"
#include "header.hpp"
#include "rewrite.hpp"
#include "syntax.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <string_view>

namespace glbudget::instrument {

namespace {

struct Token {
  std::size_t begin = 0, end = 0;
  std::string_view text;
  bool identifier = false;
};

bool identifier_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool identifier_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// Tokens outside comments and directive lines; punctuation one character each.
std::vector<Token> tokenize(std::string_view text) {
  std::vector<Token> tokens;
  bool line_start = true;
  for (std::size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (c == '\n') {
      line_start = true;
      ++i;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (c == '#' && line_start) {
      while (i < text.size() && text[i] != '\n') ++i;  // directives are the header's business
    } else if (text.compare(i, 2, "//") == 0) {
      while (i < text.size() && text[i] != '\n') ++i;
    } else if (text.compare(i, 2, "/*") == 0) {
      const std::size_t end = text.find("*/", i + 2);
      i = end == std::string_view::npos ? text.size() : end + 2;
    } else if (identifier_start(c)) {
      std::size_t j = i;
      while (j < text.size() && identifier_char(text[j])) ++j;
      tokens.push_back({i, j, text.substr(i, j - i), true});
      i = j;
      line_start = false;
    } else if (std::isdigit(static_cast<unsigned char>(c)) ||
               (c == '.' && i + 1 < text.size() && std::isdigit(static_cast<unsigned char>(text[i + 1])))) {
      std::size_t j = i;
      while (j < text.size() && (identifier_char(text[j]) || text[j] == '.')) ++j;
      tokens.push_back({i, j, text.substr(i, j - i), false});
      i = j;
      line_start = false;
    } else {
      tokens.push_back({i, i + 1, text.substr(i, 1), false});
      ++i;
      line_start = false;
    }
  }
  return tokens;
}

// The 2D sampler types glbudget stores at other sizes, and what texelFetch of them returns.
const std::map<std::string_view, std::string_view>& scalable_samplers() {
  static const std::map<std::string_view, std::string_view> types{
      {"sampler2D", "vec4"}, {"isampler2D", "ivec4"}, {"usampler2D", "uvec4"}, {"sampler2DShadow", ""}};
  return types;
}

bool is_sampler_type(std::string_view t) {
  return t.find("sampler") != std::string_view::npos || t.find("image") != std::string_view::npos;
}

struct UniformSampler {
  std::string_view type;
  bool array = false;
  std::string size;              // an array's size, as declared
  std::size_t declared_end = 0;  // after the `;` of its declaration
  bool typed_array = false;      // `sampler2D[2] t`: not followed
};

// The text from token `first` to the end of token `last - 1`.
std::string_view text_of(const std::vector<Token>& t, std::size_t first, std::size_t last) {
  return std::string_view(t[first].text.data(), t[last - 1].end - t[first].begin);
}

// Uniform declarations of opaque types at global scope: name -> type.
std::map<std::string_view, UniformSampler> uniform_samplers(const std::vector<Token>& t) {
  std::map<std::string_view, UniformSampler> out;
  int braces = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i].text == "{") ++braces;
    if (t[i].text == "}") --braces;
    if (braces != 0 || t[i].text != "uniform") continue;
    std::string_view type;
    int nesting = 0;
    std::size_t j = i + 1;
    for (; j < t.size() && !(nesting == 0 && t[j].text == ";"); ++j) {
      const std::string_view x = t[j].text;
      if (x == "(" || x == "[" || x == "{") ++nesting;
      if (x == ")" || x == "]" || x == "}") --nesting;
      if (nesting != 0 || !t[j].identifier) continue;
      if (type.empty()) {
        if (is_sampler_type(x)) type = x;
        continue;
      }
      UniformSampler u;
      u.type = type;
      u.typed_array = t[j - 1].text == "]";
      if (j + 1 < t.size() && t[j + 1].text == "[") {
        u.array = true;
        std::size_t close = j + 1;
        while (close < t.size() && t[close].text != "]") ++close;
        if (close < t.size() && close > j + 2) u.size = std::string(text_of(t, j + 2, close));
      }
      out[x] = u;
    }
    if (j < t.size())
      for (auto& [name, u] : out)
        if (u.declared_end == 0) u.declared_end = t[j].end;
    i = j;
  }
  return out;
}

// The arguments of the call whose `(` is token `open`: [first, last) token ranges; `close`
// gets the index of the matching `)`.
std::vector<std::pair<std::size_t, std::size_t>> call_arguments(const std::vector<Token>& t, std::size_t open,
                                                                std::size_t* close) {
  std::vector<std::pair<std::size_t, std::size_t>> args;
  int depth = 0;
  std::size_t start = open + 1;
  for (std::size_t j = open; j < t.size(); ++j) {
    const std::string_view x = t[j].text;
    if (x == "(" || x == "[" || x == "{") ++depth;
    if (x == ")" || x == "]" || x == "}") --depth;
    if (depth == 1 && x == ",") {
      args.emplace_back(start, j);
      start = j + 1;
    }
    if (depth == 0) {
      if (j > start) args.emplace_back(start, j);
      *close = j;
      return args;
    }
  }
  throw std::runtime_error("a call is not closed");
}

struct Edit {
  std::size_t begin = 0, end = 0;  // replaced range
  std::string text;
};

std::string declarations(const LanguageVersion& language, bool frag_coord,
                         const std::map<std::string, std::string_view>& used,
                         const std::map<std::string, std::string>& array_size) {
  std::string out;
  if (frag_coord) {
    if (language.es && language.version < 300)
      out += std::string("#ifdef GL_FRAGMENT_PRECISION_HIGH\nuniform highp vec2 ") + kFragRatioUniform +
             ";\n#else\nuniform mediump vec2 " + kFragRatioUniform + ";\n#endif\n";
    else
      out += std::string("uniform ") + (language.es || language.version >= 130 ? "highp " : "") + "vec2 " +
             kFragRatioUniform + ";\n";
  }
  if (used.empty()) return out;
  // texelFetch and textureSize need GLSL 1.30 or ES 3.00, which have precision qualifiers.
  // An array's sizes are declared after it (its size may name a constant declared before it).
  for (const auto& [name, type] : used)
    if (!array_size.count(name)) out += std::string("uniform highp ivec3 ") + kSamplerSizePrefix + name + ";\n";
  out +=
      "highp ivec2 glbudget_app_size(highp ivec2 stored, highp ivec3 app, int lod) {\n"
      "  return app.z == 0 ? stored : max(ivec2(1), app.xy >> lod);\n"
      "}\n"
      "highp ivec2 glbudget_stored_texel(highp ivec2 p, highp ivec2 stored, highp ivec3 app, int lod) {\n"
      "  if (app.z == 0) return p;\n"
      "  highp vec2 size = vec2(max(ivec2(1), app.xy >> lod));\n"
      "  return ivec2(floor((vec2(p) + 0.5) * vec2(stored) / size));\n"
      "}\n";
  std::map<std::string_view, bool> types;
  for (const auto& [name, type] : used) types[type] = true;
  for (const auto& [type, unused] : types) {
    const std::string s(type);
    out += "highp ivec2 glbudget_textureSize(highp " + s + " s, int lod, highp ivec3 app) {\n" +
           "  return glbudget_app_size(textureSize(s, lod), app, lod);\n}\n";
    const std::string_view texel = scalable_samplers().at(type);
    if (texel.empty()) continue;  // shadow samplers take no texelFetch
    const std::string r(texel);
    out += "highp " + r + " glbudget_texelFetch(highp " + s + " s, highp ivec2 p, int lod, highp ivec3 app) {\n" +
           "  return texelFetch(s, glbudget_stored_texel(p, textureSize(s, lod), app, lod), lod);\n}\n" + "highp " + r +
           " glbudget_texelFetchOffset(highp " + s +
           " s, highp ivec2 p, int lod, highp ivec2 offset, highp ivec3 app) {\n" +
           "  return glbudget_texelFetch(s, p + offset, lod, app);\n}\n";
  }
  return out;
}

// An argument `name[i]` (tokens [first, last)): true, with "[i]" in `index`, when the brackets
// close at its end and `i` changes nothing (it is written twice: for the sampler and its size).
bool element_index(const std::vector<Token>& t, std::size_t first, std::size_t last, std::string* index) {
  if (last - first < 4 || t[first + 1].text != "[" || t[last - 1].text != "]") return false;
  int depth = 0;
  for (std::size_t k = first + 1; k < last; ++k) {
    const std::string_view x = t[k].text;
    if (x == "[") ++depth;
    if (x == "]" && --depth == 0 && k + 1 != last) return false;
    if (x == "=" || x == "(") return false;  // an assignment, or a call that may have effects
    if ((x == "+" || x == "-") && t[k + 1].text == x && t[k + 1].begin == t[k].end) return false;  // ++, --
  }
  *index = "[" + std::string(text_of(t, first + 2, last - 1)) + "]";
  return true;
}

// `#version 300 es`, `#version 330 core`; 110 without one.
LanguageVersion language_of(std::string_view text, const syntax::Unit& unit) {
  for (const syntax::Directive& d : unit.directives) {
    if (d.name != "version") continue;
    const std::string_view line = text.substr(d.whole.begin, d.whole.end - d.whole.begin);
    return version_directive_language(line.substr(line.find("version") + 7));
  }
  return {};
}

}  // namespace

AppSpaceResult to_app_space(const std::string& app_source,
                            const std::optional<std::vector<std::string>>& driver_extensions) {
  AppSpaceResult result;
  if (app_source.find("gl_FragCoord") == std::string::npos && app_source.find("texelFetch") == std::string::npos &&
      app_source.find("textureSize") == std::string::npos)
    return result;

  std::string source = app_source;
  std::string preamble;
  if (driver_extensions) {
    DriverMacroSource driver = with_driver_extension_macros(source, *driver_extensions);
    source = std::move(driver.source);
    preamble = std::move(driver.preamble);
  }
  Preprocessed pre = preprocess(source, Stage::fragment, preamble);
  if (!pre.ok) {
    result.needed = true;
    result.error = "glslang cannot preprocess the shader: " + pre.error;
    return result;
  }
  std::string text = std::move(pre.text);
  try {
    const std::vector<Token> t = tokenize(text);
    const auto samplers = uniform_samplers(t);
    std::vector<Edit> edits;
    std::map<std::string, std::string_view> used;   // sampler name -> type (a static string)
    std::map<std::string, std::string> array_size;  // of the arrays among them
    for (std::size_t i = 0; i < t.size(); ++i) {
      if (!t[i].identifier) continue;
      const std::string_view x = t[i].text;
      if (x == "gl_FragCoord") {
        if (i > 0 && t[i - 1].text == "vec4") continue;  // its redeclaration (layout(origin_upper_left) ...)
        edits.push_back(
            {t[i].begin, t[i].end, std::string("vec4(gl_FragCoord.xy * ") + kFragRatioUniform + ", gl_FragCoord.zw)"});
        result.frag_coord = true;
        continue;
      }
      if (x != "texelFetch" && x != "texelFetchOffset" && x != "textureSize") continue;
      if (i + 1 >= t.size() || t[i + 1].text != "(") continue;
      std::size_t close = 0;
      const auto args = call_arguments(t, i + 1, &close);
      if (args.empty()) continue;
      const auto [first, last] = args[0];
      auto declared = t[first].identifier ? samplers.find(t[first].text) : samplers.end();
      std::string index;  // "[i]" of an array's element
      bool followed = declared != samplers.end() && !declared->second.typed_array;
      if (followed && declared->second.array) {
        followed = !declared->second.size.empty() && element_index(t, first, last, &index);
      } else if (followed) {
        followed = last - first == 1;
      }
      if (!followed) {
        // Which texture this reads is known only at run time, and then not here.
        result.needed = true;
        result.unsupported = true;
        result.error = std::string(x) + " of '" + std::string(text_of(t, first, last)) +
                       "', not a uniform sampler or an element of one";
        return result;
      }
      if (!scalable_samplers().count(declared->second.type)) continue;  // never stored at another size
      if (x == "textureSize" && args.size() != 2) continue;
      const std::string name(declared->first);
      used[name] = scalable_samplers().find(declared->second.type)->first;
      if (declared->second.array && array_size.emplace(name, declared->second.size).second)
        edits.push_back(
            {declared->second.declared_end, declared->second.declared_end,
             std::string(" uniform highp ivec3 ") + kSamplerSizePrefix + name + "[" + declared->second.size + "];"});
      edits.push_back({t[i].begin, t[i].end, "glbudget_" + std::string(x)});
      edits.push_back({t[close].begin, t[close].begin, ", " + std::string(kSamplerSizePrefix) + name + index});
    }
    if (edits.empty()) return result;
    result.needed = true;
    const syntax::Unit unit = syntax::parse(text);
    // The driver judges the result; glslang's parser lacks some of what drivers take
    // (subroutines), so the language is read from #version alone.
    const LanguageVersion language = language_of(text, unit);
    const HeaderPoints points = header_points(text, unit);
    for (const Edit& e : edits)
      if (e.begin < points.declaration) throw std::runtime_error("a declaration glbudget edits precedes an #extension");
    std::vector<Insertion> insertions;
    insertions.push_back({points.declaration, declarations(language, result.frag_coord, used, array_size) +
                                                  line_fixup(text, unit, points.declaration, language)});
    // Edits back to front keep the offsets before them valid; the declarations go before all.
    std::sort(edits.begin(), edits.end(), [](const Edit& a, const Edit& b) { return a.begin > b.begin; });
    for (const Edit& e : edits) text.replace(e.begin, e.end - e.begin, e.text);
    result.source = apply_insertions(text, std::move(insertions));
    for (const auto& [name, type] : used) result.samplers.push_back({name, array_size.count(name) > 0});
    result.ok = true;
  } catch (const std::exception& e) {
    result.needed = true;
    result.error = e.what();
  }
  return result;
}

}  // namespace glbudget::instrument
