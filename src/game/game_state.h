// The game's state: what the loop, the panel and the overlays share.
#pragma once

#include <GLFW/glfw3.h>

#include "game_replay.h"
#include "game_stream.h"
#include "grown_trees.h"
#include "particles.h"
#include "recorder.h"
#include "retired_pieces.h"
#include "scene_run.h"

enum { BK_HISTORY = 180 };

typedef struct app_game {
  GLFWwindow* window;
  app_renderer* renderer;
  bool ui;
  loaded_scene scene;
  scene_options options;
  app_render_tree render_trees[8];
  /// Their new nodes as refinement grows the trees: made ready on the
  /// worker after its steps, uploaded before the next frame is drawn.
  app_grown_trees grown;
  int looks[8];
  uint32_t scene_index;
  int next_scene; ///< -1: reload the same one
  bool reload;
  bool reload_keeps_camera; ///< the reload keeps where the camera is (the panel's re-fracture)
  /// Pieces a refinement of the loaded scene's objects makes (fixed when they
  /// were added: the panel's slider applies on reload)
  uint32_t refine_pieces_made;
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
  game_replay replay;   ///< the run recorded (--record-input) or played back (--replay)
  game_stream stream;   ///< serve: the steps sent to watchers; watch: the server's steps followed
  app_particles particles;
  double physics_ms, break_ms;
  float frame_history[BK_HISTORY], physics_history[BK_HISTORY], break_history[BK_HISTORY];
  int history_at;
} app_game;
