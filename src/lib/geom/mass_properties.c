// Exact mass properties of closed meshes by the divergence theorem
// (D. Eberly, "Polyhedral Mass Properties (Revisited)"): each triangle
// contributes closed-form surface integrals of polynomials up to degree 3.
#include "bk_geom.h"

static inline void subexpressions(double w0, double w1, double w2, double* f1, double* f2, double* f3,
                                  double* g0, double* g1, double* g2) {
  double temp0 = w0 + w1;
  *f1 = temp0 + w2;
  double temp1 = w0 * w0;
  double temp2 = temp1 + w1 * temp0;
  *f2 = temp2 + w2 * *f1;
  *f3 = w0 * temp1 + w1 * temp2 + w2 * *f2;
  *g0 = *f2 + w0 * (*f1 + w0);
  *g1 = *f2 + w1 * (*f1 + w1);
  *g2 = *f2 + w2 * (*f1 + w2);
}

bk_moments bk_mesh_moments(const bk_mesh* m) {
  double in[10] = {0};
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    bk_vec3 p0 = m->positions[bk_mesh_tri_position(m, t, 0)];
    bk_vec3 p1 = m->positions[bk_mesh_tri_position(m, t, 1)];
    bk_vec3 p2 = m->positions[bk_mesh_tri_position(m, t, 2)];
    bk_vec3 d = bk_v3_cross(bk_v3_sub(p1, p0), bk_v3_sub(p2, p0));
    double f1x, f2x, f3x, g0x, g1x, g2x, f1y, f2y, f3y, g0y, g1y, g2y, f1z, f2z, f3z, g0z, g1z, g2z;
    subexpressions(p0.x, p1.x, p2.x, &f1x, &f2x, &f3x, &g0x, &g1x, &g2x);
    subexpressions(p0.y, p1.y, p2.y, &f1y, &f2y, &f3y, &g0y, &g1y, &g2y);
    subexpressions(p0.z, p1.z, p2.z, &f1z, &f2z, &f3z, &g0z, &g1z, &g2z);
    in[0] += d.x * f1x;
    in[1] += d.x * f2x;
    in[2] += d.y * f2y;
    in[3] += d.z * f2z;
    in[4] += d.x * f3x;
    in[5] += d.y * f3y;
    in[6] += d.z * f3z;
    in[7] += d.x * (p0.y * g0x + p1.y * g1x + p2.y * g2x);
    in[8] += d.y * (p0.z * g0y + p1.z * g1y + p2.z * g2y);
    in[9] += d.z * (p0.x * g0z + p1.x * g1z + p2.x * g2z);
  }
  return (bk_moments){
      .v = in[0] / 6.0,
      .x = in[1] / 24.0,
      .y = in[2] / 24.0,
      .z = in[3] / 24.0,
      .xx = in[4] / 60.0,
      .yy = in[5] / 60.0,
      .zz = in[6] / 60.0,
      .xy = in[7] / 120.0,
      .yz = in[8] / 120.0,
      .zx = in[9] / 120.0,
  };
}

bk_moments bk_moments_add(bk_moments a, bk_moments b) {
  return (bk_moments){a.v + b.v,   a.x + b.x,   a.y + b.y,   a.z + b.z,   a.xx + b.xx,
                      a.yy + b.yy, a.zz + b.zz, a.xy + b.xy, a.yz + b.yz, a.zx + b.zx};
}

bk_mass_properties bk_moments_to_mass(bk_moments m) {
  bk_mass_properties r = {0};
  r.volume = m.v;
  if (m.v == 0.0) return r;
  bk_vec3 c = bk_v3(m.x / m.v, m.y / m.v, m.z / m.v);
  r.centroid = c;
  // Inertia about the origin, then the parallel-axis shift to the centroid.
  double ixx = m.yy + m.zz - m.v * (c.y * c.y + c.z * c.z);
  double iyy = m.xx + m.zz - m.v * (c.x * c.x + c.z * c.z);
  double izz = m.xx + m.yy - m.v * (c.x * c.x + c.y * c.y);
  double ixy = -(m.xy - m.v * c.x * c.y);
  double iyz = -(m.yz - m.v * c.y * c.z);
  double izx = -(m.zx - m.v * c.z * c.x);
  r.inertia[0][0] = ixx, r.inertia[0][1] = ixy, r.inertia[0][2] = izx;
  r.inertia[1][0] = ixy, r.inertia[1][1] = iyy, r.inertia[1][2] = iyz;
  r.inertia[2][0] = izx, r.inertia[2][1] = iyz, r.inertia[2][2] = izz;
  return r;
}

double bk_mesh_volume(const bk_mesh* m) { return bk_mesh_moments(m).v; }
