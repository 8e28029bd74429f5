// The physics budget on the command line, run as a user would: sim and
// play's --budget-ms, sim's --copies and --budget-fidelity, and what sim
// --json reports of the budget (its tiers, the mass it retired, the debris
// the player sees).
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "ensure.h"

#define RUN_STDERR_PATH BK_TEST_TMP "/cli_budget_stderr.txt"
#include "run_exe.h"

#include "cli_util.h"

static char first[1 << 16];

static void test_errors(void) {
  static const struct {
    const char* args;
    const char* message;
  } refused[] = {
      {"sim --budget-ms -1", "breakables sim: --budget-ms '-1' is out of range (0..1000)"},
      {"sim --budget-ms 1001", "breakables sim: --budget-ms '1001' is out of range (0..1000)"},
      {"sim --budget-ms nan", "breakables sim: --budget-ms 'nan' is not a decimal number (0..1000)"},
      {"sim --budget-ms 5ms", "breakables sim: --budget-ms '5ms' is not a decimal number (0..1000)"},
      {"sim --budget-ms", "breakables sim: --budget-ms needs a value"},
      {"sim --budget-fidelity-factor 0.5",
       "breakables sim: --budget-fidelity-factor '0.5' is out of range (0, or 1..1000)"},
      {"sim --budget-fidelity-factor 1001",
       "breakables sim: --budget-fidelity-factor '1001' is out of range (0..1000)"},
      {"play --budget-ms 2000", "breakables play: --budget-ms '2000' is out of range (0..1000)"},
      {"play --budget-ms -0.5", "breakables play: --budget-ms '-0.5' is out of range (0..1000)"},
      {"sim --copies 0", "breakables sim: --copies '0' is out of range (1..64)"},
      {"sim --copies 65", "breakables sim: --copies '65' is out of range (1..64)"},
      {"sim --copies 2x", "breakables sim: --copies '2x' is not a whole number (1..64)"},
      {"sim --budget-fidelity -1", "breakables sim: --budget-fidelity '-1' is out of range (0..60)"},
      {"sim --budget-fidelity 61", "breakables sim: --budget-fidelity '61' is out of range (0..60)"},
      {"sim --budget-fidelity 1s", "breakables sim: --budget-fidelity '1s' is not a decimal number (0..60)"},
      {"sim --budget-fidelity", "breakables sim: --budget-fidelity needs a value"},
  };
  for (size_t i = 0; i < sizeof refused / sizeof *refused; ++i)
    expect_error(refused[i].args, 2, refused[i].message);
  run_result* r = run("sim --help");
  ENSURE(strstr(r->out, "--budget-ms X") && strstr(r->out, "--copies N") &&
         strstr(r->out, "--budget-fidelity S") && strstr(r->out, "debris_momentum_1s"));
  r = run("play --help");
  ENSURE(strstr(r->out, "--budget-ms X") != NULL);
}

