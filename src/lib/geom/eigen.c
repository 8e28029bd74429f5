// Eigen-decomposition of symmetric 3x3 matrices (cyclic Jacobi rotations):
// principal moments and axes of inertia tensors.
#include "bk_geom.h"

void bk_sym3_eigen(const double m[3][3], double values[3], double vectors[3][3]) {
  double a[3][3], v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      a[i][j] = 0.5 * (m[i][j] + m[j][i]);
  for (int sweep = 0; sweep < 50; ++sweep) {
    double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    double scale = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
    if (off <= 1e-30 * scale || off == 0.0) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0.0) continue;
        // Rotation angle that zeroes a[p][q] (Numerical Recipes' stable form).
        double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        double t = (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
        double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < 3; ++k) { // columns p, q
          double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) { // rows p, q
          double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {
          double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
  }
  for (int i = 0; i < 3; ++i) {
    values[i] = a[i][i];
    for (int k = 0; k < 3; ++k)
      vectors[k][i] = v[k][i];
  }
  // A right-handed frame, so the axes form a rotation.
  bk_vec3 c0 = bk_v3(vectors[0][0], vectors[1][0], vectors[2][0]);
  bk_vec3 c1 = bk_v3(vectors[0][1], vectors[1][1], vectors[2][1]);
  bk_vec3 c2 = bk_v3(vectors[0][2], vectors[1][2], vectors[2][2]);
  if (bk_v3_dot(bk_v3_cross(c0, c1), c2) < 0.0)
    for (int k = 0; k < 3; ++k)
      vectors[k][2] = -vectors[k][2];
}

bk_quat bk_quat_from_matrix(const double r[3][3]) {
  // Shepperd's method: pick the largest diagonal term for stability.
  double trace = r[0][0] + r[1][1] + r[2][2];
  bk_quat q;
  if (trace > 0.0) {
    double s = 2.0 * sqrt(trace + 1.0);
    q = (bk_quat){(r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s, 0.25 * s};
  } else if (r[0][0] > r[1][1] && r[0][0] > r[2][2]) {
    double s = 2.0 * sqrt(1.0 + r[0][0] - r[1][1] - r[2][2]);
    q = (bk_quat){0.25 * s, (r[0][1] + r[1][0]) / s, (r[0][2] + r[2][0]) / s, (r[2][1] - r[1][2]) / s};
  } else if (r[1][1] > r[2][2]) {
    double s = 2.0 * sqrt(1.0 + r[1][1] - r[0][0] - r[2][2]);
    q = (bk_quat){(r[0][1] + r[1][0]) / s, 0.25 * s, (r[1][2] + r[2][1]) / s, (r[0][2] - r[2][0]) / s};
  } else {
    double s = 2.0 * sqrt(1.0 + r[2][2] - r[0][0] - r[1][1]);
    q = (bk_quat){(r[0][2] + r[2][0]) / s, (r[1][2] + r[2][1]) / s, 0.25 * s, (r[1][0] - r[0][1]) / s};
  }
  return bk_quat_normalize(q);
}
