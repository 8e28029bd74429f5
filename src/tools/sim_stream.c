// breakables sim --serve / --watch (see sim_stream.h).
#include "sim_stream.h"

#include <string.h>
#include <time.h>

#include "app.h"
#include "fracture_patterns.h"
#include "net_stream.h"

sim_stream default_sim_stream(void) {
  sim_stream s;
  memset(&s, 0, sizeof s);
  s.watchers = 1;
  s.wait_ms = 30000;
  s.send_every = 1;
  s.listener = -1;
  return s;
}

int sim_stream_parse(int argc, char** argv, int* i, sim_stream* s) {
  const char* arg = argv[*i];
  if (strcmp(arg, "--realtime") == 0) {
    s->realtime = true;
    return 0;
  }
  static const char* const names[] = {"--serve", "--watch", "--watchers", "--stream-wait", "--send-every"};
  const char* value = NULL;
  int which = take_option("sim", argc, argv, i, names, 5, &value);
  if (which == -1) return 1;
  if (which == -2) return 2;
  char host[64];
  uint16_t port = 0;
  bk_error err = {0};
  uint64_t number = 0;
  if (which <= 1 && !stream_parse_address(value, host, &port, &err)) {
    fprintf(stderr, "breakables sim: %s: %s\n", names[which], err.message);
    return 2;
  }
  if (which == 0) s->serve = value;
  if (which == 1) s->watch = value;
  if (which == 2) {
    if (!option_u64("sim", "--watchers", value, 1, SIM_STREAM_WATCHERS_MAX, &number)) return 2;
    s->watchers = (uint32_t)number;
  }
  if (which == 3) {
    if (!option_u64("sim", "--stream-wait", value, 1, 600000, &number)) return 2;
    s->wait_ms = number;
  }
  if (which == 4) {
    if (!option_u64("sim", "--send-every", value, 1, 60, &number)) return 2;
    s->send_every = (uint32_t)number;
  }
  return 0;
}

void sim_stream_help(FILE* out) {
  fputs("  --serve ADDR:PORT  send the run's destruction to watchers over TCP (127.0.0.1:7000): its\n"
        "                   first step waits for --watchers N of them (1..16, default 1), and\n"
        "                   watchers may join later (they get the world's state first)\n"
        "  --watch ADDR:PORT  build the scene given and follow a server's run instead of\n"
        "                   simulating: its state hash is checked against the server's every step\n"
        "  --realtime       the server keeps to 60 steps a second, as a game does\n"
        "  --send-every K   the server sends a frame every K steps, 1..60 (default 1): the journal of\n"
        "                   all K, and the pieces' places after the last (a watcher checks the hash then)\n"
        "  --stream-wait MS how long to wait for a watcher or a frame, 1..600000 (default 30000)\n",
        out);
}

// ---------------------------------------------------------------- server

// Sends to every watcher, packed (and compressed) once; one that has gone
// is dropped.
static void send_all_watchers(sim_stream* s, uint8_t kind, const void* a, size_t na, const void* b,
                              size_t nb) {
  size_t size = 0;
  uint8_t* frame = stream_pack(kind, a, na, b, nb, &size);
  for (uint32_t c = 0; c < s->client_count;) {
    if (stream_send_packed(s->clients[c], frame, size)) {
      s->bytes += size;
      c++;
      continue;
    }
    stream_close(s->clients[c]);
    s->clients[c] = s->clients[--s->client_count];
  }
  bk_free(frame);
}

// A new watcher: the step it joins at, the server's hash then and the
// world's state.
static void welcome(sim_stream* s, int client, const loaded_scene* scene, uint64_t step) {
  uint8_t hello[20];
  stream_put_u32(hello, STREAM_PROTOCOL);
  stream_put_u64(hello + 4, step);
  stream_put_u64(hello + 12, bk_runtime_state_hash(bk_world_runtime(scene->world)));
  bool ok = stream_send(client, STREAM_HELLO, hello, sizeof hello, NULL, 0) > 0;
  // The world's state, even before the first step: the server's world may
  // not be its scene as built (sim --load-state).
  if (ok) {
    size_t size = bk_world_state_size(scene->world);
    uint8_t* state = bk_alloc(size + 1);
    bk_error err = {0};
    size_t written = bk_world_save_state(scene->world, state, size, &err);
    size_t sent = written ? stream_send(client, STREAM_SNAPSHOT, state, written, NULL, 0) : 0;
    s->snapshot_bytes += sent;
    ok = sent > 0;
    bk_free(state);
  }
  if (!ok || s->client_count == SIM_STREAM_WATCHERS_MAX) {
    stream_close(client);
    return;
  }
  s->clients[s->client_count++] = client;
  s->joined_late += step > 0;
}

