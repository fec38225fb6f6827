// A grid of module-size cells (lines between lattice cells), anti-aliased with screen-space
// derivatives, fading into the background away from the ensemble.
#version 330 core
in vec2 v_xy;

uniform vec2 u_center;
uniform float u_fade_radius;
uniform vec3 u_ground;
uniform vec3 u_line;
uniform vec3 u_background;

out vec4 frag_color;

void main() {
  vec2 cell = v_xy + 0.5;  // module centres sit on whole numbers, borders half-way between
  vec2 width = fwidth(cell);
  vec2 distance = abs(fract(cell - 0.5) - 0.5) / max(width, vec2(1e-4));
  float line = 1.0 - min(min(distance.x, distance.y), 1.0);
  // Lines thinner than a pixel fade instead of flickering.
  line *= clamp(1.5 - max(width.x, width.y) * 4.0, 0.0, 1.0);
  vec3 color = mix(u_ground, u_line, line);
  float fade = smoothstep(u_fade_radius * 0.55, u_fade_radius, length(v_xy - u_center));
  frag_color = vec4(mix(color, u_background, fade), 1.0);
}
