#version 450 core
// PROBE_BAD_VARIANT's fragment stage, replaced: it reads an input no vertex stage writes, so
// the variant compiles but does not link.
in vec3 v_missing;
uniform uint u_val;
out uvec4 o;
void main() { o = uvec4(u_val, floatBitsToUint(v_missing)); }
