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

// sRGB-encoded colour (a colour texture's filtered bytes) to linear, as a
// cubic: within 0.002 of the exact curve. The textures are plain bytes, see
// bk_texture_load.
vec3 decode_srgb(vec3 c) { return c * (c * (c * 0.305306011 + 0.682171111) + 0.012522878); }

// Distance haze 1 - exp(-0.012 d), with exp from its cubic Taylor
// polynomial: within 0.01 of it out to 100 m, and no exp per pixel.
float haze_amount(float d) {
  float k = 0.012 * d;
  return 1.0 - 1.0 / (1.0 + k * (1.0 + k * (0.5 + k * (1.0 / 6.0))));
}

// Where to look up the shadow map (compare mode, less-or-equal) for a point
// with light-space position `light`, facing `n`: with a slope-scaled bias,
// and never shadowed beyond the light's far plane.
vec3 shadow_point(vec4 light, vec3 n, vec3 sun) {
  vec3 p = light.xyz / light.w * 0.5 + 0.5;
  float slope = clamp(1.0 - dot(n, sun), 0.0, 1.0);
  p.z = p.z > 1.0 ? -1.0 : p.z - (0.0006 + 0.002 * slope);
  return p;
}

// Sun (diffuse and Schlick's rational stand-in for a pow() highlight: one
// division instead of a log and an exp), hemisphere ambient from the sky and
// the ground. `n` is the shading normal, `view` points to the eye.
vec3 light_surface(vec3 albedo, vec3 n, vec3 view, float shadow, float gloss, vec3 sun, vec3 sun_color,
                   vec3 sky, vec3 ground) {
  float diffuse = max(dot(n, sun), 0.0);
  float x = max(dot(n, normalize(sun + view)), 0.0), e = mix(16.0, 96.0, gloss);
  float specular = x / (e - e * x + x) * mix(0.04, 0.5, gloss);
  vec3 ambient = mix(ground, sky, n.y * 0.5 + 0.5) * 0.55;
  return albedo * (ambient + sun_color * diffuse * shadow) + sun_color * specular * shadow;
}
