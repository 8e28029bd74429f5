// The game's fracture patterns: which pattern each scene's objects break
// by, the parameters fitted to them (a brick bond on the wall's texture
// whatever its scale, a radial pattern round where the shot lands, in the
// frame of the object's tree), the cache key that tells every parameter
// apart, and `sim --pattern` as a user runs it.
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "ensure.h"
#include "scene_run.h"

#define RUN_STDERR_PATH BK_TEST_TMP "/scene_patterns_stderr.txt"
#include "run_exe.h"

#include "cli_util.h"

#define CACHE BK_TEST_TMP "/scene_patterns_cache"

static const scene_object* find_object(const char* scene, const char* mesh) {
  const app_scene* s = scene_find(scene);
  ENSURE_MSG(s != NULL, "no scene %s", scene);
  for (uint32_t i = 0; i < s->object_count; ++i)
    if (strcmp(s->objects[i].mesh, mesh) == 0) return &s->objects[i];
  ENSURE_MSG(false, "scene %s has no %s", scene, mesh);
  return NULL;
}

// The scenes' choices: the walls brick, the pillars clustered, the bunnies,
// the torus (broken round where it is hit) and the structures (towers,
// bridges, balconies) radial, the eggshells voronoi, everything else planes.
static void test_scene_table(void) {
  const struct {
    const char* mesh;
    bk_fracture_pattern pattern;
  } expected[] = {
      {"wall", BK_PATTERN_BRICK},       {"pillar", BK_PATTERN_CLUSTERED}, {"bunny", BK_PATTERN_RADIAL},
      {"eggshell", BK_PATTERN_VORONOI}, {"slab", BK_PATTERN_PLANES},      {"torus", BK_PATTERN_RADIAL},
      {"tower", BK_PATTERN_RADIAL},     {"bridge", BK_PATTERN_RADIAL},    {"balcony", BK_PATTERN_RADIAL}};
  for (uint32_t i = 0; i < scene_count(); ++i) {
    const app_scene* s = scene_at(i);
    for (uint32_t o = 0; o < s->object_count; ++o)
      for (size_t e = 0; e < sizeof expected / sizeof *expected; ++e)
        if (strcmp(s->objects[o].mesh, expected[e].mesh) == 0)
          ENSURE_MSG(s->objects[o].pattern == expected[e].pattern, "%s's %s breaks by %s, not %s", s->name,
                     expected[e].mesh, bk_fracture_pattern_name(s->objects[o].pattern),
                     bk_fracture_pattern_name(expected[e].pattern));
  }
  ENSURE(find_object("showcase", "wall")->pattern == BK_PATTERN_BRICK);
  bk_fracture_pattern p = BK_PATTERN_PLANES;
  bk_error err = {0};
  ENSURE(scene_pattern_from_name("clustered", &p, &err) && p == BK_PATTERN_CLUSTERED);
  ENSURE(!scene_pattern_from_name("gravel", &p, &err));
  ENSURE_MSG(strcmp(err.message, "unknown pattern 'gravel': use planes, voronoi, clustered, radial, brick or "
                                 "cutout") == 0,
             "%s", err.message);
}

// The brick bond stays on the texture: the tree is cut from the scaled mesh
// while its uvs are the unscaled mesh's, so the bond scales with the object;
// where the object stands and how it is turned change nothing.
static void test_brick_follows_texture(void) {
  scene_options options = default_scene_options();
  bk_fracture_def defaults = bk_default_fracture_def();
  bk_fracture_def wall = scene_fracture_def(scene_find("wall"), 0, &options, NULL);
  ENSURE(wall.pattern == BK_PATTERN_BRICK && wall.pieces == scene_find("wall")->pieces);
  ENSURE(wall.brick_size.x == defaults.brick_size.x && wall.brick_size.y == defaults.brick_size.y);
  ENSURE(wall.brick_size.z == 0.0 && bk_v3_length(wall.brick_origin) == 0.0);
  app_scene scaled = *scene_find("wall");
  scaled.objects[0].scale = 2.0;
  scaled.objects[0].position = bk_v3(3.0, 0.5, -7.0);
  scaled.objects[0].axis = bk_v3(0, 1, 0);
  scaled.objects[0].angle = 0.7;
  bk_fracture_def big = scene_fracture_def(&scaled, 0, &options, NULL);
  ENSURE_SMALL(big.brick_size.x, 0.5, 1e-15);
  ENSURE_SMALL(big.brick_size.y, 0.25, 1e-15);
  ENSURE(big.brick_offset == defaults.brick_offset && bk_v3_length(big.brick_origin) == 0.0);
  // The showcase's wall stands elsewhere, unscaled: the same bond.
  const app_scene* showcase = scene_find("showcase");
  bk_fracture_def far = scene_fracture_def(showcase, 0, &options, NULL);
  ENSURE(far.pattern == BK_PATTERN_BRICK && far.brick_size.x == defaults.brick_size.x);
}

