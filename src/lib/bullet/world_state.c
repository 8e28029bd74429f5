// Saving and loading a world (bk_world_save_state, bk_world_load_state): the
// runtime's state (bk_runtime_save_state) with what the world adds, every
// breakable body where it is and how it moves, its budget tier and ages,
// the projectiles in flight and the hits waiting for the hit budget.
//
// Layout: a fixed 32-byte header, then the payload.
//   header:  "BKWORLD\0" | u32 version | u32 0x01020304 | u64 payload size | u64 XXH3-64 of the payload
//   payload: u64 runtime state bytes | the runtime's state | u64 step_count | u32 flags (1 hits hold
//            splits, 2 hits held last) | u32 bodies, each { u32 cluster index, generation, tier
//            f64 transform[7], basis[9] (the rotation as the physics keeps it), linear[3], angular[3],
//            previous[7] | u64 made, born | u32 split_waiting u64 split_since | u32 calm_steps | u64 piled,
//            shaken } u32 projectiles, each { f64 transform[7], basis[9], linear[3], angular[3], radius, mass
//            | u64 expires } u32 hits, each { u32 cluster index, generation | f64 point[3], local[3],
//            impulse, closing_speed | u64 step }
// Little endian, doubles by their bits. Bullet's contact caches and solver
// warm start are not state the world owns: a loaded world's next steps
// differ from the saved run's by rounding.
#include <inttypes.h>
#include <string.h>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include "bk_bytes.h"
#include "world_internal.h"

#define WS_VERSION 1u
#define WS_HEADER 32u
#define WS_MARKER 0x01020304u
static const uint8_t ws_magic[8] = {'B', 'K', 'W', 'O', 'R', 'L', 'D', '\0'};

static void put_transform(bk_byte_writer* w, bk_transform t) {
  bk_put_vec3(w, t.position);
  bk_put_f64(w, t.rotation.x);
  bk_put_f64(w, t.rotation.y);
  bk_put_f64(w, t.rotation.z);
  bk_put_f64(w, t.rotation.w);
}

static void put_basis(bk_byte_writer* w, const bk_physics* physics, bk_body_id body) {
  double m[9] = {0};
  bk_physics_body_basis(physics, body, m);
  for (int k = 0; k < 9; ++k)
    bk_put_f64(w, m[k]);
}

// The state's reader, and whether a value read was out of its domain (a
// double not finite, a rotation not one).
typedef struct ws_reader {
  bk_byte_reader in;
  bool bad;
} ws_reader;

static uint32_t get_u32(ws_reader* r) { return bk_get_u32(&r->in); }
static uint64_t get_u64(ws_reader* r) { return bk_get_u64(&r->in); }

static double get_f64(ws_reader* r) {
  double d = bk_get_f64(&r->in);
  if (!isfinite(d)) r->bad = true;
  return d;
}

static bk_vec3 get_vec3(ws_reader* r) {
  double x = get_f64(r), y = get_f64(r);
  return bk_v3(x, y, get_f64(r));
}

static bk_transform get_transform(ws_reader* r) {
  bk_transform t = {get_vec3(r), {0, 0, 0, 1}};
  t.rotation.x = get_f64(r);
  t.rotation.y = get_f64(r);
  t.rotation.z = get_f64(r);
  t.rotation.w = get_f64(r);
  return t;
}

// A rotation matrix (rows of unit length, determinant 1, within float rounding).
static void get_basis(ws_reader* r, double m[9]) {
  for (int k = 0; k < 9; ++k)
    m[k] = get_f64(r);
  double det = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
               m[2] * (m[3] * m[7] - m[4] * m[6]);
  bool unit = true;
  for (int row = 0; row < 3; ++row)
    unit = unit && fabs(m[3 * row] * m[3 * row] + m[3 * row + 1] * m[3 * row + 1] +
                        m[3 * row + 2] * m[3 * row + 2] - 1.0) < 1e-4;
  if (!(fabs(det - 1.0) < 1e-4) || !unit) r->bad = true;
}

static size_t left(const ws_reader* r) { return bk_bytes_left(&r->in); }

// A rotation as Bullet keeps one: a unit quaternion (a hostile one is not).
static bool unit_rotation(bk_transform t) {
  bk_quat q = t.rotation;
  double length = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
  return fabs(length - 1.0) < 1e-6;
}

