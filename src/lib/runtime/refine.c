// Refinement landing: a marked fragment's pieces spliced into its
// breakable's own copy of the tree (bk_mesh_tree_splice), the BCRB graph
// renumbered around them (leaves after it move up, bonds keep their
// indices), and the hits that waited applied to the pieces' bonds, as if the
// pieces had been there when they struck. The refined fragment's cluster
// keeps its node set (the fragment's node covers its pieces), so its body,
// mass and collider do not change; the bonds the hits break split it next.
#include <string.h>

#include "runtime_internal.h"

// The breakable's own tree, copied from the caller's at the first refinement:
// arrays copied, meshes shared (the splice never touches existing meshes).
static void own_tree(rt_breakable* b) {
  if (b->own_tree) return;
  const bk_mesh_tree* from = b->tree;
  bk_mesh_tree* t = bk_calloc(1, sizeof *t);
  *t = *from;
  t->nodes = bk_alloc(sizeof(bk_mesh_tree_node) * from->node_count);
  memcpy(t->nodes, from->nodes, sizeof(bk_mesh_tree_node) * from->node_count);
  t->leaf_nodes = bk_alloc(sizeof(uint32_t) * from->leaf_count);
  memcpy(t->leaf_nodes, from->leaf_nodes, sizeof(uint32_t) * from->leaf_count);
  t->bonds = bk_alloc(sizeof(bk_bond) * (from->bond_count + 1u));
  if (from->bond_count) memcpy(t->bonds, from->bonds, sizeof(bk_bond) * from->bond_count);
  b->own_tree = t;
  b->shared_nodes = from->node_count;
  b->tree = t;
}

// What the refined leaf's bonds were: the neighbour (new numbering), the
// fraction of hit points left, broken.
typedef struct old_bond {
  uint32_t neighbour;
  double fraction;
  uint8_t broken;
} old_bond;

static uint32_t* spread_leaves_u32(const uint32_t* from, uint32_t old_count, uint32_t leaf, uint32_t k) {
  uint32_t* to = bk_alloc(sizeof(uint32_t) * (old_count + k));
  memcpy(to, from, sizeof(uint32_t) * leaf);
  for (uint32_t p = 0; p < k; ++p)
    to[leaf + p] = from[leaf];
  memcpy(to + leaf + k, from + leaf + 1, sizeof(uint32_t) * (old_count - leaf - 1));
  return to;
}

static uint8_t* spread_leaves_u8(const uint8_t* from, uint32_t old_count, uint32_t leaf, uint32_t k) {
  uint8_t* to = bk_calloc(old_count + k, 1);
  memcpy(to, from, leaf);
  memcpy(to + leaf + k, from + leaf + 1, old_count - leaf - 1);
  return to;
}

// Hit points of the bonds the splice changed or added: a divided bond's
// parts keep the fraction its hit points had left (and its break), the
// pieces' own bonds start whole.
static void refresh_bonds(rt_breakable* b, const bk_splice_info* info, const uint32_t* olds_bond,
                          const old_bond* olds, uint32_t old_count) {
  const bk_mesh_tree* tree = b->tree;
  uint32_t bonds = tree->bond_count, first = info->first_bond;
  b->bond_hp = bk_realloc(b->bond_hp, sizeof(double) * (bonds + 1u));
  b->bond_hp_initial = bk_realloc(b->bond_hp_initial, sizeof(double) * (bonds + 1u));
  b->bond_broken = bk_realloc(b->bond_broken, bonds + 1u);
  double strength = b->material.bond_strength;
  for (uint32_t i = 0; i < old_count; ++i) {
    uint32_t j = olds_bond[i];
    b->bond_hp_initial[j] = strength * tree->bonds[j].area;
    b->bond_hp[j] = olds[i].broken ? 0.0 : olds[i].fraction * b->bond_hp_initial[j];
  }
  uint32_t lo = info->leaf, hi = info->leaf + info->leaf_count;
  for (uint32_t j = first; j < bonds; ++j) {
    const bk_bond* bd = &tree->bonds[j];
    bool in_a = bd->leaf_a >= lo && bd->leaf_a < hi, in_b = bd->leaf_b >= lo && bd->leaf_b < hi;
    b->bond_hp_initial[j] = strength * bd->area;
    b->bond_hp[j] = b->bond_hp_initial[j];
    b->bond_broken[j] = 0;
    if (in_a && in_b) continue;
    uint32_t neighbour = in_a ? bd->leaf_b : bd->leaf_a;
    for (uint32_t i = 0; i < old_count; ++i)
      if (olds[i].neighbour == neighbour) {
        b->bond_broken[j] = olds[i].broken;
        b->bond_hp[j] = olds[i].broken ? 0.0 : olds[i].fraction * b->bond_hp_initial[j];
      }
  }
}

