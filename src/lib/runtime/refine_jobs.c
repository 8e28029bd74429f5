// Refinement jobs: which fragments a hit refines, the hits that wait for
// their pieces, and the fracture of each on a worker thread (or on the
// calling thread). A job's result depends only on the leaf, its tree's
// bounds and the def, never on which thread made it or when, so the grown
// tree is the same bit for bit with any number of workers.
#include <pthread.h>
#include <string.h>

#include "runtime_internal.h"

// A seed per fragment from the tree's: the same hits, the same pieces.
static uint64_t job_seed(uint64_t seed, uint32_t node) {
  uint64_t z = seed + 0x9E3779B97F4A7C15ull * ((uint64_t)node + 1u);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

static rt_refine_job* find_job(const bk_runtime* rt, uint32_t breakable, uint32_t node) {
  for (uint32_t i = 0; i < rt->refine_job_count; ++i) {
    rt_refine_job* job = rt->refine_jobs[i];
    if (job && job->breakable == breakable && job->node == node) return job;
  }
  return NULL;
}

static void add_hit(rt_refine_job* job, rt_refine_hit hit) {
  if (job->hit_count == job->hit_capacity) {
    job->hit_capacity = bk_grow_capacity(job->hit_capacity, job->hit_count + 1);
    job->hits = bk_realloc(job->hits, sizeof(rt_refine_hit) * job->hit_capacity);
  }
  job->hits[job->hit_count++] = hit;
}

// Whether this hit refines a leaf: its damage at the leaf's bounds passes
// refine_strength x the leaf's cross-section, and its pieces would not be
// smaller than min_size.
static bool hit_refines(const bk_runtime* rt, const rt_breakable* b, uint32_t leaf, bk_vec3 local,
                        double impulse) {
  const bk_mesh_tree_node* n = bk_mesh_tree_leaf(b->tree, leaf);
  double volume = n->moments.v;
  if (!(bk_cbrt(volume / b->refine.pieces) >= b->refine.min_size)) return false;
  bk_vec3 lo = bk_v3_sub(n->bounds.min, local), hi = bk_v3_sub(local, n->bounds.max);
  bk_vec3 out = bk_v3_max(bk_v3(0, 0, 0), bk_v3_max(lo, hi));
  double s = fmax(bk_v3_length(out), rt->def.damage_min_distance);
  double damage = b->material.frailty * impulse / (s * s * s);
  double cross_section = bk_cbrt(volume) * bk_cbrt(volume);
  return damage > b->material.refine_strength * cross_section;
}

// The point of triangle abc nearest to p (by its regions: vertices, edges,
// face).
static bk_vec3 triangle_nearest(bk_vec3 p, bk_vec3 a, bk_vec3 b, bk_vec3 c) {
  bk_vec3 ab = bk_v3_sub(b, a), ac = bk_v3_sub(c, a), ap = bk_v3_sub(p, a);
  double d1 = bk_v3_dot(ab, ap), d2 = bk_v3_dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  bk_vec3 bp = bk_v3_sub(p, b);
  double d3 = bk_v3_dot(ab, bp), d4 = bk_v3_dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return bk_v3_add(a, bk_v3_scale(ab, d1 / (d1 - d3)));
  bk_vec3 cp = bk_v3_sub(p, c);
  double d5 = bk_v3_dot(ab, cp), d6 = bk_v3_dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return bk_v3_add(a, bk_v3_scale(ac, d2 / (d2 - d6)));
  double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return bk_v3_add(b, bk_v3_scale(bk_v3_sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))));
  double denominator = va + vb + vc;
  if (!(denominator > 0.0)) return a; // no area
  return bk_v3_add(a, bk_v3_add(bk_v3_scale(ab, vb / denominator), bk_v3_scale(ac, vc / denominator)));
}

// The radial pattern grows its pieces from the impact inside the source: a
// hit beside the fragment (on a neighbour, or on its box beside it) starts
// from the fragment's surface point nearest to it. Found on the worker.
static bk_vec3 surface_nearest(const bk_mesh* mesh, bk_vec3 p) {
  bk_vec3 best = p;
  double best_d = INFINITY;
  for (uint32_t t = 0; t < mesh->triangle_count; ++t) {
    bk_vec3 q = triangle_nearest(p, mesh->positions[bk_mesh_tri_position(mesh, t, 0)],
                                 mesh->positions[bk_mesh_tri_position(mesh, t, 1)],
                                 mesh->positions[bk_mesh_tri_position(mesh, t, 2)]);
    double d = bk_v3_length(bk_v3_sub(q, p));
    if (d < best_d) best_d = d, best = q;
  }
  return best;
}

