#include <exception>

#include "parsed.hpp"

namespace glbudget::manifest {

LoadResult parse_manifest(const std::string& toml_text, const std::string& path) {
  LoadResult result;
  try {
    detail::Reader reader(path, result.problems);
    toml::parse_result parsed = toml::parse(toml_text, path);
    if (!parsed) {
      const toml::parse_error& error = parsed.error();
      reader.report(error.source(), std::string(error.description()), true);
      return result;
    }
    const toml::table& root = parsed.table();
    reader.warn_unknown_keys(root, {"pass", "shader_coordinates"}, "the manifest");
    bool app_coordinates = true;
    if (const toml::node* coordinates = root.get("shader_coordinates")) {
      const auto* text = coordinates->as_string();
      if (text && (text->get() == "app" || text->get() == "scaled"))
        app_coordinates = text->get() == "app";
      else
        reader.report(coordinates->source(), "shader_coordinates must be \"app\" or \"scaled\"; \"app\" is used");
    }

    std::vector<detail::ParsedPass> passes;
    std::map<std::string, std::string> names;
    const toml::node* pass_node = root.get("pass");
    if (const toml::array* array = pass_node ? pass_node->as_array() : nullptr) {
      std::size_t index = 0;
      for (const toml::node& node : *array) {
        if (auto pass = detail::parse_pass(reader, node, index++, names)) passes.push_back(std::move(*pass));
      }
    } else if (pass_node) {
      reader.report(pass_node->source(), "pass must be an array of tables ([[pass]])");
    }
    Manifest manifest{
        .path = path, .passes = detail::resolve(reader, std::move(passes)), .app_coordinates = app_coordinates};
    if (manifest.passes.empty()) {
      reader.report(pass_node ? pass_node->source() : toml::source_region{},
                    "no passes: the manifest needs at least one usable [[pass]]", true);
      return result;
    }
    result.manifest = std::move(manifest);
  } catch (const std::exception& error) {  // std::bad_alloc: the library never throws
    result.manifest.reset();
    result.problems.push_back(Problem{path + ": " + error.what(), true});
  }
  return result;
}

LoadResult load_manifest(const std::string& path) {
  LoadResult result;
  try {
    std::string text, why;
    if (detail::read_text_file(path, &text, &why)) return parse_manifest(text, path);
    result.problems.push_back(Problem{path + ": cannot read the manifest: " + why, true});
  } catch (const std::exception& error) {
    result.problems.push_back(Problem{path + ": " + error.what(), true});
  }
  return result;
}

}  // namespace glbudget::manifest
