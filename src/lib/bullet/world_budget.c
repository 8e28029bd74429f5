// The physics budget: when a step's physics costs more than
// physics_budget_ms, the least important loose pieces are made cheaper, tier
// by tier (bk_budget_tier), and once the cost has stayed well below it they
// get their fidelity back, in the reverse order.
//
// Where the time goes (perf, Release, a glass cube of 4,096 fragments shot
// once, 2,600 bodies): each small body overlaps a hundred others, and a
// step is their pairs: a third the narrowphase (GJK and the hulls' support
// points), a quarter the pair cache adding and dropping pairs and the
// broadphase tree, a fifth the solver on their contacts. The first tier
// takes the pieces out of each other's way (debris: Bullet's filter groups,
// so that pairs among them are never made), which took the worst step from
// 225 to 62 ms of CPU time; what is left is each moving box's query of the broadphase
// tree (a third), the solver and the narrowphase against the ground and the
// large pieces. The second tier gives a piece a sphere or box (fewer contact
// points, simpler tests), the third freezes it (its box no longer moves, and
// nothing is integrated, tested or solved for it) and the last removes it.
//
// What the player sees comes first for budget_fidelity_time after a piece
// comes loose (the mass and momentum of the loose pieces over the first
// second after a hit are within a few percent of the run without a budget):
// such a piece is made debris only while it flies apart. In a pile (a
// cube's heap, bricks jammed in a wall) it would fall through the other
// pieces: 16 walls of 1,024 moved 2.2x as much, and a stand-in shape or
// retiring cost the shattered cube a third of its momentum. So while the
// pieces of a fresh pile lie on each other, the budget can only take the
// burst around them out of each other's way (pairs, narrowphase and solver
// among flying pieces) and freeze what fell asleep; the pile itself (its
// pairs, GJK and contacts, a third to a half of such a step) is paid in
// full until it is a second old, and the budget is exceeded meanwhile.
// Only near the focus, though (budget_fidelity_radius): far piles are what
// the player sees least of, and 16 walls shot at once cost 76 ms a step
// with every piece kept, 14 ms with those 8 m or more away fair game.
//
// The cost compared with the budget is by default not the clock: the same
// inputs must make the same decisions, and the time a step takes depends on
// the machine and on whatever else runs on it. It is an estimate from what
// Bullet worked on in the step, each kind of work at its cost measured on
// this project's 2-core machine.
#include <stdlib.h>
#include <string.h>

#include "world_internal.h"

// Microseconds per unit of work in one step: a least-squares fit (relative
// error, no negative terms) to the physics CPU time of the 2,800 steps
// between 3 and 40 ms of cubes of 1,024 to 4,096 fragments shattered, 16
// walls of 1,024 shot at once and the showcase's 40-shot volley at 512
// pieces, each without a budget, at 8 and 16 ms, and with every piece debris
// (Release, this project's 2-core machine). Half the steps are within 10% of
// the estimate, nine in ten within 24%. Contact points cost nothing beyond
// their manifolds.
static const double us_per_awake_body = 5.4;   // integration, its box, its solver body
static const double us_per_manifold = 0.96;    // a touching pair: its contact rows in the solver
static const double us_per_narrow_pair = 0.75; // a pair tested by GJK (or skipped as still apart)
static const double us_per_pair = 0.019;       // a pair in the cache: one box test
static const double us_per_overlap = 0.037;    // a box met by a moving box in the tree

// The level rises at once when a step goes over (a whole tier for a step at
// twice the budget, at most), and falls slowly once the average of the last
// steps is under half the budget: a tier a second, so what was made cheaper
// comes back a few pieces a step rather than all in one.
static const double relax_fraction = 0.5;
static const double relax_per_step = 1.0 / 60.0;
static const double smoothing = 0.1; // the average's weight for the last step (about ten steps)

