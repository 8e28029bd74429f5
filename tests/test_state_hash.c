// State hashes (bk_runtime_state_hash, bk_world_state_hash): the same calls
// give the same hash and a different call another, in the runtime alone;
// sim's runs give the hashes committed in tests/state_hashes.txt in every
// build (GCC and clang, Release and Debug with sanitizers: CI runs this
// under clang's ASan and UBSan, the values come from GCC's Release), and
// --hash-every prints them as the run goes.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define RUN_STDERR_PATH BK_TEST_TMP "/state_hash_stderr.txt"
#include "run_exe.h"

#include "cli_util.h"
#include "runtime_caller.h"
#include "shape_tree.h"

static uint64_t hash_after(const bk_mesh_tree* tree, bk_vec3 point, double impulse, uint32_t splits) {
  bodies* b = calloc(1, sizeof *b);
  bk_runtime_def def = bk_default_runtime_def();
  def.body_state = body_state;
  def.context = b;
  bk_runtime* rt = bk_runtime_create(&def, NULL);
  bk_breakable_def bdef = bk_default_breakable_def();
  bdef.tree = tree;
  bk_runtime_add_breakable(rt, &bdef, NULL);
  take_created(rt, b);
  bk_runtime_damage_at(rt, point, impulse);
  for (uint32_t i = 0; i < splits; ++i) {
    bk_runtime_split(rt);
    take_created(rt, b);
  }
  uint64_t hash = bk_runtime_state_hash(rt);
  bk_runtime_destroy(rt);
  free(b);
  return hash;
}

static void test_runtime(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 64, 3000);
  bk_vec3 p = {0.5, 0.1, 0.2};
  uint64_t a = hash_after(&tree, p, 2000.0, 1), again = hash_after(&tree, p, 2000.0, 1);
  ENSURE(a == again);
  ENSURE(hash_after(&tree, p, 2100.0, 1) != a);                     // other hit points left
  ENSURE(hash_after(&tree, bk_v3(0.5, 0.1, -0.2), 2000.0, 1) != a); // other bonds broken
  ENSURE(hash_after(&tree, p, 2000.0, 0) != a);                     // the split still waiting
  ENSURE(hash_after(&tree, p, 1e-9, 1) != a);                       // nothing broke
  bk_mesh_tree_free(&tree);
}

// The JSON string value of key.
static void json_hex(const char* json, const char* key, char out[17]) {
  char pattern[64];
  snprintf(pattern, sizeof pattern, "\"%s\": \"", key);
  const char* at = strstr(json, pattern);
  ENSURE_MSG(at && strlen(at) >= strlen(pattern) + 16, "key %s missing in %s", key, json);
  memcpy(out, at + strlen(pattern), 16);
  out[16] = 0;
}

static void test_sim_hashes(void) {
  FILE* f = fopen(BK_ASSET_DIR "/../tests/state_hashes.txt", "r");
  ENSURE(f != NULL);
  char line[256];
  uint32_t checked = 0;
  while (fgets(line, sizeof line, f)) {
    char scene[32] = {0}, state[17] = {0}, world[17] = {0};
    if (line[0] == '#' || sscanf(line, "%31s %16s %16s", scene, state, world) != 3) continue;
    char args[128];
    snprintf(args, sizeof args, "sim --scene %s --json", scene);
    run_result* r = run(args);
    ENSURE_MSG(r->status == 0, "%s: %s", args, r->err);
    char got_state[17], got_world[17];
    json_hex(r->out, "state_hash", got_state);
    json_hex(r->out, "world_hash", got_world);
    ENSURE_MSG(strcmp(got_state, state) == 0 && strcmp(got_world, world) == 0,
               "%s: state_hash %s world_hash %s, expected %s %s (tests/state_hashes.txt)", scene, got_state,
               got_world, state, world);
    checked++;
  }
  fclose(f);
  ENSURE(checked >= 2);
}

// The trees' bytes too: fracture builds them afresh (no cache), and their
// hash must be the committed one on every build.
static void test_tree_hashes(void) {
  FILE* f = fopen(BK_ASSET_DIR "/../tests/tree_hashes.txt", "r");
  ENSURE(f != NULL);
  char line[256];
  uint32_t checked = 0;
  while (fgets(line, sizeof line, f)) {
    char hash[17] = {0};
    if (line[0] == '#' || sscanf(line, "%16s", hash) != 1) continue;
    line[strcspn(line, "\n")] = 0;
    char args[300];
    snprintf(args, sizeof args, "fracture %s --json", line + 17);
    run_result* r = run(args);
    ENSURE_MSG(r->status == 0, "%s: %s", args, r->err);
    char got[17];
    json_hex(r->out, "tree_hash", got);
    ENSURE_MSG(strcmp(got, hash) == 0, "%s: tree_hash %s, expected %s (tests/tree_hashes.txt)", args, got,
               hash);
    checked++;
  }
  fclose(f);
  ENSURE(checked >= 4);
}

static void test_hash_every(void) {
  run_result* r = run("sim --scene wall --steps 120 --hash-every 40 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  char state[17], world[17];
  json_hex(r->out, "state_hash", state);
  json_hex(r->out, "world_hash", world);
  // Three lines on stderr (stdout is the JSON object alone), the last the end's.
  ENSURE_MSG(count_lines(r->err) == 3, "%s", r->err);
  char last[128];
  snprintf(last, sizeof last, "step 120 state_hash %s world_hash %s\n", state, world);
  ENSURE_MSG(strstr(r->err, "step 40 state_hash ") && strstr(r->err, last), "%s", r->err);
  expect_error("sim --scene wall --hash-every 0", 2, "--hash-every");
}

int main(void) {
  // The scenes' trees are built by this build, not read from a cache
  // another build wrote.
  char cache[] = BK_TEST_TMP "/state_hash_cache";
  ENSURE(system("rm -rf '" BK_TEST_TMP "/state_hash_cache'") == 0);
  setenv("BREAKABLES_CACHE_DIR", cache, 1);
  test_runtime();
  test_tree_hashes();
  test_sim_hashes();
  test_hash_every();
  printf("state hash ok\n");
  return 0;
}