// ---------------------------------------------------------------- save

static bool put_state(const bk_world* w, bk_byte_writer* o, bk_error* err) {
  uint8_t header[WS_HEADER] = {0};
  bk_put_bytes(o, header, sizeof header);
  // The runtime's state straight into the buffer when it fits (its grown
  // trees are serialised once), else only measured.
  size_t size_at = o->size;
  bk_put_u64(o, 0); // its size, once known
  size_t room = o->out && o->size <= o->capacity ? o->capacity - o->size : 0;
  size_t runtime_size = room ? bk_runtime_save_state(w->runtime, o->out + o->size, room, NULL) : 0;
  if (!runtime_size) {
    runtime_size = bk_runtime_state_size(w->runtime);
    if (runtime_size == 0 || runtime_size <= room) // it fit, so the save failed for another reason
      return bk_runtime_save_state(w->runtime, o->out + o->size, room, err) == runtime_size && runtime_size;
  }
  if (size_at + 8 <= o->capacity) {
    bk_byte_writer at = {.out = o->out + size_at, .capacity = 8};
    bk_put_u64(&at, runtime_size);
  }
  o->size += runtime_size;
  bk_put_u64(o, w->step_count);
  bk_put_u32(o, (w->hits_hold_splits ? 1u : 0u) | (w->hits_held_last ? 2u : 0u));
  uint32_t bodies = 0;
  for (uint32_t i = 0; i < w->body_capacity; ++i)
    bodies += w->bodies[i].alive;
  bk_put_u32(o, bodies);
  for (uint32_t i = 0; i < w->body_capacity; ++i) {
    const world_body* b = &w->bodies[i];
    if (!b->alive) continue;
    bk_put_u32(o, b->cluster.index);
    bk_put_u32(o, b->cluster.generation);
    bk_put_u32(o, (uint32_t)b->tier);
    put_transform(o, bk_physics_body_transform(w->physics, b->body));
    put_basis(o, w->physics, b->body);
    bk_put_vec3(o, bk_physics_body_linear_velocity(w->physics, b->body));
    bk_put_vec3(o, bk_physics_body_angular_velocity(w->physics, b->body));
    put_transform(o, b->previous);
    bk_put_u64(o, b->made);
    bk_put_u64(o, b->born);
    bk_put_u32(o, b->split_waiting);
    bk_put_u64(o, b->split_since);
    bk_put_u32(o, b->calm_steps);
    bk_put_u64(o, b->piled);
    bk_put_u64(o, b->shaken);
  }
  bk_put_u32(o, w->projectile_count);
  for (uint32_t i = 0; i < w->projectile_count; ++i) {
    bk_body_id p = w->projectiles[i];
    put_transform(o, bk_physics_body_transform(w->physics, p));
    put_basis(o, w->physics, p);
    bk_put_vec3(o, bk_physics_body_linear_velocity(w->physics, p));
    bk_put_vec3(o, bk_physics_body_angular_velocity(w->physics, p));
    bk_put_f64(o, w->projectile_radius[i]);
    bk_put_f64(o, bk_physics_body_mass(w->physics, p));
    bk_put_u64(o, w->projectile_expires[i]);
  }
  bk_put_u32(o, w->hit_count);
  for (uint32_t i = 0; i < w->hit_count; ++i) {
    const world_hit* h = &w->hits[i];
    bk_put_u32(o, h->cluster.index);
    bk_put_u32(o, h->cluster.generation);
    bk_put_vec3(o, h->point);
    bk_put_vec3(o, h->local);
    bk_put_f64(o, h->impulse);
    bk_put_f64(o, h->closing_speed);
    bk_put_u64(o, h->step);
  }
  if (o->size > o->capacity) return true;
  bk_byte_writer h = {.out = o->out, .capacity = WS_HEADER};
  bk_put_bytes(&h, ws_magic, sizeof ws_magic);
  bk_put_u32(&h, WS_VERSION);
  bk_put_u32(&h, WS_MARKER);
  bk_put_u64(&h, o->size - WS_HEADER);
  bk_put_u64(&h, XXH3_64bits(o->out + WS_HEADER, o->size - WS_HEADER));
  return true;
}

size_t bk_world_state_size(const bk_world* w) {
  bk_byte_writer o = {0};
  return put_state(w, &o, NULL) ? o.size : 0;
}