// Importance: the size a piece appears at from the focus, more when it moves
// fast (the eye follows motion), less the longer it has lain still.
static const double calm_speed = 0.25;   // m/s: slower than this, a piece is settling
static const double seen_speed = 1.0;    // m/s: moving this fast doubles its importance
static const double near_distance = 0.5; // m: nearer than this counts as this near
// Frozen only once asleep in Bullet, or after a sixth of a second calm: a
// piece slow at the top of a throw must not hang in the air.
static const uint32_t freeze_calm_steps = 10;
// A frozen piece pressed harder than this many times its own weight is set
// free: a few pieces like it may rest on it, a large body may not.
static const double press_weights = 4.0;
// Retiring, the one tier that cannot be undone, waits a quarter of a second
// at the top level, so that pieces that settle meanwhile are frozen
// instead; but not while a step costs twice the budget or more.
static const uint32_t retire_patience_steps = 15;
// Two loose pieces touching at less than this relative speed (m/s) are in
// a pile; a new piece counts as in one until its first contacts are known.
static const double pile_speed = 1.0;
static const uint64_t contacts_known_steps = 2;
static const double retire_at_once = 2.0;

typedef struct budget_candidate {
  uint32_t index; // into the world's bodies
  double importance;
  bk_budget_tier tier; // now (retired ones stay in the list)
  bool settled;        // at rest: asleep in Bullet, or calm for freeze_calm_steps
  bool one_node;       // a single mesh-tree node: what a retired body leaves to draw
  bool young;          // loose for less than budget_fidelity_time
  bool held;           // in a pile, or too new for its contacts to be known
  bool asleep;         // asleep in Bullet
} budget_candidate;

static double estimate_ms(const bk_physics_stats* s) {
  return 1e-3 *
         (us_per_awake_body * s->awake_bodies + us_per_manifold * s->manifolds +
          us_per_narrow_pair * s->narrow_pairs + us_per_pair * s->pairs + us_per_overlap * s->box_overlaps);
}

bool bk_world_budget_candidate(const bk_world* w, const bk_cluster_info* info, bk_vec3 center) {
  if (info->is_static || !(info->volume < w->def.budget_large_volume)) return false;
  if (!w->budget.has_focus) return true;
  return bk_v3_length(bk_v3_sub(center, w->budget.focus)) > w->def.budget_focus_radius;
}

// Whether a new piece at `center` keeps its first budget_fidelity_time:
// near the focus, what the player sees up close (everywhere without one),
// if it looks large enough from there to see how it moves.
static bool keeps_fidelity(const bk_world* w, const bk_cluster_info* info, bk_vec3 center) {
  if (!(w->def.budget_fidelity_time > 0.0)) return false;
  if (!w->budget.has_focus) return true;
  double distance = bk_v3_length(bk_v3_sub(center, w->budget.focus));
  return distance <= w->def.budget_fidelity_radius &&
         !(cbrt(info->volume) < w->def.budget_visible_angle * distance);
}

bk_budget_tier bk_world_budget_birth_tier(const bk_world* w, const bk_cluster_info* info, bk_vec3 center) {
  // While fidelity is kept, a new piece waits for its first contacts to
  // tell whether it flies apart or lies in a pile.
  bool everything =
      w->def.physics_budget_ms > 0.0 && w->budget.level >= 1.0 && !keeps_fidelity(w, info, center);
  return everything && bk_world_budget_candidate(w, info, center) ? BK_TIER_DEBRIS : BK_TIER_FULL;
}

bool bk_world_set_physics_budget(bk_world* w, double ms) {
  if (!(ms >= 0.0) || !isfinite(ms)) return false;
  w->def.physics_budget_ms = ms;
  return true;
}

double bk_world_physics_budget(const bk_world* w) { return w->def.physics_budget_ms; }

double bk_world_budget_fidelity_radius(const bk_world* w) { return w->def.budget_fidelity_radius; }

double bk_world_budget_visible_angle(const bk_world* w) { return w->def.budget_visible_angle; }

void bk_world_set_focus(bk_world* w, bk_vec3 point) {
  if (!bk_v3_is_finite(point)) return;
  w->budget.focus = point;
  w->budget.has_focus = true;
}

bool bk_world_focus(const bk_world* w, bk_vec3* point) {
  if (w->budget.has_focus && point) *point = w->budget.focus;
  return w->budget.has_focus;
}

uint32_t bk_world_retired_bodies(const bk_world* w, bk_retired_body* out, uint32_t capacity) {
  const world_budget* b = &w->budget;
  uint32_t n = b->retired_count < capacity ? b->retired_count : capacity;
  if (n) memcpy(out, b->retired_bodies, sizeof(bk_retired_body) * n);
  // Then the small fragments retire_volume removed (world.c).
  uint32_t aged = w->aged_count < capacity - n ? w->aged_count : capacity - n;
  if (aged) memcpy(out + n, w->aged, sizeof(bk_retired_body) * aged);
  return b->retired_count + w->aged_count;
}

