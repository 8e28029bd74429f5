#version 330 core
// Fragments, projectiles and the ground (every program of mesh.frag):
// world-space lighting inputs plus the light-space position for the shadow
// lookup; SIMPLE lights the vertex here instead, and GROUND passes only what
// its pixels need (each interpolated value costs a software renderer). Each
// vertex names its row in a node table (per node: the three rows of its
// body's model matrix and an overlay colour), so every body of a tree draws
// in one call.
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
uniform vec3 u_ground_color;
uniform vec3 u_eye;
uniform vec3 u_tint;
uniform vec3 u_mean_color; // the material's mean albedo (or interior) colour
uniform float u_gloss;
out vec3 v_color;
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
#endif

void main() {
  int row = int(in_node) * 4;
  mat4 model = transpose(mat4(texelFetch(u_nodes, row), texelFetch(u_nodes, row + 1),
                              texelFetch(u_nodes, row + 2), vec4(0.0, 0.0, 0.0, 1.0)));
  vec4 world = model * vec4(in_position, 1.0);
  mat3 rotation = mat3(model);
  gl_Position = u_view_projection * world;
#if SIMPLE
  vec3 n = normalize(rotation * in_normal);
  vec3 to_eye = u_eye - world.xyz;
  vec3 light = (u_light_view_projection * world).xyz;
  float shadow = textureLod(u_shadow_map, shadow_clip(shadow_coord(light, n, u_sun_direction)), 0.0);
  vec3 color = light_surface(u_mean_color * u_tint, n, normalize(to_eye), shadow, u_gloss, u_sun_direction,
                             u_sun_color, u_sky_color, u_ground_color);
  vec4 highlight = texelFetch(u_nodes, row + 3);
  color = mix(color, highlight.rgb, highlight.a);
  color = mix(color, u_sky_color * 0.9, haze_amount(length(to_eye)));
  v_color = encode_srgb(color);
#elif GROUND
  v_ground = world.xz;
  v_shadow = shadow_coord((u_light_view_projection * world).xyz, vec3(0.0, 1.0, 0.0), u_sun_direction);
#else
  v_position = world.xyz;
  v_normal = rotation * in_normal;
  v_tangent = vec4(rotation * in_tangent.xyz, in_tangent.w);
  v_uv = in_uv * u_uv_scale;
  v_highlight = texelFetch(u_nodes, row + 3);
  v_light_position = (u_light_view_projection * world).xyz;
#endif
}
