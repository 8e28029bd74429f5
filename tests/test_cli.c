// The breakables command line, run as a user would: help texts, JSON
// output, files written, and one-line errors with the right exit codes.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bk_fracture.h"
#include "ensure.h"

#define RUN_STDERR_PATH BK_TEST_TMP "/cli_stderr.txt"
#include "run_exe.h"

#include "cli_util.h"

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

static void test_errors(void) {
  expect_error("fracture --pieces 0", 2, "--pieces '0' is out of range (1..1048576)");
  expect_error("fracture --pieces 12abc", 2, "--pieces '12abc' is not a whole number (1..1048576)");
  expect_error("fracture --pieces", 2, "--pieces needs a value");
  expect_error("fracture --texture-scale nan", 2,
               "--texture-scale 'nan' is not a decimal number (1e-6..1e6)");
  expect_error("fracture --texture-scale -1", 2, "--texture-scale '-1' is out of range (1e-6..1e6)");
  expect_error("fracture --seed -3", 2, "--seed '-3' is not a whole number");
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
  char first[sizeof run_result_storage.out];
  memcpy(first, r->out, sizeof first);
  r = run("sim --scene wall --pieces 64 --shots 2 --steps 150 --json");
  ENSURE(strstr(r->out, "\"from_cache\": true") != NULL);
  ENSURE(json_number(r->out, "bonds_broken") == json_number(first, "bonds_broken"));
  ENSURE(json_number(r->out, "bodies_final") == json_number(first, "bodies_final"));
  // Plain BCRB: one collider per fragment.
  r = run("sim --scene wall --pieces 64 --shots 2 --steps 150 --naive --json");
  ENSURE(json_number(r->out, "colliders_final") == json_number(r->out, "colliders_naive_final"));
  // --volley moves the shots to the start: fired at step 1 instead of step 4
  // of 8, the ball reaches the wall before the run ends.
  r = run("sim --scene wall --pieces 64 --shots 1 --steps 8 --json");
  ENSURE_MSG(json_number(r->out, "bonds_broken") == 0, "%s", r->out);
  r = run("sim --scene wall --pieces 64 --shots 1 --steps 8 --volley 2 --json");
  ENSURE_MSG(json_number(r->out, "bonds_broken") > 0, "%s", r->out);
  r = run("sim --help");
  const char* options[] = {"--scene", "--pieces",  "--seed",        "--shots",    "--steps",      "--volley",
                           "--speed", "--frailty", "--density",     "--discrete", "--accumulate", "--naive",
                           "--json",  "--drop",    "--drop-radius", "--drop-at"};
  for (size_t i = 0; i < sizeof options / sizeof *options; ++i)
    ENSURE_MSG(strstr(r->out, options[i]) != NULL, "sim help does not describe %s", options[i]);
  expect_error("sim --scene castle", 2, "unknown scene 'castle'");
  expect_error("sim --steps 0", 2, "--steps '0' is out of range (1..1000000)");
  expect_error("sim --volley 0", 2, "--volley '0' is out of range (1..1000000)");
  expect_error("sim --frailty nan", 2, "--frailty 'nan' is not a decimal number (1e-6..1e6)");
  expect_error("sim --density -5", 2, "--density '-5' is out of range (1..1e5)");
  expect_error("sim --explode", 2, "unknown option '--explode'");
}

// A weight set down on the middle of the bridge's deck (issue 17): 20 t
// breaks the span by the load it carries and what it held falls; 2 t is
// carried. No shot is fired with --drop unless asked for.
static void test_sim_drop(void) {
  setenv("BREAKABLES_CACHE_DIR", BK_TEST_TMP "/cache", 1);
  run_result* r = run("sim --scene bridge --drop 20000 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE_MSG(json_number(r->out, "shots") == 0 && json_number(r->out, "drop_kg") == 20000 &&
                 strstr(r->out, "\"drop_point\": [0.0000, 1.80"),
             "%s", r->out); // on the deck's top, 1.8 m up
  ENSURE_MSG(json_number(r->out, "stress_bonds_broken") > 0 && json_number(r->out, "fragments_fallen") > 0,
             "the weight broke nothing: %s", r->out);
  r = run("sim --scene bridge --drop 2000 --json");
  ENSURE_MSG(r->status == 0 && json_number(r->out, "drop_kg") == 2000, "%s%s", r->out, r->err);
  ENSURE_MSG(json_number(r->out, "bonds_broken") == 0 && json_number(r->out, "fragments_fallen") == 0 &&
                 json_number(r->out, "bodies_final") == 1,
             "2 t broke the bridge: %s", r->out);
  r = run("sim --scene bridge --steps 1 --json");
  ENSURE_MSG(json_number(r->out, "drop_kg") == 0 && strstr(r->out, "\"drop_point\": null"), "%s", r->out);
}