// The per-leaf state and every cluster of the breakable renumbered.
static void renumber(bk_runtime* rt, uint32_t index, const bk_splice_info* info) {
  rt_breakable* b = &rt->breakables[index];
  uint32_t leaf = info->leaf, k = info->leaf_count, grow = k - 1;
  uint32_t old_count = b->tree->leaf_count - grow;
  uint32_t slot_of_leaf = b->leaf_cluster[leaf];
  uint32_t* cluster = spread_leaves_u32(b->leaf_cluster, old_count, leaf, k);
  bk_free(b->leaf_cluster);
  b->leaf_cluster = cluster;
  uint8_t* anchored = spread_leaves_u8(b->leaf_anchored, old_count, leaf, k);
  if (b->anchored) {
    const bk_mesh_tree* tree = b->tree;
    double tolerance =
        1e-6 + 1e-6 * bk_v3_length(bk_v3_sub(tree->nodes[0].bounds.max, tree->nodes[0].bounds.min));
    for (uint32_t p = leaf; p < leaf + k; ++p) {
      const bk_mesh* mesh = &bk_mesh_tree_leaf(tree, p)->mesh;
      for (uint32_t q = 0; q < mesh->position_count && !anchored[p]; ++q)
        anchored[p] = bk_v3_dot(bk_transform_point(b->placement, mesh->positions[q]), b->up) <=
                      b->anchor_height + tolerance;
    }
  }
  bk_free(b->leaf_anchored);
  b->leaf_anchored = anchored;
  uint8_t* refining = spread_leaves_u8(b->leaf_refining, old_count, leaf, k);
  bk_free(b->leaf_refining);
  b->leaf_refining = refining;
  // The stress stage's per-leaf and per-bond state is made again at its
  // next solve (stress_leaves.c), and every cluster of the breakable solved
  // again from rest.
  rt_stress_forget_leaves(b);
  for (uint32_t slot = 0; slot < rt->cluster_count; ++slot) {
    rt_cluster* c = &rt->clusters[slot];
    if (!c->alive || c->breakable != index) continue;
    bk_free(c->split_labels);
    c->split_labels = NULL;
    rt_stress_release(c);
    c->stress_stale = true;
    c->stress_settled = false;
    uint32_t at = c->leaf_count;
    for (uint32_t i = 0; i < c->leaf_count; ++i)
      if (c->leaves[i] >= leaf) {
        at = i;
        break;
      }
    if (slot == slot_of_leaf) {
      c->leaves = bk_realloc(c->leaves, sizeof(uint32_t) * (c->leaf_count + grow));
      memmove(c->leaves + at + k, c->leaves + at + 1, sizeof(uint32_t) * (c->leaf_count - at - 1));
      for (uint32_t p = 0; p < k; ++p)
        c->leaves[at + p] = leaf + p;
      c->leaf_count += grow;
      for (uint32_t i = at + k; i < c->leaf_count; ++i)
        c->leaves[i] += grow;
    } else {
      for (uint32_t i = at; i < c->leaf_count; ++i)
        c->leaves[i] += grow;
    }
  }
}

