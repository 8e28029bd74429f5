// breakables serve and breakables watch: the game as a server of the
// destruction stream (net_stream.h, the protocol of sim --serve/--watch)
// and as a window that follows one. The server plays as `play` does and
// sends every step's journal and motion to its watchers; a watcher builds
// the same scene, never steps its world, applies what arrives and checks
// its runtime state hash against the server's after every step.
#pragma once

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include <breakables/bullet.h>

#include "game_watch.h"

typedef enum game_stream_mode {
  GAME_PLAY,  ///< no stream
  GAME_SERVE, ///< breakables serve
  GAME_WATCH, ///< breakables watch
} game_stream_mode;

enum { GAME_STREAM_WATCHERS_MAX = 16 };

typedef struct game_stream {
  game_stream_mode mode;
  const char* address; ///< serve: --listen (default 127.0.0.1:7000); watch: its ADDR:PORT
  uint32_t watchers;   ///< serve: --watchers N waited for before the first step (default 0)
  uint64_t wait_ms;    ///< --stream-wait MS: for watchers, a connection, a frame (default 30000)
  bool scripted;       ///< --frames given: a watcher whose stream fails ends at once
  uint64_t step;       ///< the server's steps since the scene was loaded: the stream's step numbers
  // The server.
  int listener;
  int clients[GAME_STREAM_WATCHERS_MAX];
  uint32_t client_count, joined_late;
  uint64_t bytes_sent;
  game_watch watch; ///< the watcher
} game_stream;

/// No stream (play), or serve's or watch's defaults.
game_stream default_game_stream(game_stream_mode mode);
/// "play", "serve" or "watch".
const char* game_stream_command(const game_stream* stream);
/// Parses serve's --listen, --watchers, --stream-wait or watch's ADDR:PORT,
/// --stream-wait: 0 when argv[*i] was one of them (its value consumed), 1
/// when not ours (always for play), 2 on a bad value (one line printed).
int game_stream_parse(int argc, char** argv, int* i, game_stream* stream);
/// The usage lines of serve or watch (NULL for play: its own).
const char* game_stream_usage(const game_stream* stream);
/// The help lines of serve's or watch's own options.
void game_stream_help(const game_stream* stream, FILE* out);
/// After the command line: a watcher needs its address and refuses what
/// would change its world (--autofire, --drop, --benchmark, --record-input,
/// --replay). Returns 0, or the exit code (one line printed).
int game_stream_setup(game_stream* stream, int argc, char** argv, uint32_t frames);
/// A scene was built (on the main thread). The server's first: listens and
/// waits for --watchers; a later one: every watcher is sent the new scene's
/// start (a watcher given other scene options then leaves). The watcher's
/// first: connects. False with err set when that fails.
bool game_stream_loaded(game_stream* stream, bk_world* world, bk_error* err);
/// Before the frame's steps (main thread): the server welcomes watchers that
/// joined (their state, the step they join at); the watcher handles the
/// frames arrived (a hello, a state, the end) and sets *steps to the step
/// frames waiting (none while paused). True when the watcher must build its
/// scene anew first (the server did), then call again.
bool game_stream_frame(game_stream* stream, bk_world* world, bool paused, int* steps);
/// One step (on the worker): the server steps its world and sends the step
/// to its watchers; the watcher applies the next step frame instead.
void game_stream_world_step(game_stream* stream, bk_world* world);
/// Whether this is a watcher (its player's shots, weights, panel and reloads ignored).
bool game_stream_watching(const game_stream* stream);
/// Whether the watched stream is over (the server's end, or a failure in a
/// scripted run): the frame drawn now is the last.
bool game_stream_ended(const game_stream* stream);
/// The stream's line at the top of the window (between ui_begin_frame and ui_end_frame).
void game_stream_hud(const game_stream* stream);
/// At exit: the server sends the end and prints its final hashes; the
/// watcher prints what it followed, or (stderr) the disagreement. False
/// when the stream failed.
bool game_stream_finish(game_stream* stream, const bk_world* world);