// A user's own model in sim: a fractured .mtree is used as it is (its own
// pieces, no fracture), the material chosen changes the outcome, and the
// mistakes are named.
static void test_sim_own_mesh(void) {
  setenv("BREAKABLES_CACHE_DIR", BK_TEST_TMP "/cache", 1);
  run_result* r = run("fracture --mesh pillar --pieces 48 --out '" BK_TEST_TMP "/own.mtree'");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  r = run("sim --mesh '" BK_TEST_TMP "/own.mtree' --pieces 512 --shots 2 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE_MSG(strstr(r->out, "\"scene\": \"own.mtree\"") && json_number(r->out, "pieces") == 48, "%s", r->out);
  ENSURE_MSG(json_number(r->out, "bonds_broken") > 0, "the fitted shots missed: %s", r->out); // aimed at it
  ENSURE(json_number(r->out, "mass_rel_error") < 1e-9 && strstr(r->out, "\"nan\": false"));
  double stone = json_number(r->out, "bonds_broken");
  // Our own glTF export is a tree too: loaded, not fractured again, and it
  // gives the very same simulation as the .mtree of the same fracture.
  r = run("fracture --mesh pillar --pieces 48 --export-gltf '" BK_TEST_TMP "/own.glb'");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  r = run("sim --mesh '" BK_TEST_TMP "/own.glb' --pieces 512 --shots 2 --json");
  ENSURE_MSG(r->status == 0 && json_number(r->out, "pieces") == 48, "%s%s", r->out, r->err);
  ENSURE_MSG(json_number(r->out, "bonds_broken") == stone, "glb %s, mtree %g", r->out, stone);
  r = run("sim --mesh '" BK_TEST_TMP "/own.mtree' --material glass --shots 2 --json");
  ENSURE_MSG(r->status == 0 && json_number(r->out, "bonds_broken") > stone, "stone %g, glass: %s", stone,
             r->out);
  // A small model far from the origin is stood on the ground and aimed at:
  // the shots are fitted to its size and place.
  FILE* f = fopen(BK_TEST_TMP "/small_far.obj", "w");
  ENSURE(f);
  for (int v = 0; v < 8; ++v)
    fprintf(f, "v %g %g %g\n", 40.0 + 0.2 * (v & 1), 7.0 + 0.2 * ((v >> 1) & 1), -9.0 + 0.2 * ((v >> 2) & 1));
  fputs("f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n", f);
  fclose(f);
  r = run("sim --mesh '" BK_TEST_TMP "/small_far.obj' --pieces 16 --material glass --shots 2 --json");
  ENSURE_MSG(r->status == 0 && json_number(r->out, "bonds_broken") > 0, "%s%s", r->out, r->err);
  // A built-in shape as a model, and --material over a whole scene.
  r = run("sim --mesh cube --pieces 32 --shots 1 --json");
  ENSURE_MSG(r->status == 0 && strstr(r->out, "\"scene\": \"cube\"") && json_number(r->out, "pieces") == 32,
             "%s%s", r->out, r->err);
  r = run("sim --scene wall --pieces 64 --shots 2 --steps 150 --material glass --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  double glass_wall = json_number(r->out, "bonds_broken");
  r = run("sim --scene wall --pieces 64 --shots 2 --steps 150 --json");
  ENSURE_MSG(glass_wall > json_number(r->out, "bonds_broken"), "glass wall %g, stone: %s", glass_wall,
             r->out);
  expect_error("sim --mesh cube --scene wall", 2, "--mesh and --scene cannot be used together");
  expect_error("sim --mesh cube --material gold", 2,
               "unknown material 'gold': use stone, concrete, glass, porcelain, eggshell, wood");
  expect_error("sim --mesh '" BK_TEST_TMP "/missing.mtree'", 1, "missing.mtree: cannot open");
  r = run("sim --help");
  ENSURE(strstr(r->out, "--mesh PATH") && strstr(r->out, "--material NAME"));
  r = run("play --help");
  ENSURE(strstr(r->out, "--mesh PATH") && strstr(r->out, "--material NAME"));
}

// A textured model's material names the export's materials, and its
// texture file goes into the export (which then stands alone); a model of
// four materials exports four pairs (Debian's assimp-testmodels, installed by
// scripts/setup.sh).
static const char* glb_json(const char* path, char* glb, size_t capacity, size_t* size) {
  FILE* f = fopen(path, "rb");
  ENSURE(f);
  size_t n = fread(glb, 1, capacity - 1, f);
  fclose(f);
  ENSURE(n > 20);
  uint32_t json_length = 0;
  memcpy(&json_length, glb + 12, 4);
  ENSURE(json_length < n - 20);
  *size = n;
  return glb + 20;
}

