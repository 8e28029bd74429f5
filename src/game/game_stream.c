// breakables serve and breakables watch (game_stream.h): their options, the
// server's side (as sim --serve does it, step by step, from the game's
// worker) and what both show and print. The watcher's side: game_watch.c.
#include "game_stream.h"

#include <string.h>

#include "app.h"
#include "net_stream.h"
#include "ui.h"

game_stream default_game_stream(game_stream_mode mode) {
  game_stream s;
  memset(&s, 0, sizeof s);
  s.mode = mode;
  s.address = mode == GAME_SERVE ? "127.0.0.1:7000" : NULL;
  s.wait_ms = 30000;
  s.listener = -1;
  s.watch = default_game_watch();
  return s;
}

const char* game_stream_command(const game_stream* s) {
  return s->mode == GAME_SERVE ? "serve" : s->mode == GAME_WATCH ? "watch" : "play";
}

int game_stream_parse(int argc, char** argv, int* i, game_stream* s) {
  if (s->mode == GAME_PLAY) return 1;
  const char* command = game_stream_command(s);
  const char* arg = argv[*i];
  char host[64];
  uint16_t port = 0;
  bk_error err = {0};
  if (s->mode == GAME_WATCH && arg[0] != '-') { // the server's address
    if (s->address) {
      fprintf(stderr, "breakables watch: '%s': one server address only (it was given as '%s')\n", arg,
              s->address);
      return 2;
    }
    if (!stream_parse_address(arg, host, &port, &err)) {
      fprintf(stderr, "breakables watch: %s\n", err.message);
      return 2;
    }
    s->address = arg;
    return 0;
  }
  static const char* const names[] = {"--stream-wait", "--listen", "--watchers"};
  const char* value = NULL;
  int which = take_option(command, argc, argv, i, names, s->mode == GAME_SERVE ? 3 : 1, &value);
  if (which == -1) return 1;
  if (which == -2) return 2;
  uint64_t number = 0;
  if (which == 0) {
    if (!option_u64(command, "--stream-wait", value, 1, 600000, &number)) return 2;
    s->wait_ms = number;
  } else if (which == 1) {
    if (!stream_parse_address(value, host, &port, &err)) {
      fprintf(stderr, "breakables serve: --listen: %s\n", err.message);
      return 2;
    }
    s->address = value;
  } else {
    if (!option_u64(command, "--watchers", value, 0, GAME_STREAM_WATCHERS_MAX, &number)) return 2;
    s->watchers = (uint32_t)number;
  }
  return 0;
}

const char* game_stream_usage(const game_stream* s) {
  if (s->mode == GAME_SERVE)
    return "usage: breakables serve [play's options] [--listen ADDR:PORT] [--watchers N] [--stream-wait MS]\n"
           "\n"
           "The demo game as a server: played as 'breakables play' is, with every physics step's\n"
           "destruction (the runtime's journal, the moving pieces' places) sent over TCP to\n"
           "'breakables watch' windows and 'breakables sim --watch' runs given the same scene options.\n"
           "Prints the final state hash on exit.\n"
           "\n"
           "options:\n";
  if (s->mode == GAME_WATCH)
    return "usage: breakables watch ADDR:PORT [--scene NAME | --mesh PATH] [scene options] [--frames N]\n"
           "                  [--screenshot FILE.png] [--width W] [--height H] [--stream-wait MS]\n"
           "\n"
           "A window on a server's game ('breakables serve', 'breakables sim --serve'): builds the\n"
           "scene given (the server's options), never steps it, applies the server's steps as they\n"
           "arrive and checks its state hash against the server's after each. No shooting, weights,\n"
           "panel or scene keys: the server's world is the one that changes. Ends with the server's\n"
           "end, the window or --frames; prints the steps watched and the hashes agreed (exit 0) or\n"
           "the first difference (exit 1). --autofire, --drop, --benchmark, --record-input and\n"
           "--replay are refused.\n"
           "\n"
           "options:\n";
  return NULL;
}

void game_stream_help(const game_stream* s, FILE* out) {
  if (s->mode == GAME_SERVE)
    fputs("  --listen ADDR:PORT    where watchers connect: a numeric IPv4 address or localhost, and a\n"
          "                        port (default 127.0.0.1:7000)\n"
          "  --watchers N          wait for N watchers, 0..16, before the first step (default 0: do not\n"
          "                        wait); others may join at any time (they get the world's state)\n",
          out);
  if (s->mode != GAME_PLAY)
    fputs("  --stream-wait MS      how long to wait for the watchers, the server or a frame, 1..600000\n"
          "                        (default 30000)\n",
          out);
}

int game_stream_setup(game_stream* s, int argc, char** argv, uint32_t frames) {
  s->scripted = frames != 0;
  if (s->mode != GAME_WATCH) return 0;
  if (!s->address) {
    fprintf(stderr, "breakables watch: give the server's address, e.g. 'breakables watch 127.0.0.1:7000'\n");
    return 2;
  }
  static const char* const changing[] = {"--autofire", "--drop", "--benchmark", "--record-input", "--replay"};
  for (int i = 1; i < argc; ++i)
    for (int k = 0; k < 5; ++k)
      if (strcmp(argv[i], changing[k]) == 0) {
        fprintf(stderr,
                "breakables watch: '%s' cannot be given: a watcher's world changes as the server's only\n",
                argv[i]);
        return 2;
      }
  return 0;
}