// A job for the leaf of `node` hit at `local`, due at `due_call`, in the
// list (its neighbours are the caller's to fill in).
static rt_refine_job* new_job(bk_runtime* rt, uint32_t breakable_index, uint32_t node, bk_vec3 local,
                              uint32_t due_call, bk_aabb tree_bounds, uint32_t neighbour_capacity) {
  rt_breakable* b = &rt->breakables[breakable_index];
  const bk_mesh_tree* tree = b->tree;
  rt_refine_job* job = bk_calloc(1, sizeof *job);
  job->breakable = breakable_index;
  job->generation = b->generation;
  job->node = node;
  job->due_call = due_call;
  job->mesh = tree->nodes[node].mesh;
  job->tree_bounds = tree_bounds;
  bk_fracture_def def = bk_default_fracture_def();
  def.pattern = b->refine.pattern;
  def.pieces = b->refine.pieces;
  def.seed = job_seed(tree->desc.seed, node);
  def.impact = local; // moved onto the fragment's surface on the worker
  def.radial_falloff = b->refine.radial_falloff;
  def.texture_scale = tree->desc.texture_scale;
  def.aspect_bias = tree->desc.aspect_bias;
  def.threads = 1; // one worker per fragment: the game keeps the other core
  job->def = def;
  job->neighbours = bk_alloc(sizeof(bk_piece_neighbour) * (neighbour_capacity + 1u));
  job->prepare = rt->def.refine_prepare;
  job->context = rt->def.context;
  if (rt->refine_job_count == rt->refine_job_capacity) {
    rt->refine_job_capacity = bk_grow_capacity(rt->refine_job_capacity, rt->refine_job_count + 1);
    rt->refine_jobs = bk_realloc(rt->refine_jobs, sizeof(rt_refine_job*) * rt->refine_job_capacity);
  }
  rt->refine_jobs[rt->refine_job_count++] = job;
  uint32_t leaf = tree->nodes[node].leaf_begin;
  if (!b->leaf_refining) b->leaf_refining = bk_calloc(tree->leaf_count, 1);
  b->leaf_refining[leaf] = 1;
  return job;
}

static void mark(bk_runtime* rt, uint32_t breakable_index, uint32_t leaf, bk_vec3 local) {
  rt_breakable* b = &rt->breakables[breakable_index];
  const bk_mesh_tree* tree = b->tree;
  rt_refine_job* job = new_job(rt, breakable_index, tree->leaf_nodes[leaf], local,
                               rt->refine_calls + 1u + rt->def.refine_latency, tree->nodes[0].bounds,
                               b->adjacency_start[leaf + 1] - b->adjacency_start[leaf]);
  // Its neighbours as they are now (their meshes never change): the worker
  // measures how the pieces touch each one's face, so the landing need not.
  for (uint32_t k = b->adjacency_start[leaf]; k < b->adjacency_start[leaf + 1]; ++k) {
    const bk_bond* bd = &tree->bonds[b->adjacency[k]];
    uint32_t other = bd->leaf_a == leaf ? bd->leaf_b : bd->leaf_a;
    job->neighbours[job->neighbour_count++] = (bk_piece_neighbour){
        .node = tree->leaf_nodes[other], .mesh = bk_mesh_tree_leaf(tree, other)->mesh, .bond_area = bd->area};
  }
  rt->refine_marked++;
}

void rt_refine_restore(bk_runtime* rt, uint32_t breakable_index, uint32_t node, uint32_t due_call,
                       bk_aabb tree_bounds, const uint32_t* neighbour_nodes, const double* neighbour_areas,
                       uint32_t neighbour_count, rt_refine_hit* hits, uint32_t hit_count) {
  const bk_mesh_tree* tree = rt->breakables[breakable_index].tree;
  rt_refine_job* job =
      new_job(rt, breakable_index, node, hits[0].local, due_call, tree_bounds, neighbour_count);
  for (uint32_t k = 0; k < neighbour_count; ++k)
    job->neighbours[job->neighbour_count++] =
        (bk_piece_neighbour){.node = neighbour_nodes[k],
                             .mesh = tree->nodes[neighbour_nodes[k]].mesh,
                             .bond_area = neighbour_areas[k]};
  job->hits = hits;
  job->hit_count = job->hit_capacity = hit_count;
}

void rt_refine_hit_cluster(bk_runtime* rt, uint32_t slot, bk_vec3 local, double impulse) {
  rt_cluster* c = &rt->clusters[slot];
  rt_breakable* b = &rt->breakables[c->breakable];
  bool refines = b->material.refine_strength > 0.0 && b->material.frailty > 0.0;
  if (!refines && !b->leaf_refining) return;
  rt_refine_hit hit = {++rt->hit_sequence, local, impulse, b->material.frailty};
  for (uint32_t i = 0; i < c->leaf_count; ++i) {
    uint32_t leaf = c->leaves[i];
    if (!(b->leaf_refining && b->leaf_refining[leaf])) {
      if (!refines || rt->refine_marked >= rt->def.max_refinements_per_call ||
          !hit_refines(rt, b, leaf, local, impulse))
        continue;
      mark(rt, c->breakable, leaf, local);
    }
    rt_refine_job* job = find_job(rt, c->breakable, b->tree->leaf_nodes[leaf]);
    if (job) add_hit(job, hit);
  }
}

