// breakables serve and breakables watch over loopback, windowed under a
// virtual display (xvfb-run) as test_game runs play: a game server's shots
// reach a watching window, which never steps its world and has the server's
// runtime state hash after every step and at the end, and draws the same
// broken wall; `sim --watch` follows a game server as well, and a game
// window joins a `sim --serve` run late, from the world's state; a server
// that loads its scene anew sends its watchers the new start. Every wait is
// bounded (the processes' --stream-wait and timeout(1) around the whole run).
#include <stb_image.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "ensure.h"
#include "recording.h"

// Another range than test_stream's, so that both may run at once.
static unsigned port_base(void) { return 40000u + (unsigned)getpid() % 20000u; }

static char* read_file(const char* tag) {
  char path[512];
  snprintf(path, sizeof path, "%s/game_stream_%s.txt", BK_TEST_TMP, tag);
  FILE* f = fopen(path, "rb");
  ENSURE_MSG(f != NULL, "%s missing", path);
  static char text[6][1 << 14];
  static int which = 0;
  char* out = text[which++ % 6];
  size_t n = fread(out, 1, sizeof text[0] - 1, f);
  out[n] = 0;
  fclose(f);
  return out;
}

// Runs `script` (processes of BK_BREAKABLES_EXE as $B, files under $T) in
// one virtual display, at most 300 s; the script's exit status (kept in a
// file: xvfb-run's own may be its cleanup's).
static int run_script(const char* script) {
  char command[8192], path[512];
  snprintf(path, sizeof path, "%s/game_stream_status.txt", BK_TEST_TMP);
  remove(path);
  // W: a small window for the runs whose pictures are not compared (a
  // quarter of the pixels for llvmpipe to draw). Q: those runs' windows
  // skip LeakSanitizer, whose tracer now and then crashes among llvmpipe's
  // threads (the first run's windows, which check for leaks, go through the
  // same code).
  snprintf(command, sizeof command,
           "B='%s'; T='%s/game_stream'; W='--width 640 --height 360'; "
           "Q=\"env ASAN_OPTIONS=${ASAN_OPTIONS:-}:detect_leaks=0\"; export B T W Q; timeout 300 xvfb-run -a "
           "-s '-screen 0 1280x720x24' sh -c "
           "'%s; echo $? >${T}_status.txt'",
           BK_BREAKABLES_EXE, BK_TEST_TMP, script);
  ENSURE(system(command) != -1);
  FILE* f = fopen(path, "rb");
  int status = -1;
  if (f) {
    if (fscanf(f, "%d", &status) != 1) status = -1;
    fclose(f);
  }
  return status;
}

// The 16 hex digits after "state hash " in a line that starts with `head`.
static void state_hash_of(const char* text, const char* head, char out[17]) {
  const char* line = strstr(text, head);
  ENSURE_MSG(line, "no '%s' line in: %s", head, text);
  const char* at = strstr(line, "state hash ");
  ENSURE_MSG(at, "no state hash in: %s", line);
  memcpy(out, at + strlen("state hash "), 16);
  out[16] = 0;
}

// The server's own final line: its steps and state hash.
static unsigned long long server_steps(const char* text) {
  const char* line = strstr(text, "serve: steps 1..");
  ENSURE_MSG(line, "no serve line in: %s", text);
  return strtoull(line + strlen("serve: steps 1.."), NULL, 10);
}

// "watch: steps A..B, K state hashes agreed, state hash H".
static void watched(const char* text, unsigned long long* from, unsigned long long* to,
                    unsigned long long* agreed) {
  const char* line = strstr(text, "watch: steps ");
  ENSURE_MSG(line, "no watch line in: %s", text);
  ENSURE_MSG(sscanf(line, "watch: steps %llu..%llu, %llu state hashes agreed", from, to, agreed) == 3, "%s",
             line);
}

static int count_lines_of(const char* text) {
  int lines = 0;
  for (const char* p = text; *p; ++p)
    lines += *p == '\n';
  return lines;
}

