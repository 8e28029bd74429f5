// Fuzzes the runtime API (breakables::runtime) as a game would call it, and
// as a buggy game might: the input is a program of runtime calls on a few
// small trees built once (a cube in 8 and in 27 pieces, a tower in 12 that
// stands on y = 0, a cube left whole: one leaf, no bonds).
//
// Input: byte 0 sets the runtime (split budget, stress budget), byte 1 its
// refinement (latency, a worker or not, per call), then each op is one byte
// (op % 11) followed by its arguments, read on demand (an
// input that runs out reads zeros and stops at the next op):
//   0 add a breakable (tree, anchored, transform, material: NaN, huge and
//     non-unit values included; its user data; refinement where it is
//     hit)    1 contacts    2 damage
//   at a point    3 split    4 remove a cluster or a whole breakable
//   5 setters (material, frailty, density, bond strength, a cluster's user
//   data, gravity)    6 stress solves (1..32 calls, random gravity,
//   supports and loads; or its two halves: fracture commands, forged
//   ones, applied)    7 move a body (the caller's physics; NaN and
//   huge states included)    8 pull the events into small buffers, then
//   take them or leave them to accumulate    9 queries with stale and
//   forged ids    10 refine (lands refinements: the tracked leaves renumbered).
// Numbers come from a table of the usual suspects (0, -0, NaN, +-inf,
// +-1e300, denormals) and of plausible values. Ids come live, stale
// (removed), forged (wrong generation, index out of range) or null.
//
// After every call it checks (fuzz_runtime_check.c): every leaf of every
// breakable is in exactly one live cluster (none once its cluster was
// removed), and bk_runtime_leaf_cluster agrees; each cluster's nodes cover exactly its
// leaves; cluster volumes (with those removed) add up to the tree's and
// masses to density x volume, within 1e-9 relative; no mass or inertia is
// negative or not finite. Events accumulate until taken: the live count
// moved by the created and removed events since the last take, the broken
// bonds reported are those counted since (events taken = events that
// happened), every broken bond is dead, and none broke on a body whose
// transform is not finite; a removed cluster is one the caller was given,
// a created one is not; the runtime asks where a body is only for one the
// caller was given. A take checks the user data (the breakable's on every
// event and its first cluster, a part's its parent's) and that the
// caller's clusters are then exactly the live ones. Calls that fail,
// setters and queries leave the events as they were; setters and removals
// return BK_OK or the code that says why not.
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_runtime.h"

const char bk_fuzz_harness[] = "fuzz_runtime";

// ---------------------------------------------------------------- input

typedef struct reader {
  const uint8_t* data;
  size_t size, at;
} reader;

static uint8_t u8(reader* r) { return r->at < r->size ? r->data[r->at++] : 0; }

// A number: the usual suspects, or a plausible value around `typical`.
static double pick_double(reader* r, double typical) {
  uint8_t b = u8(r);
  switch (b % 16) {
  case 0:
    return typical;
  case 1:
    return 0.0;
  case 2:
    return -typical;
  case 3:
    return NAN;
  case 4:
    return INFINITY;
  case 5:
    return -INFINITY;
  case 6:
    return 1e300;
  case 7:
    return -1e300;
  case 8:
    return 1e-300;
  case 9:
    return 5e-324; // the smallest denormal
  case 10:
    return -0.0;
  case 11:
    return DBL_MAX;
  case 12:
    return typical * 1e6;
  default:
    return typical * (1.0 + (int8_t)u8(r) / 32.0); // around it, either sign
  }
}

static bk_vec3 pick_vec3(reader* r, double typical) {
  double x = pick_double(r, typical), y = pick_double(r, typical), z = pick_double(r, typical);
  return bk_v3(x, y, z);
}

// Mostly small offsets (so hits land on the objects), sometimes anything.
static bk_vec3 pick_offset(reader* r) {
  uint8_t b = u8(r);
  if (b & 1) return pick_vec3(r, 0.5);
  double x = (int8_t)u8(r) / 128.0, y = (int8_t)u8(r) / 128.0, z = (int8_t)u8(r) / 128.0;
  return bk_v3(x, y, z);
}

