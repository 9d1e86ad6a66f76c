#version 330 core
in vec3 v_world;
in float v_weight;
uniform int u_pass;
uniform mat3 u_rotation;       // world -> camera
uniform vec3 u_translation;
uniform vec4 u_intrinsics;     // fx fy cx cy (pixel centres at integers)
uniform vec4 u_distortion;     // k1 k2 p1 p2
uniform float u_k3;
uniform vec2 u_size;           // image width, height
uniform sampler2D u_image;     // straight RGBA, row 0 at the top
out vec4 o_accum;
void main() {
  if (u_pass == 0) {
    // Grey, weighed below anything a camera gives (a fill's least is ~1e-10).
    o_accum = vec4(0.5, 0.5, 0.5, 1.0) * 1e-14;
    return;
  }
  vec3 p = u_rotation * v_world + u_translation;
  if (p.z <= 1e-6 || v_weight <= 0.0) discard;
  vec2 n = p.xy / p.z;
  float r2 = dot(n, n);
  float k1 = u_distortion.x, k2 = u_distortion.y, p1 = u_distortion.z, p2 = u_distortion.w;
  float radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * u_k3));
  vec2 d = vec2(n.x * radial + 2.0 * p1 * n.x * n.y + p2 * (r2 + 2.0 * n.x * n.x),
                n.y * radial + p1 * (r2 + 2.0 * n.y * n.y) + 2.0 * p2 * n.x * n.y);
  vec2 uv = (u_intrinsics.xy * d + u_intrinsics.zw + 0.5) / u_size;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) discard;
  vec4 s = texture(u_image, uv);
  // Straight colour, the actor's or the nearest of it (ExpandSilhouette);
  // s.a how much of the sample lies on the (expanded) silhouette. The fill
  // beyond it (alpha 1/255) counts a thousandth as much: it only colours
  // what no camera's silhouette covers, which would otherwise be grey.
  if (s.a <= 0.0) discard;
  float w = v_weight * (s.a >= 0.02 ? s.a : s.a * 1e-3);
  o_accum = vec4(s.rgb * w, w);
}
