// headless_wall: the whole Breakables pipeline in one file, with no window.
//
//   1. authoring: build a wall mesh and fracture it into 256 fragments (a
//      mesh tree: the wall at the root, the fragments at the leaves, bonds
//      between the fragments that touch);
//   2. bullet: put it in a bk_world, standing on the ground and anchored to
//      it, made of the "stone" material preset;
//   3. fire one projectile at it, step the world for two seconds and print
//      what broke: bonds, bodies, free fragments and the first break events.
//
// In a game the fracture would be baked offline (see examples/bake_and_load)
// and bk_world_step would run once per frame; everything else is the same.
#include <breakables/bullet.h>
#include <stdio.h>

enum { STEPS = 120, EVENTS_SHOWN = 5 }; // 120 steps of 1/60 s: two seconds

int main(void) {
  bk_error err = {0};

  // 1. The wall: 2 m wide, 1.2 m high, 0.2 m thick, standing on y = 0.
  bk_mesh wall = {0};
  bk_shape_build(BK_SHAPE_WALL, &wall);
  bk_fracture_def fracture = bk_default_fracture_def();
  fracture.pieces = 256;
  // Bias cuts along the wall's long axes: chunky bricks instead of thin plates.
  fracture.aspect_bias = 1.5;
  bk_mesh_tree tree = {0};
  if (!bk_mesh_tree_build(&wall, &fracture, &tree, &err)) {
    fprintf(stderr, "headless_wall: fracture failed: %s\n", err.message);
    return 1;
  }
  bk_mesh_free(&wall); // the tree keeps its own copy of the source at its root
  printf("fractured the wall: %u fragments, %u bonds\n", tree.leaf_count, tree.bond_count);

  // 2. A Bullet world with a ground plane at y = 0 (the default).
  bk_world_def world_def = bk_default_world_def();
  bk_world* world = bk_world_create(&world_def, &err);
  if (!world) {
    fprintf(stderr, "headless_wall: %s\n", err.message);
    return 1;
  }
  bk_world_breakable_def wall_def = bk_default_world_breakable_def();
  wall_def.breakable.tree = &tree; // borrowed: the tree must outlive the world
  wall_def.breakable.material = *bk_material_find("stone");
  // Fragments touching the ground are bonded to it, so the wall stands until
  // it is shot and pieces that lose their connection to the ground fall.
  wall_def.breakable.anchored = true;
  if (bk_breakable_is_null(bk_world_add_breakable(world, &wall_def, &err))) {
    fprintf(stderr, "headless_wall: %s\n", err.message);
    return 1;
  }
  bk_world_stats before = bk_world_get_stats(world);

  // 3. An 8 kg ball at 40 m/s, fired from 3 m in front of the wall at its middle.
  bk_projectile_def shot = bk_default_projectile_def();
  shot.position = bk_v3(0.0, 0.6, 3.0);
  shot.velocity = bk_v3(0.0, 0.0, -40.0);
  shot.radius = 0.1;
  shot.mass = 8.0;
  if (bk_body_is_null(bk_world_fire(world, &shot, &err))) {
    fprintf(stderr, "headless_wall: %s\n", err.message);
    return 1;
  }

  uint32_t events_shown = 0;
  for (int step = 1; step <= STEPS; ++step) {
    bk_world_step(world);
    // Break events are where to spawn dust and play sounds: each is one bond
    // that broke in the step just taken, at its world position. Damage falls
    // off with distance cubed, but a bond's hit points grow with its area, so
    // tiny slivers break even far from the hit.
    bk_break_event events[EVENTS_SHOWN];
    uint32_t count = bk_world_break_events(world, events, EVENTS_SHOWN);
    if (count == 0) continue;
    printf("step %3d (t = %.3f s): %u bonds broke\n", step, step * world_def.fixed_dt, count);
    for (uint32_t i = 0; i < count && i < EVENTS_SHOWN && events_shown < EVENTS_SHOWN; ++i, ++events_shown) {
      const bk_break_event* e = &events[i];
      printf("  bond %4u at (%+.2f, %+.2f, %+.2f), area %.2f cm^2, moving at %.2f m/s\n", e->bond,
             e->position.x, e->position.y, e->position.z, e->area * 1e4, bk_v3_length(e->velocity));
    }
  }

  bk_world_stats after = bk_world_get_stats(world);
  printf("after %.1f s: bonds broken %u of %u, bodies %u (was %u, %u dynamic), fragments free %u, "
         "splits %u, mass %.1f kg%s\n",
         STEPS * world_def.fixed_dt, after.bonds_broken, tree.bond_count, after.bodies, before.bodies,
         after.dynamic_bodies, after.fragments_free, after.break_events, after.total_mass,
         after.nan ? ", NaN in a body!" : "");

  bk_world_destroy(world); // first the world, then the tree it borrowed
  bk_mesh_tree_free(&tree);
  return after.bonds_broken > 0 && !after.nan ? 0 : 1;
}
