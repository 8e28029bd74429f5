#version 330 core
// Debris chips: one of a few small convex shapes of radius 1, per instance
// turned by a quaternion, scaled and placed; textured with the material's
// interior on every face (uvs lie in each face's plane).
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 3) in vec4 in_center_size; // xyz, radius
layout(location = 4) in vec4 in_rotation;    // quaternion x, y, z, w
layout(location = 5) in vec4 in_tint_fade;   // linear rgb (all zero = white), fade
uniform mat4 u_view_projection;
out vec3 v_position;
out vec3 v_normal;
out vec2 v_uv;
flat out vec3 v_tint;
flat out float v_fade;

vec3 rotate(vec4 q, vec3 v) { return v + 2.0 * cross(q.xyz, cross(q.xyz, v) + q.w * v); }

void main() {
  float length2 = dot(in_rotation, in_rotation);
  vec4 q = length2 > 1e-12 ? in_rotation * inversesqrt(length2) : vec4(0.0, 0.0, 0.0, 1.0);
  vec3 p = in_center_size.xyz + rotate(q, in_position) * in_center_size.w;
  v_position = p;
  v_normal = rotate(q, in_normal);
  // A few centimetres of the texture, a different part for each chip.
  v_uv = in_uv * 0.06 + fract(in_center_size.xz * 7.31 + in_center_size.y * 3.17);
  v_tint = dot(in_tint_fade.rgb, vec3(1.0)) > 0.0 ? in_tint_fade.rgb : vec3(1.0);
  float fade = in_tint_fade.a;
  v_fade = fade == fade ? clamp(fade, 0.0, 1.0) : 0.0; // NaN: drawn
  gl_Position = u_view_projection * vec4(p, 1.0);
}
