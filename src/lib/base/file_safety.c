// What every reader and writer checks about a path before it touches it:
// readers open regular files only (a FIFO would block the open forever, a
// device could do anything), writers refuse a target that is a directory, not
// a regular file or read-only, and callers can tell whether two paths name the
// same file.
#define _XOPEN_SOURCE 700 // realpath
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bk_base.h"

// Why a path that exists cannot be read as a file; NULL when it is a regular file.
static const char* not_regular_reason(const struct stat* st) {
  if (S_ISREG(st->st_mode)) return NULL;
  return S_ISDIR(st->st_mode) ? "is a directory" : "is not a regular file";
}

FILE* bk_file_open_read(const char* path, uint64_t* size, bk_error* err) {
  if (size) *size = 0;
  // stat first so that a FIFO or a device is never opened at all; then the
  // opened descriptor is checked again, in case the path changed in between.
  struct stat st = {0};
  if (stat(path, &st) != 0) return bk_error_set(err, "%s: cannot open: %s", path, strerror(errno)), NULL;
  const char* reason = not_regular_reason(&st);
  if (reason) return bk_error_set(err, "%s: %s", path, reason), NULL;
  // O_NONBLOCK: should a FIFO have been put there since, the open still returns.
  int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) return bk_error_set(err, "%s: cannot open: %s", path, strerror(errno)), NULL;
  reason = fstat(fd, &st) != 0 ? strerror(errno) : not_regular_reason(&st);
  int flags = reason ? 0 : fcntl(fd, F_GETFL);
  if (!reason && (flags < 0 || fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) != 0)) reason = strerror(errno);
  FILE* f = reason ? NULL : fdopen(fd, "rb");
  if (!f) {
    if (!reason) reason = strerror(errno);
    close(fd);
    return bk_error_set(err, "%s: %s", path, reason), NULL;
  }
  if (size) *size = (uint64_t)st.st_size;
  return f;
}

bool bk_file_check_read(const char* path, bk_error* err) {
  FILE* f = bk_file_open_read(path, NULL, err);
  if (f) fclose(f);
  return f != NULL;
}

// Whether the mode bits let this process write: the bits of its class (owner,
// group, others). Root may write anything, so for root a file without any
// write bit counts as one the user marked as not to be replaced.
static bool mode_allows_write(const struct stat* st) {
  uid_t uid = geteuid();
  if (uid == 0) return (st->st_mode & (S_IWUSR | S_IWGRP | S_IWOTH)) != 0;
  if (st->st_uid == uid) return (st->st_mode & S_IWUSR) != 0;
  bool in_group = st->st_gid == getegid();
  gid_t groups[256];
  int count = in_group ? 0 : getgroups(256, groups);
  for (int i = 0; i < count && !in_group; ++i)
    in_group = groups[i] == st->st_gid;
  return (st->st_mode & (in_group ? S_IWGRP : S_IWOTH)) != 0;
}

// The directory part of path ("." when it has none, "/" for "/x").
static void directory_of(const char* path, char* out, size_t size) {
  const char* slash = strrchr(path, '/');
  if (!slash)
    snprintf(out, size, ".");
  else if (slash == path)
    snprintf(out, size, "/");
  else
    snprintf(out, size, "%.*s", (int)(slash - path), path);
}

bool bk_file_check_target(const char* path, bk_error* err) {
  if (!path[0]) return bk_error_set(err, "an output file name is empty");
  if (path[strlen(path) - 1] == '/') return bk_error_set(err, "%s: is a directory", path);
  struct stat st = {0};
  if (stat(path, &st) == 0) {
    const char* reason = not_regular_reason(&st);
    if (reason) return bk_error_set(err, "%s: %s; not replaced", path, reason);
    if (!mode_allows_write(&st))
      return bk_error_set(err, "%s: is read-only (mode %04o); not replaced", path,
                          (unsigned)(st.st_mode & 07777));
  }
  return true;
}

bool bk_file_check_write(const char* path, bk_error* err) {
  if (!bk_file_check_target(path, err)) return false;
  struct stat st = {0};
  if (stat(path, &st) != 0 && errno != ENOENT)
    return bk_error_set(err, "%s: cannot write: %s", path, strerror(errno));
  char dir[PATH_MAX];
  directory_of(path, dir, sizeof dir);
  if (stat(dir, &st) != 0)
    return bk_error_set(err, "%s: cannot write: directory '%s': %s", path, dir, strerror(errno));
  if (!S_ISDIR(st.st_mode)) return bk_error_set(err, "%s: cannot write: '%s' is not a directory", path, dir);
  // The file is made beside its target and renamed: the directory must take new entries.
  if (!mode_allows_write(&st) || (st.st_mode & (S_IXUSR | S_IXGRP | S_IXOTH)) == 0)
    return bk_error_set(err, "%s: cannot write in directory '%s' (mode %04o): %s", path, dir,
                        (unsigned)(st.st_mode & 07777), strerror(EACCES));
  return true;
}

// An absolute, normalised name of the directory entry `path` (its directory
// resolved, symlinks included, when it exists; "." and ".." folded otherwise).
static void entry_name(const char* path, char* out, size_t size) {
  char dir[PATH_MAX], resolved[PATH_MAX];
  directory_of(path, dir, sizeof dir);
  const char* slash = strrchr(path, '/');
  const char* base = slash ? slash + 1 : path;
  char joined[2 * PATH_MAX + 2];
  if (realpath(dir, resolved)) {
    snprintf(joined, sizeof joined, "%s/%s", resolved, base);
  } else {
    char cwd[PATH_MAX] = "";
    if (path[0] != '/' && !getcwd(cwd, sizeof cwd)) cwd[0] = 0;
    snprintf(joined, sizeof joined, "%s/%s", cwd, path);
  }
  // Fold "//", "/./" and "/x/.." lexically (what is left after realpath, or all of it).
  size_t used = 0;
  const char* p = joined;
  while (*p && used + 1 < size) {
    while (*p == '/')
      ++p;
    const char* end = strchr(p, '/');
    size_t length = end ? (size_t)(end - p) : strlen(p);
    if (length == 0 || (length == 1 && p[0] == '.')) {
      // nothing to add
    } else if (length == 2 && p[0] == '.' && p[1] == '.') {
      while (used > 0 && out[used - 1] != '/')
        --used;
      if (used > 0) --used;
    } else if (used + 1 + length < size) {
      out[used++] = '/';
      memcpy(out + used, p, length);
      used += length;
    }
    p += length;
  }
  if (used == 0) out[used++] = '/';
  out[used] = 0;
}

bool bk_file_same(const char* a, const char* b) {
  struct stat sa = {0}, sb = {0};
  if (stat(a, &sa) == 0 && stat(b, &sb) == 0) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  char na[PATH_MAX], nb[PATH_MAX];
  entry_name(a, na, sizeof na);
  entry_name(b, nb, sizeof nb);
  return strcmp(na, nb) == 0;
}
