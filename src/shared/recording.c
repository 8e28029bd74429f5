// The .bkrec file: a run's recording, field by field in little-endian order
// (doubles by their bits), so the same recording always gives the same bytes
// on any compiler or host.
//
// Layout: a 32-byte header, then the payload.
//   header:  "BKREC\0\0\0" | u32 version | u32 0x01020304 | u64 payload size | u64 XXH3-64 of the payload
//   payload: str program | u64 steps | u8 has_hashes | u32 event_count
//            event_count x { u8 kind | u64 step | the kind's fields }
//            steps x { u64 state_hash | u64 world_hash } when has_hashes
//   str: u16 length | bytes (no NUL)
//   SCENE:    str name, mesh, material, units | f64 model_scale | u32 pieces | u64 seed
//             f64 texture_scale | i32 pattern | u32 clusters | f64 cluster_border, radial_falloff, noise
//             f64 frailty, density, bond_strength | i32 accumulate | u8 naive, convex_colliders
//             f64 retire_volume | u8 stress | f64 stress_scale, compression_limit, tension_limit,
//             shear_limit, physics_budget_ms, budget_fidelity_time, budget_fidelity_factor
//             u32 copies | u8 refine | u32 refine_pieces
//   FIRE:     f64 position[3], velocity[3], radius, mass, lifetime
//   WEIGHT:   f64 surface[3], kg, radius
//   FOCUS:    f64 point[3]
//   MATERIAL: u32 breakable | u8 setter | str name | f64 density, frailty, bond_strength | u8 accumulate
//             f64 friction, restitution, compression_limit, tension_limit, shear_limit, refine_strength
//   STRESS:   u8 on
//   BUDGET:   f64 ms
#include "recording.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define XXH_INLINE_ALL
#include <xxhash.h>

static const uint8_t magic[8] = {'B', 'K', 'R', 'E', 'C', '\0', '\0', '\0'};
enum { HEADER_BYTES = 32, VERSION = 1, ENDIAN_MARKER = 0x01020304, EVENT_MIN_BYTES = 1 + 8 + 1 };

// ---------------------------------------------------------------- building

void recording_free(recording* rec) {
  bk_free(rec->events);
  bk_free(rec->scenes);
  bk_free(rec->hashes);
  memset(rec, 0, sizeof *rec);
}

void recording_add(recording* rec, const recording_event* event) {
  if (rec->event_count == rec->event_capacity) {
    rec->event_capacity = rec->event_capacity ? 2 * rec->event_capacity : 64;
    rec->events = bk_realloc(rec->events, sizeof *rec->events * rec->event_capacity);
  }
  rec->events[rec->event_count++] = *event;
}

void recording_add_scene(recording* rec, uint64_t step, const recording_scene* scene) {
  if (rec->scene_count == rec->scene_capacity) {
    rec->scene_capacity = rec->scene_capacity ? 2 * rec->scene_capacity : 4;
    rec->scenes = bk_realloc(rec->scenes, sizeof *rec->scenes * rec->scene_capacity);
  }
  rec->scenes[rec->scene_count] = *scene;
  rec->scenes[rec->scene_count].options.material = NULL; // recording_scene_options points it anew
  rec->scenes[rec->scene_count].options.progress = NULL;
  rec->scenes[rec->scene_count].options.progress_user = NULL;
  recording_event e = {.step = step, .kind = RECORDING_SCENE, .scene = rec->scene_count++};
  recording_add(rec, &e);
}

void recording_add_material(recording* rec, uint64_t step, uint32_t index, recording_setter setter,
                            const bk_material* material) {
  recording_event e = {.step = step, .kind = RECORDING_MATERIAL};
  e.material.breakable = index;
  e.material.setter = setter;
  e.material.material = *material;
  e.material.material.name = NULL;
  snprintf(e.material.name, sizeof e.material.name, "%s", material->name ? material->name : "");
  recording_add(rec, &e);
}

