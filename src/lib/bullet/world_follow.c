// Following another world (a watching client of a server-authoritative
// game): the leader's runtime journal (bk_runtime_journal) breaks the same
// bonds and makes the same clusters here, with no damage of its own, and the
// motion of the leader's moving bodies places them; the follower is never
// stepped. The motion encoding, per body: cluster index and generation
// (varints), position (3 x float32: 0.01 mm at 100 m), rotation as its
// smallest three components (3 x int16 over [-1/sqrt2, 1/sqrt2]) and which
// one was dropped (u8): about 22 bytes.
#include <math.h>
#include <string.h>

#include "world_internal.h"

#define SQRT2 1.4142135623730950488

bk_result bk_world_set_journal(bk_world* w, bool journal) {
  return w ? bk_runtime_set_journal(w->runtime, journal) : BK_ERROR_INVALID_ARGUMENT;
}

const void* bk_world_journal(const bk_world* w, size_t* size) {
  if (!w) {
    if (size) *size = 0;
    return NULL;
  }
  return bk_runtime_journal(w->runtime, size);
}

void bk_world_clear_journal(bk_world* w) {
  if (w) bk_runtime_clear_journal(w->runtime);
}

bool bk_world_apply_journal(bk_world* w, const void* data, size_t size, bk_error* err) {
  if (!w) return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "journal: world is NULL");
  w->event_count = w->events_of_last_step = 0; // the break events are this journal's
  bool ok = bk_runtime_apply_journal(w->runtime, data, size, err);
  // What the entries that applied did, as a step does it: refined trees'
  // hulls, break events, then bodies made and removed in order.
  bk_world_take_refined(w);
  bk_world_copy_breaks(w);
  bk_error body_err = {0};
  bk_world_apply_results(w, &body_err); // a body Bullet refuses stays without one, as in a step
  bk_world_refresh_live(w);
  w->events_of_last_step = w->event_count;
  return ok;
}

// ---------------------------------------------------------------- motion

enum { MOTION_BODY_MAX_BYTES = 5 + 5 + 12 + 7 };

static size_t put_varint(uint8_t* p, uint32_t v) {
  size_t n = 0;
  while (v >= 0x80) {
    p[n++] = (uint8_t)(v | 0x80);
    v >>= 7;
  }
  p[n++] = (uint8_t)v;
  return n;
}

static void put_f32(uint8_t* p, double v) {
  float f = (float)v;
  uint32_t bits = 0;
  memcpy(&bits, &f, sizeof bits);
  for (int i = 0; i < 4; ++i)
    p[i] = (uint8_t)(bits >> (8 * i));
}

static void put_i16(uint8_t* p, int v) {
  p[0] = (uint8_t)(v & 0xff);
  p[1] = (uint8_t)((v >> 8) & 0xff);
}

// A unit quaternion's smallest three components, scaled to int16, with
// the largest dropped (it is sqrt(1 - the others' squares), sign made +).
static size_t put_rotation(uint8_t* p, bk_quat q) {
  double c[4] = {q.x, q.y, q.z, q.w};
  double length = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] + c[3] * c[3]);
  if (!(length > 0.0) || !isfinite(length)) c[0] = c[1] = c[2] = 0.0, c[3] = length = 1.0;
  int largest = 0;
  for (int i = 1; i < 4; ++i)
    if (fabs(c[i]) > fabs(c[largest])) largest = i;
  double sign = c[largest] < 0.0 ? -1.0 : 1.0;
  p[0] = (uint8_t)largest;
  size_t n = 1;
  for (int i = 0; i < 4; ++i) {
    if (i == largest) continue;
    double v = sign * c[i] / length * SQRT2; // in [-1, 1]
    put_i16(p + n, (int)lrint(fmax(-1.0, fmin(1.0, v)) * 32767.0));
    n += 2;
  }
  return n;
}

// A body that moved less than this since it was last placed is not sent
// again: one at rest (asleep, frozen, settled) costs nothing. Anything that
// moves at all is sent: filtering more (0.05 mm) saved 2% of the bytes on a
// shot wall and let pieces lag by a millimetre.
#define MOTION_POSITION_EPSILON 1e-6
#define MOTION_ROTATION_EPSILON 1e-6

// Bodies placed nowhere yet (new ones), or that moved since their last
// placement by more than the epsilons.
static bool moved(const bk_world* w, const world_body* body) {
  if (!body->sent_valid) return true;
  bk_transform now = bk_physics_body_transform(w->physics, body->body);
  bk_quat a = now.rotation, b = body->sent.rotation;
  double dot = fabs(a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w);
  // 1 - |dot| is about angle^2 / 8 for a small rotation between them.
  return bk_v3_length(bk_v3_sub(now.position, body->sent.position)) > MOTION_POSITION_EPSILON ||
         1.0 - dot > MOTION_ROTATION_EPSILON * MOTION_ROTATION_EPSILON / 8.0 || !(dot == dot);
}