size_t bk_world_save_state(const bk_world* w, void* out, size_t capacity, bk_error* err) {
  if (!out && capacity) return bk_error_set(err, "world state: out is NULL"), 0;
  bk_byte_writer o = {.out = out, .capacity = out ? capacity : 0};
  if (!put_state(w, &o, err)) return 0;
  if (o.size > o.capacity)
    return bk_error_set(err, "world state: buffer of %zu bytes is too small, the state needs %zu", capacity,
                        o.size),
           0;
  return o.size;
}

// ---------------------------------------------------------------- load

typedef struct ws_body {
  bk_cluster_id cluster;
  double basis[9];
  uint32_t tier, split_waiting, calm_steps;
  bk_transform transform, previous;
  bk_vec3 linear, angular;
  uint64_t made, born, split_since, piled, shaken;
} ws_body;

typedef struct ws_projectile {
  bk_transform transform;
  double basis[9];
  bk_vec3 linear, angular;
  double radius, mass;
  uint64_t expires;
} ws_projectile;

typedef struct ws_state {
  const uint8_t* runtime;
  size_t runtime_size;
  uint64_t step_count;
  uint32_t flags, body_count, projectile_count, hit_count;
  ws_body* bodies;
  ws_projectile* projectiles;
  world_hit* hits;
} ws_state;

static bool check_header(const uint8_t* data, size_t size, bk_error* err) {
  if (!data || size < WS_HEADER)
    return bk_error_set(err, "world state: truncated header (%zu bytes, needs %u)", data ? size : 0,
                        WS_HEADER);
  if (memcmp(data, ws_magic, sizeof ws_magic) != 0)
    return bk_error_set(err, "world state: not a saved world state (bad magic)");
  ws_reader r = {.in = {.data = data, .size = size, .pos = 8}};
  uint32_t version = get_u32(&r), marker = get_u32(&r);
  if (version != WS_VERSION && marker != 0x04030201u)
    return bk_error_set(err, "world state: version %" PRIu32 " is not supported (expected %u)", version,
                        WS_VERSION);
  if (marker != WS_MARKER)
    return bk_error_set(err, "world state: wrong byte order (marker 0x%08" PRIx32 ", expected 0x%08x)",
                        marker, WS_MARKER);
  uint64_t declared = get_u64(&r), checksum = get_u64(&r), actual = (uint64_t)(size - WS_HEADER);
  if (actual < declared)
    return bk_error_set(err, "world state: truncated: payload is %" PRIu64 " bytes, header says %" PRIu64,
                        actual, declared);
  if (actual > declared)
    return bk_error_set(err, "world state: size mismatch: payload is %" PRIu64 " bytes, header says %" PRIu64,
                        actual, declared);
  if (XXH3_64bits(data + WS_HEADER, (size_t)actual) != checksum)
    return bk_error_set(err, "world state: checksum mismatch (the state is corrupt)");
  return true;
}

