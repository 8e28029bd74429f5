// 'breakables bench': output files written atomically, tables printed and
// written as CSV and Markdown, gnuplot plots and the report's header.
#include "bench_report.h"

#include <errno.h>
#include <math.h>
#include <spawn.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "app.h"
#include "scene_run.h"

extern char** environ; // for gnuplot's environment (posix_spawnp)

// ---------------------------------------------------------------- output files

// The bench reports every write failure the same way.
static const bk_atomic_messages bench_write_messages = {"cannot write", "cannot write", "cannot write"};

bool bench_output_open(const bench* b, const char* name, bench_output* out) {
  out->file = NULL;
  if (snprintf(out->path, sizeof out->path, "%s/%s", b->dir, name) >= (int)sizeof out->path) {
    fprintf(stderr, "breakables bench: cannot write %s/%s: the path is too long\n", b->dir, name);
    return false;
  }
  bk_error err = {{0}};
  // bk_file_check_write first: a directory made read-only is refused even for root.
  if (!bk_file_check_write(out->path, &err) ||
      !bk_file_begin_atomic(out->path, &bench_write_messages, &out->atomic, &err)) {
    fprintf(stderr, "breakables bench: %s\n", err.message);
    return false;
  }
  out->file = out->atomic.stream;
  return true;
}

/// Closes the file and renames it into place (keep = true), or removes it.
bool bench_output_close(bench_output* out, bool keep) {
  if (!out->file) return false;
  out->file = NULL;
  if (!keep) {
    bk_file_abort_atomic(&out->atomic);
    return false;
  }
  bk_error err = {{0}};
  if (bk_file_commit_atomic(&out->atomic, out->path, &bench_write_messages, &err)) return true;
  fprintf(stderr, "breakables bench: %s\n", err.message);
  return false;
}

void bench_say(const bench* b, const char* format, ...) {
  va_list args;
  va_start(args, format);
  vfprintf(b->report, format, args);
  va_end(args);
}

/// Starts a section: a heading on stdout, a heading and what is measured in the report.
void bench_section(const bench* b, const char* title, const char* method) {
  printf("\n%s\n", title);
  bench_say(b, "\n## %s\n\n%s\n\n", title, method);
}

bool bench_make_directories(const char* path) {
  char buffer[PATH_MAX];
  snprintf(buffer, sizeof buffer, "%s", path);
  for (char* p = buffer + 1; *p; ++p) {
    if (*p != '/') continue;
    *p = 0;
    if (mkdir(buffer, 0755) != 0 && errno != EEXIST) return false;
    *p = '/';
  }
  if (mkdir(buffer, 0755) != 0 && errno != EEXIST) return false;
  struct stat st = {0};
  if (stat(buffer, &st) != 0) return false;
  if (!S_ISDIR(st.st_mode)) return errno = ENOTDIR, false;
  return true;
}

// ---------------------------------------------------------------- tables

bench_table bench_table_make(const char* name, const bench_column* columns, uint32_t column_count) {
  return (bench_table){.name = name, .columns = columns, .column_count = column_count};
}

void bench_table_cell(bench_table* t, const char* format, ...) {
  if (t->cell_count == t->capacity) {
    t->capacity = t->capacity ? 2 * t->capacity : 64;
    t->cells = bk_realloc(t->cells, sizeof *t->cells * t->capacity);
  }
  va_list args;
  va_start(args, format);
  vsnprintf(t->cells[t->cell_count++], BENCH_CELL_SIZE, format, args);
  va_end(args);
}

static uint32_t table_rows(const bench_table* t) { return t->cell_count / t->column_count; }
static const char* table_at(const bench_table* t, uint32_t row, uint32_t col) {
  return t->cells[row * t->column_count + col];
}

void bench_table_free(bench_table* t) {
  free(t->cells);
  t->cells = NULL;
  t->cell_count = t->capacity = 0;
}

