// The runtime's def: its checks, shared by bk_runtime_create and every def
// that contains one (the Bullet world's names it "world: runtime.<field>").
#include "runtime_internal.h"

bool bk_runtime_def_validate(const bk_runtime_def* def, const char* prefix, bk_error* err) {
  if (!prefix) prefix = "";
  if (!def) return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "%sdef is NULL", prefix);
  if (!def->body_state)
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "%sbody_state must be set (the runtime asks it where clusters are)", prefix);
  if (!(def->impact_speed >= 0.0) || !isfinite(def->impact_speed))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "%simpact_speed must be finite and >= 0 (got %g)", prefix, def->impact_speed);
  if (!(def->impulse_threshold >= 0.0) || !isfinite(def->impulse_threshold))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "%simpulse_threshold must be finite and >= 0 (got %g)", prefix,
                             def->impulse_threshold);
  if (!(def->damage_min_distance > 0.0) || !isfinite(def->damage_min_distance))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "%sdamage_min_distance must be positive (got %g)", prefix,
                             def->damage_min_distance);
  if (def->max_new_clusters_per_split < 2)
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "%smax_new_clusters_per_split must be at least 2 (got %u)", prefix,
                             def->max_new_clusters_per_split);
  if (def->stress_budget < 1)
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "%sstress_budget must be at least 1 (got %u)",
                             prefix, def->stress_budget);
  if (!(def->stress_tolerance > 0.0 && def->stress_tolerance <= 0.1))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "%sstress_tolerance must be in (0, 0.1] (got %g)", prefix,
                             def->stress_tolerance);
  if (!(def->stress_rest_speed >= 0.0) || !isfinite(def->stress_rest_speed))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "%sstress_rest_speed must be finite and >= 0 (got %g)", prefix,
                             def->stress_rest_speed);
  if (!bk_v3_is_finite(def->gravity))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "%sgravity must be finite", prefix);
  if (def->refine_latency > 8)
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "%srefine_latency must be in [0, 8] (got %u)",
                             prefix, def->refine_latency);
  if (def->refine_threads > 64)
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "%srefine_threads must be in [0, 64] (got %u)",
                             prefix, def->refine_threads);
  if (def->max_refinements_per_call < 1)
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "%smax_refinements_per_call must be at least 1 (got %u)", prefix,
                             def->max_refinements_per_call);
  return true;
}
