// Saving and loading a world (bk_world_save_state, bk_world_load_state): a
// wall after three shots (bodies flying, a projectile in flight, a refined
// fragment) loads into a world built the same way with the saved world's
// state hash; a state is refused in one line by a world of other trees,
// leaving it as it was; and sim's --save-state/--load-state give, with
// --steps 0, the hashes of the run at the step it saved.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef BK_BREAKABLES_EXE // the command line's part, in a build with the executable
#define RUN_STDERR_PATH BK_TEST_TMP "/world_state_stderr.txt"
#include "run_exe.h"

#include "cli_util.h"
#endif
#include "ensure.h"
#include "shape_tree.h"
#include <breakables/bullet.h>

static bk_world* make_world(const bk_mesh_tree* tree) {
  bk_world_def def = bk_default_world_def();
  // With the stress stage, as the game runs: a refined, anchored wall once
  // made its coarser levels read past their group keys (caught here by ASan).
  def.stress = true;
  bk_error err = {0};
  bk_world* world = bk_world_create(&def, &err);
  ENSURE_MSG(world != NULL, "%s", err.message);
  bk_world_breakable_def bd = bk_default_world_breakable_def();
  bd.breakable.tree = tree;
  bd.breakable.anchored = true;
  bd.breakable.material = *bk_material_find("stone");
  bd.breakable.material.refine_strength = bd.breakable.material.bond_strength / 8.0;
  bd.breakable.refine =
      (bk_refine_def){.pattern = BK_PATTERN_RADIAL, .pieces = 16, .min_size = 0.02, .radial_falloff = 1.0};
  ENSURE_MSG(!bk_breakable_is_null(bk_world_add_breakable(world, &bd, &err)), "%s", err.message);
  return world;
}

static void shoot(bk_world* world, double x, double y) {
  bk_projectile_def p = bk_default_projectile_def();
  p.position = bk_v3(x, y, 3.0);
  p.velocity = bk_v3(0, 0, -60.0);
  p.mass = 8.0;
  bk_error err = {0};
  ENSURE_MSG(!bk_body_is_null(bk_world_fire(world, &p, &err)), "%s", err.message);
}

static uint8_t* save(const bk_world* world, size_t* size) {
  *size = bk_world_state_size(world);
  uint8_t* bytes = malloc(*size);
  bk_error err = {0};
  ENSURE_MSG(bk_world_save_state(world, bytes, *size, &err) == *size, "%s", err.message);
  return bytes;
}

static void test_world_round_trip(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_WALL, 48, 3000), other_tree = make_tree(BK_SHAPE_WALL, 40, 3000);
  bk_world* a = make_world(&tree);
  const double xs[3] = {-0.5, 0.4, 0.0}, ys[3] = {1.0, 1.4, 0.6};
  for (int shot = 0; shot < 3; ++shot) {
    shoot(a, xs[shot], ys[shot]);
    for (int s = 0; s < 30; ++s)
      bk_world_step(a);
  }
  shoot(a, 0.2, 1.8); // in flight at the save
  bk_world_step(a);
  bk_world_stats stats = bk_world_get_stats(a);
  ENSURE(stats.bodies > 3 && bk_world_projectile_count(a) >= 1);
  size_t size = 0;
  uint8_t* bytes = save(a, &size);
  uint64_t hash = bk_world_state_hash(a);

  bk_world* b = make_world(&tree);
  ENSURE(bk_world_state_hash(b) != hash);
  bk_error err = {0};
  ENSURE_MSG(bk_world_load_state(b, bytes, size, &err), "%s", err.message);
  ENSURE(bk_world_state_hash(b) == hash);
  ENSURE(bk_runtime_state_hash(bk_world_runtime(b)) == bk_runtime_state_hash(bk_world_runtime(a)));
  ENSURE(bk_world_get_stats(b).bodies == stats.bodies);
  ENSURE(bk_world_projectile_count(b) == bk_world_projectile_count(a));
  // Saved again: the same bytes.
  size_t again_size = 0;
  uint8_t* again = save(b, &again_size);
  ENSURE(again_size == size && memcmp(again, bytes, size) == 0);
  free(again);
  // Both go on: Bullet's caches are not state, so they may drift, but
  // nothing is lost and the loaded world steps as a world does.
  for (int s = 0; s < 60; ++s) {
    bk_world_step(a);
    bk_world_step(b);
  }
  bk_world_stats sa = bk_world_get_stats(a), sb = bk_world_get_stats(b);
  ENSURE(!sb.nan && sb.bodies > 3);
  fprintf(
      stderr,
      "after 60 more steps: bodies %u and %u, bonds broken %u and %u, runtime hashes %s, world hashes %s\n",
      sa.bodies, sb.bodies, sa.bonds_broken, sb.bonds_broken,
      bk_runtime_state_hash(bk_world_runtime(a)) == bk_runtime_state_hash(bk_world_runtime(b)) ? "equal"
                                                                                               : "differ",
      bk_world_state_hash(a) == bk_world_state_hash(b) ? "equal" : "differ");
  // Loaded back into the world that went on: as saved.
  ENSURE_MSG(bk_world_load_state(a, bytes, size, &err), "%s", err.message);
  ENSURE(bk_world_state_hash(a) == hash);

  // Refused by a world of another tree, in one line, leaving it as it was.
  bk_world* c = make_world(&other_tree);
  uint64_t before = bk_world_state_hash(c);
  ENSURE(!bk_world_load_state(c, bytes, size, &err));
  ENSURE_MSG(strncmp(err.message, "state: breakable 0 is another tree: ", 36) == 0 &&
                 !strchr(err.message, '\n'),
             "%s", err.message);
  ENSURE(bk_world_state_hash(c) == before);
  // Damaged: refused, nothing changed.
  bytes[size / 2] ^= 4;
  before = bk_world_state_hash(b);
  ENSURE(!bk_world_load_state(b, bytes, size, &err));
  ENSURE_MSG(strcmp(err.message, "world state: checksum mismatch (the state is corrupt)") == 0, "%s",
             err.message);
  ENSURE(bk_world_state_hash(b) == before);
  ENSURE(!bk_world_load_state(b, bytes, 20, &err) && strstr(err.message, "world state: truncated header"));
  free(bytes);
  bk_world_destroy(a);
  bk_world_destroy(b);
  bk_world_destroy(c);
  bk_mesh_tree_free(&tree);
  bk_mesh_tree_free(&other_tree);
}

