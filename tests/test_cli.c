// The breakables command line, run as a user would: help texts, JSON
// output, files written, and one-line errors with the right exit codes
// (the benchmark's in test_cli_bench.c, the physics budget's in
// test_cli_budget.c).
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
  // A double pyramid with a face across its middle: the hole it leaves in
  // either half cannot be filled.
  write_file("twisted.obj",
             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\nv 0.5 0.5 -1\nf 1 2 5\nf 2 3 5\n"
             "f 3 4 5\nf 4 1 5\nf 2 1 6\nf 3 2 6\nf 4 3 6\nf 1 4 6\nf 1 3 5\n");
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
                        "break_ms_p50",
                        "break_ms_p99",
                        "break_wait_steps_max",
                        "settled_physics_ms",
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
  // Break handling: percentiles in order; one wall's hits leave nothing waiting.
  ENSURE(json_number(r->out, "break_ms_p50") <= json_number(r->out, "break_ms_p99"));
  ENSURE(json_number(r->out, "break_ms_p99") <= json_number(r->out, "break_ms_max"));
  ENSURE_MSG(json_number(r->out, "break_wait_steps_max") == 0, "%s", r->out);
  ENSURE(json_number(r->out, "settled_physics_ms") >= 0.0);
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
  expect_error("sim --steps 0", 2, "--steps 0 needs --load-state (the state to report)");
  expect_error("sim --steps 1000001", 2, "--steps '1000001' is out of range (0..1000000)");
  expect_error("sim --volley 0", 2, "--volley '0' is out of range (1..10000000)");
  expect_error("sim --frailty nan", 2, "--frailty 'nan' is not a decimal number (1e-6..1e6)");
  expect_error("sim --density -5", 2, "--density '-5' is out of range (1..1e5)");
  expect_error("sim --explode", 2, "unknown option '--explode'");
}

// The structures fall at their defaults (issue 32): the bridge's and the
// balcony's own shots break them by the load they carry (not chips alone)
// and at least 10 fragments fall, while untouched they carry themselves;
// the slab's split it into parts (a crack to see, not one body shedding
// chips). The tower still topples and the wall still only loses bricks.
static void test_structures_fall(void) {
  setenv("BREAKABLES_CACHE_DIR", BK_TEST_TMP "/cache", 1);
  const char* structures[] = {"bridge", "balcony"};
  for (int i = 0; i < 2; ++i) {
    char args[128] = {0};
    snprintf(args, sizeof args, "sim --scene %s --json", structures[i]);
    run_result* r = run(args);
    ENSURE_MSG(r->status == 0, "%s", r->err);
    fprintf(stderr, "    %s: %g fragments fell, %g bonds broken, %g by stress\n", structures[i],
            json_number(r->out, "fragments_fallen"), json_number(r->out, "bonds_broken"),
            json_number(r->out, "stress_bonds_broken"));
    ENSURE_MSG(json_number(r->out, "shots") == 3 && json_number(r->out, "fragments_fallen") >= 10 &&
                   json_number(r->out, "stress_bonds_broken") > 0,
               "%s stands after its shots: %s", structures[i], r->out);
    snprintf(args, sizeof args, "sim --scene %s --shots 0 --json", structures[i]);
    r = run(args);
    ENSURE_MSG(r->status == 0 && json_number(r->out, "fragments_fallen") == 0 &&
                   json_number(r->out, "bodies_final") == 1,
               "%s falls under its own weight: %s", structures[i], r->out);
  }
  run_result* r = run("sim --scene slab --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  // Bodies of more than one fragment: what is left of the slab.
  double parts = json_number(r->out, "bodies_final") - json_number(r->out, "fragments_free");
  ENSURE_MSG(parts >= 2, "the slab is still one piece: %s", r->out);
  // What the tower's and the wall's tests hold them to (their scene data
  // is checked in test_scenes): the tower topples, its base broken by its
  // load (about 80 of its 192 fragments fall); the wall loses
  // bricks and stands (3 of 85 fell, 16 freed).
  r = run("sim --scene tower --json");
  ENSURE_MSG(r->status == 0 && json_number(r->out, "fragments_fallen") >= 60 &&
                 json_number(r->out, "stress_bonds_broken") > 0,
             "the tower stands: %s", r->out);
  r = run("sim --scene wall --json");
  ENSURE_MSG(r->status == 0 && json_number(r->out, "fragments_free") >= 10 &&
                 json_number(r->out, "fragments_fallen") <= 10 &&
                 json_number(r->out, "stress_bonds_broken") == 0,
             "the wall changed: %s", r->out);
}

// A weight set down on the middle of the bridge's deck (issue 17): 20 t
// breaks the span by the load it carries and what it held falls; 500 kg is
// carried (the bridge's old concrete gives way under 1 t). No shot is
// fired with --drop unless asked for.
static void test_sim_drop(void) {
  setenv("BREAKABLES_CACHE_DIR", BK_TEST_TMP "/cache", 1);
  run_result* r = run("sim --scene bridge --drop 20000 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE_MSG(json_number(r->out, "shots") == 0 && json_number(r->out, "drop_kg") == 20000 &&
                 strstr(r->out, "\"drop_point\": [0.0000, 1.80"),
             "%s", r->out); // on the deck's top, 1.8 m up
  ENSURE_MSG(json_number(r->out, "stress_bonds_broken") > 0 && json_number(r->out, "fragments_fallen") > 0,
             "the weight broke nothing: %s", r->out);
  r = run("sim --scene bridge --drop 500 --json");
  ENSURE_MSG(r->status == 0 && json_number(r->out, "drop_kg") == 500, "%s%s", r->out, r->err);
  ENSURE_MSG(json_number(r->out, "bonds_broken") == 0 && json_number(r->out, "fragments_fallen") == 0 &&
                 json_number(r->out, "bodies_final") == 1,
             "500 kg broke the bridge: %s", r->out);
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
      {"sim --steps ' 5'", "--steps ' 5' is not a whole number (0..1000000)"},
      {"sim --volley 1e3", "--volley '1e3' is not a whole number (1..10000000)"},
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
       "breakables play: --overlay must be bonds, stress, nodes, hulls or budget (got 'bricks')"},
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
      {"bench", "1..10"},
      {"sim", "0..1000 ms"},
      {"sim", "1..64"},
      {"play", "0..1000 ms"},
  };
  for (size_t i = 0; i < sizeof helps / sizeof *helps; ++i) {
    char args[64];
    snprintf(args, sizeof args, "%s --help", helps[i].command);
    r = run(args);
    ENSURE_MSG(r->status == 0 && strstr(r->out, helps[i].range), "%s --help does not state %s",
               helps[i].command, helps[i].range);
  }
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
  RUN(test_structures_fall);
  RUN(test_sim_own_mesh);
  RUN(test_export_keeps_material);
  RUN(test_number_options);
  return 0;
}
