// The game and the editor, run as a user would under a virtual display
// (xvfb-run, Mesa's software OpenGL): every scene starts, runs scripted
// frames with autofire and saves a screenshot. The picture must show sky and
// objects, the shots must break something, and no GL error may occur.
#include <stb_image.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "ensure.h"

static char output[4096];

static int run(const char* args) {
  char command[2048];
  snprintf(command, sizeof command, "xvfb-run -a -s '-screen 0 1280x720x24' '%s' %s 2>'%s/game_stderr.txt'",
           BK_BREAKABLES_EXE, args, BK_TEST_TMP);
  FILE* pipe = popen(command, "r");
  ENSURE(pipe != NULL);
  size_t n = fread(output, 1, sizeof output - 1, pipe);
  output[n] = 0;
  int status = pclose(pipe);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    char path[512], err[4096] = {0};
    snprintf(path, sizeof path, "%s/game_stderr.txt", BK_TEST_TMP);
    FILE* f = fopen(path, "rb");
    if (f) {
      size_t got = fread(err, 1, sizeof err - 1, f);
      err[got] = 0;
      fclose(f);
    }
    fprintf(stderr, "'%s' failed:\n%s\n%s\n", args, output, err);
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static int compare_doubles(const void* a, const void* b) {
  double x = *(const double*)a, y = *(const double*)b;
  return (x > y) - (x < y);
}

typedef struct picture_stats {
  double sky_blue;      // mean (b - r) of the top rows: the sky is blue
  double center_spread; // colour spread in the middle: objects, not a flat fill
  double center_sky_difference;
} picture_stats;

static picture_stats measure(const char* path) {
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels = stbi_load(path, &w, &h, &channels, 3);
  ENSURE_MSG(pixels != NULL, "cannot read %s", path);
  picture_stats s = {0};
  double top[3] = {0}, centre[3] = {0}, centre_sq[3] = {0};
  int top_count = 0, centre_count = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const unsigned char* p = &pixels[3 * (y * w + x)];
      if (y < h / 10 && x > w / 2) { // top right: away from the panel
        for (int k = 0; k < 3; ++k)
          top[k] += p[k];
        top_count++;
      }
      if (y > h / 3 && y < 2 * h / 3 && x > w / 3 && x < 2 * w / 3) {
        for (int k = 0; k < 3; ++k)
          centre[k] += p[k], centre_sq[k] += (double)p[k] * p[k];
        centre_count++;
      }
    }
  for (int k = 0; k < 3; ++k) {
    top[k] /= top_count;
    centre[k] /= centre_count;
    s.center_spread += sqrt(fmax(0.0, centre_sq[k] / centre_count - centre[k] * centre[k]));
  }
  s.sky_blue = top[2] - top[0];
  s.center_sky_difference = fabs(centre[0] - top[0]) + fabs(centre[1] - top[1]) + fabs(centre[2] - top[2]);
  stbi_image_free(pixels);
  return s;
}

static void test_scene(const char* scene) {
  char args[1024], shot[512];
  snprintf(shot, sizeof shot, "%s/%s.png", BK_TEST_TMP, scene);
  remove(shot);
  snprintf(args, sizeof args,
           "play --scene %s --frames 60 --autofire 3 --screenshot '%s' --width 640 --height 360", scene,
           shot);
  ENSURE_MSG(run(args) == 0, "scene %s", scene);
  // "frames 60, bodies B (from B0), fragments free F, mean frame ms M (last second L, physics P),
  // shots 3, gl errors none": the shots at frames 15, 30 and 45 have broken something by the last.
  unsigned frames = 0, bodies = 0, from = 0;
  ENSURE_MSG(sscanf(output, "frames %u, bodies %u (from %u)", &frames, &bodies, &from) == 3, "summary: %s",
             output);
  ENSURE(frames == 60);
  ENSURE_MSG(bodies > from, "%s: the shots broke nothing (%u bodies, from %u)", scene, bodies, from);
  ENSURE_MSG(strstr(output, "gl errors none") != NULL, "%s", output);
  picture_stats s = measure(shot);
  ENSURE_MSG(s.sky_blue > 20.0, "%s: no blue sky at the top (b - r = %.1f)", scene, s.sky_blue);
  ENSURE_MSG(s.center_spread > 15.0 && s.center_sky_difference > 40.0,
             "%s: the middle of the picture looks empty (spread %.1f, difference from sky %.1f)", scene,
             s.center_spread, s.center_sky_difference);
  fprintf(stderr, "    %s: bodies %u -> %u, sky b-r %.0f, centre spread %.0f\n", scene, from, bodies,
          s.sky_blue, s.center_spread);
}

