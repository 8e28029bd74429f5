// The mesh tree of the planes and brick patterns: the source mesh at the
// root, every intermediate piece kept, fragments at the leaves. The largest
// leaf is split next, so pieces stay even-sized instead of clustering (the
// thesis saw clusters of tiny pieces from depth-first splitting); with a
// brick bond, pieces spanning several bricks go first, cut along the mortar.
//
// On several threads: the order of splits is the one-thread order (the
// calling thread takes them into the tree one by one, largest first), but
// the splits themselves are made ahead, on every thread, for the largest
// leaves waiting. A split depends only on its node (plane_split.h), so the
// tree is byte-identical for any thread count. A split made ahead with room
// for more pieces than the tree has left when it is taken is made again
// (only near the end, when a cut would pass the count asked for).
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "plane_split.h"

static uint32_t add_node(bk_mesh_tree* tree, uint32_t* capacity, bk_mesh* mesh, bk_moments moments,
                         uint32_t parent) {
  if (tree->node_count == *capacity) {
    *capacity = bk_grow_capacity(*capacity, tree->node_count + 1);
    tree->nodes = bk_realloc(tree->nodes, sizeof(bk_mesh_tree_node) * *capacity);
  }
  uint32_t index = tree->node_count++;
  bk_mesh_tree_node* node = &tree->nodes[index];
  memset(node, 0, sizeof *node);
  node->mesh = *mesh; // takes ownership
  node->bounds = bk_mesh_bounds(mesh);
  node->moments = moments;
  node->parent = parent;
  node->first_child = BK_NULL_INDEX;
  node->depth = parent == BK_NULL_INDEX ? 0 : tree->nodes[parent].depth + 1;
  if (node->depth > tree->max_depth) tree->max_depth = node->depth;
  return index;
}

// Leaves waiting to be split, largest volume first (keys negated), ties by
// lower node index. With a brick bond, pieces that span several bricks wait
// in a heap of their own that is emptied first: the source parts along its
// mortar into whole bricks (or groups of them, with fewer pieces than
// bricks) before any brick is broken.
typedef struct leaf_queue {
  bk_heap within;            // pieces within one brick (every piece, without a bond)
  bk_heap across;            // pieces spanning several bricks
  const bk_brick_bond* bond; // NULL: the planes pattern
} leaf_queue;

static void queue_push(leaf_queue* q, const bk_mesh_tree_node* node, uint32_t index) {
  bk_plane plane = {0};
  bool across = q->bond && bk_brick_bond_plane(q->bond, node->bounds,
                                               bk_moments_to_mass(node->moments).centroid, &plane);
  bk_heap_push(across ? &q->across : &q->within, -node->moments.v, index);
}

static bool queue_empty(const leaf_queue* q) { return q->within.count == 0 && q->across.count == 0; }

static uint32_t queue_pop(leaf_queue* q) {
  return bk_heap_pop(q->across.count ? &q->across : &q->within).value;
}

static void queue_free(leaf_queue* q) {
  bk_heap_free(&q->within);
  bk_heap_free(&q->across);
}

static void count_shortfall(bk_fracture_shortfall* s, bk_split_failure why) {
  s->uncut++;
  switch (why) {
  case BK_SPLIT_MISSED:
    s->missed++;
    break;
  case BK_SPLIT_CAP_FAILED:
    s->cap_failed++;
    break;
  case BK_SPLIT_NOT_CLOSED:
    s->not_closed++;
    break;
  case BK_SPLIT_VOLUME_CHANGED:
  case BK_SPLIT_NO_VOLUME: // only a cut of no solid piece at all (a sheet cut alone)
    s->volume_changed++;
    break;
  case BK_SPLIT_NOT_SOLID:
    s->not_solid++;
    break;
  }
}

// ---------------------------------------------------------------- splitting ahead

typedef enum slot_state { SLOT_WAITING, SLOT_SPLITTING, SLOT_MADE } slot_state;

// A leaf's split made ahead (indexed by node).
typedef struct split_slot {
  slot_state state;
  uint32_t allowed; // what the split was made for
  uint32_t owner;   // the thread that made it (0: the calling thread)
  bk_plane_split split;
} split_slot;

