// breakables editor: preview the fragments of a mesh (thesis Appendix A).
// Orbit with Alt + left drag, zoom with Alt + right drag, pull the fragments
// apart with Shift + drag or the explode slider; change mesh, pattern, pieces,
// seed and texture scale; export the fragments to OBJ and the tree to .mtree and .glb.
#include <GLFW/glfw3.h>
#include <stdio.h>
#include <string.h>

#include <stdlib.h>

#include "commands.h"
#include "particles.h"
#include "scene_run.h"
#include "ui.h"
#include "window.h"

static const char* const editor_usage =
    "usage: breakables editor [--mesh NAME|PATH] [--pattern NAME] [--pieces N] [--seed S]\n"
    "                         [--texture-scale X] [--noise X] [--explode X] [--colors]\n"
    "                         [--export PATH]\n"
    "                         [--frames N] [--screenshot FILE.png]\n"
    "                         [--width W] [--height H] [--max-memory MIB]\n"
    "                         [--scale S] [--units mm|cm|m|in]\n"
    "\n"
    "Preview the fragments of a mesh and export them.\n"
    "\n"
    "options:\n"
    "  --mesh NAME|PATH      cube, torus, eggshell, bunny, wall, slab, pillar, tower, bridge,\n"
    "                        balcony, a model file or an .mtree (default: bunny); the panel\n"
    "                        opens others by path\n" BK_MODEL_UNITS_USAGE
    "  --pattern NAME        planes, voronoi, clustered, radial, brick or cutout (default: planes);\n"
    "                        radial centres on the surface facing the first view, brick follows\n"
    "                        the wall's brick texture, cutout uses the game's cobweb map\n"
    "  --pieces N            fragments, 1..65536 (default: 64)\n"
    "  --seed S              fracture seed, 0..2147483647 (default: 3000)\n"
    "  --texture-scale X     world size of one interior texture tile, 1e-6..1e6 (default: 0.1)\n"
    "  --noise X             rough cut faces: how far they bend, a fraction of the mesh's size,\n"
    "                        0..0.1, at four noise waves per size (default: 0, flat; brick\n"
    "                        stays flat along its mortar)\n"
    "  --explode X           pull fragments apart, 0..3 (default: 0)\n"
    "  --colors              tint each fragment its own colour (the panel's 'colors' box)\n"
    "  --export PATH         where the panel's export writes: PATH.obj, PATH.mtree and PATH.glb\n"
    "                        (default: fragments, in the current directory); a run with\n"
    "                        --frames exports there when it ends\n"
    "  --frames N            run N frames, 1..10000000, then exit with a one-line summary\n"
    "  --screenshot FILE.png save the last frame\n"
    "  --width W --height H  window size, each 64..8192 (default: 1280x720)\n"
    "  --max-memory MIB      memory a fracture may use, 1..1073741824 MiB (default: the\n"
    "                        available memory); a tree estimated to need more is refused\n"
    "  -h, --help            show this help\n"
    "\n"
    "controls: Alt + left drag = orbit, Alt + right drag = zoom, Shift + drag = explode,\n"
    "F1 = panel, Esc = quit.\n";

typedef struct editor {
  GLFWwindow* window;
  app_renderer* renderer;
  bool ui, show_panel;
  char mesh[4096];
  char open_path[4096];   // the panel's "open" field
  char export_path[4096]; // the panel's export base name: <path>.obj and <path>.mtree
  char file_label[128];   // the mesh selector's entry for a file (its name)
  int mesh_choice;
  int pattern; // a bk_fracture_pattern
  int pieces, seed;
  double texture_scale, explode;
  double noise; // cut faces' noise amplitude, a fraction of the mesh's size
  bool colors;  // each fragment tinted its own colour: a pattern reads at a glance
  bk_mesh_tree tree;
  app_render_tree render_tree;
  bk_vec3* leaf_offsets; // leaf centroid - source centroid
  double yaw, pitch, distance;
  bk_vec3 target;
  double mouse_x, mouse_y;
  char status[600];
} editor;

