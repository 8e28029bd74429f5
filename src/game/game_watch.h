// breakables watch's side of the stream (game_stream.h): the connection to
// the server, a thread reading its frames, and their application to the
// world, which is never stepped.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include <breakables/bullet.h>

/// The reading thread and the frames it has received.
typedef struct game_watch_reader game_watch_reader;

typedef struct game_watch {
  int server; ///< the socket, or -1
  game_watch_reader* reader;
  bool greeted;     ///< a hello arrived (a second one: the server loaded its scene anew)
  bool scene_fresh; ///< the scene was built and nothing applied to it since
  uint64_t joined_at, step, agreed, server_state;
  bool ended, failed;
  char error[512]; ///< the first disagreement or failure
} game_watch;

/// Not connected.
game_watch default_game_watch(void);
/// Connects to the server at `address` (waiting up to wait_ms for it) and
/// starts reading; false with err set.
bool watch_connect(game_watch* watch, const char* address, uint64_t wait_ms, bk_error* err);
/// Main thread: handles the hello, state and end frames at the head of what
/// arrived and returns how many step frames follow them, to apply on the
/// worker. *rebuild is set when a hello after the first asks for the scene
/// to be built anew first (then call again).
uint32_t watch_frames(game_watch* watch, bk_world* world, bool* rebuild);
/// Worker: applies the next step frame and checks the state hash after it.
void watch_step(game_watch* watch, bk_world* world);
/// Stops the reading thread and closes the connection.
void watch_close(game_watch* watch);