// Blocks a thread allocated that another must let go of. Each thread
// allocates from its own malloc arena; freeing a block of another thread's
// arena takes that arena's lock, which the owner holds while it allocates
// (and grows its heap), and threads then sleep on each other. So the
// calling thread hands worker blocks back, and each worker frees its own.
typedef struct garbage {
  void** blocks;
  uint32_t count, capacity;
} garbage;

typedef struct tree_builder {
  pthread_mutex_t lock;
  pthread_cond_t changed; // a split was made, or the build ended
  bk_mesh_tree* tree;
  uint32_t capacity; // of tree->nodes
  split_slot* slots; // one per node
  uint32_t slot_capacity;
  leaf_queue taken; // leaves in the order the tree takes them
  leaf_queue ahead; // leaves nobody is splitting yet, in the same order
  uint32_t leaves;  // in the tree
  uint32_t pending; // splits made or being made ahead, not yet taken
  bool done;
  const bk_plane_split_context* ctx;
  garbage* garbage; // per thread: its blocks to bk_free(lock held to add or take)
} tree_builder;

static void discard(tree_builder* b, uint32_t owner, void* block) {
  if (owner == 0) {
    bk_free(block);
    return;
  }
  garbage* g = &b->garbage[owner];
  if (g->count == g->capacity) {
    g->capacity = bk_grow_capacity(g->capacity, g->count + 1);
    g->blocks = bk_realloc(g->blocks, sizeof(void*) * g->capacity);
  }
  g->blocks[g->count++] = block;
}

// Lets go of a split the tree does not take (lock held).
static void discard_split(tree_builder* b, uint32_t owner, bk_plane_split* split) {
  for (uint32_t i = 0; i < split->count; ++i) {
    bk_mesh* m = &split->pieces[i];
    void* blocks[5] = {m->positions, m->corners, m->indices, m->materials, m->tags};
    for (int k = 0; k < 5; ++k)
      discard(b, owner, blocks[k]);
  }
  discard(b, owner, split->pieces);
  discard(b, owner, split->moments);
  *split = (bk_plane_split){0};
}

// Frees the blocks handed back to thread `t` (lock held).
static void free_garbage(tree_builder* b, uint32_t t) {
  garbage* g = &b->garbage[t];
  for (uint32_t i = 0; i < g->count; ++i)
    bk_free(g->blocks[i]);
  g->count = 0;
}

// A leaf may be split ahead while fewer splits are pending than the tree can
// still take (each split adds at least one leaf): the waste at the end stays
// within the thread count.
static bool may_split_ahead(const tree_builder* b) {
  return !queue_empty(&b->ahead) && b->pending < b->tree->desc.pieces - b->leaves;
}

// Splits the next leaf of `ahead` on thread `thread`, with the lock held on
// entry and exit.
static void split_ahead(tree_builder* b, bk_plane_splitter* splitter, uint32_t thread) {
  uint32_t index = queue_pop(&b->ahead);
  bk_mesh_tree_node node = b->tree->nodes[index]; // the meshes stay; the array may move
  uint32_t allowed = b->tree->desc.pieces - b->leaves + 1;
  b->slots[index].state = SLOT_SPLITTING;
  b->pending++;
  pthread_mutex_unlock(&b->lock);
  bk_plane_split split = {0};
  bk_plane_split_node(splitter, b->ctx, &node, index, allowed, &split);
  pthread_mutex_lock(&b->lock);
  b->slots[index] = (split_slot){SLOT_MADE, allowed, thread, split};
  pthread_cond_broadcast(&b->changed);
}

typedef struct worker {
  tree_builder* builder;
  uint32_t thread;
} worker;

// A worker makes its cutting tools itself, so that all it allocates comes
// from its own arena (without them it leaves the work to the others).
static void* work(void* arg) {
  worker* w = arg;
  tree_builder* b = w->builder;
  bk_plane_splitter* splitter = bk_plane_splitter_create();
  if (!splitter) return NULL;
  pthread_mutex_lock(&b->lock);
  while (!b->done) {
    free_garbage(b, w->thread);
    if (may_split_ahead(b))
      split_ahead(b, splitter, w->thread);
    else
      pthread_cond_wait(&b->changed, &b->lock);
  }
  free_garbage(b, w->thread);
  pthread_mutex_unlock(&b->lock);
  bk_plane_splitter_destroy(splitter);
  return NULL;
}