void recording_add_hashes(recording* rec, uint64_t step, uint64_t state_hash, uint64_t world_hash) {
  if (step >= rec->hash_capacity) {
    uint64_t capacity = rec->hash_capacity ? 2 * rec->hash_capacity : 1024;
    while (capacity <= step)
      capacity *= 2;
    rec->hashes = bk_realloc(rec->hashes, sizeof *rec->hashes * 2 * capacity);
    rec->hash_capacity = capacity;
  }
  rec->hashes[2 * step] = state_hash;
  rec->hashes[2 * step + 1] = world_hash;
  rec->has_hashes = true;
}

scene_options recording_scene_options(const recording_scene* scene) {
  scene_options o = scene->options;
  o.material = scene->material[0] ? scene->material : NULL;
  o.progress = NULL;
  o.progress_user = NULL;
  return o;
}

bk_material recording_material(const recording_event* event) {
  bk_material m = event->material.material;
  m.name = event->material.name;
  return m;
}

// ---------------------------------------------------------------- writing

typedef struct writer {
  uint8_t* data;
  size_t size, capacity;
} writer;

static void put(writer* w, const void* bytes, size_t n) {
  if (w->size + n > w->capacity) {
    size_t capacity = w->capacity ? w->capacity : 4096;
    while (capacity < w->size + n)
      capacity *= 2;
    w->data = bk_realloc(w->data, capacity);
    w->capacity = capacity;
  }
  memcpy(w->data + w->size, bytes, n);
  w->size += n;
}

static void put_uint(writer* w, uint64_t v, int bytes) {
  uint8_t b[8];
  for (int i = 0; i < bytes; ++i)
    b[i] = (uint8_t)(v >> (8 * i));
  put(w, b, (size_t)bytes);
}

static void put_u8(writer* w, uint32_t v) { put_uint(w, v, 1); }
static void put_u32(writer* w, uint32_t v) { put_uint(w, v, 4); }
static void put_u64(writer* w, uint64_t v) { put_uint(w, v, 8); }
static void put_f64(writer* w, double v) {
  uint64_t bits = 0;
  memcpy(&bits, &v, sizeof bits);
  put_u64(w, bits);
}
static void put_vec(writer* w, bk_vec3 v) { put_f64(w, v.x), put_f64(w, v.y), put_f64(w, v.z); }
static void put_str(writer* w, const char* s) {
  size_t n = strlen(s);
  put_uint(w, n, 2);
  put(w, s, n);
}

static void put_scene(writer* w, const recording_scene* s) {
  const scene_options* o = &s->options;
  put_str(w, s->name), put_str(w, s->mesh), put_str(w, s->material), put_str(w, s->units);
  put_f64(w, s->model_scale);
  put_u32(w, o->pieces), put_u64(w, o->seed), put_f64(w, o->texture_scale), put_u32(w, (uint32_t)o->pattern);
  put_u32(w, o->clusters), put_f64(w, o->cluster_border), put_f64(w, o->radial_falloff), put_f64(w, o->noise);
  put_f64(w, o->frailty), put_f64(w, o->density), put_f64(w, o->bond_strength);
  put_u32(w, (uint32_t)o->accumulate), put_u8(w, o->naive), put_u8(w, o->convex_colliders);
  put_f64(w, o->retire_volume), put_u8(w, o->stress), put_f64(w, o->stress_scale);
  put_f64(w, o->compression_limit), put_f64(w, o->tension_limit), put_f64(w, o->shear_limit);
  put_f64(w, o->physics_budget_ms), put_f64(w, o->budget_fidelity_time),
      put_f64(w, o->budget_fidelity_factor);
  put_u32(w, o->copies), put_u8(w, o->refine), put_u32(w, o->refine_pieces);
}

