#version 330 core
// One triangle covering the screen. The view ray is made here, per vertex:
// in homogeneous form (far point minus eye, scaled by the far point's w) it
// is linear across the screen, so interpolation gives every pixel its exact
// direction and the fragment shader only normalises it.
uniform mat4 u_inverse_view_projection;
uniform float u_below_horizon; // how far below the horizon to draw, as a slope
out vec3 v_ray;

// The (unnormalised) view ray through a point of the screen, in NDC.
vec3 ray_through(vec2 p) {
  // The eye is the clip-space point at infinity along z.
  vec4 eye = u_inverse_view_projection * vec4(0.0, 0.0, 1.0, 0.0);
  vec4 far_point = u_inverse_view_projection * vec4(p, 1.0, 1.0);
  return (far_point.xyz - eye.xyz / eye.w * far_point.w) * sign(far_point.w);
}

void main() {
  vec2 p = vec2((gl_VertexID == 1) ? 3.0 : -1.0, (gl_VertexID == 2) ? 3.0 : -1.0);
  v_ray = ray_through(p);
  // Clipped below the horizon where the ground's far edge lies (a slope
  // along the view's heading, which is linear across the screen too): the
  // ground covers the rest, and a software renderer would still test each
  // of its pixels.
  vec2 heading = normalize(ray_through(vec2(0.0)).xz + vec2(1e-6, 0.0));
  gl_ClipDistance[0] = v_ray.y + u_below_horizon * dot(v_ray.xz, heading);
  gl_Position = vec4(p, 1.0, 1.0);
}
