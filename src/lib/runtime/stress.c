// Structural stress (bk_runtime_solve_stress, bk_runtime_stress_commands):
// which clusters carry a load to supports, their systems (stress_system.c)
// kept across calls and warm-started, and the bonds that give way. A stage
// above the core: it reads the clusters and reports the bonds to break as
// fracture commands, which the core applies (fracture_commands.c), as
// Blast's stress extension emits fracture commands for its core.
//
// A static cluster rests on its anchored fragments. A moving cluster rests
// on the fragments where the caller's physics has it touching something
// static, while it is slow; a falling or tumbling one carries no weight of
// its own (free fall loads nothing) and is left alone. A cluster's system is
// made once per set of bonds and supports: a broken bond or a new support
// set makes it stale; a new gravity direction (the body turned) reloads it.
// Once a load has converged its bonds are checked against the material's
// limits, and the cluster is settled: until something changes, it costs
// nothing. A half-converged load never breaks a bond; a converged one
// reports every bond past its limit at once (applied, the split follows) and
// the rest is solved again, so an overload spreads as it would.
#include <stdlib.h>
#include <string.h>

#include "stress_leaves.h"
#include "stress_loads.h"

// A moving cluster counts as resting after this many calls in a row at rest
// on something static (a quarter of a second at 60 Hz).
enum { DOF = 6, GROUP_LEVELS = 5, REST_CALLS = 15 };

static int compare_u32(const void* a, const void* b) {
  uint32_t x = *(const uint32_t*)a, y = *(const uint32_t*)b;
  return x < y ? -1 : x > y;
}

static uint32_t local_index(const rt_cluster* c, uint32_t leaf) {
  const uint32_t* found = bsearch(&leaf, c->leaves, c->leaf_count, sizeof(uint32_t), compare_u32);
  return (uint32_t)(found - c->leaves);
}

static bool is_held(const rt_cluster* c, uint32_t leaf) {
  return c->stress_held_count &&
         bsearch(&leaf, c->stress_held, c->stress_held_count, sizeof(uint32_t), compare_u32);
}

// The cluster's system: its leaves (supports fixed), its intact bonds.
static void build_system(rt_breakable* b, rt_cluster* c, uint32_t slot) {
  const bk_mesh_tree* tree = b->tree;
  rt_stress_node* nodes = bk_alloc(sizeof(rt_stress_node) * c->leaf_count);
  for (uint32_t i = 0; i < c->leaf_count; ++i) {
    uint32_t leaf = c->leaves[i];
    nodes[i] = (rt_stress_node){.centroid = b->leaf_centroid[leaf],
                                .mass = b->material.density * b->leaf_volume[leaf],
                                .fixed = c->is_static ? b->leaf_anchored[leaf] : is_held(c, leaf)};
  }
  uint32_t bond_count = 0, capacity = 16;
  rt_stress_bond* bonds = bk_alloc(sizeof(rt_stress_bond) * capacity);
  for (uint32_t i = 0; i < c->leaf_count; ++i) {
    uint32_t leaf = c->leaves[i];
    for (uint32_t k = b->adjacency_start[leaf]; k < b->adjacency_start[leaf + 1]; ++k) {
      uint32_t bond = b->adjacency[k];
      const bk_bond* bd = &tree->bonds[bond];
      if (!rt_bond_inside(b, bond, leaf, slot)) continue;
      if (bond_count == capacity) {
        capacity *= 2;
        bonds = bk_realloc(bonds, sizeof(rt_stress_bond) * capacity);
      }
      bonds[bond_count++] = (rt_stress_bond){.a = i,
                                             .b = local_index(c, bd->leaf_b),
                                             .centroid = bd->centroid,
                                             .normal = bd->normal,
                                             .area = bd->area,
                                             .tree_bond = bond};
    }
  }
  // Coarse groups: the leaves under one tree node of at least 8, 64, 512 ...
  // leaves move as one (the tree's nodes are compact, connected pieces).
  uint32_t* keys[GROUP_LEVELS] = {0};
  for (uint32_t g = 0; g < GROUP_LEVELS; ++g)
    keys[g] = bk_alloc(sizeof(uint32_t) * c->leaf_count);
  for (uint32_t i = 0; i < c->leaf_count; ++i) {
    uint32_t node = tree->leaf_nodes[c->leaves[i]], size = 8;
    for (uint32_t g = 0; g < GROUP_LEVELS; ++g, size *= 8) {
      while (tree->nodes[node].parent != BK_NULL_INDEX &&
             tree->nodes[node].leaf_end - tree->nodes[node].leaf_begin < size)
        node = tree->nodes[node].parent;
      keys[g][i] = node;
    }
  }
  rt_stress_destroy(c->stress);
  c->stress =
      rt_stress_create(nodes, c->leaf_count, bonds, bond_count, (const uint32_t* const*)keys, GROUP_LEVELS);
  for (uint32_t g = 0; g < GROUP_LEVELS; ++g)
    bk_free(keys[g]);
  for (uint32_t i = 0; i < c->leaf_count; ++i)
    memcpy(&c->stress->x[DOF * i], &b->leaf_motion[DOF * (size_t)c->leaves[i]], sizeof(double) * DOF);
  bk_free(nodes);
  bk_free(bonds);
  c->stress_stale = false;
  c->stress_settled = false;
}

