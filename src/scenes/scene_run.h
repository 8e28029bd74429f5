// A scene run in a world: the options over its defaults, how its objects
// are fractured and their trees cached, setting it up, shots and weights,
// and what a run measures (the debris seen, an impact's step times).
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include "app.h"
#include "scenes.h"

/// Builds the mesh tree of a mesh (scaled uniformly by `scale` when not 0 or
/// 1), or loads it from the cache directory ($BREAKABLES_CACHE_DIR, else
/// $XDG_CACHE_HOME/breakables, else ~/.cache/breakables) when a file made
/// from the same mesh and parameters is there; a fresh build is cached.
bool app_load_tree(const char* mesh_spec, double scale, const bk_fracture_def* desc, bk_mesh_tree* out,
                   bool* from_cache, bk_error* err);

/// Overrides for a scene's defaults (zero = the scene's or material's value).
typedef struct scene_options {
  uint32_t pieces;
  uint64_t seed;
  double texture_scale;
  const char* material; ///< a preset for every object (NULL = each object's own)
  /// A bk_fracture_pattern for every object, or -1 (the default) = each
  /// object's own (scene_object.pattern).
  int pattern;
  uint32_t clusters;     ///< clustered: large chunks (0 = the library's default)
  double cluster_border; ///< clustered: border width, a fraction of the size (0 = the library's default)
  double radial_falloff; ///< radial: how fast pieces grow with distance (< 0, the default: the library's)
  /// Rough cut faces: the noise amplitude as a fraction of each object's
  /// size, at four waves per size (0, the default: flat; brick stays flat).
  double noise;
  double frailty, density, bond_strength;
  int accumulate; ///< -1 = material's choice, 0 = discrete, 1 = accumulating
  bool naive, convex_colliders;
  double retire_volume; ///< world: loose fragments smaller than this (m^3) retire after 10 s; 0 = never
  bool stress;          ///< world: structural stress (what lost its support falls); default true
  /// Every material's stress limits times this (1, the default: as they are).
  double stress_scale;
  /// Stress limits (Pa) for every object, in place of the material's times
  /// stress_scale (0, the default: the material's).
  double compression_limit, tension_limit, shear_limit;
  /// world: the physics budget per step in ms (bk_world_def.physics_budget_ms;
  /// 0 = off); the default is the world's
  double physics_budget_ms;
  /// world: how long (s) a new piece keeps what the player sees of it under
  /// the budget (bk_world_def.budget_fidelity_time; sim --budget-fidelity);
  /// the default is the world's
  double budget_fidelity_time;
  /// world: how many times the budget a step may cost while new pieces keep
  /// that (bk_world_def.budget_fidelity_factor; sim --budget-fidelity-factor;
  /// 0 = no bound); the default is the world's
  double budget_fidelity_factor;
  /// Copies of the whole scene side by side along x (sim --copies; 1, the
  /// default: the scene alone), spaced so that they do not touch
  uint32_t copies;
  /// Refinement (--refine): every object's fragments are fractured again
  /// around the hits that strike them hard enough (scene_object_def sets
  /// the material's refine_strength and the breakable's refine def); off by
  /// default
  bool refine;
  /// Pieces per refinement (--refine-pieces), 2..1024; default 32
  uint32_t refine_pieces;
  /// Optional fracture progress report (leaves so far, target), from the building thread.
  bool (*progress)(void* user, uint32_t leaves, uint32_t target);
  void* progress_user;
} scene_options;

scene_options default_scene_options(void);

/// How object `object` of `scene` is fractured: pieces, seed and texture
/// scale from the options (else the scene's, and the library's
/// defaults), the pattern from options->pattern (else the object's), and the
/// pattern's parameters fitted to the object: a brick bond scaled with the
/// object so it stays on its texture, the game's fracture map
/// (app_cutout_map) for the cutout pattern, and a radial pattern's impact
/// at the object's aim point (scene_object_aim) taken into the frame of
/// its tree (the scaled mesh, placed by the object's position and rotation).
/// With `source`, the object's mesh as it is fractured (scene_object_source;
/// may be NULL), the impact moves along the line from the scene's eye through
/// the aim point to where that line first meets the surface, where the shot
/// lands; a user's model (fit_to_mesh) is placed by its bounds first.
bk_fracture_def scene_fracture_def(const app_scene* scene, uint32_t object, const scene_options* options,
                                   const bk_mesh* source);
/// The mesh an object's tree is cut from (app_load_mesh, scaled by the
/// object's scale); false when it is a tree file (loaded as it is) or cannot
/// be read (loading the tree then says why). Free it with bk_mesh_free.
bool scene_object_source(const scene_object* object, bk_mesh* out);
/// A 64-bit key of every parameter of `desc` that shapes a tree: pieces,
/// seed, texture scale, jitter, aspect bias, the pattern and all its
/// parameters, the seed points and fracture map themselves (not the
/// progress callback or the thread count, which change nothing in the
/// tree). Cache files are named by it, so another pattern or parameter never
/// loads a tree made for different ones.
uint64_t app_fracture_key(const bk_fracture_def* desc);

