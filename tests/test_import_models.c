// Models as a new user brings them (assimp-testmodels and small files
// written here): the same spider fractures alike from OBJ, STL and FBX (a
// face wound against its neighbours is turned, not split off as a shell of
// no volume); --scale and --units change the loaded size by their factor
// and refuse bad values naming the option; a model outside 1 cm..100 m
// across is warned about; FBX's unit is honoured; Wuson.ply (free text in
// its header) loads, a PLY header our reader does not know goes to assimp,
// damaged data keeps our reader's error; TGA and BMP textures are exported
// as PNG; in play a model's own texture is on its surface and a model in
// centimetres is framed.
#include <stb_image.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "bk_geom.h"
#include "ensure.h"
#include "model_surface.h"
#include "scene_run.h"

#define RUN_STDERR_PATH BK_TEST_TMP "/test_import_models_stderr.txt"
#include "run_exe.h"

#define MODELS "/usr/share/assimp/models"
#define TMP BK_TEST_TMP "/import_models_"

static void write_text(const char* path, const char* text) {
  FILE* f = fopen(path, "wb");
  ENSURE(f != NULL);
  ENSURE(fputs(text, f) >= 0);
  ENSURE(fclose(f) == 0);
}

// A box [0,sx]x[0,sy]x[0,sz] as OBJ, every face counter-clockwise from
// outside but `flipped` (0..5, or -1 for none) wound the other way.
static void write_box_obj(const char* path, double sx, double sy, double sz, int flipped, const char* mtl) {
  static const int quads[6][4] = {{1, 4, 3, 2}, {5, 6, 7, 8}, {1, 2, 6, 5},
                                  {4, 8, 7, 3}, {1, 5, 8, 4}, {2, 3, 7, 6}};
  char text[2048];
  int n = snprintf(text, sizeof text, "%s%s%s", mtl ? "mtllib " : "", mtl ? mtl : "",
                   mtl ? "\nusemtl skin\n" : "");
  for (int i = 0; i < 8; ++i) {
    int x = (i & 1) ^ ((i >> 1) & 1), y = (i >> 1) & 1, z = (i >> 2) & 1;
    n += snprintf(text + n, sizeof text - (size_t)n, "v %.9g %.9g %.9g\nvt %d %d\n", x * sx, y * sy, z * sz,
                  x, y ^ z);
  }
  for (int f = 0; f < 6; ++f) {
    const int* q = quads[f];
    for (int t = 0; t < 2; ++t) {
      int a = q[0], b = q[1 + t], c = q[2 + t];
      if (f == flipped) {
        int swap = b;
        b = c, c = swap;
      }
      n += snprintf(text + n, sizeof text - (size_t)n, "f %d/%d %d/%d %d/%d\n", a, a, b, b, c, c);
    }
  }
  ENSURE((size_t)n < sizeof text);
  write_text(path, text);
}

static bk_vec3 extent_of(const char* path) {
  bk_mesh m = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_model_import(path, NULL, &m, NULL, &err), "%s", err.message);
  bk_aabb box = bk_mesh_bounds(&m);
  bk_mesh_free(&m);
  return bk_v3_sub(box.max, box.min);
}

// ---------------------------------------------------------------- the spider

// One face wound against its neighbours: turned by repair (with the count),
// the box stays one closed shell of its whole volume, not a box with a hole
// closed plus a flat two-triangle shell.
static void test_flipped_face_turned(void) {
  write_box_obj(TMP "flipped.obj", 1, 1, 1, 2, NULL);
  bk_mesh m = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_model_import(TMP "flipped.obj", NULL, &m, NULL, &err), "%s", err.message);
  bk_repair_info info = {0};
  ENSURE_MSG(bk_mesh_repair(&m, &info, &err), "%s", err.message);
  ENSURE_MSG(info.faces_turned == 2 && info.positions_split == 0 && info.holes_closed == 0 &&
                 info.shells == 1,
             "turned %u, split %u, holes %u, shells %u", info.faces_turned, info.positions_split,
             info.holes_closed, info.shells);
  ENSURE(bk_mesh_is_closed(&m));
  ENSURE_SMALL(bk_mesh_volume(&m), 1.0, 1e-12);
  bk_mesh_free(&m);
  // A closed box has nothing to turn.
  write_box_obj(TMP "box.obj", 1, 1, 1, -1, NULL);
  ENSURE(bk_model_import(TMP "box.obj", NULL, &m, NULL, &err));
  ENSURE(bk_mesh_repair(&m, &info, &err) && info.faces_turned == 0);
  bk_mesh_free(&m);
}

