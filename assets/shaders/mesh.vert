// Modules and props: one mesh drawn once per instance, placed by the instance's transform.
#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in mat4 i_model;  // locations 2 to 5
layout(location = 6) in vec4 i_color;

uniform mat4 u_view_projection;

out vec3 v_normal;
out vec4 v_color;

void main() {
  // Transforms are rotations with a uniform scale, so the normal turns with the model matrix.
  v_normal = mat3(i_model) * a_normal;
  v_color = i_color;
  gl_Position = u_view_projection * i_model * vec4(a_position, 1.0);
}
