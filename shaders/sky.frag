#version 330 core
in vec3 v_ray;
uniform vec3 u_sun_direction;
uniform vec3 u_sky_color;
uniform vec3 u_horizon_color;
out vec4 out_color;
void main() {
  vec3 ray = normalize(v_ray);
  float up = clamp(ray.y, -0.2, 1.0);
  vec3 color = mix(u_horizon_color, u_sky_color, sqrt(max(up, 0.0)));
  // Sun disc and glow without pow(): it costs on software renderers.
  float sun = max(dot(ray, u_sun_direction), 0.0);
  float s4 = sun * sun;
  s4 *= s4;
  float glow = s4 * s4 * s4; // sun^12
  color += vec3(1.0, 0.9, 0.7) * (smoothstep(0.9990, 0.9996, sun) * 4.0 + glow * 0.25);
  out_color = vec4(encode_srgb(color), 1.0);
}
