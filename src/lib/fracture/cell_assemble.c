// The cell patterns' tree nodes: a balanced hierarchy over the leaves (each
// node's children are the connected parts of its two halves along its
// longest extent; the clustered pattern's root splits into its chunks
// first), each node's mesh made of its leaves' triangles minus the faces its
// leaves share. Corners: surface pieces interpolate the source triangle's
// attributes; cut faces get the face's normal, planar uvs in texture tiles
// (the same on both sides, so the halves of a crack match) and a tangent
// along u.
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "cell_stages.h"
#include "tree_data.h"

typedef struct csr {
  uint32_t *start, *items;
} csr;

static void csr_free(csr* c) {
  bk_free(c->start);
  bk_free(c->items);
}

// Groups `count` items by key (< keys), keeping their order within a key.
static csr csr_build(const uint32_t* key_of, uint32_t count, uint32_t keys) {
  csr c = {bk_calloc(keys + 1, sizeof(uint32_t)), bk_alloc(sizeof(uint32_t) * (count ? count : 1))};
  for (uint32_t i = 0; i < count; ++i)
    c.start[key_of[i] + 1]++;
  for (uint32_t k = 0; k < keys; ++k)
    c.start[k + 1] += c.start[k];
  uint32_t* fill = bk_alloc(sizeof(uint32_t) * (keys ? keys : 1));
  memcpy(fill, c.start, sizeof(uint32_t) * keys);
  for (uint32_t i = 0; i < count; ++i)
    c.items[fill[key_of[i]]++] = i;
  bk_free(fill);
  return c;
}

typedef struct leaf_info {
  double moments[4];
  uint32_t cluster;
} leaf_info;

typedef struct hierarchy {
  uint32_t *parent, *first_child, *child_count, *leaf_first, *leaf_count;
  uint32_t count, capacity;
  uint32_t* pool; // leaves of each node
  uint32_t pool_count, pool_capacity;
} hierarchy;

static uint32_t add_node(hierarchy* h, uint32_t parent, const uint32_t* leaves, uint32_t n) {
  if (h->count == h->capacity) {
    h->capacity = bk_grow_capacity(h->capacity, h->count + 1);
    h->parent = bk_realloc(h->parent, sizeof(uint32_t) * h->capacity);
    h->first_child = bk_realloc(h->first_child, sizeof(uint32_t) * h->capacity);
    h->child_count = bk_realloc(h->child_count, sizeof(uint32_t) * h->capacity);
    h->leaf_first = bk_realloc(h->leaf_first, sizeof(uint32_t) * h->capacity);
    h->leaf_count = bk_realloc(h->leaf_count, sizeof(uint32_t) * h->capacity);
  }
  if (h->pool_count + n > h->pool_capacity) {
    h->pool_capacity = bk_grow_capacity(h->pool_capacity, h->pool_count + n);
    h->pool = bk_realloc(h->pool, sizeof(uint32_t) * h->pool_capacity);
  }
  memmove(h->pool + h->pool_count, leaves, sizeof(uint32_t) * n);
  uint32_t i = h->count++;
  h->parent[i] = parent;
  h->first_child[i] = BK_NULL_INDEX;
  h->child_count[i] = 0;
  h->leaf_first[i] = h->pool_count;
  h->leaf_count[i] = n;
  h->pool_count += n;
  return i;
}

typedef struct sort_key {
  double x;
  uint32_t leaf;
} sort_key;

static int compare_sort_keys(const void* pa, const void* pb) {
  const sort_key *a = pa, *b = pb;
  if (a->x != b->x) return a->x < b->x ? -1 : 1;
  return a->leaf < b->leaf ? -1 : (a->leaf > b->leaf);
}

static bk_vec3 leaf_centroid(const leaf_info* l) {
  return bk_v3(l->moments[1] / l->moments[0], l->moments[2] / l->moments[0], l->moments[3] / l->moments[0]);
}

