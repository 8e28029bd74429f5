// breakables play: the demo game. Fixed 60 Hz physics with interpolated
// drawing, a free-fly camera, projectiles, dust and debris, the tuning panel,
// and scripted runs that save a screenshot.
#include <GLFW/glfw3.h>
#include <stdio.h>
#include <string.h>

#include "bond_overlay.h"
#include "commands.h"
#include "game.h"
#include "game_budget.h"
#include "game_save.h"
#include "game_stream.h"
#include "hud.h"
#include "interpolate.h"
#include "model_surface.h"
#include "panel.h"
#include "scene_args.h"
#include "ui.h"
#include "window.h"
#include "worker.h"

static const char* const play_usage =
    "usage: breakables [play] [--scene NAME | --mesh PATH] [--material NAME] [--pattern NAME] [--pieces N]\n"
    "                  [--seed S] [--frames N] [--autofire K] [--hide-hud]\n"
    "                  [--screenshot FILE.png] [--width W] [--height H] [--hide-panel] [--overlay NAME]\n"
    "                  [--volley V] [--benchmark] [--no-stress] [--stress-scale X] [--drop KG]\n"
    "                  [--drop-radius M] [--drop-at FRAME] [--max-memory MIB] [--budget-ms X]\n"
    "                  [--record DIR] [--record-every K] [--camera X,Y,Z]\n"
    "                  [--scale S] [--units mm|cm|m|in] [--refine] [--refine-pieces N]\n"
    "                  [--record-input F.bkrec | --replay F.bkrec]\n"
    "\n"
    "The demo game: shoot projectiles at breakable objects and tune them live.\n"
    "\n"
    "options:\n";

// The options only play takes (scene_args_help prints the shared ones first).
static const char* const play_options =
    "  --frames N            run N frames, 1..10000000, then exit with a one-line summary\n"
    "  --autofire K          fire K projectiles, 0..10000, at the scene's target at regular\n"
    "                        intervals\n"
    "  --screenshot FILE.png save the last frame\n"
    "  --record DIR          save frames 0, K, 2K, ... as DIR/frame_00000.png, frame_00001.png, ...\n"
    "                        (needs --frames; DIR is made if missing and may hold only an earlier\n"
    "                        recording's frame_*.png, which are removed)\n"
    "  --record-every K      the K of --record, 1..10000000 (default 1: every frame)\n"
    "  --camera X,Y,Z        stand the camera there, looking at the scene's target, each\n"
    "                        -1000..1000 m (default: the scene's own view)\n"
    "  --width W --height H  window size, each 64..8192 (default: 1280x720)\n"
    "  --hide-panel          start with the tuning panel hidden (F1 shows it)\n"
    "  --hide-hud            no crosshair and no controls hint (shown for the first 6 s)\n"
    "  --overlay NAME        start with a debug overlay on: bonds (by hit points left), stress\n"
    "                        (bonds by their stress over its limit), nodes, hulls or budget\n"
    "                        (bodies by their physics budget tier) (repeatable)\n"
    "  --benchmark           start the panel's runtime sweep (16..512 fragments, mesh tree against\n"
    "                        plain BCRB); a scripted run waits for it before its last frame\n";

bk_vec3 game_forward(const app_game* g) {
  return bk_v3(cos(g->pitch) * sin(g->yaw), sin(g->pitch), -cos(g->pitch) * cos(g->yaw));
}

static void aim_camera(app_game* g, bk_vec3 eye, bk_vec3 target) {
  g->eye = eye;
  bk_vec3 d = bk_v3_normalize(bk_v3_sub(target, eye));
  g->pitch = asin(fmax(-1.0, fmin(1.0, d.y)));
  g->yaw = atan2(d.x, -d.z);
}

