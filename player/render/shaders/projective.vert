#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in float a_weight;
uniform mat4 u_view_proj;
out vec3 v_world;
out float v_weight;
void main() {
  v_world = a_pos;
  v_weight = a_weight;
  gl_Position = u_view_proj * vec4(a_pos, 1.0);
}
