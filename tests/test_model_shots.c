// The shots at a user's model (--mesh) are weighed on the model, so that a
// few of them break it whatever its size. The rock of assimp-testmodels
// (3DS/fels.3ds, 4.7 m across, 89 t of stone) stood whole after three
// shots of a steel ball a twentieth of its size; the same ball shatters a
// pebble and bounces off a bigger rock, as what breaks a bond grows with
// the size to the fifth power and a ball's weight with its cube. Each
// size here must lose bonds and pieces to three shots: the rock as it is,
// shrunk to 4.7 cm and grown to 23 m (--scale).
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ensure.h"

#define RUN_STDERR_PATH BK_TEST_TMP "/test_model_shots_stderr.txt"
#include "run_exe.h"
// run_exe.h first: cli_util.h's expect_error runs the command.
#include "cli_util.h"

#define ROCK "/usr/share/assimp/models/3DS/fels.3ds"

static void expect_breaks(const char* scale) {
  char args[512];
  snprintf(args, sizeof args, "sim --mesh " ROCK " --shots 3 --scale %s --json", scale);
  run_result* r = run(args);
  ENSURE_MSG(r->status == 0, "%s: exit %d: %s", args, r->status, r->err);
  const char* json = strchr(r->out, '{');
  ENSURE_MSG(json != NULL, "%s: no JSON in %s", args, r->out);
  double broken = json_number(json, "bonds_broken"), free = json_number(json, "fragments_free");
  printf("--scale %s: %.0f bonds broken, %.0f fragments free, %.0f bodies\n", scale, broken, free,
         json_number(json, "bodies_final"));
  ENSURE_MSG(broken > 0 && free > 0, "%s: %.0f bonds broken, %.0f fragments free", args, broken, free);
  ENSURE(strstr(json, "\"nan\": false") && json_number(json, "mass_rel_error") < 1e-9);
}

int main(void) {
  FILE* f = fopen(ROCK, "rb");
  ENSURE_MSG(f != NULL, "%s is missing: scripts/setup.sh installs assimp-testmodels", ROCK);
  fclose(f);
  setenv("BREAKABLES_CACHE_DIR", BK_TEST_TMP "/model_shots_cache", 1);
  expect_breaks("1");
  expect_breaks("0.01");
  expect_breaks("5");
  puts("test_model_shots: ok");
  return 0;
}