// Each value read in its own declarator: the order of the arguments of a
// call, or of the members of a compound literal, is unspecified in C, and
// an input must mean the same to every compiler.
static bk_quat pick_quat(reader* r) {
  double x = pick_double(r, 0.5), y = pick_double(r, 0.5), z = pick_double(r, 0.5), w = pick_double(r, 0.5);
  return (bk_quat){x, y, z, w};
}

// ---------------------------------------------------------------- the caller's side

// The runtime asks only about clusters the caller was given (took the
// created event of): it answers for the others itself.
static bk_body_state body_state(bk_cluster_id cluster, void* context) {
  const session* s = context;
  if (cluster.index >= MAX_CLUSTERS) bk_fuzz_fail("body_state asked for cluster index %u", cluster.index);
  if (!bk_cluster_equal(s->known[cluster.index], cluster))
    bk_fuzz_fail("body_state asked for cluster %u, not given to the caller", cluster.index);
  return s->bodies[cluster.index];
}

static bk_cluster_id pick_cluster(session* s, reader* r) {
  uint8_t b = u8(r);
  uint32_t k = u8(r);
  switch (b % 8) {
  case 0:
    return (bk_cluster_id){0, 0};
  case 1:
    return s->stale_count ? s->stale[k % s->stale_count] : (bk_cluster_id){k, 1};
  case 2: // wrong generation
    if (s->live_count)
      return (bk_cluster_id){s->live[k % s->live_count].index, s->live[k % s->live_count].generation + 1};
    return (bk_cluster_id){0, 2};
  case 3:
    return (bk_cluster_id){MAX_CLUSTERS + k * 977u, 1};
  case 4:
    return (bk_cluster_id){UINT32_MAX, UINT32_MAX};
  default:
    return s->live_count ? s->live[k % s->live_count] : (bk_cluster_id){0, 1};
  }
}

static bk_breakable_id pick_breakable(session* s, reader* r) {
  uint8_t b = u8(r);
  uint32_t k = u8(r);
  const bk_breakable_id live =
      s->breakable_count ? s->breakables[k % s->breakable_count].id : (bk_breakable_id){0, 1};
  switch (b % 6) {
  case 0:
    return (bk_breakable_id){0, 0};
  case 1:
    return (bk_breakable_id){live.index, live.generation + 1};
  case 2:
    return (bk_breakable_id){MAX_BREAKABLES + k, 1};
  default:
    return live;
  }
}

// A point near a live cluster's body (where hits and contacts land), or anywhere.
static bk_vec3 pick_point(session* s, reader* r) {
  uint8_t b = u8(r);
  if (b % 4 == 3 || !s->live_count) return pick_vec3(r, 1.0);
  bk_cluster_id c = s->live[u8(r) % s->live_count];
  return bk_v3_add(s->bodies[c.index].transform.position, pick_offset(r));
}

static bk_material pick_material(reader* r) {
  bk_material m = *bk_material_at(u8(r) % bk_material_count());
  uint8_t b = u8(r);
  switch (b % 12) { // one field off (or not)
  case 0:
    m.density = pick_double(r, m.density);
    break;
  case 1:
    m.frailty = pick_double(r, m.frailty);
    break;
  case 2:
    m.bond_strength = pick_double(r, m.bond_strength);
    break;
  case 3:
    m.compression_limit = pick_double(r, m.compression_limit);
    break;
  case 4:
    m.tension_limit = pick_double(r, m.tension_limit);
    break;
  case 5:
    m.shear_limit = pick_double(r, m.shear_limit);
    break;
  case 6:
    m.restitution = pick_double(r, 0.5);
    break;
  case 7:
    m.friction = pick_double(r, 0.5);
    break;
  case 8:
    m.name = "a material name far longer than thirty-one bytes";
    break;
  case 9:
    m.name = NULL;
    break;
  case 10:
    m.accumulate = !m.accumulate;
    break;
  case 11:
    m.refine_strength = pick_double(r, 2e4); // refinement (bk_runtime_refine)
    break;
  default:
    break;
  }
  return m;
}
// ---------------------------------------------------------------- the calls

