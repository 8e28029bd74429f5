// Runs a fuzz harness over saved inputs without libFuzzer, so the normal
// (gcc, sanitizer) build replays the seed and regression corpora as tests.
//
//   fuzz_<name>_replay FILE|DIR...
//
// Directories are read one level deep, in name order; hidden files and
// README* are skipped. Each input runs in a child process, so one crash does
// not hide the next and the sanitizers' leak check runs per input. Prints one
// line per input and exits 1 if any failed.
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "fuzz_util.h"

typedef struct path_list {
  char** items;
  size_t count, capacity;
} path_list;

static void add_path(path_list* list, const char* path) {
  if (list->count == list->capacity) {
    list->capacity = list->capacity ? 2 * list->capacity : 16;
    list->items = bk_realloc(list->items, sizeof(char*) * list->capacity);
  }
  size_t length = strlen(path);
  list->items[list->count] = bk_alloc(length + 1);
  memcpy(list->items[list->count++], path, length + 1);
}

static int compare_paths(const void* a, const void* b) { return strcmp(*(char* const*)a, *(char* const*)b); }

// Adds the regular files of a directory (sorted) or the file itself; false if
// the path does not exist.
static bool collect(path_list* list, const char* path) {
  struct stat st;
  if (stat(path, &st) != 0) return false;
  if (!S_ISDIR(st.st_mode)) {
    add_path(list, path);
    return true;
  }
  DIR* dir = opendir(path);
  if (!dir) return false;
  size_t first = list->count;
  char child[4096];
  for (struct dirent* e = readdir(dir); e; e = readdir(dir)) {
    if (e->d_name[0] == '.' || strncmp(e->d_name, "README", 6) == 0) continue;
    snprintf(child, sizeof child, "%s/%s", path, e->d_name);
    if (stat(child, &st) == 0 && S_ISREG(st.st_mode)) add_path(list, child);
  }
  closedir(dir);
  qsort(list->items + first, list->count - first, sizeof(char*), compare_paths);
  return true;
}

// Removes a directory whose entries are plain files or directories of plain
// files: the children's scratch directories, which a crash leaves behind.
static void remove_tree(const char* path, int depth) {
  DIR* dir = opendir(path);
  if (dir) {
    char child[4096];
    for (struct dirent* e = readdir(dir); e; e = readdir(dir)) {
      if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
      snprintf(child, sizeof child, "%s/%s", path, e->d_name);
      struct stat st;
      if (depth > 0 && lstat(child, &st) == 0 && S_ISDIR(st.st_mode))
        remove_tree(child, depth - 1);
      else
        unlink(child);
    }
    closedir(dir);
  }
  rmdir(path);
}

// Runs one input in a child; returns true when it passed.
static bool replay(const char* path) {
  size_t size = 0;
  uint8_t* data = bk_fuzz_read_file(path, &size);
  if (!data) {
    printf("FAIL %s: cannot read\n", path);
    return false;
  }
  fflush(stdout);
  fflush(stderr);
  pid_t child = fork();
  if (child < 0) {
    free(data);
    printf("FAIL %s: cannot fork\n", path);
    return false;
  }
  if (child == 0) {
    LLVMFuzzerTestOneInput(data, size);
    free(data);
    exit(0); // a normal exit, so the leak check runs
  }
  free(data);
  int status = 0;
  while (waitpid(child, &status, 0) < 0) {
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    printf("ok   %s\n", path);
    return true;
  }
  if (WIFSIGNALED(status))
    printf("FAIL %s: signal %d\n", path, WTERMSIG(status));
  else
    printf("FAIL %s: exit status %d\n", path, WEXITSTATUS(status));
  return false;
}

int main(int argc, char** argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: %s FILE|DIR...\n", argv[0]);
    return 2;
  }
  path_list inputs = {0};
  for (int i = 1; i < argc; ++i)
    if (!collect(&inputs, argv[i])) {
      fprintf(stderr, "%s: %s: no such file or directory\n", bk_fuzz_harness, argv[i]);
      return 2;
    }
  // The children make their scratch directories in here, removed at the end
  // even when a crash kept a child from removing its own.
  const char* base = getenv("TMPDIR");
  char scratch[4096];
  snprintf(scratch, sizeof scratch, "%s/bk-fuzz-replay-XXXXXX", base && *base ? base : "/tmp");
  if (!mkdtemp(scratch)) {
    fprintf(stderr, "%s: cannot create a scratch directory in %s\n", bk_fuzz_harness, base ? base : "/tmp");
    return 2;
  }
  setenv("BK_FUZZ_TMP", scratch, 1);
  size_t failed = 0;
  for (size_t i = 0; i < inputs.count; ++i)
    failed += !replay(inputs.items[i]);
  remove_tree(scratch, 1);
  printf("%s: %zu inputs, %zu failed\n", bk_fuzz_harness, inputs.count, failed);
  for (size_t i = 0; i < inputs.count; ++i)
    free(inputs.items[i]);
  free(inputs.items);
  // An empty corpus would make the test pass without testing anything.
  if (inputs.count == 0) {
    fprintf(stderr, "%s: no inputs found\n", bk_fuzz_harness);
    return 1;
  }
  return failed ? 1 : 0;
}