// Share of the pixels in the band of ground round the showcase's objects
// (rows 50-72% down) at most half as bright as the band's median: their
// shadows on the ground, plus the darkest sides of the objects.
static double dark_ground_share(const char* path) {
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels = stbi_load(path, &w, &h, &channels, 3);
  ENSURE_MSG(pixels != NULL, "cannot read %s", path);
  int first = h / 2, end = h * 72 / 100, count = (end - first) * w;
  double* luminance = malloc(sizeof(double) * (size_t)count);
  double* sorted = malloc(sizeof(double) * (size_t)count);
  ENSURE(luminance != NULL && sorted != NULL);
  for (int y = first; y < end; ++y)
    for (int x = 0; x < w; ++x) {
      const unsigned char* p = &pixels[3 * (y * w + x)];
      luminance[(y - first) * w + x] = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    }
  stbi_image_free(pixels);
  memcpy(sorted, luminance, sizeof(double) * (size_t)count);
  qsort(sorted, (size_t)count, sizeof(double), compare_doubles);
  double median = sorted[count / 2];
  int dark = 0;
  for (int i = 0; i < count; ++i)
    dark += luminance[i] < 0.5 * median;
  free(sorted);
  free(luminance);
  return (double)dark / count;
}

// Mean luminance of the box [x0, x1) x [y0, y1) of the picture, as shares of its size.
static double box_luminance(const char* path, double x0, double x1, double y0, double y1) {
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels = stbi_load(path, &w, &h, &channels, 3);
  ENSURE_MSG(pixels != NULL, "cannot read %s", path);
  double sum = 0.0;
  int count = 0;
  for (int y = (int)(y0 * h); y < (int)(y1 * h); ++y)
    for (int x = (int)(x0 * w); x < (int)(x1 * w); ++x, ++count) {
      const unsigned char* p = &pixels[3 * (y * w + x)];
      sum += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    }
  stbi_image_free(pixels);
  return count ? sum / count : 0.0;
}

// The showcase as it stands, drawn in the order the passes need: the sun's
// shadow map darkens the ground beside the objects (3.5% of the band with
// it, 1.8% when every lookup passes, none when every lookup fails), and the
// depth test is on again after the sky, which is drawn without it (left off,
// the glazed eggshell turns dark grey: luminance 113 where it is 209).
static void test_showcase_picture(void) {
  char args[1024], shot[512];
  snprintf(shot, sizeof shot, "%s/showcase_still.png", BK_TEST_TMP);
  remove(shot);
  snprintf(
      args, sizeof args,
      "play --scene showcase --frames 2 --hide-panel --hide-hud --screenshot '%s' --width 640 --height 360",
      shot);
  ENSURE(run(args) == 0);
  double share = dark_ground_share(shot);
  ENSURE_MSG(share > 0.025, "no shadows on the ground beside the objects (dark share %.4f)", share);
  double egg = box_luminance(shot, 0.39, 0.42, 0.57, 0.65);
  ENSURE_MSG(egg > 170.0, "the eggshell is not drawn white (luminance %.1f)", egg);
  fprintf(stderr, "    showcase: dark share of the ground band %.4f, eggshell luminance %.0f\n", share, egg);
}

