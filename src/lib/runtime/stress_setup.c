// The stress system's setup (stress_system.c has the model and the solve):
// each bond's stiffness blocks, the multigrid's levels (groups of nodes that
// move as one, their bonds merged by pair and assembled), the finest level's
// Jacobi blocks and the coarsest's dense factor, made a level per step so a
// big system's setup spreads over a few calls.
#include <stdlib.h>
#include <string.h>

#include "stress_setup.h"

enum { DOF = RT_STRESS_DOF, BLOCK = RT_STRESS_DOF * RT_STRESS_DOF, COARSEST_NODES = 24 };

static const double shear_modulus = 0.4; // G / E
// Measured on a 1,024-fragment wall after a hole was shot in it (with a
// V-cycle at every level): one sweep at 0.8 needed 36 iterations, 0.6 39,
// two sweeps 25 but cost more.
static const double jacobi_damping = 0.8;

// A bond's stiffness blocks. With d = u - [r]x t at each end (r the lever
// arm from the node), the energy's Hessian block coupling end i's rows to
// end j's motion is E_i^T diag(K, K_rot) E_j, E = [I -[r]x; 0 I], i.e.
//   [ K            -A_j                ]     A_r = K [r]x
//   [ -A_i^T       K_rot - [ri]x A_j   ]
// with K = k_s I + (k_n - k_s) n n^T, K_rot = k_b I + (k_t - k_b) n n^T and
// A_r = k_s [r]x + (k_n - k_s) n (n x r)^T: a few dozen products per block
// (a system's setup is mostly these blocks). The block between the two ends
// enters with a minus sign (d is b's side minus a's).
typedef struct bond_blocks {
  double k[9], rotation[9], arm[2][9]; // K, K_rot, A_a, A_b
} bond_blocks;

static void bond_blocks_make(const double* g, const double stiff[4], bond_blocks* out) {
  const double* n = g;
  double c = stiff[0] - stiff[1], ct = stiff[3] - stiff[2];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double id = i == j ? 1.0 : 0.0, nn = n[i] * n[j];
      out->k[3 * i + j] = stiff[1] * id + c * nn;
      out->rotation[3 * i + j] = stiff[2] * id + ct * nn;
    }
  for (int end = 0; end < 2; ++end) {
    const double* r = g + 3 + 3 * end;
    double rx[9] = {0, -r[2], r[1], r[2], 0, -r[0], -r[1], r[0], 0};
    double n_r[3] = {0};
    rt_stress_cross(n, r, n_r);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        out->arm[end][3 * i + j] = stiff[1] * rx[3 * i + j] + c * n[i] * n_r[j];
  }
}

// block (row stride `stride`) += sign x the coupling of end i to end j.
static void bond_blocks_add(const bond_blocks* bb, const double* g, int i, int j, double sign, double* block,
                            uint32_t stride) {
  const double* ri = g + 3 + 3 * i;
  const double *ai = bb->arm[i], *aj = bb->arm[j];
  for (int row = 0; row < 3; ++row) {
    double* top = &block[row * stride];
    double* bottom = &block[(3 + row) * stride];
    int p = (row + 1) % 3, q = (row + 2) % 3;
    for (int col = 0; col < 3; ++col) {
      top[col] += sign * bb->k[3 * row + col];
      top[3 + col] -= sign * aj[3 * row + col];
      bottom[col] -= sign * ai[3 * col + row];
      double turned = ri[p] * aj[3 * q + col] - ri[q] * aj[3 * p + col]; // ([ri]x A_j)
      bottom[3 + col] += sign * (bb->rotation[3 * row + col] - turned);
    }
  }
}

