// No file lost, no hang, as a user meets them on the command line: bench
// never follows a symlink planted at its temporary or final names; fracture
// refuses, before any work, an output that is its input, two outputs that are
// one file, a read-only target, a wrong extension or a missing directory; a
// FIFO as a model or as its mtllib is refused at once; a directory or an
// unsupported format is named for what it is; file content is escaped.
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define RUN_STDERR_PATH BK_TEST_TMP "/test_cli_files.stderr"
#include "run_exe.h"

#include "cli_util.h"

#define DIR_PATH BK_TEST_TMP "/cli_files"

static const char tetrahedron[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

static void put(const char* path, const char* text) {
  FILE* f = fopen(path, "wb");
  ENSURE_MSG(f != NULL, "%s: %s", path, strerror(errno));
  fputs(text, f);
  ENSURE(fclose(f) == 0);
}

// The whole file, NUL-terminated (at most 1 MiB), in a fresh buffer.
static char* slurp(const char* path) {
  FILE* f = fopen(path, "rb");
  ENSURE_MSG(f != NULL, "%s: %s", path, strerror(errno));
  char* text = calloc(1, (1 << 20) + 1);
  ENSURE(text != NULL);
  size_t n = fread(text, 1, 1 << 20, f);
  text[n] = 0;
  fclose(f);
  return text;
}

static void expect_same(const char* path, const char* text) {
  char* now = slurp(path);
  ENSURE_MSG(strcmp(now, text) == 0, "%s was changed", path);
  free(now);
}

static double now_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

// run() under `timeout`: a regression that blocks fails (status 124) instead of hanging the suite.
static run_result* run_limited(int seconds, const char* args) {
  char command[4096];
  snprintf(command, sizeof command, "timeout %d '%s' %s 2>'%s' </dev/null", seconds, BK_BREAKABLES_EXE, args,
           RUN_STDERR_PATH);
  return run_command(command);
}

static void expect_refusal(const run_result* r, const char* args, int status, const char* message) {
  ENSURE_MSG(r->status == status, "'%s' exited %d, expected %d (%s)", args, r->status, status, r->err);
  ENSURE_MSG(strstr(r->err, message) != NULL, "'%s': expected '%s' in: %s", args, message, r->err);
  const char* newline = strchr(r->err, '\n');
  ENSURE_MSG(newline && newline[1] == 0, "'%s': error is not one line: %s", args, r->err);
}

// bench writes every file beside its target under a fresh, exclusive name:
// symlinks planted at the old fixed temporary names (DIR/<name>.tmp) and at a
// final name keep their target intact.
static void test_bench_symlinks(void) {
  const char* bench_dir = DIR_PATH "/bench";
  ENSURE(system("rm -rf '" DIR_PATH "/bench' && mkdir -p '" DIR_PATH "/bench'") == 0);
  put(DIR_PATH "/victim", "precious\n");
  const char* planted[] = {"report.md.tmp", "stress.csv.tmp", "stress.csv"};
  for (size_t i = 0; i < sizeof planted / sizeof *planted; ++i) {
    char link_path[512];
    snprintf(link_path, sizeof link_path, "%s/%s", bench_dir, planted[i]);
    ENSURE(symlink(DIR_PATH "/victim", link_path) == 0);
  }
  run_result* r = run_limited(600, "bench --quick --only 8 --out '" DIR_PATH "/bench'");
  ENSURE_MSG(r->status == 0, "bench exited %d: %s", r->status, r->err);
  expect_same(DIR_PATH "/victim", "precious\n");
  struct stat st = {0};
  ENSURE(lstat(DIR_PATH "/bench/report.md.tmp", &st) == 0 && S_ISLNK(st.st_mode));
  ENSURE(lstat(DIR_PATH "/bench/stress.csv", &st) == 0 && S_ISREG(st.st_mode)); // the link was replaced
  char* csv = slurp(DIR_PATH "/bench/stress.csv");
  ENSURE_MSG(strncmp(csv, "fragments,", 10) == 0, "stress.csv: %.40s", csv);
  free(csv);
  char* report = slurp(DIR_PATH "/bench/report.md");
  ENSURE(strstr(report, "stress") != NULL || strstr(report, "Stress") != NULL);
  free(report);
}

// An output that is the input: refused, the model byte for byte as it was.
static void test_output_is_input(void) {
  put(DIR_PATH "/model.obj", tetrahedron);
  ENSURE(chdir(DIR_PATH) == 0);
  unlink("link.obj");
  ENSURE(symlink("model.obj", "link.obj") == 0);
  const char* cases[] = {
      "fracture --mesh model.obj --pieces 2 --export-obj model.obj",
      "fracture --mesh model.obj --pieces 2 --export-obj ./model.obj",
      "fracture --mesh '" DIR_PATH "/model.obj' --pieces 2 --export-obj model.obj",
      "fracture --mesh link.obj --pieces 2 --export-obj model.obj",
  };
  for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
    expect_refusal(run(cases[i]), cases[i], 1, "--export-obj");
    ENSURE_MSG(strstr(run_result_storage.err, "is the file --mesh reads"), "%s", run_result_storage.err);
    expect_same(DIR_PATH "/model.obj", tetrahedron);
  }
  ENSURE(chdir(BK_TEST_TMP) == 0);
}