static void test_export_keeps_material(void) {
  const char* model = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf";
  run_result* r = run("fracture --mesh /usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf "
                      "--pieces 8 --export-gltf '" BK_TEST_TMP "/textured.glb'");
  ENSURE_MSG(r->status == 0, "%s: %s", model, r->err);
  static char glb[1 << 20];
  size_t size = 0;
  const char* json = glb_json(BK_TEST_TMP "/textured.glb", glb, sizeof glb, &size);
  ENSURE_MSG(strstr(json, "{\"name\":\"Texture\"") && strstr(json, "{\"name\":\"Texture_interior\""),
             "%.400s", strstr(json, "\"materials\""));
  ENSURE_MSG(strstr(json, "\"images\":[{\"bufferView\":") && strstr(json, "\"mimeType\":\"image/png\"}"),
             "no image inside: %.300s", strstr(json, "\"images\""));
  // The texture file's bytes are in the binary chunk, as they are on disk.
  FILE* f = fopen("/usr/share/assimp/models/glTF2/BoxTextured-glTF/CesiumLogoFlat.png", "rb");
  ENSURE(f);
  static char png[1 << 18];
  size_t png_size = fread(png, 1, sizeof png, f);
  fclose(f);
  ENSURE(png_size > 8 && png_size < sizeof png);
  bool found = false;
  for (size_t at = 0; at + png_size <= size && !found;
       at += 4) // glTF buffer views here start at multiples of 4
    found = memcmp(glb + at, png, png_size) == 0;
  ENSURE_MSG(found, "the texture's bytes are not in the export");

  r = run("fracture --mesh /usr/share/assimp/models/BLEND/4Cubes4Mats_248.blend --pieces 16 --json "
          "--export-gltf '" BK_TEST_TMP "/four.glb'");
  ENSURE_MSG(r->status == 0 && json_number(r->out, "source_materials") == 4, "%s%s", r->out, r->err);
  json = glb_json(BK_TEST_TMP "/four.glb", glb, sizeof glb, &size);
  const char* names[4] = {"Grey", "Grey.001", "Grey.002", "Grey.003"};
  for (int i = 0; i < 4; ++i) {
    char surface[64], interior[64];
    snprintf(surface, sizeof surface, "{\"name\":\"%s\"", names[i]);
    snprintf(interior, sizeof interior, "{\"name\":\"%s_interior\"", names[i]);
    ENSURE_MSG(strstr(json, surface) && strstr(json, interior), "no %s pair in %.600s", names[i],
               strstr(json, "\"materials\""));
  }
  // Every one of the eight materials is used by some primitive.
  for (int k = 0; k < 8; ++k) {
    char use[32];
    snprintf(use, sizeof use, "\"material\":%d}", k);
    ENSURE_MSG(strstr(json, use), "no primitive uses material %d", k);
  }
  // Exactly the pieces asked for, also with more shells than pieces (18
  // separate, overlapping legs and parts): the nearest shells are merged.
  r = run("fracture --mesh /usr/share/assimp/models/STL/Spider_binary.stl --pieces 16 --json");
  ENSURE_MSG(r->status == 0 && json_number(r->out, "pieces_made") == 16, "%s%s", r->out, r->err);
  ENSURE_MSG(!strstr(r->out, "more than the") && !strstr(r->err, "note:"), "%s%s", r->out, r->err);
}

// ---------------------------------------------------------------- number options

