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
// the ground, the ambient times `occlusion` (1 = open: the sun reaches into
// no crevice a texture can know of). `n` is the shading normal, `view`
// points to the eye.
vec3 light_surface_occluded(vec3 albedo, vec3 n, vec3 view, float shadow, float gloss, vec3 sun,
                            vec3 sun_color, vec3 sky, vec3 ground, float occlusion) {
  float diffuse = max(dot(n, sun), 0.0);
  float x = max(dot(n, normalize(sun + view)), 0.0), e = mix(16.0, 96.0, gloss);
  float specular = x / (e - e * x + x) * mix(0.04, 0.5, gloss);
  vec3 ambient = mix(ground, sky, n.y * 0.5 + 0.5) * (0.55 * occlusion);
  return albedo * (ambient + sun_color * diffuse * shadow) + sun_color * specular * shadow;
}

vec3 light_surface(vec3 albedo, vec3 n, vec3 view, float shadow, float gloss, vec3 sun, vec3 sun_color,
                   vec3 sky, vec3 ground) {
  return light_surface_occluded(albedo, n, view, shadow, gloss, sun, sun_color, sky, ground, 1.0);
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

// The 4x4 ordered-dither (Bayer) threshold of a pixel, in (0, 1): a piece
// fading out drops the pixels whose threshold its fade exceeds, the same
// share in every 4x4 block, so it needs no sorting or blending.
float dither_threshold(vec2 frag_coord) {
  ivec2 p = ivec2(frag_coord) & 3;
  int a = p.x ^ p.y;
  return (float(((a & 1) << 3) | ((p.y & 1) << 2) | (a & 2) | ((p.y & 2) >> 1)) + 0.5) / 16.0;
}

// Lit colour eased above 0.6 towards 1, per channel: a white glaze in full
// sun (three times the light a surface gets from the sky) kept its shading
// instead of clipping to a flat white disc.
vec3 tone(vec3 c) {
  vec3 over = max(c - 0.6, 0.0);
  return min(c, 0.6) + over / (1.0 + 2.5 * over);
}

// Schlick's Fresnel for a dielectric (4% head on), from the cosine between
// the normal and the view.
float fresnel(float cosine) {
  float f = 1.0 - clamp(cosine, 0.0, 1.0), f2 = f * f;
  return 0.04 + 0.96 * f2 * f2 * f;
}

// What a smooth surface facing `n` mirrors towards `view`: the sky above
// the horizon, the ground's bounce below it.
vec3 mirrored(vec3 n, vec3 view, vec3 sun, vec3 sky, vec3 horizon, vec3 ground) {
  vec3 ray = reflect(-view, n);
  return mix(sky_radiance(ray, sun, sky, horizon), ground * 0.6, clamp(-4.0 * ray.y, 0.0, 1.0));
}

// A sharp highlight of the sun on a polished coat: Schlick's rational
// stand-in for x^150.
float sharp_highlight(vec3 n, vec3 view, vec3 sun) {
  float x = max(dot(n, normalize(sun + view)), 0.0);
  return x / (150.0 - 149.0 * x);
}

// Glass along `view` at `n` (both facing the eye): returns the light it
// adds (the sky's reflection, the sun's highlight, and `scatter`, the share
// of the sun and sky its rough cut faces send back) and sets `through`, the
// share of what is behind it that it lets through: `transmit` head on,
// squared at grazing angles where the light crosses more glass, less what
// the surface reflects.
vec3 light_glass(vec3 n, vec3 view, vec3 transmit, vec3 scatter, float shadow, vec3 sun, vec3 sun_color,
                 vec3 sky, vec3 horizon, vec3 ground, out vec3 through) {
  float cosine = clamp(dot(n, view), 0.0, 1.0), f = fresnel(cosine);
  through = mix(transmit, transmit * transmit, 1.0 - cosine) * (1.0 - f);
  vec3 ambient = mix(ground, sky, n.y * 0.5 + 0.5) * 0.55;
  return mirrored(n, view, sun, sky, horizon, ground) * f + sun_color * (sharp_highlight(n, view, sun) * shadow) +
         scatter * (ambient + sun_color * (max(dot(n, sun), 0.0) * shadow));
}