static void grow_slots(tree_builder* b) {
  if (b->tree->node_count <= b->slot_capacity) return;
  uint32_t old = b->slot_capacity;
  b->slot_capacity =
      bk_grow_capacity(old, b->tree->node_count > b->capacity ? b->tree->node_count : b->capacity);
  b->slots = bk_realloc(b->slots, sizeof(split_slot) * b->slot_capacity);
  memset(b->slots + old, 0, sizeof(split_slot) * (b->slot_capacity - old));
}

// Takes a split made by thread `owner` into the tree (lock held): its
// pieces become the leaf's children and wait in both queues.
static void take_split(tree_builder* b, uint32_t index, bk_plane_split* split, uint32_t owner) {
  bk_mesh_tree* tree = b->tree;
  uint32_t first = tree->node_count;
  for (uint32_t i = 0; i < split->count; ++i)
    add_node(tree, &b->capacity, &split->pieces[i], split->moments[i], index);
  grow_slots(b);
  bk_mesh_tree_node* node = &tree->nodes[index];
  node->plane = split->plane;
  node->first_child = first;
  node->child_count = split->count;
  b->leaves += split->count - 1;
  for (uint32_t i = 0; i < split->count; ++i) {
    queue_push(&b->taken, &tree->nodes[first + i], first + i);
    queue_push(&b->ahead, &tree->nodes[first + i], first + i);
  }
  discard(b, owner, split->pieces);
  discard(b, owner, split->moments);
  *split = (bk_plane_split){0};
  pthread_cond_broadcast(&b->changed); // idle workers: new leaves wait
}

// Splits leaves, largest first, until the tree has d.pieces leaves or none
// can be split. False when the progress callback cancelled.
static bool grow_tree(tree_builder* b, bk_plane_splitter* splitter, uint32_t threads) {
  const bk_fracture_def* d = b->ctx->def;
  worker* workers = bk_calloc(threads, sizeof(worker));
  pthread_t* ids = bk_calloc(threads, sizeof(pthread_t));
  b->garbage = bk_calloc(threads, sizeof(garbage));
  uint32_t started = 1;
  for (uint32_t t = 1; t < threads; ++t, ++started) {
    workers[t] = (worker){b, t};
    if (pthread_create(&ids[t], NULL, work, &workers[t]) != 0) break; // this thread does their share
  }
  bool cancelled = false;
  pthread_mutex_lock(&b->lock);
  while (b->leaves < d->pieces && !queue_empty(&b->taken)) {
    uint32_t index = queue_pop(&b->taken);
    split_slot* slot = &b->slots[index];
    if (slot->state == SLOT_WAITING) {
      // Not split ahead: it is the largest leaf nobody took, so it heads `ahead` too.
      split_ahead(b, splitter, 0);
      slot = &b->slots[index];
    }
    while (b->slots[index].state != SLOT_MADE) {
      if (may_split_ahead(b))
        split_ahead(b, splitter, 0);
      else
        pthread_cond_wait(&b->changed, &b->lock);
    }
    slot = &b->slots[index];
    b->pending--;
    bk_plane_split split = slot->split;
    uint32_t owner = slot->owner;
    slot->split = (bk_plane_split){0};
    uint32_t allowed = d->pieces - b->leaves + 1;
    if (split.count > allowed) {
      // Made with room for more pieces than are left: made again for what is left.
      discard_split(b, owner, &split);
      owner = 0;
      pthread_mutex_unlock(&b->lock);
      bk_plane_split_node(splitter, b->ctx, &b->tree->nodes[index], index, allowed, &split);
      pthread_mutex_lock(&b->lock);
    }
    b->tree->shortfall.bond_fallbacks += split.bond_fallbacks;
    b->tree->shortfall.sheets_merged += split.sheets_merged;
    if (split.count == 0) { // no cut held: stays a leaf
      count_shortfall(&b->tree->shortfall, split.why);
      continue;
    }
    take_split(b, index, &split, owner);
    if (d->progress) {
      uint32_t leaves = b->leaves;
      pthread_mutex_unlock(&b->lock);
      cancelled = !d->progress(d->progress_user, leaves, d->pieces);
      pthread_mutex_lock(&b->lock);
      if (cancelled) break;
    }
  }
  b->done = true;
  pthread_cond_broadcast(&b->changed);
  pthread_mutex_unlock(&b->lock);
  for (uint32_t t = 1; t < started; ++t)
    pthread_join(ids[t], NULL);
  // Splits made ahead that the tree did not take, and what a worker that
  // could not start was handed (the threads are done: anyone may free).
  for (uint32_t i = 0; i < b->slot_capacity; ++i)
    bk_plane_split_free(&b->slots[i].split);
  for (uint32_t t = 0; t < threads; ++t) {
    free_garbage(b, t);
    bk_free(b->garbage[t].blocks);
  }
  bk_free(b->garbage);
  bk_free(workers);
  bk_free(ids);
  return !cancelled;
}

