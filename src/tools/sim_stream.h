// breakables sim --serve / --watch: the destruction stream (net_stream.h)
// headless. The server steps its scene and sends every step's journal and
// motion to its watchers; a watcher builds the same scene, is never
// stepped, applies what it receives and checks its runtime state hash
// against the server's after every step.
#pragma once

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "scene_run.h"

/// At most this many watchers at once.
enum { SIM_STREAM_WATCHERS_MAX = 16 };

typedef struct sim_stream {
  const char* serve;   ///< --serve ADDR:PORT, or NULL
  const char* watch;   ///< --watch ADDR:PORT, or NULL
  uint32_t watchers;   ///< --watchers N: the server's first step waits for them (default 1)
  bool realtime;       ///< --realtime: the server keeps to 60 steps a second, as a game does
  uint32_t send_every; ///< --send-every K: a frame every K steps (default 1)
  uint64_t wait_ms;    ///< --stream-wait MS: how long to wait for a watcher or a frame (default 30000)
  int listener;        ///< the server's socket, or -1
  int clients[SIM_STREAM_WATCHERS_MAX];
  uint32_t client_count, joined_late;
  uint64_t bytes, journal_bytes, motion_bytes, snapshot_bytes, frames;
  double started_ms;
} sim_stream;

/// No stream; one watcher, 30 s of waiting.
sim_stream default_sim_stream(void);
/// Parses --serve, --watch, --watchers, --realtime, --stream-wait and --send-every:
/// 0 when argv[*i] was one of them (its value consumed), 1 when not ours,
/// 2 on a bad value (one line printed).
int sim_stream_parse(int argc, char** argv, int* i, sim_stream* s);
/// Help lines of those options.
void sim_stream_help(FILE* out);
/// The server: listens, waits for its watchers and greets them; false with
/// one line printed when it cannot.
bool sim_serve_start(sim_stream* s, const loaded_scene* scene);
/// After step `step` (1 = the first), every send_every steps and at the
/// `last`: sends the steps' frame, then welcomes watchers that joined (the
/// world's state, the step they join at).
void sim_serve_step(sim_stream* s, loaded_scene* scene, uint64_t step, bool last);
/// The end: the final hashes to every watcher, and the sockets closed.
void sim_serve_finish(sim_stream* s, uint64_t steps, uint64_t state_hash, uint64_t world_hash);
/// The server's JSON members ("\"stream_frames\": ..., "), its bytes per
/// break event and per second over the steps.
void sim_serve_json(const sim_stream* s, FILE* out, uint32_t break_events, uint64_t steps);
/// The watcher's whole run over the scene it built: returns the exit code
/// (0: every step's hash agreed; 1: a difference, a lost server; one line).
int sim_watch_run(sim_stream* s, loaded_scene* scene, bool json);
