// Uploaded mesh trees: each tree's vertices (one per corner, naming its
// node's row in the node table) and index buffer (outer triangles, then cut
// faces, then the same for the coarse copies SIMPLE draws), its node table,
// and the per-node bounds the batching culls with. A tree that grows at run
// time (a fragment refined where it was hit) has its new nodes appended the
// same way after the ones it had: nothing uploaded is built again.
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render_internal.h"

void render_vertex_layout(void) {
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(vertex), (void*)offsetof(vertex, position));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(vertex), (void*)offsetof(vertex, normal));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, sizeof(vertex), (void*)offsetof(vertex, uv));
  glEnableVertexAttribArray(3);
  glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, sizeof(vertex), (void*)offsetof(vertex, tangent));
  // The node attribute stays off here: the ground and the spheres read its
  // constant value (glVertexAttribI4ui), which names their row of the loose table.
}

// A node table: a float buffer read in the vertex shaders through a texture.
void render_make_table(GLuint* buffer, GLuint* texture, uint32_t rows) {
  glGenBuffers(1, buffer);
  glBindBuffer(GL_TEXTURE_BUFFER, *buffer);
  glBufferData(GL_TEXTURE_BUFFER, (GLsizeiptr)(sizeof(float) * TABLE_FLOATS * (rows ? rows : 1)), NULL,
               GL_DYNAMIC_DRAW);
  glGenTextures(1, texture);
  glBindTexture(GL_TEXTURE_BUFFER, *texture);
  glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, *buffer);
  glBindTexture(GL_TEXTURE_BUFFER, 0);
  glBindBuffer(GL_TEXTURE_BUFFER, 0);
}

tree_buffers* render_find_tree(app_renderer* r, app_render_tree id) {
  if (id.generation == 0 || id.index >= r->tree_count) return NULL;
  tree_buffers* t = &r->trees[id.index];
  return t->used && t->generation == id.generation ? t : NULL;
}

// Copies of the nodes for SIMPLE, which draws nodes under
// simple_below_pixels wide: decimated (bk_mesh_decimate) while no point
// moves by more than 8% of the node's radius, under a pixel at that size;
// under tiny_below_pixels, that copy decimated again at 20% (a pixel at
// most). Vertex and triangle set-up is what a software renderer spends on a
// shard a few pixels wide: at the first level, shards of curved shapes keep
// 55-65% of their triangles and 55-65% of their vertices, flat ones ~85%.
static const double coarse_tolerance[COARSE_LEVELS] = {0.08, 0.2};

// One vertex per corner of `m`, all in `node`'s row of the table.
static uint32_t add_vertices(vertex* out, const bk_mesh* m, uint32_t node) {
  for (uint32_t c = 0; c < m->corner_count; ++c) {
    const bk_corner* corner = &m->corners[c];
    bk_vec3 p = m->positions[corner->position];
    out[c] = (vertex){{(float)p.x, (float)p.y, (float)p.z},
                      {corner->normal[0], corner->normal[1], corner->normal[2]},
                      {corner->uv[0], corner->uv[1]},
                      {corner->tangent[0], corner->tangent[1], corner->tangent[2], corner->tangent[3]},
                      node};
  }
  return m->corner_count;
}

// One section (outer surface or cut faces) of `count` meshes, mesh after
// mesh, appended at index_data[*k], each offset by its first vertex `base`;
// writes where each mesh's indices start in index_data and how many they are.
static void add_section(uint32_t* index_data, uint32_t* k, const bk_mesh* const* meshes, const uint32_t* base,
                        uint32_t count, bool interior, uint32_t* first, uint32_t* index_count) {
  for (uint32_t i = 0; i < count; ++i) {
    const bk_mesh* m = meshes[i];
    first[i] = *k;
    for (uint32_t tri = 0; tri < m->triangle_count; ++tri)
      if (bk_material_is_interior(m->materials[tri]) == interior)
        for (int j = 0; j < 3; ++j)
          index_data[(*k)++] = base[i] + m->indices[3 * tri + j];
    index_count[i] = *k - first[i];
  }
}

// Nodes [first, first + count) of a tree made ready for the GPU, numbered
// as if they were all there is: their vertices from 0 and their indices from
// 0 (renderer_append_nodes moves them after what the tree holds).
struct render_nodes {
  uint32_t first, count;
  vertex* vertices;
  uint32_t vertex_count;
  uint32_t* indices;
  uint32_t index_count;
  // Per level (the detailed meshes, then each coarse copy) and section, per
  // node: where its indices start and how many.
  uint32_t* range_first[1 + COARSE_LEVELS][SECTIONS];
  uint32_t* range_count[1 + COARSE_LEVELS][SECTIONS];
  float (*spheres)[4]; // per node: bounding sphere in tree space
};

