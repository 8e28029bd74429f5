#version 330 core
// Sun with a soft shadow map, hemisphere ambient, normal-mapped outer
// surface, separate texture for interior (cut) faces, and a distance haze
// that matches the sky.
in vec3 v_position;
in vec3 v_normal;
in vec4 v_tangent;
in vec2 v_uv;
in float v_interior;
in vec4 v_light_position;
flat in vec4 v_highlight; // overlay colour of the node: rgb, strength (0 = none)

uniform sampler2D u_albedo;
uniform sampler2D u_normal_map;
uniform sampler2D u_interior;
uniform sampler2DShadow u_shadow_map;
uniform vec3 u_sun_direction; // towards the sun
uniform vec3 u_sun_color;
uniform vec3 u_sky_color;
uniform vec3 u_ground_color;
uniform vec3 u_eye;
uniform vec3 u_tint;
uniform float u_interior_scale;
uniform float u_gloss;
uniform int u_detail; // 0: the ground, lit cheaply (it covers most of the screen)

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
  vec3 n = normalize(v_normal);
  if (u_detail == 0) {
    vec3 ground = texture(u_albedo, v_uv).rgb * u_tint;
    float lit = max(dot(n, u_sun_direction), 0.0) * shadow_factor(n);
    vec3 sky_light = mix(u_ground_color, u_sky_color, n.y * 0.5 + 0.5) * 0.55;
    float fog = haze_amount(length(u_eye - v_position));
    out_color = vec4(mix(ground * (sky_light + u_sun_color * lit), u_sky_color * 0.9, fog), 1.0);
    return;
  }
  vec3 albedo;
  if (v_interior > 0.5) {
    albedo = texture(u_interior, v_uv * u_interior_scale).rgb;
  } else {
    albedo = texture(u_albedo, v_uv).rgb;
    vec3 t = normalize(v_tangent.xyz - n * dot(n, v_tangent.xyz));
    vec3 b = cross(n, t) * v_tangent.w;
    vec3 m = texture(u_normal_map, v_uv).xyz * 2.0 - 1.0;
    n = normalize(mat3(t, b, n) * m);
  }
  albedo *= u_tint;
  vec3 view = normalize(u_eye - v_position);
  float diffuse = max(dot(n, u_sun_direction), 0.0);
  float shadow = shadow_factor(normalize(v_normal));
  vec3 half_vector = normalize(u_sun_direction + view);
  // Schlick's rational stand-in for pow(x, e): one division instead of a
  // log and an exp per pixel, which a software renderer pays in full.
  float x = max(dot(n, half_vector), 0.0), e = mix(16.0, 96.0, u_gloss);
  float specular = x / (e - e * x + x) * mix(0.04, 0.5, u_gloss);
  vec3 ambient = mix(u_ground_color, u_sky_color, n.y * 0.5 + 0.5) * 0.55;
  vec3 color = albedo * (ambient + u_sun_color * diffuse * shadow) + u_sun_color * specular * shadow;
  color = mix(color, v_highlight.rgb, v_highlight.a);
  float haze = haze_amount(length(u_eye - v_position));
  color = mix(color, u_sky_color * 0.9, haze);
  out_color = vec4(color, 1.0); // the framebuffer encodes sRGB
}