static void restore(bk_world* w, uint32_t index);

// One tier back up for a piece at rest: a frozen one is unpinned where it
// lies, asleep (a moving body touching it, or its support going, wakes
// it), not restless: set free restless, each woke the pieces it touched,
// so that while the level relaxed, settled heaps were woken a tier at a
// time (16 walls of 1,024 shot at once cost 3.8 ms a step 15 s after the
// shot, 209 bodies awake, and 0.2 ms once everything slept).
static void restore_resting(bk_world* w, uint32_t index) {
  world_body* wb = &w->bodies[index];
  if (wb->tier != BK_TIER_FROZEN) {
    restore(w, index);
    return;
  }
  bk_physics_body_unpin_at_rest(w->physics, wb->body);
  wb->tier--;
  w->budget.restorations++;
}

void bk_world_budget_settle(bk_world* w, uint32_t index) {
  while (w->bodies[index].tier == BK_TIER_FROZEN || w->bodies[index].tier == BK_TIER_SIMPLIFIED)
    restore_resting(w, index);
}

void bk_world_budget_free(bk_world* w) {
  bk_free(w->budget.candidates);
  bk_free(w->budget.retired_bodies);
  bk_free(w->budget.retired_index);
}

// A stand-in fitted to the piece along its principal axes (the body frame):
// a sphere of its own volume when it is about as wide every way (one contact
// point on the ground, not a box's four), else a box of its extents, so that
// a flat shard still lies flat. The box is centred on the centre of mass,
// which is off the extents' middle by a small part of the piece's size.
static bk_shape_id make_simple_shape(bk_world* w, const bk_cluster_info* info) {
  const bk_mesh_tree* tree = bk_runtime_breakable_tree(w->runtime, info->breakable);
  bk_transform to_body = bk_transform_inverse(info->principal);
  bk_vec3 lo = bk_v3(INFINITY, INFINITY, INFINITY), hi = bk_v3(-INFINITY, -INFINITY, -INFINITY);
  for (uint32_t n = 0; n < info->node_count; ++n) {
    const bk_mesh* mesh = &tree->nodes[info->nodes[n]].mesh;
    for (uint32_t i = 0; i < mesh->position_count; ++i) {
      bk_vec3 p = bk_transform_point(to_body, mesh->positions[i]);
      lo = bk_v3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
      hi = bk_v3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
    }
  }
  bk_vec3 half = bk_v3_scale(bk_v3_sub(hi, lo), 0.5);
  double smallest = fmin(half.x, fmin(half.y, half.z)), largest = fmax(half.x, fmax(half.y, half.z));
  if (!(smallest > 0.0) || !isfinite(largest)) return (bk_shape_id){0, 0};
  if (smallest >= 0.6 * largest)
    return bk_physics_create_sphere(w->physics, cbrt(3.0 * info->volume / (4.0 * 3.14159265358979323846)));
  return bk_physics_create_box(w->physics, half);
}

// One tier down. A piece too flat for a stand-in keeps its own shape at the
// simplified tier, so that the tiers after it still come in order.
static void demote(bk_world* w, uint32_t index, const bk_cluster_info* info) {
  world_body* wb = &w->bodies[index];
  switch (wb->tier) {
  case BK_TIER_FULL:
    bk_physics_body_set_debris(w->physics, wb->body, true);
    break;
  case BK_TIER_DEBRIS:
    if (bk_shape_is_null(wb->simple)) wb->simple = make_simple_shape(w, info);
    if (!bk_shape_is_null(wb->simple)) bk_physics_body_set_shape(w->physics, wb->body, wb->simple);
    break;
  case BK_TIER_SIMPLIFIED:
    bk_physics_body_set_pinned(w->physics, wb->body, true);
    break;
  default:
    return;
  }
  wb->tier++;
  w->budget.demotions++;
}