// The radial pattern's impact, in the tree's frame: the aim point taken
// back through the object's rotation and position (the tree is the scaled
// mesh, so not through its scale), then along the shot to the surface.
static void test_radial_impact(void) {
  scene_options options = default_scene_options();
  const app_scene* showcase = scene_find("showcase");
  uint32_t bunny = 3;
  ENSURE(strcmp(showcase->objects[bunny].mesh, "bunny") == 0);
  bk_vec3 aim = scene_object_aim(showcase, bunny);
  ENSURE(aim.x == showcase->extra_targets[1].x && aim.z == showcase->extra_targets[1].z);
  bk_fracture_def inside = scene_fracture_def(showcase, bunny, &options, NULL);
  bk_vec3 expected = bk_v3_sub(aim, showcase->objects[bunny].position);
  ENSURE_SMALL(bk_v3_length(bk_v3_sub(inside.impact, expected)), 0.0, 1e-12);

  // A turned, moved and scaled bunny: the impact lies on its scaled mesh,
  // on the line from the eye through the aim point, on the eye's side.
  app_scene turned = *scene_find("bunny");
  scene_object* o = &turned.objects[0];
  o->position = bk_v3(0.4, 0.1, -0.3);
  o->axis = bk_v3(0, 1, 0);
  o->angle = 2.0;
  o->scale = 1.5;
  turned.target = bk_v3(0.4, 0.6, -0.3);
  bk_mesh source = {0};
  ENSURE(scene_object_source(o, &source));
  bk_aabb box = bk_mesh_bounds(&source);
  ENSURE_SMALL(box.max.y - box.min.y, 1.5, 1e-9); // the bunny is 1 tall, scaled by 1.5
  bk_fracture_def def = scene_fracture_def(&turned, 0, &options, &source);
  bk_transform place = {o->position, bk_quat_axis_angle(o->axis, o->angle)};
  bk_vec3 world = bk_transform_point(place, def.impact);
  bk_vec3 to_aim = bk_v3_sub(turned.target, turned.eye), to_hit = bk_v3_sub(world, turned.eye);
  double off_line = bk_v3_length(bk_v3_cross(bk_v3_normalize(to_aim), to_hit));
  ENSURE_MSG(off_line < 1e-9, "the impact is %g off the line of the shot", off_line);
  ENSURE(bk_v3_dot(to_hit, to_aim) > 0.0 && bk_v3_length(to_hit) < bk_v3_length(to_aim));
  double nearest = 1e30; // on the surface: as close to a triangle of the mesh as rounding allows
  for (uint32_t t = 0; t < source.triangle_count; ++t) {
    bk_vec3 a = source.positions[bk_mesh_tri_position(&source, t, 0)];
    bk_vec3 n = bk_v3_cross(bk_v3_sub(source.positions[bk_mesh_tri_position(&source, t, 1)], a),
                            bk_v3_sub(source.positions[bk_mesh_tri_position(&source, t, 2)], a));
    if (bk_v3_length(n) > 0.0) {
      double d = fabs(bk_v3_dot(bk_v3_normalize(n), bk_v3_sub(def.impact, a)));
      bool within = bk_v3_length(bk_v3_sub(def.impact, a)) < 0.1;
      if (within && d < nearest) nearest = d;
    }
  }
  ENSURE_MSG(nearest < 1e-9, "the impact is %g from the surface", nearest);
  bk_mesh_free(&source);
}

// The options' pattern overrides every object's; its parameters go through.
static void test_override(void) {
  scene_options options = default_scene_options();
  ENSURE(options.pattern == -1);
  options.pattern = BK_PATTERN_CUTOUT;
  options.clusters = 9;
  options.radial_falloff = 0.0;
  const app_scene* showcase = scene_find("showcase");
  for (uint32_t i = 0; i < showcase->object_count; ++i) {
    bk_fracture_def d = scene_fracture_def(showcase, i, &options, NULL);
    ENSURE(d.pattern == BK_PATTERN_CUTOUT && d.clusters == 9 && d.radial_falloff == 0.0);
    ENSURE(d.cutout_pixels != NULL && d.cutout_width >= 2 && d.cutout_height >= 2);
    bk_error err = {0};
    ENSURE_MSG(bk_fracture_def_validate(&d, &err), "%s", err.message);
  }
}

