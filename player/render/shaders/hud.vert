#version 330 core
layout(location = 0) in vec2 a_pixel;
uniform vec2 u_viewport;
void main() {
  // Pixel coordinates, origin at the top left, to clip space.
  gl_Position = vec4(2.0 * a_pixel.x / u_viewport.x - 1.0, 1.0 - 2.0 * a_pixel.y / u_viewport.y,
                     0.0, 1.0);
}