// Every number option of every command takes exactly a number of its kind
// within its range; the rest exits 2 with one line naming the option, the
// text and the range. Refusals come before any window opens, so play and
// editor are checked without a display.
static void test_number_options(void) {
  setenv("BREAKABLES_CACHE_DIR", BK_TEST_TMP "/cache", 1);
  static const struct {
    const char* args;
    const char* message;
  } refused[] = {
      // Blanks, signs, hex and trailing text: not a number of the option's kind.
      {"fracture --seed ' -1'",
       "breakables fracture: --seed ' -1' is not a whole number (0..18446744073709551615)"},
      {"fracture --pieces ' -18446744073709551615'",
       "--pieces ' -18446744073709551615' is not a whole number (1..1048576)"},
      {"fracture --pieces ' 8'", "--pieces ' 8' is not a whole number"},
      {"fracture --pieces '8 '", "--pieces '8 ' is not a whole number"},
      {"fracture --pieces +8", "--pieces '+8' is not a whole number"},
      {"fracture --pieces 0x10", "--pieces '0x10' is not a whole number"},
      {"fracture --pieces 1e3", "--pieces '1e3' is not a whole number"},
      {"fracture --seed \"$(printf '1\\n2')\"", "--seed '1\\x0a2' is not a whole number"},
      {"fracture --seed 18446744073709551616",
       "--seed '18446744073709551616' is out of range (0..18446744073709551615)"},
      {"fracture --pieces 1048577", "--pieces '1048577' is out of range (1..1048576)"},
      {"fracture --texture-scale ' 0.5'", "--texture-scale ' 0.5' is not a decimal number (1e-6..1e6)"},
      {"fracture --texture-scale '0.5 '", "--texture-scale '0.5 ' is not a decimal number"},
      {"fracture --texture-scale 0x1p-3", "--texture-scale '0x1p-3' is not a decimal number"},
      {"fracture --texture-scale inf", "--texture-scale 'inf' is not a decimal number"},
      {"fracture --texture-scale 1e999", "--texture-scale '1e999' is out of range (1e-6..1e6)"},
      // Finite but tiny: cut-face UVs would overflow a float.
      {"fracture --texture-scale 1e-300",
       "breakables fracture: --texture-scale '1e-300' is out of range (1e-6..1e6)"},
      {"fracture --texture-scale 9.9e-7", "--texture-scale '9.9e-7' is out of range (1e-6..1e6)"},
      {"fracture --texture-scale 1000001", "--texture-scale '1000001' is out of range (1e-6..1e6)"},
      {"sim --pieces 65537", "breakables sim: --pieces '65537' is out of range (1..65536)"},
      {"sim --seed ' 1'", "breakables sim: --seed ' 1' is not a whole number (0..18446744073709551615)"},
      {"sim --shots 1001", "--shots '1001' is out of range (0..1000)"},
      {"sim --shots -1", "--shots '-1' is not a whole number (0..1000)"},
      {"sim --steps ' 5'", "--steps ' 5' is not a whole number (1..1000000)"},
      {"sim --volley 1e3", "--volley '1e3' is not a whole number (1..1000000)"},
      {"sim --speed 0.09", "--speed '0.09' is out of range (0.1..2000)"},
      {"sim --speed 2000.5", "--speed '2000.5' is out of range (0.1..2000)"},
      {"sim --speed -inf", "--speed '-inf' is not a decimal number (0.1..2000)"},
      {"sim --frailty 1e-300", "--frailty '1e-300' is out of range (1e-6..1e6)"},
      {"sim --frailty 2e6", "--frailty '2e6' is out of range (1e-6..1e6)"},
      {"sim --density 0.5", "--density '0.5' is out of range (1..1e5)"},
      {"sim --density 1e300", "--density '1e300' is out of range (1..1e5)"},
      {"sim --density 2,5", "--density '2,5' is not a decimal number (1..1e5)"},
      {"sim --drop 0", "breakables sim: --drop '0' is out of range (1..1e6)"},
      {"sim --drop nan", "breakables sim: --drop 'nan' is not a decimal number (1..1e6)"},
      {"sim --drop 2e6", "breakables sim: --drop '2e6' is out of range (1..1e6)"},
      {"sim --drop", "breakables sim: --drop needs a value"},
      {"sim --drop 100 --drop-radius 0", "breakables sim: --drop-radius '0' is out of range (0.01..2)"},
      {"sim --drop 100 --drop-at 1.5", "breakables sim: --drop-at '1.5' is not a whole number (0..10000000)"},
      {"sim --drop 100 --drop-at 300", "breakables sim: --drop-at 300 is past the run's end (--steps 300)"},
      {"sim --drop-at 5", "breakables sim: --drop-at needs --drop KG"},
      {"sim --drop-radius 0.5", "breakables sim: --drop-radius needs --drop KG"},
      {"play --pieces 0", "breakables play: --pieces '0' is out of range (1..65536)"},
      {"play --seed ' -1'", "breakables play: --seed ' -1' is not a whole number (0..18446744073709551615)"},
      {"play --volley +5", "breakables play: --volley '+5' is not a whole number (1..10000000)"},
      {"play --frames 0x10", "breakables play: --frames '0x10' is not a whole number (1..10000000)"},
      {"play --autofire 10001", "breakables play: --autofire '10001' is out of range (0..10000)"},
      {"play --width 63", "breakables play: --width '63' is out of range (64..8192)"},
      {"play --height ' 720'", "breakables play: --height ' 720' is not a whole number (64..8192)"},
      {"play --stress-scale 0", "breakables play: --stress-scale '0' is out of range (1e-6..1e6)"},
      {"play --drop -1", "breakables play: --drop '-1' is out of range (1..1e6)"},
      {"play --drop inf", "breakables play: --drop 'inf' is not a decimal number (1..1e6)"},
      {"play --drop 100 --drop-radius 2.5", "breakables play: --drop-radius '2.5' is out of range (0.01..2)"},
      {"play --drop 100 --frames 50",
       "breakables play: --drop-at 60 (the default) is past the run's end (--frames 50)"},
      {"play --drop-at 5", "breakables play: --drop-at needs --drop KG"},
      {"play --overlay bricks",
       "breakables play: --overlay must be bonds, stress, nodes or hulls (got 'bricks')"},
      {"editor --pieces 65537", "breakables editor: --pieces '65537' is out of range (1..65536)"},
      {"editor --seed 2147483648", "breakables editor: --seed '2147483648' is out of range (0..2147483647)"},
      {"editor --texture-scale 1e-300",
       "breakables editor: --texture-scale '1e-300' is out of range (1e-6..1e6)"},
      {"editor --explode 3.01", "breakables editor: --explode '3.01' is out of range (0..3)"},
      {"editor --explode -0.1", "breakables editor: --explode '-0.1' is out of range (0..3)"},
      {"editor --width 8193", "breakables editor: --width '8193' is out of range (64..8192)"},
      {"bench --seed ' -1'",
       "breakables bench: --seed ' -1' is not a whole number (0..18446744073709551615)"},
  };
  for (size_t i = 0; i < sizeof refused / sizeof *refused; ++i)
    expect_error(refused[i].args, 2, refused[i].message);

  // The edges of the ranges are accepted and reach the output.
  run_result* r =
      run("fracture --mesh cube --pieces 2 --seed 18446744073709551615 --texture-scale 1e-6 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE(strstr(r->out, "\"seed\": 18446744073709551615") && json_number(r->out, "texture_scale") == 1e-6);
  r = run("fracture --mesh cube --pieces 1 --seed 0 --texture-scale 1e6 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE(strstr(r->out, "\"seed\": 0,") && json_number(r->out, "texture_scale") == 1e6);
  r = run("fracture --mesh cube --pieces 0002 --texture-scale .25 --json");
  ENSURE_MSG(r->status == 0 && json_number(r->out, "texture_scale") == 0.25, "%s", r->err);
  const char* sims[] = {
      "sim --scene wall --pieces 1 --shots 1 --steps 30 --speed 0.1 --frailty 1e-6 --density 1 --json",
      "sim --scene wall --pieces 1 --shots 1 --steps 30 --speed 2000 --frailty 1e6 --density 1e5 --json",
      "sim --scene wall --pieces 1 --shots 0 --steps 1 --volley 1000000 --json",
  };
  for (size_t i = 0; i < sizeof sims / sizeof *sims; ++i) {
    r = run(sims[i]);
    ENSURE_MSG(r->status == 0, "'%s': %s", sims[i], r->err);
    ENSURE_MSG(strstr(r->out, "\"nan\": false") != NULL, "'%s': %s", sims[i], r->out);
  }

  // Each help states the ranges it enforces.
  static const struct {
    const char* command;
    const char* range;
  } helps[] = {
      {"fracture", "1..1048576"},
      {"fracture", "0..18446744073709551615"},
      {"fracture", "1e-6..1e6"},
      {"sim", "1..65536"},
      {"sim", "0..1000"},
      {"sim", "1..1000000"},
      {"sim", "0.1..2000"},
      {"sim", "1e-6..1e6"},
      {"sim", "1..1e5"},
      {"sim", "1..1e6"},
      {"sim", "0.01..2"},
      {"play", "1..1e6"},
      {"play", "0.01..2"},
      {"play", "1..65536"},
      {"play", "1..10000000"},
      {"play", "0..10000"},
      {"play", "64..8192"},
      {"editor", "1..65536"},
      {"editor", "0..2147483647"},
      {"editor", "1e-6..1e6"},
      {"editor", "0..3"},
      {"editor", "64..8192"},
      {"bench", "0..18446744073709551615"},
  };
  for (size_t i = 0; i < sizeof helps / sizeof *helps; ++i) {
    char args[64];
    snprintf(args, sizeof args, "%s --help", helps[i].command);
    r = run(args);
    ENSURE_MSG(r->status == 0 && strstr(r->out, helps[i].range), "%s --help does not state %s",
               helps[i].command, helps[i].range);
  }
}

