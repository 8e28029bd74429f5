// own_physics: the Breakables runtime driven by your own physics engine.
// breakables::runtime knows fragments, bonds and clusters (a cluster is a
// connected set of fragments: one rigid body) but never moves anything and
// links no physics engine. Your engine's side of the contract:
//   - one body per cluster: create it when bk_runtime_created_clusters says,
//     destroy it when bk_runtime_removed_clusters says. Those events (and the
//     broken bonds) accumulate over the runtime's calls until you clear them:
//     take them once a step, after its last runtime call, then
//     bk_runtime_clear_events;
//   - answer the body_state callback: where a cluster's body is, how it moves;
//   - feed damage (contacts or blasts), then call bk_runtime_split.
// Each cluster carries a pointer of yours (its user data: here its body) and
// each breakable one (here its name), handed back in every event.
// The "engine" here is gravity, Euler steps and a crude floor: a spinning glass cube is hit by a
// scripted contact, an anchored stone wall by a blast. Two runs print the same, digit for digit.
#include <breakables/runtime.h>
#include <stdio.h>
#include <stdlib.h>

enum { MAX_BODIES = 1024 }; // cluster indices stay below the most clusters alive at once

// One body of "your" engine, stored at its cluster's index: the runtime
// reuses the indices of removed clusters, so a flat array stays small.
typedef struct body {
  bool alive, is_static;
  double mass, radius; // radius: a rough size, only for the floor
  bk_vec3 position;    // the cluster's centre of mass, in the world
  bk_quat orientation; // its principal axes, in the world
  bk_vec3 velocity, angular_velocity;
} body;
static body bodies[MAX_BODIES];

static bk_body_state body_state(bk_cluster_id cluster, void* context) {
  (void)context; // a real engine would pass itself here (bk_runtime_def.context)
  const body* b = &bodies[cluster.index];
  return (bk_body_state){{b->position, b->orientation}, b->velocity, b->angular_velocity};
}

// Once a step, after the runtime's calls of that step: the events since the
// last take. Removed ones first: a created one may reuse its index.
static void take_events(bk_runtime* runtime, const char* why) {
  static bk_cluster_removed removed[MAX_BODIES];
  static bk_cluster_created created[MAX_BODIES];
  static bk_bond_break broken[4 * MAX_BODIES];
  uint32_t removed_count = bk_runtime_removed_clusters(runtime, removed, MAX_BODIES);
  uint32_t created_count = bk_runtime_created_clusters(runtime, created, MAX_BODIES);
  uint32_t broken_count = bk_runtime_broken_bonds(runtime, broken, 4 * MAX_BODIES);
  if (removed_count > MAX_BODIES || created_count > MAX_BODIES || broken_count > 4 * MAX_BODIES)
    fprintf(stderr, "too many events\n"), exit(1);
  if (bk_runtime_cluster_capacity(runtime) > MAX_BODIES) fprintf(stderr, "too many bodies\n"), exit(1);
  if (broken_count) { // e.g. dust where they broke; here, which object
    double area = 0.0;
    for (uint32_t i = 0; i < broken_count; ++i)
      area += broken[i].area;
    printf("%s: %u bonds of the %s broke (%.3f m^2)\n", why, broken_count,
           (const char*)broken[0].breakable_user_data, area);
  }
  for (uint32_t i = 0; i < removed_count; ++i)
    ((body*)removed[i].user_data)->alive = false; // the body we gave it
  if (created_count) printf("%s: %u clusters removed, %u created\n", why, removed_count, created_count);
  for (uint32_t i = 0; i < created_count; ++i) {
    const bk_cluster_info* c = &created[i].cluster;
    body* b = &bodies[c->id.index];
    // A new cluster starts with its parent's user data: give it its own body.
    bk_runtime_set_cluster_user_data(runtime, c->id, b);
    *b = (body){.alive = true, .is_static = c->is_static, .mass = c->mass, .radius = 0.5 * cbrt(c->volume)};
    b->position = created[i].body.transform.position;
    b->orientation = created[i].body.transform.rotation;
    b->velocity = created[i].body.linear_velocity; // its parent's motion at its own centre: v + w x r
    b->angular_velocity = created[i].body.angular_velocity;
    printf("  cluster %2u%s: %2u fragments, %7.2f kg, centre (%+.3f, %+.3f, %+.3f), nodes {", c->id.index,
           c->is_static ? " (static)" : "", c->leaf_count, c->mass, b->position.x, b->position.y,
           b->position.z);
    for (uint32_t n = 0; n < c->node_count; ++n)
      printf(n ? " %u" : "%u", c->nodes[n]);
    printf("}\n");
  }
  bk_runtime_clear_events(runtime); // taken: the next ones start afresh
}

// Semi-implicit Euler under gravity; a floor at y = 0 stops bodies dead.
static void integrate(double dt) {
  const double h = 0.5 * dt;
  for (uint32_t i = 0; i < MAX_BODIES; ++i) {
    body* b = &bodies[i];
    if (!b->alive || b->is_static) continue; // static clusters hold anchored fragments
    b->velocity.y -= 9.81 * dt;
    b->position = bk_v3_add(b->position, bk_v3_scale(b->velocity, dt));
    bk_vec3 w = b->angular_velocity; // dq/dt = 0.5 (w, 0) q
    bk_quat q = b->orientation, dq = bk_quat_mul((bk_quat){h * w.x, h * w.y, h * w.z, 0.0}, q);
    b->orientation = bk_quat_normalize((bk_quat){q.x + dq.x, q.y + dq.y, q.z + dq.z, q.w + dq.w});
    if (b->position.y < b->radius) {
      b->position.y = b->radius;
      b->velocity = b->angular_velocity = bk_v3(0.0, 0.0, 0.0);
    }
  }
}