// In-place Cholesky of an n x n matrix (lower triangle kept). A pivot that
// rounding drives to zero is lifted, so a node held by one thin bond still
// has a usable (if rough) factor.
static void factor(double* a, uint32_t n) {
  double scale = 0.0;
  for (uint32_t i = 0; i < n; ++i)
    scale = fmax(scale, a[i * n + i]);
  double floor_value = 1e-12 * scale + 1e-300;
  for (uint32_t j = 0; j < n; ++j) {
    double diagonal = a[j * n + j];
    for (uint32_t m = 0; m < j; ++m)
      diagonal -= a[j * n + m] * a[j * n + m];
    diagonal = sqrt(fmax(diagonal, floor_value));
    a[j * n + j] = diagonal;
    for (uint32_t i = j + 1; i < n; ++i) {
      double v = a[i * n + j];
      for (uint32_t m = 0; m < j; ++m)
        v -= a[i * n + m] * a[j * n + m];
      a[i * n + j] = v / diagonal;
    }
  }
}

// Allocates a level's arrays for its node and bond counts.
static void level_alloc(rt_stress_level* l, uint32_t nodes, uint32_t bonds, bool coarse) {
  l->node_count = nodes;
  l->bond_count = bonds;
  size_t n = nodes ? nodes : 1u, m = bonds ? bonds : 1u;
  l->fixed = bk_calloc(n, 1);
  l->centroid = bk_calloc(3 * n, sizeof(double));
  l->ends = bk_alloc(sizeof(uint32_t) * 2 * m);
  l->frame = bk_alloc(sizeof(double) * 9 * m);
  l->stiffness = bk_alloc(sizeof(double) * 4 * m);
  l->inverse = bk_calloc(BLOCK * n, sizeof(double));
  // Coarse levels' scratch: residual, input, output, the coarsest's packing
  // (the finest needs none: its preconditioner makes no product).
  if (coarse) l->work = bk_calloc(4 * DOF * n, sizeof(double));
}

static void level_free(rt_stress_level* l) {
  bk_free(l->fixed);
  bk_free(l->centroid);
  bk_free(l->ends);
  bk_free(l->frame);
  bk_free(l->stiffness);
  bk_free(l->inverse);
  bk_free(l->diagonal);
  bk_free(l->pair_ends);
  bk_free(l->pair_block);
  bk_free(l->work);
  bk_free(l->coarse_of);
  bk_free(l->offset);
  bk_free(l->dense);
  bk_free(l->dense_index);
}

// Each node's own block from its bonds, into blocks (36 per node).
static void level_diagonal(const rt_stress_level* l, double* blocks) {
  for (uint32_t k = 0; k < l->bond_count; ++k) {
    const double* g = &l->frame[9 * k];
    uint32_t a = l->ends[2 * k], b = l->ends[2 * k + 1];
    bond_blocks bb = {0};
    bond_blocks_make(g, &l->stiffness[4 * k], &bb);
    bond_blocks_add(&bb, g, 0, 0, 1.0, &blocks[BLOCK * a], DOF);
    bond_blocks_add(&bb, g, 1, 1, 1.0, &blocks[BLOCK * b], DOF);
  }
}

// Each free node's damped inverse block (for Jacobi) from its own block:
// Cholesky, then the inverse of the factor L, then (L L^T)^-1 = L^-T L^-1.
static void level_invert(rt_stress_level* l, const double* blocks) {
  for (uint32_t i = 0; i < l->node_count; ++i) {
    if (l->fixed[i]) continue;
    double f[BLOCK] = {0}, li[BLOCK] = {0};
    memcpy(f, &blocks[BLOCK * i], sizeof f);
    factor(f, DOF);
    for (int j = 0; j < DOF; ++j) {
      li[DOF * j + j] = 1.0 / f[DOF * j + j];
      for (int r = j + 1; r < DOF; ++r) {
        double v = 0.0;
        for (int m = j; m < r; ++m)
          v -= f[DOF * r + m] * li[DOF * m + j];
        li[DOF * r + j] = v / f[DOF * r + r];
      }
    }
    double* out = &l->inverse[BLOCK * i];
    for (int r = 0; r < DOF; ++r)
      for (int col = r; col < DOF; ++col) {
        double v = 0.0;
        for (int m = col; m < DOF; ++m)
          v += li[DOF * m + r] * li[DOF * m + col];
        out[DOF * r + col] = out[DOF * col + r] = jacobi_damping * v;
      }
  }
}

