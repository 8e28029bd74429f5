#version 330 core
// Sun with a soft shadow map, hemisphere ambient and a distance haze that
// matches the sky. The programs come from this file and mesh.vert (the
// renderer defines their macros): SURFACE, an object's outer surface with
// its normal map (with GLAZE, a clear coat over it: porcelain, eggshell);
// INTERIOR, cut faces with their own texture and relief, the relief's
// occlusion darkening the sky's light; SIMPLE, pieces a few pixels wide, lit
// per vertex in their material's mean colours; GROUND, the flat paving.
// GLASS (with SURFACE, INTERIOR or SIMPLE) writes two colours for
// dual-source blending: the light the glass adds, and the share of the
// background it lets through. A software renderer runs both sides of every
// branch, so each program holds only the work its pixels need. Nodes that
// fade out (all but GROUND) leave out a dithered share of their pixels.
#if SIMPLE
in vec3 v_color; // lit, hazed and (but for GLASS) encoded per vertex
#if GLASS
in vec3 v_through;
#endif
flat in float v_fade;
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
flat in float v_fade;     // share of the node's pixels to leave out

uniform sampler2D u_albedo;     // the interior texture in INTERIOR
uniform sampler2D u_normal_map; // in INTERIOR the cut faces' relief, occlusion in alpha
uniform sampler2DShadow u_shadow_map;
uniform vec3 u_sun_direction; // towards the sun
uniform vec3 u_sun_color;
uniform vec3 u_sky_color;
uniform vec3 u_horizon_color;
uniform vec3 u_ground_color;
uniform vec3 u_eye;
uniform vec3 u_tint;
uniform vec3 u_transmit; // GLASS: what an outer surface lets through head on
uniform float u_interior_scale;
uniform float u_gloss;
uniform float u_glaze; // GLAZE: the coat's strength
#endif

#if GLASS
layout(location = 0, index = 0) out vec4 out_color;    // added to the background
layout(location = 0, index = 1) out vec4 out_transmit; // multiplies the background
#else
out vec4 out_color;
#endif

void main() {
#if !GROUND
  if (v_fade > dither_threshold(gl_FragCoord.xy)) discard;
#endif
#if SIMPLE
  out_color = vec4(v_color, 1.0);
#if GLASS
  out_transmit = vec4(v_through, 1.0);
#endif
#elif GROUND
  // Flat and facing up: the sun and the sky light are the same everywhere.
  // One hardware-filtered shadow tap is already a 2x2 comparison.
  vec3 albedo = decode_srgb(texture(u_albedo, v_ground * u_uv_scale).rgb) * u_tint;
  float lit = max(u_sun_direction.y, 0.0) * texture(u_shadow_map, shadow_clip(v_shadow));
  vec3 color = tone(albedo * (u_sky_color * 0.55 + u_sun_color * lit));
  color = mix(color, u_sky_color * 0.9, haze_amount(length(u_eye - vec3(v_ground.x, 0.0, v_ground.y))));
  out_color = vec4(encode_srgb(color), 1.0);
#else
  vec3 geometric = normalize(v_normal);
#if GLASS
  // Back faces (drawn first, through the front ones) are lit from inside.
  geometric = gl_FrontFacing ? geometric : -geometric;
#endif
#if INTERIOR
  vec2 uv = v_uv * u_interior_scale;
#else
  vec2 uv = v_uv;
#endif
  // The maps' +Y runs towards their first row, which is v = 0: down the v axis.
  vec4 relief = texture(u_normal_map, uv);
  vec3 t = normalize(v_tangent.xyz - geometric * dot(geometric, v_tangent.xyz));
  vec3 b = cross(geometric, t) * v_tangent.w;
  vec3 n = normalize(mat3(t, -b, geometric) * (relief.xyz * 2.0 - 1.0));
  vec3 view = normalize(u_eye - v_position);
  float shadow = texture(u_shadow_map, shadow_clip(shadow_coord(v_light_position, geometric, u_sun_direction)));
  float haze = haze_amount(length(u_eye - v_position));
#if GLASS
#if INTERIOR
  // A cut through glass is a rough edge seen through the thickness: greener,
  // letting less through, and scattering back the sun and sky that catch
  // it. A crack is two faces (one of each piece), and a broken body has
  // many: each lets through a little more than half its tint's darkening.
  vec3 body = decode_srgb(texture(u_albedo, uv).rgb);
  vec3 transmit = mix(vec3(1.0), body, 0.45), scatter = body * 0.2;
#else
  vec3 transmit = u_transmit, scatter = vec3(0.0);
#endif
  vec3 through = vec3(1.0);
  vec3 color = light_glass(n, view, transmit, scatter, shadow, u_sun_direction, u_sun_color, u_sky_color,
                           u_horizon_color, u_ground_color, through);
  color = mix(tone(color), v_highlight.rgb, v_highlight.a) * (1.0 - haze);
  out_color = vec4(color, 1.0);
  out_transmit = vec4(encode_srgb(mix(through * (1.0 - v_highlight.a), vec3(1.0), haze)), 1.0);
#else
#if INTERIOR
  // The relief's occlusion darkens the sky's light only: the colour map
  // already holds part of it, and the sun reaches into no crevice it knows of.
  vec3 albedo = decode_srgb(texture(u_albedo, uv).rgb) * u_tint;
  vec3 color = light_surface_occluded(albedo, n, view, shadow, u_gloss, u_sun_direction, u_sun_color,
                                      u_sky_color, u_ground_color, relief.a);
#else
  vec3 albedo = decode_srgb(texture(u_albedo, uv).rgb) * u_tint;
  vec3 color = light_surface(albedo, n, view, shadow, u_gloss, u_sun_direction, u_sun_color, u_sky_color,
                             u_ground_color);
#endif
#if GLAZE
  // A clear coat over the body, smooth whatever the body's relief: it
  // mirrors the sky as glass does and takes a sharp highlight of the sun.
  float coat = fresnel(dot(geometric, view)) * u_glaze;
  color = mix(color, mirrored(geometric, view, u_sun_direction, u_sky_color, u_horizon_color, u_ground_color),
              coat) +
          u_sun_color * (sharp_highlight(geometric, view, u_sun_direction) * shadow * u_glaze);
#endif
  color = mix(tone(color), v_highlight.rgb, v_highlight.a);
  color = mix(color, u_sky_color * 0.9, haze);
  out_color = vec4(encode_srgb(color), 1.0);
#endif
#endif
}
