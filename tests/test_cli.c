// The breakables command line, run as a user would: help texts, JSON
// output, files written, and one-line errors with the right exit codes.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "bk_fracture.h"
#include "ensure.h"

typedef struct run_result {
  int status;
  char out[1 << 16];
  char err[1 << 14];
} run_result;

static run_result result;

// Runs the executable with a shell argument string; captures stdout and stderr.
static run_result* run(const char* args) {
  char command[2048];
  snprintf(command, sizeof command, "'%s' %s 2>'%s/stderr.txt'", BK_BREAKABLES_EXE, args, BK_TEST_TMP);
  FILE* pipe = popen(command, "r");
  ENSURE(pipe != NULL);
  size_t n = fread(result.out, 1, sizeof result.out - 1, pipe);
  result.out[n] = 0;
  int status = pclose(pipe);
  result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  char path[512];
  snprintf(path, sizeof path, "%s/stderr.txt", BK_TEST_TMP);
  FILE* err = fopen(path, "rb");
  ENSURE(err != NULL);
  n = fread(result.err, 1, sizeof result.err - 1, err);
  result.err[n] = 0;
  fclose(err);
  return &result;
}

static void write_file(const char* name, const char* text) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", BK_TEST_TMP, name);
  FILE* f = fopen(path, "wb");
  ENSURE(f != NULL);
  fputs(text, f);
  fclose(f);
}

static double json_number(const char* json, const char* key) {
  char pattern[64];
  snprintf(pattern, sizeof pattern, "\"%s\": ", key);
  const char* at = strstr(json, pattern);
  ENSURE_MSG(at != NULL, "key %s missing in %s", key, json);
  return strtod(at + strlen(pattern), NULL);
}

static void test_help(void) {
  run_result* r = run("--help");
  ENSURE(r->status == 0 && strstr(r->out, "fracture") != NULL);
  r = run("fracture --help");
  ENSURE(r->status == 0);
  const char* options[] = {"--mesh", "--pieces",     "--seed", "--texture-scale",
                           "--out",  "--export-obj", "--json"};
  for (size_t i = 0; i < sizeof options / sizeof *options; ++i)
    ENSURE_MSG(strstr(r->out, options[i]) != NULL, "help does not describe %s", options[i]);
  r = run("explode");
  ENSURE(r->status == 2 && strstr(r->err, "unknown command 'explode'") != NULL);
}

static void test_json(void) {
  run_result* r = run("fracture --mesh cube --pieces 64 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  const char* keys[] = {
      "\"mesh\": \"cube\"", "\"pieces\": 64", "\"nodes\": 127",       "\"max_depth\"",       "\"ms\"",
      "\"leaf_triangles\"", "\"bonds\"",      "\"watertight\": true", "\"volume_rel_error\""};
  for (size_t i = 0; i < sizeof keys / sizeof *keys; ++i)
    ENSURE_MSG(strstr(r->out, keys[i]) != NULL, "missing %s in %s", keys[i], r->out);
  ENSURE(json_number(r->out, "volume_rel_error") < 1e-9);
  ENSURE(json_number(r->out, "bonds") >= 63);
  ENSURE(strchr(r->err, '\r') == NULL); // no progress bar when stderr is not a terminal
  // Defaults: the bunny, 256 pieces, seed 3000.
  r = run("fracture --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE(strstr(r->out, "\"mesh\": \"bunny\"") && strstr(r->out, "\"seed\": 3000") &&
         json_number(r->out, "pieces") >= 256 && strstr(r->out, "\"watertight\": true"));
}