static void op_add(session* s, reader* r) {
  bk_breakable_def def = bk_default_breakable_def();
  uint32_t tree = u8(r) % TREE_COUNT;
  def.tree = &bk_fuzz_trees[tree];
  uint8_t flags = u8(r);
  def.anchored = flags & 1;
  if (flags & 2) def.transform.position = pick_vec3(r, 2.0);
  if (flags & 4) def.transform.rotation = pick_quat(r);
  if (flags & 8) def.material = pick_material(r);
  if (flags & 16) def.anchor_height = pick_double(r, 0.1);
  if (flags & 32) def.tree = NULL;
  if (flags & 64) { // refines where it is hit: few pieces, not too small (the leaves stay under MAX_LEAVES)
    uint8_t how = u8(r);
    static const bk_fracture_pattern patterns[4] = {BK_PATTERN_RADIAL, BK_PATTERN_VORONOI, BK_PATTERN_PLANES,
                                                    BK_PATTERN_BRICK};
    def.refine.pattern = patterns[how % 4];
    def.refine.pieces = 1u + (how >> 2) % 4u; // 1: refused
    def.refine.min_size = (how & 64) ? 0.15 : 0.3;
    def.material.refine_strength = (how & 128) ? 1e3 : def.material.bond_strength / 8.0;
  }
  if (s->breakable_count == MAX_BREAKABLES || bk_runtime_get_stats(s->rt).breakables == MAX_LIVE_BREAKABLES)
    return;
  tracked* tb = &s->breakables[s->breakable_count];
  memset(tb, 0, sizeof *tb);
  def.user_data = &tb->tag;
  bk_error err = {{0}};
  uint32_t live_before = s->live_count, bonds_before = s->bonds_broken;
  uint32_t created_before = s->created, removed_before = s->removed;
  bk_breakable_id id = bk_runtime_add_breakable(s->rt, &def, &err);
  if (bk_breakable_is_null(id)) {
    if (!err.message[0] || strchr(err.message, '\n'))
      bk_fuzz_fail("add_breakable: refused without a one-line message: '%s'", err.message);
    if (err.code != BK_ERROR_INVALID_ARGUMENT && err.code != BK_ERROR_BAD_TREE)
      bk_fuzz_fail("add_breakable: refused with code %d: '%s'", (int)err.code, err.message);
    bk_fuzz_check_state(s, "add_breakable (refused)");
    bk_fuzz_check_results_kept(s, "add_breakable (refused)");
    return;
  }
  s->breakable_count++;
  tb->id = id;
  tb->tree = tree;
  bk_fuzz_check_state(s, "add_breakable");
  bk_fuzz_check_results(s, "add_breakable", live_before, bonds_before, false);
  if (s->created != created_before + 1 || s->removed != removed_before)
    bk_fuzz_fail("add_breakable: %u created, %u removed", s->created - created_before,
                 s->removed - removed_before);
}

static void op_contacts(session* s, reader* r) {
  bk_damage_contact contacts[4];
  uint32_t count = u8(r) % 5;
  for (uint32_t i = 0; i < count; ++i) {
    contacts[i].cluster = pick_cluster(s, r);
    contacts[i].point = pick_point(s, r);
    contacts[i].impulse = pick_double(r, 2000.0);
    contacts[i].closing_speed = pick_double(r, 5.0);
  }
  uint32_t live_before = s->live_count, bonds_before = s->bonds_broken;
  bk_runtime_apply_contacts(s->rt, count ? contacts : NULL, count);
  bk_fuzz_check_state(s, "apply_contacts");
  bk_fuzz_check_results(s, "apply_contacts", live_before, bonds_before, true);
}

static void op_damage(session* s, reader* r) {
  bk_vec3 point = pick_point(s, r);
  double impulse = pick_double(r, 2000.0);
  uint32_t live_before = s->live_count, bonds_before = s->bonds_broken;
  bk_runtime_damage_at(s->rt, point, impulse);
  bk_fuzz_check_state(s, "damage_at");
  bk_fuzz_check_results(s, "damage_at", live_before, bonds_before, true);
}