static void test_spider_forms(void) {
  static const char* const forms[] = {MODELS "/OBJ/spider.obj", MODELS "/STL/Spider_binary.stl",
                                      MODELS "/FBX/spider.fbx"};
  for (size_t i = 0; i < sizeof forms / sizeof *forms; ++i) {
    char args[512];
    snprintf(args, sizeof args, "fracture --mesh '%s' --pieces 64 --json", forms[i]);
    run_result* r = run(args);
    ENSURE_MSG(r->status == 0 && strstr(r->out, "\"pieces_made\": 64,") &&
                   strstr(r->out, "\"watertight\": true"),
               "%s: %s%s", forms[i], r->out, r->err);
    // The size warning follows the others in the JSON's list (the OBJ has no
    // unit: 193 m; the FBX says centimetres: 193 m too; the STL is 8 m).
    if (i != 1)
      ENSURE_MSG(strstr(r->out, "\", \"the model is 193.4 m across, outside 1 cm..100 m"), "%s: %s", forms[i],
                 r->out);
    // What was repaired is said.
    ENSURE_MSG(strstr(r->err, "4 triangles were wound against their neighbours; turned"), "%s: %s", forms[i],
               r->err);
  }
}

// ---------------------------------------------------------------- size

static void test_scale_and_units(void) {
  write_box_obj(TMP "units.obj", 2, 3, 4, -1, NULL);
  static const struct {
    const char* options;
    double factor;
  } cases[] = {{"", 1.0},
               {"--scale 2.5", 2.5},
               {"--units cm", 0.01},
               {"--units in", 0.0254},
               {"--units mm --scale 10", 0.01},
               {"--units m", 1.0}};
  for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
    char args[512];
    snprintf(args, sizeof args, "fracture --mesh '%s' %s --pieces 1 --export-obj '%s'", TMP "units.obj",
             cases[i].options, TMP "units_out.obj");
    run_result* r = run(args);
    ENSURE_MSG(r->status == 0, "%s: %s", cases[i].options, r->err);
    bk_vec3 e = extent_of(TMP "units_out.obj");
    ENSURE_MSG(fabs(e.x - 2.0 * cases[i].factor) < 1e-9 * cases[i].factor &&
                   fabs(e.y - 3.0 * cases[i].factor) < 1e-9 * cases[i].factor &&
                   fabs(e.z - 4.0 * cases[i].factor) < 1e-9 * cases[i].factor,
               "%s: %g x %g x %g", cases[i].options, e.x, e.y, e.z);
  }
  // Bad values are refused before any work, naming the option, by every command.
  static const char* const commands[] = {"fracture", "sim", "play", "editor"};
  for (size_t i = 0; i < sizeof commands / sizeof *commands; ++i) {
    char args[512];
    snprintf(args, sizeof args, "%s --mesh '%s' --scale 0", commands[i], TMP "units.obj");
    run_result* r = run(args);
    ENSURE_MSG(r->status == 2 && strstr(r->err, "--scale '0' is out of range"), "%s: %s", commands[i],
               r->err);
    snprintf(args, sizeof args, "%s --mesh '%s' --units furlong", commands[i], TMP "units.obj");
    r = run(args);
    ENSURE_MSG(r->status == 2 && strstr(r->err, "--units 'furlong' is not a unit"), "%s: %s", commands[i],
               r->err);
    snprintf(args, sizeof args, "%s --units", commands[i]);
    r = run(args);
    ENSURE_MSG(r->status == 2 && strstr(r->err, "--units needs a value"), "%s: %s", commands[i], r->err);
  }
  // sim takes them too: a box scaled to a tenth still runs.
  char args[512];
  snprintf(args, sizeof args, "sim --mesh '%s' --scale 0.1 --steps 2 --shots 0 --pieces 2 --json",
           TMP "units.obj");
  run_result* r = run(args);
  ENSURE_MSG(r->status == 0, "%s", r->err);
}

