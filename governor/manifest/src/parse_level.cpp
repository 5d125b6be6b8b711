#include <cmath>
#include <functional>

#include "parsed.hpp"
#include "values.hpp"

namespace glbudget::manifest::detail {
namespace {

using Fail = std::function<void(const toml::node&, const std::string&)>;

void parse_defines(const toml::node& node, Level& level, const Fail& fail) {
  const toml::table* table = node.as_table();
  if (!table) return fail(node, "defines must be a table of NAME = value");
  for (const auto& [key, value] : in_file_order(*table)) {
    const std::string name(key->str());
    if (!is_identifier(name)) {
      fail(*value, "define name '" + name + "' is not a GLSL identifier");
    } else if (const auto text = define_text(*value)) {
      level.defines.emplace_back(name, *text);
    } else {
      fail(*value, "define '" + name + "' must be a one-line string, an integer, a finite float or a bool");
    }
  }
}

void parse_replace(Reader& reader, const toml::node& node, Level& level, const Fail& fail) {
  const toml::table* table = node.as_table();
  if (!table) return fail(node, "replace must be a table of stage = \"file\"");
  for (const auto& [key, value] : in_file_order(*table)) {
    const std::string name(key->str());
    const std::optional<Stage> stage = parse_stage(name);
    if (!stage) {
      fail(*value, "unknown stage '" + name +
                       "' in replace (expected vertex, tess_control, tess_evaluation, geometry, fragment or "
                       "compute)");
      continue;
    }
    const auto* file = value->as_string();
    if (!file || file->get().empty()) {
      fail(*value, "replace " + name + " must be a file name");
      continue;
    }
    const std::filesystem::path path = (reader.directory() / file->get()).lexically_normal();
    std::string source, why;
    if (!read_text_file(path, &source, &why)) {
      fail(*value, "cannot read replace file '" + path.string() + "': " + why);
      continue;
    }
    level.replace[*stage] = path.string();
    level.replace_source[*stage] = std::move(source);
  }
}

void parse_uniforms(const toml::node& node, Level& level, const Fail& fail) {
  const toml::table* table = node.as_table();
  if (!table) return fail(node, "uniforms must be a table of name = value");
  for (const auto& [key, value] : in_file_order(*table)) {
    const std::string name(key->str());
    if (auto uniform = uniform_value(*value)) {
      level.uniforms.emplace_back(name, std::move(*uniform));
    } else {
      fail(*value, "uniform '" + name + "' must be a number, a bool or an array of numbers");
    }
  }
}

void parse_targets(Reader& reader, const toml::node& node, bool has_match, ParsedLevel& out, const Fail& fail) {
  const toml::array* array = node.as_array();
  if (!array) return fail(node, "targets must be an array of strings");
  for (const toml::node& element : *array) {
    const auto* text = element.as_string();
    const std::optional<Target> target = text ? parse_target(text->get()) : std::nullopt;
    if (!target) {
      fail(element, "unknown target " + (text ? "'" + text->get() + "'" : std::string("(not a string)")) +
                        " (expected self, default, pass:NAME, texture:N or framebuffer:N)");
    } else if (target->kind == Target::Kind::self && !has_match) {
      fail(element, "target 'self' needs a pass with a match (this pass owns no programs)");
    } else {
      bool seen = false;
      for (const Target& t : out.level.targets) seen = seen || t == *target;
      if (seen) continue;
      out.level.targets.push_back(*target);
      out.target_at.push_back(reader.at(element.source()));
    }
  }
}

std::string level_label(const toml::table* table, std::size_t index, const std::string& pass_name) {
  std::string label = "level " + std::to_string(index);
  if (table) {
    if (const auto* name = (*table)["name"].as_string(); name && !name->get().empty())
      label += " ('" + name->get() + "')";
  }
  return label + " of pass '" + pass_name + "'";
}

}  // namespace

std::optional<ParsedLevel> parse_level(Reader& reader, const toml::node& node, std::size_t index,
                                       const std::string& pass_name, bool has_match) {
  const toml::table* table = node.as_table();
  ParsedLevel out;
  out.label = level_label(table, index, pass_name);
  out.at = reader.at(node.source());
  const std::string consequence = index == 0 ? "; pass dropped" : "; level dropped";
  bool ok = true;
  const Fail fail = [&](const toml::node& where, const std::string& what) {
    reader.report(where.source(), out.label + ": " + what + consequence);
    ok = false;
  };
  if (!table) {
    fail(node, "not a table");
    return std::nullopt;
  }
  Level& level = out.level;
  const toml::node* targets = nullptr;
  for (const auto& [key, value] : in_file_order(*table)) {
    const std::string_view name = key->str();
    if (name == "name") {
      if (const auto* text = value->as_string())
        level.name = text->get();
      else
        fail(*value, "name must be a string");
    } else if (name == "defines") {
      parse_defines(*value, level, fail);
    } else if (name == "replace") {
      parse_replace(reader, *value, level, fail);
    } else if (name == "uniforms") {
      parse_uniforms(*value, level, fail);
    } else if (name == "draws") {
      if (const auto* flag = value->as_boolean())
        level.draws = flag->get();
      else
        fail(*value, "draws must be a bool");
    } else if (name == "scale") {
      const std::optional<double> scale = number(*value);
      if (scale && *scale > 0.0 && *scale <= 1.0)
        level.scale = *scale;
      else
        fail(*value, "scale must be a number in (0, 1]" + (scale ? ", not " + format_number(*scale) : ""));
    } else if (name == "targets") {
      targets = value;
      parse_targets(reader, *value, has_match, out, fail);
    } else if (name == "fragment_scale") {
      const std::optional<double> scale = number(*value);
      if (scale && *scale > 0.0 && std::isfinite(*scale))
        level.fragment_scale = *scale;
      else
        fail(*value, "fragment_scale must be a finite number > 0");
    } else if (name == "error") {
      const std::optional<double> error = number(*value);
      if (error && *error >= 0.0 && *error <= 1.0) {
        if (index == 0 && *error != 0.0) {
          reader.report(value->source(), out.label + ": error ignored: level 0 is the reference, its error is 0");
        } else {
          level.error = *error;
        }
      } else {
        fail(*value, "error must be a number in [0, 1] (1 - SSIM)" + (error ? ", not " + format_number(*error) : ""));
      }
    } else {
      reader.warn_unknown_key(*key, out.label);
    }
  }
  if (!ok) return std::nullopt;

  if (level.scale == 1.0 && targets) {
    reader.report(targets->source(), out.label + ": targets ignored: the level's scale is 1");
    level.targets.clear();
    out.target_at.clear();
  } else if (level.scale < 1.0 && targets && level.targets.empty()) {
    fail(*targets, "targets is empty but scale is " + format_number(level.scale));
    return std::nullopt;
  } else if (level.scale < 1.0 && !targets) {
    level.targets = {make_target(has_match ? Target::Kind::self : Target::Kind::default_framebuffer)};
    out.target_at = {std::string()};
  }
  return out;
}

}  // namespace glbudget::manifest::detail
