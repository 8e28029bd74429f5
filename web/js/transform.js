// Rigid transforms {p: [x,y,z], q: [x,y,z,w]} (rotate, then translate), as
// bk_transform in include/breakables/types.h.

export function rotate(q, v) {
  const [x, y, z, w] = q;
  // v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z)
  const tx = 2 * (y * v[2] - z * v[1]), ty = 2 * (z * v[0] - x * v[2]), tz = 2 * (x * v[1] - y * v[0]);
  return [v[0] + w * tx + (y * tz - z * ty), v[1] + w * ty + (z * tx - x * tz), v[2] + w * tz + (x * ty - y * tx)];
}

export function qmul(a, b) {
  const [ax, ay, az, aw] = a, [bx, by, bz, bw] = b;
  return [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
    aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz];
}

export const conjugate = (q) => [-q[0], -q[1], -q[2], q[3]];

export function apply(t, v) {
  const r = rotate(t.q, v);
  return [r[0] + t.p[0], r[1] + t.p[1], r[2] + t.p[2]];
}

// a after b: apply(mul(a, b), v) = apply(a, apply(b, v)).
export function mul(a, b) {
  return { p: apply(a, b.p), q: qmul(a.q, b.q) };
}

export function inverse(t) {
  const q = conjugate(t.q);
  const p = rotate(q, t.p);
  return { p: [-p[0], -p[1], -p[2]], q };
}
