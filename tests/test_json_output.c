// No JSON the project writes contains inf or nan (neither is JSON): the
// command line's number writer and the glTF exporter's write a non-finite
// number as null, and what `sim --json` and `fracture --json` print parses
// as strict JSON.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"
#include "bk_json.h"
#include "ensure.h"
#include "fracture_patterns.h"
#include "gltf_internal.h"

// True when text is one strict JSON value.
static bool parses(const char* text) {
  bk_json_doc doc = {0};
  char why[160] = "";
  bool ok = bk_json_parse(text, strlen(text), &doc, why, sizeof why);
  bk_json_free(&doc);
  return ok;
}

// True when inf or nan stands outside a string (a key may well be "nan").
static bool bare_non_finite(const char* text) {
  bool in_string = false;
  for (const char* p = text; *p; ++p) {
    if (in_string) {
      if (*p == '\\' && p[1])
        ++p;
      else if (*p == '"')
        in_string = false;
    } else if (*p == '"') {
      in_string = true;
    } else if (strncmp(p, "inf", 3) == 0 || strncmp(p, "nan", 3) == 0 || strncmp(p, "INF", 3) == 0 ||
               strncmp(p, "NAN", 3) == 0) {
      return true;
    }
  }
  return false;
}

// The parser the checks below trust refuses what printf makes of non-finite numbers.
static void test_parser_refuses_inf_and_nan(void) {
  ENSURE(parses("{\"a\": 1.5, \"b\": null}"));
  ENSURE(bare_non_finite("{\"a\": -inf}") && bare_non_finite("[nan]") &&
         !bare_non_finite("{\"nan\": \"inf\"}"));
  const char* bad[] = {"{\"a\": inf}", "{\"a\": -inf}", "{\"a\": nan}", "{\"a\": -nan}", "{\"a\": 1e999x}"};
  for (size_t i = 0; i < sizeof bad / sizeof *bad; ++i)
    ENSURE_MSG(!parses(bad[i]), "parsed %s", bad[i]);
}

static void test_app_number_writer(void) {
  char text[48] = "";
  ENSURE(strcmp(app_json_text(text, sizeof text, "%.4f", 1.25), "1.2500") == 0);
  ENSURE(strcmp(app_json_text(text, sizeof text, "%.3e", 2.5e-7), "2.500e-07") == 0);
  const double bad[] = {INFINITY, -INFINITY, NAN, -NAN};
  for (int i = 0; i < 4; ++i) {
    ENSURE_MSG(strcmp(app_json_text(text, sizeof text, "%.4f", bad[i]), "null") == 0, "%g gave %s", bad[i],
               text);
    ENSURE(strcmp(BK_APP_JSON_NUMBER("%g", bad[i]), "null") == 0);
  }
  // Several in one printf, each with its own buffer.
  char line[200];
  snprintf(line, sizeof line, "{\"a\": %s, \"b\": %s, \"c\": %s}", BK_APP_JSON_NUMBER("%.4f", 1.0),
           BK_APP_JSON_NUMBER("%.3e", NAN), BK_APP_JSON_NUMBER("%g", 1e300 * 1e300));
  ENSURE_MSG(strcmp(line, "{\"a\": 1.0000, \"b\": null, \"c\": null}") == 0, "%s", line);
  ENSURE(parses(line));
  // The shortest-text writer too.
  FILE* f = tmpfile();
  ENSURE(f != NULL);
  app_json_number(f, NAN);
  fputc(' ', f);
  app_json_number(f, -INFINITY);
  rewind(f);
  char back[32] = "";
  ENSURE(fgets(back, sizeof back, f) && strcmp(back, "null null") == 0);
  fclose(f);
}

static void test_gltf_number_writer(void) {
  text_buffer t = {0};
  bk_tb_raw(&t, "[");
  bk_tb_doubles(&t, (const double[4]){0.5, INFINITY, NAN, -INFINITY}, 4);
  bk_tb_raw(&t, "]");
  ENSURE_MSG(strcmp(t.data, "[[0.5,null,null,null]]") == 0, "%s", t.data);
  ENSURE(parses(t.data));
  free(t.data);
}

#ifdef BK_BREAKABLES_EXE
#define RUN_STDERR_PATH BK_TEST_TMP "/test_json_output.stderr"
#include "run_exe.h"

static void expect_json(const char* args) {
  run_result* r = run(args);
  ENSURE_MSG(r->status == 0, "'%s' exited %d: %s", args, r->status, r->err);
  ENSURE_MSG(parses(r->out), "'%s' printed no JSON: %s", args, r->out);
  ENSURE_MSG(!bare_non_finite(r->out), "'%s': %s", args, r->out);
}

static void test_commands_print_json(void) {
  expect_json("sim --scene wall --pieces 16 --shots 1 --steps 40 --json");
  expect_json("sim --scene wall --pieces 16 --shots 0 --steps 1 --json"); // no breaks, no stress steps
  char args[1024];
  snprintf(args, sizeof args, "fracture --mesh cube --pieces 8 --json --out '%s/json_output.mtree'",
           BK_TEST_TMP);
  expect_json(args);
  snprintf(args, sizeof args, "sim --mesh '%s/json_output.mtree' --shots 1 --steps 30 --json", BK_TEST_TMP);
  expect_json(args);
  snprintf(args, sizeof args, "%s/json_output.mtree", BK_TEST_TMP);
  remove(args);
}
#endif

int main(void) {
  RUN(test_parser_refuses_inf_and_nan);
  RUN(test_app_number_writer);
  RUN(test_gltf_number_writer);
#ifdef BK_BREAKABLES_EXE
  RUN(test_commands_print_json);
#endif
  return 0;
}
