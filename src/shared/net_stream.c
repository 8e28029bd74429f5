// The destruction stream's sockets and frames (see net_stream.h): plain
// POSIX TCP, Nagle off (a step's frame goes out at once), zstd for step
// frames when it makes them smaller.
#include "net_stream.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>
#include <zstd.h>

#include "app.h"

uint64_t stream_u64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i)
    v |= (uint64_t)p[i] << (8 * i);
  return v;
}

void stream_put_u64(uint8_t* p, uint64_t v) {
  for (int i = 0; i < 8; ++i)
    p[i] = (uint8_t)(v >> (8 * i));
}

static uint32_t get_u32(const uint8_t* p) {
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

void stream_put_u32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i)
    p[i] = (uint8_t)(v >> (8 * i));
}

bool stream_parse_address(const char* text, char host[64], uint16_t* port, bk_error* err) {
  const char* colon = text ? strrchr(text, ':') : NULL;
  if (!colon || colon == text || (size_t)(colon - text) >= 64)
    return bk_error_set(err, "'%s' is not an address: give HOST:PORT, e.g. 127.0.0.1:7000", text ? text : "");
  char* end = NULL;
  errno = 0;
  unsigned long value = strtoul(colon + 1, &end, 10);
  if (errno || !colon[1] || *end || value < 1 || value > 65535)
    return bk_error_set(err, "'%s': port must be a number in 1..65535", text);
  memcpy(host, text, (size_t)(colon - text));
  host[colon - text] = '\0';
  if (strcmp(host, "localhost") == 0) strcpy(host, "127.0.0.1");
  struct in_addr address;
  if (inet_pton(AF_INET, host, &address) != 1)
    return bk_error_set(err, "'%s': host must be a numeric IPv4 address or localhost", text);
  *port = (uint16_t)value;
  return true;
}

static struct sockaddr_in socket_address(const char* host, uint16_t port) {
  struct sockaddr_in a;
  memset(&a, 0, sizeof a);
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  inet_pton(AF_INET, host, &a.sin_addr);
  return a;
}