// FBX states its unit: UnitScaleFactor 1 is centimetres (the spider), 100
// metres (the box). --units is then ignored with a warning.
static void test_fbx_units(void) {
  bk_mesh m = {0};
  bk_import_info info = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_model_import(MODELS "/FBX/spider.fbx", NULL, &m, &info, &err), "%s", err.message);
  ENSURE(info.units_given && fabs(info.metres_per_unit - 0.01) < 1e-9);
  bk_aabb box = bk_mesh_bounds(&m);
  ENSURE_MSG(fabs(box.max.z - box.min.z - 193.38) < 0.01, "%g m",
             box.max.z - box.min.z); // the OBJ's 193.38 units
  bk_mesh_free(&m);
  bk_import_info_free(&info);
  ENSURE(bk_model_import(MODELS "/FBX/box.fbx", NULL, &m, &info, &err));
  ENSURE(info.units_given && info.metres_per_unit == 1.0);
  bk_mesh_free(&m);
  bk_import_info_free(&info);
  ENSURE(bk_model_import(MODELS "/OBJ/spider.obj", NULL, &m, &info, &err));
  ENSURE(!info.units_given && info.metres_per_unit == 1.0);
  bk_mesh_free(&m);
  bk_import_info_free(&info);
  run_result* r = run("fracture --mesh '" MODELS "/FBX/box.fbx' --units cm --pieces 2");
  ENSURE_MSG(r->status == 0 && strstr(r->err, "the file gives its own unit of length; --units cm ignored"),
             "%s", r->err);
}

static int count_of(const char* text, const char* what) {
  int n = 0;
  for (const char* p = text; (p = strstr(p, what)) != NULL; p += strlen(what))
    n++;
  return n;
}

static void test_size_warning(void) {
  static const struct {
    double size;
    const char* said; // NULL: no warning
  } cases[] = {{0.001, "the model is 1 mm across, outside 1 cm..100 m"},
               {1000.0, "the model is 1 km across, outside 1 cm..100 m"},
               {1.0, NULL},
               {0.02, NULL},
               {90.0, NULL}};
  for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
    write_box_obj(TMP "sized.obj", cases[i].size, cases[i].size, cases[i].size, -1, NULL);
    run_result* r = run("fracture --mesh '" TMP "sized.obj' --pieces 2 --json");
    ENSURE_MSG(r->status == 0, "%g: %s", cases[i].size, r->err);
    if (cases[i].said) {
      ENSURE_MSG(count_of(r->err, cases[i].said) == 1, "%g: %s", cases[i].size, r->err);
      ENSURE_MSG(strstr(r->out, "\"warnings\": [\"the model is") && strstr(r->out, cases[i].said), "%g: %s",
                 cases[i].size, r->out);
    } else {
      ENSURE_MSG(!strstr(r->err, "outside 1 cm..100 m") && strstr(r->out, "\"warnings\": []"), "%g: %s%s",
                 cases[i].size, r->err, r->out);
    }
  }
  // --scale brings it into range: no warning.
  write_box_obj(TMP "sized.obj", 0.001, 0.001, 0.001, -1, NULL);
  run_result* r = run("fracture --mesh '" TMP "sized.obj' --scale 1000 --pieces 2");
  ENSURE_MSG(r->status == 0 && !strstr(r->err, "outside 1 cm..100 m"), "%s", r->err);
}

// ---------------------------------------------------------------- PLY

static void* read_whole(const char* path, size_t* size) {
  void* data = NULL;
  bk_error err = {0};
  ENSURE_MSG(bk_file_read(path, 1u << 30, "1 GiB", &data, size, &err), "%s", err.message);
  return data;
}

