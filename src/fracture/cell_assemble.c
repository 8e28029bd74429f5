// The cell patterns' tree nodes: a balanced hierarchy over the leaves (each
// node's children are the connected parts of its two halves along its
// longest extent; the clustered pattern's root splits into its chunks
// first), each node's mesh made of its leaves' triangles minus the faces its
// leaves share. Corners: surface pieces interpolate the source triangle's
// attributes; cut faces get the face's normal, planar uvs in texture tiles
// (the same on both sides, so the halves of a crack match) and a tangent
// along u.
#include <stdlib.h>
#include <string.h>

#include "cell_tree.h"

typedef struct csr {
  uint32_t *start, *items;
} csr;

static void csr_free(csr* c) {
  free(c->start);
  free(c->items);
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
  free(fill);
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
    qsort(keys, n, sizeof(sort_key), compare_sort_keys);
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
    qsort(keys, n, sizeof(sort_key), compare_sort_keys);
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
  free(own);
  free(keys);
  free(part_of);
}

static void free_hierarchy(hierarchy* h) {
  free(h->parent);
  free(h->first_child);
  free(h->child_count);
  free(h->leaf_first);
  free(h->leaf_count);
  free(h->pool);
}

typedef struct mesh_maker {
  const bk_cell_build* b;
  const bk_mesh* root;
  double texture_scale; // local
  double uv_shift[3];   // the frame origin over the tile size, for planar uvs
  uint32_t* stamp;
  uint32_t* local;
} mesh_maker;

static uint32_t position_of(mesh_maker* mm, bk_mesh* out, uint32_t v, uint32_t node) {
  if (mm->stamp[v] != node) {
    mm->stamp[v] = node;
    mm->local[v] = bk_mesh_add_position(out, mm->b->cx.points[v]);
  }
  return mm->local[v];
}

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

