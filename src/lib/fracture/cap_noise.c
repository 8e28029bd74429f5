// Noisy caps for the planes pattern (APEX's noisy slices). A cut's cap is
// meshed at the noise's own resolution: the nodes of a square grid laid in
// the cut plane, about a quarter wave apart, are inserted into the cap's
// triangulation wherever they fall inside it (away from its border), the
// triangulation is made Delaunay again by edge flips, and the new points are
// pushed along the plane's normal by coherent noise. (Refining the cap's own
// triangles, splitting the long diagonals the tessellator makes, gives far
// more triangles, and every later cut inherits them.)
//
// The cap's border (where it meets the piece's surface) is neither split nor
// moved and the push tapers towards it, so both pieces of the cut still
// close against their surfaces; both use the one refined cap, so they fit
// each other and their volumes add up. The push is along the normal only:
// seen along it, the cap is a flat triangulation, which is how bonds measure
// their contact.
#include <stdlib.h>
#include <string.h>

#include "cap.h"

typedef struct cap_mesher {
  bk_cap_noise* out;
  double (*xy)[2]; // per point: plane coordinates
  uint32_t xy_capacity;
  int32_t* nbr;          // per triangle edge k (v[k] -> v[k+1]): the triangle across, or -1 (border)
  uint32_t nbr_capacity; // triangles
  double turn;           // +1: triangles run counter-clockwise in (x, y), -1: clockwise
} cap_mesher;

static uint32_t add_point(cap_mesher* m, bk_vec3 p, double x, double y) {
  bk_cap_noise* out = m->out;
  if (out->point_count == out->point_capacity) {
    out->point_capacity = bk_grow_capacity(out->point_capacity, out->point_count + 1);
    out->points = bk_realloc(out->points, sizeof(bk_vec3) * out->point_capacity);
  }
  if (out->point_count >= m->xy_capacity) {
    m->xy_capacity = bk_grow_capacity(m->xy_capacity, out->point_count + 1);
    m->xy = bk_realloc(m->xy, sizeof(double[2]) * m->xy_capacity);
  }
  out->points[out->point_count] = p;
  m->xy[out->point_count][0] = x, m->xy[out->point_count][1] = y;
  return out->point_count++;
}

static uint32_t add_triangle(cap_mesher* m, uint32_t parent, uint32_t a, uint32_t b, uint32_t c) {
  bk_cap_noise* out = m->out;
  if (out->triangle_count == out->triangle_capacity) {
    out->triangle_capacity = bk_grow_capacity(out->triangle_capacity, out->triangle_count + 1);
    out->triangles = bk_realloc(out->triangles, sizeof(uint32_t) * 3 * out->triangle_capacity);
    out->parents = bk_realloc(out->parents, sizeof(uint32_t) * out->triangle_capacity);
  }
  if (out->triangle_count >= m->nbr_capacity) { // out keeps its storage from call to call; nbr does not
    m->nbr_capacity = out->triangle_capacity;
    m->nbr = bk_realloc(m->nbr, sizeof(int32_t) * 3 * m->nbr_capacity);
  }
  uint32_t t = out->triangle_count++;
  out->triangles[3 * t] = a, out->triangles[3 * t + 1] = b, out->triangles[3 * t + 2] = c;
  out->parents[t] = parent;
  m->nbr[3 * t] = m->nbr[3 * t + 1] = m->nbr[3 * t + 2] = -1;
  return t;
}

// Twice the signed area of (a, b, c), positive when they turn the cap's way.
static double orient(const cap_mesher* m, uint32_t a, uint32_t b, const double c[2]) {
  const double *p = m->xy[a], *q = m->xy[b];
  return m->turn * ((q[0] - p[0]) * (c[1] - p[1]) - (q[1] - p[1]) * (c[0] - p[0]));
}

// Points the triangle across `t`'s edge from a to b back at `t`.
static void relink(cap_mesher* m, int32_t across, uint32_t a, uint32_t b, uint32_t t) {
  if (across < 0) return;
  const uint32_t* v = m->out->triangles + 3 * across;
  for (int k = 0; k < 3; ++k)
    if (v[k] == b && v[(k + 1) % 3] == a) m->nbr[3 * across + k] = (int32_t)t;
}