static void test_files(void) {
  run_result* r = run("fracture --mesh torus --pieces 8 --seed 9 --out '" BK_TEST_TMP
                      "/a.mtree' --export-obj '" BK_TEST_TMP "/a.obj'");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_load(BK_TEST_TMP "/a.mtree", &tree, &err), "%s", err.message);
  ENSURE(tree.leaf_count >= 8 && tree.desc.seed == 9);
  // The OBJ holds one object per fragment, together the whole torus.
  FILE* f = fopen(BK_TEST_TMP "/a.obj", "rb");
  ENSURE(f != NULL);
  char line[256];
  uint32_t objects = 0;
  while (fgets(line, sizeof line, f))
    if (strncmp(line, "o fragment_", 11) == 0) objects++;
  fclose(f);
  ENSURE(objects == tree.leaf_count);
  bk_mesh all = {0};
  ENSURE_MSG(bk_obj_load(BK_TEST_TMP "/a.obj", &all, &err), "%s", err.message);
  ENSURE_REL(bk_mesh_volume(&all), tree.nodes[0].moments.v, 1e-9);
  bk_mesh_free(&all);
  bk_mesh_tree_free(&tree);

  // --pieces 1 exports the source mesh itself.
  r = run("fracture --mesh cube --pieces 1 --export-obj '" BK_TEST_TMP "/one.obj'");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE(bk_obj_load(BK_TEST_TMP "/one.obj", &all, &err));
  ENSURE(all.triangle_count == 12 && all.position_count == 8);
  ENSURE_REL(bk_mesh_volume(&all), 1.0, 1e-12);
  bk_mesh_free(&all);
}

static void test_same_seed_same_file(void) {
  ENSURE(run("fracture --mesh eggshell --pieces 32 --seed 4 --out '" BK_TEST_TMP "/s1.mtree'")->status == 0);
  ENSURE(run("fracture --mesh eggshell --pieces 32 --seed 4 --out '" BK_TEST_TMP "/s2.mtree'")->status == 0);
  ENSURE(run("fracture --mesh eggshell --pieces 32 --seed 5 --out '" BK_TEST_TMP "/s3.mtree'")->status == 0);
  ENSURE(system("cmp -s '" BK_TEST_TMP "/s1.mtree' '" BK_TEST_TMP "/s2.mtree'") == 0);
  ENSURE(system("cmp -s '" BK_TEST_TMP "/s1.mtree' '" BK_TEST_TMP "/s3.mtree'") != 0);
}

static void expect_error(const char* args, int status, const char* message) {
  run_result* r = run(args);
  ENSURE_MSG(r->status == status, "'%s' exited %d, expected %d (%s)", args, r->status, status, r->err);
  ENSURE_MSG(strstr(r->err, message) != NULL, "'%s': expected '%s' in: %s", args, message, r->err);
  // One line, naming the problem.
  const char* newline = strchr(r->err, '\n');
  ENSURE_MSG(newline && newline[1] == 0, "'%s': error is not one line: %s", args, r->err);
}

static void test_errors(void) {
  expect_error("fracture --pieces 0", 2, "--pieces must be a whole number from 1 to 1048576");
  expect_error("fracture --pieces 12abc", 2, "--pieces must be");
  expect_error("fracture --pieces", 2, "--pieces needs a value");
  expect_error("fracture --texture-scale nan", 2, "--texture-scale must be a positive finite number");
  expect_error("fracture --texture-scale -1", 2, "--texture-scale must be");
  expect_error("fracture --seed -3", 2, "--seed must be");
  expect_error("fracture --bogus", 2, "unknown option '--bogus'");
  expect_error("fracture --mesh sphere", 1, "unknown mesh 'sphere'");
  expect_error("fracture --mesh '" BK_TEST_TMP "/missing.obj'", 1, "cannot open");
  write_file("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1\nf 1 2 3\n");
  expect_error("fracture --mesh '" BK_TEST_TMP "/bad.obj'", 1, "bad.obj:3:");
  write_file("nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n");
  expect_error("fracture --mesh '" BK_TEST_TMP "/nan.obj'", 1, "nan.obj:2:");
  // Two triangles sharing an edge in the same direction: cannot be repaired.
  write_file("twisted.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n");
  expect_error("fracture --mesh '" BK_TEST_TMP "/twisted.obj'", 1, "not watertight");
  expect_error("fracture --mesh cube --out /nonexistent-dir/x.mtree", 1, "cannot write");
}