/// A scene set up in a world: its trees (owned) and breakables.
typedef struct loaded_scene {
  const app_scene* scene; ///< the scene, or `fitted` for a user's model (fit_to_mesh)
  app_scene fitted;
  bk_world* world;
  bk_mesh_tree trees[8];
  bk_breakable_id ids[8];
  uint32_t tree_count;
  bool from_cache; ///< a tree came from the cache directory
  /// options->copies: copy c > 0 of object i is copy_ids[(c - 1) * tree_count + i]
  /// (owned), placed copy_spacing m apart along x by copy_offset
  uint32_t copies;
  bk_breakable_id* copy_ids;
  double copy_spacing;
} loaded_scene;

/// The breakable of object `object` in copy `copy` (copy 0: ids[object]).
bk_breakable_id loaded_scene_id(const loaded_scene* scene, uint32_t copy, uint32_t object);
/// Fires shot number `shot` of the scene's volley (scene_shot) at every
/// copy in the same step; returns how many projectiles it fired.
uint32_t loaded_scene_fire(loaded_scene* scene, uint32_t shot, double speed);
/// Where copy `copy` of `copies` side by side is moved along x, `spacing`
/// m apart and centred on the original (which is copy (copies - 1) / 2 when
/// their number is odd).
double copy_offset(uint32_t copy, uint32_t copies, double spacing);
/// sim --copies: at most this many (a 16-wall scaling run, and room above).
enum { BK_COPIES_MAX = 64 };
/// --refine-pieces (sim, play): pieces per refinement, as bk_refine_def.pieces allows.
enum { BK_REFINE_PIECES_MIN = 2, BK_REFINE_PIECES_MAX = 1024, BK_REFINE_PIECES_DEFAULT = 32 };
/// What --refine does to an object's breakable: its material's
/// refine_strength from its bond strength (scene_object_def) and a radial
/// refinement of options->refine_pieces pieces. Nothing when refinement is off.
void scene_refine(bk_breakable_def* breakable, const scene_options* options);
/// --budget-ms (sim, play): the physics budget per step, 0 (off) .. this.
#define BK_BUDGET_MS_MAX 1000.0
/// Parses the value of --budget-ms for `command` into options->physics_budget_ms;
/// prints one line naming the option and returns false on a bad value.
bool app_parse_budget_ms(const char* command, const char* text, scene_options* options);
/// --budget-fidelity (sim): the first seconds a piece keeps under the budget, 0 .. this.
#define BK_BUDGET_FIDELITY_MAX 60.0
/// --budget-fidelity-factor (sim): 0 (no bound) or 1 .. this.
#define BK_BUDGET_FIDELITY_FACTOR_MAX 1000.0

/// A scene object's breakable: its placement and its material (the object's
/// preset, or options->material), with the options' overrides (options may be NULL).
bk_world_breakable_def scene_object_def(const scene_object* object, const bk_mesh_tree* tree,
                                        const scene_options* options);
/// Applies a material preset to every object of a loaded scene now, and makes
/// it the options' choice for the next load (clearing the other overrides).
void loaded_scene_apply_material(loaded_scene* scene, scene_options* options, const bk_material* material);
/// The first half of loaded_scene_create: the scene's trees, built (and
/// cached) or loaded from the cache, and no world. Pure authoring work, so
/// it may run on any thread while a world steps on another (the panel's
/// re-fracture); loaded_scene_destroy frees them.
bool loaded_scene_load_trees(const app_scene* scene, const scene_options* options, loaded_scene* out,
                             bk_error* err);
/// The scene's trees and a world holding its breakables. Creates a Bullet
/// world: call it from the thread that steps worlds (bullet.h).
bool loaded_scene_create(const app_scene* scene, const scene_options* options, loaded_scene* out,
                         bk_error* err);
void loaded_scene_destroy(loaded_scene* scene);
/// The i-th shot of a volley from the scene's eye towards (around) its target.
bk_projectile_def scene_shot(const app_scene* scene, uint32_t shot, double speed);

/// A weight set down on a scene (--drop KG, --drop-radius M, --drop-at
/// STEP): a ball of `kg` set at rest on the top surface over the first
/// object's aim point at step (sim) or frame (play) `at`, a load for the
/// structure to carry (see app_drop_weight).
typedef struct app_drop {
  double kg;     ///< 0: no weight
  double radius; ///< m
  uint64_t at;   ///< the step or frame it is set down
  bool radius_given, at_given;
} app_drop;

/// The options' ranges: from a sack to a loaded lorry and more (Bullet's
/// float masses stay meaningful against a 256-piece concrete deck of about
/// 12 t); a ball of 1 cm to 2 m; a step within what sim can run.
#define BK_DROP_KG_MIN 1.0
#define BK_DROP_KG_MAX 1e6
#define BK_DROP_RADIUS_MIN 0.01
#define BK_DROP_RADIUS_MAX 2.0
#define BK_DROP_RADIUS_DEFAULT 0.3
enum {
  BK_DROP_AT_DEFAULT = 60, ///< a second in: the structure has settled and been solved once
  BK_DROP_AT_MAX = 10000000,
};

