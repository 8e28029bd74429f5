// Put after the #version line of every shader (and after a program's variant
// macro) by the loader: what several shaders share.

// Linear colour to sRGB for the framebuffer, as a + b sqrt: within 3/255 of
// the exact curve above 1% intensity. An sRGB framebuffer would convert each
// written pixel (and each blended one twice) in a software renderer's
// slowest path.
vec3 encode_srgb(vec3 linear) {
  vec3 c = max(linear, 0.0);
  return 1.111 * sqrt(c) - 0.111 * c;
}