static bool parse(ws_reader* r, ws_state* s, bk_error* err) {
  uint64_t runtime_size = get_u64(r);
  if (r->in.failed || runtime_size > left(r))
    return bk_error_set(err, "world state: corrupt: runtime state size");
  s->runtime = r->in.data + r->in.pos;
  s->runtime_size = (size_t)runtime_size;
  r->in.pos += (size_t)runtime_size;
  s->step_count = get_u64(r);
  s->flags = get_u32(r);
  s->body_count = get_u32(r);
  if (r->in.failed || s->flags > 3 || (uint64_t)s->body_count * 292u > left(r))
    return bk_error_set(err, "world state: corrupt: %" PRIu32 " bodies", s->body_count);
  s->bodies = bk_calloc(s->body_count + 1u, sizeof(ws_body));
  for (uint32_t i = 0; i < s->body_count; ++i) {
    ws_body* b = &s->bodies[i];
    b->cluster.index = get_u32(r);
    b->cluster.generation = get_u32(r);
    b->tier = get_u32(r);
    b->transform = get_transform(r);
    get_basis(r, b->basis);
    b->linear = get_vec3(r);
    b->angular = get_vec3(r);
    b->previous = get_transform(r);
    b->made = get_u64(r);
    b->born = get_u64(r);
    b->split_waiting = get_u32(r);
    b->split_since = get_u64(r);
    b->calm_steps = get_u32(r);
    b->piled = get_u64(r);
    b->shaken = get_u64(r);
    bool ascending = i == 0 || b->cluster.index > s->bodies[i - 1].cluster.index;
    if (!r->in.failed && !r->bad && !(unit_rotation(b->transform) && unit_rotation(b->previous)))
      r->bad = true;
    if (r->in.failed || r->bad || b->tier >= BK_TIER_RETIRED || b->split_waiting > 1 || !ascending)
      return bk_error_set(err, "world state: corrupt: body %" PRIu32 " (%s)", i,
                          r->in.failed ? "truncated"
                          : r->bad     ? "a value not finite or not a unit rotation"
                          : !ascending ? "clusters not ascending"
                                       : "bad tier or flag");
  }
  s->projectile_count = get_u32(r);
  if (r->in.failed || (uint64_t)s->projectile_count * 192u > left(r))
    return bk_error_set(err, "world state: corrupt: %" PRIu32 " projectiles", s->projectile_count);
  s->projectiles = bk_calloc(s->projectile_count + 1u, sizeof(ws_projectile));
  for (uint32_t i = 0; i < s->projectile_count; ++i) {
    ws_projectile* p = &s->projectiles[i];
    p->transform = get_transform(r);
    get_basis(r, p->basis);
    p->linear = get_vec3(r);
    p->angular = get_vec3(r);
    p->radius = get_f64(r);
    p->mass = get_f64(r);
    p->expires = get_u64(r);
    if (r->in.failed || r->bad || !unit_rotation(p->transform) || !(p->radius > 0.0) || !(p->mass > 0.0))
      return bk_error_set(err, "world state: corrupt: projectile %" PRIu32, i);
  }
  s->hit_count = get_u32(r);
  if (r->in.failed || (uint64_t)s->hit_count * 80u > left(r))
    return bk_error_set(err, "world state: corrupt: %" PRIu32 " hits", s->hit_count);
  s->hits = bk_calloc(s->hit_count + 1u, sizeof(world_hit));
  for (uint32_t i = 0; i < s->hit_count; ++i) {
    world_hit* h = &s->hits[i];
    h->cluster.index = get_u32(r);
    h->cluster.generation = get_u32(r);
    h->point = get_vec3(r);
    h->local = get_vec3(r);
    h->impulse = get_f64(r);
    h->closing_speed = get_f64(r);
    h->step = get_u64(r);
    if (r->in.failed || r->bad) return bk_error_set(err, "world state: corrupt: hit %" PRIu32, i);
  }
  if (r->in.pos != r->in.size)
    return bk_error_set(err, "world state: corrupt: %zu bytes after the state", r->in.size - r->in.pos);
  return true;
}

// The loaded runtime's clusters are exactly the bodies' (one each, in order).
static bool bodies_match(const bk_world* w, const ws_state* s, bk_error* err) {
  uint32_t n = bk_runtime_clusters(w->runtime, NULL, 0);
  if (n != s->body_count)
    return bk_error_set(err, "world state: corrupt: %" PRIu32 " bodies for %" PRIu32 " clusters",
                        s->body_count, n);
  for (uint32_t i = 0; i < s->body_count; ++i) {
    bk_cluster_info info = {0};
    if (!bk_runtime_cluster(w->runtime, s->bodies[i].cluster, &info))
      return bk_error_set(err, "world state: corrupt: body %" PRIu32 " has no cluster", i);
  }
  return true;
}

