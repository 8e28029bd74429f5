// Determinism: the same seed gives a byte-identical .mtree, built twice in one
// process (with another build in between) and by two runs of the CLI, and two
// `sim --json` runs report the same results apart from their timings; any
// thread count builds the same tree. A different seed must give a different
// tree, so none of this passes vacuously.
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bk_fracture.h"
#include "ensure.h"
#include "tree_bytes.h"

// Everything this test writes lives here (other tests share BK_TEST_TMP and run in parallel).
#define TEST_DIR BK_TEST_TMP "/determinism"

static void make_fresh_dir(const char* path) {
  char command[1024];
  snprintf(command, sizeof command, "rm -rf '%s'", path);
  ENSURE(system(command) == 0);
  ENSURE_MSG(mkdir(path, 0755) == 0, "%s: %s", path, strerror(errno));
}

static uint8_t* read_all(const char* path, size_t* size) {
  void* data = NULL;
  bk_error err = {{0}};
  ENSURE_MSG(bk_file_read(path, (uint64_t)1 << 30, "1 GiB", &data, size, &err), "%s", err.message);
  return data;
}

static bool same_file(const char* a, const char* b) {
  size_t size_a = 0, size_b = 0;
  uint8_t *data_a = read_all(a, &size_a), *data_b = read_all(b, &size_b);
  bool same = size_a == size_b && memcmp(data_a, data_b, size_a) == 0;
  free(data_a);
  free(data_b);
  return same;
}

#ifdef BK_BREAKABLES_EXE // the CLI's side runs where the demo is built (CI always builds it)
// Runs the executable (arguments as shell words) and returns its stdout
// (static buffer); stderr goes to a file and is printed if the run fails.
static const char* run(const char* args) {
  static char out[1 << 16];
  char command[2048];
  snprintf(command, sizeof command, "'%s' %s 2>'%s/stderr.txt'", BK_BREAKABLES_EXE, args, TEST_DIR);
  FILE* pipe = popen(command, "r");
  ENSURE(pipe != NULL);
  size_t n = fread(out, 1, sizeof out - 1, pipe);
  out[n] = 0;
  int status = pclose(pipe);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    size_t size = 0;
    uint8_t* err = read_all(TEST_DIR "/stderr.txt", &size);
    fprintf(stderr, "'breakables %s' failed:\n%.*s\n", args, (int)size, (const char*)err);
    free(err);
    exit(1);
  }
  return out;
}
#endif

// ---------------------------------------------------------------- .mtree

static void build_and_save(const bk_mesh* mesh, uint64_t seed, const char* path) {
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = 64;
  desc.seed = seed;
  bk_mesh_tree tree = {0};
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_build(mesh, &desc, &tree, &err), "%s", err.message);
  ENSURE(tree.leaf_count >= 64);
  ENSURE_MSG(bk_mesh_tree_save(&tree, path, &err), "%s", err.message);
  bk_mesh_tree_free(&tree);
}

// The eggshell has a cavity and curved faces: every part of the build (cuts,
// caps with holes, hull separation, bonds) has to be deterministic for it.
static void test_same_seed_same_tree_in_process(void) {
  bk_mesh egg = {0};
  bk_shape_build(BK_SHAPE_EGGSHELL, &egg);
  build_and_save(&egg, 7, TEST_DIR "/a.mtree");
  build_and_save(&egg, 8, TEST_DIR "/other_seed.mtree"); // and any state it leaves behind
  build_and_save(&egg, 7, TEST_DIR "/b.mtree");
  bk_mesh_free(&egg);
  ENSURE_MSG(same_file(TEST_DIR "/a.mtree", TEST_DIR "/b.mtree"), "seed 7 built twice gives different files");
  ENSURE_MSG(!same_file(TEST_DIR "/a.mtree", TEST_DIR "/other_seed.mtree"),
             "seeds 7 and 8 give the same file");
}

static bk_mesh_tree build_with_threads(const bk_mesh* mesh, bk_fracture_def desc, uint32_t threads) {
  desc.threads = threads;
  bk_mesh_tree tree = {0};
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_build(mesh, &desc, &tree, &err), "%s", err.message);
  ENSURE_MSG(tree.leaf_count == desc.pieces, "%u of %u pieces", tree.leaf_count, desc.pieces);
  return tree;
}

