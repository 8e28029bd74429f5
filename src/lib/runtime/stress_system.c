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
// node is connected to a support, and is solved by conjugate gradients,
// warm-started from the last solution and preconditioned by a multigrid
// over the mesh tree: the fragments under one tree node make one coarse
// node that moves rigidly, and since a rigid motion strains no bond inside
// it, the coarse system is made of the bonds between coarse nodes alone,
// each with its lever arms moved to the coarse centroids: the same beams,
// exactly (Galerkin). Coarse nodes share many bonds, so each coarse level is
// assembled, its bonds merged into one 6 x 6 block per pair of nodes, and
// V-cycled with damped block-Jacobi smoothing (each node's own 6 x 6
// stiffness, inverted once per system); the coarsest is solved directly.
// The finest level is matrix-free (bond by bond) and joins the rest
// additively: z = D^-1 r + P (coarse V-cycle) P^T r, so the conjugate
// gradients' product is the only one with the finest matrix per iteration.
// Measured on a 1,024-fragment wall (6,060 bonds): Jacobi alone needed 200
// to 450 iterations; a V-cycle at every level 15 (sound) and 30 (holed) at
// 0.45 and 0.22 ms each; the additive finest level 25 and 63 at 0.20 and
// 0.11 ms each: less work in all, in steps a third the size, which is what
// a per-call budget needs.
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

enum { DOF = RT_STRESS_DOF, BLOCK = RT_STRESS_DOF * RT_STRESS_DOF };

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
  rt_stress_cross(xa + 3, ra, ta_r);
  rt_stress_cross(xb + 3, rb, tb_r);
  double d[3] = {xb[0] + tb_r[0] - xa[0] - ta_r[0], xb[1] + tb_r[1] - xa[1] - ta_r[1],
                 xb[2] + tb_r[2] - xa[2] - ta_r[2]};
  double w[3] = {xb[3] - xa[3], xb[4] - xa[4], xb[5] - xa[5]};
  double dn = rt_stress_dot3(d, n), wn = rt_stress_dot3(w, n);
  for (int i = 0; i < 3; ++i) {
    force[i] = stiff[0] * dn * n[i] + stiff[1] * (d[i] - dn * n[i]);
    moment[i] = stiff[3] * wn * n[i] + stiff[2] * (w[i] - wn * n[i]);
  }
}

// out = K x over a level's free nodes (fixed nodes' rows are zero), bond by
// bond (the finest level: most of its bonds join distinct pairs).
static void apply_bonds(const rt_stress_level* l, const double* x, double* out) {
  memset(out, 0, sizeof(double) * DOF * l->node_count);
  for (uint32_t k = 0; k < l->bond_count; ++k) {
    double f[3] = {0}, m[3] = {0}, arm[3] = {0};
    bond_response(l, k, x, f, m);
    const double* g = &l->frame[9 * k];
    double* oa = &out[DOF * l->ends[2 * k]];
    double* ob = &out[DOF * l->ends[2 * k + 1]];
    rt_stress_cross(g + 6, f, arm);
    for (int i = 0; i < 3; ++i) {
      ob[i] += f[i];
      ob[3 + i] += arm[i] + m[i];
    }
    rt_stress_cross(g + 3, f, arm);
    for (int i = 0; i < 3; ++i) {
      oa[i] -= f[i];
      oa[3 + i] -= arm[i] + m[i];
    }
  }
  for (uint32_t i = 0; i < l->node_count; ++i)
    if (l->fixed[i]) memset(&out[DOF * i], 0, sizeof(double) * DOF);
}

// out += m x (6 x 6 by 6) and out2 += m^T x2.
static void multiply_block(const double* m, const double* x, double* out) {
  for (int i = 0; i < DOF; ++i) {
    double v = 0.0;
    for (int j = 0; j < DOF; ++j)
      v += m[DOF * i + j] * x[j];
    out[i] += v;
  }
}

static void multiply_block_transposed(const double* m, const double* x, double* out) {
  for (int j = 0; j < DOF; ++j) {
    double xj = x[j];
    for (int i = 0; i < DOF; ++i)
      out[i] += m[DOF * j + i] * xj;
  }
}

// out = K x from the assembled blocks (coarse levels). Pairs with a fixed
// end are left out of the assembly: a fixed node's x is always zero.
static void apply_assembled(const rt_stress_level* l, const double* x, double* out) {
  memset(out, 0, sizeof(double) * DOF * l->node_count);
  for (uint32_t i = 0; i < l->node_count; ++i)
    if (!l->fixed[i]) multiply_block(&l->diagonal[BLOCK * i], &x[DOF * i], &out[DOF * i]);
  for (uint32_t k = 0; k < l->pair_count; ++k) {
    uint32_t a = l->pair_ends[2 * k], b = l->pair_ends[2 * k + 1];
    const double* m = &l->pair_block[BLOCK * k];
    multiply_block(m, &x[DOF * b], &out[DOF * a]);
    multiply_block_transposed(m, &x[DOF * a], &out[DOF * b]);
  }
}