static void test_wuson_ply(void) {
  bk_mesh m = {0};
  bk_import_info info = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_model_import(MODELS "/PLY/Wuson.ply", NULL, &m, &info, &err), "%s", err.message);
  ENSURE_MSG(m.triangle_count == 3732 && strcmp(info.format, "ply") == 0, "%u triangles, %s",
             m.triangle_count, info.format);
  ENSURE_MSG(strstr(info.note, "PLY header line 3 ('Created by Blender3D 247") &&
                 strstr(info.note, "is not a PLY keyword: read as a comment"),
             "%s", info.note);
  bk_mesh_free(&m);
  bk_import_info_free(&info);
  // The same file cut short is damaged: our reader's error, assimp never tried.
  size_t size = 0;
  char* data = read_whole(MODELS "/PLY/Wuson.ply", &size);
  ENSURE(!bk_model_import_memory(data, size / 2, "ply", "half.ply", NULL, &m, &info, &err));
  ENSURE_MSG(strstr(err.message, "half.ply: PLY element 0 item") && strstr(err.message, "ends early"), "%s",
             err.message);
  free(data);
  // A layout our reader does not know (triangle strips): read by assimp, saying so.
  const char* strip =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n0 0 1\n6 0 2 1 3 0 2\n";
  ENSURE_MSG(bk_model_import_memory(strip, strlen(strip), "ply", "strip.ply", NULL, &m, &info, &err), "%s",
             err.message);
  ENSURE_MSG(m.triangle_count >= 1 && strcmp(info.format, "assimp:ply") == 0 &&
                 strstr(info.note, "our PLY reader does not know this header") &&
                 strstr(info.note, "read by assimp"),
             "%u, %s, %s", m.triangle_count, info.format, info.note);
  bk_mesh_free(&m);
  bk_import_info_free(&info);
  // Such a file damaged never reaches assimp (which trusts indices): the
  // body is walked first and the problem named.
  const char* bad_strip = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                          "property float z\nelement tristrips 1\nproperty list int int vertex_indices\n"
                          "end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n6 0 2 1 3 0 4000000\n";
  ENSURE(!bk_model_import_memory(bad_strip, strlen(bad_strip), "ply", "bad.ply", NULL, &m, &info, &err));
  ENSURE_MSG(strstr(err.message, "bad.ply: PLY element 1 item 0 names vertex 4000000 of 4"), "%s",
             err.message);
  const char* short_strip = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                            "property float z\nelement tristrips 1\nproperty list int int vertex_indices\n"
                            "end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n6 0 2 1\n";
  ENSURE(
      !bk_model_import_memory(short_strip, strlen(short_strip), "ply", "short.ply", NULL, &m, &info, &err));
  ENSURE_MSG(strstr(err.message, "short.ply: PLY element 1 item 0 ends early"), "%s", err.message);
  // The CLI says it too.
  run_result* r = run("fracture --mesh '" MODELS "/PLY/Wuson.ply' --pieces 2");
  ENSURE_MSG(strstr(r->err, "Wuson.ply: PLY header line 3") && !strstr(r->err, "malformed PLY header"), "%s",
             r->err);
}

// ---------------------------------------------------------------- textures

static bool contains(const unsigned char* data, size_t size, const void* what, size_t length) {
  for (size_t i = 0; i + length <= size; ++i)
    if (memcmp(data + i, what, length) == 0) return true;
  return false;
}

// The export's only image is a PNG: its mime type and the bytes' signature.
static void ensure_png_export(const char* glb) {
  size_t size = 0;
  unsigned char* data = read_whole(glb, &size);
  ENSURE_MSG(contains(data, size, "\"mimeType\":\"image/png\"", 22), "%s: no PNG image", glb);
  ENSURE_MSG(!contains(data, size, "image/jpeg", 10), "%s", glb);
  ENSURE_MSG(contains(data, size, "\x89PNG\r\n\x1a\n", 8), "%s: no PNG signature", glb);
  free(data);
}

// A 2 x 2 24-bit BMP: red, green / blue, white.
static void write_bmp(const char* path) {
  unsigned char bmp[70] = {'B', 'M', 70, 0, 0, 0, 0, 0, 0, 0,  54, 0, 0, 0, 40, 0,  0, 0, 2,
                           0,   0,   0,  2, 0, 0, 0, 1, 0, 24, 0,  0, 0, 0, 0,  16, 0, 0, 0};
  // Rows bottom up, b g r, each padded to 4 bytes.
  const unsigned char pixels[16] = {255, 0, 0, 255, 255, 255, 0, 0, 0, 0, 255, 0, 255, 0, 0, 0};
  memcpy(bmp + 54, pixels, sizeof pixels);
  FILE* f = fopen(path, "wb");
  ENSURE(f != NULL);
  ENSURE(fwrite(bmp, 1, sizeof bmp, f) == sizeof bmp);
  ENSURE(fclose(f) == 0);
}

static void test_textures_exported_as_png(void) {
  // The Collada duck's texture is a TGA file.
  run_result* r =
      run("fracture --mesh '" MODELS "/Collada/duck.dae' --pieces 4 --export-gltf '" TMP "duck.glb'");
  ENSURE_MSG(r->status == 0 && !strstr(r->err, "without"), "%s", r->err);
  ensure_png_export(TMP "duck.glb");
  // An OBJ whose MTL names a BMP.
  write_bmp(TMP "skin.bmp");
  write_text(TMP "skin.mtl", "newmtl skin\nKd 1 1 1\nmap_Kd import_models_skin.bmp\n");
  write_box_obj(TMP "skin.obj", 1, 1, 1, -1, "import_models_skin.mtl");
  r = run("fracture --mesh '" TMP "skin.obj' --pieces 2 --export-gltf '" TMP "skin.glb'");
  ENSURE_MSG(r->status == 0 && !strstr(r->err, "without"), "%s", r->err);
  ensure_png_export(TMP "skin.glb");
}