// ---------------------------------------------------------------- bench

typedef struct csv_table {
  char header[1024];
  char rows[32][1024];
  uint32_t row_count;
} csv_table;

static csv_table csv_data;

// Reads BK_TEST_TMP/bench/<name>.csv, checking its header and row count.
static const csv_table* read_csv(const char* name, const char* header, uint32_t rows) {
  char path[512];
  snprintf(path, sizeof path, "%s/bench/%s.csv", BK_TEST_TMP, name);
  FILE* f = fopen(path, "rb");
  ENSURE_MSG(f != NULL, "missing %s", path);
  memset(&csv_data, 0, sizeof csv_data);
  ENSURE(fgets(csv_data.header, sizeof csv_data.header, f) != NULL);
  csv_data.header[strcspn(csv_data.header, "\n")] = 0;
  ENSURE_MSG(strcmp(csv_data.header, header) == 0, "%s: header '%s', expected '%s'", name, csv_data.header,
             header);
  char line[1024];
  while (fgets(line, sizeof line, f)) {
    ENSURE(csv_data.row_count < 32);
    line[strcspn(line, "\n")] = 0;
    snprintf(csv_data.rows[csv_data.row_count++], sizeof line, "%s", line);
  }
  fclose(f);
  ENSURE_MSG(csv_data.row_count == rows, "%s: %u rows, expected %u", name, csv_data.row_count, rows);
  return &csv_data;
}

// The field of a row under a header key, as text.
static const char* csv_field(const csv_table* t, uint32_t row, const char* key) {
  static char field[128];
  uint32_t column = 0;
  const char* h = t->header;
  size_t key_length = strlen(key);
  while (!(strncmp(h, key, key_length) == 0 && (h[key_length] == ',' || h[key_length] == 0))) {
    h = strchr(h, ',');
    ENSURE_MSG(h != NULL, "no column %s in %s", key, t->header);
    ++h;
    ++column;
  }
  const char* f = t->rows[row];
  for (uint32_t c = 0; c < column; ++c) {
    f = strchr(f, ',');
    ENSURE_MSG(f != NULL, "row %u is short: %s", row, t->rows[row]);
    ++f;
  }
  snprintf(field, sizeof field, "%.*s", (int)strcspn(f, ","), f);
  return field;
}