static void put_event(writer* w, const recording* rec, const recording_event* e) {
  put_u8(w, (uint32_t)e->kind);
  put_u64(w, e->step);
  switch (e->kind) {
  case RECORDING_SCENE:
    put_scene(w, &rec->scenes[e->scene]);
    break;
  case RECORDING_FIRE:
    put_vec(w, e->fire.position), put_vec(w, e->fire.velocity);
    put_f64(w, e->fire.radius), put_f64(w, e->fire.mass), put_f64(w, e->fire.lifetime);
    break;
  case RECORDING_WEIGHT:
    put_vec(w, e->weight.surface), put_f64(w, e->weight.kg), put_f64(w, e->weight.radius);
    break;
  case RECORDING_FOCUS:
    put_vec(w, e->focus);
    break;
  case RECORDING_MATERIAL: {
    const bk_material* m = &e->material.material;
    put_u32(w, e->material.breakable), put_u8(w, (uint32_t)e->material.setter), put_str(w, e->material.name);
    put_f64(w, m->density), put_f64(w, m->frailty), put_f64(w, m->bond_strength), put_u8(w, m->accumulate);
    put_f64(w, m->friction), put_f64(w, m->restitution), put_f64(w, m->compression_limit);
    put_f64(w, m->tension_limit), put_f64(w, m->shear_limit), put_f64(w, m->refine_strength);
    break;
  }
  case RECORDING_STRESS:
    put_u8(w, e->stress);
    break;
  case RECORDING_BUDGET:
    put_f64(w, e->budget_ms);
    break;
  default:
    break;
  }
}

uint8_t* recording_encode(const recording* rec, size_t* size) {
  writer w = {0};
  put(&w, magic, sizeof magic);
  put_u32(&w, VERSION), put_u32(&w, ENDIAN_MARKER), put_u64(&w, 0), put_u64(&w, 0); // size and sum below
  put_str(&w, rec->program);
  put_u64(&w, rec->steps);
  put_u8(&w, rec->has_hashes);
  put_u32(&w, rec->event_count);
  for (uint32_t i = 0; i < rec->event_count; ++i)
    put_event(&w, rec, &rec->events[i]);
  if (rec->has_hashes)
    for (uint64_t s = 0; s < rec->steps; ++s)
      put_u64(&w, s < rec->hash_capacity ? rec->hashes[2 * s] : 0),
          put_u64(&w, s < rec->hash_capacity ? rec->hashes[2 * s + 1] : 0);
  uint64_t payload = w.size - HEADER_BYTES, sum = XXH3_64bits(w.data + HEADER_BYTES, payload);
  for (int i = 0; i < 8; ++i) {
    w.data[16 + i] = (uint8_t)(payload >> (8 * i));
    w.data[24 + i] = (uint8_t)(sum >> (8 * i));
  }
  *size = w.size;
  return w.data;
}

static const bk_atomic_messages write_messages = {"cannot create a temporary file beside it",
                                                  "cannot write the recording", "cannot replace it"};

bool recording_write(const recording* rec, const char* path, bk_error* err) {
  size_t size = 0;
  uint8_t* data = recording_encode(rec, &size);
  bk_atomic_file file = {0};
  bool ok = bk_file_begin_atomic(path, &write_messages, &file, err);
  if (ok) {
    fwrite(data, 1, size, file.stream); // a short write leaves the stream in error, which commit reports
    ok = bk_file_commit_atomic(&file, path, &write_messages, err);
  }
  bk_free(data);
  return ok;
}

// ---------------------------------------------------------------- reading

typedef struct reader {
  const uint8_t* data;
  size_t size, at;
  const char* name;
  bk_error* err;
  bool failed;
} reader;

// The first problem is the one reported: later reads of a failed reader
// give zeros and change nothing.
static bool fail(reader* r, const char* what, const char* detail) {
  if (!r->failed) bk_error_set(r->err, "%s: %s%s", r->name, what, detail ? detail : "");
  r->failed = true;
  return false;
}

