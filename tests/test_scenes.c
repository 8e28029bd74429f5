// The demo's scene table.
#include <string.h>

#include "ensure.h"
#include "scenes.h"

// Scene data: every scene is findable by name, and a scene's extra aim
// points each lie by a different one of its objects (so a volley in the
// showcase goes round all of them).
static void test_scene_targets(void) {
  ENSURE(bk_scene_count() >= 7);
  for (uint32_t i = 0; i < bk_scene_count(); ++i) {
    const bk_scene* scene = bk_scene_at(i);
    ENSURE(bk_scene_find(scene->name) == scene);
    ENSURE(scene->extra_target_count <= 7);
    bool used[8] = {false};
    for (uint32_t t = 0; t < scene->extra_target_count; ++t) {
      bk_vec3 aim = scene->extra_targets[t];
      int nearest = -1;
      double best = 1e30;
      for (uint32_t o = 0; o < scene->object_count; ++o) {
        bk_vec3 d = bk_v3_sub(aim, scene->objects[o].position);
        double horizontal = sqrt(d.x * d.x + d.z * d.z);
        if (horizontal < best) best = horizontal, nearest = (int)o;
      }
      ENSURE_MSG(nearest >= 0 && best < 0.6, "%s: aim point %u is %g m from any object", scene->name, t,
                 best);
      ENSURE_MSG(!used[nearest], "%s: two aim points at object %d", scene->name, nearest);
      used[nearest] = true;
    }
  }
  const bk_scene* showcase = bk_scene_find("showcase");
  ENSURE(showcase && showcase->extra_target_count + 1 == showcase->object_count);
}

int main(void) {
  test_scene_targets();
  return 0;
}