static double csv_number(const csv_table* t, uint32_t row, const char* key) {
  const char* text = csv_field(t, row, key);
  char* end = NULL;
  double value = strtod(text, &end);
  ENSURE_MSG(end != text && *end == 0, "%s of row %u is not a number: '%s'", key, row, text);
  return value;
}

// Every row's value of each key is finite and > 0.
static void ensure_positive(const csv_table* t, const char* const* keys, size_t count) {
  for (uint32_t r = 0; r < t->row_count; ++r)
    for (size_t k = 0; k < count; ++k) {
      double value = csv_number(t, r, keys[k]);
      ENSURE_MSG(isfinite(value) && value > 0.0, "%s of row %u is %g", keys[k], r, value);
    }
}

static bool bench_file_exists(const char* name) {
  char path[512];
  snprintf(path, sizeof path, "%s/bench/%s", BK_TEST_TMP, name);
  FILE* f = fopen(path, "rb");
  if (f) fclose(f);
  return f != NULL;
}

// 7. Fracture patterns (--quick): each pattern at 64 and 1024 pieces (brick
// and planes on the wall, the others on the bunny) and planes and each cell
// pattern with noise at 1024; every row's tree closed, with all its pieces and its volume.
static void test_bench_patterns(const char* out, const char* report) {
  static const struct {
    const char* mesh;
    const char* pattern;
    uint32_t pieces;
    bool noisy;
  } expected[] = {{"bunny", "planes", 64, false},     {"bunny", "planes", 1024, false},
                  {"bunny", "voronoi", 64, false},    {"bunny", "voronoi", 1024, false},
                  {"bunny", "clustered", 64, false},  {"bunny", "clustered", 1024, false},
                  {"bunny", "radial", 64, false},     {"bunny", "radial", 1024, false},
                  {"wall", "brick", 64, false},       {"wall", "brick", 1024, false},
                  {"wall", "planes", 64, false},      {"wall", "planes", 1024, false},
                  {"bunny", "planes", 1024, true},    {"bunny", "voronoi", 1024, true},
                  {"bunny", "clustered", 1024, true}, {"bunny", "radial", 1024, true}};
  enum { EXPECTED = sizeof expected / sizeof *expected };
  const csv_table* t =
      read_csv("patterns",
               "mesh,pattern,noise,fragments,runs,ms_median,leaves,nodes,bonds,leaf_triangles,"
               "sliver_fraction,volume_ratio_p95_p5,open_nodes,volume_rel_error",
               EXPECTED);
  const char* keys[] = {"ms_median", "leaves", "nodes", "bonds", "leaf_triangles", "volume_ratio_p95_p5"};
  ensure_positive(t, keys, sizeof keys / sizeof *keys);
  for (uint32_t e = 0; e < EXPECTED; ++e) {
    uint32_t found = 0;
    for (uint32_t i = 0; i < t->row_count; ++i)
      found += strcmp(csv_field(t, i, "mesh"), expected[e].mesh) == 0 &&
               strcmp(csv_field(t, i, "pattern"), expected[e].pattern) == 0 &&
               csv_number(t, i, "fragments") == expected[e].pieces &&
               (csv_number(t, i, "noise") > 0.0) == expected[e].noisy;
    ENSURE_MSG(found == 1, "patterns.csv has %u rows of %s on the %s at %u pieces%s", found,
               expected[e].pattern, expected[e].mesh, expected[e].pieces,
               expected[e].noisy ? " with noise" : "");
  }
  for (uint32_t i = 0; i < t->row_count; ++i) {
    ENSURE_MSG(csv_number(t, i, "open_nodes") == 0.0, "patterns.csv row %u (%s) has open nodes", i,
               csv_field(t, i, "pattern"));
    ENSURE(csv_number(t, i, "runs") == 1.0 && csv_number(t, i, "leaves") == csv_number(t, i, "fragments"));
    ENSURE(csv_number(t, i, "nodes") >= csv_number(t, i, "leaves"));
    double slivers = csv_number(t, i, "sliver_fraction");
    ENSURE(slivers >= 0.0 && slivers <= 1.0 && csv_number(t, i, "volume_ratio_p95_p5") >= 1.0);
    ENSURE(csv_number(t, i, "volume_rel_error") < 1e-9);
  }
  // The answers: planes' time against each cell pattern's, Voronoi's slivers against planes'.
  const char* answers[] = {"**Are the cell patterns fast enough?** At 1024 pieces on the bunny, planes take",
                           "**Do Voronoi cells avoid slivers?**", "Every tree is closed"};
  for (size_t i = 0; i < sizeof answers / sizeof *answers; ++i)
    ENSURE_MSG(strstr(report, answers[i]) != NULL, "report lacks %s", answers[i]);
  const char* lines[] = {
      "voronoi at 1024 pieces on the bunny: ", "clustered at 1024 pieces on the bunny: ",
      "radial at 1024 pieces on the bunny: ", "slivers at 1024 pieces on the bunny: voronoi"};
  for (size_t i = 0; i < sizeof lines / sizeof *lines; ++i)
    ENSURE_MSG(strstr(out, lines[i]) != NULL, "stdout lacks '%s'", lines[i]);
}

