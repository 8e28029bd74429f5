// The frame's draw list (nodes, spheres, lines) and how it becomes draw
// calls: culling against the view and the shadow map, the choice between
// detailed and SIMPLE per node, batches of items that share a tree, material
// and interior scale, node table rows, and the index ranges each pass draws.
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render_internal.h"

// A sphere's level of detail when its width on screen is at least this many pixels.
static const float sphere_level_pixels[SPHERE_LEVELS] = {48.0f, 16.0f, 0.0f};

// Nodes whose bounding sphere spans fewer pixels than this are drawn with
// SIMPLE: a shard a few pixels wide shows no texture or normal map, and a
// heap of debris is thousands of them.
static const float simple_below_pixels = 24.0f;
// Under this many pixels SIMPLE draws a second, coarser copy (see coarse_tolerance).
static const float tiny_below_pixels = 10.0f;
// A node's batch when it is out of view but casts a shadow into the map.
#define SHADOW_ONLY UINT32_MAX

// The node table stores the top three rows of the matrix (the last is 0 0 0 1).
static void model_rows(bk_transform t, float rows[12]) {
  versor q = {(float)t.rotation.x, (float)t.rotation.y, (float)t.rotation.z, (float)t.rotation.w};
  mat4 m = GLM_MAT4_IDENTITY_INIT;
  glm_quat_mat4(q, m);
  m[3][0] = (float)t.position.x;
  m[3][1] = (float)t.position.y;
  m[3][2] = (float)t.position.z;
  for (int row = 0; row < 3; ++row)
    for (int column = 0; column < 4; ++column)
      rows[4 * row + column] = m[column][row];
}

void renderer_draw_nodes(app_renderer* r, const node_draw* d) {
  // Written so that NaN reads as 0: drawn as usual.
  float fade = d->fade > 0.0 ? (float)fmin(d->fade, 1.0) : 0.0f;
  if (!render_find_tree(r, d->tree) || d->node_count == 0 || fade >= 1.0f) return;
  if (r->item_count == r->item_capacity) {
    r->item_capacity = bk_grow_capacity(r->item_capacity, r->item_count + 1);
    r->items = bk_realloc(r->items, sizeof(draw_item) * r->item_capacity);
  }
  if (r->node_count + d->node_count > r->node_capacity) {
    r->node_capacity = bk_grow_capacity(r->node_capacity, r->node_count + d->node_count);
    r->nodes = bk_realloc(r->nodes, sizeof(uint32_t) * r->node_capacity);
    r->node_colors = bk_realloc(r->node_colors, sizeof(float) * 4u * r->node_capacity);
    r->multi_counts = bk_realloc(r->multi_counts, sizeof(GLsizei) * 2u * SECTIONS * r->node_capacity);
    r->multi_offsets = bk_realloc(r->multi_offsets, sizeof(void*) * 2u * SECTIONS * r->node_capacity);
  }
  draw_item* item = &r->items[r->item_count++];
  item->tree = d->tree;
  item->first_node = r->node_count;
  item->node_count = d->node_count;
  model_rows(d->model, item->rows);
  item->material = d->material >= 0 && d->material < r->material_count ? d->material : 0;
  item->interior_scale = d->interior_scale > 0.0 ? (float)d->interior_scale : 1.0f;
  item->fade = fade;
  item->colored = d->node_colors != NULL;
  memcpy(&r->nodes[r->node_count], d->nodes, sizeof(uint32_t) * d->node_count);
  if (d->node_colors)
    memcpy(&r->node_colors[4 * r->node_count], d->node_colors, sizeof(float) * 4 * d->node_count);
  r->node_count += d->node_count;
}

void renderer_draw_sphere(app_renderer* r, bk_vec3 center, double radius, const float rgb[3]) {
  if (r->sphere_count == r->sphere_capacity) {
    r->sphere_capacity = bk_grow_capacity(r->sphere_capacity, r->sphere_count + 1);
    r->spheres = bk_realloc(r->spheres, sizeof(float[7]) * r->sphere_capacity);
    r->sphere_levels = bk_realloc(r->sphere_levels, sizeof(int8_t[2]) * r->sphere_capacity);
  }
  float* s = r->spheres[r->sphere_count++];
  s[0] = (float)center.x, s[1] = (float)center.y, s[2] = (float)center.z, s[3] = (float)radius;
  s[4] = rgb[0], s[5] = rgb[1], s[6] = rgb[2];
}