// The view the editor opens with (radians); the radial pattern's impact faces it.
#define START_YAW 0.6
#define START_PITCH 0.35

static const char* const mesh_names[] = {"bunny", "cube",   "torus", "eggshell", "wall",
                                         "slab",  "pillar", "tower", "bridge",   "balcony"};

// The mesh to fracture, when it can be read here (a tree file cannot: it
// is not fractured anyway, and the patterns' aims fall back to defaults).
static bool load_source(const char* spec, bk_mesh* out) {
  bk_error err = {{0}};
  size_t length = strlen(spec);
  return !(length > 6 && strcmp(spec + length - 6, ".mtree") == 0) && app_load_mesh(spec, out, &err);
}

// The radial pattern's impact: the point of the mesh's surface that faces
// the editor's first view most (a fixed direction, so turning the view does
// not make a new tree), where a shot from there would land.
static bk_vec3 facing_point(const bk_mesh* mesh) {
  bk_vec3 towards =
      bk_v3(cos(START_PITCH) * sin(START_YAW), sin(START_PITCH), cos(START_PITCH) * cos(START_YAW));
  bk_vec3 best = bk_v3(0, 0, 0);
  double most = -INFINITY;
  for (uint32_t i = 0; i < mesh->position_count; ++i) {
    double along = bk_v3_dot(mesh->positions[i], towards);
    if (along > most) most = along, best = mesh->positions[i];
  }
  return best;
}

static bool rebuild(editor* e, bk_error* err) {
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = (uint32_t)e->pieces;
  desc.seed = (uint64_t)e->seed;
  desc.texture_scale = e->texture_scale;
  desc.pattern = (bk_fracture_pattern)e->pattern;
  bool noisy = e->noise > 0.0 && desc.pattern != BK_PATTERN_BRICK;
  bk_mesh source = {0};
  if ((desc.pattern == BK_PATTERN_RADIAL || noisy) && load_source(e->mesh, &source)) {
    if (desc.pattern == BK_PATTERN_RADIAL) desc.impact = facing_point(&source);
    // Noise as a fraction of the mesh's size (its bounds' diagonal), four waves across it.
    bk_aabb box = bk_mesh_bounds(&source);
    double extent = bk_v3_length(bk_v3_sub(box.max, box.min));
    if (noisy && extent > 0.0) desc.noise_amplitude = e->noise * extent, desc.noise_frequency = 4.0 / extent;
    bk_mesh_free(&source);
  }
  if (desc.pattern == BK_PATTERN_CUTOUT) {
    uint32_t size = 0;
    desc.cutout_pixels = app_cutout_map(&size);
    desc.cutout_width = desc.cutout_height = size;
  }
  bk_mesh_tree tree = {0};
  bool cached = false;
  double start = glfwGetTime();
  if (!app_load_tree(e->mesh, 0.0, &desc, &tree, &cached, err)) return false;
  if (e->tree.node_count) {
    renderer_release_tree(e->renderer, e->render_tree);
    bk_mesh_tree_free(&e->tree);
    free(e->leaf_offsets);
  }
  e->tree = tree;
  e->render_tree = renderer_upload_tree(e->renderer, &e->tree);
  bk_vec3 centre = bk_mesh_tree_mass(&e->tree, e->tree.nodes[0].moments).centroid;
  e->leaf_offsets = bk_alloc(sizeof(bk_vec3) * e->tree.leaf_count);
  for (uint32_t l = 0; l < e->tree.leaf_count; ++l)
    e->leaf_offsets[l] =
        bk_v3_sub(bk_mesh_tree_mass(&e->tree, bk_mesh_tree_leaf(&e->tree, l)->moments).centroid, centre);
  e->target = centre;
  bk_aabb box = e->tree.nodes[0].bounds;
  double diagonal = bk_v3_length(bk_v3_sub(box.max, box.min));
  e->distance = 2.2 * diagonal + fmin(0.5, diagonal); // a model of a few centimetres fills the view too
  snprintf(e->status, sizeof e->status, "%u fragments, %u bonds (%s in %.0f ms)", e->tree.leaf_count,
           e->tree.bond_count,
           cached                                                                    ? "cache"
           : strlen(e->mesh) > 6 && !strcmp(e->mesh + strlen(e->mesh) - 6, ".mtree") ? "loaded"
                                                                                     : "fractured",
           (glfwGetTime() - start) * 1e3);
  return true;
}