// Where a call's fracture commands go: the caller's array (a fixed
// capacity) or the runtime's own, grown as needed (bk_runtime_solve_stress).
typedef struct command_sink {
  bk_fracture_command* commands;
  uint32_t count, capacity;
  bool grows;
} command_sink;

// Checks every bond of a converged load; reports those past their limits.
// When they do not all fit the sink, it reports none and the cluster is not
// settled: the next call checks it again.
static void settle(const bk_runtime* rt, rt_breakable* b, rt_cluster* c, uint32_t slot,
                   bk_transform tree_to_world, const bk_body_state* state, command_sink* sink) {
  const rt_stress* s = c->stress;
  for (uint32_t i = 0; i < c->leaf_count; ++i)
    memcpy(&b->leaf_motion[DOF * (size_t)c->leaves[i]], &s->x[DOF * i], sizeof(double) * DOF);
  const bk_material* m = &b->material;
  uint32_t first = sink->count;
  bool overflow = false;
  for (uint32_t k = 0; k < s->bond_count; ++k) {
    double stress[3] = {0};
    rt_stress_bond_stress(s, k, stress);
    double ratio = fmax(stress[0] / m->compression_limit,
                        fmax(stress[1] / m->tension_limit, stress[2] / m->shear_limit));
    uint32_t bond = s->tree_bond[k];
    double* out = &b->bond_stress[4 * (size_t)bond];
    out[0] = stress[0], out[1] = stress[1], out[2] = stress[2], out[3] = ratio;
    if (!(ratio > 1.0) || overflow) continue;
    if (sink->count == sink->capacity) {
      if (!sink->grows) {
        overflow = true;
        continue;
      }
      sink->capacity = bk_grow_capacity(sink->capacity, sink->count + 1u);
      sink->commands = bk_realloc(sink->commands, sizeof(bk_fracture_command) * sink->capacity);
    }
    bk_vec3 position = bk_transform_point(tree_to_world, b->tree->bonds[bond].centroid);
    bk_vec3 r = bk_v3_sub(position, state->transform.position);
    bk_vec3 velocity = bk_v3_add(state->linear_velocity, bk_v3_cross(state->angular_velocity, r));
    sink->commands[sink->count++] = (bk_fracture_command){.cluster = rt_cluster_id(rt, slot),
                                                          .bond = bond,
                                                          .position = position,
                                                          .velocity = velocity,
                                                          .cause = BK_BREAK_STRESS};
  }
  if (overflow) {
    sink->count = first;
    return;
  }
  c->stress_settled = true;
}

// ---------------------------------------------------------------- supports

typedef struct held_leaf {
  uint32_t slot, leaf; // while gathering: the support point's index in place of the leaf
} held_leaf;

// The range of entries of one cluster slot in an array sorted by slot, each
// entry `stride` bytes starting with its slot (held_leaf, rt_leaf_load).
static void slot_range(const void* entries, size_t stride, uint32_t count, uint32_t slot, uint32_t* first,
                       uint32_t* last) {
  const unsigned char* bytes = entries;
  uint32_t lo = 0, hi = count;
  while (lo < hi) {
    uint32_t mid = lo + (hi - lo) / 2, at = 0;
    memcpy(&at, bytes + stride * mid, sizeof at);
    if (at < slot)
      lo = mid + 1;
    else
      hi = mid;
  }
  *first = *last = lo;
  for (uint32_t at = 0; *last < count; ++*last) {
    memcpy(&at, bytes + stride * *last, sizeof at);
    if (at != slot) break;
  }
}

