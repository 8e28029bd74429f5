// Every public header compiles as C++ (pedantic, no compound literals) and
// its inline math gives the C results: engines and tools written in C++
// include them directly.
#include <breakables/authoring.h>
#include <breakables/base.h>
#include <breakables/runtime.h>
#include <breakables/types.h>
#if BK_TEST_BULLET
#include <breakables/bullet.h>
#endif

#include <cstdio>
#include <cstdlib>

#define CHECK(cond)                                                                                          \
  do {                                                                                                       \
    if (!(cond)) {                                                                                           \
      std::fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);                          \
      std::exit(1);                                                                                          \
    }                                                                                                        \
  } while (0)

int main() {
  bk_vec3 c = bk_v3_cross(bk_v3(1, 0, 0), bk_v3(0, 1, 0));
  CHECK(c.x == 0.0 && c.y == 0.0 && c.z == 1.0);
  bk_quat q = bk_quat_axis_angle(bk_v3(0, 0, 1), 1.5707963267948966);
  bk_vec3 r = bk_quat_rotate(q, bk_v3(1, 0, 0));
  CHECK(std::abs(r.y - 1.0) < 1e-12 && std::abs(r.x) < 1e-12);
  bk_transform t = bk_transform_mul(bk_transform_identity(), bk_transform{{1, 2, 3}, bk_quat_identity()});
  CHECK(t.position.z == 3.0);
  bk_runtime_def def = bk_default_runtime_def();
  CHECK(def.max_new_clusters_per_split == 48);
  bk_mesh mesh = {};
  bk_shape_build(BK_SHAPE_CUBE, &mesh);
  CHECK(std::abs(bk_mesh_volume(&mesh) - 1.0) < 1e-12);
  bk_mesh_free(&mesh);
  bk_rng rng = bk_rng_seed(1, 2);
  double u = bk_rng_unit(&rng);
  CHECK(u >= 0.0 && u < 1.0);
  void* block = bk_alloc(16);
  CHECK(block != nullptr && bk_allocation_count() == 1);
  bk_free(block);
  CHECK(bk_allocation_count() == 0);
  return 0;
}