// Mean absolute difference of two pictures' pixels inside a rectangle.
static double picture_difference(const char* a_path, const char* b_path, int x0, int y0, int x1, int y1) {
  int w = 0, h = 0, c = 0, w2 = 0, h2 = 0;
  unsigned char* a = stbi_load(a_path, &w, &h, &c, 3);
  unsigned char* b = stbi_load(b_path, &w2, &h2, &c, 3);
  ENSURE_MSG(a && b && w == w2 && h == h2 && x1 <= w && y1 <= h, "cannot compare %s and %s", a_path, b_path);
  double sum = 0.0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      for (int k = 0; k < 3; ++k)
        sum += abs((int)a[3 * (y * w + x) + k] - (int)b[3 * (y * w + x) + k]);
  stbi_image_free(a);
  stbi_image_free(b);
  return sum / (3.0 * (x1 - x0) * (y1 - y0));
}

// A game server with two watchers from the start: a window and sim --watch.
static void test_watchers(void) {
  unsigned port = port_base();
  char script[4096];
  snprintf(
      script, sizeof script,
      "$B serve --scene wall --frames 200 --autofire 3 --watchers 2 --listen 127.0.0.1:%u --stream-wait "
      "60000 "
      "--hide-panel --hide-hud --screenshot ${T}_server.png >${T}_server.txt 2>${T}_server_err.txt & p1=$!; "
      "$B watch 127.0.0.1:%u --scene wall --frames 100000 --stream-wait 60000 --hide-hud "
      "--screenshot ${T}_window.png >${T}_window.txt 2>${T}_window_err.txt & p2=$!; "
      "$B sim --scene wall --watch 127.0.0.1:%u --stream-wait 60000 --json >${T}_sim.txt "
      "2>${T}_sim_err.txt; s=$?; wait $p1 || s=1; wait $p2 || s=1; (exit $s)",
      port, port, port);
  int status = run_script(script);
  const char* server = read_file("server");
  const char* window = read_file("window");
  const char* sim = read_file("sim");
  ENSURE_MSG(status == 0, "status %d\nserver: %s%s\nwindow: %s%s\nsim: %s%s", status, server,
             read_file("server_err"), window, read_file("window_err"), sim, read_file("sim_err"));
  char server_hash[17], window_hash[17], sim_hash[17];
  state_hash_of(server, "serve: ", server_hash);
  state_hash_of(window, "watch: ", window_hash);
  ENSURE(server_steps(server) == 200 && strstr(server, "shots 3,"));
  ENSURE_MSG(strcmp(server_hash, window_hash) == 0, "server %s, window %s", server_hash, window_hash);
  // Every step's hash compared and agreed, from the first to the last.
  unsigned long long from = 0, to = 0, agreed = 0;
  watched(window, &from, &to, &agreed);
  ENSURE_MSG(from == 0 && to == 200 && agreed == 200, "%s", window);
  ENSURE(count_lines_of(window) == 1); // the watcher's one line
  // sim --watch follows the game server too.
  const char* at = strstr(sim, "\"state_hash\": \"");
  ENSURE_MSG(at, "%s", sim);
  memcpy(sim_hash, at + strlen("\"state_hash\": \""), 16);
  sim_hash[16] = 0;
  ENSURE_MSG(strcmp(server_hash, sim_hash) == 0, "server %s, sim --watch %s", server_hash, sim_hash);
  ENSURE(strstr(sim, "\"hash_checks\": 200,") && strstr(sim, "\"joined_at_step\": 0,"));
  // The shots broke the wall (bonds broken), and the watching window draws
  // it as the server does: the wall's upper part (its hole; the projectile
  // lies below it) the same in both pictures, to the light's dust.
  ENSURE(!strstr(sim, "\"bonds_broken\": 0,"));
  char a[512], b[512];
  snprintf(a, sizeof a, "%s/game_stream_server.png", BK_TEST_TMP);
  snprintf(b, sizeof b, "%s/game_stream_window.png", BK_TEST_TMP);
  double difference = picture_difference(a, b, 390, 200, 930, 440);
  // Dust differs between the two windows (each runs its own), so the bound
  // is 6 of 255, where the unbroken wall is more than four times further.
  ENSURE_MSG(difference < 6.0, "the window's wall differs from the server's by %.2f", difference);
  // ... where the wall before the shots differs: the region shows the hole.
  ENSURE(run_script("$B play --scene wall --frames 2 --hide-panel --hide-hud --screenshot ${T}_whole.png "
                    ">/dev/null 2>&1") == 0);
  snprintf(b, sizeof b, "%s/game_stream_whole.png", BK_TEST_TMP);
  double whole = picture_difference(a, b, 390, 200, 930, 440);
  printf("wall region: mean difference %.2f of 255 between the server's and the window's pictures, %.2f "
         "between the server's and the unbroken wall's\n",
         difference, whole);
  ENSURE_MSG(whole > 4.0 * difference && whole > 4.0, "the unbroken wall differs by %.2f only", whole);
}