app_drop default_drop(void);
/// Parses --drop, --drop-radius and --drop-at for `command`: returns 0 if
/// `argv[*i]` was one of them (consuming its value), 1 if not ours, 2 on a
/// bad value (one line printed, naming the option).
int parse_drop_option(const char* command, int argc, char** argv, int* i, app_drop* drop);
/// Refuses --drop-radius or --drop-at without --drop, and a drop at or past
/// `last` (the run's steps or frames, 0 = unbounded), named by
/// `last_option`, with one line printed.
bool check_drop(const char* command, const app_drop* drop, uint64_t last, const char* last_option);
/// The first surface straight down from `height` m above `point` (only a
/// breakable's, when breakables_only); false if the ray meets none.
bool app_top_surface(bk_world* world, bk_vec3 point, double height, bool breakables_only, bk_vec3* out);
/// Where a scene's weight goes: the top of its first object over that
/// object's aim point (else over the object's middle); false if neither is
/// over it.
bool scene_drop_point(loaded_scene* scene, bk_vec3* out);
/// Sets a ball of `kg` and `radius` at rest just above `surface` (a
/// projectile: it leaves after the world's projectile_lifetime, 8 s).
bool app_drop_weight(bk_world* world, bk_vec3 surface, double kg, double radius, bk_error* err);

/// What the player sees of the loose pieces, to compare a run under the
/// physics budget with one without: the simulated debris is every dynamic
/// breakable body still in the world (projectiles are not breakables';
/// retired pieces are gone; frozen ones are there, at rest).
typedef struct debris_sample {
  double mass;         ///< kg
  double momentum;     ///< sum of |m v| over the bodies (kg m/s): how much moves
  double net_momentum; ///< |sum of m v| (kg m/s): where it goes together
} debris_sample;

/// The simulated debris now, from the body views.
debris_sample debris_measure(bk_world* world);

enum {
  BK_FIDELITY_STEPS = 60, ///< the first second after a hit, in 60 Hz steps
};
/// The debris averaged over the first second after each hit: each hit's
/// own average, then the mean over hits (so overlapping seconds count once
/// per hit). Zero-initialise, then fidelity_step after every step.
typedef struct app_fidelity {
  uint32_t ending[BK_FIDELITY_STEPS]; ///< hits whose second ends at a step, by step % BK_FIDELITY_STEPS
  uint32_t open;                      ///< hits whose second is running
  double weight;                      ///< hit-steps summed
  debris_sample sum;                  ///< weighted sums
  debris_sample near_sum;             ///< the same, of the debris near the focus only
} app_fidelity;

/// Whether a step had break work, the steps whose break handling (damage,
/// splits, body removal and creation: bk_world_stats.fracture_ms) sim and
/// bench take percentiles of: bonds broke, a body split, or hits or splits
/// waited for the world's budgets before it.
bool break_step(const bk_world_stats* before, const bk_world_stats* now);

/// Takes the step just run, `hits` being the shots fired just before it.
void fidelity_step(app_fidelity* f, bk_world* world, uint64_t step, uint32_t hits);
/// The averages (zero when there was no hit).
debris_sample fidelity_mean(const app_fidelity* f);
/// The averages of the debris within bk_world_budget_fidelity_radius of the
/// world's focus (what the player sees up close; all of it with no focus).
debris_sample fidelity_near_mean(const app_fidelity* f);

enum {
  BK_IMPACT_STEADY_STEPS = 30, ///< steps before the shot, and the last steps, for steady-state medians
};
/// Metres between the centres of copies side by side.
#define BK_IMPACT_SPACING 2.5

/// One simulated impact: `copies` of a scene's first object side by side
/// (BK_IMPACT_SPACING apart along x), one shot at each after BK_IMPACT_STEADY_STEPS steps.
typedef struct app_impact {
  const app_scene* scene;
  const bk_mesh_tree* tree;
  uint32_t copies;
  bool naive;
  uint32_t steps_after; ///< steps from the shot on (at least BK_IMPACT_STEADY_STEPS)
} app_impact;

typedef struct impact_result {
  double before_ms;                 ///< median step over the steady steps before the shot
  double after_ms;                  ///< median step over the last steady steps
  double hit_median_ms;             ///< median step from the shot on
  double hit_step_ms;               ///< worst step from the shot on
  double hit_physics_ms;            ///< worst physics part of a step from the shot on
  double hit_break_ms;              ///< worst break handling of a step from the shot on
  uint32_t bodies, colliders;       ///< breakable bodies and their colliders at the end
  double start_rss_mb, peak_rss_mb; ///< set when run in a separate process
  bool nan;
} impact_result;

/// The mesh tree of a scene's first object at this fragment count (cached).
bool app_load_scene_tree(uint64_t seed, const app_scene* scene, uint32_t pieces, bk_mesh_tree* tree,
                         bk_error* err);
/// Runs an impact in a fresh world.
bool impact_run(const app_impact* setup, impact_result* out, bk_error* err);