bool game_stream_watching(const game_stream* s) { return s->mode == GAME_WATCH; }

bool game_stream_ended(const game_stream* s) {
  return s->mode == GAME_WATCH && (s->watch.ended || (s->watch.failed && s->scripted));
}

// ---------------------------------------------------------------- server

static void drop_client(game_stream* s, uint32_t c) {
  stream_close(s->clients[c]);
  s->clients[c] = s->clients[--s->client_count];
}

// Sends to every watcher, packed (and compressed) once; one that has gone
// is dropped.
static void send_all(game_stream* s, uint8_t kind, const void* a, size_t na, const void* b, size_t nb) {
  size_t size = 0;
  uint8_t* frame = stream_pack(kind, a, na, b, nb, &size);
  for (uint32_t c = 0; c < s->client_count;) {
    if (stream_send_packed(s->clients[c], frame, size)) {
      s->bytes_sent += size;
      c++;
      continue;
    }
    drop_client(s, c);
  }
  bk_free(frame);
}

static void hello_frame(uint8_t out[20], const bk_world* world, uint64_t step) {
  stream_put_u32(out, STREAM_PROTOCOL);
  stream_put_u64(out + 4, step);
  stream_put_u64(out + 12, bk_runtime_state_hash(bk_world_runtime(world)));
}

// A new watcher: the step it joins at and the state hash then; after the
// scene's first step, the world's state too (as sim --serve welcomes one).
static void welcome(game_stream* s, int client, const bk_world* world) {
  uint8_t hello[20];
  hello_frame(hello, world, s->step);
  size_t sent = stream_send(client, STREAM_HELLO, hello, sizeof hello, NULL, 0);
  if (sent && s->step > 0) {
    size_t size = bk_world_state_size(world);
    uint8_t* state = bk_alloc(size + 1);
    bk_error err = {0};
    size_t written = bk_world_save_state(world, state, size, &err);
    size_t more = written ? stream_send(client, STREAM_SNAPSHOT, state, written, NULL, 0) : 0;
    if (!written) fprintf(stderr, "breakables serve: a watcher's state: %s\n", err.message);
    sent = more ? sent + more : 0;
    bk_free(state);
  }
  if (!sent || s->client_count == GAME_STREAM_WATCHERS_MAX) {
    stream_close(client);
    return;
  }
  s->bytes_sent += sent;
  s->clients[s->client_count++] = client;
  s->joined_late += s->step > 0;
}

static bool serve_loaded(game_stream* s, bk_world* world, bk_error* err) {
  s->step = 0;
  // The journal starts with the scene: watchers build the same one.
  bk_world_set_journal(world, true);
  bk_world_clear_journal(world);
  if (s->listener >= 0) {
    // A reload or another scene: every watcher starts again from it.
    uint8_t hello[20];
    hello_frame(hello, world, 0);
    uint32_t watching = s->client_count;
    send_all(s, STREAM_HELLO, hello, sizeof hello, NULL, 0);
    if (watching)
      fprintf(stderr,
              "breakables serve: a scene loaded anew: %u watcher%s sent its start (one given other scene "
              "options leaves)\n",
              watching, watching == 1 ? "" : "s");
    return true;
  }
  char host[64];
  uint16_t port = 0;
  if (!stream_parse_address(s->address, host, &port, err)) return false;
  s->listener = stream_listen(host, port, err);
  if (s->listener < 0) return false;
  while (s->client_count < s->watchers) {
    int client = stream_accept(s->listener, (int)s->wait_ms);
    if (client < 0) {
      bk_error_set(err, "%u of %u watchers connected to %s within %llu ms", s->client_count, s->watchers,
                   s->address, (unsigned long long)s->wait_ms);
      for (uint32_t c = s->client_count; c > 0; --c)
        drop_client(s, c - 1);
      stream_close(s->listener);
      s->listener = -1;
      return false;
    }
    welcome(s, client, world);
  }
  return true;
}

// After a step: its journal and the moving bodies' places to every watcher
// (the frame sim --serve sends), and the journal emptied.
static void serve_step(game_stream* s, bk_world* world) {
  if (s->client_count) {
    size_t journal_size = 0;
    const void* journal = bk_world_journal(world, &journal_size);
    size_t motion_capacity = bk_world_motion_size(world);
    uint8_t* motion = bk_alloc(motion_capacity + 1);
    size_t motion_size = bk_world_motion(world, motion, motion_capacity);
    uint8_t* head = bk_alloc(20 + journal_size);
    stream_put_u64(head, s->step);
    stream_put_u64(head + 8, bk_runtime_state_hash(bk_world_runtime(world)));
    stream_put_u32(head + 16, (uint32_t)journal_size);
    if (journal_size) memcpy(head + 20, journal, journal_size);
    send_all(s, STREAM_STEP, head, 20 + journal_size, motion, motion_size);
    bk_free(head);
    bk_free(motion);
  }
  bk_world_clear_journal(world);
}

