#include "values.hpp"

#include <charconv>
#include <cmath>

#include "reader.hpp"

namespace glbudget::manifest::detail {

std::optional<double> number(const toml::node& node) {
  if (const auto* i = node.as_integer()) return static_cast<double>(i->get());
  if (const auto* f = node.as_floating_point()) return f->get();
  return std::nullopt;
}

std::optional<std::string> define_text(const toml::node& node) {
  if (const auto* i = node.as_integer()) return std::to_string(i->get());
  if (const auto* b = node.as_boolean()) return std::string(b->get() ? "true" : "false");
  if (const auto* s = node.as_string()) {
    if (s->get().find_first_of("\r\n") != std::string::npos) return std::nullopt;
    return s->get();
  }
  if (const auto* f = node.as_floating_point()) {
    if (!std::isfinite(f->get())) return std::nullopt;
    std::string text = format_number(f->get());
    if (text.find('.') == std::string::npos) {
      const auto exponent = text.find('e');
      text.insert(exponent == std::string::npos ? text.size() : exponent, ".0");
    }
    return text;
  }
  return std::nullopt;
}

namespace {
bool flatten(const toml::node& node, std::vector<double>& values) {
  if (const auto* b = node.as_boolean()) {
    values.push_back(b->get() ? 1.0 : 0.0);
    return true;
  }
  if (const auto n = number(node)) {
    values.push_back(*n);
    return true;
  }
  if (const auto* array = node.as_array()) {
    for (const toml::node& element : *array) {
      if (!flatten(element, values)) return false;
    }
    return true;
  }
  return false;
}
}  // namespace

std::optional<UniformValue> uniform_value(const toml::node& node) {
  UniformValue value;
  if (!flatten(node, value.values) || value.values.empty()) return std::nullopt;
  return value;
}

Target make_target(Target::Kind kind, std::string name, uint32_t id) {
  Target target;
  target.kind = kind;
  target.name = std::move(name);
  target.id = id;
  return target;
}

std::optional<Target> parse_target(std::string_view text) {
  if (text == "self") return make_target(Target::Kind::self);
  if (text == "default") return make_target(Target::Kind::default_framebuffer);
  if (text == "window-sized") return make_target(Target::Kind::window_sized);
  if (text.starts_with("pass:")) {
    if (text.size() == 5) return std::nullopt;
    return make_target(Target::Kind::pass, std::string(text.substr(5)));
  }
  for (const auto& [prefix, kind] : {std::pair{std::string_view("texture:"), Target::Kind::texture},
                                     std::pair{std::string_view("framebuffer:"), Target::Kind::framebuffer}}) {
    if (!text.starts_with(prefix)) continue;
    const std::string_view digits = text.substr(prefix.size());
    uint32_t id = 0;
    const auto [end, status] = std::from_chars(digits.data(), digits.data() + digits.size(), id);
    if (status != std::errc() || end != digits.data() + digits.size() || id == 0) return std::nullopt;
    return make_target(kind, {}, id);
  }
  return std::nullopt;
}

std::string target_text(const Target& target) {
  switch (target.kind) {
    case Target::Kind::self:
      return "self";
    case Target::Kind::pass:
      return "pass:" + target.name;
    case Target::Kind::default_framebuffer:
      return "default";
    case Target::Kind::window_sized:
      return "window-sized";
    case Target::Kind::texture:
      return "texture:" + std::to_string(target.id);
    case Target::Kind::framebuffer:
      return "framebuffer:" + std::to_string(target.id);
  }
  return {};
}

bool is_identifier(std::string_view name) {
  if (name.empty() || (name.front() >= '0' && name.front() <= '9')) return false;
  for (const char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
    if (!ok) return false;
  }
  return true;
}

}  // namespace glbudget::manifest::detail