static const uint8_t* take(reader* r, size_t n, const char* what) {
  if (r->failed) return NULL;
  if (n > r->size - r->at) {
    char detail[96];
    snprintf(detail, sizeof detail, " (at byte %zu of %zu)", HEADER_BYTES + r->at, HEADER_BYTES + r->size);
    fail(r, "truncated in ", what);
    if (r->err)
      snprintf(r->err->message + strlen(r->err->message), sizeof r->err->message - strlen(r->err->message),
               "%s", detail);
    return NULL;
  }
  const uint8_t* p = r->data + r->at;
  r->at += n;
  return p;
}

static uint64_t get_uint(reader* r, int bytes, const char* what) {
  const uint8_t* p = take(r, (size_t)bytes, what);
  uint64_t v = 0;
  for (int i = 0; p && i < bytes; ++i)
    v |= (uint64_t)p[i] << (8 * i);
  return v;
}

static uint32_t get_u8(reader* r, const char* what) { return (uint32_t)get_uint(r, 1, what); }
static uint32_t get_u32(reader* r, const char* what) { return (uint32_t)get_uint(r, 4, what); }
static uint64_t get_u64(reader* r, const char* what) { return get_uint(r, 8, what); }

static bool get_bool(reader* r, const char* what) {
  uint32_t v = get_u8(r, what);
  if (v > 1) fail(r, what, " is neither 0 nor 1");
  return v == 1;
}

// A double within [lo, hi] (NaN never is; an infinite bound lets infinity in).
static double get_f64(reader* r, const char* what, double lo, double hi) {
  uint64_t bits = get_u64(r, what);
  double v = 0.0;
  memcpy(&v, &bits, sizeof v);
  if (r->failed) return 0.0;
  if (isnan(v))
    fail(r, what, " is NaN");
  else if (!(v >= lo && v <= hi)) {
    char detail[96];
    snprintf(detail, sizeof detail, " %g is out of range (%g..%g)", v, lo, hi);
    fail(r, what, detail);
  }
  return r->failed ? 0.0 : v;
}

static bk_vec3 get_vec(reader* r, const char* what, double limit) {
  bk_vec3 v = {0.0, 0.0, 0.0};
  v.x = get_f64(r, what, -limit, limit), v.y = get_f64(r, what, -limit, limit);
  v.z = get_f64(r, what, -limit, limit);
  return v;
}

// A string of printable bytes (no NUL, so it writes back the same) of at most `max`.
static void get_str(reader* r, char* out, size_t max, const char* what) {
  out[0] = '\0';
  uint64_t n = get_uint(r, 2, what);
  if (!r->failed && n > max) {
    char detail[64];
    snprintf(detail, sizeof detail, " is too long (%llu bytes, at most %zu)", (unsigned long long)n, max);
    fail(r, what, detail);
  }
  const uint8_t* p = take(r, (size_t)n, what);
  if (!p) return;
  for (uint64_t i = 0; i < n; ++i)
    if (p[i] < 0x20 || p[i] == 0x7f) {
      fail(r, what, " holds a control byte");
      return;
    }
  memcpy(out, p, (size_t)n);
  out[n] = '\0';
}

// 0 (the default) or within [lo, hi].
static double get_optional(reader* r, const char* what, double lo, double hi) {
  double v = get_f64(r, what, 0.0 > lo ? lo : 0.0, hi);
  if (v != 0.0 && v < lo) {
    char detail[96];
    snprintf(detail, sizeof detail, " %g is out of range (0, or %g..%g)", v, lo, hi);
    fail(r, what, detail);
  }
  return v;
}

