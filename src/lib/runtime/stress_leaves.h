// runtime (private): the per-leaf data of a breakable that its stress
// solves and their supports and loads are made of (stress_leaves.c).
#pragma once

#include "runtime_internal.h"

/// The per-leaf data stress solves need (centroids, volumes, warm starts),
/// made once per breakable.
void rt_stress_prepare_breakable(rt_breakable* b);
/// The leaf of a cluster nearest a point of the tree frame.
uint32_t rt_stress_leaf_at(const rt_breakable* b, const rt_cluster* c, bk_vec3 point);
