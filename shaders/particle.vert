#version 330 core
// Camera-facing quads, one instance per particle: dust puffs (kind 0) lit
// here, at the corners, and glints (kind 1) as given. Lighting per corner
// rather than per pixel: a puff is soft, and a software renderer pays per pixel.
layout(location = 0) in vec2 in_corner;
layout(location = 1) in vec4 in_center_size; // xyz, radius
layout(location = 2) in vec4 in_color;       // linear rgb, opacity
layout(location = 3) in vec2 in_kind_seed;   // kind (0 puff, 1 glint), shape seed
uniform mat4 u_view_projection;
uniform vec3 u_camera_right;
uniform vec3 u_camera_up;
uniform vec3 u_camera_back; // from the scene towards the eye
uniform vec3 u_eye;
uniform vec3 u_sun_direction;
uniform vec3 u_sun_color;
uniform vec3 u_sky_color;
uniform vec3 u_ground_color;
out vec2 v_corner;
out vec2 v_noise_uv;
out vec4 v_color;
flat out float v_kind;
out float v_ground; // height over the ground over the distance across which a puff fades into it
out float v_eye;    // distance from the eye along the view

void main() {
  float size = in_center_size.w;
  // The quad stands at the front of the ball it stands for: dust born at a
  // bond inside a wall still shows where it leaves the wall's face.
  vec3 p = in_center_size.xyz + (u_camera_right * in_corner.x + u_camera_up * in_corner.y + u_camera_back * 1.5) * size;
  v_corner = in_corner;
  // Each puff its own piece of the noise, turned its own way.
  float angle = fract(in_kind_seed.y * 0.618034) * 6.2831853;
  vec2 turned = mat2(cos(angle), sin(angle), -sin(angle), cos(angle)) * in_corner;
  v_noise_uv = turned * 0.45 + fract(in_kind_seed.y * vec2(0.1373, 0.7071));
  v_kind = in_kind_seed.x;
  vec3 color = in_color.rgb;
  if (in_kind_seed.x < 0.5) {
    // A ball of dust: the normal at the corner leans out of the ball and
    // towards the eye; the sun wraps round it (light passes through dust).
    vec3 n = normalize(u_camera_right * in_corner.x + u_camera_up * in_corner.y + u_camera_back * 0.8);
    float sun = clamp(dot(n, u_sun_direction) * 0.5 + 0.5, 0.0, 1.0);
    vec3 ambient = mix(u_ground_color, u_sky_color, n.y * 0.5 + 0.5) * 0.55;
    color *= ambient + u_sun_color * (0.15 + 0.45 * sun);
  }
  v_color = vec4(encode_srgb(color), in_color.a);
  v_ground = p.y / max(size, 0.01);
  v_eye = -dot(p - u_eye, u_camera_back);
  gl_Position = u_view_projection * vec4(p, 1.0);
}