// A cube missing one face (two triangles): the hole is closed with a warning.
static void test_repairs_simple_hole(void) {
  write_file("open_cube.obj",
             "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
             "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\n");
  run_result* r = run("fracture --mesh '" BK_TEST_TMP "/open_cube.obj' --pieces 16 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE_MSG(strstr(r->err, "warning") && strstr(r->err, "closed 1 hole") && strstr(r->err, "4 open edges"),
             "%s", r->err);
  ENSURE(strstr(r->out, "\"watertight\": true") != NULL);
}

static void test_sim(void) {
  setenv("BREAKABLES_CACHE_DIR", BK_TEST_TMP "/cache", 1);
  run_result* r = run("sim --scene wall --pieces 64 --shots 2 --steps 150 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  const char* keys[] = {"scene",
                        "pieces",
                        "bodies_initial",
                        "bodies_final",
                        "break_events",
                        "bonds_broken",
                        "colliders_initial",
                        "colliders_final",
                        "colliders_naive_final",
                        "step_ms_median",
                        "step_ms_max",
                        "break_ms_median",
                        "break_ms_max",
                        "mass_rel_error",
                        "nan"};
  for (size_t i = 0; i < sizeof keys / sizeof *keys; ++i) {
    char quoted[64];
    snprintf(quoted, sizeof quoted, "\"%s\"", keys[i]);
    ENSURE_MSG(strstr(r->out, quoted) != NULL, "missing %s in %s", keys[i], r->out);
  }
  ENSURE(strstr(r->out, "\"nan\": false") && json_number(r->out, "mass_rel_error") < 1e-9);
  ENSURE(json_number(r->out, "bodies_initial") == 1 && json_number(r->out, "colliders_initial") == 1);
  ENSURE(json_number(r->out, "bodies_final") > 1 && json_number(r->out, "bonds_broken") > 0);
  ENSURE(json_number(r->out, "colliders_final") < json_number(r->out, "colliders_naive_final"));
  // The second run loads the mesh tree from the cache, and gives the same result.
  char first[sizeof result.out];
  memcpy(first, r->out, sizeof first);
  r = run("sim --scene wall --pieces 64 --shots 2 --steps 150 --json");
  ENSURE(strstr(r->out, "\"from_cache\": true") != NULL);
  ENSURE(json_number(r->out, "bonds_broken") == json_number(first, "bonds_broken"));
  ENSURE(json_number(r->out, "bodies_final") == json_number(first, "bodies_final"));
  // Plain BCRB: one collider per fragment.
  r = run("sim --scene wall --pieces 64 --shots 2 --steps 150 --naive --json");
  ENSURE(json_number(r->out, "colliders_final") == json_number(r->out, "colliders_naive_final"));
  r = run("sim --help");
  const char* options[] = {"--scene",   "--pieces",  "--seed",     "--shots",      "--steps", "--speed",
                           "--frailty", "--density", "--discrete", "--accumulate", "--naive", "--json"};
  for (size_t i = 0; i < sizeof options / sizeof *options; ++i)
    ENSURE_MSG(strstr(r->out, options[i]) != NULL, "sim help does not describe %s", options[i]);
  expect_error("sim --scene castle", 2, "unknown scene 'castle'");
  expect_error("sim --steps 0", 2, "--steps must be a whole number from 1 to 1000000");
  expect_error("sim --frailty nan", 2, "--frailty must be a positive number");
  expect_error("sim --density -5", 2, "--density must be a positive number");
  expect_error("sim --explode", 2, "unknown option '--explode'");
}

int main(void) {
  RUN(test_help);
  RUN(test_json);
  RUN(test_files);
  RUN(test_same_seed_same_file);
  RUN(test_errors);
  RUN(test_repairs_simple_hole);
  RUN(test_sim);
  return 0;
}
