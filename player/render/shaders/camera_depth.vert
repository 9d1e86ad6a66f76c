#version 330 core
// The posed mesh, skinned once per frame by transform feedback, seen from a
// capture camera.
layout(location = 0) in vec3 a_world;
uniform mat4 u_view_proj;
void main() { gl_Position = u_view_proj * vec4(a_world, 1.0); }