render_nodes* renderer_build_nodes(const bk_mesh_tree* tree, uint32_t first, uint32_t end) {
  if (!tree || end > tree->node_count || first > end) return NULL;
  const uint32_t nodes = end - first, mesh_count = (COARSE_LEVELS + 1) * nodes;
  render_nodes* out = bk_calloc(1, sizeof *out);
  out->first = first;
  out->count = nodes;
  bk_mesh* coarse = bk_calloc((size_t)COARSE_LEVELS * nodes + 1, sizeof(bk_mesh)); // level by level
  // Every mesh drawn: the nodes', then each level's copies.
  const bk_mesh** meshes = bk_alloc(sizeof(bk_mesh*) * (mesh_count + 1));
  for (uint32_t i = 0; i < nodes; ++i) {
    const bk_mesh_tree_node* node = &tree->nodes[first + i];
    double radius = 0.5 * bk_v3_length(bk_v3_sub(node->bounds.max, node->bounds.min));
    meshes[i] = &node->mesh;
    for (uint32_t level = 0; level < COARSE_LEVELS; ++level) {
      bk_mesh* m = &coarse[level * nodes + i];
      bk_mesh_decimate(meshes[level * nodes + i], coarse_tolerance[level] * radius, m);
      meshes[(level + 1) * nodes + i] = m;
    }
  }
  uint64_t corners = 0, indices = 0;
  for (uint32_t i = 0; i < mesh_count; ++i) {
    corners += meshes[i]->corner_count;
    indices += 3ull * meshes[i]->triangle_count;
  }
  out->vertices = bk_alloc(sizeof(vertex) * (corners + 1));
  out->indices = bk_alloc(sizeof(uint32_t) * (indices + 1));
  uint32_t* base = bk_alloc(sizeof(uint32_t) * (mesh_count + 1)); // per mesh: its first vertex
  uint32_t v = 0, k = 0;
  for (uint32_t i = 0; i < mesh_count; ++i) {
    base[i] = v;
    v += add_vertices(&out->vertices[v], meshes[i], first + i % nodes);
  }
  out->spheres = bk_alloc(sizeof(float[4]) * (nodes + 1));
  for (uint32_t i = 0; i < nodes; ++i) {
    const bk_mesh* m = &tree->nodes[first + i].mesh;
    const bk_aabb* box = &tree->nodes[first + i].bounds;
    bk_vec3 c = bk_v3_scale(bk_v3_add(box->min, box->max), 0.5);
    double radius = 0.0;
    for (uint32_t p = 0; p < m->position_count; ++p)
      radius = fmax(radius, bk_v3_length(bk_v3_sub(m->positions[p], c)));
    out->spheres[i][0] = (float)c.x, out->spheres[i][1] = (float)c.y, out->spheres[i][2] = (float)c.z;
    out->spheres[i][3] = (float)radius;
  }
  // Outer triangles of every node, then cut faces of every node; the same for each level's copies.
  for (uint32_t level = 0; level <= COARSE_LEVELS; ++level)
    for (int section = 0; section < SECTIONS; ++section) {
      out->range_first[level][section] = bk_alloc(sizeof(uint32_t) * (nodes + 1));
      out->range_count[level][section] = bk_alloc(sizeof(uint32_t) * (nodes + 1));
      add_section(out->indices, &k, &meshes[level * nodes], &base[level * nodes], nodes, section == INTERIOR,
                  out->range_first[level][section], out->range_count[level][section]);
    }
  for (uint32_t i = 0; i < COARSE_LEVELS * nodes; ++i)
    bk_mesh_free(&coarse[i]);
  free(coarse);
  free(meshes);
  free(base);
  out->vertex_count = v;
  out->index_count = k;
  return out;
}

void renderer_free_nodes(render_nodes* nodes) {
  if (!nodes) return;
  for (int level = 0; level <= COARSE_LEVELS; ++level)
    for (int section = 0; section < SECTIONS; ++section) {
      free(nodes->range_first[level][section]);
      free(nodes->range_count[level][section]);
    }
  free(nodes->vertices);
  free(nodes->indices);
  free(nodes->spheres);
  free(nodes);
}

// An array of `row`-byte rows grown from `old` to `count` rows (and one
// spare, so that an empty tree allocates), the new rows zeroed.
static void* grow_rows(void* rows, size_t row, uint32_t old, uint32_t count) {
  rows = bk_realloc(rows, row * ((size_t)count + 1));
  memset((char*)rows + row * old, 0, row * ((size_t)count + 1 - old));
  return rows;
}