static void get_scene(reader* r, recording_scene* s) {
  scene_options* o = &s->options;
  memset(s, 0, sizeof *s);
  get_str(r, s->name, RECORDING_NAME_MAX, "the scene's name");
  get_str(r, s->mesh, RECORDING_PATH_MAX, "the model's path");
  get_str(r, s->material, RECORDING_NAME_MAX, "the material's name");
  get_str(r, s->units, RECORDING_NAME_MAX, "the model's units");
  s->model_scale = get_f64(r, "the model's scale", 1e-6, 1e6);
  o->pieces = get_u32(r, "pieces");
  if (o->pieces > 65536) fail(r, "pieces", " is out of range (0..65536)");
  o->seed = get_u64(r, "the seed");
  o->texture_scale = get_f64(r, "the texture scale", 1e-9, 1e9);
  o->pattern = (int32_t)get_u32(r, "the pattern");
  if (o->pattern < -1 || o->pattern >= BK_PATTERN_COUNT) fail(r, "the pattern", " is not one");
  o->clusters = get_u32(r, "clusters");
  if (o->clusters > 65536) fail(r, "clusters", " is out of range (0..65536)");
  o->cluster_border = get_f64(r, "the cluster border", 0.0, 1.0);
  o->radial_falloff = get_f64(r, "the radial falloff", -1.0, 1e3);
  o->noise = get_f64(r, "the noise", 0.0, 1.0);
  o->frailty = get_optional(r, "the frailty", 1e-6, 1e6);
  o->density = get_optional(r, "the density", 1.0, 1e5);
  o->bond_strength =
      get_optional(r, "the bond strength", BK_MATERIAL_BOND_STRENGTH_MIN, BK_MATERIAL_BOND_STRENGTH_MAX);
  o->accumulate = (int32_t)get_u32(r, "accumulate");
  if (o->accumulate < -1 || o->accumulate > 1) fail(r, "accumulate", " is not -1, 0 or 1");
  o->naive = get_bool(r, "naive"), o->convex_colliders = get_bool(r, "convex colliders");
  o->retire_volume = get_f64(r, "the retire volume", 0.0, 1e6);
  o->stress = get_bool(r, "stress");
  o->stress_scale = get_f64(r, "the stress scale", 1e-6, 1e6);
  o->compression_limit = get_f64(r, "the compression limit", 0.0, INFINITY);
  o->tension_limit = get_f64(r, "the tension limit", 0.0, INFINITY);
  o->shear_limit = get_f64(r, "the shear limit", 0.0, INFINITY);
  o->physics_budget_ms = get_f64(r, "the physics budget", 0.0, BK_BUDGET_MS_MAX);
  o->budget_fidelity_time = get_f64(r, "the budget fidelity", 0.0, BK_BUDGET_FIDELITY_MAX);
  o->budget_fidelity_factor =
      get_optional(r, "the budget fidelity factor", 1.0, BK_BUDGET_FIDELITY_FACTOR_MAX);
  o->copies = get_u32(r, "copies");
  if (o->copies < 1 || o->copies > BK_COPIES_MAX) fail(r, "copies", " is out of range (1..64)");
  o->refine = get_bool(r, "refine");
  o->refine_pieces = get_u32(r, "refine pieces");
  if (o->refine_pieces != 0 &&
      (o->refine_pieces < BK_REFINE_PIECES_MIN || o->refine_pieces > BK_REFINE_PIECES_MAX))
    fail(r, "refine pieces", " is out of range (0, or 2..1024)");
  if (!r->failed && s->units[0] && strcmp(s->units, "mm") && strcmp(s->units, "cm") &&
      strcmp(s->units, "m") && strcmp(s->units, "in"))
    fail(r, "the model's units", " are not mm, cm, m or in");
  if (!r->failed && !s->name[0]) fail(r, "the scene's name", " is empty");
}

static const double position_limit = 1e6, speed_limit = 1e6;

