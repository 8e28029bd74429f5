// The points a refined node's hull is made from: its mesh's extreme
// vertices along 96 fixed directions (4 x 4 on each face of a cube), so a
// piece of a smooth 10,000-triangle part, all of whose hundreds of vertices
// lie on its hull, costs Bullet a hull of at most 96 points instead of
// simplifying hundreds in the step its body is made. The hull of the
// support points lies inside the mesh's and touches it in every direction.
#include <stdlib.h>

#include "world_internal.h"

enum { GRID = 4, DIRECTIONS = 6 * GRID * GRID };

static bk_vec3 direction(uint32_t index) {
  uint32_t face = index / (GRID * GRID), cell = index % (GRID * GRID);
  double a = -1.0 + (2.0 * (cell % GRID) + 1.0) / GRID, b = -1.0 + (2.0 * (cell / GRID) + 1.0) / GRID;
  double s = face % 2 ? -1.0 : 1.0;
  bk_vec3 d = face / 2 == 0 ? bk_v3(s, a, b) : face / 2 == 1 ? bk_v3(a, s, b) : bk_v3(a, b, s);
  return bk_v3_normalize(d);
}

static int compare_u32(const void* pa, const void* pb) {
  uint32_t a = *(const uint32_t*)pa, b = *(const uint32_t*)pb;
  return (a > b) - (a < b);
}

uint32_t bk_world_hull_points(const bk_mesh* mesh, bk_vec3* out) {
  if (mesh->position_count <= DIRECTIONS) {
    for (uint32_t i = 0; i < mesh->position_count; ++i)
      out[i] = mesh->positions[i];
    return mesh->position_count;
  }
  uint32_t chosen[DIRECTIONS];
  for (uint32_t k = 0; k < DIRECTIONS; ++k) {
    bk_vec3 d = direction(k);
    uint32_t best = 0;
    double best_dot = -INFINITY;
    for (uint32_t i = 0; i < mesh->position_count; ++i) {
      double dot = bk_v3_dot(mesh->positions[i], d);
      if (dot > best_dot) best_dot = dot, best = i;
    }
    chosen[k] = best;
  }
  qsort(chosen, DIRECTIONS, sizeof(uint32_t), compare_u32);
  uint32_t count = 0;
  for (uint32_t k = 0; k < DIRECTIONS; ++k)
    if (k == 0 || chosen[k] != chosen[k - 1]) out[count++] = mesh->positions[chosen[k]];
  return count;
}