static void handle_mouse(editor* e) {
  double x = 0, y = 0;
  glfwGetCursorPos(e->window, &x, &y);
  double dx = x - e->mouse_x, dy = y - e->mouse_y;
  e->mouse_x = x, e->mouse_y = y;
  if (e->ui && ui_wants_mouse()) return;
  bool alt = glfwGetKey(e->window, GLFW_KEY_LEFT_ALT) == GLFW_PRESS ||
             glfwGetKey(e->window, GLFW_KEY_RIGHT_ALT) == GLFW_PRESS;
  bool shift = glfwGetKey(e->window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS;
  bool left = glfwGetMouseButton(e->window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
  bool right = glfwGetMouseButton(e->window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  if (alt && left) {
    e->yaw += dx * 0.008;
    e->pitch = fmax(-1.5, fmin(1.5, e->pitch + dy * 0.008));
  } else if (alt && right) {
    e->distance = fmax(0.2, e->distance * exp(dx * 0.006));
  } else if (shift && (left || right)) {
    e->explode = fmax(0.0, fmin(3.0, e->explode + dx * 0.004));
  }
}

static void export_files(editor* e) {
  bk_error err = {0};
  char obj[4200], mtree[4200], glb[4200];
  snprintf(obj, sizeof obj, "%s.obj", e->export_path);
  snprintf(mtree, sizeof mtree, "%s.mtree", e->export_path);
  snprintf(glb, sizeof glb, "%s.glb", e->export_path);
  // Nothing is written unless all three can be, and none is the model shown.
  const app_file input = {"--mesh", e->mesh, NULL, false};
  const app_file outputs[] = {{"the .obj export", obj, NULL, false},
                              {"the .mtree export", mtree, NULL, false},
                              {"the .glb export", glb, NULL, false}};
  if (!e->export_path[0] || !app_check_files(&input, 1, outputs, 3, &err)) {
    snprintf(e->status, sizeof e->status, "%s",
             e->export_path[0] ? err.message : "export: the path is empty");
    return;
  }
  bk_mesh* leaves = bk_alloc(sizeof(bk_mesh) * e->tree.leaf_count);
  for (uint32_t i = 0; i < e->tree.leaf_count; ++i)
    leaves[i] = bk_mesh_tree_leaf(&e->tree, i)->mesh;
  // A model file's own materials, else the material the editor shows (stone)
  // with its textures; the textures go into the .glb.
  app_export_materials materials = {0};
  bk_import_info info = {0};
  bk_mesh model = {0};
  bk_error model_err = {0};
  if (bk_model_import_supports(e->mesh) && app_load_model(e->mesh, NULL, &model, &info, &model_err))
    app_export_materials_from_import(&info, e->mesh, &materials);
  else
    app_export_materials_from_look("stone", &materials);
  bk_mesh_free(&model);
  bk_import_info_free(&info);
  bk_gltf_def gltf = bk_default_gltf_def();
  gltf.materials = materials.list;
  gltf.material_count = materials.count;
  bool ok = e->export_path[0] && bk_obj_save(obj, leaves, e->tree.leaf_count, &err) &&
            bk_mesh_tree_save(&e->tree, mtree, &err) && bk_mesh_tree_save_gltf(&e->tree, glb, &gltf, &err);
  app_export_materials_free(&materials);
  free(leaves);
  if (!e->export_path[0]) snprintf(err.message, sizeof err.message, "export: the path is empty");
  if (ok)
    snprintf(e->status, sizeof e->status, "wrote %.180s, %.180s and %.180s", obj, mtree, glb);
  else
    snprintf(e->status, sizeof e->status, "%s", err.message);
}

// The selector lists the built-in meshes, then the file last opened (by name).
static void set_file_label(editor* e) {
  const char* slash = strrchr(e->mesh, '/');
  snprintf(e->file_label, sizeof e->file_label, "%.120s", slash ? slash + 1 : e->mesh); // long names cut
}

static void panel(editor* e) {
  if (!ui_begin_window("Fragment editor", 10.0f, 10.0f, 340.0f, 0.0f, &e->show_panel)) {
    ui_end_window();
    return;
  }
  bool rebuild_now = false;
  enum { BUILT_IN = sizeof mesh_names / sizeof *mesh_names };
  const char* choices[BUILT_IN + 1];
  for (int i = 0; i < BUILT_IN; ++i)
    choices[i] = mesh_names[i];
  choices[BUILT_IN] = e->file_label;
  int count = e->file_label[0] ? BUILT_IN + 1 : BUILT_IN;
  if (ui_combo("mesh", &e->mesh_choice, choices, count)) {
    if (e->mesh_choice < BUILT_IN) snprintf(e->mesh, sizeof e->mesh, "%s", mesh_names[e->mesh_choice]);
    rebuild_now = true;
  }
  bool open_now = ui_input_text("##open", e->open_path, sizeof e->open_path);
  ui_same_line();
  if ((ui_button("open") || open_now) && e->open_path[0]) {
    snprintf(e->mesh, sizeof e->mesh, "%s", e->open_path);
    set_file_label(e);
    e->mesh_choice = BUILT_IN;
    rebuild_now = true;
  }
  ui_tooltip("a model file (obj, glb, gltf, fbx, ply, stl, ...) or an .mtree");
  const char* patterns[BK_PATTERN_COUNT];
  for (int p = 0; p < BK_PATTERN_COUNT; ++p)
    patterns[p] = bk_fracture_pattern_name((bk_fracture_pattern)p);
  // A new pattern is what the preview is for: it fractures at once, as a new mesh does.
  if (ui_combo("pattern", &e->pattern, patterns, BK_PATTERN_COUNT)) rebuild_now = true;
  ui_tooltip("planes: random cuts; voronoi: even cells; clustered: chunks with broken borders; radial: "
             "fine round the side facing the first view; brick: along the wall texture's mortar; cutout: "
             "the game's cobweb map, seen along z");
  ui_slider_int_log("pieces", &e->pieces, 1, 65536);
  ui_slider_int("seed", &e->seed, 0, 100000);
  ui_slider_double("texture scale", &e->texture_scale, 0.01, 2.0, "%.2f", true);
  ui_slider_double("noise", &e->noise, 0.0, 0.1, "%.3f", false);
  ui_tooltip("rough cut faces: how far they bend, a fraction of the mesh's size (0 = flat; brick stays "
             "flat)");
  if (ui_button("fracture")) rebuild_now = true;
  ui_slider_double("explode", &e->explode, 0.0, 3.0, "%.2f", false);
  ui_tooltip("or Shift + drag");
  ui_checkbox("colors", &e->colors);
  ui_tooltip("tint each fragment its own colour");
  ui_input_text("export to", e->export_path, sizeof e->export_path);
  ui_tooltip("writes <path>.obj (the fragments), <path>.mtree (the tree) and <path>.glb (glTF 2.0)");
  if (ui_button("export")) export_files(e);
  ui_text("%s", e->status);
  ui_end_window();
  if (rebuild_now) {
    bk_error err = {0};
    if (!rebuild(e, &err)) snprintf(e->status, sizeof e->status, "%s", err.message);
  }
}

int cmd_editor(int argc, char** argv) {
  window_options wo = {.width = 1280, .height = 720};
  editor* e = bk_calloc(1, sizeof *e);
  snprintf(e->mesh, sizeof e->mesh, "bunny");
  snprintf(e->export_path, sizeof e->export_path, "fragments");
  bool export_given = false;
  e->pieces = 64, e->seed = 3000, e->texture_scale = 0.1, e->show_panel = true;
  e->pitch = START_PITCH, e->yaw = START_YAW;
  for (int i = 1; i < argc; ++i) {
    const char* arg = argv[i];
    int parsed = parse_window_option("editor", argc, argv, &i, &wo);
    if (parsed == 0) continue;
    if (parsed == 2) return free(e), 2;
    parsed = parse_model_units_option("editor", argc, argv, &i);
    if (parsed == 0) continue;
    if (parsed == 2) return free(e), 2;
    uint64_t number = 0;
    const char* value = i + 1 < argc ? argv[i + 1] : NULL;
    if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
      fputs(editor_usage, stdout);
      return free(e), 0;
    }
    if (strcmp(arg, "--colors") == 0) {
      e->colors = true;
      continue;
    }
    bool ok = value != NULL;
    if (ok && strcmp(arg, "--mesh") == 0)
      ok = snprintf(e->mesh, sizeof e->mesh, "%s", value) < (int)sizeof e->mesh;
    else if (ok && strcmp(arg, "--pattern") == 0) {
      bk_fracture_pattern pattern = BK_PATTERN_PLANES;
      bk_error pattern_err = {0};
      if (!scene_pattern_from_name(value, &pattern, &pattern_err)) {
        fprintf(stderr, "breakables editor: %s\n", pattern_err.message);
        return free(e), 2;
      }
      e->pattern = (int)pattern;
    } else if (ok && strcmp(arg, "--pieces") == 0)
      ok = option_u64("editor", arg, value, 1, 65536, &number), e->pieces = (int)number;
    else if (ok && strcmp(arg, "--seed") == 0) // the panel's seed is an int
      ok = option_u64("editor", arg, value, 0, 2147483647, &number), e->seed = (int)number;
    else if (ok && strcmp(arg, "--texture-scale") == 0) // as in 'breakables fracture'
      ok = option_double("editor", arg, value, 1e-6, 1e6, &e->texture_scale);
    else if (ok && strcmp(arg, "--max-memory") == 0)
      ok = app_parse_max_memory("editor", value);
    else if (ok && strcmp(arg, "--export") == 0)
      ok = snprintf(e->export_path, sizeof e->export_path, "%s", value) < (int)sizeof e->export_path,
      export_given = true;
    else if (ok && strcmp(arg, "--noise") == 0)
      ok = option_double("editor", arg, value, 0.0, 0.1, &e->noise);
    else if (ok && strcmp(arg, "--explode") == 0)
      ok = option_double("editor", arg, value, 0.0, 3.0, &e->explode);
    else {
      fprintf(stderr,
              "breakables editor: unknown option or missing value '%s' (see 'breakables editor --help')\n",
              arg);
      return free(e), 2;
    }
    if (!ok) return free(e), 2;
    ++i;
  }
  enum { BUILT_IN = sizeof mesh_names / sizeof *mesh_names };
  e->mesh_choice = -1;
  for (int i = 0; i < BUILT_IN; ++i)
    if (strcmp(e->mesh, mesh_names[i]) == 0) e->mesh_choice = i;
  if (e->mesh_choice < 0) {
    set_file_label(e);
    e->mesh_choice = BUILT_IN;
  }
  snprintf(e->open_path, sizeof e->open_path, "%s", e->mesh_choice == BUILT_IN ? e->mesh : "");

  bk_error err = {0};
  void* window = NULL;
  if (!window_open("Breakables editor", &wo, &window, &e->renderer, &err)) {
    fprintf(stderr, "breakables editor: %s\n", err.message);
    return free(e), 1;
  }
  e->window = window;
  int status = 0;
  if (!rebuild(e, &err)) {
    fprintf(stderr, "breakables editor: %s: %s\n", e->mesh, err.message);
    window_close(window, e->renderer);
    return free(e), 1;
  }
  e->ui = ui_create(e->window);
  uint32_t frame = 0;
  unsigned gl_error = 0;
  double frame_ms_sum = 0.0;
  int look = app_renderer_material(e->renderer, "stone");
  while (!glfwWindowShouldClose(e->window) && (wo.frames == 0 || frame < wo.frames)) {
    double start = glfwGetTime();
    glfwPollEvents();
    if (glfwGetKey(e->window, GLFW_KEY_ESCAPE) == GLFW_PRESS) break;
    if (glfwGetKey(e->window, GLFW_KEY_F1) == GLFW_PRESS) e->show_panel = true;
    handle_mouse(e);
    int width = 0, height = 0;
    glfwGetFramebufferSize(e->window, &width, &height);
    bk_vec3 offset = bk_v3(cos(e->pitch) * sin(e->yaw), sin(e->pitch), cos(e->pitch) * cos(e->yaw));
    // The preview stands on the ground: lift the mesh so its lowest point is at y = 0.
    bk_vec3 lift = bk_v3(0, -e->tree.nodes[0].bounds.min.y + 0.02, 0);
    // Aim a little left of the object so it sits clear of the panel.
    bk_vec3 right = bk_v3_normalize(bk_v3_cross(bk_v3_scale(offset, -1.0), bk_v3(0, 1, 0)));
    bk_vec3 focus =
        bk_v3_sub(bk_v3_add(e->target, lift), bk_v3_scale(right, e->show_panel ? 0.22 * e->distance : 0.0));
    app_camera camera = {.eye = bk_v3_add(focus, bk_v3_scale(offset, e->distance)), .target = focus};
    camera_fit_planes(&camera, e->distance);
    renderer_begin_frame(e->renderer, &camera, width, height);
    for (uint32_t l = 0; l < e->tree.leaf_count; ++l) {
      uint32_t node = e->tree.leaf_nodes[l];
      bk_transform model = {bk_v3_add(lift, bk_v3_scale(e->leaf_offsets[l], e->explode)), bk_quat_identity()};
      // Hues a golden angle apart: neighbours never look alike, however many there are.
      double hue = fmod(l * 0.618033988749895, 1.0);
      float tint[4] = {(float)(0.5 + 0.5 * cos(6.283185307 * hue)),
                       (float)(0.5 + 0.5 * cos(6.283185307 * (hue + 0.33))),
                       (float)(0.5 + 0.5 * cos(6.283185307 * (hue + 0.67))), 0.6f};
      node_draw draw = {.tree = e->render_tree,
                        .nodes = &node,
                        .node_count = 1,
                        .model = model,
                        .material = look,
                        .node_colors = e->colors ? tint : NULL};
      renderer_draw_nodes(e->renderer, &draw);
    }
    unsigned error = renderer_end_frame(e->renderer);
    if (error && !gl_error) gl_error = error;
    if (e->ui) {
      ui_begin_frame();
      if (e->show_panel) panel(e);
      ui_end_frame();
    }
    if (wo.frames && frame + 1 == wo.frames && wo.screenshot &&
        !renderer_screenshot(e->renderer, width, height, wo.screenshot, &err)) {
      fprintf(stderr, "breakables editor: %s\n", err.message);
      status = 1;
    }
    glfwSwapBuffers(e->window);
    frame_ms_sum += (glfwGetTime() - start) * 1e3;
    frame++;
  }
  if (wo.frames)
    printf("frames %u, fragments %u, mean frame ms %.2f, gl errors %s\n", frame, e->tree.leaf_count,
           frame ? frame_ms_sum / frame : 0.0, gl_error ? "yes" : "none");
  // A scripted run given --export ends with the export the panel's button makes.
  if (wo.frames && export_given) {
    export_files(e);
    printf("%s\n", e->status);
    if (strncmp(e->status, "wrote ", 6) != 0) status = 1;
  }
  if (gl_error) status = 1;
  if (e->ui) ui_destroy();
  renderer_release_tree(e->renderer, e->render_tree);
  bk_mesh_tree_free(&e->tree);
  free(e->leaf_offsets);
  window_close(window, e->renderer);
  free(e);
  return status;
}