static void get_event(reader* r, recording* rec, recording_event* e) {
  switch (e->kind) {
  case RECORDING_SCENE: {
    recording_scene scene;
    get_scene(r, &scene);
    if (r->failed) break;
    // Grown as scenes come (each takes at least 189 bytes of the file), as the events are.
    if (rec->scene_count == rec->scene_capacity) {
      rec->scene_capacity = rec->scene_capacity ? 2 * rec->scene_capacity : 4;
      rec->scenes = bk_realloc(rec->scenes, sizeof *rec->scenes * rec->scene_capacity);
    }
    rec->scenes[rec->scene_count] = scene;
    e->scene = rec->scene_count++;
    break;
  }
  case RECORDING_FIRE:
    e->fire.position = get_vec(r, "a shot's position", position_limit);
    e->fire.velocity = get_vec(r, "a shot's velocity", speed_limit);
    e->fire.radius = get_f64(r, "a shot's radius", 1e-6, 1e3);
    e->fire.mass = get_f64(r, "a shot's mass", 1e-9, 1e9);
    e->fire.lifetime = get_f64(r, "a shot's lifetime", 0.0, INFINITY);
    if (!r->failed && !(e->fire.radius > 0.0)) fail(r, "a shot's radius", " is not positive");
    break;
  case RECORDING_WEIGHT:
    e->weight.surface = get_vec(r, "a weight's place", position_limit);
    e->weight.kg = get_f64(r, "a weight's mass", 1e-9, 1e9);
    e->weight.radius = get_f64(r, "a weight's radius", 1e-6, 1e3);
    break;
  case RECORDING_FOCUS:
    e->focus = get_vec(r, "the focus", position_limit);
    break;
  case RECORDING_MATERIAL: {
    bk_material* m = &e->material.material;
    e->material.breakable = get_u32(r, "a material's breakable");
    if (!r->failed && e->material.breakable >= RECORDING_BREAKABLES_MAX)
      fail(r, "a material's breakable", " is out of range");
    e->material.setter = (recording_setter)get_u8(r, "a material's setter");
    if (!r->failed && e->material.setter >= RECORDING_SET_END) fail(r, "a material's setter", " is not one");
    get_str(r, e->material.name, BK_MATERIAL_NAME_MAX, "a material's name");
    m->density = get_f64(r, "a material's density", BK_MATERIAL_DENSITY_MIN, BK_MATERIAL_DENSITY_MAX);
    m->frailty = get_f64(r, "a material's frailty", 0.0, 1e12);
    m->bond_strength = get_f64(r, "a material's bond strength", BK_MATERIAL_BOND_STRENGTH_MIN,
                               BK_MATERIAL_BOND_STRENGTH_MAX);
    m->accumulate = get_bool(r, "a material's accumulate");
    m->friction = get_f64(r, "a material's friction", 0.0, 1e6);
    m->restitution = get_f64(r, "a material's restitution", 0.0, 1.0);
    m->compression_limit = get_f64(r, "a material's compression limit", 1e-300, INFINITY);
    m->tension_limit = get_f64(r, "a material's tension limit", 1e-300, INFINITY);
    m->shear_limit = get_f64(r, "a material's shear limit", 1e-300, INFINITY);
    m->refine_strength = get_f64(r, "a material's refine strength", 0.0, 1e300);
    m->name = e->material.name;
    bk_error why = {0};
    if (!r->failed && !bk_material_validate(m, &why)) fail(r, "a material change: ", why.message);
    m->name = NULL;
    break;
  }
  case RECORDING_STRESS:
    e->stress = get_bool(r, "a stress switch");
    break;
  case RECORDING_BUDGET:
    e->budget_ms = get_f64(r, "a physics budget", 0.0, BK_BUDGET_MS_MAX);
    break;
  default:
    break;
  }
}