static void op_split(session* s) {
  uint32_t live_before = s->live_count, bonds_before = s->bonds_broken;
  uint32_t splits_before = bk_runtime_get_stats(s->rt).splits;
  uint32_t made = bk_runtime_split(s->rt);
  bk_fuzz_check_state(s, "split");
  bk_fuzz_check_results(s, "split", live_before, bonds_before, false);
  // Each split takes one cluster out and puts its parts in.
  uint32_t splits = bk_runtime_get_stats(s->rt).splits - splits_before;
  if (s->live_count + splits != live_before + made)
    bk_fuzz_fail("split: returned %u made by %u splits, the live count went from %u to %u", made, splits,
                 live_before, s->live_count);
}

// Lands and starts refinements: leaves renumbered (the tracked retired
// leaves with them), bonds broken by the hits that waited, no cluster made
// or removed.
static void op_refine(session* s) {
  uint32_t live_before = s->live_count, bonds_before = s->bonds_broken;
  uint32_t events_before = bk_runtime_refined_leaves(s->rt, NULL, 0);
  uint32_t landed = bk_runtime_refine(s->rt);
  uint32_t events = bk_runtime_refined_leaves(s->rt, NULL, 0);
  if (events != events_before + landed)
    bk_fuzz_fail("refine: landed %u, refined events went from %u to %u", landed, events_before, events);
  bk_leaf_refined* refined = calloc(events + 1u, sizeof *refined);
  bk_runtime_refined_leaves(s->rt, refined, events);
  for (uint32_t i = events_before; i < events; ++i) {
    tracked* tb = bk_fuzz_find_tracked(s, refined[i].breakable);
    const bk_splice_info* sp = &refined[i].splice;
    const bk_mesh_tree* tree = tb ? bk_runtime_breakable_tree(s->rt, tb->id) : NULL;
    if (!tb || !tree || sp->leaf_count < 2 || sp->leaf + sp->leaf_count > tree->leaf_count ||
        tree->leaf_count > MAX_LEAVES || refined[i].breakable_user_data != &tb->tag)
      bk_fuzz_fail("refine: event %u names no refined leaf of a live breakable", i);
    uint32_t grow = sp->leaf_count - 1, old_count = tree->leaf_count - grow;
    memmove(tb->retired + sp->leaf + sp->leaf_count, tb->retired + sp->leaf + 1, old_count - sp->leaf - 1);
    memset(tb->retired + sp->leaf, tb->retired[sp->leaf], sp->leaf_count);
    tb->refined = true;
  }
  free(refined);
  bk_fuzz_check_state(s, "refine");
  bk_fuzz_check_results(s, "refine", live_before, bonds_before, true);
  if (s->live_count != live_before) bk_fuzz_fail("refine: the live count changed");
}

// Removes a whole breakable: its clusters go (those the caller was given
// reported removed), its id is stale everywhere.
static void op_remove_breakable(session* s, reader* r) {
  bk_breakable_id id = pick_breakable(s, r);
  tracked* tb = bk_fuzz_find_tracked(s, id);
  uint32_t live_before = s->live_count, bonds_before = s->bonds_broken;
  uint32_t mine = 0, given = 0;
  for (uint32_t i = 0; i < s->live_count; ++i) {
    bk_cluster_info info = {0};
    if (!bk_runtime_cluster(s->rt, s->live[i], &info) || info.breakable.index != id.index ||
        info.breakable.generation != id.generation)
      continue;
    mine++;
    given += bk_cluster_equal(s->known[s->live[i].index], s->live[i]);
  }
  uint32_t removed_before = s->removed;
  bk_result result = bk_runtime_remove_breakable(s->rt, id);
  if ((result == BK_OK) != (tb != NULL) || (result != BK_OK && result != BK_ERROR_STALE_ID))
    bk_fuzz_fail("remove_breakable: returned %d for a breakable that is %slive", (int)result,
                 tb ? "" : "not ");
  if (!tb) {
    bk_fuzz_check_state(s, "remove_breakable (stale)");
    bk_fuzz_check_results_kept(s, "remove_breakable (stale)");
    return;
  }
  tb->removed = true;
  bk_fuzz_check_state(s, "remove_breakable");
  bk_fuzz_check_results(s, "remove_breakable", live_before, bonds_before, false);
  if (s->live_count + mine != live_before || s->removed != removed_before + given)
    bk_fuzz_fail("remove_breakable: %u of its %u clusters were given, %u reported removed", given, mine,
                 s->removed - removed_before);
}