bool game_load_scene(app_game* g, uint32_t index, bk_error* err) {
  const app_scene* scene = scene_at(index);
  if (!scene) return bk_error_set(err, "no scene %u", index);
  game_unload_scene(g);
  if (!loaded_scene_create(scene, &g->options, &g->scene, err)) return false;
  g->scene_index = index;
  scene = g->scene.scene; // a user's model's scene is fitted to it when loaded
  if (g->scene.tree_count)
    g->refine_pieces_made =
        scene_object_def(&scene->objects[0], &g->scene.trees[0], &g->options).breakable.refine.pieces;
  for (uint32_t i = 0; i < g->scene.tree_count; ++i) {
    g->render_trees[i] = renderer_upload_tree(g->renderer, &g->scene.trees[i]);
    const scene_object* object = &scene->objects[i];
    g->looks[i] = app_renderer_material(g->renderer, object->look ? object->look : object->material);
  }
  grown_trees_reset(&g->grown, g->scene.trees, g->scene.tree_count);
  game_replay_loaded(&g->replay, &g->scene, index, &g->options);
  // A user's model with a texture or colour of its own shows them on its
  // surface, its cut faces the chosen material's.
  app_model_surface surface = {0};
  if (scene->fit_to_mesh && g->scene.tree_count && app_read_model_surface(scene->objects[0].mesh, &surface)) {
    g->looks[0] =
        renderer_model_look(g->renderer, g->looks[0], surface.image, surface.image_size, surface.color);
    app_model_surface_free(&surface);
  }
  bk_vec3 eye = bk_v3_length(scene->camera) > 0.0 ? scene->camera : scene->eye;
  aim_camera(g, g->record.camera_given ? g->record.camera : eye, scene->target);
  g->view_distance = bk_v3_length(bk_v3_sub(eye, scene->target));
  g->projectile_speed = scene->projectile_speed;
  g->projectile_radius = scene->projectile_radius;
  g->projectile_mass = scene->projectile_mass;
  g->accumulator = 0.0;
  g->shots = 0;
  game_retired_reset(g);
  // serve: the watchers are sent its start; watch: the server is connected.
  return game_stream_loaded(&g->stream, g->scene.world, err);
}

void game_unload_scene(app_game* g) {
  grown_trees_reset(&g->grown, NULL, 0);
  for (uint32_t i = 0; i < g->scene.tree_count; ++i)
    renderer_release_tree(g->renderer, g->render_trees[i]);
  if (g->scene.world) loaded_scene_destroy(&g->scene);
  memset(&g->scene, 0, sizeof g->scene);
}

void game_fire(app_game* g, bk_vec3 from, bk_vec3 direction) {
  // A replay's shots are the recording's, a watcher's the server's.
  if (game_replay_playing(&g->replay) || game_stream_watching(&g->stream)) return;
  bk_projectile_def shot = {.position = from,
                            .velocity = bk_v3_scale(bk_v3_normalize(direction), g->projectile_speed),
                            .radius = g->projectile_radius,
                            .mass = g->projectile_mass};
  bk_world_fire(g->scene.world, &shot, NULL);
  game_replay_fired(&g->replay, &shot);
  g->shots++;
}

bool game_drop_weight(app_game* g, bk_vec3 from, bk_vec3 direction) {
  bk_world* world = g->scene.world;
  if (game_replay_playing(&g->replay) || game_stream_watching(&g->stream)) return false;
  bk_vec3 forward = bk_v3_normalize(direction);
  bk_ray_hit hit = {0};
  if (!bk_physics_ray_cast(bk_world_physics(world), from, bk_v3_add(from, bk_v3_scale(forward, 1000.0)),
                           &hit))
    return false;
  // A little behind the face that was hit, so that a wall seen head on
  // still has its top over the point; the weight goes where one let go from
  // high above would land, whatever stands over the point.
  bk_vec3 across = {hit.normal.x, 0.0, hit.normal.z}, surface = {0.0, 0.0, 0.0};
  bk_vec3 under = bk_v3_sub(hit.point, bk_v3_scale(across, 0.02));
  if (!app_top_surface(world, under, 100.0, false, &surface)) return false;
  if (!app_drop_weight(world, surface, g->weight_kg, g->weight_radius, NULL)) return false;
  game_replay_weight(&g->replay, surface, g->weight_kg, g->weight_radius);
  g->weights++;
  return true;
}