// The per-node arrays of a tree, from t->node_count rows to `count`.
static void grow_node_arrays(tree_buffers* t, uint32_t count) {
  uint32_t old = t->node_count;
  for (int section = 0; section < SECTIONS; ++section) {
    t->first_index[section] = grow_rows(t->first_index[section], sizeof(uint32_t), old, count);
    t->index_count[section] = grow_rows(t->index_count[section], sizeof(uint32_t), old, count);
    for (int level = 0; level < COARSE_LEVELS; ++level) {
      t->coarse_first[level][section] =
          grow_rows(t->coarse_first[level][section], sizeof(uint32_t), old, count);
      t->coarse_count[level][section] =
          grow_rows(t->coarse_count[level][section], sizeof(uint32_t), old, count);
    }
  }
  t->spheres = grow_rows(t->spheres, sizeof(float[4]), old, count);
  t->table = grow_rows(t->table, sizeof(float) * TABLE_FLOATS, old, count);
  t->node_frame = grow_rows(t->node_frame, sizeof(uint32_t), old, count);
  t->node_batch = grow_rows(t->node_batch, sizeof(uint32_t), old, count);
  t->node_level = grow_rows(t->node_level, 1, old, count);
  t->node_distance = grow_rows(t->node_distance, sizeof(float), old, count);
}

// A buffer of `bytes` holding the first `used` bytes of `old` (copied on
// the GPU, so nothing of a tree's meshes needs to stay in memory); `old` is
// deleted.
static GLuint regrown_buffer(GLuint old, size_t used, size_t bytes) {
  GLuint buffer = 0;
  glGenBuffers(1, &buffer);
  glBindBuffer(GL_COPY_WRITE_BUFFER, buffer);
  glBufferData(GL_COPY_WRITE_BUFFER, (GLsizeiptr)bytes, NULL, GL_STATIC_DRAW);
  if (old && used) {
    glBindBuffer(GL_COPY_READ_BUFFER, old);
    glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0, (GLsizeiptr)used);
    glBindBuffer(GL_COPY_READ_BUFFER, 0);
  }
  glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
  if (old) glDeleteBuffers(1, &old);
  return buffer;
}

// Room for `vertices` more vertices and `indices` more indices. The first
// upload makes buffers of the tree's size; a tree that outgrows them gets
// new ones twice as large (a wall shot again and again grows many times),
// and its VAO is pointed at them.
static void reserve(tree_buffers* t, uint32_t vertices, uint32_t indices) {
  bool first = t->vbo == 0;
  uint32_t need_vertices = t->vertex_count + vertices, need_indices = t->index_total + indices;
  if (first || need_vertices > t->vertex_capacity) {
    uint32_t capacity = first ? need_vertices : bk_grow_capacity(t->vertex_capacity, need_vertices);
    t->vbo =
        regrown_buffer(t->vbo, sizeof(vertex) * t->vertex_count, sizeof(vertex) * ((size_t)capacity + 1));
    t->vertex_capacity = capacity;
  }
  if (first || need_indices > t->index_capacity) {
    uint32_t capacity = first ? need_indices : bk_grow_capacity(t->index_capacity, need_indices);
    t->ibo =
        regrown_buffer(t->ibo, sizeof(uint32_t) * t->index_total, sizeof(uint32_t) * ((size_t)capacity + 1));
    t->index_capacity = capacity;
  }
  glBindVertexArray(t->vao);
  glBindBuffer(GL_ARRAY_BUFFER, t->vbo);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, t->ibo);
  render_vertex_layout();
  glEnableVertexAttribArray(NODE_ATTRIBUTE);
  glVertexAttribIPointer(NODE_ATTRIBUTE, 1, GL_UNSIGNED_INT, sizeof(vertex), (void*)offsetof(vertex, node));
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