static uint32_t moved_count(const bk_world* w) {
  uint32_t count = 0;
  for (uint32_t i = 0; i < w->live_count; ++i)
    count += moved(w, &w->bodies[w->live[i]]);
  return count;
}

size_t bk_world_motion_size(const bk_world* w) {
  return w ? 5 + (size_t)moved_count(w) * MOTION_BODY_MAX_BYTES : 0;
}

size_t bk_world_motion(bk_world* w, void* out, size_t capacity) {
  if (!w || !out) return 0;
  uint32_t count = moved_count(w);
  if (capacity < 5 + (size_t)count * MOTION_BODY_MAX_BYTES) return 0;
  uint8_t* p = out;
  size_t n = put_varint(p, count);
  for (uint32_t i = 0; i < w->live_count; ++i) {
    world_body* body = &w->bodies[w->live[i]];
    if (!moved(w, body)) continue;
    bk_transform t = bk_physics_body_transform(w->physics, body->body);
    body->sent = t;
    body->sent_valid = true;
    n += put_varint(p + n, body->cluster.index);
    n += put_varint(p + n, body->cluster.generation);
    put_f32(p + n, t.position.x);
    put_f32(p + n + 4, t.position.y);
    put_f32(p + n + 8, t.position.z);
    n += 12;
    n += put_rotation(p + n, t.rotation);
  }
  return n;
}

static bool get_varint(const uint8_t* p, size_t size, size_t* at, uint32_t* out) {
  uint64_t v = 0;
  for (int shift = 0; shift < 35 && *at < size; shift += 7) {
    uint8_t byte = p[(*at)++];
    v |= (uint64_t)(byte & 0x7f) << shift;
    if (!(byte & 0x80)) {
      *out = (uint32_t)v;
      return v <= UINT32_MAX;
    }
  }
  return false;
}

static double get_f32(const uint8_t* p) {
  uint32_t bits = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
  float f = 0.0f;
  memcpy(&f, &bits, sizeof f);
  return f;
}

static double get_i16(const uint8_t* p) { return (double)(int16_t)(uint16_t)(p[0] | p[1] << 8) / 32767.0; }

bool bk_world_apply_motion(bk_world* w, const void* data, size_t size, bk_error* err) {
  if (!w) return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "motion: world is NULL");
  const uint8_t* p = data;
  size_t at = 0;
  uint32_t count = 0;
  if (!p || !get_varint(p, size, &at, &count) || count > size / 20)
    return bk_error_set(err, "motion: malformed (%zu bytes)", size);
  // Checked whole first: malformed bytes move nothing.
  for (int pass = 0; pass < 2; ++pass) {
    at = 0;
    get_varint(p, size, &at, &count);
    uint32_t unknown = 0;
    for (uint32_t k = 0; k < count; ++k) {
      uint32_t index = 0, generation = 0;
      if (!get_varint(p, size, &at, &index) || !get_varint(p, size, &at, &generation) || size - at < 19 ||
          p[at + 12] > 3)
        return bk_error_set(err, "motion: body %u of %u: truncated or malformed", k, count);
      bk_vec3 position = {get_f32(p + at), get_f32(p + at + 4), get_f32(p + at + 8)};
      double c[4] = {0.0, 0.0, 0.0, 0.0}, sum = 0.0;
      int largest = p[at + 12];
      for (int i = 0, j = 0; i < 4; ++i) {
        if (i == largest) continue;
        c[i] = get_i16(p + at + 13 + 2 * j++) / SQRT2;
        sum += c[i] * c[i];
      }
      at += 19;
      if (!bk_v3_is_finite(position) || sum > 1.0 + 1e-6)
        return bk_error_set(err, "motion: body %u of %u: position not finite or rotation not unit", k, count);
      if (pass == 0) continue;
      c[largest] = sqrt(fmax(0.0, 1.0 - sum));
      bk_transform t = {position, bk_quat_normalize((bk_quat){c[0], c[1], c[2], c[3]})};
      world_body* body = index < w->body_capacity ? &w->bodies[index] : NULL;
      if (!body || !body->alive || body->cluster.generation != generation) {
        unknown++;
        continue;
      }
      body->previous = bk_world_tree_to_world(w, index); // drawn from here to there
      bk_physics_body_set_transform(w->physics, body->body, t);
    }
    if (pass == 0 && at != size) return bk_error_set(err, "motion: %zu bytes after the last body", size - at);
    if (pass == 1 && unknown)
      return bk_error_set(err, "motion: %u bodies of clusters this world does not have (it has diverged)",
                          unknown);
  }
  return true;
}
