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
// at `light` in the sun's clip space, facing `n`: with a slope-scaled bias.
// The sun's box is orthographic (w = 1), so for a plane this is linear in
// the position and may be interpolated; shadow_clip is not.
vec3 shadow_coord(vec3 light, vec3 n, vec3 sun) {
  float slope = clamp(1.0 - dot(n, sun), 0.0, 1.0);
  return light * 0.5 + 0.5 - vec3(0.0, 0.0, 0.0006 + 0.002 * slope);
}

// Never shadowed beyond the light's far plane.
vec3 shadow_clip(vec3 p) { return vec3(p.xy, p.z > 1.0 ? -1.0 : p.z); }

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

// The sky's colour along the normalised `ray`: a gradient up from the
// horizon and the sun's glow (its 12th power without pow(), which costs on
// software renderers).
vec3 sky_radiance(vec3 ray, vec3 sun, vec3 sky, vec3 horizon) {
  vec3 color = mix(horizon, sky, sqrt(max(ray.y, 0.0)));
  float s = max(dot(ray, sun), 0.0);
  float s4 = s * s;
  s4 *= s4;
  return color + vec3(1.0, 0.9, 0.7) * (s4 * s4 * s4 * 0.25);
}