static void test_scenes(void) {
  const char* scenes[] = {"wall",  "eggshell", "pillar", "slab",   "bunny",
                          "torus", "showcase", "tower",  "bridge", "balcony"};
  for (size_t i = 0; i < sizeof scenes / sizeof *scenes; ++i)
    test_scene(scenes[i]);
}

static void test_editor(void) {
  char args[1024], shot[512];
  snprintf(shot, sizeof shot, "%s/editor.png", BK_TEST_TMP);
  snprintf(
      args, sizeof args,
      "editor --mesh torus --pieces 32 --explode 0.6 --frames 10 --screenshot '%s' --width 640 --height 360",
      shot);
  ENSURE(run(args) == 0);
  unsigned frames = 0, fragments = 0;
  ENSURE_MSG(sscanf(output, "frames %u, fragments %u", &frames, &fragments) == 2, "summary: %s", output);
  ENSURE(frames == 10 && fragments >= 32);
  ENSURE(strstr(output, "gl errors none") != NULL);
  picture_stats s = measure(shot);
  ENSURE(s.sky_blue > 20.0 && s.center_spread > 15.0);
}

// A user's own model, exported by fracture as glTF, is shot in the game:
// the tree is loaded as it is (its 40 fragments, not --pieces), stood in
// front of the camera and broken by the fitted shots; the editor opens it
// by path too.
static void test_own_model(void) {
  char args[2048], glb[512], shot[512];
  snprintf(glb, sizeof glb, "%s/own_model.glb", BK_TEST_TMP);
  snprintf(shot, sizeof shot, "%s/own_model.png", BK_TEST_TMP);
  snprintf(args, sizeof args, "fracture --mesh torus --pieces 40 --export-gltf '%s'", glb);
  ENSURE(run(args) == 0);
  snprintf(args, sizeof args,
           "play --mesh '%s' --material glass --pieces 512 --frames 60 --autofire 3 --screenshot '%s' "
           "--width 640 --height 360",
           glb, shot);
  ENSURE(run(args) == 0);
  unsigned frames = 0, bodies = 0, from = 0;
  ENSURE_MSG(sscanf(output, "frames %u, bodies %u (from %u)", &frames, &bodies, &from) == 3, "summary: %s",
             output);
  ENSURE_MSG(from == 1 && bodies > 1, "the shots broke nothing (%u bodies, from %u)", bodies, from);
  picture_stats s = measure(shot);
  ENSURE_MSG(s.center_spread > 15.0 && s.center_sky_difference > 40.0,
             "the model is not in view (%.1f, %.1f)", s.center_spread, s.center_sky_difference);
  snprintf(args, sizeof args, "editor --mesh '%s' --frames 3 --width 640 --height 360 --export '%s/edited'",
           glb, BK_TEST_TMP);
  ENSURE(run(args) == 0);
  unsigned fragments = 0;
  ENSURE_MSG(sscanf(output, "frames %u, fragments %u", &frames, &fragments) == 2 && fragments == 40, "%s",
             output);
  // The export the run ends with: the tree again, as .mtree and as .glb.
  ENSURE_MSG(strstr(output, "wrote ") && strstr(output, "edited.glb"), "%s", output);
  snprintf(args, sizeof args, "sim --mesh '%s/edited.glb' --shots 0 --steps 1 --json", BK_TEST_TMP);
  ENSURE(run(args) == 0);
  ENSURE_MSG(strstr(output, "\"pieces\": 40"), "%s", output);
}

// Pixels of the overlays' colour ramp (green, yellow, red: strong red or
// green, little blue); the sky, the ground and the objects have none.
static int ramp_pixels(const char* path) {
  int w = 0, h = 0, channels = 0, count = 0;
  unsigned char* pixels = stbi_load(path, &w, &h, &channels, 3);
  ENSURE_MSG(pixels != NULL, "cannot read %s", path);
  for (int i = 0; i < w * h; ++i) {
    const unsigned char* p = &pixels[3 * i];
    int top = p[0] > p[1] ? p[0] : p[1];
    count += top > 150 && p[2] < 0.4 * top;
  }
  stbi_image_free(pixels);
  return count;
}