// A window follows a sim --serve run as well, joining it late (after a
// sim --watch from the start): it gets the world's state and follows from
// there.
static void test_window_follows_sim(void) {
  unsigned port = port_base() + 3;
  char script[4096];
  snprintf(
      script, sizeof script,
      "$B sim --scene wall --shots 4 --steps 240 --volley 200 --realtime --serve 127.0.0.1:%u "
      "--stream-wait 60000 --json >${T}_sim.txt 2>${T}_sim_err.txt & p1=$!; "
      "$B sim --scene wall --watch 127.0.0.1:%u --stream-wait 60000 >/dev/null 2>${T}_first_err.txt & p2=$!; "
      "sleep 1.5; $Q $B watch $W 127.0.0.1:%u --scene wall --frames 100000 --stream-wait 60000 "
      ">${T}_window.txt "
      "2>${T}_window_err.txt; s=$?; wait $p1 || s=1; wait $p2 || s=1; (exit $s)",
      port, port, port);
  int status = run_script(script);
  const char* sim = read_file("sim");
  const char* window = read_file("window");
  ENSURE_MSG(status == 0, "status %d\nsim: %s%s\nwindow: %s%s", status, sim, read_file("sim_err"), window,
             read_file("window_err"));
  char window_hash[17];
  state_hash_of(window, "watch: ", window_hash);
  const char* at = strstr(sim, "\"state_hash\": \"");
  ENSURE_MSG(at && strncmp(at + strlen("\"state_hash\": \""), window_hash, 16) == 0, "%s vs %s", sim,
             window_hash);
  unsigned long long from = 0, to = 0, agreed = 0;
  watched(window, &from, &to, &agreed);
  ENSURE_MSG(from > 0 && from < 240 && to == 240 && agreed == 240 - from, "%s", window);
}

// A server that loads its scene anew (here a replay's scene event at step
// 150, as the R key or a scene key makes one): its watchers are sent the
// new start; a window of the same scene builds it again and follows on,
// one of another scene leaves in one line.
static void write_reloading(const char* base, const char* path, const char* scene) {
  recording rec = {0};
  bk_error err = {0};
  ENSURE_MSG(recording_read(base, &rec, &err), "%s", err.message);
  rec.has_hashes = false; // the run changes: nothing recorded to compare
  recording_scene again = rec.scenes[rec.events[0].scene];
  snprintf(again.name, sizeof again.name, "%s", scene);
  recording_add_scene(&rec, 80, &again);
  // In step order: the scene event before the later shots.
  recording_event e = rec.events[rec.event_count - 1];
  uint32_t i = rec.event_count - 1;
  for (; i > 0 && rec.events[i - 1].step > e.step; --i)
    rec.events[i] = rec.events[i - 1];
  rec.events[i] = e;
  ENSURE_MSG(recording_write(&rec, path, &err), "%s", err.message);
  recording_free(&rec);
}