// ---------------------------------------------------------------- the build

// Moves nodes [first, last) back to the source's coordinates; the root
// keeps the source's own positions bit for bit.
typedef struct world_job {
  bk_mesh_tree* tree;
  const bk_mesh* source;
  bk_tree_frame frame;
  uint32_t first, last;
} world_job;

static void* world_work(void* arg) {
  world_job* job = arg;
  // A source already in its frame (centred on the origin, about unit size)
  // moves by p + 0 (only -0 becomes 0), which keeps the order of
  // coordinates: the local bounds moved the same way are the world bounds.
  bk_tree_frame f = job->frame;
  bool identity = f.exponent == 0 && f.origin.x == 0.0 && f.origin.y == 0.0 && f.origin.z == 0.0 &&
                  !signbit(f.origin.x) && !signbit(f.origin.y) && !signbit(f.origin.z);
  for (uint32_t i = job->first; i < job->last; ++i) {
    bk_mesh_tree_node* node = &job->tree->nodes[i];
    if (i == 0)
      memcpy(node->mesh.positions, job->source->positions, sizeof(bk_vec3) * job->source->position_count);
    else
      bk_tree_frame_to_world(job->frame, &node->mesh);
    if (identity && i != 0)
      node->bounds = (bk_aabb){bk_v3_add(node->bounds.min, f.origin), bk_v3_add(node->bounds.max, f.origin)};
    else
      node->bounds = bk_mesh_bounds(&node->mesh);
    node->moments = bk_tree_frame_moments_to_world(job->frame, node->moments);
    if (node->child_count) node->plane = bk_tree_frame_plane_to_world(job->frame, node->plane);
  }
  return NULL;
}

// Moves the tree back to the source's coordinates, nodes shared out between
// the threads (each node on its own: any split gives the same tree).
static void tree_to_world(bk_mesh_tree* tree, const bk_mesh* source, bk_tree_frame frame, uint32_t threads) {
  world_job* jobs = bk_calloc(threads, sizeof(world_job));
  for (uint32_t t = 0; t < threads; ++t)
    jobs[t] = (world_job){tree, source, frame, (uint32_t)((uint64_t)tree->node_count * t / threads),
                          (uint32_t)((uint64_t)tree->node_count * (t + 1) / threads)};
  bk_fracture_run_jobs(world_work, jobs, sizeof(world_job), threads);
  bk_free(jobs);
  if (tree->overlap.pairs) { // named in the source's coordinates
    bk_fracture_overlap* o = &tree->overlap;
    o->volume_a = ldexp(o->volume_a, 3 * frame.exponent);
    o->volume_b = ldexp(o->volume_b, 3 * frame.exponent);
    o->point = bk_v3_add(bk_v3(ldexp(o->point.x, frame.exponent), ldexp(o->point.y, frame.exponent),
                               ldexp(o->point.z, frame.exponent)),
                         frame.origin);
  }
}

