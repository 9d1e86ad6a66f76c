#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in uvec4 a_joints;
layout(location = 4) in vec4 a_weights;
layout(std140) uniform Bones { mat4 u_skin[256]; };
uniform mat4 u_view_proj;
uniform int u_skinned;
out vec3 v_world;
out vec3 v_normal;
out vec2 v_uv;
void main() {
  mat4 s = mat4(1.0);
  if (u_skinned != 0) {
    s = a_weights.x * u_skin[a_joints.x] + a_weights.y * u_skin[a_joints.y] +
        a_weights.z * u_skin[a_joints.z] + a_weights.w * u_skin[a_joints.w];
  }
  vec4 w = s * vec4(a_pos, 1.0);
  v_world = w.xyz;
  v_normal = mat3(s) * a_normal;
  v_uv = a_uv;
  gl_Position = u_view_proj * w;
}