// Children of node `at`: its leaves cut in parts (chunks at a clustered root,
// else two halves), each part then taken apart into its connected pieces.
static void split(hierarchy* h, uint32_t at, const leaf_info* leaves, const csr* adjacent, uint32_t* mark,
                  uint32_t* scratch, bool by_cluster) {
  uint32_t n = h->leaf_count[at];
  uint32_t* own = bk_alloc(sizeof(uint32_t) * n);
  memcpy(own, h->pool + h->leaf_first[at], sizeof(uint32_t) * n);
  sort_key* keys = bk_alloc(sizeof(sort_key) * n);
  uint32_t part_start[2] = {0, n / 2}, parts = 2;
  uint32_t* part_of = bk_alloc(sizeof(uint32_t) * n);
  bool clustered = false;
  if (by_cluster) {
    for (uint32_t i = 0; i < n; ++i)
      keys[i] = (sort_key){(double)leaves[own[i]].cluster, own[i]};
    bk_sort(keys, n, sizeof(sort_key), compare_sort_keys);
    clustered = keys[0].x != keys[n - 1].x;
  }
  if (clustered) {
    for (uint32_t i = 0; i < n; ++i) {
      own[i] = keys[i].leaf;
      part_of[i] = leaves[own[i]].cluster;
    }
  } else {
    bk_aabb box = {leaf_centroid(&leaves[own[0]]), leaf_centroid(&leaves[own[0]])};
    for (uint32_t i = 1; i < n; ++i) {
      box.min = bk_v3_min(box.min, leaf_centroid(&leaves[own[i]]));
      box.max = bk_v3_max(box.max, leaf_centroid(&leaves[own[i]]));
    }
    bk_vec3 size = bk_v3_sub(box.max, box.min);
    int axis = size.x >= size.y && size.x >= size.z ? 0 : (size.y >= size.z ? 1 : 2);
    for (uint32_t i = 0; i < n; ++i) {
      bk_vec3 c = leaf_centroid(&leaves[own[i]]);
      keys[i] = (sort_key){axis == 0 ? c.x : (axis == 1 ? c.y : c.z), own[i]};
    }
    bk_sort(keys, n, sizeof(sort_key), compare_sort_keys);
    for (uint32_t i = 0; i < n; ++i) {
      own[i] = keys[i].leaf;
      part_of[i] = i < part_start[1] ? 0 : 1;
    }
  }
  (void)parts;
  // Connected pieces of each part, in order of their lowest position in `own`.
  for (uint32_t i = 0; i < n; ++i)
    mark[own[i]] = part_of[i] + 1;
  uint32_t first_child = h->count, children = 0;
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t start = own[i];
    if (mark[start] == 0) continue;
    uint32_t want = mark[start], head = 0, tail = 0;
    scratch[tail++] = start;
    mark[start] = 0;
    while (head < tail) {
      uint32_t l = scratch[head++];
      for (uint32_t k = adjacent->start[l]; k < adjacent->start[l + 1]; ++k) {
        uint32_t o = adjacent->items[k];
        if (mark[o] != want) continue;
        mark[o] = 0;
        scratch[tail++] = o;
      }
    }
    add_node(h, at, scratch, tail);
    children++;
  }
  h->first_child[at] = first_child;
  h->child_count[at] = children;
  bk_free(own);
  bk_free(keys);
  bk_free(part_of);
}

static void free_hierarchy(hierarchy* h) {
  bk_free(h->parent);
  bk_free(h->first_child);
  bk_free(h->child_count);
  bk_free(h->leaf_first);
  bk_free(h->leaf_count);
  bk_free(h->pool);
}

// What every thread reads while making the nodes' meshes.
typedef struct mesh_job {
  const bk_cell_build* b;
  const bk_mesh* root;
  const hierarchy* h;
  const uint32_t* leaf_start;   // per leaf: its first entry in leaf_tris (leaves + 1)
  const uint32_t* leaf_tris;    // per leaf: its cell triangles, bar the faces inside it, in order
  const uint32_t* node_of_leaf; // per leaf: the node that is that leaf
  double texture_scale;         // local
  double uv_shift[3];           // the frame origin over the tile size, for planar uvs
  bk_tree_frame frame;
  bk_mesh_tree* tree;
  uint8_t* open; // per node: a leaf that is not closed
  bool inner;    // the pass making the inner nodes (the leaves are made)
  atomic_uint next_node;
} mesh_job;

