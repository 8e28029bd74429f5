#version 330 core
// One triangle covering the screen. The view ray is made here, per vertex:
// in homogeneous form (far point minus eye, scaled by the far point's w) it
// is linear across the screen, so interpolation gives every pixel its exact
// direction and the fragment shader only normalises it.
uniform mat4 u_inverse_view_projection;
out vec3 v_ray;
void main() {
  vec2 p = vec2((gl_VertexID == 1) ? 3.0 : -1.0, (gl_VertexID == 2) ? 3.0 : -1.0);
  // The eye is the clip-space point at infinity along z.
  vec4 eye = u_inverse_view_projection * vec4(0.0, 0.0, 1.0, 0.0);
  vec4 far_point = u_inverse_view_projection * vec4(p, 1.0, 1.0);
  v_ray = (far_point.xyz - eye.xyz / eye.w * far_point.w) * sign(far_point.w);
  gl_Position = vec4(p, 1.0, 1.0);
}
