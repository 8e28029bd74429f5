// Fuzzes bk_runtime_load_state, the reader of saved destruction states, on
// a small runtime (a cube in 27 pieces whose fragments refine into 6 where
// hit hard, and a cube in 8 beside it; no worker threads).
//
// Byte 0 chooses the input's meaning:
//   even: bytes 1.. are a saved state; with bit 1 set, its header's payload
//     size and checksum are made to match first, so that mutations reach the
//     parser behind them (a hostile state, not only a damaged one).
//   odd: bytes 1.. are a program of damage, split, refine and remove calls
//     on a runtime (as fuzz_journal's), whose state is saved, loaded into a
//     fresh runtime (its hash must be the same) and continued alike (the
//     hashes must stay the same); byte 1 picks a byte of that state to
//     change (0: none), to load it damaged as well.
// Every load that fails must say so in one line starting "state: " and leave
// the runtime's hash as it was; every load that succeeds must give a runtime
// whose leaves are each in one live cluster and whose own state, saved and
// loaded again into a fresh runtime, has the same hash.
//
// The seeds in corpus/fuzz_state are real states (raw, byte 0 = 2; those
// under 16 KB, the fuzzer's input limit) and programs; BK_FUZZ_STATE_SEEDS=DIR fuzz_state_replay ANY_FILE
// writes the state seeds again into DIR.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include <breakables/runtime.h>

#include "fuzz_util.h"

const char bk_fuzz_harness[] = "fuzz_state";

enum { MAX_STATES = 1024 };

typedef struct side {
  bk_body_state states[MAX_STATES];
  bk_runtime* rt;
} side;

static bk_body_state body_state(bk_cluster_id cluster, void* context) {
  side* s = context;
  return cluster.index < MAX_STATES ? s->states[cluster.index] : (bk_body_state){0};
}

static const bk_mesh_tree* cube_tree(uint32_t pieces) {
  static bk_mesh_tree trees[2];
  static bool built[2] = {false, false};
  int k = pieces == 27 ? 0 : 1;
  if (!built[k]) {
    bk_mesh mesh = {0};
    bk_shape_build(BK_SHAPE_CUBE, &mesh);
    bk_fracture_def def = bk_default_fracture_def();
    def.pieces = pieces;
    def.seed = 5;
    bk_error err = {0};
    if (!bk_mesh_tree_build(&mesh, &def, &trees[k], &err)) bk_fuzz_fail("tree: %s", err.message);
    bk_mesh_free(&mesh);
    built[k] = true;
  }
  return &trees[k];
}

static void take_events(side* s) {
  bk_cluster_created created[256];
  uint32_t n = bk_runtime_created_clusters(s->rt, created, 256);
  for (uint32_t i = 0; i < n && i < 256; ++i)
    if (created[i].cluster.id.index < MAX_STATES) s->states[created[i].cluster.id.index] = created[i].body;
  bk_runtime_clear_events(s->rt);
}

static side* make_side(void) {
  side* s = calloc(1, sizeof *s);
  bk_runtime_def def = bk_default_runtime_def();
  def.body_state = body_state;
  def.context = s;
  def.refine_threads = 0;
  def.max_new_clusters_per_split = 4;
  s->rt = bk_runtime_create(&def, NULL);
  for (int k = 0; k < 2; ++k) {
    bk_breakable_def b = bk_default_breakable_def();
    b.tree = cube_tree(k == 0 ? 27 : 8);
    b.material = *bk_material_find("stone");
    b.material.accumulate = k == 1;
    if (k == 0) b.material.refine_strength = b.material.bond_strength / 8.0;
    b.refine.pieces = 6;
    b.refine.min_size = 0.01;
    b.transform.position = bk_v3(3.0 * k, 0, 0);
    if (bk_breakable_is_null(bk_runtime_add_breakable(s->rt, &b, NULL))) bk_fuzz_fail("add failed");
  }
  take_events(s);
  return s;
}

static void free_side(side* s) {
  bk_runtime_destroy(s->rt);
  free(s);
}

