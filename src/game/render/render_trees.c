// Uploaded mesh trees: each tree's vertices (one per corner, naming its
// node's row in the node table) and index buffer (outer triangles, then cut
// faces, then the same for the coarse copies SIMPLE draws), its node table,
// and the per-node bounds the batching culls with.
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
// fills (fresh arrays) where each mesh's indices start and how many they are.
static void add_section(uint32_t* index_data, uint32_t* k, const bk_mesh* const* meshes, const uint32_t* base,
                        uint32_t count, bool interior, uint32_t** first, uint32_t** index_count) {
  *first = bk_alloc(sizeof(uint32_t) * count);
  *index_count = bk_alloc(sizeof(uint32_t) * count);
  for (uint32_t i = 0; i < count; ++i) {
    const bk_mesh* m = meshes[i];
    (*first)[i] = *k;
    for (uint32_t tri = 0; tri < m->triangle_count; ++tri)
      if (bk_material_is_interior(m->materials[tri]) == interior)
        for (int j = 0; j < 3; ++j)
          index_data[(*k)++] = base[i] + m->indices[3 * tri + j];
    (*index_count)[i] = *k - (*first)[i];
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
  // One vertex per corner and one index per triangle corner, node after
  // node: the full meshes, then the coarse copies.
  const uint32_t nodes = tree->node_count, mesh_count = (COARSE_LEVELS + 1) * nodes;
  bk_mesh* coarse = bk_calloc((size_t)COARSE_LEVELS * nodes + 1, sizeof(bk_mesh)); // level by level
  // Every mesh drawn: the nodes', then each level's copies.
  const bk_mesh** meshes = bk_alloc(sizeof(bk_mesh*) * (mesh_count + 1));
  for (uint32_t i = 0; i < nodes; ++i) {
    const bk_mesh_tree_node* node = &tree->nodes[i];
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
  vertex* vertices = bk_alloc(sizeof(vertex) * (corners + 1));
  uint32_t* index_data = bk_alloc(sizeof(uint32_t) * (indices + 1));
  t->node_count = nodes;
  uint32_t* base = bk_alloc(sizeof(uint32_t) * (mesh_count + 1)); // per mesh: its first vertex
  uint32_t v = 0, k = 0;
  for (uint32_t i = 0; i < mesh_count; ++i) {
    base[i] = v;
    v += add_vertices(&vertices[v], meshes[i], i % nodes);
  }
  t->spheres = bk_alloc(sizeof(float[4]) * (nodes + 1));
  for (uint32_t i = 0; i < nodes; ++i) {
    const bk_mesh* m = &tree->nodes[i].mesh;
    const bk_aabb* box = &tree->nodes[i].bounds;
    bk_vec3 c = bk_v3_scale(bk_v3_add(box->min, box->max), 0.5);
    double radius = 0.0;
    for (uint32_t p = 0; p < m->position_count; ++p)
      radius = fmax(radius, bk_v3_length(bk_v3_sub(m->positions[p], c)));
    t->spheres[i][0] = (float)c.x, t->spheres[i][1] = (float)c.y, t->spheres[i][2] = (float)c.z;
    t->spheres[i][3] = (float)radius;
  }
  // Outer triangles of every node, then cut faces of every node; the same for each level's copies.
  for (int section = 0; section < SECTIONS; ++section)
    add_section(index_data, &k, meshes, base, nodes, section == INTERIOR, &t->first_index[section],
                &t->index_count[section]);
  for (uint32_t level = 0; level < COARSE_LEVELS; ++level)
    for (int section = 0; section < SECTIONS; ++section)
      add_section(index_data, &k, &meshes[(level + 1) * nodes], &base[(level + 1) * nodes], nodes,
                  section == INTERIOR, &t->coarse_first[level][section], &t->coarse_count[level][section]);
  for (uint32_t i = 0; i < COARSE_LEVELS * nodes; ++i)
    bk_mesh_free(&coarse[i]);
  free(coarse);
  free(meshes);
  free(base);
  glGenVertexArrays(1, &t->vao);
  glGenBuffers(1, &t->vbo);
  glGenBuffers(1, &t->ibo);
  glBindVertexArray(t->vao);
  glBindBuffer(GL_ARRAY_BUFFER, t->vbo);
  glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(vertex) * v), vertices, GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, t->ibo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(sizeof(uint32_t) * k), index_data, GL_STATIC_DRAW);
  render_vertex_layout();
  glEnableVertexAttribArray(NODE_ATTRIBUTE);
  glVertexAttribIPointer(NODE_ATTRIBUTE, 1, GL_UNSIGNED_INT, sizeof(vertex), (void*)offsetof(vertex, node));
  glBindVertexArray(0);
  free(vertices);
  free(index_data);
  render_make_table(&t->table_buffer, &t->table_texture, t->node_count);
  t->table = bk_calloc((size_t)t->node_count + 1, sizeof(float) * TABLE_FLOATS);
  t->node_frame = bk_calloc((size_t)t->node_count + 1, sizeof(uint32_t));
  t->node_batch = bk_calloc((size_t)t->node_count + 1, sizeof(uint32_t));
  t->node_level = bk_calloc((size_t)t->node_count + 1, 1);
  t->node_distance = bk_calloc((size_t)t->node_count + 1, sizeof(float));
  return (app_render_tree){slot, t->generation};
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