static app_debris_look debris_look(void* game, bk_breakable_id id) {
  const app_game* g = game;
  const scene_object* object = &g->scene.scene->objects[id.index < g->scene.tree_count ? id.index : 0];
  return debris_look_of(object->look ? object->look : object->material); // as it is drawn
}

static void step_world(app_game* g) {
  game_stream_world_step(&g->stream, g->scene.world); // sent to watchers; a watcher applies the server's
  game_replay_step(&g->replay, &g->scene);
  game_collect_retired(g);
  // A big hit breaks hundreds of bonds at once, and so does a structure
  // giving way: the pool spreads its capped dust and chips evenly over them.
  bk_break_event events[1024];
  uint32_t total = bk_world_break_events(g->scene.world, events, 1024);
  particles_emit_step(&g->particles, events, total < 1024 ? total : 1024, debris_look, g);
  bk_world_stats s = bk_world_get_stats(g->scene.world);
  g->physics_ms = s.physics_ms;
  g->break_ms = s.break_ms;
}

// The worker's job: the steps the last frame's time asked for.
static void run_steps(void* game) {
  app_game* g = game;
  double start = glfwGetTime();
  for (int i = 0; i < g->pending_steps; ++i)
    step_world(g);
  // Fragments the steps refined: their pieces' meshes made ready for the GPU here.
  grown_trees_build(&g->grown, g->scene.world, g->scene.ids, g->scene.tree_count);
  g->steps_ms = (glfwGetTime() - start) * 1e3;
}

static void handle_input(app_game* g, double dt) {
  GLFWwindow* w = g->window;
  bool ui_keys = g->ui && ui_wants_keyboard(), ui_mouse = g->ui && ui_wants_mouse();
  double mx = 0, my = 0;
  glfwGetCursorPos(w, &mx, &my);
  if (!ui_mouse && glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS) {
    g->yaw += (mx - g->mouse_x) * 0.004;
    g->pitch = fmax(-1.5, fmin(1.5, g->pitch - (my - g->mouse_y) * 0.004));
  }
  g->mouse_x = mx, g->mouse_y = my;
  if (ui_keys) return;
  bk_vec3 f = game_forward(g), right = bk_v3_normalize(bk_v3_cross(f, bk_v3(0, 1, 0)));
  double speed = (glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ? 12.0 : 3.5) * dt;
  if (glfwGetKey(w, GLFW_KEY_W) == GLFW_PRESS) g->eye = bk_v3_add(g->eye, bk_v3_scale(f, speed));
  if (glfwGetKey(w, GLFW_KEY_S) == GLFW_PRESS) g->eye = bk_v3_sub(g->eye, bk_v3_scale(f, speed));
  if (glfwGetKey(w, GLFW_KEY_D) == GLFW_PRESS) g->eye = bk_v3_add(g->eye, bk_v3_scale(right, speed));
  if (glfwGetKey(w, GLFW_KEY_A) == GLFW_PRESS) g->eye = bk_v3_sub(g->eye, bk_v3_scale(right, speed));
  if (glfwGetKey(w, GLFW_KEY_E) == GLFW_PRESS) g->eye.y += speed;
  if (glfwGetKey(w, GLFW_KEY_Q) == GLFW_PRESS) g->eye.y = fmax(0.1, g->eye.y - speed);
}

