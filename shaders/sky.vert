#version 330 core
// The sky, drawn first on the far plane without depth writes (everything
// after covers it), from gl_VertexID alone. DOME: a closed sphere of directions, coloured per
// vertex, so the gradient and the sun's glow cost nothing per pixel; its
// rings crowd near the horizon, where the gradient bends most. SUN: a small
// square around the sun, shaded per pixel for its sharp disc.
uniform mat4 u_view_projection; // directions have w = 0: the eye's position drops out
uniform vec3 u_sun_direction;
uniform vec3 u_sky_color;
uniform vec3 u_horizon_color;
uniform vec3 u_heading;         // the view's direction on the ground plane, normalised
uniform float u_below_horizon;  // how far below the horizon to draw, as a slope
#if DOME
out vec3 v_color; // encoded
#else
out vec3 v_ray;
#endif

const int segments = 48;
const int bands = 19;
const float ring_degrees[bands + 1] =
    float[](-90.0, -10.0, 0.0, 1.0, 2.5, 4.5, 7.0, 10.0, 14.0, 19.0, 25.0, 32.0, 39.0, 46.0, 53.0, 60.0, 68.0,
            76.0, 84.0, 90.0);
const float sun_square = 0.1; // half its side, as a slope from the sun: 5.7 degrees

void main() {
#if DOME
  // Two triangles per cell of the (segment, band) grid.
  int cell = gl_VertexID / 6, corner = gl_VertexID % 6;
  int around = cell % segments + ((corner == 1 || corner == 2 || corner == 4) ? 1 : 0);
  int ring = cell / segments + ((corner == 2 || corner == 4 || corner == 5) ? 1 : 0);
  float azimuth = radians(360.0) * float(around) / float(segments), elevation = radians(ring_degrees[ring]);
  vec3 ray = vec3(cos(elevation) * cos(azimuth), sin(elevation), cos(elevation) * sin(azimuth));
  v_color = encode_srgb(sky_radiance(ray, u_sun_direction, u_sky_color, u_horizon_color));
#else
  vec3 side = normalize(cross(u_sun_direction, abs(u_sun_direction.y) < 0.99 ? vec3(0, 1, 0) : vec3(1, 0, 0)));
  vec3 up = cross(side, u_sun_direction);
  vec2 offset = vec2((gl_VertexID == 1 || gl_VertexID == 2 || gl_VertexID == 4) ? 1.0 : -1.0,
                     (gl_VertexID == 2 || gl_VertexID == 4 || gl_VertexID == 5) ? 1.0 : -1.0);
  vec3 ray = u_sun_direction + sun_square * (offset.x * side + offset.y * up);
  v_ray = ray;
#endif
  // Clipped below the horizon where the ground's far edge lies: the ground
  // covers the rest, and a software renderer would shade each of its pixels
  // twice.
  gl_ClipDistance[0] = ray.y + u_below_horizon * dot(ray.xz, u_heading.xz);
  gl_Position = (u_view_projection * vec4(ray, 0.0)).xyww; // z = w: on the far plane
}