// Every leaf of every breakable in at most one live cluster, which agrees.
static void check_leaves(const side* s) {
  for (uint32_t index = 0; index < 2; ++index) {
    bk_breakable_id id = {index, 1};
    const bk_mesh_tree* tree = bk_runtime_breakable_tree(s->rt, id);
    if (!tree) bk_fuzz_fail("breakable %u is gone", index);
    bk_cluster_id ids[1024];
    uint32_t n = bk_runtime_clusters(s->rt, ids, 1024);
    uint32_t covered = 0;
    for (uint32_t i = 0; i < n && i < 1024; ++i) {
      bk_cluster_info info = {0};
      if (!bk_runtime_cluster(s->rt, ids[i], &info)) bk_fuzz_fail("cluster %u listed but not live", i);
      if (info.breakable.index != index) continue;
      if (info.leaf_count == 0 || info.node_count == 0 || !(info.mass > 0.0) || !isfinite(info.mass))
        bk_fuzz_fail("cluster %u: %u leaves, %u nodes, mass %g", i, info.leaf_count, info.node_count,
                     info.mass);
      for (uint32_t k = 0; k < info.leaf_count; ++k)
        if (!bk_cluster_equal(bk_runtime_leaf_cluster(s->rt, id, info.leaves[k]), ids[i]))
          bk_fuzz_fail("leaf %u is not in its cluster", info.leaves[k]);
      covered += info.leaf_count;
    }
    if (covered > tree->leaf_count) bk_fuzz_fail("%u leaves covered of %u", covered, tree->leaf_count);
  }
}

static uint8_t* save(const side* s, size_t* size) {
  *size = bk_runtime_state_size(s->rt);
  uint8_t* bytes = malloc(*size + 1u);
  bk_error err = {0};
  if (bk_runtime_save_state(s->rt, bytes, *size, &err) != *size) bk_fuzz_fail("save: %s", err.message);
  return bytes;
}

// A loaded state saves and loads again into a fresh runtime with its hash.
static void check_round_trip(const side* s) {
  size_t size = 0;
  uint8_t* bytes = save(s, &size);
  side* again = make_side();
  bk_error err = {0};
  if (!bk_runtime_load_state(again->rt, bytes, size, &err))
    bk_fuzz_fail("saved state refused: %s", err.message);
  if (bk_runtime_state_hash(again->rt) != bk_runtime_state_hash(s->rt))
    bk_fuzz_fail("round trip changed the hash");
  free(bytes);
  free_side(again);
}

// Loads `data` into a fresh runtime: refused cleanly, or a sound state.
static void load(const uint8_t* data, size_t size) {
  side* s = make_side();
  uint64_t before = bk_runtime_state_hash(s->rt);
  bk_error err = {0};
  if (bk_runtime_load_state(s->rt, data, size, &err)) {
    check_leaves(s);
    check_round_trip(s);
    // And it goes on: hits, refinements and splits on the loaded clusters.
    for (int k = 0; k < 3; ++k) {
      bk_runtime_damage_at(s->rt, bk_v3(0.2 * k, 0.1, 0.5), 400.0);
      bk_runtime_refine(s->rt);
      bk_runtime_split(s->rt);
      take_events(s);
    }
    check_leaves(s);
  } else {
    if (strncmp(err.message, "state: ", 7) != 0 || strchr(err.message, '\n'))
      bk_fuzz_fail("refusal not one line: '%s'", err.message);
    if (bk_runtime_state_hash(s->rt) != before)
      bk_fuzz_fail("refused state changed the runtime: %s", err.message);
  }
  free_side(s);
}

static void fix_header(uint8_t* data, size_t size) {
  if (size < 32) return;
  uint64_t payload = size - 32, checksum = XXH3_64bits(data + 32, payload);
  for (int i = 0; i < 8; ++i) {
    data[16 + i] = (uint8_t)(payload >> (8 * i));
    data[24 + i] = (uint8_t)(checksum >> (8 * i));
  }
}

static double number(const uint8_t* data, size_t size, size_t* at, double scale) {
  uint8_t b = *at < size ? data[(*at)++] : 0;
  return ((double)b - 128.0) / 128.0 * scale;
}