static int compare_u64(const void* a, const void* b) {
  uint64_t x = *(const uint64_t*)a, y = *(const uint64_t*)b;
  return x < y ? -1 : x > y;
}

// A coarse level's matrix: its own blocks, and its bonds merged by pair of
// free nodes (a level of 129 nodes over a 1,024-fragment wall has 3,933
// bonds but about 600 pairs).
static void level_assemble(rt_stress_level* l) {
  size_t n = l->node_count ? l->node_count : 1u, m = l->bond_count ? l->bond_count : 1u;
  l->diagonal = bk_calloc(BLOCK * n, sizeof(double));
  uint64_t* keys = bk_alloc(sizeof(uint64_t) * m);
  uint32_t count = 0;
  for (uint32_t k = 0; k < l->bond_count; ++k) {
    uint32_t a = l->ends[2 * k], b = l->ends[2 * k + 1];
    if (l->fixed[a] || l->fixed[b]) continue;
    uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
    keys[count++] = (uint64_t)lo << 32 | hi;
  }
  bk_sort(keys, count, sizeof *keys, compare_u64);
  uint32_t pairs = 0;
  for (uint32_t k = 0; k < count; ++k)
    if (pairs == 0 || keys[pairs - 1] != keys[k]) keys[pairs++] = keys[k];
  l->pair_count = pairs;
  l->pair_ends = bk_alloc(sizeof(uint32_t) * 2 * (pairs ? pairs : 1u));
  l->pair_block = bk_calloc(BLOCK * (size_t)(pairs ? pairs : 1u), sizeof(double));
  for (uint32_t k = 0; k < pairs; ++k) {
    l->pair_ends[2 * k] = (uint32_t)(keys[k] >> 32);
    l->pair_ends[2 * k + 1] = (uint32_t)keys[k];
  }
  for (uint32_t k = 0; k < l->bond_count; ++k) {
    uint32_t a = l->ends[2 * k], b = l->ends[2 * k + 1];
    const double* g = &l->frame[9 * k];
    bond_blocks bb = {0};
    bond_blocks_make(g, &l->stiffness[4 * k], &bb);
    bond_blocks_add(&bb, g, 0, 0, 1.0, &l->diagonal[BLOCK * a], DOF);
    bond_blocks_add(&bb, g, 1, 1, 1.0, &l->diagonal[BLOCK * b], DOF);
    if (l->fixed[a] || l->fixed[b]) continue;
    bool swapped = a > b;
    uint64_t key = swapped ? (uint64_t)b << 32 | a : (uint64_t)a << 32 | b;
    const uint64_t* found = bsearch(&key, keys, pairs, sizeof *keys, compare_u64);
    // Rows of the pair's first node, columns of its second.
    double* block = &l->pair_block[BLOCK * (size_t)(found - keys)];
    bond_blocks_add(&bb, g, swapped ? 1 : 0, swapped ? 0 : 1, -1.0, block, DOF);
  }
  bk_free(keys);
  level_invert(l, l->diagonal);
}

// The finest level's inverse blocks (its bonds are applied one by one).
static void level_prepare_finest(rt_stress_level* l) {
  level_diagonal(l, l->inverse); // inverted in place, node by node
  level_invert(l, l->inverse);
}

// The coarsest level's whole matrix over its free nodes, factored.
static void level_factor_dense(rt_stress_level* l) {
  l->dense_index = bk_alloc(sizeof(uint32_t) * (l->node_count ? l->node_count : 1u));
  uint32_t free_count = 0;
  for (uint32_t i = 0; i < l->node_count; ++i)
    l->dense_index[i] = l->fixed[i] ? UINT32_MAX : free_count++;
  uint32_t n = DOF * free_count;
  l->dense_size = n;
  l->dense = bk_calloc((size_t)n * n + 1u, sizeof(double));
  for (uint32_t k = 0; k < l->bond_count; ++k) {
    const double* g = &l->frame[9 * k];
    uint32_t end[2] = {l->dense_index[l->ends[2 * k]], l->dense_index[l->ends[2 * k + 1]]};
    bond_blocks bb = {0};
    bond_blocks_make(g, &l->stiffness[4 * k], &bb);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) {
        if (end[i] == UINT32_MAX || end[j] == UINT32_MAX) continue;
        double* at = &l->dense[(size_t)DOF * end[i] * n + DOF * end[j]];
        bond_blocks_add(&bb, g, i, j, i == j ? 1.0 : -1.0, at, n);
      }
  }
  factor(l->dense, n);
}

