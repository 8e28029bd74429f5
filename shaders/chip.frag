#version 330 core
// A chip lit like the pieces' cut faces (sun, sky and ground ambient, a
// highlight by the material's gloss), without shadows: it is small and
// mostly in the open. Fading chips leave out dithered pixels, as pieces do.
in vec3 v_position;
in vec3 v_normal;
in vec2 v_uv;
flat in vec3 v_tint;
flat in float v_fade;
uniform sampler2D u_interior;
uniform vec3 u_sun_direction;
uniform vec3 u_sun_color;
uniform vec3 u_sky_color;
uniform vec3 u_ground_color;
uniform vec3 u_eye;
uniform float u_gloss;
out vec4 out_color;

void main() {
  if (v_fade > dither_threshold(gl_FragCoord.xy)) discard;
  vec3 albedo = decode_srgb(texture(u_interior, v_uv).rgb) * v_tint;
  vec3 n = normalize(v_normal);
  vec3 view = normalize(u_eye - v_position);
  vec3 color = light_surface(albedo, n, view, 1.0, u_gloss, u_sun_direction, u_sun_color, u_sky_color,
                             u_ground_color);
  out_color = vec4(encode_srgb(color), 1.0);
}
