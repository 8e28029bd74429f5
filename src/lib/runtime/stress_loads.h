// runtime (private): the loads a stress solve carries, from the caller's
// bk_stress_load entries to forces on a system's nodes (stress_loads.c).
#pragma once

#include "runtime_internal.h"

/// Maps the caller's loads to (cluster, leaf) entries, sorted, one per
/// leaf, into rt's load scratch; returns how many.
uint32_t rt_stress_gather_loads(bk_runtime* rt, const bk_stress_load* loads, uint32_t count);
/// Adds a cluster's loads of this call (sorted by leaf) to its window; once
/// the window spans enough calls, their average replaces the loads its
/// solve carries if it differs from them by more than a tenth of its weight
/// and loads (weight, N), and true is returned: the cluster must be loaded
/// again.
bool rt_stress_window_loads(rt_cluster* c, const rt_leaf_load* loads, uint32_t count, double weight);
/// The cluster's loads as forces on its system's nodes (6 per leaf, in the
/// order of its leaves), or NULL when it carries none; the caller frees it.
double* rt_stress_node_loads(const rt_cluster* c);