// The stress overlay: a bridge with weakened limits, standing, shows its
// bonds in the ramp's colours once it is solved; with stress off the same
// bonds are grey (nothing solved).
static void test_stress_overlay(void) {
  char args[1024], shot[512];
  int counts[2] = {0, 0};
  for (int off = 0; off < 2; ++off) {
    snprintf(shot, sizeof shot, "%s/stress_overlay_%d.png", BK_TEST_TMP, off);
    snprintf(args, sizeof args,
             "play --scene bridge --stress-scale 0.3 --frames 30 --overlay stress --hide-panel%s "
             "--screenshot '%s' --width 640 --height 360",
             off ? " --no-stress" : "", shot);
    ENSURE_MSG(run(args) == 0, "%s", args);
    counts[off] = ramp_pixels(shot);
  }
  fprintf(stderr, "    ramp-coloured pixels: %d with stress, %d without\n", counts[0], counts[1]);
  ENSURE(counts[0] > 500 && counts[1] < counts[0] / 20);
}

// A weight set down on the bridge in the game (issue 17): 20 t at frame 60
// breaks the deck by frame 140 (the load breaks its first bonds about 22
// frames later, and the deck is off its legs by frame 100); 500 kg is
// carried (the bridge's old concrete gives way under 1 t).
static void test_drop_weight(void) {
  char args[1024], shot[512];
  unsigned bodies[2] = {0, 0};
  const char* masses[2] = {"500", "20000"};
  for (int heavy = 0; heavy < 2; ++heavy) {
    snprintf(shot, sizeof shot, "%s/drop_weight_%s.png", BK_TEST_TMP, masses[heavy]);
    snprintf(
        args, sizeof args,
        "play --scene bridge --drop %s --frames 140 --hide-panel --screenshot '%s' --width 640 --height 360",
        masses[heavy], shot);
    ENSURE_MSG(run(args) == 0, "%s", args);
    unsigned frames = 0, from = 0;
    ENSURE_MSG(sscanf(output, "frames %u, bodies %u (from %u)", &frames, &bodies[heavy], &from) == 3 &&
                   from == 1,
               "summary: %s", output);
    ENSURE_MSG(strstr(output, "shots 0, weights 1, gl errors none") != NULL, "%s", output);
  }
  fprintf(stderr, "    bridge bodies after 140 frames: %u under 500 kg, %u under 20 t\n", bodies[0],
          bodies[1]);
  ENSURE(bodies[0] == 1 && bodies[1] > 5);
}

// Brick-red pixels (the wall's bricks, and what falls from it) in the rows
// [y0, y1) of the picture, as shares of its height.
static int brick_pixels(const char* path, double y0, double y1) {
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels = stbi_load(path, &w, &h, &channels, 3);
  ENSURE_MSG(pixels != NULL, "cannot read %s", path);
  int count = 0;
  for (int y = (int)(y0 * h); y < (int)(y1 * h); ++y)
    for (int x = 0; x < w; ++x) {
      const unsigned char* p = &pixels[3 * (y * w + x)];
      count += p[0] > p[1] + 50 && p[0] > p[2] + 60;
    }
  stbi_image_free(pixels);
  return count;
}