#ifdef BK_BREAKABLES_EXE
static void json_hex(const char* json, const char* key, char out[17]) {
  char pattern[64];
  snprintf(pattern, sizeof pattern, "\"%s\": \"", key);
  const char* at = strstr(json, pattern);
  ENSURE_MSG(at && strlen(at) >= strlen(pattern) + 16, "key %s missing in %s", key, json);
  memcpy(out, at + strlen(pattern), 16);
  out[16] = 0;
}

static void test_cli(void) {
  const char* path = BK_TEST_TMP "/wall150.bkstate";
  const char* tower = BK_TEST_TMP "/tower.bkstate";
  remove(path);
  // Saved at step 150 of the wall's 300: the hashes --hash-every prints there.
  run_result* r =
      run("sim --scene wall --save-state " BK_TEST_TMP "/wall150.bkstate --at 150 --hash-every 150 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE(json_number(r->out, "state_bytes") > 1000);
  char state[17] = {0}, world[17] = {0};
  const char* line = strstr(r->err, "step 150 state_hash ");
  ENSURE_MSG(line && sscanf(line, "step 150 state_hash %16s world_hash %16s", state, world) == 2, "%s",
             r->err);
  FILE* f = fopen(path, "rb");
  ENSURE(f != NULL);
  fseek(f, 0, SEEK_END);
  ENSURE((double)ftell(f) == json_number(r->out, "state_bytes"));
  fclose(f);
  r = run("sim --scene wall --load-state " BK_TEST_TMP "/wall150.bkstate --steps 0 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  char got_state[17], got_world[17];
  json_hex(r->out, "state_hash", got_state);
  json_hex(r->out, "world_hash", got_world);
  ENSURE_MSG(strcmp(got_state, state) == 0 && strcmp(got_world, world) == 0, "loaded %s %s, saved %s %s",
             got_state, got_world, state, world);
  // Saved at the end of a 150-step run (no --at): that run's hashes.
  r = run("sim --scene wall --steps 150 --save-state " BK_TEST_TMP "/wall_end.bkstate --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  json_hex(r->out, "state_hash", state);
  json_hex(r->out, "world_hash", world);
  r = run("sim --scene wall --load-state " BK_TEST_TMP "/wall_end.bkstate --steps 0 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  json_hex(r->out, "state_hash", got_state);
  json_hex(r->out, "world_hash", got_world);
  ENSURE(strcmp(got_state, state) == 0 && strcmp(got_world, world) == 0);
  // A tower's state in the wall: refused in one line, exit 1.
  r = run("sim --scene tower --steps 20 --save-state " BK_TEST_TMP "/tower.bkstate --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  r = run("sim --scene wall --load-state " BK_TEST_TMP "/tower.bkstate --steps 0");
  ENSURE(r->status == 1);
  char expected[256];
  snprintf(expected, sizeof expected,
           "breakables sim: --load-state %s: state: breakable 0 is another tree: ", tower);
  ENSURE_MSG(strncmp(r->err, expected, strlen(expected)) == 0, "%s", r->err);
  ENSURE_MSG(strchr(r->err, '\n') == r->err + strlen(r->err) - 1, "%s", r->err);
  // The options' own checks.
  expect_error("sim --scene wall --steps 0", 2,
               "breakables sim: --steps 0 needs --load-state (the state to report)");
  expect_error("sim --scene wall --at 5", 2, "breakables sim: --at needs --save-state");
  expect_error("sim --scene wall --steps 10 --at 20 --save-state " BK_TEST_TMP "/x.bkstate", 2,
               "breakables sim: --at 20 is past the run's 10 steps");
  expect_error("sim --scene wall --save-state " BK_TEST_TMP "/x.state", 1, "--save-state");
  remove(path);
  remove(tower);
  remove(BK_TEST_TMP "/wall_end.bkstate");
}
#endif

int main(void) {
  test_world_round_trip();
#ifdef BK_BREAKABLES_EXE
  test_cli();
#endif
  return 0;
}