// Every body, projectile and grown node's hull goes; then the loaded ones come.
static bool install(bk_world* w, ws_state* s, bk_error* err) {
  for (uint32_t i = 0; i < w->body_capacity; ++i)
    bk_world_release_body(w, i);
  for (uint32_t i = 0; i < w->projectile_count; ++i) {
    bk_physics_destroy_body(w->physics, w->projectiles[i]);
    bk_physics_destroy_shape(w->physics, w->projectile_shape[i]);
  }
  w->projectile_count = 0;
  for (uint32_t k = 0; k < w->breakable_count; ++k) {
    world_breakable* wb = &w->breakables[k];
    if (bk_breakable_is_null(wb->id)) continue;
    // A grown tree's nodes past the caller's are the saved tree's now: their
    // hulls are made when a body first needs them, as after a refinement.
    for (uint32_t i = wb->source_nodes; i < wb->node_count; ++i) {
      if (!bk_shape_is_null(wb->node_hull[i])) bk_physics_destroy_shape(w->physics, wb->node_hull[i]);
      if (!bk_shape_is_null(wb->node_body_hull[i]))
        bk_physics_destroy_shape(w->physics, wb->node_body_hull[i]);
    }
    if (wb->node_count > wb->source_nodes) wb->node_count = wb->source_nodes;
    bk_world_prepare_hulls(w, k);
  }
  bool ok = true;
  for (uint32_t i = 0; i < s->body_count; ++i) {
    const ws_body* b = &s->bodies[i];
    bk_cluster_created created = {0};
    bk_runtime_cluster(w->runtime, b->cluster, &created.cluster);
    created.body = (bk_body_state){b->transform, b->linear, b->angular};
    if (!bk_world_make_body(w, &created, b->born, err)) {
      ok = false;
      continue;
    }
    world_body* wbody = &w->bodies[b->cluster.index];
    bk_physics_body_set_basis(w->physics, wbody->body, b->basis);
    if (!created.cluster.is_static)
      bk_physics_body_set_velocity(w->physics, wbody->body, b->linear, b->angular);
    bk_world_budget_set_tier(w, b->cluster.index, (bk_budget_tier)b->tier);
    wbody->previous = b->previous;
    wbody->made = b->made;
    wbody->born = b->born;
    wbody->split_waiting = b->split_waiting != 0;
    wbody->split_since = b->split_since;
    wbody->calm_steps = b->calm_steps;
    wbody->piled = b->piled;
    wbody->shaken = b->shaken;
  }
  for (uint32_t i = 0; i < s->projectile_count; ++i) {
    const ws_projectile* p = &s->projectiles[i];
    bk_projectile_def def = bk_default_projectile_def();
    def.position = p->transform.position;
    def.velocity = p->linear;
    def.radius = p->radius;
    def.mass = p->mass;
    bk_body_id body = bk_world_fire(w, &def, err);
    if (bk_body_is_null(body)) {
      ok = false;
      continue;
    }
    bk_physics_body_set_transform(w->physics, body, p->transform);
    bk_physics_body_set_basis(w->physics, body, p->basis);
    bk_physics_body_set_velocity(w->physics, body, p->linear, p->angular);
    w->projectile_expires[w->projectile_count - 1] = p->expires;
  }
  if (s->hit_count > w->hit_capacity) {
    w->hit_capacity = s->hit_count;
    w->hits = bk_realloc(w->hits, sizeof(world_hit) * w->hit_capacity);
  }
  if (s->hit_count) memcpy(w->hits, s->hits, sizeof(world_hit) * s->hit_count);
  w->hit_count = s->hit_count;
  w->step_count = s->step_count;
  w->hits_hold_splits = s->flags & 1;
  w->hits_held_last = (s->flags & 2) != 0;
  w->event_count = 0;
  w->events_of_last_step = 0;
  w->contact_count = 0;
  w->aged_count = 0;
  w->budget.retired_count = 0;
  w->live_dirty = true;
  bk_world_refresh_live(w);
  return ok;
}

bool bk_world_load_state(bk_world* w, const void* data, size_t size, bk_error* err) {
  if (!w) return bk_error_set(err, "world state: world is NULL");
  if (!check_header(data, size, err)) return false;
  ws_reader r = {.in = {.data = (const uint8_t*)data + WS_HEADER, .size = size - WS_HEADER}};
  ws_state s = {0};
  bool ok = parse(&r, &s, err);
  // The runtime as it is, should its loaded clusters not be the bodies' (a
  // hostile state): put back, the world is as it was.
  size_t backup_size = ok ? bk_runtime_state_size(w->runtime) : 0;
  uint8_t* backup = ok ? bk_alloc(backup_size + 1u) : NULL;
  if (ok) ok = bk_runtime_save_state(w->runtime, backup, backup_size, err) == backup_size;
  if (ok) ok = bk_runtime_load_state(w->runtime, s.runtime, s.runtime_size, err);
  if (ok && !bodies_match(w, &s, err)) {
    bk_runtime_load_state(w->runtime, backup, backup_size, NULL);
    ok = false;
  }
  bk_free(backup);
  if (ok) ok = install(w, &s, err);
  bk_free(s.bodies);
  bk_free(s.projectiles);
  bk_free(s.hits);
  return ok;
}