// One thread's scratch, sized by the complex and the leaves.
typedef struct mesh_worker {
  mesh_job* job;
  uint32_t* stamp;     // per complex vertex: the node it was last placed in
  uint32_t* local;     // per complex vertex: its position in that node
  uint32_t* in_node;   // per leaf: the node being made, when it is one of its leaves
  uint32_t* kept;      // the node's triangles (entries of leaf_tris)
  uint32_t* kept_leaf; // the leaf of each
  uint32_t* order;     // the node's complex vertices, in order of first use
  uint32_t kept_capacity, order_capacity;
  uint32_t *edge_start, *edge_fill, *edge_to; // a leaf's directed edges by first position
  uint32_t edge_position_capacity, edge_capacity;
} mesh_worker;

static void surface_corner(const bk_mesh* root, uint32_t t, bk_vec3 p, bk_corner* c) {
  bk_vec3 p0 = root->positions[bk_mesh_tri_position(root, t, 0)],
          p1 = root->positions[bk_mesh_tri_position(root, t, 1)],
          p2 = root->positions[bk_mesh_tri_position(root, t, 2)];
  bk_vec3 e1 = bk_v3_sub(p1, p0), e2 = bk_v3_sub(p2, p0), n = bk_v3_cross(e1, e2);
  double nn = bk_v3_dot(n, n);
  double w1 = nn > 0.0 ? bk_v3_dot(bk_v3_cross(bk_v3_sub(p, p0), e2), n) / nn : 0.0;
  double w2 = nn > 0.0 ? bk_v3_dot(bk_v3_cross(e1, bk_v3_sub(p, p0)), n) / nn : 0.0;
  double w[3] = {1.0 - w1 - w2, w1, w2};
  const bk_corner* src[3] = {&root->corners[root->indices[3 * t]], &root->corners[root->indices[3 * t + 1]],
                             &root->corners[root->indices[3 * t + 2]]};
  memset(c, 0, sizeof *c);
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < 3; ++i)
      c->normal[i] += (float)(w[k] * src[k]->normal[i]);
    for (int i = 0; i < 2; ++i)
      c->uv[i] += (float)(w[k] * src[k]->uv[i]);
    for (int i = 0; i < 3; ++i)
      c->tangent[i] += (float)(w[k] * src[k]->tangent[i]);
  }
  c->tangent[3] = src[0]->tangent[3];
  float ln = sqrtf(c->normal[0] * c->normal[0] + c->normal[1] * c->normal[1] + c->normal[2] * c->normal[2]);
  float lt =
      sqrtf(c->tangent[0] * c->tangent[0] + c->tangent[1] * c->tangent[1] + c->tangent[2] * c->tangent[2]);
  for (int i = 0; i < 3; ++i) {
    if (ln > 0.0f) c->normal[i] /= ln;
    if (lt > 0.0f) c->tangent[i] /= lt;
  }
}

// The corners (positions unset), material and tag of cell triangle `index`.
static void triangle_corners(const mesh_job* job, uint32_t index, bk_corner corners[3], uint8_t* material,
                             uint32_t* tag) {
  const bk_cell_build* b = job->b;
  const bk_cell_tri* t = &b->parts.tris[index];
  if (!t->is_face) {
    for (int k = 0; k < 3; ++k)
      surface_corner(job->root, t->origin, b->cx.points[t->v[k]], &corners[k]);
    *material = job->root->materials[t->origin];
    *tag = 0;
    return;
  }
  const bk_cell_face* f = &b->faces.faces[t->origin];
  bk_vec3 u = bk_v3(0, 0, 0), v = bk_v3(0, 0, 0);
  bk_plane_basis(f->normal, &u, &v);
  float sign = t->reversed ? -1.0f : 1.0f;
  double su = job->uv_shift[0] * u.x + job->uv_shift[1] * u.y + job->uv_shift[2] * u.z;
  double sv = job->uv_shift[0] * v.x + job->uv_shift[1] * v.y + job->uv_shift[2] * v.z;
  su -= floor(su), sv -= floor(sv);
  for (int k = 0; k < 3; ++k) {
    bk_vec3 p = b->cx.points[t->v[k]];
    bk_corner c = {.position = 0};
    c.normal[0] = sign * (float)f->normal.x, c.normal[1] = sign * (float)f->normal.y,
    c.normal[2] = sign * (float)f->normal.z;
    c.uv[0] = (float)(bk_v3_dot(p, u) / job->texture_scale + su);
    c.uv[1] = (float)(bk_v3_dot(p, v) / job->texture_scale + sv);
    c.tangent[0] = (float)u.x, c.tangent[1] = (float)u.y, c.tangent[2] = (float)u.z;
    c.tangent[3] = sign;
    corners[k] = c;
  }
  uint32_t source =
      f->source_triangle != UINT32_MAX ? bk_material_source(job->root->materials[f->source_triangle]) : 0;
  *material = bk_material_id(source, true);
  *tag = t->origin + 1;
}

