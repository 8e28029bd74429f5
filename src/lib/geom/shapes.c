// Procedural test meshes. Every shape is built closed by construction: corners
// that sit on a UV or normal seam are duplicated but reuse the welded position,
// so topology (carried by position indices) never sees the seam.
//
// Conventions shared by the builders: y is up; surfaces of revolution turn
// around +y with points (r cos phi, y, -r sin phi), which makes
// d/dphi x d/dy point outward, so quads listed as (phi, y) -> (phi + 1, y) ->
// (phi + 1, y + 1) -> (phi, y + 1) wind counter-clockwise seen from outside and
// u along phi / v along y is an unmirrored mapping.
#include <string.h>

#include "bk_geom.h"

#define BK_PI 3.14159265358979323846

static const char* const shape_names[BK_SHAPE_COUNT] = {
    [BK_SHAPE_CUBE] = "cube",   [BK_SHAPE_TORUS] = "torus",   [BK_SHAPE_EGGSHELL] = "eggshell",
    [BK_SHAPE_WALL] = "wall",   [BK_SHAPE_SLAB] = "slab",     [BK_SHAPE_PILLAR] = "pillar",
    [BK_SHAPE_TOWER] = "tower", [BK_SHAPE_BRIDGE] = "bridge", [BK_SHAPE_BALCONY] = "balcony",
};

const char* bk_shape_name(bk_shape shape) {
  // A string rather than NULL so callers can print any value without checking.
  if ((unsigned)shape >= (unsigned)BK_SHAPE_COUNT) return "unknown";
  return shape_names[shape];
}

bool bk_shape_from_name(const char* name, bk_shape* out) {
  if (!name) return false;
  for (int i = 0; i < BK_SHAPE_COUNT; ++i) {
    if (strcmp(name, shape_names[i]) == 0) {
      if (out) *out = (bk_shape)i;
      return true;
    }
  }
  return false;
}

// ---------------------------------------------------------------- helpers

/// Appends a corner with the given normal and uv; tangents are filled in by
/// bk_mesh_compute_tangents once all triangles exist.
static uint32_t add_corner(bk_mesh* m, uint32_t position, bk_vec3 normal, double u, double v) {
  bk_corner c = {0};
  c.position = position;
  c.normal[0] = (float)normal.x;
  c.normal[1] = (float)normal.y;
  c.normal[2] = (float)normal.z;
  c.uv[0] = (float)u;
  c.uv[1] = (float)v;
  return bk_mesh_add_corner(m, &c);
}

static void add_outer_triangle(bk_mesh* m, uint32_t a, uint32_t b, uint32_t c) {
  bk_mesh_add_triangle(m, a, b, c, BK_MATERIAL_OUTER, 0);
}

/// Two triangles for a quad whose corners a, b, c, d are counter-clockwise from outside.
static void add_quad(bk_mesh* m, uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
  add_outer_triangle(m, a, b, c);
  add_outer_triangle(m, a, c, d);
}

// ---------------------------------------------------------------- boxes

/// How box faces are textured.
typedef enum box_uv {
  BOX_UV_UNIT,   ///< each face maps to the whole 0..1 square
  BOX_UV_METRES, ///< uv = world coordinates along the face, so textures tile at a fixed scale
} box_uv;

/// One box face: outward axis plus the world directions of +u and +v, with
/// u x v == normal so the texture is not mirrored when seen from outside.
typedef struct box_face {
  int normal[3], u[3], v[3];
} box_face;

