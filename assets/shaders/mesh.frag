// Simple lighting: a sky-to-ground ambient term and a key light from above the camera's
// shoulder; `u_unlit` paints the flat colour (outlines).
#version 330 core
in vec3 v_normal;
in vec4 v_color;

uniform vec3 u_light;  // towards the light, unit length
uniform int u_unlit;

out vec4 frag_color;

void main() {
  if (u_unlit != 0) {
    frag_color = v_color;
    return;
  }
  vec3 n = normalize(v_normal);
  float key = max(dot(n, u_light), 0.0);
  float sky = 0.5 + 0.5 * n.z;
  vec3 lit = v_color.rgb * (0.42 + 0.18 * sky + 0.5 * key);
  frag_color = vec4(min(lit, vec3(1.0)), v_color.a);
}