// N copies: N times the fragments and bodies, each copy hit by the same shot.
static void test_copies(void) {
  run_result* r = run("sim --scene wall --pieces 64 --shots 1 --steps 90 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  double pieces = json_number(r->out, "pieces"), bonds = json_number(r->out, "bonds_broken");
  double mass = json_number(r->out, "debris_mass_1s");
  ENSURE(json_number(r->out, "copies") == 1.0 && pieces >= 64.0 && bonds > 0.0 && mass > 0.0);
  r = run("sim --scene wall --pieces 64 --shots 1 --steps 90 --copies 3 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE(json_number(r->out, "copies") == 3.0);
  ENSURE_MSG(json_number(r->out, "pieces") == 3.0 * pieces, "%s", r->out);
  ENSURE(json_number(r->out, "bodies_initial") == 3.0 && json_number(r->out, "colliders_initial") == 3.0);
  // Every copy broke (the copies stand apart, so each breaks about as the one alone does).
  ENSURE_MSG(json_number(r->out, "bonds_broken") > 2.0 * bonds, "%s", r->out);
  ENSURE(json_number(r->out, "debris_mass_1s") > 2.0 * mass);
  ENSURE(strstr(r->out, "\"nan\": false") != NULL);
  // Copies apply to every object of a scene of several.
  r = run("sim --scene showcase --pieces 16 --shots 0 --steps 1 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  double objects = json_number(r->out, "bodies_initial");
  r = run("sim --scene showcase --pieces 16 --shots 0 --steps 1 --copies 2 --json");
  ENSURE_MSG(r->status == 0 && json_number(r->out, "bodies_initial") == 2.0 * objects, "%s", r->out);
}

static const char* const tier_keys[] = {"budget_debris",  "budget_simplified", "budget_frozen",
                                        "budget_retired", "budget_demotions",  "budget_restorations"};

// The JSON with its timings (members named *_ms*) and from_cache left out.
static void strip_timings(const char* json, char* out, size_t size) {
  size_t used = 0;
  const char* at = json;
  while (*at && used + 1 < size) {
    const char* key = strstr(at, "\"");
    if (!key) break;
    const char* end = strchr(key + 1, '"');
    ENSURE(end != NULL);
    const char* next = strstr(end, ", \"");
    size_t length = next ? (size_t)(next - key) : strlen(key);
    bool timing = false;
    for (const char* c = key; c < end; ++c)
      timing = timing || strncmp(c, "_ms", 3) == 0;
    timing = timing || strncmp(key, "\"from_cache\"", 12) == 0;
    if (!timing && used + length + 1 < size) {
      memcpy(out + used, key, length);
      used += length;
      out[used++] = '|';
    }
    if (!next) break;
    at = next + 2;
  }
  out[used] = 0;
}

// A budget far below what the breaks cost: every tier is used, and the
// same inputs make the same decisions (the cost is estimated from counts).
static void test_budget_json(void) {
  const char* args = "sim --scene wall --pieces 512 --shots 3 --steps 200 --budget-ms 0.3 --json";
  run_result* r = run(args);
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE(json_number(r->out, "budget_ms") == 0.3);
  double tiers = 0.0;
  for (size_t i = 0; i < 4; ++i)
    tiers += json_number(r->out, tier_keys[i]);
  ENSURE_MSG(tiers > 0.0 && json_number(r->out, "budget_demotions") > 0.0, "%s", r->out);
  // Retired pieces have left the world, not the books.
  ENSURE_MSG(json_number(r->out, "budget_retired") > 0.0 && json_number(r->out, "mass_retired") > 0.0,
             "no piece retired: %s", r->out);
  ENSURE_MSG(json_number(r->out, "mass_rel_error") < 1e-9, "%s", r->out);
  const char* timings[] = {"step_ms_p95", "physics_ms_median", "physics_ms_p95", "physics_ms_max"};
  for (size_t i = 0; i < 4; ++i)
    ENSURE(json_number(r->out, timings[i]) >= 0.0);
  ENSURE(json_number(r->out, "physics_ms_p95") <= json_number(r->out, "physics_ms_max"));
  ENSURE(json_number(r->out, "physics_ms_median") <= json_number(r->out, "physics_ms_p95"));
  ENSURE(json_number(r->out, "step_ms_p95") <= json_number(r->out, "step_ms_max"));
  double mass_on = json_number(r->out, "debris_mass_1s");
  // The wall stands within budget_fidelity_radius (8 m) of the eye: its debris is all near.
  ENSURE_MSG(json_number(r->out, "debris_near_mass_1s") > 0.0 &&
                 json_number(r->out, "debris_near_mass_1s") <= mass_on * (1.0 + 1e-12) &&
                 json_number(r->out, "debris_near_momentum_1s") <=
                     json_number(r->out, "debris_momentum_1s") * (1.0 + 1e-12),
             "%s", r->out);
  strip_timings(r->out, first, sizeof first);
  ENSURE(strstr(first, "budget_retired") != NULL && strstr(first, "physics_ms") == NULL);

  // Again: every number but the timings is the same.
  r = run(args);
  ENSURE_MSG(r->status == 0, "%s", r->err);
  static char second[1 << 16];
  strip_timings(r->out, second, sizeof second);
  ENSURE_MSG(strcmp(first, second) == 0, "two runs differ:\n%s\n%s", first, second);

  // Without a budget nothing is made cheaper, and nothing is lost.
  r = run("sim --scene wall --pieces 512 --shots 3 --steps 200 --budget-ms 0 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  for (size_t i = 0; i < sizeof tier_keys / sizeof *tier_keys; ++i)
    ENSURE_MSG(json_number(r->out, tier_keys[i]) == 0.0, "%s without a budget: %s", tier_keys[i], r->out);
  ENSURE(json_number(r->out, "budget_ms") == 0.0 && json_number(r->out, "mass_retired") == 0.0);
  ENSURE(json_number(r->out, "mass_rel_error") < 1e-9);
  // The budget retired pieces in the first second: less debris is simulated.
  double mass_off = json_number(r->out, "debris_mass_1s");
  ENSURE_MSG(mass_off > 0.0 && mass_on < mass_off, "debris %g kg with the budget, %g without", mass_on,
             mass_off);
  // No shot, no second after one.
  r = run("sim --scene wall --pieces 64 --shots 0 --steps 30 --json");
  ENSURE_MSG(r->status == 0 && json_number(r->out, "debris_mass_1s") == 0.0, "%s", r->out);
}

// --budget-fidelity: for its seconds a new piece near the eye (within the
// world's budget_fidelity_radius, 8 m) is never retired, so what the player
// sees of one hit stays; at 0 the budget may take pieces at once. (Bricks
// the shot throws past 8 m are fair game either way.)
// With no bound on what keeping it costs (--budget-fidelity-factor 0); the
// default bound, 4 times the 0.3 ms budget, is far below what the hit
// costs, and the pieces give their second up.
static void test_budget_fidelity(void) {
  const char* args =
      "sim --scene wall --pieces 512 --shots 1 --steps 120 --budget-ms 0.3 --budget-fidelity-factor 0 --json";
  run_result* r = run(args);
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE(json_number(r->out, "budget_fidelity_s") == 1.0); // the world's default
  ENSURE(json_number(r->out, "budget_fidelity_factor") == 0.0);
  double kept = json_number(r->out, "debris_mass_1s"), kept_retired = json_number(r->out, "budget_retired");
  r = run("sim --scene wall --pieces 512 --shots 1 --steps 120 --budget-ms 0.3 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE(json_number(r->out, "budget_fidelity_factor") == 2.0); // the world's default
  ENSURE_MSG(json_number(r->out, "budget_retired") > kept_retired,
             "%g pieces retired under the default bound, %g with none: %s",
             json_number(r->out, "budget_retired"), kept_retired, r->out);
  r = run("sim --scene wall --pieces 512 --shots 1 --steps 120 --budget-ms 0.3 --budget-fidelity 0 "
          "--budget-fidelity-factor 0 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE(json_number(r->out, "budget_fidelity_s") == 0.0);
  ENSURE_MSG(json_number(r->out, "budget_retired") > kept_retired,
             "%g pieces retired at --budget-fidelity 0, %g at 1: %s", json_number(r->out, "budget_retired"),
             kept_retired, r->out);
  double taken = json_number(r->out, "debris_mass_1s");
  ENSURE_MSG(taken < 0.6 * kept, "debris %g kg in the first second at --budget-fidelity 0, %g at 1", taken,
             kept);
}

int main(void) {
  setenv("BREAKABLES_CACHE_DIR", BK_TEST_TMP "/cache", 1);
  RUN(test_errors);
  RUN(test_copies);
  RUN(test_budget_json);
  RUN(test_budget_fidelity);
  return 0;
}