// play --refine (issue 34): the 64-fragment wall shot three times refines
// the fragments it is hit on (the summary counts them, and the first
// object's fragments grow by them) and breaks into far more bodies than
// without; the refined pieces are drawn: the band of the picture below the
// wall's middle, where they fall, shows more brick than the same shots
// without refinement (were the grown trees' new nodes not uploaded, they
// would vanish and leave less). Every overlay on over a grown tree draws
// without a GL error.
static void test_refine(void) {
  char args[1024], shot[512];
  unsigned bodies[2] = {0, 0};
  int low_brick[2] = {0, 0};
  for (int refine = 0; refine < 2; ++refine) {
    snprintf(shot, sizeof shot, "%s/refine_%d.png", BK_TEST_TMP, refine);
    remove(shot);
    // No physics budget: it goes by the clock, and the pictures must repeat.
    snprintf(
        args, sizeof args,
        "play --scene wall --pieces 64 --frames 240 --autofire 3 --budget-ms 0 --hide-panel --hide-hud%s "
        "--screenshot '%s' --width 480 --height 270",
        refine ? " --refine" : "", shot);
    ENSURE_MSG(run(args) == 0, "%s", args);
    unsigned frames = 0, from = 0, refined = 0, leaves = 0, grown = 0;
    ENSURE_MSG(sscanf(output, "frames %u, bodies %u (from %u)", &frames, &bodies[refine], &from) == 3,
               "summary: %s", output);
    ENSURE_MSG(strstr(output, "gl errors none") != NULL, "%s", output);
    const char* line = strstr(output, "refined ");
    if (refine) {
      ENSURE_MSG(line && sscanf(line, "refined %u fragments: the first object's %u -> %u", &refined, &leaves,
                                &grown) == 3,
                 "%s", output);
      ENSURE_MSG(refined > 0 && leaves == 64 && grown >= leaves + refined, "%s", output);
    } else {
      ENSURE_MSG(line == NULL, "%s", output);
    }
    low_brick[refine] = brick_pixels(shot, 0.62, 1.0);
  }
  fprintf(stderr,
          "    wall of 64, 3 shots: bodies %u, %u refined; brick pixels below the middle %d, %d refined\n",
          bodies[0], bodies[1], low_brick[0], low_brick[1]);
  ENSURE(bodies[1] > 4 * bodies[0]);
  ENSURE(low_brick[1] > low_brick[0] * 6 / 5);
  ENSURE(
      run("play --scene wall --pieces 64 --refine --frames 120 --autofire 2 --overlay bonds --overlay stress "
          "--overlay nodes --overlay hulls --overlay budget --hide-panel --width 320 --height 180") == 0);
  ENSURE_MSG(strstr(output, "gl errors none") != NULL && strstr(output, "refined "), "%s", output);
}

// Without a display the game says so in one line and exits 1 (no crash).
static void test_no_display(void) {
  char command[1024];
  snprintf(command, sizeof command, "env -u DISPLAY -u WAYLAND_DISPLAY '%s' play --frames 1 2>&1",
           BK_BREAKABLES_EXE);
  FILE* pipe = popen(command, "r");
  ENSURE(pipe != NULL);
  size_t n = fread(output, 1, sizeof output - 1, pipe);
  output[n] = 0;
  int status = pclose(pipe);
  ENSURE(WIFEXITED(status) && WEXITSTATUS(status) == 1);
  ENSURE_MSG(strstr(output, "cannot open a window") != NULL, "%s", output);
  const char* newline = strchr(output, '\n');
  ENSURE_MSG(newline && newline[1] == 0, "not one line: %s", output);
}

static void test_bad_options(void) {
  ENSURE(run("play --scene castle --frames 1") == 2);
  ENSURE(run("play --frames 0") == 2);
  ENSURE(run("editor --pieces 0 --frames 1") == 2);
}

int main(void) {
  setenv("BREAKABLES_CACHE_DIR", BK_TEST_TMP "/cache", 1);
  if (system("command -v xvfb-run >/dev/null 2>&1") != 0) {
    fprintf(stderr, "xvfb-run is missing: scripts/setup.sh installs it\n");
    return 1;
  }
  RUN(test_no_display);
  RUN(test_bad_options);
  RUN(test_editor);
  RUN(test_own_model);
  RUN(test_stress_overlay);
  RUN(test_drop_weight);
  RUN(test_refine);
  RUN(test_showcase_picture);
  RUN(test_scenes);
  return 0;
}