// One tier back up.
static void restore(bk_world* w, uint32_t index) {
  world_body* wb = &w->bodies[index];
  switch (wb->tier) {
  case BK_TIER_FROZEN:
    bk_physics_body_set_pinned(w->physics, wb->body, false);
    break;
  case BK_TIER_SIMPLIFIED:
    bk_physics_body_set_shape(w->physics, wb->body, wb->shape);
    bk_physics_destroy_shape(w->physics, wb->simple);
    wb->simple = (bk_shape_id){0, 0};
    break;
  case BK_TIER_DEBRIS:
    bk_physics_body_set_debris(w->physics, wb->body, false);
    break;
  default:
    return;
  }
  wb->tier--;
  w->budget.restorations++;
}

void bk_world_budget_set_tier(bk_world* w, uint32_t index, bk_budget_tier tier) {
  world_body* wb = &w->bodies[index];
  bk_cluster_info info = {0};
  if (tier >= BK_TIER_RETIRED || !bk_runtime_cluster(w->runtime, wb->cluster, &info)) return;
  while (wb->tier > tier)
    restore(w, index);
  while (wb->tier < tier) {
    uint32_t was = wb->tier;
    demote(w, index, &info);
    if (wb->tier == was) break;
  }
}

bk_retired_body bk_world_retired_record(const bk_world* w, uint32_t index, const bk_cluster_info* info) {
  bk_body_id body = w->bodies[index].body;
  return (bk_retired_body){.breakable = info->breakable,
                           .node = info->nodes[0],
                           .tree_to_world = bk_world_tree_to_world(w, index),
                           .linear_velocity = bk_physics_body_linear_velocity(w->physics, body),
                           .angular_velocity = bk_physics_body_angular_velocity(w->physics, body),
                           .center = bk_physics_body_transform(w->physics, body).position,
                           .mass = info->mass};
}

// The last tier: the body leaves, and what it was is kept for the renderer
// to fade out. Its mass is accounted for as retire_volume's is.
static void retire(bk_world* w, uint32_t index, const bk_cluster_info* info) {
  world_budget* b = &w->budget;
  world_body* wb = &w->bodies[index];
  if (b->retired_count == b->retired_capacity) {
    b->retired_capacity = bk_grow_capacity(b->retired_capacity, b->retired_count + 1);
    b->retired_bodies = bk_realloc(b->retired_bodies, sizeof(bk_retired_body) * b->retired_capacity);
    b->retired_index = bk_realloc(b->retired_index, sizeof(uint32_t) * b->retired_capacity);
  }
  b->retired_index[b->retired_count] = index;
  b->retired_bodies[b->retired_count++] = bk_world_retired_record(w, index, info);
  w->retired_mass += info->mass;
  w->fragments_retired += info->leaf_count;
  b->retired++;
  b->demotions++;
  bk_runtime_remove_cluster(w->runtime, wb->cluster);
  bk_runtime_clear_events(w->runtime); // the world removes the body itself
  // Its body leaves Bullet's world with the step's others (release_retired).
}

// The bodies retired this step leave Bullet's world in one call: one walk
// over its pairs for all of them, where one each cost a step that retired
// hundreds as many walks.
static void release_retired(bk_world* w) {
  world_budget* b = &w->budget;
  if (b->retired_count == 0) return;
  bk_body_id* gone = bk_alloc(sizeof(bk_body_id) * b->retired_count);
  for (uint32_t i = 0; i < b->retired_count; ++i) {
    world_body* wb = &w->bodies[b->retired_index[i]];
    gone[i] = wb->body;
    wb->body = (bk_body_id){0, 0};
  }
  bk_physics_destroy_bodies(w->physics, gone, b->retired_count);
  bk_free(gone);
  for (uint32_t i = 0; i < b->retired_count; ++i)
    bk_world_release_body(w, b->retired_index[i]);
}

static int by_importance(const void* a, const void* b) {
  const budget_candidate* x = a;
  const budget_candidate* y = b;
  if (x->importance != y->importance) return x->importance < y->importance ? -1 : 1;
  return (x->index > y->index) - (x->index < y->index); // the same order every run
}

