// Writing .mtree cache files safely: the temporary beside the target is
// created exclusively under a unique name, so a symlink planted there is never
// followed, concurrent writers never tear each other's file, a failed save
// leaves the existing file byte for byte, and the result has the permissions
// of any new file.
#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bk_fracture.h"
#include "bk_geom.h"
#include "ensure.h"

#define DIR_PATH BK_TEST_TMP "/cache_write"
#define TREE_PATH DIR_PATH "/t.mtree"
#define VICTIM_PATH BK_TEST_TMP "/cache_write_victim.txt"
#define VICTIM_TEXT "not to be overwritten\n"

enum { WRITERS = 4, SAVES_PER_WRITER = 30 };

static void build_tree(uint32_t pieces, uint64_t seed, bk_mesh_tree* tree) {
  bk_mesh cube = {0};
  bk_shape_build(BK_SHAPE_CUBE, &cube);
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = pieces;
  desc.seed = seed;
  desc.jitter = 0.0;
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_build(&cube, &desc, tree, &err), "%s", err.message);
  bk_mesh_free(&cube);
}

// Returns the file's bytes (NULL if it cannot be opened); *size gets the length.
static uint8_t* read_bytes(const char* path, size_t* size) {
  *size = 0;
  FILE* f = fopen(path, "rb");
  if (!f) return NULL;
  size_t capacity = 1 << 16, length = 0;
  uint8_t* data = malloc(capacity);
  ENSURE(data != NULL);
  for (size_t got = 1; got > 0; length += got) {
    if (length == capacity) {
      capacity *= 2;
      data = realloc(data, capacity);
      ENSURE(data != NULL);
    }
    got = fread(data + length, 1, capacity - length, f);
  }
  fclose(f);
  *size = length;
  return data;
}

static void write_text(const char* path, const char* text) {
  FILE* f = fopen(path, "wb");
  ENSURE_MSG(f != NULL, "cannot create %s", path);
  fputs(text, f);
  ENSURE(fclose(f) == 0);
}

static bool same_bytes(const char* path, const uint8_t* expected, size_t expected_size) {
  size_t size = 0;
  uint8_t* data = read_bytes(path, &size);
  bool same = data && size == expected_size && memcmp(data, expected, size) == 0;
  free(data);
  return same;
}

// Removes every entry of the test directory (files and symlinks, one level of subdirectories).
static void clear_dir(void) {
  mkdir(DIR_PATH, 0755);
  chmod(DIR_PATH, 0755);
  DIR* d = opendir(DIR_PATH);
  ENSURE(d != NULL);
  for (struct dirent* e = readdir(d); e; e = readdir(d)) {
    if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
    char path[1024] = {0};
    snprintf(path, sizeof path, "%s/%s", DIR_PATH, e->d_name);
    if (unlink(path) != 0) {
      char inner[1100] = {0};
      snprintf(inner, sizeof inner, "%s/keep", path);
      unlink(inner);
      ENSURE_MSG(rmdir(path) == 0, "cannot remove %s: %s", path, strerror(errno));
    }
  }
  closedir(d);
}

// Entries in the test directory other than "." and "..".
static int dir_entries(void) {
  DIR* d = opendir(DIR_PATH);
  ENSURE(d != NULL);
  int count = 0;
  for (struct dirent* e = readdir(d); e; e = readdir(d))
    count += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
  closedir(d);
  return count;
}

static void save_ok(const bk_mesh_tree* tree, const char* path) {
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_save(tree, path, &err), "%s", err.message);
}

// The bytes a save of `tree` produces (saving is deterministic).
static uint8_t* reference_bytes(const bk_mesh_tree* tree, size_t* size) {
  const char* path = BK_TEST_TMP "/cache_write_reference.mtree";
  save_ok(tree, path);
  uint8_t* data = read_bytes(path, size);
  ENSURE(data != NULL);
  remove(path);
  return data;
}

