#version 330 core
// A puff: noise under a soft round falloff, so no two share an outline and
// none has a hard edge; faded where it meets the ground and near the eye.
// A glint: a small four-pointed sparkle.
in vec2 v_corner;
in vec2 v_noise_uv;
in vec4 v_color;
flat in float v_kind;
in float v_ground;
in float v_eye;
uniform sampler2D u_noise;
uniform float u_near; // the near plane
out vec4 out_color;

void main() {
  float r2 = dot(v_corner, v_corner);
  if (r2 > 1.0) discard;
  float alpha;
  if (v_kind < 0.5) {
    float noise = texture(u_noise, v_noise_uv).r;
    float falloff = 1.0 - r2;
    // The noise eats the edge first: a ragged cloud, densest in the middle.
    float density = clamp(falloff * (0.2 + 1.9 * noise) - 0.2, 0.0, 1.0);
    float soft = clamp(v_ground, 0.0, 1.0) * clamp((v_eye - u_near) * 4.0, 0.0, 1.0);
    alpha = v_color.a * density * density * (3.0 - 2.0 * density) * soft;
  } else {
    vec2 a = abs(v_corner);
    float core = max(1.0 - sqrt(r2) * 3.0, 0.0);
    float rays = max(1.0 - a.x * 10.0, 0.0) * (1.0 - a.y) + max(1.0 - a.y * 10.0, 0.0) * (1.0 - a.x);
    alpha = v_color.a * min(core + rays, 1.0);
  }
  out_color = vec4(v_color.rgb, alpha);
}