static void op_remove(session* s, reader* r) {
  if (u8(r) & 1) {
    op_remove_breakable(s, r);
    return;
  }
  bk_cluster_id id = pick_cluster(s, r);
  bk_cluster_info info = {0};
  bool live = bk_runtime_cluster(s->rt, id, &info);
  tracked* tb = NULL;
  uint32_t leaves[MAX_LEAVES] = {0}, leaf_count = live ? info.leaf_count : 0;
  if (live) {
    tb = bk_fuzz_find_tracked(s, info.breakable);
    if (!tb || leaf_count > MAX_LEAVES)
      bk_fuzz_fail("remove_cluster: cluster %u of an unknown breakable", id.index);
    memcpy(leaves, info.leaves, sizeof(uint32_t) * leaf_count);
  }
  uint32_t live_before = s->live_count, bonds_before = s->bonds_broken;
  uint32_t created_before = s->created, removed_before = s->removed;
  bool given = live && bk_cluster_equal(s->known[id.index], id);
  bk_result result = bk_runtime_remove_cluster(s->rt, id);
  bool removed = result == BK_OK;
  if (removed != live || (!removed && result != BK_ERROR_STALE_ID))
    bk_fuzz_fail("remove_cluster: returned %d for a cluster that is %slive", (int)result, live ? "" : "not ");
  if (!removed) {
    bk_fuzz_check_state(s, "remove_cluster (stale)");
    bk_fuzz_check_results_kept(s, "remove_cluster (stale)");
    return;
  }
  for (uint32_t k = 0; k < leaf_count; ++k)
    tb->retired[leaves[k]] = 1;
  tb->removed_volume += info.volume;
  bk_fuzz_check_state(s, "remove_cluster");
  bk_fuzz_check_results(s, "remove_cluster", live_before, bonds_before, false);
  // One the caller was given is reported removed; one it was not is taken
  // out of the created events instead.
  bool reported = s->removed == removed_before + 1 && s->created == created_before;
  bool withdrawn = s->removed == removed_before && s->created + 1 == created_before;
  if (given ? !reported : !withdrawn)
    bk_fuzz_fail("remove_cluster: %u removed, %u created, were %u, %u (given: %d)", s->removed, s->created,
                 removed_before, created_before, given);
}

