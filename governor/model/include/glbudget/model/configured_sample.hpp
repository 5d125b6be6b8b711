#pragma once
// A frame with the configuration it was drawn in: what the run-time model keeps as history.
#include "glbudget/model/configuration_space.hpp"
#include "glbudget/model/power_model.hpp"

namespace glbudget::model {

struct ConfiguredSample {
  FrameSample sample;
  Configuration configuration;
};

}  // namespace glbudget::model
