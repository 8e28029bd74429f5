#version 330 core
// Sun with a soft shadow map, hemisphere ambient and a distance haze that
// matches the sky. Three programs come from this file (the renderer defines
// one macro): SURFACE, an object's outer surface with its normal map;
// INTERIOR, cut faces with their own texture; GROUND, the flat paving. A
// software renderer runs both sides of every branch, so each program holds
// only the work its pixels need.
in vec3 v_position;
in vec3 v_normal;
in vec4 v_tangent;
in vec2 v_uv;
in vec4 v_light_position;
flat in vec4 v_highlight; // overlay colour of the node: rgb, strength (0 = none)

uniform sampler2D u_albedo; // the interior texture in INTERIOR
uniform sampler2D u_normal_map;
uniform sampler2DShadow u_shadow_map;
uniform vec3 u_sun_direction; // towards the sun
uniform vec3 u_sun_color;
uniform vec3 u_sky_color;
uniform vec3 u_ground_color;
uniform vec3 u_eye;
uniform vec3 u_tint;
uniform float u_interior_scale;
uniform float u_gloss;

out vec4 out_color;

float shadow_factor(vec3 n) {
  vec3 p = v_light_position.xyz / v_light_position.w * 0.5 + 0.5;
  if (p.z > 1.0) return 1.0;
  float slope = clamp(1.0 - dot(n, u_sun_direction), 0.0, 1.0);
  p.z -= 0.0006 + 0.002 * slope;
  // One hardware-filtered tap is already a 2x2 comparison: soft enough, and
  // software renderers pay for every extra lookup.
  return texture(u_shadow_map, p);
}

// Distance haze 1 - exp(-0.012 d), with exp from its cubic Taylor
// polynomial: within 0.01 of it out to 100 m, and no exp per pixel.
float haze_amount(float d) {
  float k = 0.012 * d;
  return 1.0 - 1.0 / (1.0 + k * (1.0 + k * (0.5 + k * (1.0 / 6.0))));
}

void main() {
#if GROUND
  // Flat and facing up: the sun and the sky light are the same everywhere.
  vec3 albedo = texture(u_albedo, v_uv).rgb * u_tint;
  float lit = max(u_sun_direction.y, 0.0) * shadow_factor(vec3(0.0, 1.0, 0.0));
  vec3 color = albedo * (u_sky_color * 0.55 + u_sun_color * lit);
#else
  vec3 geometric = normalize(v_normal);
#if INTERIOR
  vec3 albedo = texture(u_albedo, v_uv * u_interior_scale).rgb * u_tint;
  vec3 n = geometric;
#else
  vec3 albedo = texture(u_albedo, v_uv).rgb * u_tint;
  vec3 t = normalize(v_tangent.xyz - geometric * dot(geometric, v_tangent.xyz));
  vec3 b = cross(geometric, t) * v_tangent.w;
  vec3 m = texture(u_normal_map, v_uv).xyz * 2.0 - 1.0;
  vec3 n = normalize(mat3(t, b, geometric) * m);
#endif
  vec3 view = normalize(u_eye - v_position);
  float diffuse = max(dot(n, u_sun_direction), 0.0);
  float shadow = shadow_factor(geometric);
  vec3 half_vector = normalize(u_sun_direction + view);
  // Schlick's rational stand-in for pow(x, e): one division instead of a
  // log and an exp per pixel, which a software renderer pays in full.
  float x = max(dot(n, half_vector), 0.0), e = mix(16.0, 96.0, u_gloss);
  float specular = x / (e - e * x + x) * mix(0.04, 0.5, u_gloss);
  vec3 ambient = mix(u_ground_color, u_sky_color, n.y * 0.5 + 0.5) * 0.55;
  vec3 color = albedo * (ambient + u_sun_color * diffuse * shadow) + u_sun_color * specular * shadow;
  color = mix(color, v_highlight.rgb, v_highlight.a);
#endif
  color = mix(color, u_sky_color * 0.9, haze_amount(length(u_eye - v_position)));
  out_color = vec4(encode_srgb(color), 1.0);
}
