#version 330 core
in vec2 v_ndc;
uniform mat4 u_inverse_view_projection;
uniform vec3 u_sun_direction;
uniform vec3 u_sky_color;
uniform vec3 u_horizon_color;
out vec4 out_color;
void main() {
  vec4 far_point = u_inverse_view_projection * vec4(v_ndc, 1.0, 1.0);
  vec4 near_point = u_inverse_view_projection * vec4(v_ndc, -1.0, 1.0);
  vec3 ray = normalize(far_point.xyz / far_point.w - near_point.xyz / near_point.w);
  float up = clamp(ray.y, -0.2, 1.0);
  vec3 color = mix(u_horizon_color, u_sky_color, pow(max(up, 0.0), 0.6));
  float sun = max(dot(ray, u_sun_direction), 0.0);
  color += vec3(1.0, 0.9, 0.7) * (pow(sun, 800.0) * 4.0 + pow(sun, 12.0) * 0.25);
  out_color = vec4(color, 1.0); // the framebuffer encodes sRGB
}
