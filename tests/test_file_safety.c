// Files are never lost and readers never hang: every reader opens regular
// files only (a FIFO or a directory is named for what it is, at once), the
// atomic writer refuses a read-only target and leaves it as it was, paths
// naming one file are told apart from others, text quoted from a file is
// escaped in messages, and a glTF's JSON is counted before it is allocated.
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bk_geom.h"
#include "bk_json.h"
#include "ensure.h"

#define DIR_PATH BK_TEST_TMP "/file_safety"

static void on_alarm(int signal) {
  (void)signal;
  static const char text[] = "test_file_safety: a reader blocked (FIFO opened?)\n";
  if (write(STDERR_FILENO, text, sizeof text - 1) < 0) _exit(3);
  _exit(2);
}

static void write_bytes(const char* path, const void* data, size_t size) {
  FILE* f = fopen(path, "wb");
  ENSURE_MSG(f != NULL, "%s: %s", path, strerror(errno));
  ENSURE(fwrite(data, 1, size, f) == size);
  ENSURE(fclose(f) == 0);
}

static void write_text(const char* path, const char* text) { write_bytes(path, text, strlen(text)); }

static bool same_text(const char* path, const char* text) {
  void* data = NULL;
  size_t size = 0;
  bk_error err = {{0}};
  if (!bk_file_read(path, (uint64_t)1 << 20, "1 MiB", &data, &size, &err)) return false;
  bool same = size == strlen(text) && memcmp(data, text, size) == 0;
  free(data);
  return same;
}

static void make_fifo(const char* path) {
  unlink(path);
  ENSURE_MSG(mkfifo(path, 0644) == 0, "mkfifo %s: %s", path, strerror(errno));
}

static void expect_message(bool ok, const bk_error* err, const char* part) {
  ENSURE_MSG(!ok, "expected a refusal containing '%s'", part);
  ENSURE_MSG(strstr(err->message, part) != NULL, "expected '%s' in: %s", part, err->message);
  ENSURE_MSG(strchr(err->message, '\n') == NULL, "not one line: %s", err->message);
}