// Splits triangle t into three at the new point p (inside it).
static void split(cap_mesher* m, uint32_t t, uint32_t p, uint32_t** children, uint32_t* child_count,
                  uint32_t* child_capacity) {
  uint32_t* v = m->out->triangles + 3 * t;
  uint32_t a = v[0], b = v[1], c = v[2];
  int32_t nab = m->nbr[3 * t], nbc = m->nbr[3 * t + 1], nca = m->nbr[3 * t + 2];
  uint32_t parent = m->out->parents[t];
  uint32_t t1 = add_triangle(m, parent, b, c, p), t2 = add_triangle(m, parent, c, a, p);
  v = m->out->triangles + 3 * t; // storage may have moved
  v[2] = p;                      // t becomes (a, b, p)
  m->nbr[3 * t] = nab, m->nbr[3 * t + 1] = (int32_t)t1, m->nbr[3 * t + 2] = (int32_t)t2;
  m->nbr[3 * t1] = nbc, m->nbr[3 * t1 + 1] = (int32_t)t2, m->nbr[3 * t1 + 2] = (int32_t)t;
  m->nbr[3 * t2] = nca, m->nbr[3 * t2 + 1] = (int32_t)t, m->nbr[3 * t2 + 2] = (int32_t)t1;
  relink(m, nbc, b, c, t1);
  relink(m, nca, c, a, t2);
  if (*child_count + 2 > *child_capacity) {
    *child_capacity = bk_grow_capacity(*child_capacity, *child_count + 2);
    *children = bk_realloc(*children, sizeof(uint32_t) * *child_capacity);
  }
  (*children)[(*child_count)++] = t1;
  (*children)[(*child_count)++] = t2;
}

// Whether d lies inside the circle through a, b, c (which turn the cap's way).
static bool in_circle(const cap_mesher* m, uint32_t a, uint32_t b, uint32_t c, uint32_t d, double tiny) {
  const double *pa = m->xy[a], *pb = m->xy[b], *pc = m->xy[c], *pd = m->xy[d];
  double ax = pa[0] - pd[0], ay = pa[1] - pd[1], bx = pb[0] - pd[0], by = pb[1] - pd[1];
  double cx = pc[0] - pd[0], cy = pc[1] - pd[1];
  double det = (ax * ax + ay * ay) * (bx * cy - cx * by) - (bx * bx + by * by) * (ax * cy - cx * ay) +
               (cx * cx + cy * cy) * (ax * by - bx * ay);
  return m->turn * det > tiny;
}

// Lawson's flips until every inner edge is locally Delaunay (the border
// edges have no triangle across and are never flipped).
static void make_delaunay(cap_mesher* m, double tiny_area, double tiny_circle) {
  uint32_t count = m->out->triangle_count;
  uint32_t capacity = 3u * count + 16u, top = 0;
  uint32_t* stack = bk_alloc(sizeof(uint32_t) * capacity);
  for (uint32_t e = 0; e < 3u * count; ++e)
    if (m->nbr[e] >= 0) stack[top++] = e;
  uint64_t budget = 64ull * count; // a guard against rounding cycles
  while (top > 0 && budget-- > 0) {
    uint32_t e = stack[--top], t1 = e / 3, k = e % 3;
    int32_t t2 = m->nbr[e];
    if (t2 < 0) continue;
    uint32_t* v1 = m->out->triangles + 3 * t1;
    uint32_t* v2 = m->out->triangles + 3 * t2;
    uint32_t a = v1[k], b = v1[(k + 1) % 3], c = v1[(k + 2) % 3];
    int l = 0;
    while (l < 3 && !(v2[l] == b && v2[(l + 1) % 3] == a))
      ++l;
    if (l == 3) continue;
    uint32_t d = v2[(l + 2) % 3];
    if (!in_circle(m, a, b, c, d, tiny_circle)) continue;
    if (!(orient(m, a, d, m->xy[c]) > tiny_area) || !(orient(m, d, b, m->xy[c]) > tiny_area)) continue;
    int32_t nbc = m->nbr[3 * t1 + (k + 1) % 3], nca = m->nbr[3 * t1 + (k + 2) % 3];
    int32_t nad = m->nbr[3 * t2 + (l + 1) % 3], ndb = m->nbr[3 * t2 + (l + 2) % 3];
    // (a, b, c) + (b, a, d) -> (a, d, c) + (d, b, c)
    v1[0] = a, v1[1] = d, v1[2] = c;
    v2[0] = d, v2[1] = b, v2[2] = c;
    m->nbr[3 * t1] = nad, m->nbr[3 * t1 + 1] = t2, m->nbr[3 * t1 + 2] = nca;
    m->nbr[3 * t2] = ndb, m->nbr[3 * t2 + 1] = nbc, m->nbr[3 * t2 + 2] = (int32_t)t1;
    relink(m, nad, a, d, t1);
    relink(m, nbc, b, c, (uint32_t)t2);
    if (top + 4 > capacity) {
      capacity = bk_grow_capacity(capacity, top + 4);
      stack = bk_realloc(stack, sizeof(uint32_t) * capacity);
    }
    stack[top++] = 3 * t1, stack[top++] = 3 * t1 + 2;
    stack[top++] = 3 * (uint32_t)t2, stack[top++] = 3 * (uint32_t)t2 + 1;
  }
  bk_free(stack);
}