static void key_callback(GLFWwindow* window, int key, int scancode, int action, int mods) {
  (void)scancode;
  (void)mods;
  app_game* g = glfwGetWindowUserPointer(window);
  if (action != GLFW_PRESS || (g->ui && ui_wants_keyboard())) return;
  if (key == GLFW_KEY_ESCAPE) glfwSetWindowShouldClose(window, GLFW_TRUE);
  if (key == GLFW_KEY_SPACE) game_fire(g, g->eye, game_forward(g));
  if (key == GLFW_KEY_X) game_drop_weight(g, g->eye, game_forward(g));
  if (key == GLFW_KEY_R) g->reload = true;
  if (key == GLFW_KEY_P) g->paused = !g->paused;
  if (key == GLFW_KEY_N) g->step_once = true;
  if (key == GLFW_KEY_T) g->time_scale = g->time_scale < 1.0 ? 1.0 : 0.2;
  if (key == GLFW_KEY_B) g->show_bonds = !g->show_bonds;
  if (key == GLFW_KEY_V) g->show_stress = !g->show_stress;
  if (key == GLFW_KEY_G) g->show_nodes = !g->show_nodes;
  if (key == GLFW_KEY_H) g->show_hulls = !g->show_hulls;
  if (key == GLFW_KEY_L) g->show_budget = !g->show_budget;
  if (key == GLFW_KEY_F1) g->show_panel = !g->show_panel;
  // Between steps (the worker waited before the events were polled).
  if (key == GLFW_KEY_F5) game_save_state(g, game_panel_busy());
  if (key == GLFW_KEY_F9) game_load_state(g, game_panel_busy(), game_load_scene);
  // 1-9 are the first nine scenes and 0 the tenth, in the keyboard's order.
  int scene_key = key == GLFW_KEY_0 ? 9 : key >= GLFW_KEY_1 && key <= GLFW_KEY_9 ? key - GLFW_KEY_1 : -1;
  if (scene_key >= 0 && (uint32_t)scene_key < scene_count()) {
    g->next_scene = scene_key;
    g->reload = true;
  }
}

static void mouse_callback(GLFWwindow* window, int button, int action, int mods) {
  (void)mods;
  app_game* g = glfwGetWindowUserPointer(window);
  if (button == GLFW_MOUSE_BUTTON_LEFT && action == GLFW_PRESS && !(g->ui && ui_wants_mouse()))
    game_fire(g, g->eye, game_forward(g));
}

// Distinct colours for a body's chosen nodes.
static void node_color(uint32_t i, float out[4]) {
  float h = (float)((i * 0.618033988749895) - floor(i * 0.618033988749895));
  out[0] = 0.5f + 0.5f * cosf(6.2831853f * h), out[1] = 0.5f + 0.5f * cosf(6.2831853f * (h + 0.33f));
  out[2] = 0.5f + 0.5f * cosf(6.2831853f * (h + 0.67f)), out[3] = 0.55f;
}

static void draw_world(app_game* g, double alpha) {
  bk_world* w = g->scene.world;
  // Fragments refined in the last steps are new nodes of their trees: the
  // renderer gets them before a body names them.
  grown_trees_upload(&g->grown, g->renderer, w, g->scene.ids, g->render_trees, g->scene.tree_count);
  uint32_t bodies = bk_world_body_count(w);
  for (uint32_t i = 0; i < bodies; ++i) {
    bk_body_view v = {0};
    if (!bk_world_body_view(w, i, &v)) continue;
    bk_transform model = lerp_transform(v.tree_to_world_previous, v.tree_to_world, alpha);
    float colors[4 * 256];
    bool colored = (g->show_nodes || g->show_budget) && v.node_count <= 256;
    for (uint32_t k = 0; colored && k < v.node_count; ++k)
      g->show_budget ? game_tier_color(v.tier, &colors[4 * k]) : node_color(v.nodes[k], &colors[4 * k]);
    node_draw draw = {.tree = g->render_trees[v.breakable.index],
                      .nodes = v.nodes,
                      .node_count = v.node_count,
                      .model = model,
                      .material = g->looks[v.breakable.index],
                      .node_colors = colored ? colors : NULL};
    renderer_draw_nodes(g->renderer, &draw);
    if (g->show_hulls) {
      // Collider hulls as wireframe: the edges of each collider node's mesh.
      uint32_t colliders[512];
      uint32_t n = bk_world_body_colliders(w, i, colliders, 512);
      const float wire[4] = {0.1f, 1.0f, 0.3f, 0.8f};
      for (uint32_t k = 0; k < n && k < 512; ++k) {
        const bk_mesh* m = &v.tree->nodes[colliders[k]].mesh;
        for (uint32_t t = 0; t < m->triangle_count && t < 4096; ++t)
          for (int e = 0; e < 3; ++e) {
            uint32_t a = bk_mesh_tri_position(m, t, e), b = bk_mesh_tri_position(m, t, (e + 1) % 3);
            if (a < b)
              renderer_draw_line(g->renderer, bk_transform_point(model, m->positions[a]),
                                 bk_transform_point(model, m->positions[b]), wire);
          }
      }
    }
  }
  game_draw_retired(g, alpha);
  if (g->show_bonds) game_draw_bonds(g, alpha, false);
  if (g->show_stress) game_draw_bonds(g, alpha, true);
  const float steel[3] = {0.25f, 0.25f, 0.28f};
  for (uint32_t i = 0; i < bk_world_projectile_count(w); ++i) {
    bk_vec3 p = {0};
    double radius = 0.0;
    if (bk_world_projectile(w, i, &p, &radius)) renderer_draw_sphere(g->renderer, p, radius, steel);
  }
}