/// Writes DIR/<name>.csv, prints the table aligned on stdout and appends it to the report as Markdown.
bool bench_table_write(const bench* b, const bench_table* t) {
  char name[128];
  snprintf(name, sizeof name, "%s.csv", t->name);
  bench_output csv = {0};
  if (!bench_output_open(b, name, &csv)) return false;
  uint32_t rows = table_rows(t);
  for (uint32_t c = 0; c < t->column_count; ++c)
    fprintf(csv.file, "%s%s", c ? "," : "", t->columns[c].key);
  fputc('\n', csv.file);
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = 0; c < t->column_count; ++c)
      fprintf(csv.file, "%s%s", table_at(t, r, c), c + 1 < t->column_count ? "," : "\n");
  if (!bench_output_close(&csv, true)) return false;

  int* widths = bk_calloc(t->column_count, sizeof(int));
  for (uint32_t c = 0; c < t->column_count; ++c) {
    widths[c] = (int)strlen(t->columns[c].title);
    for (uint32_t r = 0; r < rows; ++r)
      if ((int)strlen(table_at(t, r, c)) > widths[c]) widths[c] = (int)strlen(table_at(t, r, c));
  }
  for (uint32_t c = 0; c < t->column_count; ++c)
    printf("  %*s", widths[c], t->columns[c].title);
  putchar('\n');
  for (uint32_t r = 0; r < rows; ++r) {
    for (uint32_t c = 0; c < t->column_count; ++c)
      printf("  %*s", widths[c], table_at(t, r, c));
    putchar('\n');
  }
  fflush(stdout);
  free(widths);

  for (uint32_t c = 0; c < t->column_count; ++c)
    bench_say(b, "| %s ", t->columns[c].title);
  bench_say(b, "|\n");
  for (uint32_t c = 0; c < t->column_count; ++c)
    bench_say(b, "| ---: ");
  bench_say(b, "|\n");
  for (uint32_t r = 0; r < rows; ++r) {
    for (uint32_t c = 0; c < t->column_count; ++c)
      bench_say(b, "| %s ", table_at(t, r, c));
    bench_say(b, "|\n");
  }
  bench_say(b, "\nCSV: [%s](%s)\n\n", name, name);
  return true;
}

// ---------------------------------------------------------------- measurements

double bench_leaf_volume_error(const bk_mesh_tree* tree) {
  double source = bk_mesh_volume(&tree->nodes[0].mesh), sum = 0.0;
  for (uint32_t l = 0; l < tree->leaf_count; ++l)
    sum += bk_mesh_volume(&bk_mesh_tree_leaf(tree, l)->mesh);
  return fabs(sum - source) / fabs(source);
}

// ---------------------------------------------------------------- plots

/// True if an executable of this name is in a PATH directory.
static bool on_path(const char* program) {
  const char* path = getenv("PATH");
  if (!path) return false;
  while (*path) {
    size_t length = strcspn(path, ":");
    char candidate[PATH_MAX];
    snprintf(candidate, sizeof candidate, "%.*s/%s", (int)(length ? length : 1), length ? path : ".",
             program);
    if (access(candidate, X_OK) == 0) return true;
    path += length;
    if (*path == ':') ++path;
  }
  return false;
}

/// gnuplot's PNG terminal: pngcairo, else png; NULL if gnuplot is missing or has neither.
const char* bench_gnuplot_terminal(void) {
  if (!on_path("gnuplot")) return NULL;
  fflush(NULL);
  FILE* pipe = popen("gnuplot -e 'set terminal' 2>&1 </dev/null", "r");
  if (!pipe) return NULL;
  bool cairo = false, plain = false;
  char line[512];
  while (fgets(line, sizeof line, pipe)) {
    char word[32] = {0};
    if (sscanf(line, "%31s", word) != 1) continue;
    cairo = cairo || strcmp(word, "pngcairo") == 0;
    plain = plain || strcmp(word, "png") == 0;
  }
  pclose(pipe);
  return cairo ? "pngcairo" : plain ? "png" : NULL;
}

/// Writes a gnuplot single-quoted string ('' stands for ').
static void gnuplot_quoted(FILE* out, const char* text) {
  fputc('\'', out);
  for (const char* p = text; *p; ++p)
    fputs(*p == '\'' ? "''" : (char[2]){*p, 0}, out);
  fputc('\'', out);
}