// Entries [first, last) of such an array, NULL when there are none: an
// empty array may be NULL (no supports or loads given), and offsetting a
// null pointer, even by zero, is undefined.
static const void* slot_entries(const void* entries, size_t stride, uint32_t first, uint32_t last) {
  return last > first ? (const unsigned char*)entries + stride * first : NULL;
}

static int compare_held(const void* a, const void* b) {
  const held_leaf *x = a, *y = b;
  if (x->slot != y->slot) return x->slot < y->slot ? -1 : 1;
  return x->leaf < y->leaf ? -1 : x->leaf > y->leaf;
}

// Maps the caller's support points to (cluster, leaf) pairs, sorted, unique,
// into rt's scratch. Points are taken cluster by cluster (one body state and
// one transform each); a cluster whose rest is already solved needs no leaf
// search, only to be seen resting: it gets one pair.
static uint32_t gather_supports(bk_runtime* rt, const bk_stress_support* supports, uint32_t count) {
  if (rt->stress_scratch_capacity < count) {
    rt->stress_scratch_capacity = bk_grow_capacity(rt->stress_scratch_capacity, count);
    rt->stress_scratch = bk_realloc(rt->stress_scratch, sizeof(held_leaf) * rt->stress_scratch_capacity);
  }
  held_leaf* out = rt->stress_scratch;
  uint32_t n = 0;
  for (uint32_t i = 0; i < count; ++i) // (slot, index of the point) first, to group them
    if (rt_find_cluster(rt, supports[i].cluster) && bk_v3_is_finite(supports[i].point))
      out[n++] = (held_leaf){supports[i].cluster.index, i};
  if (n) bk_sort(out, n, sizeof *out, compare_held);
  uint32_t held = 0;
  for (uint32_t first = 0, last = 0; first < n; first = last) {
    uint32_t slot = out[first].slot;
    while (last < n && out[last].slot == slot)
      last++;
    rt_cluster* c = &rt->clusters[slot];
    if (c->is_static || c->dirty || c->leaf_count < 2) continue;
    if (c->stress_rest_calls >= REST_CALLS) {
      out[held++] = (held_leaf){slot, 0};
      continue;
    }
    rt_breakable* b = &rt->breakables[c->breakable];
    rt_stress_prepare_breakable(b);
    bk_body_state state = rt_body_state(rt, slot);
    bk_transform to_tree = bk_transform_inverse(rt_tree_to_world(c, &state));
    for (uint32_t j = first; j < last; ++j) { // held <= j: each pair is read before it is overwritten
      bk_vec3 point = bk_transform_point(to_tree, supports[out[j].leaf].point);
      if (bk_v3_is_finite(point)) out[held++] = (held_leaf){slot, rt_stress_leaf_at(b, c, point)};
    }
  }
  if (held) bk_sort(out, held, sizeof *out, compare_held);
  uint32_t unique = 0;
  for (uint32_t i = 0; i < held; ++i)
    if (unique == 0 || compare_held(&out[unique - 1], &out[i]) != 0) out[unique++] = out[i];
  return unique;
}

// A moving cluster rests when no point of it moves faster than rest_speed.
// Its radius from its inertia: twice the radius of gyration about its
// weakest axis (a cube's half diagonal is 2.1 times it), so a chip of a big
// object is not judged by the whole object's size.
static bool at_rest(const bk_runtime* rt, const rt_cluster* c, const bk_body_state* state) {
  double largest = fmax(c->inertia.x, fmax(c->inertia.y, c->inertia.z));
  double radius = c->mass > 0.0 ? 2.0 * sqrt(largest / c->mass) : 0.0;
  double speed = bk_v3_length(state->linear_velocity) + bk_v3_length(state->angular_velocity) * radius;
  return speed <= rt->def.stress_rest_speed;
}