// Two outputs that are one file, a wrong extension, a missing directory: refused
// before any work (a fracture of 50,000 pieces would take a long while).
static void test_outputs_checked_first(void) {
  ENSURE(chdir(DIR_PATH) == 0);
  unlink("x.glb");
  unlink("x.mtree");
  put("x.glb", "glb before\n");
  ENSURE(symlink("x.glb", "x.mtree") == 0);
  struct {
    const char* args;
    const char* message;
  } cases[] = {
      {"--out x.mtree --export-gltf x.glb", "--out 'x.mtree' and --export-gltf 'x.glb' are the same file"},
      {"--out x.glb --export-gltf x.glb", "--out 'x.glb': the file name must end in .mtree"},
      {"--out y.mtree --export-gltf y.mtree",
       "--export-gltf 'y.mtree': the file name must end in .glb or .gltf"},
      {"--export-obj y.txt", "--export-obj 'y.txt': the file name must end in .obj"},
      {"--export-gltf no_such_dir/y.glb", "no_such_dir/y.glb: cannot write: directory 'no_such_dir'"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
    char args[512];
    snprintf(args, sizeof args, "fracture --mesh bunny --pieces 50000 %s", cases[i].args);
    double start = now_s();
    expect_refusal(run(args), args, 1, cases[i].message);
    double seconds = now_s() - start;
    ENSURE_MSG(seconds < 20.0, "'%s' took %.1f s: the refusal came after the work", args, seconds);
    ENSURE_MSG(run_result_storage.out[0] == 0, "'%s' printed: %s", args, run_result_storage.out);
    expect_same("x.glb", "glb before\n");
  }
  ENSURE(access("y.mtree", F_OK) != 0 && access("y.glb", F_OK) != 0);
  ENSURE(chdir(BK_TEST_TMP) == 0);
}

// A read-only target is refused and kept, even for root: the mode bits decide.
static void test_read_only_target(void) {
  const char* path = DIR_PATH "/read_only.mtree";
  unlink(path);
  put(path, "keep me\n");
  ENSURE(chmod(path, 0444) == 0);
  const char* args = "fracture --mesh cube --pieces 4 --out '" DIR_PATH "/read_only.mtree'";
  expect_refusal(run(args), args, 1, "read_only.mtree: is read-only (mode 0444); not replaced");
  expect_same(path, "keep me\n");
  const char* obj = DIR_PATH "/read_only.obj";
  unlink(obj);
  put(obj, "keep me too\n");
  ENSURE(chmod(obj, 0444) == 0);
  args = "fracture --mesh cube --pieces 4 --export-obj '" DIR_PATH "/read_only.obj'";
  expect_refusal(run(args), args, 1, "is read-only");
  expect_same(obj, "keep me too\n");
  // A screenshot: checked when the options are read, before any window opens.
  const char* png = DIR_PATH "/read_only.png";
  unlink(png);
  put(png, "not a png\n");
  ENSURE(chmod(png, 0444) == 0);
  args = "play --frames 1 --screenshot '" DIR_PATH "/read_only.png'";
  expect_refusal(run(args), args, 2, "is read-only");
  expect_same(png, "not a png\n");
  args = "play --frames 1 --screenshot '" DIR_PATH "/shot.txt'";
  expect_refusal(run(args), args, 2, "--screenshot '" DIR_PATH "/shot.txt': the file name must end in .png");
}

// A FIFO is never opened for reading: as --mesh, and as an OBJ's mtllib.
static void test_fifo(void) {
  const char* fifo = DIR_PATH "/pipe.obj";
  unlink(fifo);
  ENSURE(mkfifo(fifo, 0644) == 0);
  const char* args = "fracture --mesh '" DIR_PATH "/pipe.obj'";
  double start = now_s();
  expect_refusal(run_limited(30, args), args, 1, DIR_PATH "/pipe.obj: is not a regular file");
  const char* ply = DIR_PATH "/pipe.ply";
  unlink(ply);
  ENSURE(mkfifo(ply, 0644) == 0);
  args = "sim --mesh '" DIR_PATH "/pipe.ply' --steps 1";
  expect_refusal(run_limited(30, args), args, 1, "pipe.ply: is not a regular file");
  const char* mtl = DIR_PATH "/pipe.mtl";
  unlink(mtl);
  ENSURE(mkfifo(mtl, 0644) == 0);
  char obj[512];
  snprintf(obj, sizeof obj, "mtllib pipe.mtl\nusemtl stone\n%s", tetrahedron);
  put(DIR_PATH "/uses_pipe.obj", obj);
  args = "fracture --mesh '" DIR_PATH "/uses_pipe.obj' --pieces 2";
  expect_refusal(run_limited(30, args), args, 1, "pipe.mtl: is not a regular file (mtllib of ");
  ENSURE_MSG(now_s() - start < 30.0, "the refusals took %.1f s", now_s() - start);
}

// What a path is, said plainly; content quoted from a file escaped.
static void test_messages(void) {
  ENSURE(mkdir(DIR_PATH "/a_dir", 0755) == 0 || errno == EEXIST);
  ENSURE(mkdir(DIR_PATH "/a_dir.obj", 0755) == 0 || errno == EEXIST);
  expect_error("fracture --mesh '" DIR_PATH "/a_dir'", 1, DIR_PATH "/a_dir: is a directory");
  expect_error("fracture --mesh '" DIR_PATH "/a_dir.obj'", 1, DIR_PATH "/a_dir.obj: is a directory");
  put(DIR_PATH "/model.dat", tetrahedron);
  expect_error("fracture --mesh '" DIR_PATH "/model.dat'", 1,
               DIR_PATH "/model.dat: unsupported model format (.dat); known: obj, ");
  expect_error("fracture --mesh no_such_shape", 1, "unknown mesh 'no_such_shape'");
  // ESC bytes in a model: never raw on stderr.
  put(DIR_PATH "/escape.ply", "ply\nformat ascii 1.0\n\x1b]0;pwned\x07\nend_header\n");
  run_result* r = run("fracture --mesh '" DIR_PATH "/escape.ply'");
  ENSURE_MSG(r->status == 1 && strstr(r->err, "escape.ply"), "%s", r->err);
  ENSURE_MSG(strchr(r->err, 0x1b) == NULL && strchr(r->err, 0x07) == NULL, "raw control bytes in: %s",
             r->err);
  put(DIR_PATH "/escape.obj", "v 0 0 \x1b[2J\n");
  expect_error("fracture --mesh '" DIR_PATH "/escape.obj'", 1, "'\\x1b[2J'");
  ENSURE_MSG(strchr(run_result_storage.err, 0x1b) == NULL, "a raw ESC in: %s", run_result_storage.err);
}

int main(void) {
  ENSURE(system("mkdir -p '" DIR_PATH "'") == 0);
  RUN(test_output_is_input);
  RUN(test_outputs_checked_first);
  RUN(test_read_only_target);
  RUN(test_fifo);
  RUN(test_messages);
  RUN(test_bench_symlinks);
  return 0;
}