static void op_setters(session* s, reader* r) {
  bk_breakable_id id = pick_breakable(s, r);
  uint8_t which = u8(r);
  bool live = bk_fuzz_find_tracked(s, id) != NULL;
  bk_material before = bk_runtime_material(s->rt, id);
  bk_result result = BK_OK;
  double value = 0.0;
  switch (which % 6) {
  case 0: {
    bk_material m = pick_material(r);
    result = bk_runtime_set_material(s->rt, id, &m);
    if ((result == BK_OK) != (live && bk_material_validate(&m, NULL)))
      bk_fuzz_fail("set_material: returned %d", (int)result);
    break;
  }
  case 1:
    value = pick_double(r, 1.0);
    result = bk_runtime_set_frailty(s->rt, id, value);
    if (result == BK_OK && bk_runtime_frailty(s->rt, id) != value)
      bk_fuzz_fail("set_frailty: %g did not stick", value);
    break;
  case 2:
    value = pick_double(r, 2400.0);
    result = bk_runtime_set_density(s->rt, id, value);
    if (result == BK_OK && bk_runtime_density(s->rt, id) != value)
      bk_fuzz_fail("set_density: %g did not stick", value);
    break;
  case 3:
    value = pick_double(r, 2e5);
    result = bk_runtime_set_bond_strength(s->rt, id, value);
    if (result == BK_OK && bk_runtime_bond_strength(s->rt, id) != value)
      bk_fuzz_fail("set_bond_strength: %g did not stick", value);
    break;
  case 4: { // a cluster's user data: only on one the caller was given (it knows no other)
    bk_cluster_id c = pick_cluster(s, r);
    void* data = (void*)&s->bodies[u8(r) % MAX_CLUSTERS];
    // Given, and not removed since (its removal not taken yet leaves it in the mirror).
    bool alive = bk_runtime_cluster(s->rt, c, &(bk_cluster_info){0});
    bool known = alive && c.index < MAX_CLUSTERS && bk_cluster_equal(s->known[c.index], c);
    if (!known && alive) break;
    bk_result set = bk_runtime_set_cluster_user_data(s->rt, c, data);
    if (set != (known ? BK_OK : BK_ERROR_STALE_ID))
      bk_fuzz_fail("set_cluster_user_data: returned %d", (int)set);
    if (known) s->user_data[c.index] = data;
    if (bk_runtime_cluster_user_data(s->rt, c) != (known ? data : NULL))
      bk_fuzz_fail("cluster_user_data: not what was set");
    break;
  }
  default: { // gravity: up for the next anchors
    bk_vec3 gravity = pick_vec3(r, 9.81);
    bk_result set = bk_runtime_set_gravity(s->rt, gravity);
    if ((set == BK_OK) != bk_v3_is_finite(gravity)) bk_fuzz_fail("set_gravity: returned %d", (int)set);
    break;
  }
  }
  bool ok = result == BK_OK;
  if (!ok && result != (live ? BK_ERROR_INVALID_ARGUMENT : BK_ERROR_STALE_ID))
    bk_fuzz_fail("a setter returned %d for a %s id", (int)result, live ? "live" : "stale");
  if (ok && !live && which % 6 < 4)
    bk_fuzz_fail("a setter accepted a stale breakable id {%u, %u}", id.index, id.generation);
  if (ok && (which % 6) && !isfinite(value)) bk_fuzz_fail("a setter accepted %g", value);
  if (!ok && memcmp(&before, &(bk_material){0}, sizeof before) != 0) {
    bk_material after = bk_runtime_material(s->rt, id);
    if (after.density != before.density || after.frailty != before.frailty ||
        after.bond_strength != before.bond_strength)
      bk_fuzz_fail("a refused setter changed the material");
  }
  bk_fuzz_check_state(s, "material setter");
  bk_fuzz_check_results_kept(s, "material setter");
}

// The stress solve's two halves: its fracture commands into a small array
// (a full one defers a cluster), the commands applied as reported (each
// breaks its bond) and forged ones (a stale cluster, a bond out of range, a
// cause that is none) refused.
static void stress_halves(session* s, bk_vec3 gravity, const bk_stress_support* supports,
                          uint32_t support_count, const bk_stress_load* loads, uint32_t load_count,
                          uint32_t capacity) {
  bk_fracture_command commands[12];
  uint32_t n = bk_runtime_stress_commands(s->rt, gravity, supports, support_count, loads, load_count,
                                          capacity ? commands : NULL, capacity);
  if (n > capacity) bk_fuzz_fail("stress_commands: %u commands in an array of %u", n, capacity);
  bk_fuzz_check_state(s, "stress_commands");
  bk_fuzz_check_results_kept(s, "stress_commands");
  for (uint32_t i = 0; i < n; ++i) {
    bk_fracture_command forged[3] = {commands[i], commands[i], commands[i]};
    forged[0].cluster.generation++;
    forged[1].bond += 1u << 20;
    forged[2].cause = (bk_break_cause)(BK_BREAK_STRESS + 1);
    if (bk_runtime_apply_fracture_commands(s->rt, forged, 3) != 0)
      bk_fuzz_fail("apply_fracture_commands: a forged command broke a bond");
  }
  bk_fuzz_check_results_kept(s, "forged fracture commands");
  uint32_t live_before = s->live_count, bonds_before = s->bonds_broken;
  uint32_t broken = bk_runtime_apply_fracture_commands(s->rt, commands, n);
  if (broken != n) bk_fuzz_fail("apply_fracture_commands: %u of %u commands broke their bond", broken, n);
  bk_fuzz_check_state(s, "apply_fracture_commands");
  bk_fuzz_check_results(s, "apply_fracture_commands", live_before, bonds_before, true);
}

