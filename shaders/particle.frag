#version 330 core
in vec2 v_corner;
in vec4 v_color;
in float v_kind;
out vec4 out_color;
void main() {
  float r = length(v_corner);
  if (r > 1.0) discard;
  // Dust is a soft disc; chips are hard-edged flecks.
  float alpha = v_kind < 0.5 ? v_color.a * (1.0 - r * r) * (1.0 - r) : v_color.a * step(r, 0.8);
  out_color = vec4(v_color.rgb, alpha);
}
