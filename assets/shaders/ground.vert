// The ground: one square under the ensemble.
#version 330 core
layout(location = 0) in vec2 a_corner;  // -1..1

uniform mat4 u_view_projection;
uniform vec2 u_center;
uniform float u_half_size;
uniform float u_z;

out vec2 v_xy;

void main() {
  v_xy = u_center + a_corner * u_half_size;
  gl_Position = u_view_projection * vec4(v_xy, u_z, 1.0);
}