// A fragment the radial pattern cannot seed (too thin where it was hit) is
// divided evenly instead.
static void job_work(rt_refine_job* job) {
  if (job->def.pattern == BK_PATTERN_RADIAL) job->def.impact = surface_nearest(&job->mesh, job->def.impact);
  job->ok = bk_mesh_fracture_leaf(&job->mesh, job->tree_bounds, &job->def, &job->pieces, &job->err);
  if (!job->ok && job->def.pattern == BK_PATTERN_RADIAL) {
    job->def.pattern = BK_PATTERN_VORONOI;
    job->ok = bk_mesh_fracture_leaf(&job->mesh, job->tree_bounds, &job->def, &job->pieces, &job->err);
  }
  if (job->ok)
    bk_mesh_measure_piece_contacts(&job->mesh, job->tree_bounds, &job->pieces, job->neighbours,
                                   job->neighbour_count, &job->contacts);
  if (job->ok && job->prepare) job->prepared = job->prepare(&job->pieces, job->context);
  job->built = true;
}

/// Jobs one worker thread builds in turn.
typedef struct rt_refine_batch {
  rt_refine_job** jobs;
  uint32_t count;
  uint32_t refs; // jobs not freed yet
  bool joined;
  pthread_t thread;
} rt_refine_batch;

static void* batch_work(void* arg) {
  rt_refine_batch* batch = arg;
  for (uint32_t i = 0; i < batch->count; ++i)
    job_work(batch->jobs[i]);
  return NULL;
}

void rt_refine_start(bk_runtime* rt, uint32_t call) {
  // The jobs waiting to be built, oldest first, shared out among the free
  // workers in runs (each worker builds its run in order).
  uint32_t waiting = 0;
  for (uint32_t i = 0; i < rt->refine_job_count; ++i) {
    const rt_refine_job* job = rt->refine_jobs[i];
    waiting += job->due_call > call && !job->batch && !job->built;
  }
  uint32_t free_workers =
      rt->def.refine_threads > rt->refine_threads ? rt->def.refine_threads - rt->refine_threads : 0;
  uint32_t batches = waiting < free_workers ? waiting : free_workers;
  uint32_t at = 0;
  for (uint32_t k = 0; k < batches; ++k) {
    uint32_t size = waiting / batches + (k < waiting % batches);
    rt_refine_batch* batch = bk_calloc(1, sizeof *batch);
    batch->jobs = bk_alloc(sizeof(rt_refine_job*) * size);
    while (batch->count < size) {
      rt_refine_job* job = rt->refine_jobs[at++];
      if (job->due_call > call && !job->batch && !job->built) batch->jobs[batch->count++] = job;
    }
    if (pthread_create(&batch->thread, NULL, batch_work, batch) != 0) {
      bk_free(batch->jobs); // no thread: the landing call does the work
      bk_free(batch);
      continue;
    }
    for (uint32_t i = 0; i < batch->count; ++i)
      batch->jobs[i]->batch = batch;
    batch->refs = batch->count;
    rt->refine_threads++;
  }
}

void rt_refine_finish(bk_runtime* rt, rt_refine_job* job) {
  rt_refine_batch* batch = job->batch;
  if (batch && !batch->joined) {
    pthread_join(batch->thread, NULL);
    batch->joined = true;
    rt->refine_threads--;
  }
  if (!job->built) job_work(job);
}

void rt_refine_job_free(const bk_runtime* rt, rt_refine_job* job) {
  if (job->prepared && rt->def.refine_discard) rt->def.refine_discard(job->prepared, rt->def.context);
  rt_refine_batch* batch = job->batch;
  if (batch && --batch->refs == 0) {
    bk_free(batch->jobs);
    bk_free(batch);
  }
  bk_mesh_tree_free(&job->pieces);
  bk_piece_contacts_free(&job->contacts);
  bk_free(job->neighbours);
  bk_free(job->hits);
  bk_free(job);
}

void rt_refine_cancel(bk_runtime* rt, uint32_t breakable_index) {
  uint32_t kept = 0;
  for (uint32_t i = 0; i < rt->refine_job_count; ++i) {
    rt_refine_job* job = rt->refine_jobs[i];
    if (breakable_index != UINT32_MAX && job->breakable != breakable_index) {
      rt->refine_jobs[kept++] = job;
      continue;
    }
    if (job->batch) rt_refine_finish(rt, job); // its worker reads the leaf's mesh
    rt_refine_job_free(rt, job);
  }
  rt->refine_job_count = kept;
}
