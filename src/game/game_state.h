// Internal to the executable: the game's state, shared by the loop and the panel.
#pragma once

#include <GLFW/glfw3.h>

#include "game.h"
#include "recorder.h"
#include "retired_pieces.h"

enum { BK_HISTORY = 180 };

typedef struct app_game {
  GLFWwindow* window;
  app_renderer* renderer;
  bool ui;
  loaded_scene scene;
  scene_options options;
  app_render_tree render_trees[8];
  int looks[8];
  uint32_t scene_index;
  int next_scene; ///< -1: reload the same one
  bool reload;
  // Camera.
  bk_vec3 eye;
  double view_distance; ///< from the scene's camera to its target when loaded (camera_fit_planes)
  double yaw, pitch, mouse_x, mouse_y;
  // Time.
  double accumulator, time_scale;
  bool paused, step_once;
  int pending_steps; ///< fixed steps the worker runs for this frame
  double alpha;      ///< where between the last two steps the drawn frame lies
  double steps_ms;   ///< wall time of the last frame's steps (on the worker)
  // Projectiles.
  double projectile_speed, projectile_radius, projectile_mass;
  uint32_t shots;
  // Weights: the scripted one (--drop) and the X key's, of the panel's mass and radius.
  app_drop drop;
  double weight_kg, weight_radius;
  uint32_t weights; ///< set down so far
  // Overlays and panel.
  bool show_bonds, show_stress, show_nodes, show_hulls, show_panel;
  bool show_budget; ///< bodies coloured by their physics budget tier (L)
  /// Pieces the physics budget retired, fading out (filled on the worker, after each step).
  app_retired_pieces retired;
  bool hide_hud;        ///< no crosshair or controls hint (--hide-hud)
  double hud_seconds;   ///< since the game started, for the hint's fade
  bool start_benchmark; ///< run the panel's runtime sweep at start (--benchmark)
  app_recorder record;  ///< a scripted run's frames as pictures (--record)
  app_particles particles;
  double physics_ms, break_ms;
  float frame_history[BK_HISTORY], physics_history[BK_HISTORY], break_history[BK_HISTORY];
  int history_at;
} app_game;

/// Loads scene `index` (replacing the current one) and points the camera at it.
bool game_load_scene(app_game* game, uint32_t index, bk_error* err);
void game_unload_scene(app_game* game);
/// Fires a projectile with the current projectile settings.
void game_fire(app_game* game, bk_vec3 from, bk_vec3 direction);
/// Sets a weight of the panel's mass and radius on the top surface over
/// what the ray from `from` along `direction` meets first; false (nothing
/// set) if it meets nothing.
bool game_drop_weight(app_game* game, bk_vec3 from, bk_vec3 direction);
/// The camera's view direction.
bk_vec3 game_forward(const app_game* game);
/// The pose `t` (0..1) of the way from `a` to `b`: positions lerped, rotations
/// nlerped along the shorter arc.
bk_transform game_lerp_transform(bk_transform a, bk_transform b, double t);
/// The intact bonds inside each body as lines, coloured by their hit points
/// left or, when `by_stress`, by their stress over its limit (bond_overlay.c).
void game_draw_bonds(app_game* game, double alpha, bool by_stress);
/// Empties the retired pieces (a scene is loaded: their trees are gone).
void game_retired_reset(app_game* game);
/// After a world step (on the worker): ages the retired pieces by a step and
/// adds those the step retired.
void game_collect_retired(app_game* game);
/// Draws the retired pieces fading out, `alpha` of the way through the last step as the world is.
void game_draw_retired(app_game* game, double alpha);
/// The budget overlay's colour (rgb, strength) of a body at `tier`: none for full fidelity.
void game_tier_color(bk_budget_tier tier, float out[4]);
/// Turns on the overlay --overlay names; false (and one line on stderr) for an unknown name.
bool game_set_overlay(app_game* game, const char* name);
/// The panel's Physics budget section (panel_budget.c).
void game_budget_section(app_game* game);
/// Draws the tuning panel (between ui_begin_frame and ui_end_frame).
void game_panel(app_game* game);
/// True while the panel's benchmark sweep runs.
bool game_panel_busy(void);
/// Waits for a running re-fracture and frees what it made.
void game_panel_shutdown(void);