static void op_stress(session* s, reader* r) {
  bk_stress_support supports[4];
  bk_stress_load loads[4];
  uint8_t a = u8(r);
  uint32_t calls = 1 + a % 32;
  // 32: the two halves instead, into an array of 0, 4, 8 or 12 commands.
  bool halves = a & 32;
  uint32_t capacity = 4u * (a >> 6);
  uint8_t b = u8(r);
  bk_vec3 gravity = b & 1 ? pick_vec3(r, 9.81) : bk_v3(0, -9.81, 0);
  uint32_t support_count = ((b >> 1) & 7u) % 5, load_count = (b >> 4) % 5;
  for (uint32_t i = 0; i < support_count; ++i) {
    supports[i].cluster = pick_cluster(s, r);
    supports[i].point = pick_point(s, r);
  }
  for (uint32_t i = 0; i < load_count; ++i) {
    loads[i].cluster = pick_cluster(s, r);
    loads[i].point = pick_point(s, r);
    loads[i].force = pick_vec3(r, 500.0);
  }
  for (uint32_t i = 0; i < calls; ++i) {
    if (halves) {
      stress_halves(s, gravity, support_count ? supports : NULL, support_count, load_count ? loads : NULL,
                    load_count, capacity);
      continue;
    }
    uint32_t live_before = s->live_count, bonds_before = s->bonds_broken;
    bk_runtime_solve_stress(s->rt, gravity, support_count ? supports : NULL, support_count,
                            load_count ? loads : NULL, load_count);
    bk_fuzz_check_state(s, "solve_stress");
    bk_fuzz_check_results(s, "solve_stress", live_before, bonds_before, true);
  }
  // What it reports on a bond: nothing for a stale id or a bad index, else
  // stresses that are numbers, none negative.
  bk_breakable_id id = pick_breakable(s, r);
  uint32_t bond = u8(r);
  bk_bond_stress st = {0};
  bool known = bk_runtime_bond_stress(s->rt, id, bond, &st);
  const tracked* tb = bk_fuzz_find_tracked(s, id);
  if (known && (!tb || bond >= bk_runtime_breakable_tree(s->rt, tb->id)->bond_count))
    bk_fuzz_fail("bond_stress: answered for a stale id or bond %u", bond);
  if (known && !(st.compression >= 0.0 && st.tension >= 0.0 && st.shear >= 0.0 && st.ratio >= 0.0))
    bk_fuzz_fail("bond_stress: bond %u: %g %g %g ratio %g", bond, st.compression, st.tension, st.shear,
                 st.ratio);
  bk_fuzz_check_results_kept(s, "bond_stress");
}

static void op_move(session* s, reader* r) {
  if (!s->live_count) return;
  bk_cluster_id c = s->live[u8(r) % s->live_count];
  bk_body_state* body = &s->bodies[c.index];
  uint8_t b = u8(r);
  if (b & 1) body->transform.position = bk_v3_add(body->transform.position, pick_offset(r));
  if (b & 2) body->transform.position = pick_vec3(r, 3.0);
  if (b & 4) body->transform.rotation = pick_quat(r);
  body->linear_velocity = b & 8 ? pick_vec3(r, 1.0) : bk_v3(0, 0, 0);
  body->angular_velocity = b & 16 ? pick_vec3(r, 1.0) : bk_v3(0, 0, 0);
}

// Events into buffers smaller than them (fuzz_runtime_check.c), then taken
// or left to accumulate.
static void op_pull(session* s, reader* r) {
  bk_fuzz_check_short_pulls(s, u8(r) % 4);
  if (u8(r) & 1) bk_fuzz_take(s);
}