// Overlapping shells cannot be cut together: the root's children are its
// overlapping shells (and the rest), each cut on its own below. No cap
// carries the root's tag, so its plane is only a unit placeholder. More
// shells than pieces asked for: the nearest are merged (no cut made them,
// so all count as one side). False (nothing changed) when the root has no
// such shells or they do not hold.
static bool split_shells(tree_builder* b, const bk_fracture_def* d) {
  bk_mesh* parts = NULL;
  bk_fracture_overlap overlap = {0};
  uint32_t count =
      d->pieces >= 2 ? bk_mesh_split_overlapping_shells(&b->tree->nodes[0].mesh, &parts, &overlap) : 0;
  if (count == 0) return false;
  bk_plane_split split = {parts, bk_alloc(sizeof(bk_moments) * count), count, {{0, 0, 1}, 0}, BK_SPLIT_MISSED,
                          0};
  bk_topology_scratch scratch = {0};
  bool held = bk_plane_pieces_hold(&b->tree->nodes[0], parts, count, split.moments, &split.why, &scratch);
  bk_topology_scratch_free(&scratch);
  if (!held) {
    bk_plane_split_free(&split);
    return false;
  }
  split.count = bk_merge_pieces(parts, split.moments, count, count, 0, d->pieces);
  b->tree->overlap = overlap;
  take_split(b, 0, &split, 0);
  return true;
}

bool bk_plane_tree_build(const bk_mesh* source, const bk_fracture_def* d, bk_mesh_tree* tree, bk_error* err) {
  // Everything is cut in the local frame (centred, about unit size) and moved
  // back to the source's coordinates at the end.
  bk_tree_frame frame = {0};
  bk_mesh root = {0};
  if (!bk_tree_frame_local_source(source, &frame, &root, err)) return false;
  double volume = bk_mesh_volume(&root);
  bk_aabb local_box = bk_mesh_bounds(&root);
  double area = bk_mesh_area(&root), size = bk_v3_length(bk_v3_sub(local_box.max, local_box.min));
  if (volume < BK_FRACTURE_MIN_THICKNESS * area * size) {
    bk_mesh_free(&root);
    return bk_error_set(err,
                        "mesh encloses almost no volume (%g for a surface of area %g): is it flat, or a "
                        "surface closed against its own back?",
                        ldexp(volume, 3 * frame.exponent), ldexp(area, 2 * frame.exponent));
  }
  uint32_t threads = bk_fracture_thread_count(d, d->pieces, 32);
  bk_plane_splitter* splitter = bk_plane_splitter_create(); // this thread's; workers make their own
  if (!splitter) {
    bk_mesh_free(&root);
    return bk_error_set(err, "fracture: cannot create the cap tessellator");
  }
  // Tags identify cuts of this tree and planar faces of the source, which
  // lets each piece's faces be re-triangulated over their true corners.
  bk_label_planar_faces(&root);
  tree->desc = *d;
  tree_builder b = {.tree = tree, .leaves = 1};
  // Room for the nodes of a tree of two-piece splits (a cut that makes more
  // grows it): no copying while it grows.
  b.capacity = 2u * d->pieces - 1u; // pieces <= 2^20 (validated)
  tree->nodes = bk_alloc(sizeof(bk_mesh_tree_node) * b.capacity);
  pthread_mutex_init(&b.lock, NULL);
  pthread_cond_init(&b.changed, NULL);
  add_node(tree, &b.capacity, &root, bk_mesh_moments(&root), BK_NULL_INDEX);
  grow_slots(&b);
  bk_brick_bond bond = bk_brick_bond_of(d, frame);
  b.taken.bond = b.ahead.bond = d->pattern == BK_PATTERN_BRICK ? &bond : NULL;
  bk_plane_split_context ctx = {d, &frame, b.taken.bond};
  b.ctx = &ctx;
  if (!split_shells(&b, d)) {
    queue_push(&b.taken, &tree->nodes[0], 0);
    queue_push(&b.ahead, &tree->nodes[0], 0);
  }
  bool finished = grow_tree(&b, splitter, threads);
  queue_free(&b.taken);
  queue_free(&b.ahead);
  bk_free(b.slots);
  pthread_mutex_destroy(&b.lock);
  pthread_cond_destroy(&b.changed);
  bk_plane_splitter_destroy(splitter);
  if (!finished) {
    bk_mesh_tree_free(tree);
    return bk_error_set(err, "fracture cancelled");
  }
  tree_to_world(tree, source, frame, threads);
  return true;
}