// ---------------------------------------------------------------- coarsening

typedef struct keyed {
  uint32_t key, index;
} keyed;

static int compare_keyed(const void* a, const void* b) {
  const keyed *x = a, *y = b;
  if (x->key != y->key) return x->key < y->key ? -1 : 1;
  return x->index < y->index ? -1 : x->index > y->index;
}

// The next level over `fine`: its free nodes grouped by key (nodes with one
// key move as one), its fixed nodes merged into one fixed node; the bonds
// between groups kept with lever arms from the group centroids. Returns
// false (nothing made) if grouping would not shrink the level enough.
static bool coarsen(const rt_stress_level* fine, const double* fine_mass, const uint32_t* key,
                    rt_stress_level* coarse, double** coarse_mass) {
  uint32_t n = fine->node_count;
  uint32_t* coarse_of = bk_alloc(sizeof(uint32_t) * (n ? n : 1u));
  keyed* order = bk_alloc(sizeof(keyed) * (n ? n : 1u));
  uint32_t free_count = 0;
  bool any_fixed = false;
  for (uint32_t i = 0; i < n; ++i) {
    if (fine->fixed[i])
      any_fixed = true;
    else
      order[free_count++] = (keyed){key[i], i};
  }
  bk_sort(order, free_count, sizeof *order, compare_keyed);
  // The fixed nodes (if any) are coarse node 0; the groups follow in key order.
  uint32_t first_group = any_fixed ? 1u : 0u, coarse_nodes = first_group, id = 0;
  for (uint32_t j = 0; j < free_count; ++j) {
    if (j == 0 || order[j].key != order[j - 1].key) id = coarse_nodes++;
    coarse_of[order[j].index] = id;
  }
  for (uint32_t i = 0; i < n; ++i)
    if (fine->fixed[i]) coarse_of[i] = 0;
  bk_free(order);
  if (free_count == 0 || (double)(coarse_nodes - first_group) > 0.7 * free_count) {
    bk_free(coarse_of);
    return false;
  }
  uint32_t bonds = 0;
  for (uint32_t k = 0; k < fine->bond_count; ++k) {
    uint32_t a = coarse_of[fine->ends[2 * k]], b = coarse_of[fine->ends[2 * k + 1]];
    if (a != b) bonds++;
  }
  level_alloc(coarse, coarse_nodes, bonds, true);
  double* mass = bk_calloc(coarse_nodes ? coarse_nodes : 1u, sizeof(double));
  if (any_fixed) coarse->fixed[0] = 1;
  for (uint32_t i = 0; i < n; ++i) {
    if (fine->fixed[i]) continue;
    uint32_t c = coarse_of[i];
    // Every fine node weighs something (a sliver's volume, floored), so a
    // centroid is always defined.
    double m = fmax(fine_mass[i], 1e-300);
    mass[c] += m;
    for (int d = 0; d < 3; ++d)
      coarse->centroid[3 * c + d] += m * fine->centroid[3 * i + d];
  }
  for (uint32_t c = first_group; c < coarse_nodes; ++c)
    for (int d = 0; d < 3; ++d)
      coarse->centroid[3 * c + d] /= mass[c];
  double* offset = bk_calloc(3 * (size_t)(n ? n : 1u), sizeof(double));
  for (uint32_t i = 0; i < n; ++i)
    if (!fine->fixed[i])
      for (int d = 0; d < 3; ++d)
        offset[3 * i + d] = fine->centroid[3 * i + d] - coarse->centroid[3 * coarse_of[i] + d];
  uint32_t m = 0;
  for (uint32_t k = 0; k < fine->bond_count; ++k) {
    uint32_t fa = fine->ends[2 * k], fb = fine->ends[2 * k + 1];
    uint32_t a = coarse_of[fa], b = coarse_of[fb];
    if (a == b) continue;
    coarse->ends[2 * m] = a;
    coarse->ends[2 * m + 1] = b;
    const double* g = &fine->frame[9 * k];
    double* h = &coarse->frame[9 * m];
    for (int d = 0; d < 3; ++d) {
      h[d] = g[d];
      h[3 + d] = g[3 + d] + offset[3 * fa + d]; // bond point - coarse centroid
      h[6 + d] = g[6 + d] + offset[3 * fb + d];
    }
    memcpy(&coarse->stiffness[4 * m], &fine->stiffness[4 * k], sizeof(double) * 4);
    m++;
  }
  coarse->coarse_of = coarse_of;
  coarse->offset = offset;
  *coarse_mass = mass;
  return true;
}

