#version 330 core
// Fragments, projectiles and the ground (every program of mesh.frag):
// world-space lighting inputs plus the light-space position for the shadow
// lookup; SIMPLE lights the vertex here instead, and GROUND passes only what
// its pixels need (each interpolated value costs a software renderer). Each
// vertex names its row in a node table (per node: the three rows of its
// body's model matrix, an overlay colour and its fade), so every body of a
// tree draws in one call. GLASS (with SURFACE, INTERIOR or SIMPLE) is drawn
// blended: SIMPLE GLASS passes the light its glass adds and lets through.
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 3) in vec4 in_tangent;
layout(location = 5) in uint in_node;

uniform samplerBuffer u_nodes;
uniform mat4 u_view_projection;
uniform mat4 u_light_view_projection;
uniform float u_uv_scale;

#if SIMPLE
uniform sampler2DShadow u_shadow_map;
uniform vec3 u_sun_direction;
uniform vec3 u_sun_color;
uniform vec3 u_sky_color;
uniform vec3 u_horizon_color;
uniform vec3 u_ground_color;
uniform vec3 u_eye;
uniform vec3 u_tint;
uniform vec3 u_mean_color; // the material's mean albedo (or interior) colour
uniform vec3 u_transmit;   // GLASS: what a surface lets through
uniform float u_gloss;
out vec3 v_color;
#if GLASS
out vec3 v_through; // encoded: it multiplies the encoded background
#endif
flat out float v_fade; // share of the node's pixels left out (bk_node_draw.fade)
#elif GROUND
uniform vec3 u_sun_direction;
out vec2 v_ground; // x and z in metres: the position, and the uvs before scaling
out vec3 v_shadow; // shadow_coord, linear across the plane
#else
out vec3 v_position;
out vec3 v_normal;
out vec4 v_tangent;
out vec2 v_uv;
out vec3 v_light_position;
flat out vec4 v_highlight; // overlay rgb, strength; one per node, so no interpolation
flat out float v_fade;     // share of the node's pixels left out (bk_node_draw.fade)
#endif

void main() {
  int row = int(in_node) * 5;
  mat4 model = transpose(mat4(texelFetch(u_nodes, row), texelFetch(u_nodes, row + 1),
                              texelFetch(u_nodes, row + 2), vec4(0.0, 0.0, 0.0, 1.0)));
  vec4 world = model * vec4(in_position, 1.0);
  mat3 rotation = mat3(model);
  gl_Position = u_view_projection * world;
#if SIMPLE
  vec3 n = normalize(rotation * in_normal);
  vec3 to_eye = u_eye - world.xyz;
  vec3 view = normalize(to_eye);
  vec3 light = (u_light_view_projection * world).xyz;
  float shadow = textureLod(u_shadow_map, shadow_clip(shadow_coord(light, n, u_sun_direction)), 0.0);
  vec4 highlight = texelFetch(u_nodes, row + 3);
  float haze = haze_amount(length(to_eye));
#if GLASS
  // Shards a few pixels wide: seen from either side, lit per vertex.
  n = dot(n, view) < 0.0 ? -n : n;
  vec3 through = vec3(1.0);
  vec3 color = light_glass(n, view, u_transmit, u_mean_color * 0.1, shadow, u_sun_direction, u_sun_color,
                           u_sky_color, u_horizon_color, u_ground_color, through);
  color = mix(tone(color), highlight.rgb, highlight.a) * (1.0 - haze);
  v_through = encode_srgb(mix(through * (1.0 - highlight.a), vec3(1.0), haze));
  v_color = color;
#else
  vec3 color = light_surface(u_mean_color * u_tint, n, view, shadow, u_gloss, u_sun_direction, u_sun_color,
                             u_sky_color, u_ground_color);
  color = mix(tone(color), highlight.rgb, highlight.a);
  color = mix(color, u_sky_color * 0.9, haze);
  v_color = encode_srgb(color);
#endif
  v_fade = texelFetch(u_nodes, row + 4).x;
#elif GROUND
  v_ground = world.xz;
  v_shadow = shadow_coord((u_light_view_projection * world).xyz, vec3(0.0, 1.0, 0.0), u_sun_direction);
#else
  v_position = world.xyz;
  v_normal = rotation * in_normal;
  v_tangent = vec4(rotation * in_tangent.xyz, in_tangent.w);
  v_uv = in_uv * u_uv_scale;
  v_highlight = texelFetch(u_nodes, row + 3);
  v_fade = texelFetch(u_nodes, row + 4).x;
  v_light_position = (u_light_view_projection * world).xyz;
#endif
}