// Follows every live dynamic body's calm (it makes "long settled") and lists
// the candidates with their importance; a body that stopped being one (it
// came near the focus, say) gets its full fidelity back at once.
static uint32_t gather(bk_world* w, bool engaged) {
  world_budget* b = &w->budget;
  uint64_t young_steps = (uint64_t)ceil(w->def.budget_fidelity_time / w->def.fixed_dt - 1e-9);
  if (b->candidate_capacity < w->live_count) {
    b->candidate_capacity = bk_grow_capacity(b->candidate_capacity, w->live_count);
    b->candidates = bk_realloc(b->candidates, sizeof(budget_candidate) * b->candidate_capacity);
  }
  uint32_t count = 0;
  for (uint32_t i = 0; i < w->live_count; ++i) {
    uint32_t index = w->live[i];
    world_body* wb = &w->bodies[index];
    if (wb->area) continue; // merged into static collision (world_settle.c): it costs nothing
    if (bk_physics_body_mass(w->physics, wb->body) == 0.0) continue; // static
    bk_vec3 v = bk_physics_body_linear_velocity(w->physics, wb->body);
    bk_vec3 spin = bk_physics_body_angular_velocity(w->physics, wb->body);
    bk_cluster_info info = {0};
    if (!bk_runtime_cluster(w->runtime, wb->cluster, &info)) continue;
    // Pinned, it would hold up what falls on it, and count as ground for
    // the structure's stress: a moving body landing on it sets it free.
    if (wb->tier == BK_TIER_FROZEN && wb->shaken == w->step_count) {
      restore(w, index);
      wb->calm_steps = 0;
    }
    double size = cbrt(info.volume);
    double speed = bk_v3_length(v) + 0.5 * size * bk_v3_length(spin);
    wb->calm_steps = speed < calm_speed ? wb->calm_steps + 1 : 0;
    // Its pieces came loose when its bonds broke, not when the split budget
    // lets them go: their first second counts from then (build_body).
    if (!info.split_pending)
      wb->split_waiting = false;
    else if (!wb->split_waiting)
      wb->split_waiting = true, wb->split_since = w->step_count;
    if (!engaged || info.split_pending) continue; // a body about to split keeps its tier meanwhile
    bk_vec3 center = bk_physics_body_transform(w->physics, wb->body).position;
    if (!bk_world_budget_candidate(w, &info, center)) {
      while (wb->tier > BK_TIER_FULL)
        restore(w, index);
      continue;
    }
    uint64_t age = w->step_count - wb->born;
    double distance =
        b->has_focus ? fmax(bk_v3_length(bk_v3_sub(center, b->focus)), near_distance) : near_distance;
    double settled = wb->calm_steps * w->def.fixed_dt;
    double importance = size / distance * (1.0 + speed / seen_speed) / (1.0 + settled);
    b->candidates[count++] = (budget_candidate){
        .index = index,
        .importance = isfinite(importance) ? importance : 0.0,
        .tier = wb->tier,
        .settled = wb->calm_steps >= freeze_calm_steps || !bk_physics_body_awake(w->physics, wb->body),
        .one_node = info.node_count == 1,
        .young = age < young_steps && keeps_fidelity(w, &info, center),
        .held = wb->piled == w->step_count || w->step_count - wb->made < contacts_known_steps,
        .asleep = !bk_physics_body_awake(w->physics, wb->body)};
  }
  return count;
}

static void restore_all(bk_world* w) {
  for (uint32_t i = 0; i < w->live_count; ++i)
    while (w->bodies[w->live[i]].tier > BK_TIER_FULL)
      restore(w, w->live[i]);
}

// Whether the candidate may go down from its tier to the next.
// A young piece keeps what the player sees of it: it becomes debris only
// while it flies apart (debris in a pile falls through the pile), keeps its
// own shape (a stand-in lands and rolls otherwise), and never retires.
static bool may_demote(const budget_candidate* c, uint32_t tier) {
  if (c->young && (tier == BK_TIER_RETIRED || tier == BK_TIER_SIMPLIFIED ||
                   (tier == BK_TIER_DEBRIS && c->held) || (tier == BK_TIER_FROZEN && !c->asleep)))
    return false;
  if (tier == BK_TIER_FROZEN) return c->tier == BK_TIER_SIMPLIFIED && c->settled;
  // Only a piece still moving retires: a frozen one costs next to nothing,
  // and in a burst of debris the moving ones are the cost.
  if (tier == BK_TIER_RETIRED) return c->tier == BK_TIER_SIMPLIFIED && c->one_node;
  return c->tier == tier - 1;
}

