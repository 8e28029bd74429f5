// Prisms: a simple polygon extruded along the normal of its plane, for the
// procedural shapes that are not boxes or surfaces of revolution (a bridge's
// Pi-shaped side, a balcony's L). Closed by construction: the side quads and
// both caps use the same 2n positions, and each cap is cut into triangles by
// ear clipping over exactly the polygon's corners, so no cap edge ends in
// the middle of a side's edge (no T-junction) and every edge has two faces.
#include "bk_geom.h"

/// Twice the signed area of the 2D triangle a, b, c: positive when it turns
/// counter-clockwise.
static double turn(const double a[2], const double b[2], const double c[2]) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/// Whether p lies inside the counter-clockwise triangle a, b, c or on its
/// border: a corner on the border would be left in the middle of an ear's
/// edge, so it blocks the ear as surely as one inside.
static bool inside_or_on(const double a[2], const double b[2], const double c[2], const double p[2]) {
  return turn(a, b, p) >= 0.0 && turn(b, c, p) >= 0.0 && turn(c, a, p) >= 0.0;
}

/// Cuts the counter-clockwise simple polygon into count - 2 triangles of its
/// own corners (indices into profile, each triangle counter-clockwise); false
/// when no ear is left to clip (the polygon turns clockwise or crosses itself).
static bool clip_ears(const double (*profile)[2], uint32_t count, uint32_t (*triangles)[3]) {
  uint32_t left[BK_EXTRUSION_MAX_CORNERS] = {0};
  for (uint32_t i = 0; i < count; ++i)
    left[i] = i;
  uint32_t remaining = count, made = 0;
  while (remaining > 3) {
    bool clipped = false;
    for (uint32_t k = 0; k < remaining && !clipped; ++k) {
      uint32_t prev = left[(k + remaining - 1) % remaining], tip = left[k], next = left[(k + 1) % remaining];
      // A reflex or straight corner is no ear: its triangle would lie outside or be flat.
      if (turn(profile[prev], profile[tip], profile[next]) <= 0.0) continue;
      bool empty = true;
      for (uint32_t j = 0; j < remaining && empty; ++j) {
        uint32_t other = left[j];
        if (other == prev || other == tip || other == next) continue;
        empty = !inside_or_on(profile[prev], profile[tip], profile[next], profile[other]);
      }
      if (!empty) continue;
      triangles[made][0] = prev, triangles[made][1] = tip, triangles[made][2] = next;
      made++;
      for (uint32_t j = k; j + 1 < remaining; ++j)
        left[j] = left[j + 1];
      remaining--;
      clipped = true;
    }
    if (!clipped) return false;
  }
  if (turn(profile[left[0]], profile[left[1]], profile[left[2]]) <= 0.0) return false;
  triangles[made][0] = left[0], triangles[made][1] = left[1], triangles[made][2] = left[2];
  return true;
}

/// The texture directions of a flat face with outward normal n, as the
/// boxes' metre uvs have them: v runs up the face (world +y) on walls, u
/// along +x on floors and ceilings, and u x v = n so that no face shows its
/// texture mirrored. On an axis-aligned face these are the box's own axes.
static void face_uv_axes(bk_vec3 n, bk_vec3* u_axis, bk_vec3* v_axis) {
  const bk_vec3 up = bk_v3(0.0, 1.0, 0.0);
  if (fabs(n.y) > 1.0 - 1e-9) {
    *u_axis = bk_v3(1.0, 0.0, 0.0);
    *v_axis = bk_v3_cross(n, *u_axis);
  } else {
    *v_axis = bk_v3_normalize(bk_v3_sub(up, bk_v3_scale(n, n.y)));
    *u_axis = bk_v3_cross(*v_axis, n);
  }
}

/// Appends a corner of a flat face: its normal, and uvs in metres along the
/// face's texture directions (tangents come later, from all triangles).
static uint32_t add_face_corner(bk_mesh* m, uint32_t position, bk_vec3 n, bk_vec3 u_axis, bk_vec3 v_axis) {
  bk_vec3 p = m->positions[position];
  bk_corner c = {0};
  c.position = position;
  c.normal[0] = (float)n.x;
  c.normal[1] = (float)n.y;
  c.normal[2] = (float)n.z;
  c.uv[0] = (float)bk_v3_dot(p, u_axis);
  c.uv[1] = (float)bk_v3_dot(p, v_axis);
  return bk_mesh_add_corner(m, &c);
}

