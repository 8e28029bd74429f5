// The file system assimp reads through: every file it opens (the model, a
// .gltf's buffers and images, a Collada's textures) goes through
// bk_file_open_read, so a FIFO or a device named by a model is refused at
// once instead of blocking the import forever, and nothing is ever written.
#include <assimp/cfileio.h>
#include <assimp/types.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_geom.h"
#include "model_import.h"

// The first file refused for what it is (imports hold the import lock, so
// one at a time), for the message when assimp then fails.
static bk_error refused;

static FILE* stream_of(struct aiFile* file) { return (FILE*)(void*)file->UserData; }

static size_t read_proc(struct aiFile* file, char* buffer, size_t size, size_t count) {
  return fread(buffer, size, count, stream_of(file));
}

static size_t write_proc(struct aiFile* file, const char* buffer, size_t size, size_t count) {
  (void)file, (void)buffer, (void)size, (void)count;
  return 0;
}

static size_t tell_proc(struct aiFile* file) {
  long at = ftell(stream_of(file));
  return at < 0 ? 0 : (size_t)at;
}

static size_t size_proc(struct aiFile* file) {
  FILE* f = stream_of(file);
  long at = ftell(f);
  if (at < 0 || fseek(f, 0, SEEK_END) != 0) return 0;
  long end = ftell(f);
  fseek(f, at, SEEK_SET);
  return end < 0 ? 0 : (size_t)end;
}

static enum aiReturn seek_proc(struct aiFile* file, size_t offset, enum aiOrigin origin) {
  int whence = origin == aiOrigin_SET ? SEEK_SET : origin == aiOrigin_CUR ? SEEK_CUR : SEEK_END;
  // assimp passes a negative offset from the end or the current position as a size_t.
  long signed_offset = (long)(ptrdiff_t)offset;
  return fseek(stream_of(file), signed_offset, whence) == 0 ? aiReturn_SUCCESS : aiReturn_FAILURE;
}

static void flush_proc(struct aiFile* file) { (void)file; }

static struct aiFile* open_proc(struct aiFileIO* io, const char* path, const char* mode) {
  (void)io;
  if (!path || !mode || strchr(mode, 'w') || strchr(mode, 'a') || strchr(mode, '+')) return NULL;
  bk_error err = {{0}};
  FILE* f = bk_file_open_read(path, NULL, &err);
  if (!f) {
    // A file that is missing is assimp's to report (it probes for some);
    // one that is there but is no regular file is ours.
    if (!refused.message[0] &&
        (strstr(err.message, ": is not a regular file") || strstr(err.message, ": is a directory")))
      refused = err;
    return NULL;
  }
  struct aiFile* file = bk_calloc(1, sizeof *file);
  file->ReadProc = read_proc;
  file->WriteProc = write_proc;
  file->TellProc = tell_proc;
  file->FileSizeProc = size_proc;
  file->SeekProc = seek_proc;
  file->FlushProc = flush_proc;
  file->UserData = (aiUserData)(void*)f;
  return file;
}

static void close_proc(struct aiFileIO* io, struct aiFile* file) {
  (void)io;
  if (!file) return;
  fclose(stream_of(file));
  bk_free(file);
}

struct aiFileIO* bk_import_file_io(void) {
  static struct aiFileIO io = {open_proc, close_proc, NULL};
  refused.message[0] = 0;
  return &io;
}

bool bk_import_file_io_refused(const char* name, bk_error* err) {
  if (!refused.message[0]) return false;
  bk_error_set(err, "%s (read by %s)", refused.message, name);
  refused.message[0] = 0;
  return true;
}