// Whether a hit is among a job's (its hits are in sequence order).
static bool job_has_hit(const rt_refine_job* job, uint64_t sequence) {
  uint32_t lo = 0, hi = job->hit_count;
  while (lo < hi) {
    uint32_t mid = lo + (hi - lo) / 2;
    if (job->hits[mid].sequence < sequence)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo < job->hit_count && job->hits[lo].sequence == sequence;
}

static const rt_refine_job* job_of_leaf(const bk_runtime* rt, uint32_t index, uint32_t leaf) {
  uint32_t node = rt->breakables[index].tree->leaf_nodes[leaf];
  for (uint32_t i = 0; i < rt->refine_job_count; ++i) {
    const rt_refine_job* job = rt->refine_jobs[i];
    if (job && job->breakable == index && job->node == node) return job;
  }
  return NULL;
}

// A body the caller's physics has lost (a transform not finite) takes no
// waiting damage, as it takes no hit (damage.c): its breaks would be nowhere.
static bool body_lost(const bk_runtime* rt, uint32_t slot) {
  bk_body_state state = rt_body_state(rt, slot);
  bk_quat q = state.transform.rotation;
  return !bk_v3_is_finite(state.transform.position) ||
         !(isfinite(q.x) && isfinite(q.y) && isfinite(q.z) && isfinite(q.w));
}

// The waiting hits on the bonds of leaves [leaf, leaf + count): each bond
// once; one whose other leaf waits for its own pieces takes only the hits
// that one's job has not (it takes those when it lands).
static void apply_waiting_hits(bk_runtime* rt, uint32_t index, const rt_refine_job* job, uint32_t leaf,
                               uint32_t count) {
  rt_breakable* b = &rt->breakables[index];
  double s_min = rt->def.damage_min_distance;
  for (uint32_t l = leaf; l < leaf + count; ++l) {
    for (uint32_t a = b->adjacency_start[l]; a < b->adjacency_start[l + 1]; ++a) {
      uint32_t bond = b->adjacency[a];
      const bk_bond* bd = &b->tree->bonds[bond];
      uint32_t other = bd->leaf_a == l ? bd->leaf_b : bd->leaf_a;
      bool inside = other >= leaf && other < leaf + count;
      if ((inside && other < l) || b->bond_broken[bond]) continue;
      uint32_t slot = b->leaf_cluster[l];
      if (slot == UINT32_MAX || b->leaf_cluster[other] != slot || body_lost(rt, slot)) continue;
      const rt_refine_job* other_job =
          !inside && b->leaf_refining[other] ? job_of_leaf(rt, index, other) : NULL;
      for (uint32_t h = 0; h < job->hit_count; ++h) {
        const rt_refine_hit* hit = &job->hits[h];
        if (other_job && job_has_hit(other_job, hit->sequence)) continue;
        double s = fmax(bk_v3_length(bk_v3_sub(hit->local, bd->centroid)), s_min);
        if (!rt_bond_damage(b, bond, hit->frailty * hit->impulse / (s * s * s))) continue;
        rt_break_bond_by_hit(rt, slot, bond);
        rt_queue_split(rt, slot);
        break;
      }
    }
  }
}

static void record_refined(bk_runtime* rt, uint32_t index, const bk_splice_info* info) {
  if (rt->refined_count == rt->refined_capacity) {
    rt->refined_capacity = bk_grow_capacity(rt->refined_capacity, rt->refined_count + 1);
    rt->refined = bk_realloc(rt->refined, sizeof(bk_leaf_refined) * rt->refined_capacity);
  }
  const rt_breakable* b = &rt->breakables[index];
  uint32_t slot = b->leaf_cluster[info->leaf];
  rt->refined[rt->refined_count++] =
      (bk_leaf_refined){.breakable = {index, b->generation},
                        .cluster = slot == UINT32_MAX ? (bk_cluster_id){0, 0} : rt_cluster_id(rt, slot),
                        .splice = *info,
                        .breakable_user_data = b->user_data};
}

// Lands one job: true when its leaf was refined.
static bool land(bk_runtime* rt, rt_refine_job* job) {
  rt_breakable* b = &rt->breakables[job->breakable];
  if (!b->alive || b->generation != job->generation) return false;
  const bk_mesh_tree_node* n = &b->tree->nodes[job->node];
  if (n->child_count != 0) return false;
  uint32_t leaf = n->leaf_begin;
  b->leaf_refining[leaf] = 0;
  if (b->leaf_cluster[leaf] == UINT32_MAX) return false; // taken out meanwhile: nothing to refine
  bool ok = job->ok;
  bk_splice_info info = {0};
  if (ok) {
    // The leaf's bonds as they are: their parts keep what they had left.
    uint32_t count = b->adjacency_start[leaf + 1] - b->adjacency_start[leaf];
    uint32_t* olds_bond = bk_alloc(sizeof(uint32_t) * (count + 1u));
    old_bond* olds = bk_alloc(sizeof(old_bond) * (count + 1u));
    uint32_t grow = job->pieces.leaf_count - 1;
    for (uint32_t i = 0; i < count; ++i) {
      uint32_t j = b->adjacency[b->adjacency_start[leaf] + i];
      const bk_bond* bd = &b->tree->bonds[j];
      uint32_t other = bd->leaf_a == leaf ? bd->leaf_b : bd->leaf_a;
      olds_bond[i] = j;
      olds[i] =
          (old_bond){.neighbour = other > leaf ? other + grow : other,
                     .fraction = b->bond_hp_initial[j] > 0.0 ? b->bond_hp[j] / b->bond_hp_initial[j] : 0.0,
                     .broken = b->bond_broken[j]};
    }
    own_tree(b);
    ok = bk_mesh_tree_splice_measured(b->own_tree, leaf, &job->pieces, &job->contacts, &info, &job->err);
    if (ok) {
      renumber(rt, job->breakable, &info);
      refresh_bonds(b, &info, olds_bond, olds, count);
      rt_breakable_build_adjacency(b);
    }
    bk_free(olds_bond);
    bk_free(olds);
  }
  if (!ok) {
    rt->refine_failed++; // it stays whole and takes the hits that waited
    apply_waiting_hits(rt, job->breakable, job, leaf, 1);
    return false;
  }
  rt->refined_leaves++;
  record_refined(rt, job->breakable, &info);
  rt->refined[rt->refined_count - 1].prepared = job->prepared; // the caller's now
  job->prepared = NULL;
  apply_waiting_hits(rt, job->breakable, job, info.leaf, info.leaf_count);
  return true;
}

uint32_t bk_runtime_refine(bk_runtime* rt) {
  rt_journal_refine(rt);
  uint32_t call = ++rt->refine_calls;
  rt->refine_marked = 0;
  uint32_t landed = 0;
  for (uint32_t i = 0; i < rt->refine_job_count; ++i) {
    rt_refine_job* job = rt->refine_jobs[i];
    if (job->due_call > call) continue;
    rt_refine_finish(rt, job);
    landed += land(rt, job);
    rt->refine_jobs[i] = NULL; // landing later jobs must not find it
    rt_refine_job_free(rt, job);
  }
  uint32_t kept = 0;
  for (uint32_t i = 0; i < rt->refine_job_count; ++i)
    if (rt->refine_jobs[i]) rt->refine_jobs[kept++] = rt->refine_jobs[i];
  rt->refine_job_count = kept;
  rt_refine_start(rt, call); // jobs not due yet go to the workers, freed by the landing
  return landed;
}

uint32_t bk_runtime_refined_leaves(const bk_runtime* rt, bk_leaf_refined* out, uint32_t capacity) {
  uint32_t n = rt->refined_count < capacity ? rt->refined_count : capacity;
  if (out && n) memcpy(out, rt->refined, sizeof(bk_leaf_refined) * n);
  return rt->refined_count;
}