static double distance_to_segment(const double p[2], const double a[2], const double b[2]) {
  double abx = b[0] - a[0], aby = b[1] - a[1];
  double len2 = abx * abx + aby * aby;
  double t = len2 > 0.0 ? ((p[0] - a[0]) * abx + (p[1] - a[1]) * aby) / len2 : 0.0;
  t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
  double dx = p[0] - (a[0] + abx * t), dy = p[1] - (a[1] + aby * t);
  return sqrt(dx * dx + dy * dy);
}

static double distance_to_border(const cap_mesher* m, const double p[2], const uint32_t* border,
                                 uint32_t border_count) {
  double best = INFINITY;
  for (uint32_t e = 0; e < border_count; ++e)
    best = fmin(best, distance_to_segment(p, m->xy[border[2 * e]], m->xy[border[2 * e + 1]]));
  return best;
}

void bk_cap_noise_make(const bk_cap_noise_def* def, const uint32_t* triangles, uint32_t triangle_count,
                       const bk_vec3* points, uint32_t point_count, bk_cap_noise* out) {
  out->point_count = out->triangle_count = 0;
  cap_mesher m = {.out = out, .turn = 1.0};
  bk_vec3 u = {0}, v = {0};
  bk_plane_basis(def->normal, &u, &v);
  bk_vec3 origin = point_count ? points[0] : bk_v3(0, 0, 0);
  for (uint32_t i = 0; i < point_count; ++i) {
    bk_vec3 d = bk_v3_sub(points[i], origin);
    add_point(&m, points[i], bk_v3_dot(d, u), bk_v3_dot(d, v));
  }
  double area = 0.0, signed_area = 0.0;
  for (uint32_t t = 0; t < triangle_count; ++t) {
    const uint32_t* tri = triangles + 3 * t;
    add_triangle(&m, t, tri[0], tri[1], tri[2]);
    double a2 = orient(&m, tri[0], tri[1], m.xy[tri[2]]);
    signed_area += a2, area += 0.5 * fabs(a2);
  }
  m.turn = signed_area < 0.0 ? -1.0 : 1.0;
  if (!(def->amplitude > 0.0) || !(def->frequency > 0.0) || !(area > 0.0)) {
    bk_free(m.xy);
    bk_free(m.nbr);
    return;
  }

  // Neighbours across every edge; edges with none are the border.
  bk_index_map edges = {0};
  bk_index_map_init(&edges, 3u * triangle_count);
  for (uint32_t e = 0; e < 3u * triangle_count; ++e) {
    bool inserted = false;
    bk_index_map_insert(&edges, bk_directed_edge_key(triangles[e], triangles[e - e % 3 + (e + 1) % 3]), e,
                        &inserted);
  }
  uint32_t* border = bk_alloc(sizeof(uint32_t) * 6u * triangle_count);
  uint32_t border_count = 0;
  for (uint32_t e = 0; e < 3u * triangle_count; ++e) {
    uint32_t a = triangles[e], b = triangles[e - e % 3 + (e + 1) % 3];
    const uint32_t* across = bk_index_map_find(&edges, bk_directed_edge_key(b, a));
    m.nbr[e] = across ? (int32_t)(*across / 3) : -1;
    if (!across) border[2 * border_count] = a, border[2 * border_count + 1] = b, border_count++;
  }
  bk_index_map_free(&edges);

  // Grid nodes strictly inside each cap triangle and at least half a
  // spacing from the border go into it, splitting the piece they fall in.
  double h = fmax(BK_CAP_NOISE_SPACING / def->frequency, sqrt(area / BK_CAP_NOISE_MAX_NODES));
  double tiny_area = 1e-9 * h * h;
  uint32_t *children = NULL, child_count = 0, child_capacity = 0;
  for (uint32_t t = 0; t < triangle_count; ++t) {
    const uint32_t* tri = triangles + 3 * t;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 2; ++d)
        lo[d] = fmin(lo[d], m.xy[tri[k]][d]), hi[d] = fmax(hi[d], m.xy[tri[k]][d]);
    child_count = 0;
    if (child_capacity == 0) {
      child_capacity = 64;
      children = bk_alloc(sizeof(uint32_t) * child_capacity);
    }
    children[child_count++] = t;
    for (double y = ceil(lo[1] / h) * h; y < hi[1]; y += h)
      for (double x = ceil(lo[0] / h) * h; x < hi[0]; x += h) {
        double p[2] = {x, y};
        if (!(orient(&m, tri[0], tri[1], p) > tiny_area) || !(orient(&m, tri[1], tri[2], p) > tiny_area) ||
            !(orient(&m, tri[2], tri[0], p) > tiny_area))
          continue;
        if (distance_to_border(&m, p, border, border_count) < 0.5 * h) continue;
        uint32_t inside = UINT32_MAX;
        for (uint32_t c = 0; c < child_count && inside == UINT32_MAX; ++c) {
          const uint32_t* cv = out->triangles + 3 * children[c];
          if (orient(&m, cv[0], cv[1], p) > tiny_area && orient(&m, cv[1], cv[2], p) > tiny_area &&
              orient(&m, cv[2], cv[0], p) > tiny_area)
            inside = children[c];
        }
        if (inside == UINT32_MAX) continue; // on a piece's edge: left out
        bk_vec3 q = bk_v3_add(origin, bk_v3_add(bk_v3_scale(u, x), bk_v3_scale(v, y)));
        split(&m, inside, add_point(&m, q, x, y), &children, &child_count, &child_capacity);
      }
  }
  bk_free(children);
  make_delaunay(&m, tiny_area, 1e-12 * h * h * h * h);

  // Push: never more than a quarter of the distance to the border (no fold
  // at it), a tenth of the cap's size (no piece turned inside out) or the
  // caller's limit (a quarter of the thinner piece's depth behind the cap).
  double most = fmin(fmin(def->amplitude, 0.1 * sqrt(area)), def->limit);
  int noise_seed = (int)(def->seed & 0xff);
  double offset = (double)((def->seed >> 8) & 0xffff) * 0.618;
  for (uint32_t p = point_count; p < out->point_count; ++p) {
    double to_border = distance_to_border(&m, m.xy[p], border, border_count);
    bk_vec3 q = out->points[p];
    double n = bk_noise3(bk_v3(q.x * def->frequency + offset, q.y * def->frequency, q.z * def->frequency),
                         noise_seed);
    out->points[p] = bk_v3_add(q, bk_v3_scale(def->normal, n * fmin(most, 0.25 * to_border)));
  }
  bk_free(border);
  bk_free(m.xy);
  bk_free(m.nbr);
}

void bk_cap_noise_free(bk_cap_noise* noise) {
  bk_free(noise->points);
  bk_free(noise->triangles);
  bk_free(noise->parents);
  memset(noise, 0, sizeof *noise);
}