// Whether the candidate may come back up from its tier. Debris lying still
// stays debris: at rest it looks the same either way, and pieces that fell
// into each other as debris and came to rest there would be woken and
// pushed apart, for seconds in a heap. It comes back once it moves again.
static bool may_restore(const budget_candidate* c, uint32_t tier) {
  return c->tier == tier && (tier != BK_TIER_DEBRIS || !c->settled);
}

// Tiers 1 to 3 reach the least important (level - k + 1) of the candidates:
// pieces are demoted from the least important up, and restored from the
// most important down. Retiring cannot be undone, so it is not a share:
// while everything else is reached and a step still goes over, as many
// moving pieces retire as carry the excess, at what an awake body costs on
// average.
static void apply_level(bk_world* w, uint32_t count, uint32_t awake) {
  world_budget* b = &w->budget;
  budget_candidate* c = b->candidates;
  qsort(c, count, sizeof *c, by_importance);
  // Over budget_fidelity_factor times the budget, the least important young
  // pieces give up their first second.
  uint32_t young = 0;
  for (uint32_t i = 0; i < count; ++i)
    young += c[i].young;
  uint32_t released = (uint32_t)ceil(b->young_share * young - 1e-9);
  for (uint32_t i = 0; i < count && released > 0; ++i)
    if (c[i].young) c[i].young = false, released--;
  for (uint32_t tier = BK_TIER_DEBRIS; tier <= BK_TIER_RETIRED; ++tier) {
    uint32_t target = 0, reached = 0;
    if (tier == BK_TIER_RETIRED) {
      bool patient = b->level > 3.0 && (b->top_steps >= retire_patience_steps ||
                                        b->cost_ms >= retire_at_once * w->def.physics_budget_ms);
      double excess = patient ? 1.0 - w->def.physics_budget_ms / b->cost_ms : 0.0;
      target = excess > 0.0 ? (uint32_t)ceil(excess * awake) : 0;
    } else {
      double share = fmin(fmax(b->level - (tier - 1), 0.0), 1.0);
      target = (uint32_t)ceil(share * count - 1e-9);
      for (uint32_t i = 0; i < count; ++i)
        reached += c[i].tier >= tier;
    }
    for (uint32_t i = 0; i < count && reached < target; ++i) {
      if (!may_demote(&c[i], tier)) continue;
      bk_cluster_info info = {0};
      bk_runtime_cluster(w->runtime, w->bodies[c[i].index].cluster, &info);
      if (tier == BK_TIER_RETIRED) {
        retire(w, c[i].index, &info);
        c[i].tier = BK_TIER_RETIRED;
      } else {
        demote(w, c[i].index, &info);
        c[i].tier = w->bodies[c[i].index].tier;
      }
      reached++;
    }
    for (uint32_t i = count; tier != BK_TIER_RETIRED && i-- > 0 && reached > target;) {
      if (!may_restore(&c[i], tier)) continue;
      if (c[i].settled)
        restore_resting(w, c[i].index);
      else
        restore(w, c[i].index);
      c[i].tier = w->bodies[c[i].index].tier;
      reached--;
    }
  }
}

static world_body* loose_body(bk_world* w, bk_body_id body) {
  uint64_t user = bk_physics_body_user_data(w->physics, body);
  if (!(user & BK_USER_CLUSTER)) return NULL;
  uint32_t index = (uint32_t)user;
  if (index >= w->body_capacity || !w->bodies[index].alive || !bk_body_equal(w->bodies[index].body, body))
    return NULL;
  if (bk_physics_body_mass(w->physics, body) == 0.0) return NULL;
  return &w->bodies[index];
}

// Marks the loose pieces that pressed on each other in the last step at
// less than pile_speed apart: a pile (a heap, bricks jammed in a wall), not
// a burst flying apart.
static void mark_piled(bk_world* w) {
  for (uint32_t i = 0; i < w->contact_count; ++i) {
    const bk_contact* c = &w->contacts[i];
    world_body* a = loose_body(w, c->a);
    world_body* b = loose_body(w, c->b);
    if (!a || !b) continue;
    bk_vec3 relative = bk_v3_sub(bk_physics_body_linear_velocity(w->physics, c->a),
                                 bk_physics_body_linear_velocity(w->physics, c->b));
    if (bk_v3_length(relative) >= pile_speed) continue;
    a->piled = w->step_count;
    b->piled = w->step_count;
  }
}