// Adds this call's held leaves to those of the cluster's rest so far (a
// union: contact points come and go from step to step while it rests).
static void merge_held(rt_cluster* c, const held_leaf* held, uint32_t count) {
  uint32_t* merged = bk_alloc(sizeof(uint32_t) * (c->stress_held_count + count + 1u));
  uint32_t i = 0, j = 0, n = 0;
  while (i < c->stress_held_count || j < count) {
    uint32_t next = j == count || (i < c->stress_held_count && c->stress_held[i] < held[j].leaf)
                        ? c->stress_held[i++]
                        : held[j++].leaf;
    if (n == 0 || merged[n - 1] != next) merged[n++] = next;
  }
  bk_free(c->stress_held);
  c->stress_held = merged;
  c->stress_held_count = n;
}

// ---------------------------------------------------------------- the call

static bool same_direction(bk_vec3 a, bk_vec3 b) {
  return bk_v3_length(bk_v3_sub(a, b)) <= 1e-9 * (bk_v3_length(a) + bk_v3_length(b));
}

static void solve(bk_runtime* rt, bk_vec3 gravity, const bk_stress_support* supports, uint32_t support_count,
                  const bk_stress_load* loads, uint32_t load_count, command_sink* sink) {
  rt->stress_clusters_solved = 0;
  rt->stress_iterations = 0;
  if (!bk_v3_is_finite(gravity) || (support_count && !supports) || (load_count && !loads)) return;
  uint32_t held_count = gather_supports(rt, supports, support_count);
  const held_leaf* held = rt->stress_scratch;
  uint32_t leaf_load_count = rt_stress_gather_loads(rt, loads, load_count);
  const rt_leaf_load* leaf_loads = rt->stress_load_scratch;

  // Clusters split below create slots past cluster_count's value now; they
  // are solved next call. The budget goes round: each call starts where the
  // last one ran out, so a big cluster cannot starve the others.
  uint32_t slots = rt->cluster_count;
  uint64_t budget = rt->def.stress_budget;
  bool spent = false;
  for (uint32_t visit = 0; visit < slots && !spent; ++visit) {
    uint32_t slot = (rt->stress_cursor + visit) % slots;
    rt_cluster* c = &rt->clusters[slot];
    uint32_t first = 0, last = 0;
    slot_range(held, sizeof *held, held_count, slot, &first, &last);
    if (!c->alive || c->dirty || c->leaf_count < 2) continue;
    rt_breakable* b = &rt->breakables[c->breakable];
    bk_body_state state = {0};
    if (!c->is_static) {
      // A rest is solved once, on what held the cluster over its first
      // REST_CALLS calls (the load does not move while it rests). Moving:
      // its last solve stands, and a new rest starts over. Still but with
      // no contact reported: asleep (physics engines report none for a
      // sleeping body), so resting where it was: its rest goes on (a body
      // can fall asleep before its rest is solved), and a bond broken since
      // (a hit on a sleeping body) is solved on what held it.
      bool touching = last > first;
      bool unsolved = c->stress_held_count && (c->stress_stale || !c->stress_settled);
      bool resting = c->stress_rest_calls > 0 && c->stress_rest_calls < REST_CALLS;
      if (!touching && !resting && !unsolved) continue; // airborne, or asleep with nothing new
      state = rt_body_state(rt, slot);
      if (!at_rest(rt, c, &state)) {
        c->stress_rest_calls = 0;
        c->stress_held_count = 0; // it moves: what held it is no longer under it
        continue;
      }
      if (touching && c->stress_rest_calls == 0) c->stress_held_count = 0; // a new rest
      if (c->stress_rest_calls < REST_CALLS) {
        if (touching) merge_held(c, slot_entries(held, sizeof *held, first, last), last - first);
        if (++c->stress_rest_calls < REST_CALLS || !c->stress_held_count) continue;
        c->stress_stale = true;
      }
    } else {
      state = rt_body_state(rt, slot);
    }
    bk_transform tree_to_world = rt_tree_to_world(c, &state);
    bk_vec3 local_gravity = bk_quat_rotate(bk_quat_conjugate(tree_to_world.rotation), gravity);
    // A body whose state is not finite (lost by the caller's physics) has
    // no load to solve: NaN would never converge, and would be reported.
    if (!bk_v3_is_finite(local_gravity) || !bk_v3_is_finite(tree_to_world.position)) continue;
    rt_stress_prepare_breakable(b);
    uint32_t load_first = 0, load_last = 0;
    slot_range(leaf_loads, sizeof *leaf_loads, leaf_load_count, slot, &load_first, &load_last);
    double weight = c->mass * bk_v3_length(gravity);
    const rt_leaf_load* cluster_loads = slot_entries(leaf_loads, sizeof *leaf_loads, load_first, load_last);
    if (rt_stress_window_loads(c, cluster_loads, load_last - load_first, weight)) {
      if (c->stress) c->stress->loaded = false; // carries them from its next load
      c->stress_settled = false;
    }
    // Within the budget (a step that starts within it may pass it): the
    // system made (a level per step, so a big one takes a few calls),
    // loaded, then iterated.
    uint64_t charged = 0;
    if (!c->stress || c->stress_stale) {
      build_system(b, c, slot);
      charged = rt_stress_create_cost(c->stress);
    } else if (c->is_static && c->stress->loaded && !same_direction(c->stress->gravity, local_gravity)) {
      c->stress->loaded = false; // the structure turned: its load did too
      c->stress_settled = false;
    } else if (c->stress_settled) {
      continue; // nothing changed since its last solve
    }
    rt_stress* s = c->stress;
    while (!s->ready && charged < budget)
      charged += rt_stress_setup_step(s);
    uint32_t done = 0;
    if (s->ready) {
      uint64_t cost = rt_stress_iteration_cost(s);
      if (!s->loaded && charged < budget) {
        double* node_loads = rt_stress_node_loads(c);
        rt_stress_load(s, local_gravity, node_loads);
        bk_free(node_loads);
        charged += cost;
      }
      if (s->loaded && charged < budget) {
        uint64_t iterations = (budget - charged + cost - 1u) / cost;
        done = rt_stress_iterate(s, (uint32_t)(iterations < UINT32_MAX ? iterations : UINT32_MAX),
                                 rt->def.stress_tolerance);
        charged += done * cost;
      }
    }
    rt->stress_iterations += done;
    rt->stress_clusters_solved++;
    budget = budget > charged ? budget - charged : 0u;
    if (budget == 0) {
      spent = true;
      rt->stress_cursor = slot; // this one first next call
    }
    if (rt_stress_converged(c->stress, rt->def.stress_tolerance))
      settle(rt, b, c, slot, tree_to_world, &state, sink);
  }
}

