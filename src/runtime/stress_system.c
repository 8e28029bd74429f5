// The stress system of one cluster: its fragments are rigid nodes joined by
// elastic bonds, its supports hold still, gravity loads it, and the bond
// forces follow from equilibrium (a lattice of beams).
//
// Unknowns: each free node's small displacement u and rotation t (6 per
// node). A bond from node a to b, at centroid p with unit normal n (a -> b)
// and area A, sees the relative motion of its two sides at p,
//   d = (u_b + t_b x r_b) - (u_a + t_a x r_a),  w = t_b - t_a,
// r = p - the node's centroid, and resists it as a beam of length L (the
// distance between the centroids) and square section A:
//   axial  k_n = E A / L          along n
//   shear  k_s = G A / L          across n
//   bend   k_b = E A^2 / (12 L)   w across n (I = A^2 / 12)
//   twist  k_t = G A^2 / (6 L)    w along n (J = A^2 / 6)
// E sets only the scale of the displacements, not the forces, so E = 1 and
// G = 0.4 (Poisson 0.25). The equilibrium K x = f (f = m g on u, no torque:
// gravity acts at the centroid) is symmetric positive definite once every
// node is connected to a support, and is solved matrix-free by conjugate
// gradients, warm-started from the last solution and preconditioned by one
// multigrid V-cycle over the mesh tree: the fragments under one tree node
// make one coarse node that moves rigidly, and since a rigid motion strains
// no bond inside it, the coarse system is made of the bonds between coarse
// nodes alone, each with its lever arms moved to the coarse centroids: the
// same beams, exactly (Galerkin). Each level is smoothed by damped block
// Jacobi (each node's own 6 x 6 stiffness, factored once per system); the
// coarsest is solved directly. Jacobi preconditioning alone needed 200 to
// 450 iterations on a 1,024-fragment wall; the V-cycle carries a load across
// the whole structure in one iteration.
//
// Stress of a bond from its forces: normal N = k_n (d.n) (> 0 pulls), shear
// V = k_s |d across n|, bending M = k_b |w across n|, twist T = k_t |w.n|;
// over a square section of area A (section modulus A^1.5 / 6, torsion
// modulus A^1.5 / 4.8):
//   tension     = max(0,  N / A + 6 M / A^1.5)
//   compression = max(0, -N / A + 6 M / A^1.5)
//   shear       = V / A + 4.8 T / A^1.5
#include <stdlib.h>
#include <string.h>

#include "stress_system.h"

enum { DOF = 6, BLOCK = 36, COARSEST_NODES = 24 };

static const double shear_modulus = 0.4; // G / E
// Measured on a 1,024-fragment wall after a hole was shot in it: one sweep
// at 0.8 needed 36 iterations, 0.6 39, two sweeps 25 but cost more.
static const double jacobi_damping = 0.8;
static const int smoothing_sweeps = 1;