// A frozen piece is pinned (of no mass to Bullet), so it would hold up
// anything: marks those that a dynamic body moving faster than calm_speed
// pressed on in the last step, and those pressed harder than press_weights
// times their own weight (a tower settling slowly onto the rubble at its
// foot, which must push the rubble aside, not stand on it as on rock).
static void mark_shaken(bk_world* w) {
  double weight_impulse = bk_v3_length(w->def.gravity) * w->def.fixed_dt; // per kg, one step
  for (int pass = 0; pass < 2; ++pass) {
    for (uint32_t i = 0; i < w->contact_count; ++i) {
      const bk_contact* c = &w->contacts[i];
      for (int side = 0; side < 2; ++side) {
        bk_body_id pinned = side ? c->b : c->a, other = side ? c->a : c->b;
        uint64_t user = bk_physics_body_user_data(w->physics, pinned);
        uint32_t index = (uint32_t)user;
        if (!(user & BK_USER_CLUSTER) || index >= w->body_capacity || !w->bodies[index].alive ||
            w->bodies[index].tier != BK_TIER_FROZEN || !bk_body_equal(w->bodies[index].body, pinned))
          continue;
        world_body* wb = &w->bodies[index];
        if (pass == 0) {
          wb->pressed = 0.0;
          continue;
        }
        if (bk_physics_body_mass(w->physics, other) == 0.0 || bk_physics_body_pinned(w->physics, other))
          continue;
        wb->pressed += c->impulse;
        double own = bk_physics_body_mass(w->physics, pinned) * weight_impulse;
        if (bk_v3_length(bk_physics_body_linear_velocity(w->physics, other)) >= calm_speed ||
            wb->pressed > press_weights * own)
          wb->shaken = w->step_count;
      }
    }
  }
}

void bk_world_budget_step(bk_world* w) {
  world_budget* b = &w->budget;
  b->retired_count = 0;
  double budget = w->def.physics_budget_ms;
  if (!(budget > 0.0)) {
    if (b->engaged) restore_all(w);
    *b = (world_budget){.has_focus = b->has_focus,
                        .focus = b->focus,
                        .retired = b->retired,
                        .demotions = b->demotions,
                        .restorations = b->restorations,
                        .candidates = b->candidates,
                        .candidate_capacity = b->candidate_capacity,
                        .retired_bodies = b->retired_bodies,
                        .retired_index = b->retired_index,
                        .retired_capacity = b->retired_capacity};
    return;
  }
  mark_piled(w);
  mark_shaken(w);
  bk_physics_stats stats = bk_physics_get_stats(w->physics);
  double cost = w->def.physics_budget_measured ? w->physics_ms : estimate_ms(&stats);
  b->cost_ms = cost;
  b->smoothed_ms += (cost - b->smoothed_ms) * smoothing;
  if (cost > budget)
    b->level = fmin(4.0, b->level + fmin(1.0, cost / budget - 1.0));
  else if (b->smoothed_ms < relax_fraction * budget)
    b->level = fmax(0.0, b->level - relax_per_step);
  b->top_steps = b->level > 3.0 ? b->top_steps + 1 : 0;
  // The bound on what keeping young pieces may cost: the share of them that
  // give it up rises with the excess (a quarter of them for a step at 1.5
  // times the bound), and falls by the whole over a second once a step costs
  // less than the bound again.
  double bound = w->def.budget_fidelity_factor * budget;
  if (bound > 0.0 && cost > bound)
    b->young_share = fmin(1.0, b->young_share + 0.5 * fmin(1.0, cost / bound - 1.0));
  else
    b->young_share = fmax(0.0, b->young_share - relax_per_step);
  bool engaged = b->engaged || b->level > 0.0;
  uint32_t count = gather(w, engaged);
  if (!engaged) return;
  apply_level(w, count, stats.awake_bodies);
  release_retired(w);
  // Nothing below full fidelity and nothing to reach: the next steps cost
  // only the calm count until the budget is exceeded again.
  b->engaged = b->level > 0.0;
  for (uint32_t i = 0; i < w->live_count && !b->engaged; ++i)
    b->engaged = w->bodies[w->live[i]].alive && w->bodies[w->live[i]].tier != BK_TIER_FULL;
}
