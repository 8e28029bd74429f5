// sim --refine: the wall of 64 fragments refined where it is shot reports
// what refinement did (refined_leaves, leaves_final, refine_ms_p99 and
// refine_ms_max), the same run after run; --export-obj and --export-gltf
// write the first object's tree as it stands at the end (the refined one),
// checked before the run as fracture checks its files; bad values get one
// line naming the option.
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#define RUN_STDERR_PATH BK_TEST_TMP "/cli_refine_stderr.txt"
#include "run_exe.h"

#include "cli_util.h"
#include <breakables/authoring.h>

#define OBJ_PATH BK_TEST_TMP "/cli_refine_wall.obj"
#define GLB_PATH BK_TEST_TMP "/cli_refine_wall.glb"

// The JSON object without its timings (members whose name holds "_ms") and
// from_cache: what must be the same run after run.
static void without_timings(const char* json, char* out, size_t size) {
  size_t used = 0;
  const char* p = strchr(json, '{');
  ENSURE(p != NULL);
  ++p;
  while (*p && *p != '}') {
    while (*p == ' ' || *p == ',')
      ++p;
    const char* member = p;
    // The member's end: the next comma outside strings and brackets.
    int depth = 0;
    bool quoted = false;
    for (; *p; ++p) {
      if (*p == '"' && p[-1] != '\\') quoted = !quoted;
      if (quoted) continue;
      if (*p == '[' || *p == '{') depth++;
      if (*p == ']' || (*p == '}' && depth > 0))
        depth--;
      else if (*p == '}' && depth == 0)
        break;
      if (*p == ',' && depth == 0) break;
    }
    size_t length = (size_t)(p - member);
    char name[64] = "";
    const char* close = memchr(member + 1, '"', length > 1 ? length - 1 : 0);
    ENSURE(member[0] == '"' && close != NULL && (size_t)(close - member) < sizeof name);
    memcpy(name, member + 1, (size_t)(close - member - 1));
    if (strstr(name, "_ms") || strcmp(name, "from_cache") == 0) continue;
    ENSURE(used + length + 2 < size);
    memcpy(out + used, member, length);
    used += length;
    out[used++] = ';';
  }
  out[used] = 0;
}

static uint32_t obj_objects(const char* path) {
  FILE* f = fopen(path, "rb");
  ENSURE_MSG(f != NULL, "%s was not written", path);
  char line[512];
  uint32_t objects = 0;
  while (fgets(line, sizeof line, f))
    objects += strncmp(line, "o fragment_", 11) == 0;
  fclose(f);
  return objects;
}