static void add_triangle(mesh_maker* mm, bk_mesh* out, const bk_cell_tri* t, uint32_t node) {
  const bk_cell_build* b = mm->b;
  uint32_t corners[3];
  uint8_t material = 0;
  uint32_t tag = 0;
  if (!t->is_face) {
    for (int k = 0; k < 3; ++k) {
      bk_corner c;
      surface_corner(mm->root, t->origin, b->cx.points[t->v[k]], &c);
      c.position = position_of(mm, out, t->v[k], node);
      corners[k] = bk_mesh_add_corner(out, &c);
    }
    material = mm->root->materials[t->origin];
  } else {
    const bk_cell_face* f = &b->faces.faces[t->origin];
    bk_vec3 u, v;
    bk_plane_basis(f->normal, &u, &v);
    float sign = t->reversed ? -1.0f : 1.0f;
    double su = mm->uv_shift[0] * u.x + mm->uv_shift[1] * u.y + mm->uv_shift[2] * u.z;
    double sv = mm->uv_shift[0] * v.x + mm->uv_shift[1] * v.y + mm->uv_shift[2] * v.z;
    su -= floor(su), sv -= floor(sv);
    for (int k = 0; k < 3; ++k) {
      bk_vec3 p = b->cx.points[t->v[k]];
      bk_corner c = {.position = position_of(mm, out, t->v[k], node)};
      c.normal[0] = sign * (float)f->normal.x, c.normal[1] = sign * (float)f->normal.y,
      c.normal[2] = sign * (float)f->normal.z;
      c.uv[0] = (float)(bk_v3_dot(p, u) / mm->texture_scale + su);
      c.uv[1] = (float)(bk_v3_dot(p, v) / mm->texture_scale + sv);
      c.tangent[0] = (float)u.x, c.tangent[1] = (float)u.y, c.tangent[2] = (float)u.z;
      c.tangent[3] = sign;
      corners[k] = bk_mesh_add_corner(out, &c);
    }
    uint32_t source =
        f->source_triangle != UINT32_MAX ? bk_material_source(mm->root->materials[f->source_triangle]) : 0;
    material = bk_material_id(source, true);
    tag = t->origin + 1;
  }
  bk_mesh_add_triangle(out, corners[0], corners[1], corners[2], material, tag);
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
  free(largest);
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
  free(pair_leaf);
  free(pair_other);
  // The hierarchy, breadth first so siblings are contiguous.
  hierarchy h = {0};
  uint32_t* all = bk_alloc(sizeof(uint32_t) * leaf_count);
  for (uint32_t i = 0; i < leaf_count; ++i)
    all[i] = i;
  add_node(&h, BK_NULL_INDEX, all, leaf_count);
  free(all);
  uint32_t* mark = bk_calloc(leaf_count, sizeof(uint32_t));
  uint32_t* scratch = bk_alloc(sizeof(uint32_t) * leaf_count);
  for (uint32_t i = 0; i < h.count; ++i)
    if (h.leaf_count[i] > 1) split(&h, i, leaves, &adjacent, mark, scratch, i == 0 && b->cluster_of);
  free(mark);
  free(scratch);
  csr_free(&adjacent);
  // Meshes.
  csr atoms_of_leaf = csr_build(parts->atom_leaf, parts->atom_count, leaf_count);
  csr tris_of_atom = csr_build(parts->tri_atom, parts->tri_count, parts->atom_count);
  mesh_maker mm = {.b = b, .root = root, .texture_scale = ldexp(d->texture_scale, -frame.exponent)};
  mm.uv_shift[0] = frame.origin.x / d->texture_scale;
  mm.uv_shift[1] = frame.origin.y / d->texture_scale;
  mm.uv_shift[2] = frame.origin.z / d->texture_scale;
  mm.stamp = bk_alloc(sizeof(uint32_t) * (b->cx.count ? b->cx.count : 1));
  mm.local = bk_alloc(sizeof(uint32_t) * (b->cx.count ? b->cx.count : 1));
  memset(mm.stamp, 0xff, sizeof(uint32_t) * b->cx.count);
  uint32_t* in_node = bk_alloc(sizeof(uint32_t) * (leaf_count ? leaf_count : 1));
  memset(in_node, 0xff, sizeof(uint32_t) * leaf_count);
  tree->nodes = bk_calloc(h.count, sizeof(bk_mesh_tree_node));
  tree->node_count = h.count;
  bool ok = true;
  double leaf_volume = 0.0;
  for (uint32_t i = 0; i < h.count && ok; ++i) {
    bk_mesh_tree_node* node = &tree->nodes[i];
    node->parent = h.parent[i];
    node->first_child = h.first_child[i];
    node->child_count = h.child_count[i];
    node->depth = i == 0 ? 0 : tree->nodes[node->parent].depth + 1;
    if (node->depth > tree->max_depth) tree->max_depth = node->depth;
    node->plane = (bk_plane){{0, 0, 1}, 0}; // no single plane splits a cell node
    if (i == 0) {
      bk_mesh_copy(&node->mesh, root); // the source itself, as in every tree
    } else {
      const uint32_t* own = h.pool + h.leaf_first[i];
      for (uint32_t k = 0; k < h.leaf_count[i]; ++k)
        in_node[own[k]] = i;
      for (uint32_t k = 0; k < h.leaf_count[i]; ++k)
        for (uint32_t a = atoms_of_leaf.start[own[k]]; a < atoms_of_leaf.start[own[k] + 1]; ++a) {
          uint32_t atom = atoms_of_leaf.items[a];
          for (uint32_t q = tris_of_atom.start[atom]; q < tris_of_atom.start[atom + 1]; ++q) {
            uint32_t t = tris_of_atom.items[q];
            if (parts->tris[t].is_face && in_node[parts->atom_leaf[parts->tri_atom[parts->twin[t]]]] == i)
              continue;
            add_triangle(&mm, &node->mesh, &parts->tris[t], i);
          }
        }
    }
    node->moments = bk_mesh_moments(&node->mesh);
    // Inner nodes are unions of leaves without their shared faces: closed
    // when the leaves are.
    if (node->child_count == 0 && !bk_mesh_is_closed(&node->mesh)) {
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
  free(in_node);
  free(mm.stamp);
  free(mm.local);
  csr_free(&atoms_of_leaf);
  csr_free(&tris_of_atom);
  free_hierarchy(&h);
  free(leaves);
  if (!ok) return false;
  // Back to the source's coordinates (the root is restored by the caller's copy).
  for (uint32_t i = 1; i < tree->node_count; ++i)
    bk_tree_frame_to_world(frame, &tree->nodes[i].mesh);
  bk_mesh_tree_number_leaves(tree);
  bk_fracture_def desc = *d;
  bk_fracture_def_clear_borrowed(&desc);
  if (d->pattern == BK_PATTERN_CUTOUT || d->seed_points) desc.pieces = tree->leaf_count;
  tree->desc = desc;
  return true;
}
