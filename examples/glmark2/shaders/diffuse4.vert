// The four lights of glmark2's `shading:shading=phong:num-lights=4`, ambient and diffuse only,
// per vertex: no specular highlight.
attribute vec3 position;
attribute vec3 normal;
uniform mat4 ModelViewProjectionMatrix;
uniform mat4 NormalMatrix;
uniform mat4 ModelViewMatrix;
varying vec4 vertex_color;

void main(void) {
    vec4 current_position = vec4(position, 1.0);
    vec3 n = normalize(vec3(NormalMatrix * vec4(normal, 1.0)));
    vec3 p = (ModelViewMatrix * current_position).xyz;
    float diffuse = max(0.0, dot(n, normalize(vec3(0.0, 1.0, 0.0) - p))) +
                    2.0 * max(0.0, dot(n, normalize(vec3(0.707107, 0.0, 0.707107) - p))) +
                    max(0.0, dot(n, normalize(vec3(0.0, 0.0, 1.0) - p)));
    vertex_color = vec4(0.08, 0.08, 0.08, 1.0) + vec4(0.0, 0.0, 0.2, 0.0) * diffuse;
    gl_Position = ModelViewProjectionMatrix * current_position;
}