int stream_listen(const char* host, uint16_t port, bk_error* err) {
  // A watcher that leaves mid-send must not kill the server with SIGPIPE.
  signal(SIGPIPE, SIG_IGN);
  int s = socket(AF_INET, SOCK_STREAM, 0);
  if (s < 0) return bk_error_set(err, "cannot open a socket: %s", strerror(errno)), -1;
  int yes = 1;
  setsockopt(s, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  struct sockaddr_in a = socket_address(host, port);
  if (bind(s, (struct sockaddr*)&a, sizeof a) != 0 || listen(s, 16) != 0) {
    bk_error_set(err, "cannot listen on %s:%u: %s", host, port, strerror(errno));
    close(s);
    return -1;
  }
  return s;
}

static void set_nodelay(int s) {
  int yes = 1;
  setsockopt(s, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
}

int stream_accept(int listener, int timeout_ms) {
  struct pollfd p = {listener, POLLIN, 0};
  if (poll(&p, 1, timeout_ms) <= 0) return -1;
  int s = accept(listener, NULL, NULL);
  if (s >= 0) set_nodelay(s);
  return s;
}

static double now_ms(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec * 1000.0 + (double)t.tv_nsec / 1e6;
}

int stream_connect(const char* host, uint16_t port, int timeout_ms, bk_error* err) {
  signal(SIGPIPE, SIG_IGN);
  double until = now_ms() + timeout_ms;
  // The server may not be listening yet: try again until the time is up.
  for (;;) {
    int s = socket(AF_INET, SOCK_STREAM, 0);
    if (s < 0) return bk_error_set(err, "cannot open a socket: %s", strerror(errno)), -1;
    struct sockaddr_in a = socket_address(host, port);
    if (connect(s, (struct sockaddr*)&a, sizeof a) == 0) {
      set_nodelay(s);
      return s;
    }
    int why = errno;
    close(s);
    if (now_ms() >= until) {
      bk_error_set(err, "cannot connect to %s:%u within %d ms: %s", host, port, timeout_ms, strerror(why));
      return -1;
    }
    struct timespec pause = {0, 50 * 1000 * 1000};
    nanosleep(&pause, NULL);
  }
}

void stream_close(int s) {
  if (s >= 0) close(s);
}

static bool send_all(int s, const void* data, size_t size) {
  const uint8_t* p = data;
  while (size) {
    ssize_t n = send(s, p, size, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    size -= (size_t)n;
  }
  return true;
}

uint8_t* stream_pack(uint8_t kind, const void* a, size_t a_size, const void* b, size_t b_size, size_t* size) {
  *size = 0;
  size_t plain = a_size + b_size;
  if (plain > STREAM_FRAME_MAX) return NULL;
  // The frame's header first, then the payload; a step's payload is
  // replaced by its compression when that is smaller.
  uint8_t* frame = bk_alloc(5 + plain);
  if (a_size) memcpy(frame + 5, a, a_size);
  if (b_size) memcpy(frame + 5 + a_size, b, b_size);
  size_t body = plain;
  if (kind == STREAM_STEP && plain > 64) {
    // Level 1: a step must not wait for its compression.
    size_t bound = ZSTD_compressBound(plain);
    uint8_t* packed = bk_alloc(5 + 4 + bound);
    stream_put_u32(packed + 5, (uint32_t)plain);
    size_t n = ZSTD_compress(packed + 9, bound, frame + 5, plain, 1);
    if (!ZSTD_isError(n) && n + 4 < plain) {
      bk_free(frame);
      frame = packed;
      body = n + 4;
      kind |= STREAM_COMPRESSED;
    } else {
      bk_free(packed);
    }
  }
  stream_put_u32(frame, (uint32_t)body);
  frame[4] = kind;
  *size = 5 + body;
  return frame;
}

bool stream_send_packed(int s, const uint8_t* frame, size_t size) {
  return frame && send_all(s, frame, size);
}

size_t stream_send(int s, uint8_t kind, const void* a, size_t a_size, const void* b, size_t b_size) {
  size_t size = 0;
  uint8_t* frame = stream_pack(kind, a, a_size, b, b_size, &size);
  bool ok = stream_send_packed(s, frame, size);
  bk_free(frame);
  return ok ? size : 0;
}

// Reads exactly size bytes, waiting up to timeout_ms for each part.
static bool receive_all(int s, void* data, size_t size, int timeout_ms, bk_error* err) {
  uint8_t* p = data;
  while (size) {
    struct pollfd pf = {s, POLLIN, 0};
    int ready = poll(&pf, 1, timeout_ms);
    if (ready == 0) return bk_error_set(err, "stream: nothing from the server for %d ms", timeout_ms);
    if (ready < 0 && errno == EINTR) continue;
    ssize_t n = recv(s, p, size, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n == 0) return bk_error_set(err, "stream: the server closed the connection");
    if (n < 0) return bk_error_set(err, "stream: %s", strerror(errno));
    p += n;
    size -= (size_t)n;
  }
  return true;
}

bool stream_receive(int s, int timeout_ms, stream_frame* out, bk_error* err) {
  memset(out, 0, sizeof *out);
  uint8_t header[5];
  if (!receive_all(s, header, sizeof header, timeout_ms, err)) return false;
  uint32_t size = get_u32(header);
  uint8_t kind = header[4];
  uint8_t base = kind & (uint8_t)~STREAM_COMPRESSED;
  if (base < STREAM_HELLO || base > STREAM_END || (kind & STREAM_COMPRESSED && base != STREAM_STEP))
    return bk_error_set(err, "stream: frame of unknown kind %u", kind);
  if (size > STREAM_FRAME_MAX) return bk_error_set(err, "stream: frame of %u bytes is too large", size);
  uint8_t* data = bk_alloc((size_t)size + 1);
  if (!receive_all(s, data, size, timeout_ms, err)) {
    bk_free(data);
    return false;
  }
  out->wire_size = sizeof header + size;
  if (kind & STREAM_COMPRESSED) {
    uint32_t plain = size >= 4 ? get_u32(data) : 0;
    unsigned long long declared = size >= 4 ? ZSTD_getFrameContentSize(data + 4, size - 4) : 0;
    if (size < 4 || plain > STREAM_FRAME_MAX || declared != plain) {
      bk_free(data);
      return bk_error_set(err, "stream: malformed compressed frame");
    }
    uint8_t* unpacked = bk_alloc((size_t)plain + 1);
    size_t n = ZSTD_decompress(unpacked, plain, data + 4, size - 4);
    bk_free(data);
    if (ZSTD_isError(n) || n != plain) {
      bk_free(unpacked);
      return bk_error_set(err, "stream: compressed frame does not decompress");
    }
    data = unpacked;
    size = plain;
  }
  out->kind = base;
  out->data = data;
  out->size = size;
  return true;
}

void stream_frame_free(stream_frame* f) {
  bk_free(f->data);
  memset(f, 0, sizeof *f);
}

bool stream_step_read(const stream_frame* f, stream_step* out, bk_error* err) {
  memset(out, 0, sizeof *out);
  if (f->kind != STREAM_STEP || f->size < 20) return bk_error_set(err, "stream: malformed step frame");
  out->step = stream_u64(f->data);
  out->state_hash = stream_u64(f->data + 8);
  uint32_t journal = get_u32(f->data + 16);
  if (journal > f->size - 20)
    return bk_error_set(err, "stream: step %llu: journal past the frame's end",
                        (unsigned long long)out->step);
  out->journal = f->data + 20;
  out->journal_size = journal;
  out->motion = f->data + 20 + journal;
  out->motion_size = f->size - 20 - journal;
  return true;
}
