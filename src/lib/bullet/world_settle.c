// Settled debris costs nothing: pieces at rest leave Bullet's world (their
// bodies parked, their state kept) and one static compound per cell of the
// world (bk_world_def.settle_cell) stands in for them, made of their own
// hulls where they lie. A settled heap was still a collision object per
// piece, and every pair of them was walked each step (16 walls of 1,024
// pieces at rest: 4,300 bodies, 80,000 pairs, 1.35 ms a step of physics
// with everything asleep); a compound per cell is a few objects.
//
// Merging is done in batches (every batch_steps): the pieces asleep or
// frozen then, loose (not anchored: a static cluster already costs what the
// ground does, and the stress solve needs it as it is), of any size, not
// about to split. Their clusters stay alive in the runtime, and their
// bodies keep where they are (parked, not moved), so views, splits, stress
// and damage see them as before; a contact on the compound is mapped to the
// cluster of the child it touched. With the physics budget on, merging
// waits for the budget's level to fall under 1: during a burst, pieces come
// to rest and are woken again by what flies around them, and woken cells
// made the budget retire a third more pieces.
//
// A cell wakes as a whole, its pieces bodies again at rest where they were:
// when a body moving faster than settle_wake_speed comes within watch_margin
// of one of its pieces (a shot, a falling piece, a support moving away),
// when a body one of them rests on is removed, when a projectile will reach
// its box within two steps, and when one of its pieces is released (it
// split or retired). The whole cell rather than the pieces near the touch:
// merged pieces are static, and those left merged would hang where woken
// ones moved away below them, or be pushed into by them. A cell is a few
// metres. The pieces wake awake (Bullet's active state), so that they fall
// if what held them went; they sleep again after half a second at rest.
// (Woken calm, as a touch wakes a frozen body, their islands went back to
// sleep at once, some pieces frozen under a heavy one and others not, and
// the showcase's settled heap kept 15 bodies rocking, 1 ms a step.)
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "world_internal.h"

// A batch every quarter of a second, of at most batch_pieces pieces: a
// piece costs a few microseconds to park (its pairs leave Bullet's pair
// cache one by one) and to add to its compound, plus a walk over all pairs
// a batch, so a batch stays within a few ms (unbounded, 1,600 pieces
// settling at once made one of 20 ms), and a heap of 4,000 is merged
// within 2 s. Cells that gain pieces are extended, not made again.
static const uint32_t batch_steps = 15;
static const uint32_t batch_pieces = 512;
static const uint32_t min_members = 2; // one piece gains nothing from a compound of one
// m: a body this near a piece of the compound is noticed. Boxes of moving
// bodies already cover their next substep; a wider margin paired the
// compound with every body moving near it (the narrowphase paid for each).
static const double watch_margin = 0.1;
static const double look_ahead_steps = 2; // a projectile is looked for this far ahead

