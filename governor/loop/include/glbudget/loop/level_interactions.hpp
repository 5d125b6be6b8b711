#pragma once
// How the governor predicts a combination of levels where the platform profile holds each level
// alone and the cheapest configuration measured (GLBUDGET_LEVEL_INTERACTIONS; GovernorSettings).
namespace glbudget::loop {

// calibrated: the best's power plus each level's change alone, plus the run-time model's
// interaction scaled so that the cheapest is predicted where it was measured, never amplified
// nor turned round; additive: without the interaction; model: the model's own; scaled: additive,
// each level's calibrated change scaled by one share so that the changes summed put the cheapest
// where it was measured, never amplified (levels whose savings overlap, as on the demo's Hall:
// the model's interaction, fitted on the frames of the few configurations drawn, may fall far
// short of the measured cheapest, and every combination is then predicted to save too much). The
// run's own windows correct each level from there, as under additive.
enum class LevelInteractions { calibrated, additive, model, scaled };

}  // namespace glbudget::loop