// Runs a program of calls; returns after `stop` ops (or the end).
static void run(side* s, const uint8_t* data, size_t size, size_t* at, uint32_t ops) {
  for (uint32_t op = 0; *at < size && op < ops; ++op) {
    uint8_t code = data[(*at)++] % 5;
    if (code == 0) {
      bk_vec3 p = {number(data, size, at, 4.0), number(data, size, at, 1.0), number(data, size, at, 1.0)};
      bk_runtime_damage_at(s->rt, p, 50.0 + 10.0 * fabs(number(data, size, at, 100.0)));
    } else if (code == 1) {
      bk_runtime_split(s->rt);
    } else if (code == 2) {
      bk_runtime_refine(s->rt);
    } else if (code == 3) {
      bk_cluster_id ids[64];
      uint32_t n = bk_runtime_clusters(s->rt, ids, 64);
      uint8_t pick = *at < size ? data[(*at)++] : 0;
      if (n > 1 && n <= 64) bk_runtime_remove_cluster(s->rt, ids[pick % n]);
    } else {
      bk_runtime_clear_events(s->rt);
    }
    take_events(s);
  }
}

static void program(const uint8_t* data, size_t size) {
  side* a = make_side();
  size_t at = 1;
  uint8_t damage = at < size ? data[at++] : 0;
  run(a, data, size, &at, 24);
  size_t saved_size = 0;
  uint8_t* saved = save(a, &saved_size);
  side* b = make_side();
  bk_error err = {0};
  if (!bk_runtime_load_state(b->rt, saved, saved_size, &err))
    bk_fuzz_fail("own state refused: %s", err.message);
  if (bk_runtime_state_hash(b->rt) != bk_runtime_state_hash(a->rt)) bk_fuzz_fail("load changed the hash");
  memcpy(b->states, a->states, sizeof a->states); // the caller's bodies where they were
  size_t at_b = at;
  run(a, data, size, &at, 24);
  run(b, data, size, &at_b, 24);
  if (bk_runtime_state_hash(b->rt) != bk_runtime_state_hash(a->rt)) bk_fuzz_fail("continuation diverged");
  if (damage) {
    saved[(size_t)damage * 131u % saved_size] ^= damage;
    if (damage & 1) fix_header(saved, saved_size);
    load(saved, saved_size);
  }
  free(saved);
  free_side(a);
  free_side(b);
}

static void write_seeds(const char* dir) {
  static const uint8_t programs[][12] = {
      {1, 0, 0, 0x80, 0x80, 0x80, 0xff, 2, 2, 1},
      {1, 0, 0, 0x70, 0x90, 0xc0, 0xff, 2, 0, 0x40, 0x80, 0xff},
      {1, 0, 0, 0x80, 0x80, 0x80, 0xff, 1, 3, 1, 2, 2},
  };
  for (size_t k = 0; k < sizeof programs / sizeof programs[0]; ++k) {
    side* s = make_side();
    size_t at = 2; // past the mode and the damage byte, as program() reads them
    run(s, programs[k], sizeof programs[k], &at, 24);
    size_t size = 0;
    uint8_t* bytes = save(s, &size);
    char path[512] = {0};
    FILE* f = NULL;
    if (size <= 16000) { // a refined one's is 300 KiB: the programs reach those
      snprintf(path, sizeof path, "%s/state_%zu.bin", dir, k);
      if (!(f = fopen(path, "wb"))) bk_fuzz_fail("cannot write %s", path);
      fputc(2, f);
      fwrite(bytes, 1, size, f);
      fclose(f);
    }
    snprintf(path, sizeof path, "%s/program_%zu.bin", dir, k);
    f = fopen(path, "wb");
    if (!f) bk_fuzz_fail("cannot write %s", path);
    fwrite(programs[k], 1, sizeof programs[k], f);
    fclose(f);
    free(bytes);
    free_side(s);
  }
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static bool seeded = false;
  const char* seeds = getenv("BK_FUZZ_STATE_SEEDS");
  if (seeds && !seeded) write_seeds(seeds), seeded = true;
  if (size == 0 || size > (1u << 20)) return 0;
  if (data[0] & 1) {
    program(data, size);
    return 0;
  }
  uint8_t* copy = malloc(size);
  memcpy(copy, data + 1, size - 1);
  if (data[0] & 2) fix_header(copy, size - 1);
  load(copy, size - 1);
  free(copy);
  return 0;
}
