#version 330 core
uniform sampler2D u_accum;
uniform vec3 u_background;
out vec4 o_color;
void main() {
  vec4 a = texelFetch(u_accum, ivec2(gl_FragCoord.xy), 0);
  o_color = vec4(a.a > 0.0 ? a.rgb / a.a : u_background, 1.0);
}
