#pragma once
// A fragment shader rewritten to see the app's pixels while it draws into a scaled render
// target. When glbudget stores an app's framebuffer at 60 % of its size, gl_FragCoord counts
// the stored pixels, but the app's shader may divide it by the resolution the app set in a
// uniform (`texture(scene, gl_FragCoord.xy / u_resolution)`): the image lands in a corner.
// The rewrite makes the shader's whole world the app's size again:
//   - gl_FragCoord.xy is multiplied by `glbudget_frag_ratio` (app pixels per stored pixel of
//     the draw target; 1 when it is not scaled);
//   - textureSize(s, lod) of a uniform 2D sampler answers the app's size of the level;
//   - texelFetch(s, p, lod) (and texelFetchOffset) of a uniform 2D sampler takes app texel
//     coordinates and reads the stored texel that covers them.
// For each such sampler `s` the shader gets `uniform ivec3 glbudget_size_s` (an array of as
// many for an array of samplers, indexed as the call indexes the sampler): the app's width
// and height of level 0 and 1 in z, or z = 0 when the texture bound is not one glbudget
// stores at another size (the calls then are the app's, exactly). With the ratio 1 and every
// z 0 the rewritten shader draws what the app's does, bit for bit.
// Calls whose sampler is not a uniform 2D sampler or an element of one (a function parameter,
// a struct member; an element whose index has side effects) cannot be followed: such a shader
// is not rewritten (`error` says why) and draws as it is.
#include <optional>
#include <string>
#include <vector>

namespace glbudget::instrument {

inline constexpr const char* kFragRatioUniform = "glbudget_frag_ratio";
inline constexpr const char* kSamplerSizePrefix = "glbudget_size_";

struct AppSpaceSampler {
  std::string name;
  bool array = false;  // glbudget_size_<name>[i] for element i
  bool operator==(const AppSpaceSampler&) const = default;
};

struct AppSpaceResult {
  bool needed = false;       // the shader reads gl_FragCoord, or texel coordinates of a 2D sampler
  bool ok = false;           // rewritten: `source`
  std::string source;        // preprocessed, one string
  std::string error;         // why a needed rewrite was not made
  bool unsupported = false;  // a use the rewrite cannot follow (`error` names it), not a shader it cannot read
  bool frag_coord = false;
  std::vector<AppSpaceSampler> samplers;  // each gets glbudget_size_<name>
};

// `source`: the fragment shader's strings, concatenated. `driver_extensions` as for
// instrument_shader() (extension conditionals follow the driver).
AppSpaceResult to_app_space(const std::string& source,
                            const std::optional<std::vector<std::string>>& driver_extensions);

}  // namespace glbudget::instrument
