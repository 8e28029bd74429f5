#version 330 core
// Depth only, less a dithered share of a node's texels (as in mesh.frag): a
// fading node's, and a glass node's for the light it lets through.
flat in float v_skip;
void main() {
  if (v_skip > dither_threshold(gl_FragCoord.xy)) discard;
}