bool recording_decode(const uint8_t* data, size_t size, const char* name, recording* out, bk_error* err) {
  memset(out, 0, sizeof *out);
  if (size < HEADER_BYTES)
    return bk_error_set(err, "%s: truncated: %zu bytes, not even the %d of a recording's header", name, size,
                        (int)HEADER_BYTES);
  if (memcmp(data, magic, sizeof magic) != 0)
    return bk_error_set(err, "%s: not a recording (bad magic)", name);
  reader h = {data, HEADER_BYTES, 8, name, err, false};
  uint32_t version = get_u32(&h, "the header"), endian = get_u32(&h, "the header");
  uint64_t payload = get_u64(&h, "the header"), sum = get_u64(&h, "the header");
  if (version != VERSION)
    return bk_error_set(err, "%s: version %u is not supported (this build reads version %d)", name, version,
                        (int)VERSION);
  if (endian != ENDIAN_MARKER) return bk_error_set(err, "%s: bad byte-order marker 0x%08x", name, endian);
  if (payload > RECORDING_MAX_FILE_BYTES)
    return bk_error_set(err, "%s: payload of %llu bytes is larger than a recording may be", name,
                        (unsigned long long)payload);
  if (payload != size - HEADER_BYTES)
    return bk_error_set(err, "%s: %s: the header says %llu bytes of payload, the file has %zu", name,
                        payload > size - HEADER_BYTES ? "truncated" : "trailing bytes",
                        (unsigned long long)payload, size - HEADER_BYTES);
  if (XXH3_64bits(data + HEADER_BYTES, (size_t)payload) != sum)
    return bk_error_set(err, "%s: checksum mismatch (the file is damaged)", name);
  reader r = {data + HEADER_BYTES, (size_t)payload, 0, name, err, false};
  get_str(&r, out->program, RECORDING_NAME_MAX, "the program's name");
  out->steps = get_u64(&r, "the step count");
  out->has_hashes = get_bool(&r, "the hashes' flag");
  uint32_t count = get_u32(&r, "the event count");
  if (!r.failed && (out->steps < 1 || out->steps > RECORDING_STEPS_MAX))
    fail(&r, "the step count", " is out of range (1..10000000)");
  // Counts against the bytes left before anything is allocated.
  if (!r.failed &&
      (count < 1 || count > RECORDING_EVENTS_MAX || (uint64_t)count * EVENT_MIN_BYTES > r.size - r.at))
    fail(&r, "the event count", " does not fit the file");
  if (!r.failed && out->has_hashes && out->steps * 16 > r.size - r.at)
    fail(&r, "the hashes", " do not fit the file");
  for (uint32_t i = 0; i < count && !r.failed; ++i) {
    recording_event e = {0};
    uint32_t kind = get_u8(&r, "an event");
    e.step = get_u64(&r, "an event");
    if (r.failed) break;
    const recording_event* last = i > 0 ? &out->events[i - 1] : NULL;
    char detail[96];
    if (kind < RECORDING_SCENE || kind >= RECORDING_KIND_END) {
      snprintf(detail, sizeof detail, "event %u is of an unknown kind (%u)", i, kind);
      fail(&r, detail, NULL);
    } else if (!last && (kind != RECORDING_SCENE || e.step != 0)) {
      fail(&r, "the first event is not the scene at step 0", NULL);
    } else if (last && e.step < last->step) {
      snprintf(detail, sizeof detail, "event %u: step %llu out of order (after step %llu)", i,
               (unsigned long long)e.step, (unsigned long long)last->step);
      fail(&r, detail, NULL);
    } else if (e.step >= out->steps) {
      snprintf(detail, sizeof detail, "event %u: step %llu is past the run's end (%llu steps)", i,
               (unsigned long long)e.step, (unsigned long long)out->steps);
      fail(&r, detail, NULL);
    }
    e.kind = (recording_kind)kind;
    get_event(&r, out, &e);
    if (!r.failed) recording_add(out, &e); // grown as events come: a count alone allocates nothing
  }
  if (!r.failed && out->has_hashes) {
    out->hashes = bk_alloc(sizeof *out->hashes * 2 * out->steps);
    out->hash_capacity = out->steps;
    for (uint64_t s = 0; s < 2 * out->steps; ++s)
      out->hashes[s] = get_u64(&r, "the hashes");
  }
  if (!r.failed && r.at != r.size) fail(&r, "trailing bytes after the hashes", NULL);
  if (r.failed) {
    recording_free(out);
    return false;
  }
  return true;
}

bool recording_read(const char* path, recording* out, bk_error* err) {
  memset(out, 0, sizeof *out);
  void* data = NULL;
  size_t size = 0;
  if (!bk_file_read(path, RECORDING_MAX_FILE_BYTES, "256 MiB", &data, &size, err)) return false;
  bool ok = recording_decode(data, size, path, out, err);
  bk_free(data);
  return ok;
}
