// breakables watch (game_watch.h): a thread reads the server's frames as
// they come, so that the window never waits on the network; each frame the
// main thread takes the hello, state and end frames and the worker applies
// the step frames that arrived, in order, in place of the world's steps.
#include "game_watch.h"

#include <errno.h>
#include <poll.h>
#include <pthread.h>
#include <stdarg.h>
#include <string.h>

#include "net_stream.h"

typedef struct watch_item {
  stream_frame frame;
  struct watch_item* next;
} watch_item;

struct game_watch_reader {
  pthread_t thread;
  pthread_mutex_t lock;
  int socket;
  int wait_ms;
  bool quit;       ///< the window asks the thread to stop
  bool done;       ///< the thread has stopped: the end came, or the connection failed
  char error[512]; ///< why it failed ("" after the end frame)
  watch_item *head, *tail;
};

game_watch default_game_watch(void) {
  game_watch w;
  memset(&w, 0, sizeof w);
  w.server = -1;
  return w;
}

static void fail(game_watch* s, const char* format, ...) {
  if (s->failed) return; // the first failure is the one that tells
  va_list args;
  va_start(args, format);
  vsnprintf(s->error, sizeof s->error, format, args);
  va_end(args);
  s->failed = true;
}

static bool quitting(game_watch_reader* r) {
  pthread_mutex_lock(&r->lock);
  bool quit = r->quit;
  pthread_mutex_unlock(&r->lock);
  return quit;
}

static void* reader_main(void* self) {
  game_watch_reader* r = self;
  bk_error err = {0};
  bool ended = false;
  while (!ended && !quitting(r)) {
    // A short look, so that the window's exit is never kept waiting; a
    // paused server sends nothing for as long as it likes.
    struct pollfd p = {r->socket, POLLIN, 0};
    int ready = poll(&p, 1, 100);
    if (ready == 0 || (ready < 0 && errno == EINTR)) continue;
    watch_item* item = bk_calloc(1, sizeof *item);
    if (!stream_receive(r->socket, r->wait_ms, &item->frame, &err)) {
      bk_free(item);
      break;
    }
    ended = item->frame.kind == STREAM_END;
    pthread_mutex_lock(&r->lock);
    if (r->tail)
      r->tail->next = item;
    else
      r->head = item;
    r->tail = item;
    pthread_mutex_unlock(&r->lock);
  }
  pthread_mutex_lock(&r->lock);
  r->done = true;
  if (!ended && !r->quit) snprintf(r->error, sizeof r->error, "%s", err.message);
  pthread_mutex_unlock(&r->lock);
  return NULL;
}

bool watch_connect(game_watch* s, const char* address, uint64_t wait_ms, bk_error* err) {
  char host[64];
  uint16_t port = 0;
  if (!stream_parse_address(address, host, &port, err)) return false;
  s->server = stream_connect(host, port, (int)wait_ms, err);
  if (s->server < 0) return false;
  game_watch_reader* r = bk_calloc(1, sizeof *r);
  r->socket = s->server;
  r->wait_ms = (int)wait_ms;
  pthread_mutex_init(&r->lock, NULL);
  if (pthread_create(&r->thread, NULL, reader_main, r) != 0) {
    pthread_mutex_destroy(&r->lock);
    bk_free(r);
    stream_close(s->server);
    s->server = -1;
    return bk_error_set(err, "cannot start a thread to read the stream");
  }
  s->reader = r;
  return true;
}

void watch_close(game_watch* s) {
  game_watch_reader* r = s->reader;
  if (r) {
    pthread_mutex_lock(&r->lock);
    r->quit = true;
    pthread_mutex_unlock(&r->lock);
    pthread_join(r->thread, NULL);
    for (watch_item* item = r->head; item;) {
      watch_item* next = item->next;
      stream_frame_free(&item->frame);
      bk_free(item);
      item = next;
    }
    pthread_mutex_destroy(&r->lock);
    bk_free(r);
    s->reader = NULL;
  }
  stream_close(s->server);
  s->server = -1;
}

// The head of what arrived, taken off; NULL when nothing waits.
static watch_item* take(game_watch_reader* r) {
  pthread_mutex_lock(&r->lock);
  watch_item* item = r->head;
  if (item) {
    r->head = item->next;
    if (!r->head) r->tail = NULL;
  }
  pthread_mutex_unlock(&r->lock);
  return item;
}

static void release(watch_item* item) {
  stream_frame_free(&item->frame);
  bk_free(item);
}