// Symlinks at the old fixed temporary name and at other names a writer might
// pick: a save must neither write through them nor replace them.
static void test_symlinks_not_followed(void) {
  clear_dir();
  write_text(VICTIM_PATH, VICTIM_TEXT);
  char names[8][256] = {{0}};
  int n = 0;
  snprintf(names[n++], sizeof names[0], "%s.tmp", TREE_PATH);
  snprintf(names[n++], sizeof names[0], "%s.tmp.%d", TREE_PATH, (int)getpid());
  snprintf(names[n++], sizeof names[0], "%s.%d", TREE_PATH, (int)getpid());
  snprintf(names[n++], sizeof names[0], "%s.%d.tmp", TREE_PATH, (int)getpid());
  snprintf(names[n++], sizeof names[0], "%s~", TREE_PATH);
  snprintf(names[n++], sizeof names[0], "%s.new", TREE_PATH);
  snprintf(names[n++], sizeof names[0], "%s.part", TREE_PATH);
  // A dangling link: following it would create the file it names.
  snprintf(names[n++], sizeof names[0], "%s.tmp.0", TREE_PATH);
  for (int i = 0; i < n; ++i)
    ENSURE(symlink(i == n - 1 ? DIR_PATH "/created_through_link" : VICTIM_PATH, names[i]) == 0);

  bk_mesh_tree tree = {0};
  build_tree(32, 5, &tree);
  size_t expected_size = 0;
  uint8_t* expected = reference_bytes(&tree, &expected_size);
  for (int round = 0; round < 10; ++round) // the first creates the file, the rest replace it
    save_ok(&tree, TREE_PATH);

  ENSURE_MSG(same_bytes(VICTIM_PATH, (const uint8_t*)VICTIM_TEXT, strlen(VICTIM_TEXT)),
             "the symlinks' target was overwritten");
  struct stat st = {0};
  ENSURE_MSG(lstat(DIR_PATH "/created_through_link", &st) != 0, "a dangling symlink was followed");
  for (int i = 0; i < n; ++i)
    ENSURE_MSG(lstat(names[i], &st) == 0 && S_ISLNK(st.st_mode), "%s is no longer a symlink", names[i]);
  ENSURE_MSG(lstat(TREE_PATH, &st) == 0 && S_ISREG(st.st_mode), "the cache file is not a regular file");
  ENSURE(same_bytes(TREE_PATH, expected, expected_size));
  ENSURE_MSG(dir_entries() == n + 1, "%d entries: temporary files were left behind", dir_entries());
  free(expected);
  bk_mesh_tree_free(&tree);
  remove(VICTIM_PATH);
}

// Saves in a child whose file size limit is too small for the file: the
// write fails half-way (EFBIG). Returns true if the save failed cleanly.
static bool save_with_size_limit(const bk_mesh_tree* tree, rlim_t limit) {
  fflush(NULL);
  pid_t child = fork();
  ENSURE(child >= 0);
  if (child == 0) {
    signal(SIGXFSZ, SIG_IGN); // report EFBIG instead of killing the process
    struct rlimit rl = {limit, limit};
    if (setrlimit(RLIMIT_FSIZE, &rl) != 0) _exit(3);
    bk_error err = {{0}};
    bool saved = bk_mesh_tree_save(tree, TREE_PATH, &err);
    _exit(!saved && strstr(err.message, TREE_PATH) && strstr(err.message, "cannot write") ? 0 : 1);
  }
  int status = 0;
  ENSURE(waitpid(child, &status, 0) == child);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

static void test_failed_save_keeps_file(void) {
  clear_dir();
  bk_mesh_tree old_tree = {0}, new_tree = {0};
  build_tree(16, 1, &old_tree);
  build_tree(256, 2, &new_tree);
  save_ok(&old_tree, TREE_PATH);
  size_t old_size = 0;
  uint8_t* old_bytes = read_bytes(TREE_PATH, &old_size);
  ENSURE(old_bytes != NULL);

  // A write that fails half-way (the new file is larger than the limit).
  ENSURE_MSG(save_with_size_limit(&new_tree, (rlim_t)old_size + 4096),
             "a save over the size limit succeeded");
  ENSURE_MSG(same_bytes(TREE_PATH, old_bytes, old_size), "a failed write changed the existing file");
  ENSURE_MSG(dir_entries() == 1, "a failed write left its temporary behind");

  // The target is a directory: the rename fails; the directory stays as it was.
  const char* dir_target = DIR_PATH "/is_a_dir.mtree";
  ENSURE(mkdir(dir_target, 0755) == 0);
  write_text(DIR_PATH "/is_a_dir.mtree/keep", "x");
  bk_error err = {{0}};
  ENSURE(!bk_mesh_tree_save(&new_tree, dir_target, &err));
  ENSURE_MSG(strstr(err.message, dir_target) != NULL, "%s", err.message);
  ENSURE(same_bytes(DIR_PATH "/is_a_dir.mtree/keep", (const uint8_t*)"x", 1));
  ENSURE_MSG(dir_entries() == 2, "a failed rename left its temporary behind");

  // A directory we may not write to (root may write anywhere, so only as a normal user).
  if (geteuid() != 0) {
    ENSURE(chmod(DIR_PATH, 0555) == 0);
    ENSURE(!bk_mesh_tree_save(&new_tree, TREE_PATH, &err));
    ENSURE_MSG(strstr(err.message, "Permission denied") != NULL, "%s", err.message);
    ENSURE(chmod(DIR_PATH, 0755) == 0);
    ENSURE(same_bytes(TREE_PATH, old_bytes, old_size));
  }
  free(old_bytes);
  bk_mesh_tree_free(&old_tree);
  bk_mesh_tree_free(&new_tree);
}

// The file gets 0666 less the umask, like any new file (not mkstemp's 0600).
static void test_permissions(void) {
  clear_dir();
  bk_mesh_tree tree = {0};
  build_tree(8, 1, &tree);
  mode_t old_mask = umask(022);
  save_ok(&tree, TREE_PATH);
  struct stat st = {0};
  ENSURE(stat(TREE_PATH, &st) == 0);
  ENSURE_MSG((st.st_mode & 0777) == 0644, "mode %o with umask 022", (unsigned)(st.st_mode & 0777));
  umask(077);
  save_ok(&tree, TREE_PATH); // replaces the file: the new one gets the current umask
  ENSURE(stat(TREE_PATH, &st) == 0);
  ENSURE_MSG((st.st_mode & 0777) == 0600, "mode %o with umask 077", (unsigned)(st.st_mode & 0777));
  umask(old_mask);
  bk_mesh_tree_free(&tree);
}

// A file name as long as the file system allows (255 bytes) is still saved:
// the temporary's name must fit too.
static void test_longest_name(void) {
  clear_dir();
  char path[512] = {0};
  int length = snprintf(path, sizeof path, "%s/", DIR_PATH);
  memset(path + length, 'n', 255 - 6);
  memcpy(path + length + 255 - 6, ".mtree", 7);
  bk_mesh_tree tree = {0}, loaded = {0};
  build_tree(8, 1, &tree);
  save_ok(&tree, path);
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_load(path, &loaded, &err), "%s", err.message);
  ENSURE(loaded.leaf_count == tree.leaf_count);
  ENSURE(dir_entries() == 1);
  bk_mesh_tree_free(&loaded);
  bk_mesh_tree_free(&tree);
}

