#version 330 core
// Sun with a soft shadow map, hemisphere ambient and a distance haze that
// matches the sky. Four programs come from this file and mesh.vert (the
// renderer defines one macro): SURFACE, an object's outer surface with its
// normal map; INTERIOR, cut faces with their own texture; SIMPLE, pieces a
// few pixels wide, lit per vertex in their material's mean colours; GROUND,
// the flat paving. A software renderer runs both sides of every branch, so
// each program holds only the work its pixels need.
#if SIMPLE
in vec3 v_color; // lit, hazed and encoded per vertex
#elif GROUND
in vec2 v_ground;
in vec3 v_shadow;

uniform sampler2D u_albedo;
uniform sampler2DShadow u_shadow_map;
uniform vec3 u_sun_direction;
uniform vec3 u_sun_color;
uniform vec3 u_sky_color;
uniform vec3 u_eye;
uniform vec3 u_tint;
uniform float u_uv_scale;
#else
in vec3 v_position;
in vec3 v_normal;
in vec4 v_tangent;
in vec2 v_uv;
in vec3 v_light_position;
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
#endif

out vec4 out_color;

void main() {
#if SIMPLE
  out_color = vec4(v_color, 1.0);
#elif GROUND
  // Flat and facing up: the sun and the sky light are the same everywhere.
  // One hardware-filtered shadow tap is already a 2x2 comparison.
  vec3 albedo = decode_srgb(texture(u_albedo, v_ground * u_uv_scale).rgb) * u_tint;
  float lit = max(u_sun_direction.y, 0.0) * texture(u_shadow_map, shadow_clip(v_shadow));
  vec3 color = albedo * (u_sky_color * 0.55 + u_sun_color * lit);
  color = mix(color, u_sky_color * 0.9, haze_amount(length(u_eye - vec3(v_ground.x, 0.0, v_ground.y))));
  out_color = vec4(encode_srgb(color), 1.0);
#else
  vec3 geometric = normalize(v_normal);
#if INTERIOR
  vec3 albedo = decode_srgb(texture(u_albedo, v_uv * u_interior_scale).rgb) * u_tint;
  vec3 n = geometric;
#else
  vec3 albedo = decode_srgb(texture(u_albedo, v_uv).rgb) * u_tint;
  vec3 t = normalize(v_tangent.xyz - geometric * dot(geometric, v_tangent.xyz));
  vec3 b = cross(geometric, t) * v_tangent.w;
  vec3 m = texture(u_normal_map, v_uv).xyz * 2.0 - 1.0;
  vec3 n = normalize(mat3(t, b, geometric) * m);
#endif
  float shadow = texture(u_shadow_map, shadow_clip(shadow_coord(v_light_position, geometric, u_sun_direction)));
  vec3 color = light_surface(albedo, n, normalize(u_eye - v_position), shadow, u_gloss, u_sun_direction,
                             u_sun_color, u_sky_color, u_ground_color);
  color = mix(color, v_highlight.rgb, v_highlight.a);
  color = mix(color, u_sky_color * 0.9, haze_amount(length(u_eye - v_position)));
  out_color = vec4(encode_srgb(color), 1.0);
#endif
}
