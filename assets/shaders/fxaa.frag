// Anti-aliasing as a post-process (FXAA, after Lottes): where the luma of a pixel's diagonal
// neighbours shows an edge, blend along the edge's direction. It costs one full-screen pass,
// where multisampling costs llvmpipe three to four times the whole frame.
#version 330 core
in vec2 v_uv;

uniform sampler2D u_color;
uniform vec2 u_texel;  // one pixel, in texture coordinates

out vec4 frag_color;

float luma(vec3 c) { return dot(c, vec3(0.299, 0.587, 0.114)); }

// Between pixels, filtered.
vec3 at(vec2 offset) { return texture(u_color, v_uv + offset * u_texel).rgb; }
// On a neighbouring pixel: an unfiltered fetch, much cheaper in a software rasterizer.
float luma_at(ivec2 pixel, ivec2 offset) {
  return luma(texelFetch(u_color, clamp(pixel + offset, ivec2(0), textureSize(u_color, 0) - 1), 0).rgb);
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 middle = texelFetch(u_color, pixel, 0).rgb;
  float m = luma(middle);
  float nw = luma_at(pixel, ivec2(-1, 1)), ne = luma_at(pixel, ivec2(1, 1));
  float sw = luma_at(pixel, ivec2(-1, -1)), se = luma_at(pixel, ivec2(1, -1));
  float lo = min(m, min(min(nw, ne), min(sw, se)));
  float hi = max(m, max(max(nw, ne), max(sw, se)));
  if (hi - lo < max(1.0 / 32.0, hi / 8.0)) {  // no edge worth smoothing
    frag_color = vec4(middle, 1.0);
    return;
  }
  // Along the edge: perpendicular to the luma gradient.
  vec2 along = vec2(-((nw + ne) - (sw + se)), (nw + sw) - (ne + se));
  float reduce = max((nw + ne + sw + se) * (0.25 / 8.0), 1.0 / 128.0);
  along = clamp(along / (min(abs(along.x), abs(along.y)) + reduce), vec2(-8.0), vec2(8.0));
  vec3 near = 0.5 * (at(along * (1.0 / 3.0 - 0.5)) + at(along * (2.0 / 3.0 - 0.5)));
  vec3 wide = 0.5 * near + 0.25 * (at(along * -0.5) + at(along * 0.5));
  float w = luma(wide);
  frag_color = vec4((w < lo || w > hi) ? near : wide, 1.0);
}