// Appends built nodes after what the tree's buffers hold: their vertices,
// their indices moved past the tree's vertices, their ranges past its
// indices, their bounding spheres and node table rows.
static void append_nodes(tree_buffers* t, render_nodes* n) {
  const uint32_t end = n->first + n->count;
  grow_node_arrays(t, end);
  for (uint32_t k = 0; k < n->index_count; ++k)
    n->indices[k] += t->vertex_count;
  for (uint32_t i = 0; i < n->count; ++i) {
    const uint32_t node = n->first + i;
    memcpy(t->spheres[node], n->spheres[i], sizeof(float[4]));
    for (int section = 0; section < SECTIONS; ++section) {
      t->first_index[section][node] = t->index_total + n->range_first[0][section][i];
      t->index_count[section][node] = n->range_count[0][section][i];
      for (int level = 0; level < COARSE_LEVELS; ++level) {
        t->coarse_first[level][section][node] = t->index_total + n->range_first[level + 1][section][i];
        t->coarse_count[level][section][node] = n->range_count[level + 1][section][i];
      }
    }
  }
  reserve(t, n->vertex_count, n->index_count);
  glBindBuffer(GL_COPY_WRITE_BUFFER, t->vbo);
  glBufferSubData(GL_COPY_WRITE_BUFFER, (GLintptr)(sizeof(vertex) * t->vertex_count),
                  (GLsizeiptr)(sizeof(vertex) * n->vertex_count), n->vertices);
  glBindBuffer(GL_COPY_WRITE_BUFFER, t->ibo);
  glBufferSubData(GL_COPY_WRITE_BUFFER, (GLintptr)(sizeof(uint32_t) * t->index_total),
                  (GLsizeiptr)(sizeof(uint32_t) * n->index_count), n->indices);
  glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
  t->vertex_count += n->vertex_count;
  t->index_total += n->index_count;
  t->node_count = end;
  // The node table on the GPU: rows for every node (what is in them is
  // written each frame for the nodes drawn).
  if (t->table_buffer == 0) {
    render_make_table(&t->table_buffer, &t->table_texture, end);
  } else {
    glBindBuffer(GL_TEXTURE_BUFFER, t->table_buffer);
    glBufferData(GL_TEXTURE_BUFFER, (GLsizeiptr)(sizeof(float) * TABLE_FLOATS * ((size_t)end + 1)), NULL,
                 GL_DYNAMIC_DRAW);
    glBindBuffer(GL_TEXTURE_BUFFER, 0);
  }
}

app_render_tree renderer_upload_tree(app_renderer* r, const bk_mesh_tree* tree) {
  uint32_t slot = 0;
  while (slot < r->tree_count && r->trees[slot].used)
    slot++;
  if (slot == r->tree_count) {
    if (r->tree_count == r->tree_capacity) {
      r->tree_capacity = bk_grow_capacity(r->tree_capacity, r->tree_count + 1);
      r->trees = bk_realloc(r->trees, sizeof(tree_buffers) * r->tree_capacity);
    }
    memset(&r->trees[r->tree_count], 0, sizeof(tree_buffers));
    r->tree_count++;
  }
  tree_buffers* t = &r->trees[slot];
  t->used = true;
  t->generation++;
  glGenVertexArrays(1, &t->vao);
  render_nodes* nodes = renderer_build_nodes(tree, 0, tree->node_count);
  append_nodes(t, nodes);
  renderer_free_nodes(nodes);
  return (app_render_tree){slot, t->generation};
}

uint32_t renderer_append_nodes(app_renderer* r, app_render_tree id, render_nodes* nodes) {
  tree_buffers* t = render_find_tree(r, id);
  uint32_t added = 0;
  if (t && nodes && nodes->first == t->node_count && nodes->count > 0) {
    append_nodes(t, nodes);
    added = nodes->count;
  }
  renderer_free_nodes(nodes);
  return added;
}

uint32_t renderer_grow_tree(app_renderer* r, app_render_tree id, const bk_mesh_tree* tree) {
  tree_buffers* t = render_find_tree(r, id);
  if (!t || !tree || tree->node_count <= t->node_count) return 0;
  return renderer_append_nodes(r, id, renderer_build_nodes(tree, t->node_count, tree->node_count));
}

uint32_t renderer_tree_node_count(const app_renderer* r, app_render_tree id) {
  if (id.generation == 0 || id.index >= r->tree_count) return 0;
  const tree_buffers* t = &r->trees[id.index];
  return t->used && t->generation == id.generation ? t->node_count : 0;
}

void renderer_release_tree(app_renderer* r, app_render_tree id) {
  tree_buffers* t = render_find_tree(r, id);
  if (!t) return;
  glDeleteVertexArrays(1, &t->vao);
  glDeleteTextures(1, &t->table_texture);
  GLuint buffers[3] = {t->vbo, t->ibo, t->table_buffer};
  glDeleteBuffers(3, buffers);
  for (int section = 0; section < SECTIONS; ++section) {
    free(t->first_index[section]);
    free(t->index_count[section]);
    for (int level = 0; level < COARSE_LEVELS; ++level) {
      free(t->coarse_first[level][section]);
      free(t->coarse_count[level][section]);
    }
  }
  free(t->spheres);
  free(t->table);
  free(t->node_frame);
  free(t->node_batch);
  free(t->node_level);
  free(t->node_distance);
  uint32_t generation = t->generation;
  memset(t, 0, sizeof *t);
  t->generation = generation; // the next upload here gets a new id
}