void renderer_draw_line(app_renderer* r, bk_vec3 a, bk_vec3 b, const float rgba[4]) {
  if (r->line_count + 2 > r->line_vertex_capacity) {
    r->line_vertex_capacity = bk_grow_capacity(r->line_vertex_capacity, r->line_count + 2);
    r->lines = bk_realloc(r->lines, sizeof(line_vertex) * r->line_vertex_capacity);
  }
  r->lines[r->line_count++] =
      (line_vertex){{(float)a.x, (float)a.y, (float)a.z}, {rgba[0], rgba[1], rgba[2], rgba[3]}};
  r->lines[r->line_count++] =
      (line_vertex){{(float)b.x, (float)b.y, (float)b.z}, {rgba[0], rgba[1], rgba[2], rgba[3]}};
}

static uint32_t find_batch(app_renderer* r, const draw_item* item, bool simple) {
  // Few batches (about two per breakable), and a body's neighbours in the
  // list mostly share its batch: search from the newest.
  for (uint32_t b = r->batch_count; b-- > 0;) {
    const draw_batch* batch = &r->batches[b];
    if (batch->tree == item->tree.index && batch->material == item->material &&
        batch->interior_scale == item->interior_scale && batch->simple == simple)
      return b;
  }
  if (r->batch_count == r->batch_capacity) {
    r->batch_capacity = bk_grow_capacity(r->batch_capacity, r->batch_count + 1);
    r->batches = bk_realloc(r->batches, sizeof(draw_batch) * r->batch_capacity);
  }
  r->batches[r->batch_count] =
      (draw_batch){.tree = item->tree.index,
                   .material = item->material,
                   .interior_scale = item->interior_scale,
                   .simple = simple,
                   .transparent = material_transparent(&r->materials[item->material])};
  return r->batch_count++;
}

// A node's row: its matrix, overlay colour, its fade (what the lit passes
// leave out) and the share of its shadow's texels the shadow pass leaves out:
// those of the fade and those its material lets light through (`shadow` is
// the share of light it stops).
static void write_row(float* row, const float model[12], const float color[4], float fade, float shadow) {
  memcpy(row, model, sizeof(float) * 12);
  memcpy(row + 12, color, sizeof(float) * 4);
  row[16] = fade;
  row[17] = 1.0f - (1.0f - fade) * shadow;
  row[18] = row[19] = 0.0f;
}

static float* loose_row(app_renderer* r) {
  if (r->loose_count == r->loose_capacity) {
    r->loose_capacity = bk_grow_capacity(r->loose_capacity, r->loose_count + 1);
    r->loose = bk_realloc(r->loose, sizeof(float) * TABLE_FLOATS * r->loose_capacity);
  }
  return &r->loose[TABLE_FLOATS * r->loose_count++];
}

// Appends an index range, merged into the previous one when the two are
// adjacent in the index buffer (neighbouring nodes drawn together).
static void append_range(app_renderer* r, uint32_t first, uint32_t* count, uint32_t indices, uint32_t start) {
  GLsizei* counts = &r->multi_counts[first];
  const void** offsets = &r->multi_offsets[first];
  uintptr_t offset = sizeof(uint32_t) * (uintptr_t)start;
  if (*count > 0 &&
      (uintptr_t)offsets[*count - 1] + sizeof(uint32_t) * (uintptr_t)counts[*count - 1] == offset) {
    counts[*count - 1] += (GLsizei)indices;
    return;
  }
  counts[*count] = (GLsizei)indices;
  offsets[*count] = (const void*)offset;
  (*count)++;
}

// Whether a sphere reaches into a volume given by six planes facing in.
static bool sphere_inside(vec4 planes[6], const float centre[3], float radius) {
  for (int i = 0; i < 6; ++i)
    if (planes[i][0] * centre[0] + planes[i][1] * centre[1] + planes[i][2] * centre[2] + planes[i][3] <
        -radius)
      return false;
  return true;
}