static const char tetrahedron[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

// Readers: a FIFO and a directory are refused at once, whatever the format.
static void test_readers_open_regular_files_only(void) {
  alarm(60); // a regression blocks in open(): fail instead of hanging
  const char* fifo_names[] = {DIR_PATH "/fifo.obj", DIR_PATH "/fifo.ply", DIR_PATH "/fifo.gltf",
                              DIR_PATH "/fifo.stl", DIR_PATH "/fifo.mtree"};
  for (size_t i = 0; i < sizeof fifo_names / sizeof *fifo_names; ++i) {
    make_fifo(fifo_names[i]);
    bk_error err = {{0}};
    bk_mesh mesh = {0};
    bk_mesh_tree tree = {0};
    bool ok = strstr(fifo_names[i], ".mtree") ? bk_mesh_tree_load(fifo_names[i], &tree, &err)
                                              : bk_model_import(fifo_names[i], NULL, &mesh, NULL, &err);
    expect_message(ok, &err, "is not a regular file");
    ENSURE_MSG(strstr(err.message, fifo_names[i]) != NULL, "the path is not named: %s", err.message);
  }
  void* data = NULL;
  size_t size = 0;
  bk_error err = {{0}};
  expect_message(bk_file_read(DIR_PATH "/fifo.obj", 1u << 20, "1 MiB", &data, &size, &err), &err,
                 DIR_PATH "/fifo.obj: is not a regular file");
  ENSURE(mkdir(DIR_PATH "/dir.obj", 0755) == 0 || errno == EEXIST);
  bk_mesh mesh = {0};
  expect_message(bk_model_import(DIR_PATH "/dir.obj", NULL, &mesh, NULL, &err), &err,
                 DIR_PATH "/dir.obj: is a directory");
  expect_message(bk_file_check_read(DIR_PATH, &err), &err, "is a directory");
  // An OBJ whose mtllib is a FIFO: refused (not read forever, not silently white).
  make_fifo(DIR_PATH "/fifo.mtl");
  char obj[512];
  snprintf(obj, sizeof obj, "mtllib fifo.mtl\nusemtl red\n%s", tetrahedron);
  write_text(DIR_PATH "/with_fifo_mtl.obj", obj);
  bk_import_info info = {0};
  expect_message(bk_model_import(DIR_PATH "/with_fifo_mtl.obj", NULL, &mesh, &info, &err), &err,
                 DIR_PATH "/fifo.mtl: is not a regular file");
  ENSURE_MSG(mesh.positions == NULL && mesh.triangle_count == 0, "a refused import left a mesh");
  // A .gltf whose buffer is a FIFO: assimp opens it through our file system, which refuses it.
  make_fifo(DIR_PATH "/buffer.bin");
  write_text(DIR_PATH "/external.gltf",
             "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"uri\":\"buffer.bin\",\"byteLength\":36}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],\"accessors\":[{\"bufferView\":0,"
             "\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,0]}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],\"nodes\":[{\"mesh\":0}],"
             "\"scenes\":[{\"nodes\":[0]}],\"scene\":0}");
  expect_message(bk_model_import(DIR_PATH "/external.gltf", NULL, &mesh, NULL, &err), &err,
                 "buffer.bin: is not a regular file (read by " DIR_PATH "/external.gltf)");
  // A missing library still only leaves the materials white.
  snprintf(obj, sizeof obj, "mtllib missing.mtl\nusemtl red\n%s", tetrahedron);
  write_text(DIR_PATH "/missing_mtl.obj", obj);
  ENSURE_MSG(bk_model_import(DIR_PATH "/missing_mtl.obj", NULL, &mesh, &info, &err), "%s", err.message);
  bk_mesh_free(&mesh);
  bk_import_info_free(&info);
  alarm(0);
}

// The atomic writer never replaces a read-only file, a directory or a FIFO,
// even for root (the mode bits decide), and leaves no temporary behind.
static void test_writer_refusals(void) {
  const char* target = DIR_PATH "/read_only.obj";
  unlink(target);
  write_text(target, "original\n");
  ENSURE(chmod(target, 0444) == 0);
  bk_mesh mesh = {0};
  bk_shape_build(BK_SHAPE_CUBE, &mesh);
  bk_error err = {{0}};
  expect_message(bk_obj_save(target, &mesh, 1, &err), &err,
                 DIR_PATH "/read_only.obj: is read-only (mode 0444)");
  ENSURE_MSG(same_text(target, "original\n"), "the read-only file was changed");
  expect_message(bk_file_check_write(target, &err), &err, "read-only");
  ENSURE(chmod(target, 0644) == 0);
  ENSURE_MSG(bk_obj_save(target, &mesh, 1, &err), "%s", err.message);
  ENSURE(!same_text(target, "original\n"));
  make_fifo(DIR_PATH "/fifo_out.obj");
  expect_message(bk_obj_save(DIR_PATH "/fifo_out.obj", &mesh, 1, &err), &err, "is not a regular file");
  expect_message(bk_obj_save(DIR_PATH "/dir.obj", &mesh, 1, &err), &err, "is a directory");
  expect_message(bk_file_check_write(DIR_PATH "/no_such_dir/x.obj", &err), &err, "no_such_dir");
  bk_mesh_free(&mesh);
  // Nothing but what the test made is left in the directory (no temporaries).
  ENSURE(access(DIR_PATH "/read_only.obj", F_OK) == 0);
  FILE* listing = popen("ls -A '" DIR_PATH "' | grep -c '\\.tmp$'", "r");
  ENSURE(listing != NULL);
  int temporaries = -1;
  ENSURE(fscanf(listing, "%d", &temporaries) == 1);
  pclose(listing);
  ENSURE_MSG(temporaries == 0, "%d temporaries left behind", temporaries);
}

static void test_same_file(void) {
  const char* a = DIR_PATH "/same_a.obj";
  write_text(a, "x\n");
  ENSURE(chdir(DIR_PATH) == 0);
  ENSURE(bk_file_same("same_a.obj", "./same_a.obj"));
  ENSURE(bk_file_same("same_a.obj", a));
  ENSURE(bk_file_same("same_a.obj", DIR_PATH "/../file_safety/./same_a.obj"));
  unlink("link_to_a.obj");
  ENSURE(symlink("same_a.obj", "link_to_a.obj") == 0);
  ENSURE(bk_file_same("link_to_a.obj", "same_a.obj"));
  unlink("hard_a.obj");
  ENSURE(link("same_a.obj", "hard_a.obj") == 0);
  ENSURE(bk_file_same("hard_a.obj", "same_a.obj"));
  // Names not there yet: by their normalised names.
  ENSURE(bk_file_same("new.glb", "./new.glb"));
  ENSURE(bk_file_same("new.glb", DIR_PATH "//new.glb"));
  ENSURE(bk_file_same("sub/../new.glb", "new.glb"));
  ENSURE(!bk_file_same("new.glb", "new.gltf"));
  ENSURE(!bk_file_same("same_a.obj", "new.glb"));
  ENSURE(chdir(BK_TEST_TMP) == 0);
}

// Bytes a terminal would act on are escaped in every message, once, in bk_error_set.
static void test_escaping(void) {
  char out[64];
  bk_escape_text("a\x1b[2Jb", 6, out, sizeof out);
  ENSURE_MSG(strcmp(out, "a\\x1b[2Jb") == 0, "%s", out);
  bk_escape_text("caf\xc3\xa9 \xff \xc2\x9b x", 12, out, sizeof out); // UTF-8 kept; invalid and C1 escaped
  ENSURE_MSG(strcmp(out, "caf\xc3\xa9 \\xff \\xc2\\x9b x") == 0, "%s", out);
  ENSURE(bk_escape_text("abc\0d", 5, out, sizeof out) == 5 && strcmp(out, "abc\\x00d") == 0);
  bk_error err = {{0}};
  bk_error_set(&err, "%s: '%s'", "x.ply", "\x1b]0;title\x07");
  ENSURE_MSG(strcmp(err.message, "x.ply: '\\x1b]0;title\\x07'") == 0, "%s", err.message);
  // A PLY header line with an escape sequence: refused, and nothing raw reaches the message.
  const char ply[] = "ply\nformat ascii 1.0\n\x1b[2Jhello\nend_header\n";
  write_text(DIR_PATH "/escape.ply", ply);
  bk_mesh mesh = {0};
  expect_message(bk_model_import(DIR_PATH "/escape.ply", NULL, &mesh, NULL, &err), &err, "escape.ply");
  ENSURE_MSG(strchr(err.message, 0x1b) == NULL, "a raw ESC in: %s", err.message);
  // An OBJ token the message quotes: escaped.
  write_text(DIR_PATH "/escape.obj", "v 1 \x1b[2J 0\n");
  expect_message(bk_model_import(DIR_PATH "/escape.obj", NULL, &mesh, NULL, &err), &err, "'\\x1b[2J'");
  ENSURE_MSG(strchr(err.message, 0x1b) == NULL, "a raw ESC in: %s", err.message);
}

static long peak_rss_mb(void) {
  struct rusage usage;
  ENSURE(getrusage(RUSAGE_SELF, &usage) == 0);
  return usage.ru_maxrss / 1024;
}

// 64 MiB of "0," in a .gltf: refused after counting, before the values are
// allocated (it took 1.65 GB), both as a model and as a tree.
static void test_gltf_counted_before_allocated(void) {
  const size_t size = (size_t)64 << 20;
  char* text = malloc(size);
  ENSURE(text != NULL);
  const char head[] = "{\"asset\":{\"version\":\"2.0\"},\"extras\":[";
  memcpy(text, head, sizeof head - 1);
  size_t at = sizeof head - 1;
  while (at + 4 < size) {
    text[at++] = '0';
    text[at++] = ',';
  }
  text[at++] = '0';
  text[at++] = ']';
  text[at++] = '}';
  write_bytes(DIR_PATH "/big.gltf", text, at);
  long before = peak_rss_mb();
  bk_error err = {{0}};
  bk_mesh mesh = {0};
  expect_message(bk_model_import(DIR_PATH "/big.gltf", NULL, &mesh, NULL, &err), &err,
                 "values, refusing to load");
  bk_mesh_tree tree = {0};
  ENSURE(!bk_mesh_tree_load_gltf(DIR_PATH "/big.gltf", &tree, &err));
  long after = peak_rss_mb();
  printf("  peak RSS %ld MiB before, %ld MiB after the two loads of a 64 MiB .gltf\n", before, after);
  ENSURE_MSG(after - before < 400, "loading a 64 MiB .gltf raised the peak by %ld MiB", after - before);
  // The limits: a kept value's children are checked, not stored; the count is exact.
  const char doc_text[] = "{\"a\":[1,2,3],\"extras\":{\"x\":[4,5]},\"b\":{\"c\":6}}";
  static const char* const kept[] = {"a", NULL};
  bk_json_limits limits = {BK_JSON_MAX_VALUES, 0, kept, false};
  bk_json_doc doc = {0};
  char why[96];
  ENSURE(bk_json_parse_limited(doc_text, sizeof doc_text - 1, &limits, &doc, why, sizeof why));
  ENSURE_MSG(doc.count == 7 && doc.capacity == 7, "%u values stored", doc.count); // {}, a, 1, 2, 3, extras, b
  ENSURE(bk_json_count(&doc, bk_json_get(&doc, 0, "a")) == 3);
  ENSURE(bk_json_count(&doc, bk_json_get(&doc, 0, "b")) == 0);
  bk_json_free(&doc);
  limits = (bk_json_limits){BK_JSON_MAX_VALUES, 0, NULL, true};
  ENSURE(bk_json_parse_limited(doc_text, sizeof doc_text - 1, &limits, &doc, why, sizeof why));
  ENSURE(bk_json_count(&doc, bk_json_get(&doc, 0, "extras")) == 0 &&
         bk_json_count(&doc, bk_json_get(&doc, 0, "b")) == 1);
  bk_json_free(&doc);
  limits = (bk_json_limits){BK_JSON_MAX_VALUES, 10, NULL, true};
  ENSURE(!bk_json_parse_limited(doc_text, sizeof doc_text - 1, &limits, &doc, why, sizeof why));
  ENSURE_MSG(strcmp(why, "more than 10 values") == 0, "%s", why);
  limits.max_total = 0;
  ENSURE(!bk_json_parse_limited("[1,", 3, &limits, &doc, why, sizeof why)); // the grammar is still checked
  free(text);
  unlink(DIR_PATH "/big.gltf");
}

int main(void) {
  signal(SIGALRM, on_alarm);
  ENSURE(mkdir(DIR_PATH, 0755) == 0 || errno == EEXIST);
  RUN(test_readers_open_regular_files_only);
  RUN(test_writer_refusals);
  RUN(test_same_file);
  RUN(test_escaping);
  RUN(test_gltf_counted_before_allocated);
  return 0;
}