static void record_history(app_game* g, double frame_ms) {
  int i = g->history_at % BK_HISTORY;
  g->frame_history[i] = (float)frame_ms;
  g->physics_history[i] = (float)g->physics_ms;
  g->break_history[i] = (float)g->break_ms;
  g->history_at++;
}

// The frame's recorded changes, or a replay's events due and the scenes it
// loads; false (err set) when one of those fails to load.
static bool replay_frame(app_game* g, bk_error* err) {
  game_replay_frame_io io = {.pending_steps = g->pending_steps};
  for (game_replay_frame(&g->replay, &g->scene, g->eye, &io); io.load;
       game_replay_frame(&g->replay, &g->scene, g->eye, &io)) {
    g->options = io.options;
    if (!game_load_scene(g, io.index, err)) return false;
  }
  g->pending_steps = io.pending_steps;
  g->shots += io.shots, g->weights += io.weights;
  if (io.ended) glfwSetWindowShouldClose(g->window, GLFW_TRUE); // the recording is over
  return true;
}

// Before the frame's steps: serve welcomes watchers; watch takes the frames
// that arrived, its steps the server's (a new start: the scene built anew).
static bool stream_frame(app_game* g, bk_error* err) {
  while (game_stream_frame(&g->stream, g->scene.world, g->paused, &g->pending_steps))
    if (!game_load_scene(g, g->scene_index, err)) return false;
  if (game_stream_watching(&g->stream)) g->alpha = 1.0; // the server's last place, not between steps
  return true;
}

