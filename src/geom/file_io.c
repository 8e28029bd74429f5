// Whole-file reading and atomic replacement, shared by the OBJ and mesh-tree
// cache code so both get the same size limit handling and crash safety.
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bk_geom.h"

// First buffer size when reading; doubled as needed.
#define FILE_READ_CHUNK ((size_t)1 << 16)

bool bk_file_read(const char* path, uint64_t max_bytes, const char* limit_text, void** data, size_t* size,
                  bk_error* err) {
  *data = NULL;
  *size = 0;
  FILE* f = fopen(path, "rb");
  if (!f) return bk_error_set(err, "%s: cannot open: %s", path, strerror(errno));
  // Read in chunks rather than trusting a size from fseek: works for pipes too.
  size_t length = 0, capacity = FILE_READ_CHUNK;
  char* buffer = bk_alloc(capacity);
  for (;;) {
    if (length == capacity) {
      if ((uint64_t)capacity >= max_bytes) {
        if (fgetc(f) == EOF && !ferror(f)) break; // exactly at the limit
        free(buffer);
        fclose(f);
        return bk_error_set(err, "%s: file larger than %s, refusing to load", path, limit_text);
      }
      capacity *= 2;
      buffer = bk_realloc(buffer, capacity);
    }
    size_t got = fread(buffer + length, 1, capacity - length, f);
    length += got;
    if (got == 0) break;
  }
  if (ferror(f)) {
    int code = errno;
    free(buffer);
    fclose(f);
    return bk_error_set(err, "%s: read failed: %s", path, strerror(code));
  }
  fclose(f);
  *data = buffer;
  *size = length;
  return true;
}

// The temporary lives beside the target so the final rename stays within one
// file system and is atomic.
static char* tmp_path(const char* path) {
  size_t path_length = strlen(path);
  char* tmp = bk_alloc(path_length + 5);
  memcpy(tmp, path, path_length);
  memcpy(tmp + path_length, ".tmp", 5);
  return tmp;
}

FILE* bk_file_begin_atomic(const char* path, const bk_atomic_messages* messages, bk_error* err) {
  char* tmp = tmp_path(path);
  FILE* f = fopen(tmp, "wb");
  int code = errno;
  free(tmp);
  if (!f) {
    bk_error_set(err, "%s: %s: %s", path, messages->open_failed, strerror(code));
    return NULL;
  }
  errno = 0; // so a stream error reported without errno is not blamed on an older failure
  return f;
}

bool bk_file_commit_atomic(FILE* f, const char* path, const bk_atomic_messages* messages, bk_error* err) {
  // A failed write has already set errno; checking ferror first keeps that
  // cause instead of whatever the flush reports afterwards.
  int code = 0;
  if (ferror(f) || fflush(f) != 0 || ferror(f)) code = errno ? errno : EIO;
  // Sync before the rename so a crash cannot leave a renamed but empty file.
  if (code == 0 && fsync(fileno(f)) != 0) code = errno;
  if (fclose(f) != 0 && code == 0) code = errno ? errno : EIO;
  char* tmp = tmp_path(path);
  if (code != 0) {
    remove(tmp);
    free(tmp);
    return bk_error_set(err, "%s: %s: %s", path, messages->write_failed, strerror(code));
  }
  if (rename(tmp, path) != 0) {
    code = errno;
    remove(tmp);
    free(tmp);
    return bk_error_set(err, "%s: %s: %s", path, messages->rename_failed, strerror(code));
  }
  free(tmp);
  return true;
}