// False when the scene must be built anew first (the hello stays).
static bool hello(game_watch* s, bk_world* world, const stream_frame* f) {
  if (f->size < 20 || f->data[0] != STREAM_PROTOCOL) {
    fail(s, "the server speaks another protocol");
    return true;
  }
  // A second hello: the server loaded its scene anew, and so does the
  // watcher, with its own scene options (the same give the same start).
  bool again = s->greeted;
  if (again && !s->scene_fresh) return false;
  s->greeted = true;
  s->scene_fresh = false;
  s->joined_at = s->step = stream_u64(f->data + 4);
  s->server_state = stream_u64(f->data + 12);
  uint64_t here = bk_runtime_state_hash(bk_world_runtime(world));
  // From the start: the same scene must give the same state.
  if (s->joined_at == 0 && s->server_state != here)
    fail(s,
         again ? "the server loaded another scene or options (state hash %016llx, here %016llx): watch it "
                 "again with its scene options"
               : "the server's scene is not this one (state hash %016llx, here %016llx): give the scene "
                 "options the server was given",
         (unsigned long long)s->server_state, (unsigned long long)here);
  return true;
}

static void snapshot(game_watch* s, bk_world* world, const stream_frame* f) {
  s->scene_fresh = false;
  bk_error err = {0};
  if (!bk_world_load_state(world, f->data, f->size, &err)) {
    fail(s, "the server's state: %s", err.message);
    return;
  }
  uint64_t here = bk_runtime_state_hash(bk_world_runtime(world));
  if (here != s->server_state)
    fail(s, "the server's state loaded with state hash %016llx, the server's %016llx",
         (unsigned long long)here, (unsigned long long)s->server_state);
}

static void end(game_watch* s, const bk_world* world, const stream_frame* f) {
  if (f->size < 24) {
    fail(s, "stream: malformed end frame");
    return;
  }
  s->ended = true;
  uint64_t step = stream_u64(f->data), server = stream_u64(f->data + 8);
  uint64_t here = bk_runtime_state_hash(bk_world_runtime(world));
  if (step != s->step)
    fail(s, "the server ended at step %llu, the last step here is %llu", (unsigned long long)step,
         (unsigned long long)s->step);
  else if (server != here)
    fail(s, "at the end: state hash %016llx, the server's %016llx", (unsigned long long)here,
         (unsigned long long)server);
}

uint32_t watch_frames(game_watch* s, bk_world* world, bool* rebuild) {
  game_watch_reader* r = s->reader;
  *rebuild = false;
  if (!r) return 0;
  for (;;) {
    if (s->failed || s->ended) return 0;
    pthread_mutex_lock(&r->lock);
    uint32_t steps = 0;
    for (const watch_item* item = r->head; item && item->frame.kind == STREAM_STEP; item = item->next)
      steps++;
    watch_item* head = r->head;
    bool lost = r->done && r->error[0];
    pthread_mutex_unlock(&r->lock);
    if (steps) return steps;
    if (!head) {
      // r->done is set after the last frame is queued: all of them are handled.
      if (lost) fail(s, "%s", r->error);
      return 0;
    }
    // Only this thread takes frames off while the worker is not stepping.
    if (head->frame.kind == STREAM_HELLO && !hello(s, world, &head->frame)) {
      *rebuild = true;
      return 0;
    }
    if (head->frame.kind == STREAM_SNAPSHOT)
      snapshot(s, world, &head->frame);
    else if (head->frame.kind == STREAM_END)
      end(s, world, &head->frame);
    release(take(r));
  }
}

void watch_step(game_watch* s, bk_world* world) {
  watch_item* item = s->reader ? take(s->reader) : NULL;
  if (!item) return;
  if (s->failed) { // nothing more applies: the two worlds differ
    release(item);
    return;
  }
  bk_error err = {0};
  stream_step step = {0};
  bool ok = stream_step_read(&item->frame, &step, &err) &&
            bk_world_apply_journal(world, step.journal, step.journal_size, &err) &&
            bk_world_apply_motion(world, step.motion, step.motion_size, &err);
  s->scene_fresh = false;
  if (!ok) {
    fail(s, "step %llu: %s", (unsigned long long)step.step, err.message);
  } else {
    s->step = step.step;
    uint64_t here = bk_runtime_state_hash(bk_world_runtime(world));
    if (here != step.state_hash)
      fail(s, "step %llu: state hash %016llx, the server's %016llx", (unsigned long long)step.step,
           (unsigned long long)here, (unsigned long long)step.state_hash);
    else
      s->agreed++;
  }
  release(item);
}