// ---------------------------------------------------------------- the system

rt_stress* rt_stress_create(const rt_stress_node* nodes, uint32_t node_count, const rt_stress_bond* bonds,
                            uint32_t bond_count, const uint32_t* const* group_keys, uint32_t group_levels) {
  rt_stress* s = bk_calloc(1, sizeof *s);
  rt_stress_level* l = &s->levels[0];
  level_alloc(l, node_count, bond_count, false);
  size_t n = node_count ? node_count : 1u, m = bond_count ? bond_count : 1u;
  s->node_count = node_count;
  s->bond_count = bond_count;
  s->mass = bk_alloc(sizeof(double) * n);
  s->area = bk_alloc(sizeof(double) * m);
  s->tree_bond = bk_alloc(sizeof(uint32_t) * m);
  double* vectors = bk_calloc(6 * DOF * n, sizeof(double));
  s->x = vectors;
  s->b = vectors + DOF * n;
  s->r = vectors + 2 * DOF * n;
  s->z = vectors + 3 * DOF * n;
  s->p = vectors + 4 * DOF * n;
  s->q = vectors + 5 * DOF * n;
  for (uint32_t i = 0; i < node_count; ++i) {
    l->fixed[i] = nodes[i].fixed;
    s->mass[i] = nodes[i].mass;
    double c[3] = {nodes[i].centroid.x, nodes[i].centroid.y, nodes[i].centroid.z};
    memcpy(&l->centroid[3 * i], c, sizeof c);
  }
  for (uint32_t k = 0; k < bond_count; ++k) {
    const rt_stress_bond* bd = &bonds[k];
    const rt_stress_node *a = &nodes[bd->a], *b = &nodes[bd->b];
    l->ends[2 * k] = bd->a;
    l->ends[2 * k + 1] = bd->b;
    s->tree_bond[k] = bd->tree_bond;
    bk_vec3 ra = bk_v3_sub(bd->centroid, a->centroid), rb = bk_v3_sub(bd->centroid, b->centroid);
    double values[9] = {bd->normal.x, bd->normal.y, bd->normal.z, ra.x, ra.y, ra.z, rb.x, rb.y, rb.z};
    memcpy(&l->frame[9 * k], values, sizeof values);
    // A sliver's centroids can nearly meet; its beam is never shorter than
    // a tenth of its face's width, so one bond cannot stiffen without bound.
    double area = fmax(bd->area, 1e-12);
    double length = fmax(bk_v3_length(bk_v3_sub(b->centroid, a->centroid)), 0.1 * sqrt(area));
    double* k4 = &l->stiffness[4 * k];
    k4[0] = area / length;
    k4[1] = shear_modulus * area / length;
    k4[2] = area * area / (12.0 * length);
    k4[3] = shear_modulus * area * area / (6.0 * length);
    s->area[k] = area;
  }
  s->level_count = 1;
  // What the setup steps need: the groups, and for the newest level a
  // fragment of each node and the nodes' masses.
  s->group_levels = group_levels;
  s->group_keys = bk_alloc(sizeof(uint32_t) * n * (group_levels ? group_levels : 1u));
  for (uint32_t g = 0; g < group_levels; ++g)
    memcpy(&s->group_keys[(size_t)g * n], group_keys[g], sizeof(uint32_t) * node_count);
  s->member = bk_alloc(sizeof(uint32_t) * n);
  for (uint32_t i = 0; i < node_count; ++i)
    s->member[i] = i;
  s->level_mass = s->mass;
  return s;
}