// bk_mesh_is_closed for a leaf, without hashing (a leaf has few positions):
// no edge degenerate, every directed edge used once and its reverse there.
static bool leaf_is_closed(mesh_worker* w, const bk_mesh* m) {
  uint32_t positions = m->position_count, edges = 3 * m->triangle_count;
  if (edges == 0) return false;
  if (w->edge_position_capacity < positions + 1) {
    w->edge_position_capacity = bk_grow_capacity(w->edge_position_capacity, positions + 1);
    w->edge_start = bk_realloc(w->edge_start, sizeof(uint32_t) * w->edge_position_capacity);
    w->edge_fill = bk_realloc(w->edge_fill, sizeof(uint32_t) * w->edge_position_capacity);
  }
  if (w->edge_capacity < edges) {
    w->edge_capacity = bk_grow_capacity(w->edge_capacity, edges);
    w->edge_to = bk_realloc(w->edge_to, sizeof(uint32_t) * w->edge_capacity);
  }
  uint32_t *start = w->edge_start, *fill = w->edge_fill, *to = w->edge_to;
  memset(start, 0, sizeof(uint32_t) * (positions + 1));
  for (uint32_t t = 0; t < m->triangle_count; ++t)
    for (int k = 0; k < 3; ++k) {
      uint32_t a = bk_mesh_tri_position(m, t, k), b = bk_mesh_tri_position(m, t, (k + 1) % 3);
      if (a == b) return false;
      start[a + 1]++;
    }
  for (uint32_t p = 0; p < positions; ++p)
    start[p + 1] += start[p];
  memcpy(fill, start, sizeof(uint32_t) * positions);
  for (uint32_t t = 0; t < m->triangle_count; ++t)
    for (int k = 0; k < 3; ++k)
      to[fill[bk_mesh_tri_position(m, t, k)]++] = bk_mesh_tri_position(m, t, (k + 1) % 3);
  for (uint32_t a = 0; a < positions; ++a)
    for (uint32_t i = start[a]; i < start[a + 1]; ++i) {
      uint32_t b = to[i];
      for (uint32_t j = start[a]; j < i; ++j)
        if (to[j] == b) return false; // used twice
      bool back = false;
      for (uint32_t j = start[b]; j < start[b + 1] && !back; ++j)
        back = to[j] == a;
      if (!back) return false; // open
    }
  return true;
}