void bench_script_add(bench_script* s, const char* format, ...) {
  size_t room = sizeof s->text - s->length;
  va_list args;
  va_start(args, format);
  int n = vsnprintf(s->text + s->length, room, format, args);
  va_end(args);
  if (n > 0) s->length += (size_t)n < room ? (size_t)n : room - 1;
}

/// Renders DIR/<name>.png with gnuplot (run in DIR, so the script names the
/// CSV files plainly) and embeds it in the report; notes it when skipped.
bool bench_plot(const bench* b, const char* name, const char* caption, int width, int height,
                const bench_script* script) {
  if (!b->terminal) {
    bench_say(b, "*Plot %s.png (%s) skipped: gnuplot is not on PATH.*\n\n", name, caption);
    return true;
  }
  // gnuplot draws to its standard output, which is the plot's temporary
  // (made like every output file): gnuplot's own 'set output' would follow a
  // symlink planted at DIR/<name>.png and overwrite its target.
  char file_name[256];
  snprintf(file_name, sizeof file_name, "%.200s.png", name);
  bench_output png = {0};
  if (!bench_output_open(b, file_name, &png)) return false;
  fflush(NULL);
  int script_pipe[2] = {-1, -1};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  pid_t pid = 0;
  int code = pipe(script_pipe) != 0 ? errno : 0;
  if (code == 0) {
    posix_spawn_file_actions_adddup2(&actions, script_pipe[0], STDIN_FILENO);
    posix_spawn_file_actions_adddup2(&actions, fileno(png.file), STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&actions, script_pipe[1]);
    char* gnuplot_argv[] = {"gnuplot", NULL};
    code = posix_spawnp(&pid, "gnuplot", &actions, NULL, gnuplot_argv, environ);
    close(script_pipe[0]);
  }
  posix_spawn_file_actions_destroy(&actions);
  FILE* gnuplot = code == 0 ? fdopen(script_pipe[1], "w") : NULL;
  if (!gnuplot) {
    if (script_pipe[1] >= 0) close(script_pipe[1]);
    if (code == 0) waitpid(pid, NULL, 0);
    fprintf(stderr, "breakables bench: cannot run gnuplot: %s\n", strerror(code ? code : errno));
    bench_output_close(&png, false);
    return false;
  }
  fputs("cd ", gnuplot);
  gnuplot_quoted(gnuplot, b->dir);
  fprintf(gnuplot, "\nset terminal %s size %d,%d%s\n", b->terminal, width, height,
          strcmp(b->terminal, "pngcairo") == 0 ? " font 'sans,10' linewidth 1.5" : "");
  fputs("set output\nset datafile separator ','\nset datafile columnheaders\n", gnuplot);
  // The key goes under the plot, where it hides no data; its blank title keeps it off the axis label.
  fputs("set key outside bottom center horizontal maxrows 2 title ' '\n"
        "set grid\nset logscale xy\nset format x '%g'\nset format y '%g'\n",
        gnuplot);
  fprintf(gnuplot, "%s\nunset output\n", script->text);
  fclose(gnuplot);
  int status = -1;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  struct stat drawn_stat = {0};
  bool drawn = WIFEXITED(status) && WEXITSTATUS(status) == 0 && fstat(fileno(png.file), &drawn_stat) == 0 &&
               drawn_stat.st_size > 0;
  if (!bench_output_close(&png, drawn) || !drawn) {
    if (!drawn) fprintf(stderr, "breakables bench: gnuplot could not draw %s\n", png.path);
    return false;
  }
  bench_say(b, "![%s](%s.png)\n\n", caption, name);
  return true;
}

// ---------------------------------------------------------------- report header

