// F5 and F9: a quick save of the world's state, kept in memory and written
// to <cache dir>/quicksave-<scene>.bkstate, and its load. A load reloads the
// scene first (a fresh world and render trees: a refined tree's grown nodes
// are the state's, not the ones drawn now), then loads the state into it.
#include "game_save.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "game_state.h"
#include "scenes.h"
#include "ui.h"

static struct {
  uint8_t* bytes; // the last save (bk_alloc)
  size_t size;
  uint32_t scene_index;
  char line[800]; // what the last F5 or F9 did
  bool failed;
  double shown_at;
} quick;

static const bk_atomic_messages write_messages = {"cannot create a temporary file beside it",
                                                  "cannot write the state", "cannot replace it"};

// <cache dir>/quicksave-<scene>.bkstate: $BREAKABLES_CACHE_DIR, else
// $XDG_CACHE_HOME/breakables, else ~/.cache/breakables, as the trees' cache.
static bool quick_path(const app_game* g, uint32_t scene_index, char* out, size_t size) {
  const char* dir = getenv("BREAKABLES_CACHE_DIR");
  const char* xdg = getenv("XDG_CACHE_HOME");
  const char* home = getenv("HOME");
  const char* name = scene_at(scene_index)->name;
  (void)g;
  int n = dir && dir[0]   ? snprintf(out, size, "%s/quicksave-%s.bkstate", dir, name)
          : xdg && xdg[0] ? snprintf(out, size, "%s/breakables/quicksave-%s.bkstate", xdg, name)
          : home          ? snprintf(out, size, "%s/.cache/breakables/quicksave-%s.bkstate", home, name)
                          : -1;
  return n > 0 && (size_t)n < size;
}

static void say(app_game* g, bool failed, const char* line) {
  snprintf(quick.line, sizeof quick.line, "%s", line);
  quick.failed = failed;
  quick.shown_at = g->hud_seconds;
  fprintf(failed ? stderr : stdout, "breakables play: %s\n", line);
}

// Quick saves change the run: not in a recorded, replayed or streamed one.
static bool allowed(app_game* g, bool busy, const char* key) {
  char line[128];
  if (g->stream.mode == GAME_PLAY && !g->replay.record_path && !g->replay.replay_path && !busy) return true;
  snprintf(line, sizeof line, "%s: not while %s", key,
           busy ? "the panel's sweep runs" : "recording, replaying, serving or watching");
  say(g, true, line);
  return false;
}

void game_save_state(app_game* g, bool busy) {
  if (!allowed(g, busy, "F5") || !g->scene.world) return;
  char line[600], path[512];
  bk_error err = {0};
  size_t size = bk_world_state_size(g->scene.world);
  uint8_t* bytes = bk_alloc(size + 1u);
  if (bk_world_save_state(g->scene.world, bytes, size, &err) != size) {
    snprintf(line, sizeof line, "F5: %s", err.message);
    bk_free(bytes);
    return say(g, true, line);
  }
  bk_free(quick.bytes);
  quick.bytes = bytes;
  quick.size = size;
  quick.scene_index = g->scene_index;
  bk_atomic_file file = {0};
  bool written = quick_path(g, g->scene_index, path, sizeof path) &&
                 bk_file_begin_atomic(path, &write_messages, &file, &err);
  if (written) {
    fwrite(bytes, 1, size, file.stream);
    written = bk_file_commit_atomic(&file, path, &write_messages, &err);
  }
  if (written)
    snprintf(line, sizeof line, "F5: saved the state (%zu bytes) to %s; F9 loads it", size, path);
  else
    snprintf(line, sizeof line, "F5: saved the state (%zu bytes) in memory; not to a file: %s", size,
             err.message[0] ? err.message : "no cache directory");
  say(g, false, line);
}

void game_load_state(app_game* g, bool busy, game_scene_loader load_scene) {
  if (!allowed(g, busy, "F9")) return;
  char line[700], path[512];
  bk_error err = {0};
  if (!quick.bytes && quick_path(g, g->scene_index, path, sizeof path)) {
    // An earlier run's save of this scene.
    void* data = NULL;
    size_t size = 0;
    if (bk_file_read(path, (uint64_t)1 << 32, "4 GiB", &data, &size, &err)) {
      quick.bytes = data;
      quick.size = size;
      quick.scene_index = g->scene_index;
    }
  }
  if (!quick.bytes) return say(g, true, "F9: nothing saved yet (F5 saves)");
  bk_vec3 eye = g->eye;
  double yaw = g->yaw, pitch = g->pitch;
  if (!load_scene(g, quick.scene_index, &err)) {
    snprintf(line, sizeof line, "F9: %s", err.message);
    return say(g, true, line);
  }
  g->eye = eye, g->yaw = yaw, g->pitch = pitch;
  if (!bk_world_load_state(g->scene.world, quick.bytes, quick.size, &err)) {
    snprintf(line, sizeof line, "F9: %s", err.message);
    return say(g, true, line);
  }
  snprintf(line, sizeof line, "F9: loaded the state (%zu bytes), state hash %016llx", quick.size,
           (unsigned long long)bk_runtime_state_hash(bk_world_runtime(g->scene.world)));
  say(g, false, line);
}

void game_save_hud(const app_game* g) {
  if (!quick.line[0] || g->hud_seconds - quick.shown_at > 4.0) return;
  float width = 0.0f, height = 0.0f, text_w = 0.0f, text_h = 0.0f;
  ui_display_size(&width, &height);
  if (!(width > 0.0f && height > 0.0f)) return;
  ui_text_size(quick.line, &text_w, &text_h);
  float pad = 0.6f * text_h, x = 0.5f * (width - text_w), y = 5.0f * pad;
  if (x < pad) x = pad;
  const float box[4] = {0.05f, 0.06f, 0.08f, 0.65f}, ink[4] = {0.95f, 0.95f, 0.92f, 1.0f},
              red[4] = {1.0f, 0.3f, 0.25f, 1.0f};
  ui_overlay_rect(x - pad, y - 0.5f * pad, x + text_w + pad, y + text_h + 0.5f * pad, box, 0.5f * pad);
  ui_overlay_text(x, y, quick.failed ? red : ink, quick.line);
}
