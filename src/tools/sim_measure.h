// breakables sim's measures of a run (cmd_sim.c reports them): fragments,
// their heights and falls, the trees as they stand, the patterns.
#pragma once

#include <stdbool.h>

#include "app.h"
#include "scene_run.h"

/// The patterns the objects' trees were made with: JSON members or a line of text.
void sim_print_patterns(const loaded_scene* s, bool json);
/// Fragments of one copy of the scene (the copies have the same trees).
uint32_t sim_fragments_of(const loaded_scene* s);
/// Every fragment's height now, object after object, copy after copy (bk_free it).
double* sim_heights_of(const loaded_scene* s);
/// How each breakable's tree frame was turned at the start (bk_free it).
bk_quat* sim_start_rotations(const loaded_scene* s);
/// Fragments whose centroid ended more than 0.5 m below where it started.
uint32_t sim_fragments_fallen(const loaded_scene* s, const double* rest_heights, const bk_quat* rotations);
/// Fragments of every object's tree as it is now (refinement grows them).
uint32_t sim_leaves_now(const loaded_scene* s);
/// The first object's tree as it stands now, to the files asked for; false
/// (one line printed) at the first that cannot be written.
bool sim_export_first_tree(const loaded_scene* s, const char* obj_path, const char* gltf_path);