/// The first "model name" of /proc/cpuinfo, or "unknown".
static void cpu_model(char* out, size_t size) {
  snprintf(out, size, "unknown");
  FILE* f = fopen("/proc/cpuinfo", "r");
  if (!f) return;
  char line[512];
  while (fgets(line, sizeof line, f)) {
    const char* colon = strchr(line, ':');
    if (strncmp(line, "model name", 10) != 0 || !colon) continue;
    colon += strspn(colon + 1, " \t") + 1;
    snprintf(out, size, "%.*s", (int)strcspn(colon, "\n"), colon);
    break;
  }
  fclose(f);
}

/// MemTotal of /proc/meminfo in GiB (0 if unknown).
static double memory_gib(void) {
  FILE* f = fopen("/proc/meminfo", "r");
  if (!f) return 0.0;
  char line[256];
  double kib = 0.0;
  while (fgets(line, sizeof line, f))
    if (sscanf(line, "MemTotal: %lf kB", &kib) == 1) break;
  fclose(f);
  return kib / (1024.0 * 1024.0);
}

static const char* build_type(void) {
#if defined(__SANITIZE_ADDRESS__)
  return "Debug with AddressSanitizer (timings are not representative)";
#elif defined(__OPTIMIZE__) && defined(NDEBUG)
  return "Release (optimised, assertions off)";
#elif defined(__OPTIMIZE__)
  return "optimised with assertions";
#else
  return "Debug (not optimised; timings are not representative)";
#endif
}

/// The command as run: the executable (relative to the working directory
/// when inside it) and the arguments, quoted where needed.
static void command_line(int argc, char** argv, char* out, size_t size) {
  char exe[PATH_MAX] = "breakables", cwd[PATH_MAX] = "";
  ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  exe[n > 0 ? n : (ssize_t)strlen("breakables")] = 0;
  const char* shown = exe;
  size_t cwd_length = getcwd(cwd, sizeof cwd) ? strlen(cwd) : 0;
  if (cwd_length && strncmp(exe, cwd, cwd_length) == 0 && exe[cwd_length] == '/')
    shown = exe + cwd_length + 1;
  size_t used = (size_t)snprintf(out, size, "%s", shown);
  for (int i = 0; i < argc && used < size; ++i) {
    bool plain = argv[i][0] && strspn(argv[i], "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                               "0123456789-_./=:,+") == strlen(argv[i]);
    used += (size_t)snprintf(out + used, size - used, plain ? " %s" : " '%s'", argv[i]);
  }
}

void bench_report_header(const bench* b, int argc, char** argv) {
  char command[2048] = "", cpu[256] = "", date[64] = "";
  command_line(argc, argv, command, sizeof command);
  cpu_model(cpu, sizeof cpu);
  time_t now = time(NULL);
  struct tm local = {0};
  strftime(date, sizeof date, "%Y-%m-%d %H:%M %Z", localtime_r(&now, &local));
  bench_say(b,
            "# Breakables benchmarks\n\n"
            "The tests of the thesis's chapter 6 (*Tests and Results*) run on this implementation%s, plus "
            "scaling to several objects, the speed of the asset pipeline (glTF out and in) and the fracture "
            "patterns compared. Tables are also in the CSV files next to this report; plots are drawn "
            "from them.\n\n",
            b->quick ? " (`--quick`: smaller counts)" : "");
  bench_say(b, "| | |\n| --- | --- |\n");
  bench_say(b, "| command | `%s` |\n", command);
  bench_say(b, "| date | %s |\n", date);
  bench_say(b, "| processor | %s, %ld cores |\n", cpu, sysconf(_SC_NPROCESSORS_ONLN));
  bench_say(b, "| memory | %.1f GiB |\n", memory_gib());
  bench_say(b, "| build | %s, %s |\n", build_type(), "compiler " __VERSION__);
  bench_say(b, "| fracture seed | %llu |\n", (unsigned long long)b->seed);
  if (b->terminal)
    bench_say(b, "| plots | gnuplot, %s terminal |\n", b->terminal);
  else
    bench_say(b, "| plots | none: gnuplot is not on PATH |\n");
  bench_say(b,
            "\nThe thesis's machine was a dual-core AMD Opteron 180 at 2.4 GHz with 4 GB of memory, running "
            "Unity 4.0.\n");
}