bool sim_serve_start(sim_stream* s, const loaded_scene* scene) {
  char host[64];
  uint16_t port = 0;
  bk_error err = {0};
  stream_parse_address(s->serve, host, &port, &err);
  s->listener = stream_listen(host, port, &err);
  if (s->listener < 0) {
    fprintf(stderr, "breakables sim: --serve: %s\n", err.message);
    return false;
  }
  // The journal starts with the run: the scene is set up on both sides.
  bk_world_set_journal(scene->world, true);
  bk_world_clear_journal(scene->world);
  while (s->client_count < s->watchers) {
    int client = stream_accept(s->listener, (int)s->wait_ms);
    if (client < 0) {
      fprintf(stderr, "breakables sim: --serve: %u of %u watchers connected within %llu ms\n",
              s->client_count, s->watchers, (unsigned long long)s->wait_ms);
      stream_close(s->listener);
      return false;
    }
    welcome(s, client, scene, 0);
  }
  s->started_ms = app_now_ms();
  return true;
}

void sim_serve_step(sim_stream* s, loaded_scene* scene, uint64_t step, bool last) {
  // Between frames the journal gathers; places are sent as they are at the frame.
  if (step % s->send_every != 0 && !last) return;
  size_t journal_size = 0;
  const void* journal = bk_world_journal(scene->world, &journal_size);
  size_t motion_capacity = bk_world_motion_size(scene->world);
  uint8_t* motion = bk_alloc(motion_capacity + 1);
  size_t motion_size = bk_world_motion(scene->world, motion, motion_capacity);
  uint8_t* head = bk_alloc(20 + journal_size);
  stream_put_u64(head, step);
  stream_put_u64(head + 8, bk_runtime_state_hash(bk_world_runtime(scene->world)));
  stream_put_u32(head + 16, (uint32_t)journal_size);
  if (journal_size) memcpy(head + 20, journal, journal_size);
  send_all_watchers(s, STREAM_STEP, head, 20 + journal_size, motion, motion_size);
  if (s->client_count) {
    // As one watcher sees it (each gets the same bytes).
    s->journal_bytes += journal_size;
    s->motion_bytes += motion_size;
    s->frames++;
  }
  bk_free(head);
  bk_free(motion);
  bk_world_clear_journal(scene->world);
  // Late joiners start from the state after this step.
  for (int client = stream_accept(s->listener, 0); client >= 0; client = stream_accept(s->listener, 0))
    welcome(s, client, scene, step);
  if (s->realtime) {
    double due = s->started_ms + (double)step * 1000.0 / 60.0, now = app_now_ms();
    if (due > now) {
      double wait = due - now;
      struct timespec t = {(time_t)(wait / 1000.0), (long)(((long long)(wait * 1e6)) % 1000000000LL)};
      nanosleep(&t, NULL);
    }
  }
}

void sim_serve_finish(sim_stream* s, uint64_t steps, uint64_t state_hash, uint64_t world_hash) {
  uint8_t end[24];
  stream_put_u64(end, steps);
  stream_put_u64(end + 8, state_hash);
  stream_put_u64(end + 16, world_hash);
  send_all_watchers(s, STREAM_END, end, sizeof end, NULL, 0);
  for (uint32_t c = 0; c < s->client_count; ++c)
    stream_close(s->clients[c]);
  s->client_count = 0;
  stream_close(s->listener);
  s->listener = -1;
}

void sim_serve_json(const sim_stream* s, FILE* out, uint32_t break_events, uint64_t steps) {
  // Per watcher: what one watcher that was there from the start received.
  uint64_t per_watcher = s->journal_bytes + s->motion_bytes;
  fprintf(out,
          "\"stream_watchers_late\": %u, \"stream_frames\": %llu, \"stream_journal_bytes\": %llu, "
          "\"stream_motion_bytes\": %llu, \"stream_snapshot_bytes\": %llu, \"stream_bytes_sent\": %llu, "
          "\"stream_journal_bytes_per_break\": %s, \"stream_bytes_per_second\": %s, ",
          s->joined_late, (unsigned long long)s->frames, (unsigned long long)s->journal_bytes,
          (unsigned long long)s->motion_bytes, (unsigned long long)s->snapshot_bytes,
          (unsigned long long)s->bytes,
          BK_APP_JSON_NUMBER("%.1f", break_events ? (double)s->journal_bytes / break_events : 0.0),
          BK_APP_JSON_NUMBER("%.0f", steps ? (double)per_watcher * 60.0 / (double)steps : 0.0));
}

// ---------------------------------------------------------------- watcher

