// F5 and F9 in the game: the world's state saved (bk_world_save_state) to
// memory and to a file in the cache directory, and loaded back.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include <breakables/base.h>

typedef struct app_game app_game;

/// Loads scene `index` into the game (game_load_scene), false with err set.
typedef bool (*game_scene_loader)(app_game* game, uint32_t index, bk_error* err);

/// F5: saves the world's state; the HUD says where, or why not. Called
/// between steps (the worker is not stepping the world); `busy`: the panel's
/// sweep steps worlds on its thread, so nothing is done.
void game_save_state(app_game* game, bool busy);
/// F9: reloads the scene the state was saved in and loads the state into it
/// (from memory, else from the file of an earlier run); the HUD says
/// what happened or the one-line reason it did not. Between steps.
void game_load_state(app_game* game, bool busy, game_scene_loader load_scene);
/// The last save's or load's line, for a few seconds.
void game_save_hud(const app_game* game);