static const box_face box_faces[6] = {
    {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
    {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
    {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
};

static bk_vec3 int3_to_vec(const int a[3]) { return bk_v3(a[0], a[1], a[2]); }

/// Axis-aligned box from lo to hi: 8 positions, 4 corners per face with the
/// flat face normal, 12 triangles.
static void build_box(bk_mesh* m, bk_vec3 lo, bk_vec3 hi, box_uv uv_mode) {
  bk_mesh_reserve(m, 8, 24, 12);
  // Position index bit 0/1/2 = upper x/y/z, so a corner's signs pick its position.
  for (uint32_t i = 0; i < 8; ++i) {
    bk_vec3 p = bk_v3((i & 1u) ? hi.x : lo.x, (i & 2u) ? hi.y : lo.y, (i & 4u) ? hi.z : lo.z);
    bk_mesh_add_position(m, p);
  }
  // Counter-clockwise in the face's (u, v) frame, hence from outside.
  static const int quad_signs[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (int f = 0; f < 6; ++f) {
    const box_face* face = &box_faces[f];
    bk_vec3 n = int3_to_vec(face->normal), ud = int3_to_vec(face->u), vd = int3_to_vec(face->v);
    uint32_t quad[4] = {0};
    for (int k = 0; k < 4; ++k) {
      int su = quad_signs[k][0], sv = quad_signs[k][1];
      uint32_t index = 0;
      for (int axis = 0; axis < 3; ++axis) {
        int sign = face->normal[axis] + su * face->u[axis] + sv * face->v[axis];
        if (sign > 0) index |= 1u << axis;
      }
      bk_vec3 p = m->positions[index];
      double u = 0.0, v = 0.0;
      if (uv_mode == BOX_UV_UNIT) {
        u = 0.5 * (su + 1);
        v = 0.5 * (sv + 1);
      } else {
        u = bk_v3_dot(p, ud);
        v = bk_v3_dot(p, vd);
      }
      quad[k] = add_corner(m, index, n, u, v);
    }
    add_quad(m, quad[0], quad[1], quad[2], quad[3]);
  }
}

// ---------------------------------------------------------------- torus

// 48 x 24: at 20 x 20 the ring's outline was a visible polygon (18 degrees a
// side) and its shading bent at every edge; the normals were smooth, the
// silhouette and the interpolation across long quads were not.
enum { TORUS_RING_SEGMENTS = 48, TORUS_TUBE_SEGMENTS = 24 };
#define TORUS_MAJOR_RADIUS 1.0
#define TORUS_MINOR_RADIUS 0.35
// The ring is about 2.9x longer than the tube's girth (2*pi*1.0 vs 2*pi*0.35),
// so three texture repeats around the ring keep texels close to square.
#define TORUS_U_REPEATS 3.0

static void build_torus(bk_mesh* m) {
  const uint32_t n = TORUS_RING_SEGMENTS, k = TORUS_TUBE_SEGMENTS;
  bk_mesh_reserve(m, n * k, (n + 1) * (k + 1), 2 * n * k);
  for (uint32_t i = 0; i < n; ++i) {
    double phi = 2.0 * BK_PI * i / n;
    for (uint32_t j = 0; j < k; ++j) {
      double theta = 2.0 * BK_PI * j / k;
      double rho = TORUS_MAJOR_RADIUS + TORUS_MINOR_RADIUS * bk_cos(theta);
      bk_mesh_add_position(m,
                           bk_v3(rho * bk_cos(phi), TORUS_MINOR_RADIUS * bk_sin(theta), -rho * bk_sin(phi)));
    }
  }
  // (n + 1) x (k + 1) corners: the last row and column repeat the first
  // positions with u = repeats / v = 1 so the texture wraps without a jump.
  for (uint32_t i = 0; i <= n; ++i) {
    double phi = 2.0 * BK_PI * i / n;
    for (uint32_t j = 0; j <= k; ++j) {
      double theta = 2.0 * BK_PI * j / k;
      bk_vec3 normal = bk_v3(bk_cos(theta) * bk_cos(phi), bk_sin(theta), -bk_cos(theta) * bk_sin(phi));
      uint32_t position = (i % n) * k + (j % k);
      add_corner(m, position, normal, TORUS_U_REPEATS * i / n, (double)j / k);
    }
  }
  for (uint32_t i = 0; i < n; ++i) {
    for (uint32_t j = 0; j < k; ++j) {
      uint32_t c00 = i * (k + 1) + j, c10 = (i + 1) * (k + 1) + j;
      add_quad(m, c00, c10, c10 + 1, c00 + 1);
    }
  }
}

// ---------------------------------------------------------------- eggshell

// 20 segments x 19 rings per surface gives 2 * (21 * 19 + 2 * 20) = 878 corners
// and 4 * 20 * 19 = 1520 triangles, the resolution of the reference egg.
enum { EGG_SEGMENTS = 20, EGG_RINGS = 19 };
// Profile r(t) = a sin t (1 + k cos t), y(t) = b (1 - cos t), t in [0, pi]:
// an ellipse of half-height b whose radius is scaled up near the bottom
// (cos t > 0) and down near the top, the classic egg shape. b = 0.3 makes it
// 0.6 tall; a = 0.2208 puts the widest point (t ~ 79 deg) at 0.45 across.
#define EGG_A 0.2208
#define EGG_B 0.3
#define EGG_K 0.2
#define EGG_THICKNESS 0.03
// The girth (~1.4) is about twice the meridian length (~0.85).
#define EGG_U_REPEATS 2.0

/// Point of the outer profile and its outward unit normal in the (r, y) plane.
static void egg_profile(double t, double* r, double* y, double* nr, double* ny) {
  double s = bk_sin(t), c = bk_cos(t);
  *r = EGG_A * s * (1.0 + EGG_K * c);
  *y = EGG_B * (1.0 - c);
  // Tangent (dr/dt, dy/dt) turned clockwise points away from the axis.
  double dr = EGG_A * (c + EGG_K * (c * c - s * s)), dy = EGG_B * s;
  double len = sqrt(dr * dr + dy * dy);
  *nr = dy / len;
  *ny = -dr / len;
}

/// One closed surface of revolution for the shell. The outer surface faces
/// away from the axis; the inner one is the profile offset inward by the shell
/// thickness (the profile's curvature radius stays above it, so the offset
/// curve is clean) with reversed winding and normals, facing the cavity.
static void build_egg_surface(bk_mesh* m, bool inner) {
  const uint32_t segs = EGG_SEGMENTS, rings = EGG_RINGS;
  const double offset = inner ? EGG_THICKNESS : 0.0, facing = inner ? -1.0 : 1.0;
  const uint32_t p0 = m->position_count;
  // Positions: bottom pole, rings bottom to top (segs each), top pole.
  bk_vec3 ring_normal[EGG_RINGS + 2];
  double ring_r[EGG_RINGS + 2], ring_y[EGG_RINGS + 2];
  for (uint32_t i = 0; i <= rings + 1; ++i) {
    double r = 0.0, y = 0.0, nr = 0.0, ny = 0.0;
    egg_profile(BK_PI * i / (rings + 1), &r, &y, &nr, &ny);
    ring_r[i] = r - offset * nr;
    ring_y[i] = y - offset * ny;
    ring_normal[i] = bk_v3(nr * facing, ny * facing, 0.0);
  }
  // The poles lie on the axis exactly (sin 0 = sin pi = 0 in the profile, and
  // the normal there is vertical), so no offset can move them off it.
  ring_r[0] = ring_r[rings + 1] = 0.0;
  const uint32_t bottom = bk_mesh_add_position(m, bk_v3(0.0, ring_y[0], 0.0));
  for (uint32_t i = 1; i <= rings; ++i) {
    for (uint32_t j = 0; j < segs; ++j) {
      double phi = 2.0 * BK_PI * j / segs;
      bk_mesh_add_position(m, bk_v3(ring_r[i] * bk_cos(phi), ring_y[i], -ring_r[i] * bk_sin(phi)));
    }
  }
  const uint32_t top = bk_mesh_add_position(m, bk_v3(0.0, ring_y[rings + 1], 0.0));

  // Corners: a (segs + 1)-wide grid per ring (seam column duplicated for u),
  // then one corner per segment at each pole so each fan triangle gets the u
  // of its own segment instead of a pinched texture.
  const uint32_t c0 = m->corner_count;
  for (uint32_t i = 1; i <= rings; ++i) {
    double v = (double)i / (rings + 1);
    for (uint32_t j = 0; j <= segs; ++j) {
      double phi = 2.0 * BK_PI * j / segs;
      double c = bk_cos(phi), s = bk_sin(phi);
      bk_vec3 n = bk_v3(ring_normal[i].x * c, ring_normal[i].y, -ring_normal[i].x * s);
      // Running u backwards inside keeps the texture unmirrored once the winding flips.
      double u = EGG_U_REPEATS * (inner ? 1.0 - (double)j / segs : (double)j / segs);
      uint32_t position = p0 + 1 + (i - 1) * segs + (j % segs);
      add_corner(m, position, n, u, v);
    }
  }
  const uint32_t bottom_corners = m->corner_count;
  for (uint32_t j = 0; j < segs; ++j) {
    double u = EGG_U_REPEATS * (inner ? 1.0 - (j + 0.5) / segs : (j + 0.5) / segs);
    add_corner(m, bottom, ring_normal[0], u, 0.0);
  }
  const uint32_t top_corners = m->corner_count;
  for (uint32_t j = 0; j < segs; ++j) {
    double u = EGG_U_REPEATS * (inner ? 1.0 - (j + 0.5) / segs : (j + 0.5) / segs);
    add_corner(m, top, ring_normal[rings + 1], u, 1.0);
  }

  // Triangles in the outward orientation, reversed for the inner surface.
  for (uint32_t j = 0; j < segs; ++j) {
    uint32_t a = c0 + j, b = c0 + j + 1; // first ring
    if (inner)
      add_outer_triangle(m, bottom_corners + j, a, b);
    else
      add_outer_triangle(m, bottom_corners + j, b, a);
  }
  for (uint32_t i = 0; i + 1 < rings; ++i) {
    for (uint32_t j = 0; j < segs; ++j) {
      uint32_t a = c0 + i * (segs + 1) + j, d = a + segs + 1;
      if (inner)
        add_quad(m, a, d, d + 1, a + 1);
      else
        add_quad(m, a, a + 1, d + 1, d);
    }
  }
  for (uint32_t j = 0; j < segs; ++j) {
    uint32_t a = c0 + (rings - 1) * (segs + 1) + j, b = a + 1; // last ring
    if (inner)
      add_outer_triangle(m, a, top_corners + j, b);
    else
      add_outer_triangle(m, a, b, top_corners + j);
  }
}

/// Outer surface first (triangles and corners), then the inner one: two
/// closed components whose signed volumes add up to the shell's.
static void build_eggshell(bk_mesh* m) {
  const uint32_t per_surface_corners = (EGG_SEGMENTS + 1) * EGG_RINGS + 2 * EGG_SEGMENTS;
  bk_mesh_reserve(m, 2 * (EGG_SEGMENTS * EGG_RINGS + 2), 2 * per_surface_corners,
                  4 * EGG_SEGMENTS * EGG_RINGS);
  build_egg_surface(m, false);
  build_egg_surface(m, true);
}

// ---------------------------------------------------------------- pillar

enum { PILLAR_SIDES = 8 };
#define PILLAR_RADIUS 0.25
#define PILLAR_HEIGHT 2.0

/// Octagonal prism standing on y = 0: flat side quads (own corners per face)
/// and top/bottom fans around a centre position. uvs are in metres: sides use
/// the running perimeter length and height, caps use x and z.
static void build_pillar(bk_mesh* m) {
  const uint32_t sides = PILLAR_SIDES;
  bk_mesh_reserve(m, 2 * sides + 2, 4 * sides + 2 * (sides + 1), 4 * sides);
  // Half-step rotation so flat faces (not edges) look along +-x and +-z,
  // lining up with walls and slabs.
  const double start = BK_PI / sides;
  for (uint32_t level = 0; level < 2; ++level) {
    double y = level ? PILLAR_HEIGHT : 0.0;
    for (uint32_t j = 0; j < sides; ++j) {
      double phi = start + 2.0 * BK_PI * j / sides;
      bk_mesh_add_position(m, bk_v3(PILLAR_RADIUS * bk_cos(phi), y, -PILLAR_RADIUS * bk_sin(phi)));
    }
  }
  const uint32_t bottom_centre = bk_mesh_add_position(m, bk_v3(0.0, 0.0, 0.0));
  const uint32_t top_centre = bk_mesh_add_position(m, bk_v3(0.0, PILLAR_HEIGHT, 0.0));

  const double edge = 2.0 * PILLAR_RADIUS * bk_sin(BK_PI / sides);
  for (uint32_t j = 0; j < sides; ++j) {
    uint32_t next = (j + 1) % sides;
    double mid = start + 2.0 * BK_PI * (j + 0.5) / sides;
    bk_vec3 n = bk_v3(bk_cos(mid), 0.0, -bk_sin(mid));
    double u0 = edge * j, u1 = edge * (j + 1);
    uint32_t a = add_corner(m, j, n, u0, 0.0);
    uint32_t b = add_corner(m, next, n, u1, 0.0);
    uint32_t c = add_corner(m, sides + next, n, u1, PILLAR_HEIGHT);
    uint32_t d = add_corner(m, sides + j, n, u0, PILLAR_HEIGHT);
    add_quad(m, a, b, c, d);
  }
  // Caps: (u, v) = (x, -z) on top and (x, z) underneath, unmirrored from outside.
  const bk_vec3 up = bk_v3(0.0, 1.0, 0.0), down = bk_v3(0.0, -1.0, 0.0);
  const uint32_t top_c = add_corner(m, top_centre, up, 0.0, 0.0);
  const uint32_t top_ring = m->corner_count;
  for (uint32_t j = 0; j < sides; ++j) {
    bk_vec3 p = m->positions[sides + j];
    add_corner(m, sides + j, up, p.x, -p.z);
  }
  const uint32_t bottom_c = add_corner(m, bottom_centre, down, 0.0, 0.0);
  const uint32_t bottom_ring = m->corner_count;
  for (uint32_t j = 0; j < sides; ++j) {
    bk_vec3 p = m->positions[j];
    add_corner(m, j, down, p.x, p.z);
  }
  for (uint32_t j = 0; j < sides; ++j) {
    uint32_t next = (j + 1) % sides;
    add_outer_triangle(m, top_c, top_ring + j, top_ring + next);
    add_outer_triangle(m, bottom_c, bottom_ring + next, bottom_ring + j);
  }
}

// ---------------------------------------------------------------- structures

// Shapes for structural failure: each stands on y = 0 where only the parts
// meant to be anchored touch the ground, so an unsupported part falls.

/// Bridge: a Pi-shaped side in the x-y plane, extruded 1.2 m along z. A deck
/// 5 m long and 0.3 m thick, its underside 1.5 m up, on two legs 0.5 m thick
/// set 0.2 m in from its ends (a 3.6 m clear span). Counter-clockwise from +z.
static const double bridge_profile[][2] = {
    {-2.3, 0.0}, {-1.8, 0.0}, {-1.8, 1.5}, {1.8, 1.5},  {1.8, 0.0},  {2.3, 0.0},
    {2.3, 1.5},  {2.5, 1.5},  {2.5, 1.8},  {-2.5, 1.8}, {-2.5, 1.5}, {-2.3, 1.5},
};
#define BRIDGE_HALF_WIDTH 0.6

/// Balcony: an L-shaped side in the z-y plane (z first), extruded 2.4 m
/// along x: a wall 0.3 m thick and 3 m high centred on z = 0, and a slab
/// 0.2 m thick whose top is at 2 m, reaching 1.2 m out of the wall's +z face.
/// Counter-clockwise in (z, y), seen from -x.
static const double balcony_profile[][2] = {
    {-0.15, 0.0}, {0.15, 0.0}, {0.15, 1.8}, {1.35, 1.8}, {1.35, 2.0}, {0.15, 2.0}, {0.15, 3.0}, {-0.15, 3.0},
};
#define BALCONY_HALF_WIDTH 1.2

/// Extrudes a profile whose two coordinates run along x_axis and y_axis,
/// symmetric about the origin along x_axis x y_axis. A profile that cannot
/// be extruded adds nothing: the empty mesh is what bk_mesh_validate
/// rejects, and test_shapes builds every shape.
static void build_extrusion(bk_mesh* m, const double (*profile)[2], uint32_t corners, bk_vec3 x_axis,
                            bk_vec3 y_axis, double half_depth) {
  bk_extrusion def = {.profile = profile,
                      .corner_count = corners,
                      .x_axis = x_axis,
                      .y_axis = y_axis,
                      .depth_from = -half_depth,
                      .depth_to = half_depth};
  (void)bk_shape_extrude(m, &def);
}

// ---------------------------------------------------------------- dispatch

void bk_shape_build(bk_shape shape, bk_mesh* out) {
  // Overwritten, not freed: out may be uninitialised, as with bk_mesh_copy.
  memset(out, 0, sizeof *out);
  switch (shape) {
  case BK_SHAPE_CUBE:
    build_box(out, bk_v3(-0.5, -0.5, -0.5), bk_v3(0.5, 0.5, 0.5), BOX_UV_UNIT);
    break;
  case BK_SHAPE_TORUS:
    build_torus(out);
    break;
  case BK_SHAPE_EGGSHELL:
    build_eggshell(out);
    break;
  case BK_SHAPE_WALL:
    build_box(out, bk_v3(-1.0, 0.0, -0.1), bk_v3(1.0, 1.2, 0.1), BOX_UV_METRES);
    break;
  case BK_SHAPE_SLAB:
    build_box(out, bk_v3(-0.6, 0.0, -0.4), bk_v3(0.6, 0.15, 0.4), BOX_UV_METRES);
    break;
  case BK_SHAPE_PILLAR:
    build_pillar(out);
    break;
  case BK_SHAPE_TOWER:
    // A square stone column 0.8 x 4 x 0.8 m: tall enough to topple when its base goes.
    build_box(out, bk_v3(-0.4, 0.0, -0.4), bk_v3(0.4, 4.0, 0.4), BOX_UV_METRES);
    break;
  case BK_SHAPE_BRIDGE:
    build_extrusion(out, bridge_profile, sizeof bridge_profile / sizeof *bridge_profile, bk_v3(1.0, 0.0, 0.0),
                    bk_v3(0.0, 1.0, 0.0), BRIDGE_HALF_WIDTH);
    break;
  case BK_SHAPE_BALCONY:
    build_extrusion(out, balcony_profile, sizeof balcony_profile / sizeof *balcony_profile,
                    bk_v3(0.0, 0.0, 1.0), bk_v3(0.0, 1.0, 0.0), BALCONY_HALF_WIDTH);
    break;
  case BK_SHAPE_COUNT:
  default:
    return; // unknown shape: leave the empty mesh (bk_mesh_validate rejects it)
  }
  bk_mesh_compute_tangents(out);
}
