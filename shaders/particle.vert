#version 330 core
// Camera-facing quads, one instance per particle.
layout(location = 0) in vec2 in_corner;
layout(location = 1) in vec4 in_center_size; // xyz, size
layout(location = 2) in vec4 in_color;       // rgb, alpha
layout(location = 3) in float in_kind;       // 0 dust puff, 1 chip
uniform mat4 u_view_projection;
uniform vec3 u_camera_right;
uniform vec3 u_camera_up;
out vec2 v_corner;
out vec4 v_color;
out float v_kind;
void main() {
  vec3 p = in_center_size.xyz + (u_camera_right * in_corner.x + u_camera_up * in_corner.y) * in_center_size.w;
  v_corner = in_corner;
  v_color = vec4(encode_srgb(in_color.rgb), in_color.a); // one colour per particle: encoded here
  v_kind = in_kind;
  gl_Position = u_view_projection * vec4(p, 1.0);
}