static void cross(const double a[3], const double b[3], double out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static double dot(const double* a, const double* b, uint32_t n) {
  double sum = 0.0;
  for (uint32_t i = 0; i < n; ++i)
    sum += a[i] * b[i];
  return sum;
}

// ---------------------------------------------------------------- one level

// A bond's force (on b; a gets the opposite) and moment from the relative
// motion of its sides.
static void bond_response(const rt_stress_level* l, uint32_t k, const double* x, double force[3],
                          double moment[3]) {
  const double* g = &l->frame[9 * k];
  const double *n = g, *ra = g + 3, *rb = g + 6;
  const double* stiff = &l->stiffness[4 * k];
  const double* xa = &x[DOF * l->ends[2 * k]];
  const double* xb = &x[DOF * l->ends[2 * k + 1]];
  double ta_r[3] = {0}, tb_r[3] = {0};
  cross(xa + 3, ra, ta_r);
  cross(xb + 3, rb, tb_r);
  double d[3] = {xb[0] + tb_r[0] - xa[0] - ta_r[0], xb[1] + tb_r[1] - xa[1] - ta_r[1],
                 xb[2] + tb_r[2] - xa[2] - ta_r[2]};
  double w[3] = {xb[3] - xa[3], xb[4] - xa[4], xb[5] - xa[5]};
  double dn = dot3(d, n), wn = dot3(w, n);
  for (int i = 0; i < 3; ++i) {
    force[i] = stiff[0] * dn * n[i] + stiff[1] * (d[i] - dn * n[i]);
    moment[i] = stiff[3] * wn * n[i] + stiff[2] * (w[i] - wn * n[i]);
  }
}

// out = K x over a level's free nodes (fixed nodes' rows are zero).
static void apply_stiffness(const rt_stress_level* l, const double* x, double* out) {
  memset(out, 0, sizeof(double) * DOF * l->node_count);
  for (uint32_t k = 0; k < l->bond_count; ++k) {
    double f[3] = {0}, m[3] = {0}, arm[3] = {0};
    bond_response(l, k, x, f, m);
    const double* g = &l->frame[9 * k];
    double* oa = &out[DOF * l->ends[2 * k]];
    double* ob = &out[DOF * l->ends[2 * k + 1]];
    cross(g + 6, f, arm);
    for (int i = 0; i < 3; ++i) {
      ob[i] += f[i];
      ob[3 + i] += arm[i] + m[i];
    }
    cross(g + 3, f, arm);
    for (int i = 0; i < 3; ++i) {
      oa[i] -= f[i];
      oa[3 + i] -= arm[i] + m[i];
    }
  }
  for (uint32_t i = 0; i < l->node_count; ++i)
    if (l->fixed[i]) memset(&out[DOF * i], 0, sizeof(double) * DOF);
}

// Adds a bond's 6 x 6 coupling of end i (lever ri, sign si) to end j: with
// d = s (u - [r]x t) at each end, the energy's Hessian block is
//   si sj [ K          -K [rj]x              ]
//         [ [ri]x K    -[ri]x K [rj]x + K_rot ]
static void add_bond_block(double* block, uint32_t stride, const double n[3], const double ri[3],
                           const double rj[3], double sign, const double stiff[4]) {
  double k[3][3] = {{0}}, kr[3][3] = {{0}};
  double rxi[3][3] = {{0, -ri[2], ri[1]}, {ri[2], 0, -ri[0]}, {-ri[1], ri[0], 0}};
  double rxj[3][3] = {{0, -rj[2], rj[1]}, {rj[2], 0, -rj[0]}, {-rj[1], rj[0], 0}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double nn = n[i] * n[j], id = i == j ? 1.0 : 0.0;
      k[i][j] = stiff[0] * nn + stiff[1] * (id - nn);
      kr[i][j] = stiff[3] * nn + stiff[2] * (id - nn);
    }
  double k_rxj[3][3] = {{0}}, rxi_k[3][3] = {{0}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int m = 0; m < 3; ++m) {
        k_rxj[i][j] += k[i][m] * rxj[m][j];
        rxi_k[i][j] += rxi[i][m] * k[m][j];
      }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double rxi_k_rxj = 0.0;
      for (int m = 0; m < 3; ++m)
        rxi_k_rxj += rxi_k[i][m] * rxj[m][j];
      block[i * stride + j] += sign * k[i][j];
      block[i * stride + 3 + j] -= sign * k_rxj[i][j];
      block[(3 + i) * stride + j] += sign * rxi_k[i][j];
      block[(3 + i) * stride + 3 + j] += sign * (kr[i][j] - rxi_k_rxj);
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

static void solve_factored(const double* l, uint32_t n, const double* b, double* x) {
  for (uint32_t i = 0; i < n; ++i) {
    double v = b[i];
    for (uint32_t j = 0; j < i; ++j)
      v -= l[i * n + j] * x[j];
    x[i] = v / l[i * n + i];
  }
  for (uint32_t i = n; i-- > 0;) {
    double v = x[i];
    for (uint32_t j = i + 1; j < n; ++j)
      v -= l[j * n + i] * x[j];
    x[i] = v / l[i * n + i];
  }
}

// z += damping x D^-1 r (each free node's own block).
static void jacobi(const rt_stress_level* l, const double* r, double* z) {
  for (uint32_t i = 0; i < l->node_count; ++i) {
    if (l->fixed[i]) continue;
    double step[DOF] = {0};
    solve_factored(&l->block[BLOCK * i], DOF, &r[DOF * i], step);
    for (int d = 0; d < DOF; ++d)
      z[DOF * i + d] += jacobi_damping * step[d];
  }
}

// Allocates a level's arrays for its node and bond counts.
static void level_alloc(rt_stress_level* l, uint32_t nodes, uint32_t bonds) {
  l->node_count = nodes;
  l->bond_count = bonds;
  size_t n = nodes ? nodes : 1u, m = bonds ? bonds : 1u;
  l->fixed = bk_calloc(n, 1);
  l->centroid = bk_calloc(3 * n, sizeof(double));
  l->ends = bk_alloc(sizeof(uint32_t) * 2 * m);
  l->frame = bk_alloc(sizeof(double) * 9 * m);
  l->stiffness = bk_alloc(sizeof(double) * 4 * m);
  l->block = bk_calloc(BLOCK * n, sizeof(double));
  l->work = bk_calloc(4 * DOF * n, sizeof(double)); // residual, input, output, coarsest scratch
}

static void level_free(rt_stress_level* l) {
  free(l->fixed);
  free(l->centroid);
  free(l->ends);
  free(l->frame);
  free(l->stiffness);
  free(l->block);
  free(l->work);
  free(l->coarse_of);
  free(l->offset);
  free(l->dense);
  free(l->dense_index);
}

// Each free node's block from its bonds, factored.
static void level_factor_blocks(rt_stress_level* l) {
  for (uint32_t k = 0; k < l->bond_count; ++k) {
    const double* g = &l->frame[9 * k];
    uint32_t a = l->ends[2 * k], b = l->ends[2 * k + 1];
    add_bond_block(&l->block[BLOCK * a], DOF, g, g + 3, g + 3, 1.0, &l->stiffness[4 * k]);
    add_bond_block(&l->block[BLOCK * b], DOF, g, g + 6, g + 6, 1.0, &l->stiffness[4 * k]);
  }
  for (uint32_t i = 0; i < l->node_count; ++i)
    if (!l->fixed[i]) factor(&l->block[BLOCK * i], DOF);
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
    const double* lever[2] = {g + 3, g + 6};
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) {
        if (end[i] == UINT32_MAX || end[j] == UINT32_MAX) continue;
        double* at = &l->dense[(size_t)DOF * end[i] * n + DOF * end[j]];
        add_bond_block(at, n, g, lever[i], lever[j], i == j ? 1.0 : -1.0, &l->stiffness[4 * k]);
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
  qsort(order, free_count, sizeof *order, compare_keyed);
  // The fixed nodes (if any) are coarse node 0; the groups follow in key order.
  uint32_t first_group = any_fixed ? 1u : 0u, coarse_nodes = first_group, id = 0;
  for (uint32_t j = 0; j < free_count; ++j) {
    if (j == 0 || order[j].key != order[j - 1].key) id = coarse_nodes++;
    coarse_of[order[j].index] = id;
  }
  for (uint32_t i = 0; i < n; ++i)
    if (fine->fixed[i]) coarse_of[i] = 0;
  free(order);
  if (free_count == 0 || (double)(coarse_nodes - first_group) > 0.7 * free_count) {
    free(coarse_of);
    return false;
  }
  uint32_t bonds = 0;
  for (uint32_t k = 0; k < fine->bond_count; ++k) {
    uint32_t a = coarse_of[fine->ends[2 * k]], b = coarse_of[fine->ends[2 * k + 1]];
    if (a != b) bonds++;
  }
  level_alloc(coarse, coarse_nodes, bonds);
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

// ---------------------------------------------------------------- the V-cycle

// Fine residual r (level `index`) to the coarse level's forces and torques.
static void restrict_residual(const rt_stress_level* fine, const rt_stress_level* coarse, const double* r,
                              double* out) {
  memset(out, 0, sizeof(double) * DOF * coarse->node_count);
  for (uint32_t i = 0; i < fine->node_count; ++i) {
    if (fine->fixed[i]) continue;
    const double *f = &r[DOF * i], *o = &coarse->offset[3 * i];
    double* c = &out[DOF * coarse->coarse_of[i]];
    double arm[3] = {0};
    cross(o, f, arm);
    for (int d = 0; d < 3; ++d) {
      c[d] += f[d];
      c[3 + d] += f[3 + d] + arm[d];
    }
  }
}

// z += the fine motion of the coarse motion zc (rigid per group).
static void prolong(const rt_stress_level* fine, const rt_stress_level* coarse, const double* zc, double* z) {
  for (uint32_t i = 0; i < fine->node_count; ++i) {
    if (fine->fixed[i]) continue;
    const double *c = &zc[DOF * coarse->coarse_of[i]], *o = &coarse->offset[3 * i];
    double turn[3] = {0};
    cross(c + 3, o, turn);
    for (int d = 0; d < 3; ++d) {
      z[DOF * i + d] += c[d] + turn[d];
      z[DOF * i + 3 + d] += c[3 + d];
    }
  }
}

// z = an approximate K^-1 r at level `index` (symmetric, so CG may use it).
static void v_cycle(const rt_stress* s, uint32_t index, const double* r, double* z) {
  const rt_stress_level* l = &s->levels[index];
  uint32_t n = DOF * l->node_count;
  if (index + 1 == s->level_count) {
    memset(z, 0, sizeof(double) * n);
    double* packed_r = l->work;
    double* packed_z = l->work + 3 * DOF * l->node_count;
    for (uint32_t i = 0; i < l->node_count; ++i)
      if (l->dense_index[i] != UINT32_MAX)
        memcpy(&packed_r[DOF * l->dense_index[i]], &r[DOF * i], sizeof(double) * DOF);
    solve_factored(l->dense, l->dense_size, packed_r, packed_z);
    for (uint32_t i = 0; i < l->node_count; ++i)
      if (l->dense_index[i] != UINT32_MAX)
        memcpy(&z[DOF * i], &packed_z[DOF * l->dense_index[i]], sizeof(double) * DOF);
    return;
  }
  const rt_stress_level* c = &s->levels[index + 1];
  double* t = l->work;
  double* rc = c->work + DOF * c->node_count;
  double* zc = c->work + 2 * DOF * c->node_count;
  memset(z, 0, sizeof(double) * n);
  jacobi(l, r, z);
  for (int sweep = 1; sweep < smoothing_sweeps; ++sweep) {
    apply_stiffness(l, z, t);
    for (uint32_t i = 0; i < n; ++i)
      t[i] = r[i] - t[i];
    jacobi(l, t, z);
  }
  apply_stiffness(l, z, t);
  for (uint32_t i = 0; i < n; ++i)
    t[i] = r[i] - t[i];
  restrict_residual(l, c, t, rc);
  v_cycle(s, index + 1, rc, zc);
  prolong(l, c, zc, z);
  for (int sweep = 0; sweep < smoothing_sweeps; ++sweep) {
    apply_stiffness(l, z, t);
    for (uint32_t i = 0; i < n; ++i)
      t[i] = r[i] - t[i];
    jacobi(l, t, z);
  }
}

// ---------------------------------------------------------------- the system

rt_stress* rt_stress_create(const rt_stress_node* nodes, uint32_t node_count, const rt_stress_bond* bonds,
                            uint32_t bond_count, const uint32_t* const* group_keys, uint32_t group_levels) {
  rt_stress* s = bk_calloc(1, sizeof *s);
  rt_stress_level* l = &s->levels[0];
  level_alloc(l, node_count, bond_count);
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
  level_factor_blocks(l);
  s->level_count = 1;
  // Coarser levels while they shrink and are worth a V-cycle.
  double* mass = s->mass;
  uint32_t* key = bk_alloc(sizeof(uint32_t) * n);
  uint32_t* member = bk_calloc(n, sizeof(uint32_t)); // a level-0 node of each node of the level
  uint32_t* next_member = bk_calloc(n, sizeof(uint32_t));
  for (uint32_t i = 0; i < node_count; ++i)
    member[i] = i;
  for (uint32_t g = 0; g < group_levels && s->level_count < RT_STRESS_LEVELS_MAX; ++g) {
    rt_stress_level* fine = &s->levels[s->level_count - 1];
    uint32_t free_count = 0;
    for (uint32_t i = 0; i < fine->node_count; ++i)
      free_count += !fine->fixed[i];
    if (free_count <= COARSEST_NODES) break;
    for (uint32_t i = 0; i < fine->node_count; ++i)
      key[i] = group_keys[g][member[i]];
    rt_stress_level* coarse = &s->levels[s->level_count];
    double* coarse_mass = NULL;
    if (!coarsen(fine, mass, key, coarse, &coarse_mass)) continue;
    for (uint32_t i = 0; i < fine->node_count; ++i)
      if (!fine->fixed[i]) next_member[coarse->coarse_of[i]] = member[i];
    memcpy(member, next_member, sizeof(uint32_t) * coarse->node_count);
    if (mass != s->mass) free(mass);
    mass = coarse_mass;
    level_factor_blocks(coarse);
    s->level_count++;
  }
  if (mass != s->mass) free(mass);
  free(key);
  free(member);
  free(next_member);
  level_factor_dense(&s->levels[s->level_count - 1]);
  return s;
}

void rt_stress_destroy(rt_stress* s) {
  if (!s) return;
  for (uint32_t i = 0; i < s->level_count; ++i)
    level_free(&s->levels[i]);
  free(s->mass);
  free(s->area);
  free(s->tree_bond);
  free(s->x);
  free(s);
}

void rt_stress_load(rt_stress* s, bk_vec3 gravity) {
  const rt_stress_level* l = &s->levels[0];
  uint32_t n = DOF * s->node_count;
  s->gravity = gravity;
  memset(s->b, 0, sizeof(double) * n);
  for (uint32_t i = 0; i < s->node_count; ++i) {
    if (l->fixed[i]) {
      memset(&s->x[DOF * i], 0, sizeof(double) * DOF);
      continue;
    }
    s->b[DOF * i + 0] = s->mass[i] * gravity.x;
    s->b[DOF * i + 1] = s->mass[i] * gravity.y;
    s->b[DOF * i + 2] = s->mass[i] * gravity.z;
  }
  s->load_norm = sqrt(dot(s->b, s->b, n));
  // Restart from the warm solution: r = b - K x.
  apply_stiffness(l, s->x, s->q);
  for (uint32_t i = 0; i < n; ++i)
    s->r[i] = s->b[i] - s->q[i];
  v_cycle(s, 0, s->r, s->z);
  memcpy(s->p, s->z, sizeof(double) * n);
  s->rz = dot(s->r, s->z, n);
  s->residual = s->load_norm > 0.0 ? sqrt(dot(s->r, s->r, n)) / s->load_norm : 0.0;
}

uint32_t rt_stress_iterate(rt_stress* s, uint32_t max_iterations, double tolerance) {
  const rt_stress_level* l = &s->levels[0];
  uint32_t n = DOF * s->node_count, done = 0;
  while (done < max_iterations && s->residual > tolerance) {
    apply_stiffness(l, s->p, s->q);
    double pq = dot(s->p, s->q, n);
    if (!(pq > 0.0)) break; // nothing left to descend along
    double alpha = s->rz / pq;
    for (uint32_t i = 0; i < n; ++i) {
      s->x[i] += alpha * s->p[i];
      s->r[i] -= alpha * s->q[i];
    }
    v_cycle(s, 0, s->r, s->z);
    double rz = dot(s->r, s->z, n);
    double beta = s->rz > 0.0 ? rz / s->rz : 0.0;
    s->rz = rz;
    for (uint32_t i = 0; i < n; ++i)
      s->p[i] = s->z[i] + beta * s->p[i];
    s->residual = sqrt(dot(s->r, s->r, n)) / s->load_norm;
    done++;
  }
  return done;
}

bool rt_stress_converged(const rt_stress* s, double tolerance) { return s->residual <= tolerance; }

uint64_t rt_stress_iteration_cost(const rt_stress* s) {
  // Per iteration: the CG product and two in the V-cycle at each level but
  // the coarsest.
  uint64_t cost = s->levels[0].bond_count;
  for (uint32_t i = 0; i + 1 < s->level_count; ++i)
    cost += 2u * (uint64_t)s->levels[i].bond_count;
  return cost ? cost : 1u;
}

void rt_stress_bond_stress(const rt_stress* s, uint32_t k, double out[3]) {
  const rt_stress_level* l = &s->levels[0];
  double f[3] = {0}, m[3] = {0};
  bond_response(l, k, s->x, f, m);
  const double* n = &l->frame[9 * k];
  double area = s->area[k], root = area * sqrt(area);
  double normal = dot3(f, n), twist = dot3(m, n);
  double shear[3] = {f[0] - normal * n[0], f[1] - normal * n[1], f[2] - normal * n[2]};
  double bend[3] = {m[0] - twist * n[0], m[1] - twist * n[1], m[2] - twist * n[2]};
  double bending = 6.0 * sqrt(dot3(bend, bend)) / root;
  out[0] = fmax(0.0, -normal / area + bending);
  out[1] = fmax(0.0, normal / area + bending);
  out[2] = sqrt(dot3(shear, shear)) / area + 4.8 * fabs(twist) / root;
}