static void test_refine_reports_and_repeats(void) {
  setenv("BREAKABLES_CACHE_DIR", BK_TEST_TMP "/cache", 1);
  unlink(OBJ_PATH);
  unlink(GLB_PATH);
  run_result* r = run("sim --scene wall --pieces 64 --refine --shots 3 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  static char first[sizeof run_result_storage.out], stripped[2][sizeof run_result_storage.out];
  memcpy(first, r->out, sizeof first);
  double refined = json_number(first, "refined_leaves"), leaves = json_number(first, "leaves_final");
  ENSURE_MSG(refined > 0 && leaves > 64, "refined %g, leaves %g", refined, leaves);
  // A refinement makes at least two pieces of a fragment.
  ENSURE(leaves >= 64 + refined);
  ENSURE(json_number(first, "pieces") == 64 && json_number(first, "mass_rel_error") < 1e-9);
  ENSURE(strstr(first, "\"nan\": false") != NULL);
  double p99 = json_number(first, "refine_ms_p99"), max = json_number(first, "refine_ms_max");
  ENSURE(p99 >= 0.0 && p99 <= max && max > 0.0);
  // The same run again, writing the tree: the same result but for the
  // timings (the files change nothing), and the files hold the tree of
  // leaves_final fragments (the wall is the scene's one object).
  r = run("sim --scene wall --pieces 64 --refine --shots 3 --json --export-obj " OBJ_PATH
          " --export-gltf " GLB_PATH);
  ENSURE_MSG(r->status == 0, "%s", r->err);
  without_timings(first, stripped[0], sizeof stripped[0]);
  without_timings(r->out, stripped[1], sizeof stripped[1]);
  ENSURE_MSG(strcmp(stripped[0], stripped[1]) == 0, "runs differ:\n%s\n%s", stripped[0], stripped[1]);
  ENSURE_MSG(obj_objects(OBJ_PATH) == (uint32_t)leaves, "%u objects, %g leaves", obj_objects(OBJ_PATH),
             leaves);
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_load_gltf(GLB_PATH, &tree, &err), "%s", err.message);
  ENSURE_MSG(tree.leaf_count == (uint32_t)leaves, "%u leaves loaded, %g reported", tree.leaf_count, leaves);
  ENSURE(tree.node_count > 2 * 64 - 1);
  bk_mesh_tree_free(&tree);
  // Without --refine: nothing refined, the tree as it was.
  r = run("sim --scene wall --pieces 64 --shots 3 --json --export-obj " OBJ_PATH);
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE(json_number(r->out, "refined_leaves") == 0 && json_number(r->out, "leaves_final") == 64);
  ENSURE(json_number(r->out, "refine_ms_max") == 0);
  ENSURE(obj_objects(OBJ_PATH) == 64);
  // The text report says what refinement did, and what was written.
  r = run("sim --scene wall --pieces 64 --refine-pieces 8 --shots 1 --steps 60 --export-obj " OBJ_PATH);
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE_MSG(strstr(r->out, "  refined ") && strstr(r->out, "  exported " OBJ_PATH), "%s", r->out);
  fprintf(stderr,
          "    wall x64, 3 shots: %g fragments refined, %g leaves at the end, refinement ms p99 %g max %g\n",
          refined, leaves, p99, max);
}

static void test_refine_errors(void) {
  expect_error("sim --refine-pieces 1", 2, "sim: --refine-pieces '1' is out of range (2..1024)");
  expect_error("sim --refine-pieces 2000", 2, "sim: --refine-pieces '2000' is out of range (2..1024)");
  expect_error("sim --refine-pieces abc", 2, "sim: --refine-pieces 'abc' is not a whole number (2..1024)");
  expect_error("sim --refine-pieces", 2, "--refine-pieces");
  expect_error("sim --refine --export-obj " BK_TEST_TMP "/wall.txt", 1,
               "--export-obj '" BK_TEST_TMP "/wall.txt': the file name must end in .obj");
  expect_error("sim --export-gltf " BK_TEST_TMP "/wall.obj", 1, "the file name must end in .glb or .gltf");
  expect_error("sim --export-obj " BK_TEST_TMP "/no/such/dir/wall.obj", 1, "no/such/dir");
  // The model it reads is never overwritten: refused before the run.
  write_file("cli_refine_model.obj",
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  expect_error("sim --mesh " BK_TEST_TMP "/cli_refine_model.obj --export-obj " BK_TEST_TMP
               "/cli_refine_model.obj",
               1, "is the file --mesh reads; refusing to overwrite it");
  FILE* f = fopen(BK_TEST_TMP "/cli_refine_model.obj", "rb");
  ENSURE(f != NULL);
  char head[8] = "";
  ENSURE(fread(head, 1, 7, f) == 7 && strncmp(head, "v 0 0 0", 7) == 0);
  fclose(f);
  run_result* r = run("sim --help");
  ENSURE(strstr(r->out, "--refine ") && strstr(r->out, "--refine-pieces N") &&
         strstr(r->out, "--export-obj") && strstr(r->out, "--export-gltf") && strstr(r->out, "leaves_final"));
}

int main(void) {
  test_refine_errors();
  test_refine_reports_and_repeats();
  return 0;
}