// Several processes fill the same cache entry at once while this one reads it.
static void test_concurrent_writers(void) {
  clear_dir();
  bk_mesh_tree tree = {0};
  build_tree(512, 9, &tree);
  size_t expected_size = 0;
  uint8_t* expected = reference_bytes(&tree, &expected_size);
  save_ok(&tree, TREE_PATH); // so that every load below must succeed: the entry is only ever replaced
  fflush(NULL);
  pid_t children[WRITERS] = {0};
  for (int c = 0; c < WRITERS; ++c) {
    children[c] = fork();
    ENSURE(children[c] >= 0);
    if (children[c] == 0) {
      for (int i = 0; i < SAVES_PER_WRITER; ++i) {
        bk_error err = {{0}};
        if (!bk_mesh_tree_save(&tree, TREE_PATH, &err)) {
          fprintf(stderr, "writer %d, save %d: %s\n", c, i, err.message);
          _exit(1);
        }
      }
      _exit(0);
    }
  }
  int running = WRITERS, failed_writers = 0, loads = 0;
  while (running > 0) {
    bk_mesh_tree loaded = {0};
    bk_error err = {{0}};
    ENSURE_MSG(bk_mesh_tree_load(TREE_PATH, &loaded, &err), "a reader saw a torn or missing file: %s",
               err.message);
    ENSURE(loaded.node_count == tree.node_count && loaded.bond_count == tree.bond_count);
    bk_mesh_tree_free(&loaded);
    ++loads;
    for (int c = 0; c < WRITERS; ++c) {
      int status = 0;
      if (children[c] > 0 && waitpid(children[c], &status, WNOHANG) == children[c]) {
        failed_writers += !(WIFEXITED(status) && WEXITSTATUS(status) == 0);
        children[c] = 0;
        --running;
      }
    }
  }
  printf("  %d loads during %d x %d saves\n", loads, WRITERS, SAVES_PER_WRITER);
  ENSURE_MSG(failed_writers == 0, "%d of %d writers had a failed save", failed_writers, WRITERS);
  ENSURE(same_bytes(TREE_PATH, expected, expected_size));
  ENSURE_MSG(dir_entries() == 1, "%d entries: temporary files were left behind", dir_entries());
  free(expected);
  bk_mesh_tree_free(&tree);
}

int main(void) {
  RUN(test_symlinks_not_followed);
  RUN(test_failed_save_keeps_file);
  RUN(test_permissions);
  RUN(test_longest_name);
  RUN(test_concurrent_writers);
  clear_dir();
  return 0;
}
