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
  if (!(cbrt(volume / b->refine.pieces) >= b->refine.min_size)) return false;
  bk_vec3 lo = bk_v3_sub(n->bounds.min, local), hi = bk_v3_sub(local, n->bounds.max);
  bk_vec3 out = bk_v3_max(bk_v3(0, 0, 0), bk_v3_max(lo, hi));
  double s = fmax(bk_v3_length(out), rt->def.damage_min_distance);
  double damage = b->material.frailty * impulse / (s * s * s);
  double cross_section = cbrt(volume) * cbrt(volume);
  return damage > b->material.refine_strength * cross_section;
}

static void mark(bk_runtime* rt, uint32_t breakable_index, uint32_t leaf, bk_vec3 local) {
  rt_breakable* b = &rt->breakables[breakable_index];
  const bk_mesh_tree* tree = b->tree;
  uint32_t node = tree->leaf_nodes[leaf];
  rt_refine_job* job = bk_calloc(1, sizeof *job);
  job->breakable = breakable_index;
  job->generation = b->generation;
  job->node = node;
  job->due_call = rt->refine_calls + 1u + rt->def.refine_latency;
  job->mesh = tree->nodes[node].mesh;
  job->tree_bounds = tree->nodes[0].bounds;
  bk_fracture_def def = bk_default_fracture_def();
  def.pattern = b->refine.pattern;
  def.pieces = b->refine.pieces;
  def.seed = job_seed(tree->desc.seed, node);
  def.impact = local;
  def.radial_falloff = b->refine.radial_falloff;
  def.texture_scale = tree->desc.texture_scale;
  def.aspect_bias = tree->desc.aspect_bias;
  def.threads = 1; // one worker per fragment: the game keeps the other core
  job->def = def;
  if (rt->refine_job_count == rt->refine_job_capacity) {
    rt->refine_job_capacity = bk_grow_capacity(rt->refine_job_capacity, rt->refine_job_count + 1);
    rt->refine_jobs = bk_realloc(rt->refine_jobs, sizeof(rt_refine_job*) * rt->refine_job_capacity);
  }
  rt->refine_jobs[rt->refine_job_count++] = job;
  if (!b->leaf_refining) b->leaf_refining = bk_calloc(tree->leaf_count, 1);
  b->leaf_refining[leaf] = 1;
  rt->refine_marked++;
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

static void* job_work(void* arg) {
  rt_refine_job* job = arg;
  job->ok = bk_mesh_fracture_leaf(&job->mesh, job->tree_bounds, &job->def, &job->pieces, &job->err);
  return NULL;
}

void rt_refine_start(bk_runtime* rt, rt_refine_job* job) {
  if (job->built || job->threaded || rt->refine_threads >= rt->def.refine_threads) return;
  pthread_t* thread = bk_alloc(sizeof(pthread_t));
  if (pthread_create(thread, NULL, job_work, job) != 0) {
    bk_free(thread); // no thread: the landing call does the work
    return;
  }
  job->thread = thread;
  job->threaded = true;
  rt->refine_threads++;
}

void rt_refine_finish(bk_runtime* rt, rt_refine_job* job) {
  if (job->built) return;
  if (job->threaded) {
    pthread_join(*(pthread_t*)job->thread, NULL);
    bk_free(job->thread);
    job->thread = NULL;
    job->threaded = false;
    rt->refine_threads--;
  } else {
    job_work(job);
  }
  job->built = true;
}

void rt_refine_job_free(rt_refine_job* job) {
  bk_mesh_tree_free(&job->pieces);
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
    if (job->threaded) rt_refine_finish(rt, job); // its worker reads the leaf's mesh
    rt_refine_job_free(job);
  }
  rt->refine_job_count = kept;
}