// The panel's noise is a fraction of each object's size: it reaches every
// pattern that takes noise (planes too), scaled by the object's mesh, and
// leaves brick flat; without the mesh there is no size and no noise.
static void test_noise_option(void) {
  scene_options options = default_scene_options();
  ENSURE(options.noise == 0.0);
  options.noise = 0.02;
  const app_scene* showcase = scene_find("showcase");
  uint32_t noisy = 0, brick = 0;
  for (uint32_t i = 0; i < showcase->object_count; ++i) {
    bk_mesh source = {0};
    ENSURE(scene_object_source(&showcase->objects[i], &source));
    bk_aabb box = bk_mesh_bounds(&source);
    double size = bk_v3_length(bk_v3_sub(box.max, box.min));
    bk_fracture_def d = scene_fracture_def(showcase, i, &options, &source);
    bk_error err = {0};
    ENSURE_MSG(bk_fracture_def_validate(&d, &err), "%s", err.message);
    if (d.pattern == BK_PATTERN_BRICK) {
      ENSURE(d.noise_amplitude == 0.0);
      brick++;
    } else {
      ENSURE_REL(d.noise_amplitude, 0.02 * size, 1e-12);
      ENSURE_REL(d.noise_frequency, 4.0 / size, 1e-12);
      noisy++;
    }
    ENSURE(scene_fracture_def(showcase, i, &options, NULL).noise_amplitude == 0.0);
    bk_mesh_free(&source);
  }
  ENSURE(noisy > 0 && brick > 0);
  options.pattern = BK_PATTERN_PLANES;
  bk_mesh source = {0};
  ENSURE(scene_object_source(&showcase->objects[0], &source));
  ENSURE(scene_fracture_def(showcase, 0, &options, &source).noise_amplitude > 0.0);
  bk_mesh_free(&source);
}

// Every parameter that shapes a tree changes the key; the progress
// callback and the thread count do not (the tree is the same for any).
static void test_fracture_key(void) {
  static const bk_vec3 points[2] = {{0.1, 0.2, 0.3}, {0.3, 0.2, 0.1}};
  static const uint8_t pixels[4] = {0, 255, 255, 0};
  bk_fracture_def base = bk_default_fracture_def();
  base.seed_points = points, base.seed_point_count = 2;
  base.cutout_pixels = pixels, base.cutout_width = base.cutout_height = 2;
  uint64_t key = app_fracture_key(&base);
  enum { CHANGES = 24 };
  for (int c = 0; c < CHANGES; ++c) {
    bk_fracture_def d = base;
    bk_vec3 moved[2] = {points[0], points[1]};
    uint8_t flipped[4] = {pixels[0], pixels[1], pixels[2], pixels[3]};
    switch (c) {
    case 0:
      d.pattern = BK_PATTERN_VORONOI;
      break;
    case 1:
      d.pattern = BK_PATTERN_BRICK;
      break;
    case 2:
      d.pieces += 1;
      break;
    case 3:
      d.seed += 1;
      break;
    case 4:
      d.texture_scale *= 2.0;
      break;
    case 5:
      d.jitter += 0.01;
      break;
    case 6:
      d.aspect_bias += 1.0;
      break;
    case 7:
      d.clusters += 1;
      break;
    case 8:
      d.cluster_border *= 2.0;
      break;
    case 9:
      d.impact.x += 0.5;
      break;
    case 10:
      d.impact.z -= 1e-9;
      break;
    case 11:
      d.radial_falloff = 0.5;
      break;
    case 12:
      d.brick_size.y *= 2.0;
      break;
    case 13:
      d.brick_size.z = 0.1;
      break;
    case 14:
      d.brick_origin.x = 0.125;
      break;
    case 15:
      d.brick_offset = 0.25;
      break;
    case 16:
      d.cutout_axis = 0;
      break;
    case 17:
      d.noise_amplitude = 0.01;
      break;
    case 18:
      d.noise_frequency = 4.0;
      break;
    case 19:
      d.seed_point_count = 1;
      break;
    case 20:
      moved[1].y += 1e-6, d.seed_points = moved;
      break;
    case 21:
      flipped[0] = 255, d.cutout_pixels = flipped;
      break;
    case 22:
      d.cutout_width = 1, d.cutout_height = 4;
      break;
    default:
      d.pattern = BK_PATTERN_CUTOUT;
      break;
    }
    ENSURE_MSG(app_fracture_key(&d) != key, "change %d leaves the cache key as it was", c);
  }
  bk_fracture_def same = base;
  same.threads = 3;
  same.progress_user = &same;
  ENSURE(app_fracture_key(&same) == key);
}

static int cache_files(const char* pattern_name) {
  DIR* dir = opendir(CACHE);
  ENSURE(dir != NULL);
  int count = 0;
  char part[32];
  snprintf(part, sizeof part, "-%s-", pattern_name);
  for (struct dirent* entry = readdir(dir); entry; entry = readdir(dir))
    count += strstr(entry->d_name, part) != NULL;
  closedir(dir);
  return count;
}

