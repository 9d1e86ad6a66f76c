#version 330 core
in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;
uniform sampler2DArray u_textures;
uniform sampler2DArray u_masks;
// Built twice: with FVV_DEPTH_VISIBILITY (streams without masks) each camera's
// visibility comes from its depth map (camera_depth_maps.h), else from the
// stream's masks.
#ifdef FVV_DEPTH_VISIBILITY
uniform sampler2DArray u_depth;
layout(std140) uniform DepthCameras {
  mat4 u_world_to_camera[64];
  vec4 u_projection[64];
  vec4 u_texel_angle[64];
};
#endif
uniform vec3 u_cameras[64];
// The cameras that weigh in this view and whose textures are here, the first
// u_view_camera_count entries (a few of a dome's many: the loop below costs
// what they do, not what the rig does).
uniform int u_view_cameras[64];
uniform int u_view_camera_count;
uniform vec3 u_eye;
uniform float u_exponent;
uniform float u_angle_epsilon;
uniform float u_facing_exponent;
// container/geometric_visibility.h: kDepthTolerance, kSlopeTexels, kMinFacing, kFullFacing.
uniform vec4 u_visibility_rule;
out vec4 o_color;

#ifdef FVV_DEPTH_VISIBILITY
// Without masks: how much camera i sees this point, from its depth map (the
// four nearest texels' tests, bilinearly weighted, so outlines are soft).
float DepthVisibility(int i, float facing) {
  vec4 p = u_world_to_camera[i] * vec4(v_world, 1.0);
  if (p.z <= 1e-4) return 0.0;
  vec4 k = u_projection[i];
  vec2 uv = vec2(k.x * p.x / p.z + k.z, k.y * p.y / p.z + k.w);
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 0.0;
  ivec3 size = textureSize(u_depth, 0);
  // Layer rows run bottom-up (GL); the image's top-down.
  vec2 at = vec2(uv.x, 1.0 - uv.y) * vec2(size.xy) - 0.5;
  ivec2 base = ivec2(floor(at));
  vec2 f = at - vec2(base);
  float c = clamp(facing, 0.05, 1.0);
  float slope = sqrt(max(0.0, 1.0 - c * c)) / c;
  float allowance = u_visibility_rule.x + u_visibility_rule.y * p.z * u_texel_angle[i].x * slope;
  float v[4];
  for (int n = 0; n < 4; ++n) {
    ivec2 q = clamp(base + ivec2(n & 1, n >> 1), ivec2(0), size.xy - 1);
    v[n] = p.z <= texelFetch(u_depth, ivec3(q, i), 0).r + allowance ? 1.0 : 0.0;
  }
  return mix(mix(v[0], v[1], f.x), mix(v[2], v[3], f.x), f.y);
}
#endif

void main() {
  vec3 n = normalize(v_normal);
  vec3 to_eye = normalize(u_eye - v_world);
  vec3 sum = vec3(0.0);
  float weight_sum = 0.0;
  int best_camera = -1;
  float best = -2.0;
  for (int j = 0; j < u_view_camera_count; ++j) {
    int i = u_view_cameras[j];
    vec3 to_camera = normalize(u_cameras[i] - v_world);
    float facing = dot(n, to_camera);
#ifdef FVV_DEPTH_VISIBILITY
    float seen = facing > u_visibility_rule.z
                     ? smoothstep(u_visibility_rule.z, u_visibility_rule.w, facing) *
                           DepthVisibility(i, facing)
                     : 0.0;
#else
    float seen = texture(u_masks, vec3(v_uv, float(i))).r;
#endif
    // Most cameras do not see a given texel: only the ones that do (and the
    // best-facing one, the fallback) cost a texture fetch and the weight.
    if (seen > 0.0) {
      vec3 colour = texture(u_textures, vec3(v_uv, float(i))).rgb;
      float angle = acos(clamp(dot(to_eye, to_camera), -1.0, 1.0));
      // Relative to a camera on the viewing ray (angle 0), so that no exponent
      // overflows; and a camera seeing the surface squarely sampled it more
      // finely, and is less thrown by where the model misses the actor.
      float w = seen * pow(u_angle_epsilon / (angle + u_angle_epsilon), u_exponent) *
                pow(max(facing, 1e-3), u_facing_exponent);
      sum += w * colour;
      weight_sum += w;
    }
    if (facing > best) {
      best = facing;
      best_camera = i;
    }
  }
  vec3 fallback = best_camera >= 0 ? texture(u_textures, vec3(v_uv, float(best_camera))).rgb
                                   : vec3(0.5);
  o_color = vec4(weight_sum > 1e-12 ? sum / weight_sum : fallback, 1.0);
}