int sim_watch_run(sim_stream* s, loaded_scene* scene, bool json) {
  char host[64];
  uint16_t port = 0;
  bk_error err = {0};
  stream_parse_address(s->watch, host, &port, &err);
  int server = stream_connect(host, port, (int)s->wait_ms, &err);
  if (server < 0) {
    fprintf(stderr, "breakables sim: --watch: %s\n", err.message);
    return 1;
  }
  const bk_runtime* runtime = bk_world_runtime(scene->world);
  uint64_t joined_at = 0, last_step = 0, checks = 0, bytes = 0, journal_bytes = 0, motion_bytes = 0;
  uint64_t server_state = 0, server_world = 0;
  uint32_t break_events = 0;
  bool ended = false, ok = true, unverified = false;
  stream_frame frame = {0};
  while (ok && !ended) {
    ok = stream_receive(server, (int)s->wait_ms, &frame, &err);
    if (!ok) break;
    bytes += frame.wire_size;
    stream_step step = {0};
    switch (frame.kind) {
    case STREAM_HELLO:
      if (frame.size < 20 || frame.data[0] != STREAM_PROTOCOL) {
        ok = bk_error_set(&err, "stream: the server speaks another protocol");
        break;
      }
      joined_at = last_step = stream_u64(frame.data + 4);
      server_state = stream_u64(frame.data + 12);
      // A server that sends no state at its start (the game's) starts from
      // its scene as built: the same options give the same hash.
      if (joined_at == 0 && server_state != bk_runtime_state_hash(runtime)) unverified = true;
      break;
    case STREAM_SNAPSHOT: {
      // The state of other trees is refused: the scene options differ.
      bk_error why = {0};
      ok = bk_world_load_state(scene->world, frame.data, frame.size, &why);
      if (!ok)
        bk_error_set(&err,
                     "the server's scene is not this one (%s): give the scene options the server was given",
                     why.message);
      else if (bk_runtime_state_hash(runtime) != server_state)
        ok = bk_error_set(&err, "the server's state loaded with another hash");
      unverified = false;
      break;
    }
    case STREAM_STEP:
      if (unverified) {
        ok = bk_error_set(&err,
                          "the server's scene is not this one (state hash %016llx, here %016llx): give the "
                          "scene options the server was given",
                          (unsigned long long)server_state,
                          (unsigned long long)bk_runtime_state_hash(runtime));
        break;
      }
      ok = stream_step_read(&frame, &step, &err) &&
           bk_world_apply_journal(scene->world, step.journal, step.journal_size, &err) &&
           bk_world_apply_motion(scene->world, step.motion, step.motion_size, &err);
      if (!ok) break;
      break_events += bk_world_break_events(scene->world, NULL, 0);
      journal_bytes += step.journal_size;
      motion_bytes += step.motion_size;
      last_step = step.step;
      checks++;
      if (step.state_hash != bk_runtime_state_hash(runtime))
        ok = bk_error_set(&err, "step %llu: state hash %016llx, the server's %016llx",
                          (unsigned long long)step.step, (unsigned long long)bk_runtime_state_hash(runtime),
                          (unsigned long long)step.state_hash);
      break;
    case STREAM_END:
      if (frame.size < 24) {
        ok = bk_error_set(&err, "stream: malformed end frame");
        break;
      }
      ended = true;
      last_step = stream_u64(frame.data);
      server_state = stream_u64(frame.data + 8);
      server_world = stream_u64(frame.data + 16);
      if (server_state != bk_runtime_state_hash(runtime))
        ok = bk_error_set(&err, "at the end: state hash %016llx, the server's %016llx",
                          (unsigned long long)bk_runtime_state_hash(runtime),
                          (unsigned long long)server_state);
      break;
    default:
      break;
    }
    stream_frame_free(&frame);
  }
  stream_close(server);
  if (!ok) {
    fprintf(stderr, "breakables sim: --watch: %s\n", err.message);
    return 1;
  }
  uint64_t state_hash = bk_runtime_state_hash(runtime), world_hash = bk_world_state_hash(scene->world);
  bk_world_stats stats = bk_world_get_stats(scene->world);
  if (json) {
    fputs("{\"scene\": ", stdout);
    app_json_string(stdout, scene->scene->name);
    printf(", \"joined_at_step\": %llu, \"steps\": %llu, \"hash_checks\": %llu, \"bodies_final\": %u, "
           "\"bonds_broken\": %u, \"break_events_received\": %u, \"stream_bytes_received\": %llu, "
           "\"stream_journal_bytes\": %llu, \"stream_motion_bytes\": %llu, \"server_state_hash\": "
           "\"%016llx\", \"server_world_hash\": \"%016llx\", \"state_hash\": \"%016llx\", \"world_hash\": "
           "\"%016llx\"}\n",
           (unsigned long long)joined_at, (unsigned long long)last_step, (unsigned long long)checks,
           stats.bodies, stats.bonds_broken, break_events, (unsigned long long)bytes,
           (unsigned long long)journal_bytes, (unsigned long long)motion_bytes,
           (unsigned long long)server_state, (unsigned long long)server_world, (unsigned long long)state_hash,
           (unsigned long long)world_hash);
  } else {
    printf("%s: watched steps %llu..%llu from %s: %llu state hashes agreed with the server's\n",
           scene->scene->name, (unsigned long long)joined_at, (unsigned long long)last_step, s->watch,
           (unsigned long long)checks);
    printf("  bodies %u, %u bonds broken; received %llu bytes (journal %llu, motion %llu)\n", stats.bodies,
           stats.bonds_broken, (unsigned long long)bytes, (unsigned long long)journal_bytes,
           (unsigned long long)motion_bytes);
    printf("  state hash %016llx, world hash %016llx\n", (unsigned long long)state_hash,
           (unsigned long long)world_hash);
  }
  return 0;
}
