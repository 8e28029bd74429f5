// The world's state hash (bk_world_state_hash): the runtime's, then every
// breakable body in cluster order with its transform and velocities rounded
// to BK_WORLD_HASH_PRECISION (so two runs that agree to that precision hash
// alike, whatever their last bits), and the projectiles in flight.
#include <string.h>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include "world_internal.h"

typedef struct hash_buffer {
  int64_t* values;
  size_t count, capacity;
} hash_buffer;

static void put(hash_buffer* b, int64_t v) {
  if (b->count == b->capacity) {
    b->capacity = b->capacity ? 2 * b->capacity : 1024;
    b->values = bk_realloc(b->values, sizeof(int64_t) * b->capacity);
  }
  b->values[b->count++] = v;
}

// A value in units of the precision, clamped (a lost body's NaN or huge
// coordinates hash as a fixed value, not as undefined conversions).
static void put_rounded(hash_buffer* b, double v) {
  double units = nearbyint(v / BK_WORLD_HASH_PRECISION);
  put(b, units != units   ? INT64_MIN
         : units >= 9e18  ? INT64_MAX
         : units <= -9e18 ? INT64_MIN + 1
                          : (int64_t)units);
}

static void put_vec3(hash_buffer* b, bk_vec3 v) {
  put_rounded(b, v.x);
  put_rounded(b, v.y);
  put_rounded(b, v.z);
}

uint64_t bk_world_state_hash(const bk_world* w) {
  hash_buffer b = {0};
  put(&b, (int64_t)bk_runtime_state_hash(w->runtime));
  put(&b, (int64_t)w->step_count);
  for (uint32_t i = 0; i < w->body_capacity; ++i) {
    const world_body* body = &w->bodies[i];
    if (!body->alive) continue;
    put(&b, body->cluster.index);
    put(&b, body->cluster.generation);
    put(&b, body->tier);
    bk_transform t = bk_physics_body_transform(w->physics, body->body);
    // q and -q are one rotation: hashed with w >= 0.
    bk_quat q = t.rotation;
    if (q.w < 0.0) q = (bk_quat){-q.x, -q.y, -q.z, -q.w};
    put_vec3(&b, t.position);
    put_vec3(&b, bk_v3(q.x, q.y, q.z));
    put_rounded(&b, q.w);
    put_vec3(&b, bk_physics_body_linear_velocity(w->physics, body->body));
    put_vec3(&b, bk_physics_body_angular_velocity(w->physics, body->body));
  }
  put(&b, w->projectile_count);
  for (uint32_t i = 0; i < w->projectile_count; ++i)
    put_vec3(&b, bk_physics_body_transform(w->physics, w->projectiles[i]).position);
  // Little endian on every platform this builds for; the values are
  // integers, so the bytes are the same wherever the doubles were.
  uint64_t hash = XXH3_64bits(b.values, sizeof(int64_t) * b.count);
  bk_free(b.values);
  return hash;
}