// Node i's mesh: its leaves' triangles without the faces two of its leaves
// share, positions in order of first use; then its moments, whether a leaf
// is closed, and the mesh back in the source's coordinates. A leaf makes
// its corners; an inner node copies them from its leaves' meshes (they are
// the same, and making them again on every level cost most of the time).
static void make_node(mesh_worker* w, uint32_t i) {
  const mesh_job* job = w->job;
  const bk_cell_parts* parts = &job->b->parts;
  const hierarchy* h = job->h;
  bk_mesh_tree_node* node = &job->tree->nodes[i];
  const uint32_t* own = h->pool + h->leaf_first[i];
  for (uint32_t k = 0; k < h->leaf_count[i]; ++k)
    w->in_node[own[k]] = i;
  // First the triangles and positions, to size the mesh once.
  uint32_t kept = 0, positions = 0;
  for (uint32_t k = 0; k < h->leaf_count[i]; ++k)
    for (uint32_t q = job->leaf_start[own[k]]; q < job->leaf_start[own[k] + 1]; ++q) {
      uint32_t t = job->leaf_tris[q];
      if (parts->tris[t].is_face && w->in_node[parts->atom_leaf[parts->tri_atom[parts->twin[t]]]] == i)
        continue;
      if (kept == w->kept_capacity) {
        w->kept_capacity = bk_grow_capacity(w->kept_capacity, kept + 1);
        w->kept = bk_realloc(w->kept, sizeof(uint32_t) * w->kept_capacity);
        w->kept_leaf = bk_realloc(w->kept_leaf, sizeof(uint32_t) * w->kept_capacity);
      }
      w->kept[kept] = q;
      w->kept_leaf[kept++] = own[k];
      for (int c = 0; c < 3; ++c) {
        uint32_t v = parts->tris[t].v[c];
        if (w->stamp[v] == i) continue;
        w->stamp[v] = i;
        w->local[v] = positions;
        if (positions == w->order_capacity) {
          w->order_capacity = bk_grow_capacity(w->order_capacity, positions + 1);
          w->order = bk_realloc(w->order, sizeof(uint32_t) * w->order_capacity);
        }
        w->order[positions++] = v;
      }
    }
  bk_mesh* m = &node->mesh;
  bk_mesh_reserve(m, positions, 3 * kept, kept);
  for (uint32_t p = 0; p < positions; ++p)
    m->positions[p] = job->b->cx.points[w->order[p]];
  m->position_count = positions;
  for (uint32_t k = 0; k < kept; ++k) {
    uint32_t q = w->kept[k], t = job->leaf_tris[q];
    if (node->child_count == 0) {
      triangle_corners(job, t, m->corners + 3 * k, &m->materials[k], &m->tags[k]);
    } else {
      const bk_mesh* leaf = &job->tree->nodes[job->node_of_leaf[w->kept_leaf[k]]].mesh;
      uint32_t at = q - job->leaf_start[w->kept_leaf[k]]; // its triangle in the leaf's mesh
      memcpy(m->corners + 3 * k, leaf->corners + 3 * at, sizeof(bk_corner) * 3);
      m->materials[k] = leaf->materials[at];
      m->tags[k] = leaf->tags[at];
    }
    for (int c = 0; c < 3; ++c) {
      m->corners[3 * k + c].position = w->local[parts->tris[t].v[c]];
      m->indices[3 * k + c] = 3 * k + c;
    }
  }
  m->corner_count = 3 * kept;
  m->triangle_count = kept;
  node->moments = bk_mesh_moments(m);
  // Inner nodes are unions of leaves without their shared faces: closed
  // when the leaves are.
  job->open[i] = node->child_count == 0 && !leaf_is_closed(w, m);
  bk_tree_frame_to_world(job->frame, m);
  node->bounds = bk_mesh_bounds(m);
}

static void* node_work(void* arg) {
  mesh_worker* w = arg;
  mesh_job* job = w->job;
  // Nodes in breadth-first order: the largest meshes are taken first.
  for (uint32_t i = atomic_fetch_add(&job->next_node, 1u); i < job->h->count;
       i = atomic_fetch_add(&job->next_node, 1u))
    if (i > 0 && (job->h->child_count[i] > 0) == job->inner) make_node(w, i);
  return NULL;
}