// ---------------------------------------------------------------- play

static bool have_xvfb(void) { return system("command -v xvfb-run >/dev/null 2>&1") == 0; }

static unsigned char* play_picture(const char* options, int* w, int* h) {
  char command[4096];
  snprintf(
      command, sizeof command,
      "xvfb-run -a -s '-screen 0 1280x720x24' '%s' play %s --frames 30 --hide-panel --hide-hud --width 320 "
      "--height 180 --screenshot '%s' >/dev/null 2>'%s'",
      BK_BREAKABLES_EXE, options, TMP "play.png", RUN_STDERR_PATH);
  ENSURE_MSG(system(command) == 0, "%s", command);
  int channels = 0;
  unsigned char* pixels = stbi_load(TMP "play.png", w, h, &channels, 3);
  ENSURE(pixels != NULL);
  return pixels;
}

// The duck's own yellow (its TGA texture) on its surface, not stone.
static void test_play_draws_the_model_texture(void) {
  int w = 0, h = 0;
  unsigned char* p = play_picture("--mesh '" MODELS "/Collada/duck.dae'", &w, &h);
  uint32_t yellow = 0;
  for (int i = 0; i < w * h; ++i)
    yellow += p[3 * i] > 150 && p[3 * i + 1] > 120 && p[3 * i + 2] < 80;
  stbi_image_free(p);
  ENSURE_MSG(yellow > (uint32_t)(w * h) / 50, "%u yellow pixels of %d", yellow, w * h);
}

// A spider 193 m across (an FBX in centimetres) is seen: the middle of the
// picture is not one flat fill.
static void test_play_frames_a_large_model(void) {
  int w = 0, h = 0;
  unsigned char* p = play_picture("--mesh '" MODELS "/FBX/spider.fbx'", &w, &h);
  double sum = 0.0, sum_sq = 0.0;
  int count = 0;
  for (int y = h / 3; y < 2 * h / 3; ++y)
    for (int x = w / 3; x < 2 * w / 3; ++x) {
      double v = p[3 * (y * w + x)] + p[3 * (y * w + x) + 1] + p[3 * (y * w + x) + 2];
      sum += v, sum_sq += v * v, count++;
    }
  stbi_image_free(p);
  double spread = sqrt(fmax(0.0, sum_sq / count - (sum / count) * (sum / count)));
  ENSURE_MSG(spread > 10.0, "the middle of the picture is flat (spread %g)", spread);
}

// A format's default material (3DS's "Default", 0.78 grey, untextured) is
// no look of the model's own: play draws such a model in the chosen
// material (the rock fels.3ds was drawn flat white); a texture is one.
static void test_default_material_is_no_look(void) {
  app_model_surface surface = {0};
  ENSURE_MSG(!app_read_model_surface(MODELS "/3DS/fels.3ds", &surface),
             "fels.3ds's default grey was taken as its look (%g %g %g)", surface.color[0], surface.color[1],
             surface.color[2]);
  app_model_surface_free(&surface);
  ENSURE(app_read_model_surface(MODELS "/Collada/duck.dae", &surface) && surface.image != NULL);
  app_model_surface_free(&surface);
}

int main(void) {
  FILE* f = fopen(MODELS "/OBJ/spider.obj", "rb");
  ENSURE_MSG(f != NULL, "%s is missing: scripts/setup.sh installs assimp-testmodels", MODELS);
  fclose(f);
  RUN(test_flipped_face_turned);
  RUN(test_spider_forms);
  RUN(test_scale_and_units);
  RUN(test_fbx_units);
  RUN(test_size_warning);
  RUN(test_wuson_ply);
  RUN(test_textures_exported_as_png);
  RUN(test_default_material_is_no_look);
  if (have_xvfb()) {
    RUN(test_play_draws_the_model_texture);
    RUN(test_play_frames_a_large_model);
  } else {
    fprintf(stderr, "test_import_models: no xvfb-run: play's pictures not checked\n");
  }
  fprintf(stderr, "test_import_models: all passed\n");
  return 0;
}
