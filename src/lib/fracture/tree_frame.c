// The frame a mesh tree is cut in (see tree_frame.h).
#include <string.h>

#include "tree_frame.h"

// x * 2^e. A product with a power of two is rounded once, like ldexp (the
// same bits, subnormal or overflowing results too), and costs no call; the
// frames' exponents (sources 1e-6 to 1e6 across) keep 2^e far inside the
// doubles, and ldexp takes any other. `factor` is pow2(e).
static inline double pow2(int e) { return e >= -1000 && e <= 1000 ? ldexp(1.0, e) : 0.0; }
static inline double scale2(double x, double factor, int e) {
  return e >= -1000 && e <= 1000 ? x * factor : ldexp(x, e);
}

static double round_to_grid(double x, int exponent) {
  return ldexp(nearbyint(ldexp(x, -exponent)), exponent);
}

bk_tree_frame bk_tree_frame_of(bk_aabb bounds) {
  bk_vec3 size = bk_v3_sub(bounds.max, bounds.min);
  double largest = fmax(size.x, fmax(size.y, size.z));
  bk_tree_frame frame = {{0, 0, 0}, ilogb(largest)};
  // The centre snapped to a grid of half the scale: a mesh centred on the
  // world origin keeps it (its local coordinates are its own, scaled), and a
  // far one gets an origin whose subtraction from its coordinates is exact.
  int grid = frame.exponent - 1;
  frame.origin = bk_v3(round_to_grid(0.5 * (bounds.min.x + bounds.max.x), grid),
                       round_to_grid(0.5 * (bounds.min.y + bounds.max.y), grid),
                       round_to_grid(0.5 * (bounds.min.z + bounds.max.z), grid));
  return frame;
}

void bk_tree_frame_to_local(bk_tree_frame f, bk_mesh* m) {
  int e = -f.exponent;
  double k = pow2(e);
  for (uint32_t i = 0; i < m->position_count; ++i) {
    bk_vec3 d = bk_v3_sub(m->positions[i], f.origin);
    m->positions[i] = bk_v3(scale2(d.x, k, e), scale2(d.y, k, e), scale2(d.z, k, e));
  }
}

void bk_tree_frame_to_world(bk_tree_frame f, bk_mesh* m) {
  int e = f.exponent;
  double k = pow2(e);
  for (uint32_t i = 0; i < m->position_count; ++i) {
    bk_vec3 p = m->positions[i];
    m->positions[i] = bk_v3_add(bk_v3(scale2(p.x, k, e), scale2(p.y, k, e), scale2(p.z, k, e)), f.origin);
  }
}

bk_moments bk_tree_frame_moments_to_world(bk_tree_frame f, bk_moments m) {
  int e3 = 3 * f.exponent, e4 = 4 * f.exponent, e5 = 5 * f.exponent;
  double k3 = pow2(e3), k4 = pow2(e4), k5 = pow2(e5);
  return (bk_moments){
      .v = scale2(m.v, k3, e3),
      .x = scale2(m.x, k4, e4),
      .y = scale2(m.y, k4, e4),
      .z = scale2(m.z, k4, e4),
      .xx = scale2(m.xx, k5, e5),
      .yy = scale2(m.yy, k5, e5),
      .zz = scale2(m.zz, k5, e5),
      .xy = scale2(m.xy, k5, e5),
      .yz = scale2(m.yz, k5, e5),
      .zx = scale2(m.zx, k5, e5),
  };
}

bk_plane bk_tree_frame_plane_to_world(bk_tree_frame f, bk_plane p) {
  return (bk_plane){p.normal, ldexp(p.offset, f.exponent) + bk_v3_dot(p.normal, f.origin)};
}

bool bk_tree_frame_local_source(const bk_mesh* source, bk_tree_frame* frame, bk_mesh* root, bk_error* err) {
  *frame = bk_tree_frame_of(bk_mesh_bounds(source));
  memset(root, 0, sizeof *root);
  bk_mesh_copy(root, source);
  bk_tree_frame_to_local(*frame, root);
  double volume = bk_mesh_volume(root);
  if (!(volume > 0.0)) {
    bk_mesh_free(root);
    return bk_error_set(err, "mesh encloses no volume (signed volume %g): are its triangles wound inward?",
                        ldexp(volume, 3 * frame->exponent));
  }
  return true;
}