bool bk_cell_tree_assemble(const bk_mesh* root, const bk_fracture_def* d, bk_tree_frame frame,
                           bk_cell_build* b, bk_mesh_tree* tree, bk_error* err) {
  const bk_cell_parts* parts = &b->parts;
  uint32_t leaf_count = parts->leaf_count;
  leaf_info* leaves = bk_calloc(leaf_count, sizeof(leaf_info));
  double* largest = bk_calloc(leaf_count, sizeof(double));
  for (uint32_t a = 0; a < parts->atom_count; ++a) {
    leaf_info* l = &leaves[parts->atom_leaf[a]];
    for (int k = 0; k < 4; ++k)
      l->moments[k] += parts->atoms[a].moments[k];
    if (parts->atoms[a].moments[0] > largest[parts->atom_leaf[a]]) {
      largest[parts->atom_leaf[a]] = parts->atoms[a].moments[0];
      l->cluster = b->cluster_of ? b->cluster_of[parts->atoms[a].cell] : 0;
    }
  }
  bk_free(largest);
  // Leaf adjacency (both directions).
  uint32_t* pair_leaf = bk_alloc(sizeof(uint32_t) * (2 * parts->contact_count + 1));
  uint32_t* pair_other = bk_alloc(sizeof(uint32_t) * (2 * parts->contact_count + 1));
  uint32_t pairs = 0;
  for (uint32_t i = 0; i < parts->contact_count; ++i) {
    uint32_t la = parts->atom_leaf[parts->contacts_a[i]], lb = parts->atom_leaf[parts->contacts_b[i]];
    if (la == lb) continue;
    pair_leaf[pairs] = la, pair_other[pairs++] = lb;
    pair_leaf[pairs] = lb, pair_other[pairs++] = la;
  }
  csr adjacent = csr_build(pair_leaf, pairs, leaf_count);
  for (uint32_t k = 0; k < pairs; ++k)
    adjacent.items[k] = pair_other[adjacent.items[k]];
  bk_free(pair_leaf);
  bk_free(pair_other);
  // The hierarchy, breadth first so siblings are contiguous.
  hierarchy h = {0};
  uint32_t* all = bk_alloc(sizeof(uint32_t) * leaf_count);
  for (uint32_t i = 0; i < leaf_count; ++i)
    all[i] = i;
  add_node(&h, BK_NULL_INDEX, all, leaf_count);
  bk_free(all);
  uint32_t* mark = bk_calloc(leaf_count, sizeof(uint32_t));
  uint32_t* scratch = bk_alloc(sizeof(uint32_t) * leaf_count);
  for (uint32_t i = 0; i < h.count; ++i)
    if (h.leaf_count[i] > 1) split(&h, i, leaves, &adjacent, mark, scratch, i == 0 && b->cluster_of);
  bk_free(mark);
  bk_free(scratch);
  csr_free(&adjacent);
  // Meshes, on every core: each node's mesh is a function of the node.
  // Each leaf's triangles in the order the nodes list them (its atoms in
  // order, each atom's triangles in order), without the faces between two
  // of its own atoms.
  csr atoms_of_leaf = csr_build(parts->atom_leaf, parts->atom_count, leaf_count);
  csr tris_of_atom = csr_build(parts->tri_atom, parts->tri_count, parts->atom_count);
  uint32_t* leaf_start = bk_alloc(sizeof(uint32_t) * (leaf_count + 1));
  uint32_t* leaf_tris = bk_alloc(sizeof(uint32_t) * (parts->tri_count ? parts->tri_count : 1));
  uint32_t listed = 0;
  for (uint32_t l = 0; l < leaf_count; ++l) {
    leaf_start[l] = listed;
    for (uint32_t a = atoms_of_leaf.start[l]; a < atoms_of_leaf.start[l + 1]; ++a) {
      uint32_t atom = atoms_of_leaf.items[a];
      for (uint32_t q = tris_of_atom.start[atom]; q < tris_of_atom.start[atom + 1]; ++q) {
        uint32_t t = tris_of_atom.items[q];
        if (!parts->tris[t].is_face || parts->atom_leaf[parts->tri_atom[parts->twin[t]]] != l)
          leaf_tris[listed++] = t;
      }
    }
  }
  leaf_start[leaf_count] = listed;
  csr_free(&atoms_of_leaf);
  csr_free(&tris_of_atom);
  tree->nodes = bk_calloc(h.count, sizeof(bk_mesh_tree_node));
  tree->node_count = h.count;
  uint32_t* node_of_leaf = bk_alloc(sizeof(uint32_t) * (leaf_count ? leaf_count : 1));
  for (uint32_t i = 0; i < h.count; ++i) {
    bk_mesh_tree_node* node = &tree->nodes[i];
    node->parent = h.parent[i];
    node->first_child = h.first_child[i];
    node->child_count = h.child_count[i];
    node->depth = i == 0 ? 0 : tree->nodes[node->parent].depth + 1;
    if (node->depth > tree->max_depth) tree->max_depth = node->depth;
    node->plane = (bk_plane){{0, 0, 1}, 0}; // no single plane splits a cell node
    if (node->child_count == 0) node_of_leaf[h.pool[h.leaf_first[i]]] = i;
  }
  mesh_job job = {.b = b,
                  .root = root,
                  .h = &h,
                  .leaf_start = leaf_start,
                  .leaf_tris = leaf_tris,
                  .node_of_leaf = node_of_leaf,
                  .texture_scale = ldexp(d->texture_scale, -frame.exponent),
                  .uv_shift = {frame.origin.x / d->texture_scale, frame.origin.y / d->texture_scale,
                               frame.origin.z / d->texture_scale},
                  .frame = frame,
                  .tree = tree,
                  .open = bk_calloc(h.count, 1)};
  uint32_t threads = bk_fracture_thread_count(d, h.count, 16);
  mesh_worker* workers = bk_calloc(threads, sizeof(mesh_worker));
  for (uint32_t t = 0; t < threads; ++t) {
    mesh_worker* w = &workers[t];
    w->job = &job;
    w->stamp = bk_alloc(sizeof(uint32_t) * (b->cx.count ? b->cx.count : 1));
    w->local = bk_alloc(sizeof(uint32_t) * (b->cx.count ? b->cx.count : 1));
    w->in_node = bk_alloc(sizeof(uint32_t) * (leaf_count ? leaf_count : 1));
    memset(w->stamp, 0xff, sizeof(uint32_t) * b->cx.count);
    memset(w->in_node, 0xff, sizeof(uint32_t) * leaf_count);
  }
  // The leaves first: the inner nodes copy their corners.
  for (int pass = 0; pass < 2; ++pass) {
    job.inner = pass == 1;
    atomic_store(&job.next_node, 0u);
    bk_fracture_run_jobs(node_work, workers, sizeof *workers, threads);
  }
  for (uint32_t t = 0; t < threads; ++t) {
    bk_free(workers[t].stamp);
    bk_free(workers[t].local);
    bk_free(workers[t].in_node);
    bk_free(workers[t].kept);
    bk_free(workers[t].kept_leaf);
    bk_free(workers[t].order);
    bk_free(workers[t].edge_start);
    bk_free(workers[t].edge_fill);
    bk_free(workers[t].edge_to);
  }
  bk_free(workers);
  bk_free(leaf_start);
  bk_free(leaf_tris);
  bk_free(node_of_leaf);
  // The root is the source itself, as in every tree (still local here; the
  // caller restores its coordinates).
  bk_mesh_copy(&tree->nodes[0].mesh, root);
  tree->nodes[0].moments = bk_mesh_moments(&tree->nodes[0].mesh);
  if (tree->nodes[0].child_count == 0) job.open[0] = !bk_mesh_is_closed(&tree->nodes[0].mesh);
  bool ok = true;
  double leaf_volume = 0.0;
  for (uint32_t i = 0; i < h.count && ok; ++i) {
    const bk_mesh_tree_node* node = &tree->nodes[i];
    if (job.open[i]) {
      bk_closure cl = bk_mesh_check_closure(&node->mesh);
      ok = bk_error_set(err, "fracture: cell piece %u is not closed (%u open, %u overused edges)", i,
                        cl.open_edges, cl.overused_edges);
    }
    if (node->child_count == 0) leaf_volume += node->moments.v;
  }
  double source_volume = tree->nodes[0].moments.v;
  if (ok && !(fabs(leaf_volume - source_volume) <= 1e-9 * source_volume))
    ok = bk_error_set(err, "fracture: the cells' volumes add up to %.17g, not the source's %.17g",
                      leaf_volume, source_volume);
  bk_free(job.open);
  free_hierarchy(&h);
  bk_free(leaves);
  if (!ok) return false;
  bk_mesh_tree_number_leaves(tree);
  bk_fracture_def desc = *d;
  bk_fracture_def_clear_borrowed(&desc);
  if (d->pattern == BK_PATTERN_CUTOUT || d->seed_points) desc.pieces = tree->leaf_count;
  tree->desc = desc;
  return true;
}