static void test_server_reloads(void) {
  unsigned port = port_base() + 4;
  char script[4096], base[512], path[512];
  snprintf(base, sizeof base, "%s/game_stream_base.bkrec", BK_TEST_TMP);
  snprintf(script, sizeof script, "$B sim --scene wall --shots 4 --steps 160 --record %s >/dev/null 2>&1",
           base);
  ENSURE(run_script(script) == 0);
  for (int other = 0; other < 2; ++other) {
    snprintf(path, sizeof path, "%s/game_stream_reload.bkrec", BK_TEST_TMP);
    write_reloading(base, path, other ? "tower" : "wall");
    snprintf(script, sizeof script,
             "$Q $B serve $W --replay %s --frames 160 --watchers 1 --listen 127.0.0.1:%u --stream-wait 60000 "
             ">${T}_server.txt 2>${T}_server_err.txt & p1=$!; "
             "$Q $B watch $W 127.0.0.1:%u --scene wall --frames 100000 --stream-wait 60000 >${T}_window.txt "
             "2>${T}_window_err.txt; s=$?; wait $p1 || s=9; (exit $s)",
             path, port + (unsigned)other, port + (unsigned)other);
    int status = run_script(script);
    const char* server = read_file("server");
    const char* server_err = read_file("server_err");
    const char* window = read_file("window");
    const char* window_err = read_file("window_err");
    ENSURE_MSG(strstr(server_err, "a scene loaded anew: 1 watcher sent its start") &&
                   count_lines_of(server_err) == 1,
               "%s", server_err);
    if (other) {
      ENSURE_MSG(status == 1 && count_lines_of(window_err) == 1 &&
                     strstr(window_err, "the server loaded another scene or options"),
                 "status %d: %s", status, window_err);
      continue;
    }
    ENSURE_MSG(status == 0, "status %d\nserver: %s%s\nwindow: %s%s", status, server, server_err, window,
               window_err);
    char server_hash[17], window_hash[17];
    state_hash_of(server, "serve: ", server_hash);
    state_hash_of(window, "watch: ", window_hash);
    ENSURE_MSG(strcmp(server_hash, window_hash) == 0, "server %s, window %s", server_hash, window_hash);
    // The steps since the new start; every step's hash agreed, before it too.
    unsigned long long from = 0, to = 0, agreed = 0;
    watched(window, &from, &to, &agreed);
    ENSURE_MSG(server_steps(server) == 80 && from == 0 && to == 80 && agreed == 160, "%s%s", server, window);
  }
}

// Refused in one line: a watcher without an address or with options that
// change its world, bad addresses, nobody serving, another scene.
static void test_refusals(void) {
  unsigned port = port_base() + 2;
  char script[4096];
  const struct {
    const char* args;
    int status;
    const char* message;
  } cases[] = {
      {"watch --scene wall", 2, "give the server's address"},
      {"watch 127.0.0.1:7000 --autofire 3", 2, "'--autofire' cannot be given"},
      {"watch 127.0.0.1:7000 --replay x.bkrec", 2, "'--replay' cannot be given"},
      {"watch 127.0.0.1", 2, "is not an address: give HOST:PORT"},
      {"watch 127.0.0.1:7000 127.0.0.1:7001", 2, "one server address only"},
      {"serve --listen 127.0.0.1:0", 2, "port must be a number in 1..65535"},
      {"serve --watchers 17", 2, "--watchers"},
      {"watch 127.0.0.1:1 --scene wall --stream-wait 300", 1, "cannot connect to 127.0.0.1:1 within 300 ms"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
    snprintf(script, sizeof script, "$B %s >${T}_out.txt 2>${T}_err.txt", cases[i].args);
    int status = run_script(script);
    const char* err = read_file("err");
    ENSURE_MSG(status == cases[i].status && count_lines_of(err) == 1 && strstr(err, cases[i].message),
               "'%s': status %d, %s", cases[i].args, status, err);
  }
  // A window given another scene than the server's leaves at once; the server plays on.
  snprintf(script, sizeof script,
           "$Q $B serve $W --scene wall --frames 30 --watchers 1 --listen 127.0.0.1:%u --stream-wait 60000 "
           ">${T}_server.txt 2>${T}_server_err.txt & p1=$!; "
           "$Q $B watch $W 127.0.0.1:%u --scene tower --frames 100000 --stream-wait 60000 >${T}_out.txt "
           "2>${T}_err.txt; "
           "s=$?; wait $p1 || s=9; (exit $s)",
           port, port);
  int status = run_script(script);
  const char* err = read_file("err");
  ENSURE_MSG(status == 1 && count_lines_of(err) == 1 && strstr(err, "the server's scene is not this one"),
             "status %d: %s", status, err);
  ENSURE(server_steps(read_file("server")) == 30);
}

int main(void) {
  setenv("BREAKABLES_CACHE_DIR", BK_TEST_TMP "/cache", 1);
  if (system("command -v xvfb-run >/dev/null 2>&1") != 0) {
    fprintf(stderr, "xvfb-run is missing: scripts/setup.sh installs it\n");
    return 1;
  }
  test_refusals();
  test_watchers();
  test_window_follows_sim();
  test_server_reloads();
  return 0;
}
