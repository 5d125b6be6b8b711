// glmark2's light-phong model (ambient, diffuse, specular with shininess 100) for its four
// lights of `shading:shading=phong:num-lights=4`, evaluated per vertex.
attribute vec3 position;
attribute vec3 normal;
uniform mat4 ModelViewProjectionMatrix;
uniform mat4 NormalMatrix;
uniform mat4 ModelViewMatrix;
varying vec4 vertex_color;

const vec4 MaterialDiffuse = vec4(0.0, 0.0, 1.0, 1.0);
const vec4 LightColor = vec4(0.2, 0.2, 0.2, 1.0);

vec4 compute_color(vec4 light_position, vec3 n, vec4 p) {
    vec3 eye_direction = normalize(-p.xyz);
    vec3 light_direction = normalize(light_position.xyz / light_position.w - p.xyz / p.w);
    vec3 reflection = reflect(-light_direction, n);
    float specularTerm = pow(max(0.0, dot(reflection, eye_direction)), 100.0);
    float diffuseTerm = max(0.0, dot(n, light_direction));
    return vec4(0.8, 0.8, 0.8, 1.0) * specularTerm + vec4(0.02, 0.02, 0.02, 1.0) +
           LightColor * MaterialDiffuse * diffuseTerm;
}

void main(void) {
    vec4 current_position = vec4(position, 1.0);
    vec3 n = normalize(vec3(NormalMatrix * vec4(normal, 1.0)));
    vec4 p = ModelViewMatrix * current_position;
    vertex_color = compute_color(vec4(0.0, 1.0, 0.0, 1.0), n, p) +
                   compute_color(vec4(0.707107, 0.0, 0.707107, 1.0), n, p) +
                   compute_color(vec4(0.0, 0.0, 1.0, 1.0), n, p) +
                   compute_color(vec4(0.707107, 0.0, 0.707107, 1.0), n, p);
    gl_Position = ModelViewProjectionMatrix * current_position;
}
