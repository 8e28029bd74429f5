// The cap triangles of a planes-pattern tree's leaves, for its bonds (see
// bond_caps.h). Each thread takes a run of leaves (about equal triangle
// counts) and counts their caps per (cut, side); then each measures its
// caps in their cuts' planes straight into one array ordered by (cut,
// side), each run after the ones before it, so within a (cut, side) the
// entries keep leaf and triangle order on any thread count. Reading the
// leaves in their own order here spares the bonds a pass over every leaf's
// mesh in cut order (scattered through memory).
#include <stdlib.h>
#include <string.h>

#include "bond_caps.h"

typedef struct gather_job {
  const bk_mesh_tree* tree;
  const bk_cut_frame* frames;
  double flat;
  bk_vec3 origin;
  uint32_t first_leaf, last_leaf;
  uint32_t* keys; // per cap triangle of the run, in leaf order: 2 * cut + side
  uint32_t count, capacity;
  uint32_t* key_next; // per key: this run's count, then where its next entry goes
  bk_cap_entry* sorted;
  bool measure; // the second pass
} gather_job;

// Which cut made triangle t of a leaf's mesh, when it is a cap (else false).
static bool cap_cut(const bk_mesh_tree* tree, const bk_mesh* mesh, uint32_t t, uint32_t* cut) {
  uint32_t tag = mesh->tags[t];
  if (!bk_material_is_interior(mesh->materials[t]) || tag == 0 || tag > tree->node_count) return false;
  *cut = tag - 1;
  return true;
}

// First pass: the side of every cap triangle of a leaf (the cap faces +n
// below the cut), counted per key.
static void count_leaf(gather_job* job, uint32_t leaf) {
  const bk_mesh_tree* tree = job->tree;
  const bk_mesh* mesh = &bk_mesh_tree_leaf(tree, leaf)->mesh;
  uint32_t cut = 0;
  for (uint32_t t = 0; t < mesh->triangle_count; ++t) {
    if (!cap_cut(tree, mesh, t, &cut)) continue;
    bk_vec3 a = mesh->positions[bk_mesh_tri_position(mesh, t, 0)];
    bk_vec3 e = bk_v3_cross(bk_v3_sub(mesh->positions[bk_mesh_tri_position(mesh, t, 1)], a),
                            bk_v3_sub(mesh->positions[bk_mesh_tri_position(mesh, t, 2)], a));
    uint32_t key = 2u * cut + (bk_v3_dot(e, tree->nodes[cut].plane.normal) > 0.0 ? 0u : 1u);
    if (job->count == job->capacity) {
      job->capacity = bk_grow_capacity(job->capacity, job->count + 1);
      job->keys = bk_realloc(job->keys, sizeof(uint32_t) * job->capacity);
    }
    job->keys[job->count++] = key;
    job->key_next[key]++;
  }
}

// Second pass: each cap triangle of a leaf measured into its place;
// *at walks the run's keys.
static void measure_leaf(gather_job* job, uint32_t leaf, uint32_t* at) {
  const bk_mesh_tree* tree = job->tree;
  const bk_mesh* mesh = &bk_mesh_tree_leaf(tree, leaf)->mesh;
  uint32_t cut = 0;
  for (uint32_t t = 0; t < mesh->triangle_count; ++t) {
    if (!cap_cut(tree, mesh, t, &cut)) continue;
    uint32_t key = job->keys[(*at)++];
    bk_cap_entry* entry = &job->sorted[job->key_next[key]++];
    *entry = (bk_cap_entry){cut, key & 1u, leaf, t, {0, 0, 0}, 1, {{0, 0}, {0, 0}, {0, 0}}};
    bk_vec3 n = tree->nodes[cut].plane.normal;
    const bk_cut_frame* frame = &job->frames[cut];
    for (uint32_t k = 0; k < 3; ++k) {
      entry->position[k] = bk_mesh_tri_position(mesh, t, k);
      bk_vec3 p = bk_v3_sub(mesh->positions[entry->position[k]], job->origin);
      entry->uv[k][0] = bk_v3_dot(p, frame->u);
      entry->uv[k][1] = bk_v3_dot(p, frame->v);
      if (!(fabs(bk_v3_dot(p, n) - frame->height) <= job->flat)) entry->flat = 0;
    }
  }
}

static void* gather_work(void* arg) {
  gather_job* job = arg;
  uint32_t at = 0;
  for (uint32_t leaf = job->first_leaf; leaf < job->last_leaf; ++leaf)
    if (job->measure)
      measure_leaf(job, leaf, &at);
    else
      count_leaf(job, leaf);
  return NULL;
}

uint32_t bk_gather_cap_entries(const bk_mesh_tree* tree, const bk_cut_frame* frames, double flat,
                               bk_cap_entry** entries) {
  uint64_t triangles = 0;
  for (uint32_t leaf = 0; leaf < tree->leaf_count; ++leaf)
    triangles += bk_mesh_tree_leaf(tree, leaf)->mesh.triangle_count;
  uint32_t threads = bk_fracture_thread_count(&tree->desc, triangles, 16384);
  uint32_t keys = 2u * tree->node_count;
  gather_job* jobs = bk_calloc(threads, sizeof(gather_job));
  // Runs of whole leaves with about equal triangle counts.
  uint64_t seen = 0;
  uint32_t leaf = 0;
  for (uint32_t j = 0; j < threads; ++j) {
    jobs[j] = (gather_job){.tree = tree,
                           .frames = frames,
                           .flat = flat,
                           .origin = bk_mesh_tree_origin(tree),
                           .first_leaf = leaf,
                           .key_next = bk_calloc(keys + 1u, sizeof(uint32_t))};
    uint64_t goal = j + 1 == threads ? triangles : triangles * (j + 1) / threads;
    while (leaf < tree->leaf_count && (seen < goal || j + 1 == threads))
      seen += bk_mesh_tree_leaf(tree, leaf++)->mesh.triangle_count;
    jobs[j].last_leaf = leaf;
  }
  bk_fracture_run_jobs(gather_work, jobs, sizeof(gather_job), threads);
  // Where each run's entries of each key go: keys in order, runs in order within a key.
  uint32_t total = 0;
  for (uint32_t key = 0; key < keys; ++key)
    for (uint32_t j = 0; j < threads; ++j) {
      uint32_t count = jobs[j].key_next[key];
      jobs[j].key_next[key] = total;
      total += count;
    }
  *entries = bk_alloc(sizeof(bk_cap_entry) * (total + 1u));
  for (uint32_t j = 0; j < threads; ++j) {
    jobs[j].sorted = *entries;
    jobs[j].measure = true;
  }
  bk_fracture_run_jobs(gather_work, jobs, sizeof(gather_job), threads);
  for (uint32_t j = 0; j < threads; ++j) {
    bk_free(jobs[j].keys);
    bk_free(jobs[j].key_next);
  }
  bk_free(jobs);
  return total;
}
