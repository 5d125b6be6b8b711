// Uploads the per-frame uniforms of lighting.glsl (lights, environment, camera, shadow map).
#pragma once
#include <GL/glew.h>

#include "gl_program.hpp"
#include "passes/frame_context.hpp"

namespace demo {

// Binds `shadow_map` to texture unit 0 for the program's u_shadow_map.
void set_lighting_uniforms(const Program& program, const FrameContext& frame, GLuint shadow_map);
void set_material_uniforms(const Program& program, const Object& object);  // its material

}  // namespace demo