// Switching patterns never loads a tree made by another one, even from a
// file whose name was made to match: the file's own parameters are checked.
static void test_cache_switches_pattern(void) {
  ENSURE(system("rm -rf '" CACHE "'") == 0);
  setenv("BREAKABLES_CACHE_DIR", CACHE, 1);
  const char* kinds[] = {"planes", "voronoi", "planes", "voronoi"};
  for (int i = 0; i < 4; ++i) {
    char args[256];
    snprintf(args, sizeof args, "sim --scene wall --pieces 24 --steps 1 --shots 0 --pattern %s --json",
             kinds[i]);
    run_result* r = run(args);
    ENSURE_MSG(r->status == 0, "%s", r->err);
    char said[64];
    snprintf(said, sizeof said, "\"pattern\": \"%s\"", kinds[i]);
    ENSURE_MSG(strstr(r->out, said) != NULL, "asked for %s: %s", kinds[i], r->out);
    const char* cached = i < 2 ? "\"from_cache\": false" : "\"from_cache\": true";
    ENSURE_MSG(strstr(r->out, cached) != NULL, "run %d (%s): %s", i, kinds[i], r->out);
  }
  ENSURE(cache_files("planes") == 1 && cache_files("voronoi") == 1);
  // A planes tree under the voronoi file's name is refused and made again.
  ENSURE(system("cd '" CACHE
                "' && cp wall-*-planes-*.mtree planes.tmp && for f in wall-*-voronoi-*.mtree; do "
                "mv planes.tmp \"$f\"; done") == 0);
  run_result* r = run("sim --scene wall --pieces 24 --steps 1 --shots 0 --pattern voronoi --json");
  ENSURE_MSG(r->status == 0 && strstr(r->out, "\"pattern\": \"voronoi\"") &&
                 strstr(r->out, "\"from_cache\": false"),
             "%s%s", r->out, r->err);
}

// sim --pattern: every object broken by it, the pieces asked for exactly,
// reported in --json; a wrong name is one line listing the patterns.
static void test_sim_pattern(void) {
  setenv("BREAKABLES_CACHE_DIR", CACHE, 1);
  run_result* r = run("sim --scene showcase --pattern voronoi --pieces 40 --shots 2 --steps 90 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE_MSG(strstr(r->out, "\"pattern\": \"voronoi\", \"patterns\": [\"voronoi\", \"voronoi\", \"voronoi\", "
                            "\"voronoi\", \"voronoi\", \"voronoi\"]"),
             "%s", r->out);
  ENSURE_MSG(json_number(r->out, "pieces") == 6 * 40, "%s", r->out);
  ENSURE(strstr(r->out, "\"nan\": false") && json_number(r->out, "mass_rel_error") < 1e-9);
  // Without it, each object its own, and the wall one piece per brick.
  r = run("sim --scene showcase --pieces 40 --steps 1 --shots 0 --json");
  ENSURE_MSG(strstr(r->out, "\"pattern\": \"mixed\", \"patterns\": [\"brick\", \"clustered\", \"planes\", "
                            "\"radial\", \"voronoi\", \"radial\"]"),
             "%s", r->out);
  r = run("sim --scene wall --steps 1 --shots 0 --json");
  ENSURE_MSG(strstr(r->out, "\"pattern\": \"brick\"") && json_number(r->out, "pieces") == 85, "%s", r->out);
  r = run("sim --scene eggshell --steps 1 --shots 0");
  ENSURE_MSG(r->status == 0 && strstr(r->out, "  pattern voronoi\n"), "%s", r->out);

  const char* commands[] = {"sim", "play", "editor"};
  for (size_t i = 0; i < sizeof commands / sizeof *commands; ++i) {
    char args[128], message[200];
    snprintf(args, sizeof args, "%s --pattern gravel", commands[i]);
    r = run(args);
    snprintf(
        message, sizeof message,
        "breakables %s: unknown pattern 'gravel': use planes, voronoi, clustered, radial, brick or cutout\n",
        commands[i]);
    ENSURE_MSG(r->status == 2 && strcmp(r->err, message) == 0, "'%s' exited %d: %s", args, r->status, r->err);
    snprintf(args, sizeof args, "%s --help", commands[i]);
    r = run(args);
    ENSURE_MSG(r->status == 0 && strstr(r->out, "--pattern NAME"), "%s --help: %s", commands[i], r->out);
  }
}

int main(void) {
  RUN(test_scene_table);
  RUN(test_brick_follows_texture);
  RUN(test_radial_impact);
  RUN(test_override);
  RUN(test_noise_option);
  RUN(test_fracture_key);
  RUN(test_cache_switches_pattern);
  RUN(test_sim_pattern);
  return 0;
}