static double cpu_ms(void) {
  struct timespec t = {0};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static void reserve(void** array, uint32_t* capacity, uint32_t need, size_t size) {
  if (need <= *capacity) return;
  *capacity = bk_grow_capacity(*capacity, need);
  *array = bk_realloc(*array, size * *capacity);
}

double bk_world_settle_cell(const bk_world* w) { return w->def.settle_cell; }

// The areas' pieces become bodies again, area by area and each in
// ascending order (Bullet's results depend on the order bodies enter its
// world). The compounds go first, in one walk over Bullet's pairs (one
// each cost a walk over tens of thousands while debris flew), and quietly:
// what rested on them now rests on the pieces.
static void wake_areas(bk_world* w, const uint32_t* list, uint32_t n) {
  world_settle* s = &w->settle;
  if (n == 0) return;
  uint32_t members = 0;
  for (uint32_t i = 0; i < n; ++i)
    members += s->areas[list[i]].member_count;
  reserve((void**)&s->ids, &s->id_capacity, members > n ? members : n, sizeof(bk_body_id));
  for (uint32_t i = 0; i < n; ++i)
    s->ids[i] = s->areas[list[i]].body;
  bk_physics_destroy_bodies_quietly(w->physics, s->ids, n);
  uint32_t count = 0;
  for (uint32_t i = 0; i < n; ++i) {
    settle_area* area = &s->areas[list[i]];
    if (!bk_shape_is_null(area->compound)) bk_physics_destroy_shape(w->physics, area->compound);
    for (uint32_t m = 0; m < area->member_count; ++m) {
      world_body* wb = &w->bodies[area->members[m]];
      s->ids[count++] = wb->body;
      wb->area = 0;
      wb->calm_steps = 0;
    }
    s->merged -= area->member_count;
    s->live_areas--;
    s->wakes++;
    area->member_count = 0;
    area->child_count = 0;
    area->body = (bk_body_id){0, 0};
    area->compound = (bk_shape_id){0, 0};
    area->used = false;
  }
  bk_physics_unpark_bodies(w->physics, s->ids, count, true);
}

void bk_world_settle_forget(bk_world* w, uint32_t index) {
  uint32_t area = w->bodies[index].area - 1;
  if (w->bodies[index].area) wake_areas(w, &area, 1);
}

bool bk_world_settle_cluster(const bk_world* w, bk_body_id body, int32_t child, bk_cluster_id* out) {
  uint64_t user = bk_physics_body_user_data(w->physics, body);
  if (!(user & BK_USER_AREA) || child < 0) return false;
  uint32_t a = (uint32_t)user;
  if (a >= w->settle.area_count) return false;
  const settle_area* area = &w->settle.areas[a];
  if (!area->used || !bk_body_equal(area->body, body) || (uint32_t)child >= area->child_count) return false;
  const world_body* wb = &w->bodies[area->child_member[child]];
  if (!wb->alive || wb->area != a + 1) return false;
  *out = wb->cluster;
  return true;
}

static bool boxes_overlap(bk_vec3 lo, bk_vec3 hi, bk_vec3 lo2, bk_vec3 hi2) {
  return lo.x <= hi2.x && lo2.x <= hi.x && lo.y <= hi2.y && lo2.y <= hi.y && lo.z <= hi2.z && lo2.z <= hi.z;
}

void bk_world_settle_before_physics(bk_world* w) {
  world_settle* s = &w->settle;
  if (s->live_areas == 0) return;
  reserve((void**)&s->wake, &s->wake_capacity, s->area_count, sizeof(uint32_t));
  uint32_t* wake = s->wake;
  uint32_t n = 0;
  for (uint32_t a = 0; a < s->area_count; ++a) {
    const settle_area* area = &s->areas[a];
    if (!area->used) continue;
    bool woken = bk_physics_body_take_disturbed(w->physics, area->body) != 0;
    // A shot is faster than the margin can see coming: where it will be in
    // the next steps wakes the cells it reaches before it reaches them.
    for (uint32_t p = 0; p < w->projectile_count && !woken; ++p) {
      bk_vec3 from = bk_physics_body_transform(w->physics, w->projectiles[p]).position;
      bk_vec3 v = bk_physics_body_linear_velocity(w->physics, w->projectiles[p]);
      bk_vec3 to = bk_v3_add(from, bk_v3_scale(v, look_ahead_steps * w->def.fixed_dt));
      double r = w->projectile_radius[p] + watch_margin;
      bk_vec3 lo = bk_v3(fmin(from.x, to.x) - r, fmin(from.y, to.y) - r, fmin(from.z, to.z) - r);
      bk_vec3 hi = bk_v3(fmax(from.x, to.x) + r, fmax(from.y, to.y) + r, fmax(from.z, to.z) + r);
      woken = boxes_overlap(lo, hi, area->lo, area->hi);
    }
    if (woken) wake[n++] = a;
  }
  wake_areas(w, wake, n);
}

// A candidate: a body index and its cell, sorted by cell then index.
typedef struct settle_candidate {
  int64_t cell[3];
  uint32_t index;
} settle_candidate;

static int by_cell(const void* x, const void* y) {
  const settle_candidate* a = x;
  const settle_candidate* b = y;
  for (int k = 0; k < 3; ++k)
    if (a->cell[k] != b->cell[k]) return a->cell[k] < b->cell[k] ? -1 : 1;
  return (a->index > b->index) - (a->index < b->index);
}

static bool same_cell(const int64_t* a, const int64_t* b) {
  return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

// A loose piece at rest, not merged, not about to split.
static bool mergeable(const bk_world* w, uint32_t index) {
  const world_body* wb = &w->bodies[index];
  if (!wb->alive || wb->area || bk_body_is_null(wb->body) || wb->collider_count == 0) return false;
  if (bk_physics_body_mass(w->physics, wb->body) == 0.0 || bk_physics_body_awake(w->physics, wb->body))
    return false;
  bk_cluster_info info = {0};
  return bk_runtime_cluster(w->runtime, wb->cluster, &info) && !info.is_static && !info.split_pending;
}

static uint32_t find_area(bk_world* w, const int64_t* cell) {
  world_settle* s = &w->settle;
  uint32_t free_slot = UINT32_MAX;
  for (uint32_t a = 0; a < s->area_count; ++a) {
    if (s->areas[a].used && same_cell(s->areas[a].cell, cell)) return a;
    if (!s->areas[a].used && free_slot == UINT32_MAX) free_slot = a;
  }
  if (free_slot != UINT32_MAX) return free_slot;
  reserve((void**)&s->areas, &s->area_capacity, s->area_count + 1, sizeof(settle_area));
  memset(&s->areas[s->area_count], 0, sizeof(settle_area));
  return s->area_count++;
}

static void add_child(settle_area* area, bk_physics* physics, bk_shape_id hull, bk_transform at,
                      uint32_t index) {
  reserve((void**)&area->child_member, &area->child_capacity, area->child_count + 1, sizeof(uint32_t));
  bk_physics_compound_add(physics, area->compound, hull, at);
  area->child_member[area->child_count++] = index;
}

// Adds the pieces c[0..n) to their area's compound as they lie, making
// the compound and its static body first if the area has none. Bullet
// takes children added to a compound in use (its pairs' algorithms follow
// the compound's revision), so a batch only adds what is new: making the
// compound again each time cost a third of a batch while a heap grew.
static void extend_area(bk_world* w, uint32_t a, const settle_candidate* c, uint32_t n) {
  settle_area* area = &w->settle.areas[a];
  bool made = !bk_body_is_null(area->body);
  if (!made) {
    area->compound = bk_physics_create_compound(w->physics, n);
    area->child_count = 0;
    area->lo = bk_v3(INFINITY, INFINITY, INFINITY);
    area->hi = bk_v3(-INFINITY, -INFINITY, -INFINITY);
  }
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t index = c[i].index;
    const world_body* wb = &w->bodies[index];
    if (bk_shape_is_null(wb->compound)) {
      // One hull in the body frame (every loose fragment).
      add_child(area, w->physics, wb->shape, bk_physics_body_transform(w->physics, wb->body), index);
    } else {
      // The cluster's colliders, hulls in the tree frame.
      const world_breakable* br = &w->breakables[wb->breakable];
      bk_transform tree_to_world = bk_world_tree_to_world(w, index);
      for (uint32_t k = 0; k < wb->collider_count; ++k)
        add_child(area, w->physics, br->node_hull[wb->colliders[k]], tree_to_world, index);
    }
    bk_vec3 lo = {0}, hi = {0};
    bk_physics_body_bounds(w->physics, wb->body, &lo, &hi);
    area->lo = bk_v3(fmin(area->lo.x, lo.x), fmin(area->lo.y, lo.y), fmin(area->lo.z, lo.z));
    area->hi = bk_v3(fmax(area->hi.x, hi.x), fmax(area->hi.y, hi.y), fmax(area->hi.z, hi.z));
  }
  if (!made) {
    bk_cluster_info info = {0};
    bk_runtime_cluster(w->runtime, w->bodies[area->members[0]].cluster, &info);
    bk_material material = bk_runtime_material(w->runtime, info.breakable);
    bk_body_def def = bk_default_body_def();
    def.shape = area->compound;
    def.friction = material.friction;
    def.restitution = material.restitution;
    def.user_data = BK_USER_AREA | a;
    bk_error err = {0};
    area->body = bk_physics_create_body(w->physics, &def, &err);
  }
  // Its box again, grown by the margin.
  bk_physics_body_watch(w->physics, area->body, watch_margin, w->def.settle_wake_speed);
}

// Adds the run of candidates c[0..n) (one cell, ascending) to its area;
// false if the area would hold too few pieces. New members are appended to
// ids for parking.
static bool join_area(bk_world* w, const settle_candidate* c, uint32_t n, uint32_t* joined) {
  world_settle* s = &w->settle;
  uint32_t a = find_area(w, c[0].cell);
  settle_area* area = &s->areas[a];
  if (area->member_count + n < min_members) return false;
  uint32_t old = area->member_count, total = old + n;
  reserve((void**)&area->members, &area->member_capacity, total, sizeof(uint32_t));
  // Merge the two ascending lists from the back.
  uint32_t i = old, j = n, k = total;
  while (j > 0) {
    if (i > 0 && area->members[i - 1] > c[j - 1].index)
      area->members[--k] = area->members[--i];
    else
      area->members[--k] = c[--j].index;
  }
  area->member_count = total;
  if (!area->used) {
    memcpy(area->cell, c[0].cell, sizeof area->cell);
    area->used = true;
    s->live_areas++;
  }
  for (uint32_t m = 0; m < n; ++m) {
    bk_world_budget_settle(w, c[m].index);
    w->bodies[c[m].index].area = a + 1;
    s->ids[(*joined)++] = w->bodies[c[m].index].body;
  }
  s->merged += n;
  return true;
}

void bk_world_settle_step(bk_world* w) {
  world_settle* s = &w->settle;
  if (!(w->def.settle_cell > 0.0) || w->step_count % batch_steps != 0) return;
  // While the physics budget is cutting fidelity, pieces come to rest and
  // are woken again by the burst around them: merging waits for the level
  // to fall (a pile woken as a whole made the budget retire a third more).
  if (w->def.physics_budget_ms > 0.0 && w->budget.level >= 1.0) return;
  double start = cpu_ms();
  reserve(&s->candidates, &s->candidate_capacity, w->live_count + 1u, sizeof(settle_candidate));
  settle_candidate* c = s->candidates;
  uint32_t count = 0;
  for (uint32_t i = 0; i < w->live_count; ++i) {
    uint32_t index = w->live[i];
    if (count == batch_pieces) break; // the rest wait for the next batch
    if (!mergeable(w, index)) continue;
    bk_vec3 p = bk_physics_body_transform(w->physics, w->bodies[index].body).position;
    c[count].cell[0] = (int64_t)floor(p.x / w->def.settle_cell);
    c[count].cell[1] = (int64_t)floor(p.y / w->def.settle_cell);
    c[count].cell[2] = (int64_t)floor(p.z / w->def.settle_cell);
    c[count++].index = index;
  }
  if (count == 0) return;
  qsort(c, count, sizeof *c, by_cell);
  reserve((void**)&s->ids, &s->id_capacity, count, sizeof(bk_body_id));
  // The runs of candidates that join an area: [run_start, run_end).
  uint32_t joined = 0, changed_count = 0;
  uint32_t* runs = bk_alloc(sizeof(uint32_t) * 2u * (count + 1u));
  for (uint32_t run = 0; run < count;) {
    uint32_t end = run + 1;
    while (end < count && same_cell(c[end].cell, c[run].cell))
      end++;
    if (join_area(w, c + run, end - run, &joined)) {
      runs[2 * changed_count] = run;
      runs[2 * changed_count++ + 1] = end;
    }
    run = end;
  }
  // The new pieces leave Bullet's world in one walk over its pairs; then
  // their areas' compounds take them.
  bk_physics_park_bodies(w->physics, s->ids, joined);
  for (uint32_t i = 0; i < changed_count; ++i) {
    const settle_candidate* run = c + runs[2 * i];
    extend_area(w, w->bodies[run->index].area - 1, run, runs[2 * i + 1] - runs[2 * i]);
  }
  bk_free(runs);
  s->batch_ms = cpu_ms() - start;
}

void bk_world_settle_free(bk_world* w) {
  for (uint32_t a = 0; a < w->settle.area_count; ++a) {
    bk_free(w->settle.areas[a].members);
    bk_free(w->settle.areas[a].child_member);
  }
  bk_free(w->settle.areas);
  bk_free(w->settle.candidates);
  bk_free(w->settle.ids);
  bk_free(w->settle.wake);
  bk_free(w->aged);
}