// ---------------------------------------------------------------- both

bool game_stream_loaded(game_stream* s, bk_world* world, bk_error* err) {
  if (s->mode == GAME_SERVE) return serve_loaded(s, world, err);
  if (s->mode != GAME_WATCH) return true;
  s->watch.scene_fresh = true;
  return s->watch.reader ? true : watch_connect(&s->watch, s->address, s->wait_ms, err);
}

bool game_stream_frame(game_stream* s, bk_world* world, bool paused, int* steps) {
  if (s->mode == GAME_SERVE && s->listener >= 0) {
    // Only with nothing in the journal: a watcher's state is the one after
    // the last step sent (a panel's change since then goes in the next).
    size_t journal = 0;
    bk_world_journal(world, &journal);
    for (int client = journal ? -1 : stream_accept(s->listener, 0); client >= 0;
         client = stream_accept(s->listener, 0))
      welcome(s, client, world);
  } else if (s->mode == GAME_WATCH) {
    bool rebuild = false;
    uint32_t waiting = watch_frames(&s->watch, world, &rebuild);
    *steps = paused ? 0 : (int)waiting; // paused: they wait
    return rebuild;
  }
  return false;
}

void game_stream_world_step(game_stream* s, bk_world* world) {
  if (s->mode == GAME_WATCH) {
    watch_step(&s->watch, world);
    return;
  }
  bk_world_step(world);
  s->step++;
  if (s->mode == GAME_SERVE) serve_step(s, world);
}

void game_stream_hud(const game_stream* s) {
  const game_watch* w = &s->watch;
  if (s->mode == GAME_PLAY) return;
  char line[768];
  if (s->mode == GAME_SERVE)
    snprintf(line, sizeof line, "serving %s: %u watcher%s, step %llu", s->address, s->client_count,
             s->client_count == 1 ? "" : "s", (unsigned long long)s->step);
  else if (w->failed)
    snprintf(line, sizeof line, "watching %s: %s", s->address, w->error);
  else if (!w->greeted)
    snprintf(line, sizeof line, "watching %s: waiting for the server   (shooting is off while watching)",
             s->address);
  else
    snprintf(line, sizeof line,
             "watching %s: step %llu, hashes agreed %llu%s   (shooting is off while watching)", s->address,
             (unsigned long long)w->step, (unsigned long long)w->agreed,
             w->ended ? ", the server has ended" : "");
  float width = 0.0f, height = 0.0f, text_w = 0.0f, text_h = 0.0f;
  ui_display_size(&width, &height);
  if (!(width > 0.0f && height > 0.0f)) return;
  ui_text_size(line, &text_w, &text_h);
  float pad = 0.6f * text_h, x = 0.5f * (width - text_w), y = 2.0f * pad;
  if (x < pad) x = pad;
  const float box[4] = {0.05f, 0.06f, 0.08f, 0.65f}, ink[4] = {0.95f, 0.95f, 0.92f, 1.0f},
              red[4] = {1.0f, 0.3f, 0.25f, 1.0f};
  ui_overlay_rect(x - pad, y - 0.5f * pad, x + text_w + pad, y + text_h + 0.5f * pad, box, 0.5f * pad);
  ui_overlay_text(x, y, w->failed ? red : ink, line);
}

bool game_stream_finish(game_stream* s, const bk_world* world) {
  if (s->mode == GAME_PLAY) return true;
  uint64_t state_hash = world ? bk_runtime_state_hash(bk_world_runtime(world)) : 0;
  if (s->mode == GAME_SERVE) {
    if (s->listener < 0) return true; // never listened: the scene did not load
    uint64_t world_hash = bk_world_state_hash(world);
    uint8_t end[24];
    stream_put_u64(end, s->step);
    stream_put_u64(end + 8, state_hash);
    stream_put_u64(end + 16, world_hash);
    uint32_t watching = s->client_count;
    send_all(s, STREAM_END, end, sizeof end, NULL, 0);
    for (uint32_t c = s->client_count; c > 0; --c)
      drop_client(s, c - 1);
    stream_close(s->listener);
    s->listener = -1;
    printf("serve: steps 1..%llu, %u watching at the end (%u joined late), %llu bytes sent, state hash "
           "%016llx, world hash %016llx\n",
           (unsigned long long)s->step, watching, s->joined_late, (unsigned long long)s->bytes_sent,
           (unsigned long long)state_hash, (unsigned long long)world_hash);
    return true;
  }
  game_watch* w = &s->watch;
  if (!w->reader) return true; // never connected: said when loading
  watch_close(w);
  if (w->failed) {
    fprintf(stderr, "breakables watch: %s\n", w->error);
    return false;
  }
  printf("watch: steps %llu..%llu, %llu state hashes agreed, state hash %016llx%s\n",
         (unsigned long long)w->joined_at, (unsigned long long)w->step, (unsigned long long)w->agreed,
         (unsigned long long)state_hash, w->ended ? "" : " (the server had not ended)");
  return true;
}
