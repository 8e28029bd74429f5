#version 330 core
// See sky.vert: DOME passes its colour through; SUN adds the disc.
#if DOME
in vec3 v_color;
#else
in vec3 v_ray;
uniform vec3 u_sun_direction;
uniform vec3 u_sky_color;
uniform vec3 u_horizon_color;
#endif
out vec4 out_color;

void main() {
#if DOME
  out_color = vec4(v_color, 1.0);
#else
  vec3 ray = normalize(v_ray);
  vec3 color = sky_radiance(ray, u_sun_direction, u_sky_color, u_horizon_color);
  color += vec3(1.0, 0.9, 0.7) * smoothstep(0.9990, 0.9996, dot(ray, u_sun_direction)) * 4.0;
  out_color = vec4(encode_srgb(color), 1.0);
#endif
}