static void test_bench_quick(void) {
  setenv("BREAKABLES_CACHE_DIR", BK_TEST_TMP "/cache", 1);
  run_result* r = run("bench --quick --out '" BK_TEST_TMP "/bench'");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  const char* sections[] = {"1. Fracture speed",    "2. Meshes",           "3. Maximum fragments",
                            "4. Runtime",           "5. Scaling",          "6. Asset pipeline",
                            "7. Fracture patterns", "8. Structural stress"};
  for (size_t i = 0; i < sizeof sections / sizeof *sections; ++i)
    ENSURE_MSG(strstr(r->out, sections[i]) != NULL, "stdout lacks %s", sections[i]);

  // The report: command, machine, every section, and the plots (or why they are missing).
  static char report[1 << 17];
  FILE* f = fopen(BK_TEST_TMP "/bench/report.md", "rb");
  ENSURE(f != NULL);
  report[fread(report, 1, sizeof report - 1, f)] = 0;
  fclose(f);
  const char* report_parts[] = {"bench --quick --out",
                                "| processor |",
                                "| memory |",
                                "| build |",
                                "| date |",
                                "## 1. Fracture speed",
                                "## 5. Scaling",
                                "## 6. Asset pipeline",
                                "## 7. Fracture patterns",
                                "| ---: |"};
  for (size_t i = 0; i < sizeof report_parts / sizeof *report_parts; ++i)
    ENSURE_MSG(strstr(report, report_parts[i]) != NULL, "report lacks %s", report_parts[i]);
  bool gnuplot = system("command -v gnuplot >/dev/null 2>&1") == 0;
  const char* plots[] = {"fracture_speed.png", "runtime.png", "colliders.png", "patterns_time.png",
                         "patterns_slivers.png"};
  for (size_t i = 0; i < sizeof plots / sizeof *plots; ++i) {
    char embedded[64];
    snprintf(embedded, sizeof embedded, "](%s)", plots[i]);
    if (gnuplot) {
      ENSURE_MSG(bench_file_exists(plots[i]), "missing %s", plots[i]);
      ENSURE_MSG(strstr(report, embedded) != NULL, "report does not embed %s", plots[i]);
    } else {
      ENSURE(strstr(report, "gnuplot is not on PATH") != NULL);
    }
  }

  // 1. Fracture speed: 2 .. 1024 fragments.
  const csv_table* t = read_csv(
      "fracture_speed", "fragments,leaves,nodes,leaf_triangles,runs,ms_median,ms_min,us_per_fragment", 10);
  const char* speed_keys[] = {"ms_median", "ms_min", "us_per_fragment", "leaf_triangles"};
  ensure_positive(t, speed_keys, 4);
  for (uint32_t i = 0; i < t->row_count; ++i) {
    ENSURE(csv_number(t, i, "fragments") == (double)(2u << i));
    ENSURE(csv_number(t, i, "leaves") >= csv_number(t, i, "fragments"));
    ENSURE(csv_number(t, i, "nodes") == 2.0 * csv_number(t, i, "leaves") - 1.0);
  }
  // 2. Meshes: four, all watertight.
  t = read_csv(
      "meshes",
      "mesh,source_triangles,leaves,runs,ms_median,leaf_triangles,volume_spread,tiny_leaves,watertight", 4);
  const char* mesh_keys[] = {"ms_median", "leaf_triangles", "volume_spread"};
  ensure_positive(t, mesh_keys, 3);
  for (uint32_t i = 0; i < t->row_count; ++i) {
    ENSURE(strcmp(csv_field(t, i, "watertight"), "true") == 0);
    ENSURE(csv_number(t, i, "volume_spread") >= 1.0 && csv_number(t, i, "leaves") >= 256);
  }
  ENSURE(strcmp(csv_field(t, 3, "mesh"), "bunny") == 0);
  // 3. Maximum fragments: 2 .. 2048, every level watertight with exact volumes.
  t = read_csv("max_fragments",
               "fragments,leaves,nodes,ms,watertight,open_nodes,volume_rel_error,child_volume_rel_error", 11);
  const char* max_keys[] = {"ms", "leaves", "nodes"};
  ensure_positive(t, max_keys, 3);
  for (uint32_t i = 0; i < t->row_count; ++i) {
    ENSURE_MSG(strcmp(csv_field(t, i, "watertight"), "true") == 0, "level %u is not watertight", i);
    ENSURE(csv_number(t, i, "open_nodes") == 0.0);
    ENSURE(csv_number(t, i, "volume_rel_error") < 1e-9 && csv_number(t, i, "child_volume_rel_error") < 1e-9);
  }
  ENSURE(strstr(r->out, "first failure: none up to 2048") != NULL);
  // 4. Runtime: wall and cube, 2 .. 256 fragments each.
  t = read_csv(
      "runtime",
      "object,fragments,bodies,colliders,naive_colliders,collider_ratio,before_ms,naive_before_ms,"
      "before_ratio,hit_physics_ms,hit_break_ms,naive_hit_physics_ms,naive_hit_break_ms,hit_median_ms,"
      "naive_hit_median_ms,step_ratio,after_ms,naive_after_ms",
      16);
  const char* runtime_keys[] = {"before_ms",      "naive_before_ms",      "hit_physics_ms",
                                "hit_break_ms",   "naive_hit_physics_ms", "naive_hit_break_ms",
                                "hit_median_ms",  "naive_hit_median_ms",  "after_ms",
                                "naive_after_ms", "step_ratio",           "before_ratio",
                                "colliders"};
  ensure_positive(t, runtime_keys, sizeof runtime_keys / sizeof *runtime_keys);
  for (uint32_t i = 0; i < t->row_count; ++i) {
    ENSURE(strcmp(csv_field(t, i, "object"), i < 8 ? "wall" : "cube") == 0);
    ENSURE(csv_number(t, i, "collider_ratio") >= 1.0);
    ENSURE(csv_number(t, i, "naive_colliders") == csv_number(t, i, "fragments"));
    ENSURE(csv_number(t, i, "colliders") <= csv_number(t, i, "naive_colliders"));
  }
  // The largest wall breaks into several bodies.
  ENSURE(csv_number(t, 7, "bodies") > 1.0);
  // 5. Scaling: 1 and 4 walls.
  t = read_csv(
      "scaling",
      "walls,fragments,bodies,colliders,step_ms_median,step_ms_max,break_ms_max,start_rss_mb,peak_rss_mb", 2);
  const char* scaling_keys[] = {"step_ms_median", "step_ms_max", "break_ms_max", "peak_rss_mb"};
  ensure_positive(t, scaling_keys, 4);
  ENSURE(csv_number(t, 0, "walls") == 1.0 && csv_number(t, 1, "walls") == 4.0);
  ENSURE(csv_number(t, 1, "step_ms_max") >= csv_number(t, 1, "step_ms_median"));
  // 6. Asset pipeline: export and load-back of the cube of 1024 fragments, import of 100,000 triangles.
  t = read_csv("assets", "step,source,nodes,triangles,file_mb,runs,ms_median,ms_min,target_ms,target_met", 3);
  const char* asset_keys[] = {"nodes", "triangles", "file_mb", "runs", "ms_median", "ms_min"};
  ensure_positive(t, asset_keys, sizeof asset_keys / sizeof *asset_keys);
  ENSURE(strcmp(csv_field(t, 0, "step"), "export .glb") == 0 && csv_number(t, 0, "nodes") == 2047.0);
  ENSURE(strcmp(csv_field(t, 1, "step"), "load back .glb") == 0 &&
         strcmp(csv_field(t, 1, "target_met"), "-") == 0);
  ENSURE(strcmp(csv_field(t, 2, "step"), "import .glb") == 0 && csv_number(t, 2, "triangles") == 100000.0);
  ENSURE(csv_number(t, 0, "target_ms") == 1000.0 && csv_number(t, 2, "target_ms") == 500.0);
  for (uint32_t i = 0; i < 3; i += 2) {
    const char* met = csv_field(t, i, "target_met");
    ENSURE_MSG(strcmp(met, "yes") == 0 || strcmp(met, "no") == 0, "target_met of row %u is '%s'", i, met);
  }
  ENSURE_MSG(strstr(report, "the target of under 1 s for 4096 fragments is ") != NULL &&
                 strstr(report, "`--quick`; run without it to measure 4096") != NULL,
             "the report does not state the export target and the quick cube");
  ENSURE(!bench_file_exists("cube_1024.glb") && !bench_file_exists("torus_100000.glb"));
  test_bench_patterns(r->out, report);

  r = run("bench --help");
  const char* options[] = {"--quick", "--out", "--seed"};
  for (size_t i = 0; i < sizeof options / sizeof *options; ++i)
    ENSURE_MSG(strstr(r->out, options[i]) != NULL, "bench help does not describe %s", options[i]);
  write_file("not_a_dir", "x");
  expect_error("bench --quick --out '" BK_TEST_TMP "/not_a_dir/bench'", 1, "cannot create directory");
  expect_error("bench --seed x", 2, "--seed 'x' is not a whole number (0..18446744073709551615)");
  expect_error("bench --out", 2, "--out needs a value");
  expect_error("bench --slow", 2, "unknown option '--slow'");
}

int main(void) {
  RUN(test_help);
  RUN(test_json);
  RUN(test_files);
  RUN(test_same_seed_same_file);
  RUN(test_errors);
  RUN(test_repairs_simple_hole);
  RUN(test_sim);
  RUN(test_sim_drop);
  RUN(test_sim_own_mesh);
  RUN(test_export_keeps_material);
  RUN(test_number_options);
  RUN(test_bench_quick);
  return 0;
}
