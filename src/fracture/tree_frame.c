// The frame a mesh tree is cut in (see tree_frame.h).
#include <string.h>

#include "tree_frame.h"

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
  for (uint32_t i = 0; i < m->position_count; ++i) {
    bk_vec3 d = bk_v3_sub(m->positions[i], f.origin);
    m->positions[i] = bk_v3(ldexp(d.x, -f.exponent), ldexp(d.y, -f.exponent), ldexp(d.z, -f.exponent));
  }
}

void bk_tree_frame_to_world(bk_tree_frame f, bk_mesh* m) {
  for (uint32_t i = 0; i < m->position_count; ++i) {
    bk_vec3 p = m->positions[i];
    m->positions[i] =
        bk_v3_add(bk_v3(ldexp(p.x, f.exponent), ldexp(p.y, f.exponent), ldexp(p.z, f.exponent)), f.origin);
  }
}

bk_moments bk_tree_frame_moments_to_world(bk_tree_frame f, bk_moments m) {
  int e = f.exponent;
  return (bk_moments){
      .v = ldexp(m.v, 3 * e),
      .x = ldexp(m.x, 4 * e),
      .y = ldexp(m.y, 4 * e),
      .z = ldexp(m.z, 4 * e),
      .xx = ldexp(m.xx, 5 * e),
      .yy = ldexp(m.yy, 5 * e),
      .zz = ldexp(m.zz, 5 * e),
      .xy = ldexp(m.xy, 5 * e),
      .yz = ldexp(m.yz, 5 * e),
      .zx = ldexp(m.zx, 5 * e),
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
