#version 330 core
in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;
uniform sampler2DArray u_textures;
uniform sampler2DArray u_masks;
uniform int u_has_masks;
uniform vec3 u_cameras[64];
uniform int u_present[64];  // 0: no texture of this camera, or it cannot weigh in this view
uniform int u_camera_count;
uniform vec3 u_eye;
uniform float u_exponent;
out vec4 o_color;
void main() {
  vec3 n = normalize(v_normal);
  vec3 to_eye = normalize(u_eye - v_world);
  vec3 sum = vec3(0.0);
  float weight_sum = 0.0;
  int best_camera = -1;
  float best = -2.0;
  for (int i = 0; i < u_camera_count; ++i) {
    if (u_present[i] == 0) continue;
    vec3 to_camera = normalize(u_cameras[i] - v_world);
    float facing = dot(n, to_camera);
    // Without masks a camera "sees" the surfaces facing it.
    float seen = u_has_masks != 0 ? texture(u_masks, vec3(v_uv, float(i))).r
                                  : step(0.0, facing);
    // Most cameras do not see a given texel: only the ones that do (and the
    // best-facing one, the fallback) cost a texture fetch and the weight.
    if (seen > 0.0) {
      vec3 colour = texture(u_textures, vec3(v_uv, float(i))).rgb;
      float angle = acos(clamp(dot(to_eye, to_camera), -1.0, 1.0));
      float w = seen * pow(1.0 / (angle + 0.02), u_exponent);
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