static void add_glass_node(app_renderer* r, const tree_buffers* t, uint32_t node) {
  if (r->glass_node_count == r->glass_node_capacity) {
    r->glass_node_capacity = bk_grow_capacity(r->glass_node_capacity, r->glass_node_count + 1);
    r->glass_nodes = bk_realloc(r->glass_nodes, sizeof *r->glass_nodes * r->glass_node_capacity);
  }
  r->glass_nodes[r->glass_node_count++] = (struct glass_node){.batch = t->node_batch[node],
                                                              .node = node,
                                                              .level = t->node_level[node],
                                                              .distance = t->node_distance[node]};
}

// Farthest first; ties in a fixed order, so that a frame draws the same way every time.
static int farther_node(const void* a, const void* b) {
  const struct glass_node *x = a, *y = b;
  if (x->distance != y->distance) return x->distance > y->distance ? -1 : 1;
  if (x->batch != y->batch) return x->batch < y->batch ? -1 : 1;
  return x->node < y->node ? -1 : x->node > y->node;
}

// The transparent nodes' lit ranges, back to front by the distance of their
// bounding spheres' centres, in each batch's ranges (one call draws them in
// that order); and the transparent batches, farthest first. Two batches
// interleave only in their order as a whole: a batch is one call per pass.
static void sort_glass(app_renderer* r) {
  // The list is not allocated until a glass node is drawn (qsort of a null array is undefined).
  if (r->glass_node_count > 0)
    qsort(r->glass_nodes, r->glass_node_count, sizeof *r->glass_nodes, farther_node);
  for (uint32_t i = 0; i < r->glass_node_count; ++i) {
    const struct glass_node* g = &r->glass_nodes[i];
    draw_batch* batch = &r->batches[g->batch];
    const tree_buffers* t = &r->trees[batch->tree];
    if (batch->range_count[SURFACE] == 0 && batch->range_count[INTERIOR] == 0) batch->distance = g->distance;
    for (int section = 0; section < SECTIONS; ++section) {
      uint32_t count =
          batch->simple ? t->coarse_count[g->level][section][g->node] : t->index_count[section][g->node];
      uint32_t first =
          batch->simple ? t->coarse_first[g->level][section][g->node] : t->first_index[section][g->node];
      if (count == 0) continue;
      append_range(r, batch->first_range[section], &batch->range_count[section], count, first);
      r->stats.triangles += (batch->simple ? 1 : 2) * (count / 3); // detailed: back faces, then front
    }
  }
  if (r->glass_batch_capacity < r->batch_count) {
    r->glass_batch_capacity = r->batch_capacity;
    r->glass_batches = bk_realloc(r->glass_batches, sizeof(uint32_t) * r->glass_batch_capacity);
  }
  r->glass_batch_count = 0;
  for (uint32_t b = 0; b < r->batch_count; ++b)
    if (r->batches[b].transparent) r->glass_batches[r->glass_batch_count++] = b;
  // Farthest first, by insertion: a frame has a transparent batch or two per glass object.
  for (uint32_t i = 1; i < r->glass_batch_count; ++i) {
    uint32_t b = r->glass_batches[i], j = i;
    for (; j > 0 && r->batches[r->glass_batches[j - 1]].distance < r->batches[b].distance; --j)
      r->glass_batches[j] = r->glass_batches[j - 1];
    r->glass_batches[j] = b;
  }
}