uint64_t rt_stress_create_cost(const rt_stress* s) {
  // Gathering the bonds and copying them in: a few units per bond.
  return 4u * (uint64_t)s->bond_count + 2u * (uint64_t)s->node_count;
}

// Frees what only the setup needed.
static void setup_finish(rt_stress* s) {
  if (s->level_mass != s->mass) bk_free(s->level_mass);
  s->level_mass = NULL;
  bk_free(s->group_keys);
  bk_free(s->member);
  s->group_keys = NULL;
  s->member = NULL;
  s->ready = true;
}

uint64_t rt_stress_setup_step(rt_stress* s) {
  if (s->ready) return 0;
  rt_stress_level* fine = &s->levels[s->level_count - 1];
  uint64_t cost = 4u * (uint64_t)fine->bond_count + 2u * (uint64_t)fine->node_count;
  // The next coarser level, while levels shrink and are worth a V-cycle.
  uint32_t free_count = 0;
  for (uint32_t i = 0; i < fine->node_count; ++i)
    free_count += !fine->fixed[i];
  uint32_t* key = bk_alloc(sizeof(uint32_t) * (fine->node_count ? fine->node_count : 1u));
  bool made = false;
  rt_stress_level* coarse = &s->levels[s->level_count];
  while (!made && free_count > COARSEST_NODES && s->next_group < s->group_levels &&
         s->level_count < RT_STRESS_LEVELS_MAX) {
    const uint32_t* group = &s->group_keys[(size_t)s->next_group++ * (s->node_count ? s->node_count : 1u)];
    // A fixed node's key is never read (coarsening merges them all into
    // one), and its member is not a fragment of any group.
    for (uint32_t i = 0; i < fine->node_count; ++i)
      key[i] = fine->fixed[i] ? 0u : group[s->member[i]];
    double* coarse_mass = NULL;
    made = coarsen(fine, s->level_mass, key, coarse, &coarse_mass);
    if (!made) continue;
    // Each coarse node's fragment: a member of its group (the merged fixed
    // node's is a fixed node's, never read).
    for (uint32_t i = 0; i < fine->node_count; ++i)
      key[coarse->coarse_of[i]] = s->member[i];
    memcpy(s->member, key, sizeof(uint32_t) * coarse->node_count);
    if (s->level_mass != s->mass) bk_free(s->level_mass);
    s->level_mass = coarse_mass;
    s->level_count++;
  }
  bk_free(key);
  if (made) {
    // The level before is not the coarsest: the finest is applied bond by
    // bond, the others assembled.
    if (s->level_count == 2)
      level_prepare_finest(fine);
    else
      level_assemble(fine);
    return cost + 4u * (uint64_t)fine->bond_count;
  }
  // No coarser level: the last is solved directly.
  rt_stress_level* coarsest = fine;
  if (!coarsest->work) // the finest alone: it packs its vectors for the dense solve
    coarsest->work =
        bk_calloc(4 * DOF * (size_t)(coarsest->node_count ? coarsest->node_count : 1u), sizeof(double));
  level_factor_dense(coarsest);
  setup_finish(s);
  uint64_t n = coarsest->dense_size;
  return cost + n * n * n / 300u;
}

void rt_stress_destroy(rt_stress* s) {
  if (!s) return;
  for (uint32_t i = 0; i < s->level_count; ++i)
    level_free(&s->levels[i]);
  bk_free(s->mass);
  bk_free(s->area);
  bk_free(s->tree_bond);
  bk_free(s->x);
  if (s->level_mass != s->mass) bk_free(s->level_mass);
  bk_free(s->group_keys);
  bk_free(s->member);
  bk_free(s);
}
