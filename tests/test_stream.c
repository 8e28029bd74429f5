// The destruction stream over loopback (sim --serve / --watch): a watcher
// that only applies the server's journal and motion has the server's
// runtime state hash after every step of a 40-shot run, and so does one
// that joins late (from the world's state); a watcher of another scene, a
// server that is not there and a server that sends garbage are refused in
// one line, never a crash.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#define RUN_STDERR_PATH BK_TEST_TMP "/stream_stderr.txt"
#include "run_exe.h"

#include "cli_util.h"

static unsigned port_base(void) { return 20000u + (unsigned)getpid() % 20000u; }

// The server in the background: its stdout and stderr go to files.
static FILE* start_server(const char* args, unsigned port, const char* tag) {
  char command[4096];
  snprintf(command, sizeof command,
           "'%s' sim %s --serve 127.0.0.1:%u --stream-wait 60000 --json >'%s/stream_%s.json' "
           "2>'%s/stream_%s.err'",
           BK_BREAKABLES_EXE, args, port, BK_TEST_TMP, tag, BK_TEST_TMP, tag);
  FILE* server = popen(command, "r");
  ENSURE(server != NULL);
  return server;
}

static int finish_server(FILE* server) {
  int status = pclose(server);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static char* read_text(const char* tag, const char* ext) {
  char path[512];
  snprintf(path, sizeof path, "%s/stream_%s.%s", BK_TEST_TMP, tag, ext);
  FILE* f = fopen(path, "rb");
  ENSURE_MSG(f != NULL, "%s missing", path);
  static char text[3][1 << 16];
  static int which = 0;
  char* out = text[which++ % 3];
  size_t n = fread(out, 1, sizeof text[0] - 1, f);
  out[n] = 0;
  fclose(f);
  return out;
}

// The value of "key": in a JSON object, as text (a number or a hex string).
static void json_value(const char* json, const char* key, char* out, size_t size) {
  char pattern[96];
  snprintf(pattern, sizeof pattern, "\"%s\": ", key);
  const char* at = strstr(json, pattern);
  ENSURE_MSG(at, "no %s in %s", key, json);
  at += strlen(pattern);
  if (*at == '"') at++;
  size_t n = 0;
  while (at[n] && at[n] != '"' && at[n] != ',' && at[n] != '}' && n + 1 < size)
    n++;
  memcpy(out, at, n);
  out[n] = 0;
}

static long long json_int(const char* json, const char* key) {
  char text[64];
  json_value(json, key, text, sizeof text);
  return atoll(text);
}

static void test_watchers_follow_the_server(void) {
  unsigned port = port_base();
  // 40 shots over 480 steps, kept to 60 steps a second so that the second
  // watcher joins while they land.
  const char* scene = "--scene wall --shots 40 --steps 480 --volley 400";
  char args[512];
  snprintf(args, sizeof args, "%s --realtime", scene);
  FILE* server = start_server(args, port, "server");
  char watch[512];
  snprintf(watch, sizeof watch,
           "sim %s --watch 127.0.0.1:%u --stream-wait 60000 --json >'%s/stream_first.json' "
           "2>'%s/stream_first.err' & sleep 2; '%s' sim %s --watch 127.0.0.1:%u --stream-wait 60000 --json "
           ">'%s/stream_late.json' 2>'%s/stream_late.err'; wait",
           scene, port, BK_TEST_TMP, BK_TEST_TMP, BK_BREAKABLES_EXE, scene, port, BK_TEST_TMP, BK_TEST_TMP);
  char command[4096];
  snprintf(command, sizeof command, "'%s' %s", BK_BREAKABLES_EXE, watch);
  ENSURE(system(command) == 0);
  ENSURE_MSG(finish_server(server) == 0, "server: %s", read_text("server", "err"));
  const char* served = read_text("server", "json");
  const char* first = read_text("first", "json");
  const char* late = read_text("late", "json");
  ENSURE_MSG(first[0] == '{', "first watcher: %s", read_text("first", "err"));
  ENSURE_MSG(late[0] == '{', "late watcher: %s", read_text("late", "err"));
  char server_hash[32], first_hash[32], late_hash[32];
  json_value(served, "state_hash", server_hash, sizeof server_hash);
  json_value(first, "state_hash", first_hash, sizeof first_hash);
  json_value(late, "state_hash", late_hash, sizeof late_hash);
  ENSURE(strcmp(server_hash, first_hash) == 0 && strcmp(server_hash, late_hash) == 0);
  // Every step checked: the first watcher all 480, the late one from where it joined.
  ENSURE(json_int(served, "shots") == 40 && json_int(served, "bonds_broken") > 100);
  ENSURE(json_int(first, "hash_checks") == 480 && json_int(first, "joined_at_step") == 0);
  long long joined = json_int(late, "joined_at_step");
  ENSURE_MSG(joined > 0 && joined < 480, "late watcher joined at %lld", joined);
  ENSURE(json_int(late, "hash_checks") == 480 - joined);
  ENSURE(json_int(served, "stream_watchers_late") == 1 && json_int(served, "stream_snapshot_bytes") > 0);
  ENSURE(json_int(first, "bonds_broken") == json_int(served, "bonds_broken"));
  ENSURE(json_int(late, "bodies_final") == json_int(served, "bodies_final"));
  // Compact: the journal costs a few bytes per broken bond.
  ENSURE(json_int(served, "stream_journal_bytes") < 64 * json_int(served, "bonds_broken"));
}

static void test_refusals(void) {
  unsigned port = port_base() + 1;
  char args[512];
  // Nobody serving: refused once the wait is over.
  snprintf(args, sizeof args, "sim --scene wall --watch 127.0.0.1:%u --stream-wait 300", port);
  run_result* r = run(args);
  ENSURE(r->status == 1 && count_lines(r->err) == 1 && strstr(r->err, "cannot connect to 127.0.0.1:"));
  // Another scene than the server's.
  FILE* server = start_server("--scene wall --steps 30", port, "other");
  snprintf(args, sizeof args, "sim --scene tower --watch 127.0.0.1:%u --stream-wait 60000", port);
  r = run(args);
  ENSURE_MSG(r->status == 1 && count_lines(r->err) == 1 &&
                 strstr(r->err, "the server's scene is not this one"),
             "%s", r->err);
  finish_server(server);
  // Bad addresses and counts.
  r = run("sim --serve 127.0.0.1");
  ENSURE(r->status == 2 && strstr(r->err, "is not an address: give HOST:PORT"));
  r = run("sim --watch 127.0.0.1:99999");
  ENSURE(r->status == 2 && strstr(r->err, "port must be a number in 1..65535"));
  r = run("sim --watch example:7000");
  ENSURE(r->status == 2 && strstr(r->err, "numeric IPv4 address"));
  r = run("sim --serve 127.0.0.1:7000 --watchers 17");
  ENSURE(r->status == 2 && strstr(r->err, "--watchers"));
}

// A "server" that sends the given bytes, then closes.
static void fake_server(unsigned port, const uint8_t* bytes, size_t size, const char* expected) {
  int listener = socket(AF_INET, SOCK_STREAM, 0);
  int yes = 1;
  setsockopt(listener, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  struct sockaddr_in a = {0};
  a.sin_family = AF_INET;
  a.sin_port = htons((uint16_t)port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ENSURE(bind(listener, (struct sockaddr*)&a, sizeof a) == 0 && listen(listener, 1) == 0);
  char command[1024];
  snprintf(command, sizeof command,
           "'%s' sim --scene wall --watch 127.0.0.1:%u --stream-wait 5000 >/dev/null 2>'%s/stream_fake.err'",
           BK_BREAKABLES_EXE, port, BK_TEST_TMP);
  FILE* watcher = popen(command, "r");
  int client = accept(listener, NULL, NULL);
  ENSURE(client >= 0);
  ENSURE(send(client, bytes, size, 0) == (ssize_t)size);
  close(client);
  close(listener);
  int status = pclose(watcher);
  const char* err = read_text("fake", "err");
  ENSURE_MSG(WIFEXITED(status) && WEXITSTATUS(status) == 1 && count_lines(err) == 1 && strstr(err, expected),
             "expected '%s', got status %d: %s", expected, status, err);
}

static void test_hostile_server(void) {
  unsigned port = port_base() + 2;
  const uint8_t unknown_kind[] = {4, 0, 0, 0, 9, 1, 2, 3, 4};
  fake_server(port, unknown_kind, sizeof unknown_kind, "frame of unknown kind 9");
  const uint8_t huge[] = {0xff, 0xff, 0xff, 0xff, 3};
  fake_server(port, huge, sizeof huge, "is too large");
  const uint8_t cut[] = {40, 0, 0, 0, 3, 1, 2};
  fake_server(port, cut, sizeof cut, "the server closed the connection");
  // A step before any hello: its journal names a cluster that is not there.
  uint8_t step[5 + 20 + 36] = {56, 0, 0, 0, 3};
  step[5] = 1;              // step 1
  step[5 + 16] = 36;        // journal of 36 bytes
  memset(step + 25, 0, 36); // kind 0: not an entry
  fake_server(port, step, sizeof step, "unknown kind 0");
  const uint8_t bad_zstd[] = {8, 0, 0, 0, 3 | 0x80, 100, 0, 0, 0, 1, 2, 3, 4};
  fake_server(port, bad_zstd, sizeof bad_zstd, "malformed compressed frame");
}

int main(void) {
  test_refusals();
  test_hostile_server();
  test_watchers_follow_the_server();
  return 0;
}
