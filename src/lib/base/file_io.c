// Whole-file reading and atomic replacement, shared by the OBJ and mesh-tree
// cache code so both get the same size limit handling and crash safety.
#include <errno.h>
#include <fcntl.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "bk_base.h"

// First buffer size when reading; doubled as needed.
#define FILE_READ_CHUNK ((size_t)1 << 16)

bool bk_file_read(const char* path, uint64_t max_bytes, const char* limit_text, void** data, size_t* size,
                  bk_error* err) {
  *data = NULL;
  *size = 0;
  uint64_t file_size = 0;
  FILE* f = bk_file_open_read(path, &file_size, err);
  if (!f) return false;
  // The size is checked before anything is allocated; the reading still
  // stops at the limit should the file grow meanwhile.
  if (file_size > max_bytes) {
    fclose(f);
    return bk_error_set(err, "%s: file larger than %s, refusing to load", path, limit_text);
  }
  size_t length = 0;
  size_t capacity = file_size + 1 > FILE_READ_CHUNK ? (size_t)file_size + 1 : FILE_READ_CHUNK;
  if (capacity > max_bytes) capacity = (size_t)max_bytes;
  // An allocator that runs out makes this a reported failure, not an abort.
  char* buffer = bk_try_alloc(capacity);
  if (!buffer) {
    fclose(f);
    return bk_error_set_code(err, BK_ERROR_OUT_OF_MEMORY, "%s: out of memory reading %zu bytes", path,
                             capacity);
  }
  for (;;) {
    if (length == capacity) {
      if ((uint64_t)capacity >= max_bytes) {
        if (fgetc(f) == EOF && !ferror(f)) break; // exactly at the limit
        bk_free(buffer);
        fclose(f);
        return bk_error_set(err, "%s: file larger than %s, refusing to load", path, limit_text);
      }
      capacity = (uint64_t)capacity * 2 < max_bytes ? capacity * 2 : (size_t)max_bytes;
      char* bigger = bk_try_realloc(buffer, capacity);
      if (!bigger) {
        bk_free(buffer);
        fclose(f);
        return bk_error_set_code(err, BK_ERROR_OUT_OF_MEMORY, "%s: out of memory reading %zu bytes", path,
                                 capacity);
      }
      buffer = bigger;
    }
    size_t got = fread(buffer + length, 1, capacity - length, f);
    length += got;
    if (got == 0) break;
  }
  if (ferror(f)) {
    int code = errno;
    bk_free(buffer);
    fclose(f);
    return bk_error_set_code(err, BK_ERROR_IO, "%s: read failed: %s", path, strerror(code));
  }
  fclose(f);
  *data = buffer;
  *size = length;
  return true;
}

// The temporary lives beside the target so the final rename stays within one
// file system and is atomic. Its name is unique and it is created with
// O_CREAT | O_EXCL, so a file or symlink already there (planted, or another
// process's temporary) is never opened, followed or truncated: we pick another
// name instead. open() applies the umask (and any default ACL) to 0666, so the
// result has the permissions any new file would get.
enum {
  ATOMIC_NAME_ATTEMPTS = 64,
  ATOMIC_BASE_MAX = 200, // bytes of the target's name kept in the temporary's (NAME_MAX is 255)
  ATOMIC_SUFFIX_CHARS = 12,
};

static atomic_uint_fast64_t atomic_name_counter;

static uint64_t mix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Writes "<dir>/<base, at most ATOMIC_BASE_MAX bytes>.<12 random characters>.tmp" into a fresh buffer.
static char* unique_tmp_path(const char* path) {
  struct timespec now = {0};
  clock_gettime(CLOCK_REALTIME, &now);
  uint64_t bits = mix64((uint64_t)getpid() ^ ((uint64_t)now.tv_nsec << 20) ^ (uint64_t)now.tv_sec ^
                        mix64(atomic_fetch_add(&atomic_name_counter, 1) + (uint64_t)(uintptr_t)&now));
  const char* slash = strrchr(path, '/');
  size_t dir_length = slash ? (size_t)(slash - path) + 1 : 0;
  size_t base_length = strlen(path + dir_length);
  if (base_length > ATOMIC_BASE_MAX) base_length = ATOMIC_BASE_MAX;
  char* tmp = bk_alloc(dir_length + base_length + 1 + ATOMIC_SUFFIX_CHARS + 5);
  memcpy(tmp, path, dir_length + base_length);
  char* p = tmp + dir_length + base_length;
  *p++ = '.';
  for (int i = 0; i < ATOMIC_SUFFIX_CHARS; ++i, bits >>= 5)
    *p++ = "abcdefghijklmnopqrstuvwxyz234567"[bits & 31];
  memcpy(p, ".tmp", 5);
  return tmp;
}

bool bk_file_begin_atomic(const char* path, const bk_atomic_messages* messages, bk_atomic_file* out,
                          bk_error* err) {
  out->stream = NULL;
  out->tmp_path = NULL;
  // A read-only target, a directory or a device is refused before anything
  // is made (a missing directory fails the open below, in the writer's words).
  if (!bk_file_check_target(path, err)) return false;
  int code = EEXIST;
  for (int attempt = 0; attempt < ATOMIC_NAME_ATTEMPTS && code == EEXIST; ++attempt) {
    char* tmp = unique_tmp_path(path);
    int fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    code = fd < 0 ? errno : 0;
    if (fd >= 0) {
      out->stream = fdopen(fd, "wb");
      if (out->stream) {
        out->tmp_path = tmp;
        errno = 0; // so a stream error reported without errno is not blamed on an older failure
        return true;
      }
      code = errno;
      close(fd);
      unlink(tmp);
    }
    bk_free(tmp);
  }
  return bk_error_set_code(err, BK_ERROR_IO, "%s: %s: %s", path, messages->open_failed, strerror(code));
}

bool bk_file_commit_atomic(bk_atomic_file* file, const char* path, const bk_atomic_messages* messages,
                           bk_error* err) {
  FILE* f = file->stream;
  char* tmp = file->tmp_path;
  file->stream = NULL;
  file->tmp_path = NULL;
  // A failed write has already set errno; checking ferror first keeps that
  // cause instead of whatever the flush reports afterwards.
  int code = 0;
  if (ferror(f) || fflush(f) != 0 || ferror(f)) code = errno ? errno : EIO;
  // Sync before the rename so a crash cannot leave a renamed but empty file.
  if (code == 0 && fsync(fileno(f)) != 0) code = errno;
  if (fclose(f) != 0 && code == 0) code = errno ? errno : EIO;
  if (code != 0) {
    unlink(tmp);
    bk_free(tmp);
    return bk_error_set_code(err, BK_ERROR_IO, "%s: %s: %s", path, messages->write_failed, strerror(code));
  }
  if (rename(tmp, path) != 0) {
    code = errno;
    unlink(tmp);
    bk_free(tmp);
    return bk_error_set_code(err, BK_ERROR_IO, "%s: %s: %s", path, messages->rename_failed, strerror(code));
  }
  bk_free(tmp);
  return true;
}

void bk_file_abort_atomic(bk_atomic_file* file) {
  if (file->stream) fclose(file->stream);
  if (file->tmp_path) unlink(file->tmp_path);
  bk_free(file->tmp_path);
  file->stream = NULL;
  file->tmp_path = NULL;
}
