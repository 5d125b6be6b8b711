// Scene geometry for the shadow, base and metals passes. SKINNED selects linear-blend skinning
// with two bones per vertex (the subway soldiers).
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in uvec2 a_bones;
layout(location = 3) in float a_weight;

uniform mat4 u_model;
uniform mat4 u_view_projection;
#ifdef SKINNED
#define MAX_BONES 16
uniform mat4 u_bones[MAX_BONES];
#endif

out vec3 v_world_position;
out vec3 v_world_normal;

void main() {
  mat4 model = u_model;
#ifdef SKINNED
  model = u_model * (u_bones[a_bones.x] * a_weight + u_bones[a_bones.y] * (1.0 - a_weight));
#endif
  vec4 world = model * vec4(a_position, 1.0);
  v_world_position = world.xyz;
  v_world_normal = mat3(model) * a_normal;  // models are rigid + uniform scale
  gl_Position = u_view_projection * world;
}
