#version 330 core
// Depth only. DITHERED (trees with a fading or glass node this frame) leaves
// out a dithered share of a node's texels, as mesh.frag does; the rest stay
// free of discard, which a software renderer pays for on every texel.
#if DITHERED
flat in float v_skip;
#endif
void main() {
#if DITHERED
  if (v_skip > dither_threshold(gl_FragCoord.xy)) discard;
#endif
}
