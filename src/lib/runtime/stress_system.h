// runtime (private): the stress system of one cluster solved
// (stress_system.c) for the forces that hold the cluster's weight up on its
// supports; the system's data and its making are stress_setup.h's.
#pragma once

#include "stress_setup.h"

/// Loads the free nodes with their weight under gravity (tree frame) and,
/// when node_loads is not NULL, those forces and torques (6 per node, tree
/// frame), and restarts the iteration from the current x (making what is
/// left of the setup first, at once).
void rt_stress_load(rt_stress* system, bk_vec3 gravity, const double* node_loads);
/// Runs at most max_iterations conjugate-gradient steps, stopping once the
/// unbalanced force is at most tolerance x the load; returns those run.
uint32_t rt_stress_iterate(rt_stress* system, uint32_t max_iterations, double tolerance);
/// Loaded, and the unbalanced force is at most tolerance x the load.
bool rt_stress_converged(const rt_stress* system, double tolerance);
/// Bond evaluations one iteration costs (the unit of the runtime's budget);
/// the system must be ready.
uint64_t rt_stress_iteration_cost(const rt_stress* system);
/// Bond k's stress (Pa) at the current x: compression, tension, shear.
void rt_stress_bond_stress(const rt_stress* system, uint32_t k, double out[3]);
