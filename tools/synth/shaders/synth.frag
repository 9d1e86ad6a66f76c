#version 330 core
in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;
uniform int u_mode;
uniform sampler2DArray u_texture;
uniform vec3 u_shadow;
uniform float u_shadow_on;
uniform float u_unlit;
out vec4 colour;
float hash(vec2 p) { return fract(sin(dot(p, vec2(127.1, 311.7))) * 43758.5453); }
float noise(vec2 p) {
  vec2 i = floor(p), f = fract(p);
  vec2 u = f * f * (3.0 - 2.0 * f);
  return mix(mix(hash(i), hash(i + vec2(1, 0)), u.x), mix(hash(i + vec2(0, 1)), hash(i + vec2(1, 1)), u.x), u.y);
}
// Props (v_uv.x > 0.5): a colour of their own, light grain, darker edges below.
vec3 prop(vec3 p, vec3 n, float id) {
  vec3 c = vec3(0.25 + 0.6 * hash(vec2(id, 1.0)), 0.25 + 0.6 * hash(vec2(id, 2.0)),
                0.25 + 0.6 * hash(vec2(id, 3.0)));
  float along = abs(n.x) > 0.5 ? p.z : p.x;
  return c * (0.85 + 0.2 * noise(vec2(along, p.y) * 14.0 + id));
}
vec3 studio(vec3 p, vec3 n) {
  // Rounded: the hash magnifies the interpolation's last bits into stripes.
  if (v_uv.x > 0.5) return prop(p, n, floor(v_uv.x + 0.5));
  if (n.y > 0.5) {  // floor: two-tone tiles, carpet grain, a taped circle and cross
    vec2 q = p.xz;
    float tile = mod(floor(q.x / 0.8) + floor(q.y / 0.8), 2.0);
    vec3 c = mix(vec3(0.45, 0.44, 0.42), vec3(0.38, 0.37, 0.36), tile);
    c *= 0.88 + 0.16 * noise(q * 60.0) + 0.08 * noise(q * 5.0);
    float r = length(q);
    if (abs(r - 1.7) < 0.025 || (r < 0.25 && min(abs(q.x), abs(q.y)) < 0.015)) c = vec3(0.9, 0.86, 0.55);
    float d = length(q - u_shadow.xz);
    c *= 1.0 - u_shadow_on * 0.5 * exp(-d * d / 0.06);
    return c;
  }
  if (n.y < -0.5) return vec3(0.2);  // ceiling
  // Walls: green-grey panels with dark seams, a darker skirting, light noise.
  float along = abs(n.x) > 0.5 ? p.z : p.x;
  vec3 c = vec3(0.33, 0.45, 0.40);
  if (mod(along + 30.0, 1.25) < 0.035 || mod(p.y, 1.6) < 0.03) c = vec3(0.18, 0.22, 0.2);
  if (p.y < 0.25) c = vec3(0.15, 0.15, 0.17);
  float poster = step(abs(mod(along + 30.0, 5.0) - 2.5), 0.45) * step(abs(p.y - 1.9), 0.6);
  c = mix(c, mix(vec3(0.75, 0.55, 0.2), vec3(0.2, 0.3, 0.6), step(0.5, fract(p.y * 2.5 + along))), poster);
  return c * (0.86 + 0.22 * noise(vec2(along, p.y) * 9.0));
}
void main() {
  if (u_mode == 2) { colour = vec4(1.0); return; }
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  vec3 base = u_mode == 0 ? texture(u_texture, vec3(v_uv, 0.0)).rgb : studio(v_world, n);
  vec3 key = normalize(vec3(0.4, 0.85, 0.5)), fill = normalize(vec3(-0.6, 0.3, -0.5));
  float light = 0.42 + 0.55 * max(dot(n, key), 0.0) + 0.2 * max(dot(n, fill), 0.0);
  if (u_mode == 0) light = mix(light, 1.0, u_unlit);
  colour = vec4(base * light, 1.0);
}