static void op_query(session* s, reader* r) {
  // The state hash reads the state: asked twice, the same.
  uint64_t hash = bk_runtime_state_hash(s->rt);
  if (bk_runtime_state_hash(s->rt) != hash) bk_fuzz_fail("state_hash: two answers in a row differ");
  bk_cluster_id c = pick_cluster(s, r);
  bk_cluster_info info = {0};
  bool live = false;
  for (uint32_t i = 0; i < s->live_count; ++i)
    live |= bk_cluster_equal(s->live[i], c);
  if (bk_runtime_cluster(s->rt, c, &info) != live)
    bk_fuzz_fail("cluster {%u, %u}: found %d", c.index, c.generation, !live);
  bk_breakable_id id = pick_breakable(s, r);
  const tracked* tb = bk_fuzz_find_tracked(s, id);
  uint32_t leaf = u8(r) % 40, bond = u8(r);
  bk_cluster_id owner = bk_runtime_leaf_cluster(s->rt, id, leaf);
  const bk_mesh_tree* tree = tb ? bk_runtime_breakable_tree(s->rt, tb->id) : NULL;
  if (!bk_cluster_is_null(owner) && (!tree || leaf >= tree->leaf_count))
    bk_fuzz_fail("leaf_cluster: stale breakable or leaf %u has a cluster", leaf);
  double initial = -1.0, health = bk_runtime_bond_health(s->rt, id, bond, &initial);
  if (!tree || bond >= tree->bond_count) {
    if (health != 0.0 || initial != 0.0)
      bk_fuzz_fail("bond_health: stale id or bond %u has %g of %g", bond, health, initial);
  } else if (!(health >= 0.0 && health <= initial && isfinite(initial))) {
    bk_fuzz_fail("bond_health: bond %u has %g of %g", bond, health, initial);
  }
  if (!tb && bk_runtime_breakable_tree(s->rt, id)) bk_fuzz_fail("breakable_tree: a stale id has a tree");
  bk_material m = bk_runtime_material(s->rt, id);
  if (!tb && (m.density != 0.0 || m.name)) bk_fuzz_fail("material: a stale id has one");
  if (tb && !bk_material_validate(&m, NULL)) bk_fuzz_fail("material: the live one does not validate");
  bk_fuzz_check_results_kept(s, "queries");
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  bk_fuzz_build_trees();
  bk_fuzz_trace = getenv("BK_FUZZ_TRACE") && *getenv("BK_FUZZ_TRACE") == '1';
  reader r = {data, size, 0};
  session* s = calloc(1, sizeof *s);
  for (uint32_t i = 0; i < MAX_CLUSTERS; ++i)
    s->bodies[i].transform.rotation.w = 1.0;
  bk_runtime_def def = bk_default_runtime_def();
  uint8_t setup = u8(&r);
  def.max_new_clusters_per_split = setup & 1 ? 2u + setup % 5u : 48u;
  def.stress_budget = setup & 2 ? 1u + (uint32_t)(setup >> 2) * 40u : 16000u;
  uint8_t refine_setup = u8(&r);
  def.refine_latency = refine_setup % 3u;
  def.refine_threads = (refine_setup >> 2) & 1u;
  def.max_refinements_per_call = 1u + (refine_setup >> 3) % 3u;
  def.body_state = body_state;
  def.context = s;
  bk_error err = {{0}};
  s->rt = bk_runtime_create(&def, &err);
  if (!s->rt) bk_fuzz_fail("cannot create a runtime: %s", err.message);
  for (uint32_t op = 0; op < MAX_OPS && r.at < r.size; ++op) {
    switch (u8(&r) % 11) {
    case 0:
      op_add(s, &r);
      break;
    case 1:
      op_contacts(s, &r);
      break;
    case 2:
      op_damage(s, &r);
      break;
    case 3:
      op_split(s);
      break;
    case 4:
      op_remove(s, &r);
      break;
    case 5:
      op_setters(s, &r);
      break;
    case 6:
      op_stress(s, &r);
      break;
    case 7:
      op_move(s, &r);
      break;
    case 8:
      op_pull(s, &r);
      break;
    case 9:
      op_query(s, &r);
      break;
    default:
      op_refine(s);
      break;
    }
  }
  bk_fuzz_check_state(s, "the end");
  bk_fuzz_take(s);
  bk_runtime_destroy(s->rt);
  free(s);
  return 0;
}
