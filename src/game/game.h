// The game's loop (game.c): scenes loaded into it, shots and weights.
#pragma once

#include "game_state.h"

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
