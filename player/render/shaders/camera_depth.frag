#version 330 core
// A capture camera's depth map: its z (metres along the optical axis), which
// the projection leaves as the clip w, so 1 / gl_FragCoord.w.
out float o_depth;
void main() { o_depth = 1.0 / gl_FragCoord.w; }