// The planes and brick builds split leaves ahead on every thread and take
// them in one order: one, two and three threads give the same bytes (nodes,
// planes, bonds). The concave torus and the hollow eggshell make cuts that
// pass the count near the end, which are made again; the wall's brick bond
// takes the other queue. A different seed differs, so this is not vacuous.
static void test_any_thread_count_same_tree(void) {
  static const bk_shape shapes[] = {BK_SHAPE_TORUS, BK_SHAPE_EGGSHELL, BK_SHAPE_WALL};
  for (size_t i = 0; i < sizeof shapes / sizeof shapes[0]; ++i) {
    bk_mesh mesh = {0};
    bk_shape_build(shapes[i], &mesh);
    bk_fracture_def desc = bk_default_fracture_def();
    desc.pieces = 700;
    if (shapes[i] == BK_SHAPE_WALL) {
      desc.pattern = BK_PATTERN_BRICK;
      desc.brick_size = bk_v3(0.25, 0.125, 0.0);
    }
    bk_mesh_tree one = build_with_threads(&mesh, desc, 1);
    for (uint32_t threads = 2; threads <= 3; ++threads) {
      bk_mesh_tree many = build_with_threads(&mesh, desc, threads);
      ENSURE_MSG(trees_same_bytes(&one, &many), "%s: %u threads give another tree than one",
                 bk_shape_name(shapes[i]), threads);
      bk_mesh_tree_free(&many);
    }
    desc.seed++;
    bk_mesh_tree other = build_with_threads(&mesh, desc, 2);
    ENSURE(!trees_same_bytes(&one, &other));
    bk_mesh_tree_free(&other);
    bk_mesh_tree_free(&one);
    bk_mesh_free(&mesh);
  }
}

#ifdef BK_BREAKABLES_EXE
static void test_same_seed_same_tree_from_the_cli(void) {
  run("fracture --mesh eggshell --pieces 64 --seed 7 --out '" TEST_DIR "/cli1.mtree'");
  run("fracture --mesh eggshell --pieces 64 --seed 7 --out '" TEST_DIR "/cli2.mtree'");
  run("fracture --mesh eggshell --pieces 64 --seed 8 --out '" TEST_DIR "/cli3.mtree'");
  ENSURE_MSG(same_file(TEST_DIR "/cli1.mtree", TEST_DIR "/cli2.mtree"),
             "two CLI runs with seed 7 give different files");
  ENSURE_MSG(!same_file(TEST_DIR "/cli1.mtree", TEST_DIR "/cli3.mtree"),
             "CLI seeds 7 and 8 give the same file");
  // Another process, same parameters: the CLI's tree is the library's tree.
  ENSURE_MSG(same_file(TEST_DIR "/cli1.mtree", TEST_DIR "/a.mtree"),
             "the CLI and the library give different files");
}

// ---------------------------------------------------------------- sim --json

enum { MAX_FIELDS = 64 };

typedef struct json_field {
  char key[64];
  char value[256]; // the value's raw text
} json_field;

typedef struct json_object {
  json_field fields[MAX_FIELDS];
  uint32_t count;
} json_object;

static const char* skip_blank(const char* p) {
  while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')
    p++;
  return p;
}

// End of the JSON value starting at p (a string, a number or literal, or a
// nested array or object, kept as raw text).
static const char* value_end(const char* p) {
  int depth = 0;
  bool in_string = false;
  for (; *p; ++p) {
    if (in_string) {
      if (*p == '\\' && p[1])
        p++;
      else if (*p == '"')
        in_string = false;
    } else if (*p == '"') {
      in_string = true;
    } else if (*p == '[' || *p == '{') {
      depth++;
    } else if (*p == ']' || *p == '}') {
      if (depth == 0) return p;
      depth--;
    } else if (*p == ',' && depth == 0) {
      return p;
    }
  }
  return p;
}

