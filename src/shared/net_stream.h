// The destruction stream of `sim --serve/--watch` and `breakables
// serve/watch`: a server-authoritative world sends each step's runtime
// journal and the motion of its moving bodies (bk_world_journal,
// bk_world_motion) to watching clients over TCP; a client first gets the
// world's saved state (bk_world_save_state), so it may join at any step.
//
// A frame: u32 payload size | u8 kind | payload (little endian):
//   hello     u32 protocol | u64 step | u64 runtime state hash (the server's now)
//   snapshot  the world's saved state (every client, as it joins)
//   step      u64 step | u64 runtime state hash after it | u32 journal size,
//             journal | motion (the rest)
//   end       u64 step | u64 runtime state hash | u64 world hash
// A step's payload is compressed with zstd when that makes it smaller
// (kind | 0x80; the payload then starts with its u32 size uncompressed).
#pragma once

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <breakables/base.h>

enum {
  STREAM_PROTOCOL = 1,
  STREAM_HELLO = 1,
  STREAM_SNAPSHOT = 2,
  STREAM_STEP = 3,
  STREAM_END = 4,
  STREAM_COMPRESSED = 0x80,
};

/// Frames larger than this are refused (a snapshot of a refined scene is
/// some MB; anything near this is not a stream of ours).
#define STREAM_FRAME_MAX ((uint32_t)1 << 30)

/// A received frame: its kind (compression undone) and payload (owned).
typedef struct stream_frame {
  uint8_t kind;
  uint8_t* data;
  size_t size;
  size_t wire_size; ///< bytes it took on the wire, header included
} stream_frame;

/// A step frame's fields (pointers into the frame's payload).
typedef struct stream_step {
  uint64_t step, state_hash;
  const uint8_t* journal;
  size_t journal_size;
  const uint8_t* motion;
  size_t motion_size;
} stream_step;

/// "HOST:PORT" (a numeric IPv4 address or "localhost"; port 1..65535).
bool stream_parse_address(const char* text, char host[64], uint16_t* port, bk_error* err);
/// A listening socket on host:port, or -1 with err set.
int stream_listen(const char* host, uint16_t port, bk_error* err);
/// A client that connected, waiting up to timeout_ms (0: a look), or -1.
int stream_accept(int listener, int timeout_ms);
/// Connects to host:port, retrying until timeout_ms has passed; -1 with err set.
int stream_connect(const char* host, uint16_t port, int timeout_ms, bk_error* err);
void stream_close(int socket);
/// Sends one frame whose payload is a then b (either may be empty); a step
/// frame is compressed when that pays. Returns the bytes sent (0: the peer
/// is gone).
size_t stream_send(int socket, uint8_t kind, const void* a, size_t a_size, const void* b, size_t b_size);
/// One frame's bytes, header included (a step frame compressed when that
/// pays), to send to every watcher as they are (bk_free them); NULL when
/// the payload is too large.
uint8_t* stream_pack(uint8_t kind, const void* a, size_t a_size, const void* b, size_t b_size, size_t* size);
/// Sends packed bytes whole; false when the peer is gone.
bool stream_send_packed(int socket, const uint8_t* frame, size_t size);
/// Receives one frame, waiting up to timeout_ms for it to start; false with
/// err set on a timeout, a closed connection or a malformed frame.
bool stream_receive(int socket, int timeout_ms, stream_frame* out, bk_error* err);
void stream_frame_free(stream_frame* frame);
/// Reads a step frame's fields; false with err set when malformed.
bool stream_step_read(const stream_frame* frame, stream_step* out, bk_error* err);
/// Little-endian u64 at p.
uint64_t stream_u64(const uint8_t* p);
/// Writes v little endian at p.
void stream_put_u64(uint8_t* p, uint64_t v);
void stream_put_u32(uint8_t* p, uint32_t v);