uint32_t bk_runtime_stress_commands(bk_runtime* rt, bk_vec3 gravity, const bk_stress_support* supports,
                                    uint32_t support_count, const bk_stress_load* loads, uint32_t load_count,
                                    bk_fracture_command* commands, uint32_t capacity) {
  command_sink sink = {.commands = commands, .capacity = commands ? capacity : 0u, .grows = false};
  solve(rt, gravity, supports, support_count, loads, load_count, &sink);
  return sink.count;
}

// The stage's commands, applied by the core at once: the bonds a cluster's
// converged load overstresses break together (the split follows) and the
// rest is solved again, so an overload spreads as it would.
void bk_runtime_solve_stress(bk_runtime* rt, bk_vec3 gravity, const bk_stress_support* supports,
                             uint32_t support_count, const bk_stress_load* loads, uint32_t load_count) {
  command_sink sink = {
      .commands = rt->stress_commands, .capacity = rt->stress_command_capacity, .grows = true};
  solve(rt, gravity, supports, support_count, loads, load_count, &sink);
  rt->stress_commands = sink.commands;
  rt->stress_command_capacity = sink.capacity;
  bk_runtime_apply_fracture_commands(rt, sink.commands, sink.count);
}

bool bk_runtime_bond_stress(const bk_runtime* rt, bk_breakable_id id, uint32_t bond, bk_bond_stress* out) {
  bk_bond_stress none = {0};
  if (out) *out = none;
  const rt_breakable* b = rt_find_breakable(rt, id);
  if (!b || bond >= b->tree->bond_count || !b->bond_stress) return false;
  if (b->bond_broken[bond]) return true;
  const double* s = &b->bond_stress[4 * (size_t)bond];
  if (s[3] < 0.0) return false;
  if (out) *out = (bk_bond_stress){s[0], s[1], s[2], s[3]};
  return true;
}