// After damage: split clusters into connected parts, then take the step's events.
static void break_apart(bk_runtime* runtime, int step, const char* what) {
  printf("step %d: %s\n", step, what);
  bk_runtime_split(runtime);
  take_events(runtime, "split");
}

static bk_breakable_id add(bk_runtime* runtime, bk_mesh_tree* tree, bk_shape shape, uint32_t pieces,
                           const char* material, bk_vec3 position, bool anchored) {
  bk_mesh mesh = {0};
  bk_shape_build(shape, &mesh);
  bk_fracture_def fracture = bk_default_fracture_def(); // a fixed seed: the same tree every run
  fracture.pieces = pieces;
  bk_error err = {0};
  if (!bk_mesh_tree_build(&mesh, &fracture, tree, &err)) fprintf(stderr, "%s\n", err.message), exit(1);
  bk_mesh_free(&mesh);
  bk_breakable_def def = bk_default_breakable_def();
  def.tree = tree; // borrowed: must outlive the runtime
  def.material = *bk_material_find(material);
  def.transform.position = position;
  def.anchored = anchored; // fragments touching y = 0 (up: against gravity) are bonded to the world
  def.user_data = (void*)bk_shape_name(shape); // handed back in its events
  bk_breakable_id id = bk_runtime_add_breakable(runtime, &def, &err);
  if (bk_breakable_is_null(id)) fprintf(stderr, "%s (%s)\n", err.message, bk_result_name(err.code)), exit(1);
  take_events(runtime, bk_shape_name(shape));
  return id;
}

int main(void) {
  bk_runtime_def runtime_def = bk_default_runtime_def();
  runtime_def.body_state = body_state;
  bk_error err = {0};
  bk_runtime* runtime = bk_runtime_create(&runtime_def, &err);
  if (!runtime) return fprintf(stderr, "%s (%s)\n", err.message, bk_result_name(err.code)), 1;
  // A 1 m glass cube let go 1.5 m up, and a stone wall 3 m away, anchored.
  bk_mesh_tree cube_tree = {0}, wall_tree = {0};
  bk_breakable_id cube = add(runtime, &cube_tree, BK_SHAPE_CUBE, 32, "glass", bk_v3(0.0, 1.5, 0.0), false);
  add(runtime, &wall_tree, BK_SHAPE_WALL, 32, "stone", bk_v3(3.0, 0.0, 0.0), true);
  bodies[bk_runtime_leaf_cluster(runtime, cube, 0).index].angular_velocity = bk_v3(0.0, 3.0, 0.0); // tossed
  for (int step = 1; step <= 90; ++step) { // 1.5 s at 60 Hz
    if (step == 20) {
      // Your collision detection found a 20 kg cannonball hitting the cube's
      // +x face at 40 m/s. The runtime only breaks bonds: pushing is yours.
      bk_cluster_id hit = bk_runtime_leaf_cluster(runtime, cube, 0); // the cube is one cluster yet
      body* b = &bodies[hit.index];
      bk_damage_contact contact = {hit, bk_v3_add(b->position, bk_v3(0.5, 0.0, 0.0)), 800.0, 40.0};
      b->velocity.x -= contact.impulse / b->mass;
      bk_runtime_apply_contacts(runtime, &contact, 1);
      break_apart(runtime, step, "a cannonball hits the cube"); // the parts keep the cube's new motion
    }
    if (step == 45) { // a scripted blast damages every cluster, without the contact thresholds
      bk_runtime_damage_at(runtime, bk_v3(3.0, 0.3, 0.2), 3000.0);
      break_apart(runtime, step, "a blast at the foot of the wall");
    }
    integrate(1.0 / 60.0);
  }
  // A summary two runs must agree on, bit for bit (printed to 9 digits).
  bk_cluster_id live[MAX_BODIES];
  uint32_t live_count = bk_runtime_clusters(runtime, live, MAX_BODIES);
  double total_mass = 0.0, checksum = 0.0;
  for (uint32_t i = 0; i < live_count && i < MAX_BODIES; ++i) { // our bodies, in cluster order
    const body* b = &bodies[live[i].index];
    total_mass += b->mass;
    checksum += (i + 1) * (b->position.x + 2.0 * b->position.y + 3.0 * b->position.z + b->orientation.w);
  }
  bk_runtime_stats stats = bk_runtime_get_stats(runtime);
  printf("summary: clusters %u, bonds broken %u, splits %u, total mass %.6f kg, checksum %.9f\n", live_count,
         stats.bonds_broken, stats.splits, total_mass, checksum);
  bk_runtime_destroy(runtime); // before the trees it borrowed
  bk_mesh_tree_free(&cube_tree);
  bk_mesh_tree_free(&wall_tree);
  return 0;
}