// Parses one flat-ish JSON object {"key": value, ...} of the CLI's output.
static void parse_object(const char* text, json_object* out) {
  memset(out, 0, sizeof *out);
  const char* p = skip_blank(text);
  ENSURE_MSG(*p == '{', "not a JSON object: %s", text);
  p = skip_blank(p + 1);
  while (*p != '}') {
    ENSURE_MSG(*p == '"' && out->count < MAX_FIELDS, "bad key at '%.20s' in %s", p, text);
    const char* key = p + 1;
    const char* key_end = strchr(key, '"');
    ENSURE(key_end != NULL && (size_t)(key_end - key) < sizeof out->fields[0].key);
    json_field* f = &out->fields[out->count++];
    memcpy(f->key, key, (size_t)(key_end - key));
    p = skip_blank(key_end + 1);
    ENSURE_MSG(*p == ':', "no ':' after key %s", f->key);
    p = skip_blank(p + 1);
    const char* end = value_end(p);
    size_t length = (size_t)(end - p);
    while (length && (p[length - 1] == ' ' || p[length - 1] == '\n'))
      length--;
    ENSURE(length > 0 && length < sizeof f->value);
    memcpy(f->value, p, length);
    p = skip_blank(end);
    if (*p == ',') p = skip_blank(p + 1);
    ENSURE_MSG(*p, "unterminated JSON object: %s", text);
  }
}

// Timings and memory use differ from run to run: keys with an "ms" or "mb"
// part ("step_ms_max", "ms", "peak_rss_mb").
static bool varies_by_run(const char* key) {
  char copy[64];
  snprintf(copy, sizeof copy, "%s", key);
  for (char *save = NULL, *part = strtok_r(copy, "_", &save); part; part = strtok_r(NULL, "_", &save))
    if (strcmp(part, "ms") == 0 || strcmp(part, "mb") == 0) return true;
  return false;
}

// Compares every field of `a` and `b` except run-dependent ones and `ignore`
// (may be NULL); returns how many were compared.
static uint32_t compare_results(const json_object* a, const json_object* b, const char* ignore) {
  ENSURE_MSG(a->count == b->count, "%u fields against %u", a->count, b->count);
  uint32_t compared = 0;
  for (uint32_t i = 0; i < a->count; ++i) {
    const json_field *fa = &a->fields[i], *fb = &b->fields[i];
    ENSURE_MSG(strcmp(fa->key, fb->key) == 0, "field %u is %s in one run, %s in the other", i, fa->key,
               fb->key);
    if (varies_by_run(fa->key) || (ignore && strcmp(fa->key, ignore) == 0)) continue;
    ENSURE_MSG(strcmp(fa->value, fb->value) == 0, "%s: %s in one run, %s in the other", fa->key, fa->value,
               fb->value);
    compared++;
  }
  return compared;
}

static const char* field(const json_object* o, const char* key) {
  for (uint32_t i = 0; i < o->count; ++i)
    if (strcmp(o->fields[i].key, key) == 0) return o->fields[i].value;
  return NULL;
}

#define SIM_ARGS "sim --scene wall --pieces 64 --shots 2 --steps 150 --json"

static void test_same_simulation(void) {
  static json_object first, second, cached;
  // Separate, empty cache directories: both runs build their tree.
  make_fresh_dir(TEST_DIR "/cache1");
  make_fresh_dir(TEST_DIR "/cache2");
  setenv("BREAKABLES_CACHE_DIR", TEST_DIR "/cache1", 1);
  parse_object(run(SIM_ARGS), &first);
  setenv("BREAKABLES_CACHE_DIR", TEST_DIR "/cache2", 1);
  parse_object(run(SIM_ARGS), &second);
  ENSURE(field(&first, "from_cache") && strcmp(field(&first, "from_cache"), "false") == 0);
  ENSURE(field(&first, "step_ms_max") && varies_by_run("step_ms_max")); // timings are present and dropped
  // The run must have done something worth comparing.
  ENSURE(field(&first, "bonds_broken") && atoi(field(&first, "bonds_broken")) > 0);
  uint32_t compared = compare_results(&first, &second, NULL);
  ENSURE_MSG(compared >= 10, "only %u fields compared", compared);
  // A tree from the cache gives the same simulation as a fresh one.
  setenv("BREAKABLES_CACHE_DIR", TEST_DIR "/cache1", 1);
  parse_object(run(SIM_ARGS), &cached);
  ENSURE(field(&cached, "from_cache") && strcmp(field(&cached, "from_cache"), "true") == 0);
  ENSURE(compare_results(&first, &cached, "from_cache") == compared - 1);
}

#endif

int main(void) {
  make_fresh_dir(TEST_DIR);
  RUN(test_same_seed_same_tree_in_process);
  RUN(test_any_thread_count_same_tree);
#ifdef BK_BREAKABLES_EXE
  RUN(test_same_seed_same_tree_from_the_cli);
  RUN(test_same_simulation);
#endif
  return 0;
}
