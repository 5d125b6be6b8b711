// PassIndex is the model's one pass identity; PassNames maps names onto it where they come in.
#include <catch2/catch.hpp>

#include "glbudget/model/pass_names.hpp"
#include "glbudget/model/power_model.hpp"

using namespace glbudget::model;

TEST_CASE("pass names: the space's passes at their indices, other names after them in order of sight",
          "[model][passes]") {
  const ConfigurationSpace space({{"resolution", {{}, {}}, {"scene"}}, {"scene", {{}}, {}}, {"glass", {{}}, {}}});
  PassNames names(space);
  CHECK(names.size() == 3);
  CHECK(names.index_of("scene") == 1);
  CHECK(names.index_of("glass") == 2);
  CHECK(names.find("0123456789abcdef") == std::nullopt);
  CHECK(names.index_of("0123456789abcdef") == 3);
  CHECK(names.index_of("fixed-function") == 4);
  CHECK(names.index_of("0123456789abcdef") == 3);  // asked again: the same index
  CHECK(names.find("fixed-function") == PassIndex{4});
  CHECK(names.name(3) == "0123456789abcdef");
  CHECK(names.name(0) == "resolution");
  CHECK(names.name(99).empty());
  CHECK(names.size() == 5);
  // The scales by index: resolution scales the scene.
  CHECK(space.scaled_by(0) == std::vector<std::size_t>{1});
  CHECK(space.scalers_of(1) == std::vector<std::size_t>{0});
  CHECK(space.scalers_of(2).empty());
}

TEST_CASE("pass names: an empty space, an empty name, a name the space repeats", "[model][passes][extremes]") {
  PassNames none;
  CHECK(none.size() == 0);
  CHECK(none.index_of("") == 0);  // an empty name is a name like any other here
  CHECK(none.name(0).empty());
  CHECK(none.index_of("a") == 1);

  // Two passes named alike: the name finds the first; the second is reached by its index.
  const ConfigurationSpace twice({{"p", {{}}, {}}, {"p", {{}}, {}}});
  PassNames names(twice);
  CHECK(names.size() == 2);
  CHECK(names.index_of("p") == 0);
  CHECK(names.name(1) == "p");
}

TEST_CASE("a power model is indexed by pass: unfitted passes have no entry and add nothing", "[model][passes]") {
  PlatformProfile profile;
  profile.p_min_w = 10.0;
  profile.p_max_w = 50.0;
  PowerModel model(profile);
  CHECK(model.find(0) == nullptr);
  CHECK(model.find(1000000) == nullptr);
  model.set(5, {1.0, 0.0, 0.0});
  CHECK(model.fitted_passes() == 1);
  CHECK(model.find(4) == nullptr);
  REQUIRE(model.find(5) != nullptr);
  CHECK(model.find(5)->k_b == 1.0);
  const std::vector<PassFrame> frame{{2, {1e9, 1e9, 1e9}}, {5, {0.0, 0.0, 0.0}}};
  CHECK(model.predict_power(frame) == profile.p_min_w);
}