// Turns the frame's items into node table rows and batches, and uploads the
// tables (one buffer update per tree, one for the loose table). Both passes
// then draw from the same index ranges.
void render_prepare_batches(app_renderer* r) {
  if (++r->frame == 0) {
    // Wrapped: stamps from 2^32 frames ago would pass for this frame's.
    for (uint32_t i = 0; i < r->tree_count; ++i)
      if (r->trees[i].used) {
        memset(r->trees[i].node_frame, 0, sizeof(uint32_t) * r->trees[i].node_count);
        r->trees[i].frame = 0;
      }
    r->frame = 1;
  }
  if (r->drawn_tree_capacity < r->tree_count) {
    r->drawn_tree_capacity = r->tree_capacity;
    r->drawn_trees = bk_realloc(r->drawn_trees, sizeof(uint32_t) * r->drawn_tree_capacity);
  }
  r->batch_count = r->drawn_tree_count = r->spill_count = r->loose_count = r->glass_node_count = 0;
  // Screen pixels per world unit at distance 1, and the eye.
  const float pixels_per_unit = 0.5f * (float)r->height / tanf(0.5f * (float)r->camera.fov_y);
  const float eye[3] = {(float)r->camera.eye.x, (float)r->camera.eye.y, (float)r->camera.eye.z};
  static const float no_color[4] = {0, 0, 0, 0};
  // The ground, then the spheres.
  write_row(loose_row(r), (const float[12]){1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, no_color, 0.0f, 1.0f);
  for (uint32_t i = 0; i < r->sphere_count; ++i) {
    const float* s = r->spheres[i];
    const float rows[12] = {s[3], 0, 0, s[0], 0, s[3], 0, s[1], 0, 0, s[3], s[2]};
    write_row(loose_row(r), rows, no_color, 0.0f, 1.0f);
    float distance = sqrtf((s[0] - eye[0]) * (s[0] - eye[0]) + (s[1] - eye[1]) * (s[1] - eye[1]) +
                           (s[2] - eye[2]) * (s[2] - eye[2]));
    int level = 0;
    while (level + 1 < SPHERE_LEVELS && 2.0f * s[3] * pixels_per_unit < sphere_level_pixels[level] * distance)
      level++;
    // The shadow map has a texel per centimetre or so: a level coarser is enough.
    int shadow = level + 1 < SPHERE_LEVELS ? level + 1 : level;
    r->sphere_levels[i][0] = (int8_t)(sphere_inside(r->view_planes, s, s[3]) ? level : -1);
    r->sphere_levels[i][1] = (int8_t)(sphere_inside(r->light_planes, s, s[3]) ? shadow : -1);
  }
  for (uint32_t i = 0; i < r->item_count; ++i) {
    const draw_item* item = &r->items[i];
    tree_buffers* t = render_find_tree(r, item->tree);
    if (!t) continue;
    if (t->frame != r->frame) {
      t->frame = r->frame;
      t->lowest = UINT32_MAX;
      t->highest = 0;
      t->shadow_dithered = false;
      r->drawn_trees[r->drawn_tree_count++] = item->tree.index;
    }
    uint32_t detailed = find_batch(r, item, false), simple = UINT32_MAX;
    const float shadow = r->materials[item->material].shadow;
    const float* m = item->rows;
    for (uint32_t k = 0; k < item->node_count; ++k) {
      uint32_t node = r->nodes[item->first_node + k];
      if (node >= t->node_count) continue;
      // How wide the node's bounding sphere looks: small ones draw simply.
      const float* sphere = t->spheres[node];
      float centre[3];
      for (int row = 0; row < 3; ++row)
        centre[row] = m[4 * row] * sphere[0] + m[4 * row + 1] * sphere[1] + m[4 * row + 2] * sphere[2] +
                      m[4 * row + 3] - eye[row];
      float distance = sqrtf(centre[0] * centre[0] + centre[1] * centre[1] + centre[2] * centre[2]);
      const float world[3] = {centre[0] + eye[0], centre[1] + eye[1], centre[2] + eye[2]};
      float pixels = 2.0f * sphere[3] * pixels_per_unit; // times the distance
      bool small = pixels < simple_below_pixels * distance;
      // Out of view, a node is drawn only into the shadow map, if it casts there.
      bool seen = sphere_inside(r->view_planes, world, sphere[3]);
      if (!seen && (small || !(shadow > 0.0f) || !sphere_inside(r->light_planes, world, sphere[3]))) continue;
      if (seen && small && simple == UINT32_MAX) simple = find_batch(r, item, true);
      uint32_t b = !seen ? SHADOW_ONLY : small ? simple : detailed;
      const float* color = item->colored ? &r->node_colors[4 * (item->first_node + k)] : no_color;
      if (t->node_frame[node] == r->frame) {
        // Bodies own disjoint nodes, so this is rare (the API allows it).
        if (r->spill_count == r->spill_capacity) {
          r->spill_capacity = bk_grow_capacity(r->spill_capacity, r->spill_count + 1);
          r->spills = bk_realloc(r->spills, sizeof(spill_draw) * r->spill_capacity);
        }
        r->spills[r->spill_count++] = (spill_draw){.tree = item->tree.index,
                                                   .node = node,
                                                   .entry = r->loose_count,
                                                   .material = item->material,
                                                   .interior_scale = item->interior_scale};
        write_row(loose_row(r), item->rows, color, item->fade, shadow);
        r->stats.triangles += 2 * ((t->index_count[SURFACE][node] + t->index_count[INTERIOR][node]) / 3);
        continue;
      }
      t->node_frame[node] = r->frame;
      t->node_batch[node] = b;
      t->node_level[node] = pixels < tiny_below_pixels * distance;
      t->node_distance[node] = distance;
      float* row = &t->table[TABLE_FLOATS * node];
      write_row(row, item->rows, color, item->fade, shadow);
      t->shadow_dithered |= row[17] > 0.0f;
      if (node < t->lowest) t->lowest = node;
      if (node > t->highest) t->highest = node;
      if (b != SHADOW_ONLY) r->batches[b].node_count++;
    }
  }
  uint32_t next_range = 0;
  for (uint32_t b = 0; b < r->batch_count; ++b)
    for (int section = 0; section < SECTIONS; ++section) {
      r->batches[b].first_range[section] = next_range;
      next_range += r->batches[b].node_count;
    }
  for (uint32_t i = 0; i < r->drawn_tree_count; ++i) {
    tree_buffers* t = &r->trees[r->drawn_trees[i]];
    t->first_shadow_range = next_range;
    t->shadow_range_count = 0;
    if (t->lowest > t->highest) continue;
    // In node order, so that neighbouring nodes merge into one range.
    for (int section = 0; section < SECTIONS; ++section) {
      for (uint32_t node = t->lowest; node <= t->highest; ++node) {
        if (t->node_frame[node] != r->frame) continue;
        uint32_t count = t->index_count[section][node], first = t->first_index[section][node];
        if (t->node_batch[node] == SHADOW_ONLY) {
          if (count == 0) continue;
          append_range(r, t->first_shadow_range, &t->shadow_range_count, count, first);
          r->stats.triangles += count / 3;
          continue;
        }
        draw_batch* batch = &r->batches[t->node_batch[node]];
        if (batch->transparent) {
          // Its lit ranges go in back to front below; its shadow now.
          if (section == SURFACE) add_glass_node(r, t, node);
          if (batch->simple || count == 0 || !(r->materials[batch->material].shadow > 0.0f)) continue;
          append_range(r, t->first_shadow_range, &t->shadow_range_count, count, first);
          r->stats.triangles += count / 3;
          continue;
        }
        if (batch->simple) {
          // Small nodes draw coarse and cast no shadow: theirs would be a
          // few texels, and the shadow pass paid for every one of their
          // triangles (8 ms a frame with 1500 shards in view).
          int level = t->node_level[node];
          uint32_t coarse = t->coarse_count[level][section][node];
          if (coarse == 0) continue;
          append_range(r, batch->first_range[section], &batch->range_count[section], coarse,
                       t->coarse_first[level][section][node]);
          r->stats.triangles += coarse / 3;
          continue;
        }
        if (count == 0) continue;
        append_range(r, batch->first_range[section], &batch->range_count[section], count, first);
        append_range(r, t->first_shadow_range, &t->shadow_range_count, count, first);
        r->stats.triangles += 2 * (count / 3); // lit and shadow passes
      }
    }
    next_range += t->shadow_range_count;
    glBindBuffer(GL_TEXTURE_BUFFER, t->table_buffer);
    glBufferSubData(GL_TEXTURE_BUFFER, (GLintptr)(sizeof(float) * TABLE_FLOATS * t->lowest),
                    (GLsizeiptr)(sizeof(float) * TABLE_FLOATS * (t->highest - t->lowest + 1)),
                    &t->table[TABLE_FLOATS * t->lowest]);
  }
  sort_glass(r);
  glBindBuffer(GL_TEXTURE_BUFFER, r->loose_buffer);
  GLsizeiptr loose_size = (GLsizeiptr)(sizeof(float) * TABLE_FLOATS * r->loose_count);
  if (r->loose_count > r->loose_gpu_capacity) {
    r->loose_gpu_capacity = r->loose_capacity;
    glBufferData(GL_TEXTURE_BUFFER, (GLsizeiptr)(sizeof(float) * TABLE_FLOATS * r->loose_gpu_capacity), NULL,
                 GL_DYNAMIC_DRAW);
  }
  glBufferSubData(GL_TEXTURE_BUFFER, 0, loose_size, r->loose);
  glBindBuffer(GL_TEXTURE_BUFFER, 0);
}