// play, serve and watch: the same game, the last two with the stream.
static int run_game(int argc, char** argv, game_stream_mode mode) {
  window_options wo = {.width = 1280, .height = 720};
  app_game* g = bk_calloc(1, sizeof *g);
  g->stream = default_game_stream(mode);
  const char* command = game_stream_command(&g->stream);
  scene_args args = default_scene_args("showcase");
  // Chips under 20 cm^3 leave after 10 s: a long session stays bounded.
  args.options.retire_volume = 2e-5;
  g->record = default_recorder();
  bool hide_panel = false;
  for (int i = 1; i < argc; ++i) {
    const char* arg = argv[i];
    int parsed = scene_args_parse("play", argc, argv, &i, &args);
    if (parsed == 0) continue;
    if (parsed == 2) return bk_free(g), 2;
    parsed = parse_window_option("play", argc, argv, &i, &wo);
    if (parsed == 0) continue;
    if (parsed == 2) return bk_free(g), 2;
    parsed = game_replay_parse(argc, argv, &i, &g->replay);
    if (parsed == 0) continue;
    if (parsed == 2) return bk_free(g), 2;
    parsed = game_stream_parse(argc, argv, &i, &g->stream);
    if (parsed == 0) continue;
    if (parsed == 2) return bk_free(g), 2;
    parsed = parse_record_option("play", argc, argv, &i, &g->record);
    if (parsed == 0) continue;
    if (parsed == 2) return bk_free(g), 2;
    if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
      const char* usage = game_stream_usage(&g->stream);
      fputs(usage ? usage : play_usage, stdout);
      scene_args_help(command, 24, 96, stdout);
      fputs(play_options, stdout);
      if (!game_stream_watching(&g->stream)) fputs(game_replay_help, stdout);
      game_stream_help(&g->stream, stdout);
      return bk_free(g), 0;
    } else if (strcmp(arg, "--hide-panel") == 0) {
      hide_panel = true;
    } else if (strcmp(arg, "--hide-hud") == 0) {
      g->hide_hud = true;
    } else if (strcmp(arg, "--benchmark") == 0) {
      g->start_benchmark = true;
    } else if (strcmp(arg, "--overlay") == 0 && i + 1 < argc) {
      if (!game_set_overlay(g, argv[++i])) return bk_free(g), 2;
    } else {
      fprintf(stderr, "breakables %s: unknown option or missing value '%s' (see 'breakables %s --help')\n",
              command, arg, command);
      return bk_free(g), 2;
    }
  }
  g->options = args.options;
  g->drop = args.drop;
  const char* scene_name = args.scene_name;
  const char* mesh = args.mesh;
  const char* material = args.material;
  bool scene_given = args.scene_given;
  uint64_t volley = args.volley;
  if (!check_drop("play", &g->drop, wo.frames, "--frames")) return bk_free(g), 2;
  if (!recorder_prepare("play", &g->record, wo.frames)) return bk_free(g), 2;
  // X sets down the scripted weight's mass, else one the bridge cannot carry.
  g->weight_kg = g->drop.kg > 0.0 ? g->drop.kg : 20000.0;
  g->weight_radius = g->drop.radius;
  bk_error err = {0};
  uint32_t scene_index = scene_resolve(scene_name, scene_given, mesh, material, &err);
  if (scene_index == UINT32_MAX) {
    fprintf(stderr, "breakables play: %s\n", err.message);
    return bk_free(g), 2;
  }
  g->options.material = material;
  int stream_setup = game_stream_setup(&g->stream, argc, argv, wo.frames); // watch: its address, no changes
  if (stream_setup) return bk_free(g), stream_setup;
  // A replay's scene and options.
  int replay_setup = game_replay_setup(&g->replay, argc, argv, mesh, &scene_index, &g->options);
  if (replay_setup) return bk_free(g), replay_setup;

  void* window = NULL;
  if (!window_open("Breakables", &wo, &window, &g->renderer, &err)) {
    fprintf(stderr, "breakables play: %s\n", err.message);
    recording_free(&g->replay.rec); // a replay's, read
    return bk_free(g), 1;
  }
  g->window = window;
  g->time_scale = 1.0;
  g->show_panel = !hide_panel;
  particles_init(&g->particles, 1024, 1);
  for (int i = 0; i < BK_DEBRIS_MATERIALS; ++i)
    g->particles.renderer_material[i] = app_renderer_material(g->renderer, debris_materials[i]);
  glfwSetWindowUserPointer(g->window, g);
  glfwSetKeyCallback(g->window, key_callback);
  glfwSetMouseButtonCallback(g->window, mouse_callback);
  g->ui = ui_create(g->window);
  if (!game_load_scene(g, scene_index, &err)) {
    fprintf(stderr, "breakables %s: %s\n", command, err.message);
    game_unload_scene(g);
    particles_free(&g->particles);
    if (g->ui) ui_destroy();
    window_close(window, g->renderer);
    recording_free(&g->replay.rec);
    return bk_free(g), 1;
  }
  uint32_t bodies_start = bk_world_body_count(g->scene.world);
  // The world steps on a worker while the driver draws the frame just
  // submitted: a software renderer's threads sit idle while physics runs on
  // the main thread, and vice versa. Between worker_wait and the next
  // start the world is the main thread's: input, the panel and drawing.
  app_worker* worker = worker_create();
  const double fixed = 1.0 / 60.0;
  double last = glfwGetTime(), frame_ms_sum = 0.0, physics_ms_sum = 0.0, last_ms_sum = 0.0, frame_ms = 0.0;
  double last_physics_sum = 0.0;
  unsigned gl_error = 0;
  uint32_t frame = 0, fired = 0, jobs = 0;
  int status = 0;
  while (!glfwWindowShouldClose(g->window) && (wo.frames == 0 || frame < wo.frames) &&
         !game_stream_ended(&g->stream)) {
    double now = glfwGetTime();
    // Scripted runs advance exactly one physics step per frame, so they are
    // reproducible whatever the machine's speed.
    double dt = wo.frames ? fixed : fmin(now - last, 0.1);
    last = now;
    g->hud_seconds += dt; // the hint's clock: frames in a scripted run, so its pictures repeat
    if (worker) worker_wait(worker);
    if (jobs > 0) {
      physics_ms_sum += g->steps_ms;
      if (wo.frames && frame + 59 >= wo.frames) last_physics_sum += g->steps_ms; // jobs of the last 60 frames
      record_history(g, frame_ms);
    }
    glfwPollEvents();
    handle_input(g, dt);
    // A reload creates a Bullet world: not while the panel's sweep steps
    // worlds on its thread (bullet.h: one thread at a time), so it waits.
    // Scene switches: the recording's (the server's) only.
    if (game_replay_playing(&g->replay) || game_stream_watching(&g->stream)) g->reload = false;
    if (g->reload && !game_panel_busy()) {
      g->reload = false;
      uint32_t next = g->next_scene >= 0 ? (uint32_t)g->next_scene : g->scene_index;
      g->next_scene = -1;
      bk_vec3 eye = g->eye;
      double yaw = g->yaw, pitch = g->pitch;
      if (!game_load_scene(g, next, &err)) {
        fprintf(stderr, "breakables play: %s\n", err.message);
        status = 1;
        break;
      }
      if (g->reload_keeps_camera) g->eye = eye, g->yaw = yaw, g->pitch = pitch;
      g->reload_keeps_camera = false;
    }
    uint64_t span = volley && volley < wo.frames ? volley : wo.frames;
    while (wo.autofire && fired < wo.autofire && wo.frames &&
           frame >= (fired + 1) * span / (wo.autofire + 1)) {
      bk_projectile_def shot = scene_shot(g->scene.scene, fired++, g->projectile_speed);
      bk_world_fire(g->scene.world, &shot, NULL);
      game_replay_fired(&g->replay, &shot);
    }
    if (g->drop.kg > 0.0 && frame == g->drop.at) {
      bk_vec3 surface = {0.0, 0.0, 0.0};
      if (scene_drop_point(&g->scene, &surface) &&
          app_drop_weight(g->scene.world, surface, g->drop.kg, g->drop.radius, NULL))
        g->weights++, game_replay_weight(&g->replay, surface, g->drop.kg, g->drop.radius);
      else
        fprintf(stderr, "breakables play: --drop: no surface of the first object to set the weight on\n");
    }
    uint32_t particles = particles_update(&g->particles, g->paused ? 0.0 : dt * g->time_scale);

    // The world as the last steps left it, between their two states.
    int width = 0, height = 0;
    glfwGetFramebufferSize(g->window, &width, &height);
    app_camera camera = {.eye = g->eye, .target = bk_v3_add(g->eye, game_forward(g))};
    camera_fit_planes(&camera, g->view_distance);
    renderer_begin_frame(g->renderer, &camera, width, height);
    draw_world(g, g->alpha);
    renderer_draw_particles(g->renderer, g->particles.instances, particles);
    renderer_draw_chips(g->renderer, g->particles.chips, g->particles.chip_count);
    unsigned error = renderer_end_frame(g->renderer);
    if (error && !gl_error) gl_error = error;
    if (g->ui) {
      ui_begin_frame();
      // A replay's changes are recorded ones (a watcher's, the server's).
      if (g->show_panel && !game_replay_playing(&g->replay) && !game_stream_watching(&g->stream))
        game_panel(g);
      if (!g->hide_hud) hud_draw(g->hud_seconds);
      if (!g->hide_hud) game_stream_hud(&g->stream);
      if (!g->hide_hud) game_save_hud(g);
      ui_end_frame();
    }

    // This frame's time in fixed steps, run while the driver draws.
    if (!g->paused) g->accumulator += dt * g->time_scale;
    if (g->step_once) {
      g->accumulator += fixed;
      g->step_once = false;
    }
    g->pending_steps = 0;
    // The panel's sweep steps worlds of its own: the game's waits meanwhile.
    if (game_panel_busy()) g->accumulator = 0.0;
    while (g->accumulator >= fixed && g->pending_steps < 4) {
      g->accumulator -= fixed;
      g->pending_steps++;
    }
    if (g->pending_steps == 4) g->accumulator = 0.0; // far behind: drop time rather than spiral
    g->alpha = g->accumulator / fixed;
    if (!replay_frame(g, &err)) { // the camera as the budget's focus; a recording's changes, or a replay's
      fprintf(stderr, "breakables play: replay: %s\n", err.message);
      status = 1;
      break;
    }
    if (!stream_frame(g, &err)) {
      fprintf(stderr, "breakables %s: %s\n", command, err.message);
      status = 1;
      break;
    }
    if (worker)
      worker_start(worker, run_steps, g);
    else
      run_steps(g);
    jobs++;

    bool last_frame = (wo.frames && frame + 1 == wo.frames) || game_stream_ended(&g->stream);
    if (last_frame && game_panel_busy()) { // a scripted benchmark run shows the sweep's result
      glfwSwapBuffers(g->window);
      continue;
    }
    if (last_frame && wo.screenshot &&
        !renderer_screenshot(g->renderer, width, height, wo.screenshot, &err)) {
      fprintf(stderr, "breakables play: %s\n", err.message);
      status = 1;
    }
    if (!recorder_frame(&g->record, g->renderer, frame, width, height, &err)) {
      fprintf(stderr, "breakables play: %s\n", err.message);
      status = 1;
      break;
    }
    glfwSwapBuffers(g->window);
    frame_ms = (glfwGetTime() - now) * 1e3;
    frame_ms_sum += frame_ms;
    if (wo.frames && frame + 60 >= wo.frames) last_ms_sum += frame_ms; // the last second
    frame++;
  }
  if (worker) worker_destroy(worker);
  if (jobs > 0) {
    physics_ms_sum += g->steps_ms;
    last_physics_sum += g->steps_ms;
  }
  bk_world_stats s = bk_world_get_stats(g->scene.world);
  if (wo.frames && !game_stream_watching(&g->stream)) // a watcher's line is the stream's
    printf("frames %u, bodies %u (from %u), fragments free %u, mean frame ms %.2f (last second %.2f), "
           "physics ms %.2f (last second %.2f), shots %u, weights %u, gl errors %s\n",
           frame, s.bodies, bodies_start, s.fragments_free, frame ? frame_ms_sum / frame : 0.0,
           frame ? last_ms_sum / (frame < 60 ? frame : 60) : 0.0, jobs ? physics_ms_sum / jobs : 0.0,
           frame ? last_physics_sum / (frame < 60 ? frame : 60) : 0.0, fired + g->shots, g->weights,
           gl_error ? "yes" : "none");
  if (wo.frames && g->options.refine) {
    const bk_mesh_tree* tree = bk_runtime_breakable_tree(bk_world_runtime(g->scene.world), g->scene.ids[0]);
    printf("refined %u fragments: the first object's %u -> %u\n", s.refined_leaves,
           g->scene.trees[0].leaf_count, tree ? tree->leaf_count : 0);
  }
  if (!game_replay_finish(&g->replay, &g->scene)) status = 1;
  if (!game_stream_finish(&g->stream, g->scene.world)) status = 1;
  if (gl_error) {
    fprintf(stderr, "breakables play: OpenGL error 0x%x while rendering\n", gl_error);
    status = 1;
  }
  game_panel_shutdown();
  game_unload_scene(g);
  particles_free(&g->particles);
  if (g->ui) ui_destroy();
  window_close(window, g->renderer);
  bk_free(g);
  return status;
}

int cmd_play(int argc, char** argv) { return run_game(argc, argv, GAME_PLAY); }
int cmd_serve(int argc, char** argv) { return run_game(argc, argv, GAME_SERVE); }
int cmd_watch(int argc, char** argv) { return run_game(argc, argv, GAME_WATCH); }