static void apply_stiffness(const rt_stress_level* l, const double* x, double* out) {
  if (l->diagonal)
    apply_assembled(l, x, out);
  else
    apply_bonds(l, x, out);
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

// z += damping x D^-1 r (each free node's own block, inverted once: a
// product is a fraction of the cost of two triangular solves).
static void jacobi(const rt_stress_level* l, const double* r, double* z) {
  for (uint32_t i = 0; i < l->node_count; ++i)
    if (!l->fixed[i]) multiply_block(&l->inverse[BLOCK * i], &r[DOF * i], &z[DOF * i]);
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
    rt_stress_cross(o, f, arm);
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
    rt_stress_cross(c + 3, o, turn);
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
  if (index == 0) {
    // The finest level, additively: z = D^-1 r + P Kc^-1 P^T r. Symmetric,
    // and it needs no product with the finest matrix (the conjugate
    // gradients make the only one), so an iteration costs about a third of
    // a V-cycle's there. It takes about twice the iterations (25 against 15
    // on a sound 1,024-fragment wall) for less work in all, and a call's
    // budget is spent in steps a third the size.
    jacobi(l, r, z);
    restrict_residual(l, c, r, rc);
    v_cycle(s, index + 1, rc, zc);
    prolong(l, c, zc, z);
    return;
  }
  // Coarser levels (assembled, small): a V-cycle, one Jacobi sweep before
  // and after the coarse correction.
  jacobi(l, r, z);
  apply_stiffness(l, z, t);
  for (uint32_t i = 0; i < n; ++i)
    t[i] = r[i] - t[i];
  restrict_residual(l, c, t, rc);
  v_cycle(s, index + 1, rc, zc);
  prolong(l, c, zc, z);
  apply_stiffness(l, z, t);
  for (uint32_t i = 0; i < n; ++i)
    t[i] = r[i] - t[i];
  jacobi(l, t, z);
}

// ---------------------------------------------------------------- the solve

void rt_stress_load(rt_stress* s, bk_vec3 gravity, const double* node_loads) {
  const rt_stress_level* l = &s->levels[0];
  uint32_t n = DOF * s->node_count;
  while (!s->ready) // the rest of the setup, all at once
    rt_stress_setup_step(s);
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
    if (node_loads)
      for (int d = 0; d < DOF; ++d)
        s->b[DOF * i + d] += node_loads[DOF * i + d];
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
  s->loaded = true;
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

bool rt_stress_converged(const rt_stress* s, double tolerance) {
  return s->loaded && s->residual <= tolerance;
}

uint64_t rt_stress_iteration_cost(const rt_stress* s) {
  // In bond evaluations: the finest level's product (one per bond) and its
  // Jacobi, restriction and prolongation (about two per node); per coarse
  // level two assembled products (a pair's block costs about a bond) and
  // two sweeps; the coarsest's triangular solves (n^2 products, a bond
  // evaluation being some 60). Measured: 0.2 ms for a sound 1,024-fragment
  // wall (6,060 bonds; 9,800 units), 0.11 ms for it holed (2,577 bonds).
  const rt_stress_level* finest = &s->levels[0];
  uint64_t cost = (uint64_t)finest->bond_count + 2u * (uint64_t)finest->node_count;
  for (uint32_t i = 1; i + 1 < s->level_count; ++i)
    cost += 2u * (uint64_t)s->levels[i].pair_count + 4u * (uint64_t)s->levels[i].node_count;
  uint64_t dense = s->levels[s->level_count - 1].dense_size;
  cost += dense * dense / 60u;
  return cost ? cost : 1u;
}

void rt_stress_bond_stress(const rt_stress* s, uint32_t k, double out[3]) {
  const rt_stress_level* l = &s->levels[0];
  double f[3] = {0}, m[3] = {0};
  bond_response(l, k, s->x, f, m);
  const double* n = &l->frame[9 * k];
  double area = s->area[k], root = area * sqrt(area);
  double normal = rt_stress_dot3(f, n), twist = rt_stress_dot3(m, n);
  double shear[3] = {f[0] - normal * n[0], f[1] - normal * n[1], f[2] - normal * n[2]};
  double bend[3] = {m[0] - twist * n[0], m[1] - twist * n[1], m[2] - twist * n[2]};
  double bending = 6.0 * sqrt(rt_stress_dot3(bend, bend)) / root;
  out[0] = fmax(0.0, -normal / area + bending);
  out[1] = fmax(0.0, normal / area + bending);
  out[2] = sqrt(rt_stress_dot3(shear, shear)) / area + 4.8 * fabs(twist) / root;
}