/// One cap: the ear triangles on the ring of positions starting at `ring`,
/// turned to face `n` (flipped for the back cap, whose normal is -depth).
static void add_cap(bk_mesh* m, const uint32_t (*triangles)[3], uint32_t count, uint32_t ring, bk_vec3 n,
                    bool flip) {
  bk_vec3 u_axis = {0}, v_axis = {0};
  face_uv_axes(n, &u_axis, &v_axis);
  const uint32_t first = m->corner_count;
  for (uint32_t i = 0; i < count; ++i)
    add_face_corner(m, ring + i, n, u_axis, v_axis);
  for (uint32_t t = 0; t + 2 < count; ++t) {
    uint32_t a = first + triangles[t][0], b = first + triangles[t][1], c = first + triangles[t][2];
    if (flip)
      bk_mesh_add_triangle(m, a, c, b, BK_MATERIAL_OUTER, 0);
    else
      bk_mesh_add_triangle(m, a, b, c, BK_MATERIAL_OUTER, 0);
  }
}

bool bk_shape_extrude(bk_mesh* m, const bk_extrusion* def) {
  const uint32_t n = def->corner_count;
  if (n < 3 || n > BK_EXTRUSION_MAX_CORNERS || !(def->depth_to > def->depth_from)) return false;
  uint32_t triangles[BK_EXTRUSION_MAX_CORNERS - 2][3] = {{0}};
  if (!clip_ears(def->profile, n, triangles)) return false;
  const bk_vec3 depth_axis = bk_v3_cross(def->x_axis, def->y_axis);

  // Positions: the polygon at depth_from (the back ring), then at depth_to.
  bk_mesh_reserve(m, m->position_count + 2 * n, m->corner_count + 6 * n, m->triangle_count + 4 * n - 4);
  const uint32_t back = m->position_count, front = back + n;
  for (uint32_t ring = 0; ring < 2; ++ring) {
    bk_vec3 along = bk_v3_scale(depth_axis, ring ? def->depth_to : def->depth_from);
    for (uint32_t i = 0; i < n; ++i) {
      bk_vec3 in_plane = bk_v3_add(bk_v3_scale(def->x_axis, def->profile[i][0]),
                                   bk_v3_scale(def->y_axis, def->profile[i][1]));
      bk_mesh_add_position(m, bk_v3_add(in_plane, along));
    }
  }

  // Sides: edge i -> j of a counter-clockwise polygon has the outside on its
  // right, edge x depth; (back i, back j, front j, front i) winds
  // counter-clockwise around that normal.
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t j = (i + 1) % n;
    bk_vec3 edge = bk_v3_sub(m->positions[back + j], m->positions[back + i]);
    bk_vec3 normal = bk_v3_normalize(bk_v3_cross(edge, depth_axis));
    bk_vec3 u_axis = {0}, v_axis = {0};
    face_uv_axes(normal, &u_axis, &v_axis);
    uint32_t a = add_face_corner(m, back + i, normal, u_axis, v_axis);
    uint32_t b = add_face_corner(m, back + j, normal, u_axis, v_axis);
    uint32_t c = add_face_corner(m, front + j, normal, u_axis, v_axis);
    uint32_t d = add_face_corner(m, front + i, normal, u_axis, v_axis);
    bk_mesh_add_triangle(m, a, b, c, BK_MATERIAL_OUTER, 0);
    bk_mesh_add_triangle(m, a, c, d, BK_MATERIAL_OUTER, 0);
  }
  // Caps: counter-clockwise in (x_axis, y_axis) faces +depth, so the front
  // takes the ears as they are and the back turns them over.
  add_cap(m, (const uint32_t(*)[3])triangles, n, front, depth_axis, false);
  add_cap(m, (const uint32_t(*)[3])triangles, n, back, bk_v3_scale(depth_axis, -1.0), true);
  return true;
}
