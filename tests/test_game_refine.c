// The game with refinement (play --refine). Trees that grow while the game
// runs, drawn: the renderer appends a grown tree's new nodes (made ready by
// renderer_build_nodes, appended by renderer_append_nodes), and the game
// makes them ready after each step and uploads them before drawing
// (grown_trees_build, grown_trees_upload). Read back from the GPU, every
// node's index ranges (outer surface, cut faces, both coarse copies) name
// only vertices of that node, its mesh's triangles in order with their
// positions and normals; what was uploaded before a growth stays byte for
// byte; the node table and the bounding spheres cover every node. In a world
// whose wall refines where it is shot, the uploaded node count equals the
// runtime's tree's after every upload, every body's nodes are uploaded, and
// the pieces the world retires are all kept to fade out. The panel's switch
// turns refinement on and off live, its strength following the bond
// strength. Needs a GL context: without a display the test runs itself
// again under xvfb-run.
#define GLFW_INCLUDE_NONE // the GL declarations are glad's (render_internal.h)
#include <GLFW/glfw3.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>

#include <breakables/bullet.h>

#include "ensure.h"
#include "game_budget.h"
#include "grown_trees.h"
#include "panel_refine.h"
#include "render_internal.h"
#include "shape_tree.h"

static app_renderer* renderer;

static double now_ms(void) {
  struct timespec t = {0};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

// The GPU's copy of a buffer's first `bytes`.
static void* read_buffer(GLuint buffer, size_t bytes) {
  void* data = malloc(bytes + 1);
  ENSURE(data);
  glBindBuffer(GL_COPY_READ_BUFFER, buffer);
  glGetBufferSubData(GL_COPY_READ_BUFFER, 0, (GLsizeiptr)bytes, data);
  glBindBuffer(GL_COPY_READ_BUFFER, 0);
  return data;
}

static GLint buffer_size(GLuint buffer) {
  GLint size = 0;
  glBindBuffer(GL_COPY_READ_BUFFER, buffer);
  glGetBufferParameteriv(GL_COPY_READ_BUFFER, GL_BUFFER_SIZE, &size);
  glBindBuffer(GL_COPY_READ_BUFFER, 0);
  return size;
}

// A node's range of `count` indices from `first` names its own vertices only.
static void check_range(const tree_buffers* t, const vertex* vertices, const uint32_t* indices, uint32_t node,
                        uint32_t first, uint32_t count) {
  ENSURE_MSG(count % 3 == 0 && first + count <= t->index_total, "node %u: range %u + %u of %u", node, first,
             count, t->index_total);
  for (uint32_t j = 0; j < count; ++j) {
    uint32_t v = indices[first + j];
    ENSURE_MSG(v < t->vertex_count && vertices[v].node == node,
               "node %u: index %u names vertex %u of node %u", node, first + j, v,
               v < t->vertex_count ? vertices[v].node : UINT32_MAX);
  }
}

// Reads a tree's buffers back and checks every node against `tree`: its
// detailed ranges are its mesh's triangles of that section in order, its
// coarse ones name its vertices, its sphere holds its points; the VAO
// reads the tree's buffers and the node table has a row per node.
static void check_uploaded(app_render_tree id, const bk_mesh_tree* tree) {
  tree_buffers* t = render_find_tree(renderer, id);
  ENSURE(t != NULL);
  ENSURE_MSG(t->node_count == tree->node_count && renderer_tree_node_count(renderer, id) == tree->node_count,
             "uploaded %u nodes of %u", t->node_count, tree->node_count);
  ENSURE(t->vertex_count <= t->vertex_capacity && t->index_total <= t->index_capacity);
  ENSURE(buffer_size(t->vbo) >= (GLint)(sizeof(vertex) * t->vertex_count));
  ENSURE(buffer_size(t->ibo) >= (GLint)(sizeof(uint32_t) * t->index_total));
  ENSURE(buffer_size(t->table_buffer) >= (GLint)(sizeof(float) * TABLE_FLOATS * t->node_count));
  GLint element_buffer = 0, node_buffer = 0;
  glBindVertexArray(t->vao);
  glGetIntegerv(GL_ELEMENT_ARRAY_BUFFER_BINDING, &element_buffer);
  glGetVertexAttribiv(NODE_ATTRIBUTE, GL_VERTEX_ATTRIB_ARRAY_BUFFER_BINDING, &node_buffer);
  glBindVertexArray(0);
  ENSURE((GLuint)element_buffer == t->ibo && (GLuint)node_buffer == t->vbo);
  vertex* vertices = read_buffer(t->vbo, sizeof(vertex) * t->vertex_count);
  uint32_t* indices = read_buffer(t->ibo, sizeof(uint32_t) * t->index_total);
  for (uint32_t n = 0; n < tree->node_count; ++n) {
    const bk_mesh* m = &tree->nodes[n].mesh;
    for (int section = 0; section < SECTIONS; ++section) {
      uint32_t first = t->first_index[section][n], count = t->index_count[section][n], k = 0;
      check_range(t, vertices, indices, n, first, count);
      for (uint32_t tri = 0; tri < m->triangle_count; ++tri) {
        if (bk_material_is_interior(m->materials[tri]) != (section == INTERIOR)) continue;
        for (int c = 0; c < 3; ++c, ++k) {
          ENSURE_MSG(k < count, "node %u section %d: %u indices, more triangles", n, section, count);
          const bk_corner* corner = &m->corners[m->indices[3 * tri + c]];
          bk_vec3 p = m->positions[corner->position];
          const vertex* v = &vertices[indices[first + k]];
          ENSURE_MSG(v->position[0] == (float)p.x && v->position[1] == (float)p.y &&
                         v->position[2] == (float)p.z && v->normal[0] == corner->normal[0] &&
                         v->normal[1] == corner->normal[1] && v->normal[2] == corner->normal[2],
                     "node %u triangle %u corner %d", n, tri, c);
        }
      }
      ENSURE_MSG(k == count, "node %u section %d: %u indices for %u corners", n, section, count, k);
      for (int level = 0; level < COARSE_LEVELS; ++level)
        check_range(t, vertices, indices, n, t->coarse_first[level][section][n],
                    t->coarse_count[level][section][n]);
    }
    const float* s = t->spheres[n];
    for (uint32_t p = 0; p < m->position_count; ++p) {
      double dx = m->positions[p].x - s[0], dy = m->positions[p].y - s[1], dz = m->positions[p].z - s[2];
      ENSURE_MSG(sqrt(dx * dx + dy * dy + dz * dz) <= s[3] * (1.0 + 1e-5) + 1e-6, "node %u point %u outside",
                 n, p);
    }
  }
  free(vertices);
  free(indices);
}

// Fractures leaf `leaf` of `tree` again (as a refinement does) and splices
// its pieces in: the tree grows by appending nodes.
static bk_splice_info grow(bk_mesh_tree* tree, uint32_t leaf, uint32_t pieces) {
  const bk_mesh_tree_node* n = bk_mesh_tree_leaf(tree, leaf);
  bk_fracture_def def = bk_default_fracture_def();
  def.pattern = BK_PATTERN_RADIAL;
  def.pieces = pieces;
  def.seed = 11 + leaf;
  def.impact = n->bounds.max;
  def.threads = 1;
  bk_mesh_tree pieces_tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_fracture_leaf(&n->mesh, tree->nodes[0].bounds, &def, &pieces_tree, &err), "%s",
             err.message);
  bk_splice_info info = {0};
  ENSURE_MSG(bk_mesh_tree_splice(tree, leaf, &pieces_tree, &info, &err), "%s", err.message);
  return info;
}

// A tree uploaded, then grown three times (the first outgrows the buffers
// made to its size; later ones may fit): only the new nodes are added,
// everything uploaded before stays as it was, and the id does not change.
static void test_grow_tree(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_WALL, 12, 5);
  app_render_tree id = renderer_upload_tree(renderer, &tree);
  check_uploaded(id, &tree);
  ENSURE(renderer_grow_tree(renderer, id, &tree) == 0); // nothing new
  const uint32_t leaves[3] = {0, 7, 3};
  uint32_t regrown = 0;
  for (int round = 0; round < 3; ++round) {
    tree_buffers* t = render_find_tree(renderer, id);
    uint32_t old_nodes = t->node_count, old_vertices = t->vertex_count, old_indices = t->index_total;
    GLuint old_vbo = t->vbo;
    vertex* vertices_before = read_buffer(t->vbo, sizeof(vertex) * old_vertices);
    uint32_t* indices_before = read_buffer(t->ibo, sizeof(uint32_t) * old_indices);
    uint32_t* surface_before = malloc(sizeof(uint32_t) * 2 * old_nodes);
    ENSURE(surface_before);
    memcpy(surface_before, t->first_index[SURFACE], sizeof(uint32_t) * old_nodes);
    memcpy(surface_before + old_nodes, t->index_count[INTERIOR], sizeof(uint32_t) * old_nodes);
    bk_splice_info info = grow(&tree, leaves[round], 6 + 4 * (uint32_t)round);
    ENSURE(info.first_node == old_nodes && tree.node_count == old_nodes + info.node_count);
    ENSURE_MSG(renderer_grow_tree(renderer, id, &tree) == info.node_count, "round %d", round);
    t = render_find_tree(renderer, id); // the same slot, the same id
    ENSURE(t != NULL && t->vertex_count > old_vertices && t->index_total > old_indices);
    regrown += t->vbo != old_vbo;
    check_uploaded(id, &tree);
    vertex* vertices_after = read_buffer(t->vbo, sizeof(vertex) * old_vertices);
    uint32_t* indices_after = read_buffer(t->ibo, sizeof(uint32_t) * old_indices);
    ENSURE(memcmp(vertices_before, vertices_after, sizeof(vertex) * old_vertices) == 0);
    ENSURE(memcmp(indices_before, indices_after, sizeof(uint32_t) * old_indices) == 0);
    ENSURE(memcmp(surface_before, t->first_index[SURFACE], sizeof(uint32_t) * old_nodes) == 0);
    ENSURE(memcmp(surface_before + old_nodes, t->index_count[INTERIOR], sizeof(uint32_t) * old_nodes) == 0);
    free(vertices_before), free(indices_before), free(vertices_after), free(indices_after),
        free(surface_before);
  }
  ENSURE(regrown >= 1); // the first growth needed larger buffers: their contents were copied over
  ENSURE(renderer_grow_tree(renderer, id, &tree) == 0);
  // Drawn: every leaf (new nodes among them) without a GL error.
  app_camera camera = {.eye = bk_v3(0.0, 1.0, 3.0), .target = bk_v3(0.0, 0.6, 0.0)};
  renderer_begin_frame(renderer, &camera, 320, 240);
  renderer_draw_nodes(renderer, &(node_draw){.tree = id,
                                             .nodes = tree.leaf_nodes,
                                             .node_count = tree.leaf_count,
                                             .model = bk_transform_identity(),
                                             .material = 0});
  ENSURE(renderer_end_frame(renderer) == 0);
  ENSURE(renderer_stats(renderer).triangles > 0);
  renderer_release_tree(renderer, id);
  ENSURE(renderer_grow_tree(renderer, id, &tree) == 0 && renderer_tree_node_count(renderer, id) == 0);
  bk_mesh_tree_free(&tree);
}

// A 64-fragment wall refining where it is shot (as play --refine makes it),
// stepped as the game does with the upload after every step: the renderer
// holds exactly the runtime's nodes each time, every body's nodes among
// them, and the nodes it was given are the grown tree's. Small loose pieces
// retire at once: the game keeps every one the world hands over to fade
// out, pieces of refined fragments (nodes the scene's tree never had)
// among them.
static void test_world_growth(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_WALL, 64, 3000);
  bk_world_def world_def = bk_default_world_def();
  world_def.physics_budget_ms = 0.0;
  world_def.retire_volume = 1e-3;
  world_def.retire_after = 0.25;
  bk_error err = {0};
  bk_world* world = bk_world_create(&world_def, &err);
  ENSURE_MSG(world, "%s", err.message);
  bk_world_breakable_def def = bk_default_world_breakable_def();
  def.breakable.tree = &tree;
  def.breakable.anchored = true;
  def.breakable.material = *bk_material_find("stone");
  def.breakable.material.refine_strength = def.breakable.material.bond_strength / 8.0;
  def.breakable.refine =
      (bk_refine_def){.pattern = BK_PATTERN_RADIAL, .pieces = 16, .min_size = 0.02, .radial_falloff = 1.0};
  bk_breakable_id ids[1] = {bk_world_add_breakable(world, &def, &err)};
  ENSURE_MSG(ids[0].generation != 0, "%s", err.message);
  app_render_tree trees[1] = {renderer_upload_tree(renderer, &tree)};
  // The game as far as its retired pieces go (game_collect_retired).
  app_game* game = calloc(1, sizeof *game);
  ENSURE(game);
  game->renderer = renderer;
  game->scene.world = world;
  game->scene.tree_count = 1;
  game->scene.ids[0] = ids[0];
  game->scene.trees[0] = tree; // borrowed: freed below, once
  game->render_trees[0] = trees[0];
  retired_pieces_init(&game->retired, 1e9, bk_v3(0.0, -9.81, 0.0)); // none fades while counted
  grown_trees_reset(&game->grown, &tree, 1);
  uint32_t uploads = 0, added = 0, built = 0, caught_up = 0, merged = 0, retired = 0, retired_new_nodes = 0;
  // Reported, not checked (the machine decides them): the GL thread's part, and the stepping thread's.
  double upload_ms = 0.0, upload_max_ms = 0.0, build_ms = 0.0, build_max_ms = 0.0;
  for (int step = 0; step < 90; ++step) {
    if (step == 5 || step == 40) {
      bk_projectile_def shot = {.position = bk_v3(step == 5 ? 0.0 : 0.3, 0.7, 2.0),
                                .velocity = bk_v3(0, 0, -40.0),
                                .radius = 0.14,
                                .mass = 40.0};
      ENSURE(!bk_body_is_null(bk_world_fire(world, &shot, NULL)));
    }
    bk_world_step(world);
    uint32_t kept = game->retired.count + game->retired.pushed_out;
    game_collect_retired(game);
    bk_retired_body bodies[256];
    uint32_t total = bk_world_retired_bodies(world, bodies, 256);
    ENSURE(total <= 256);
    ENSURE_MSG(game->retired.count + game->retired.pushed_out - kept == total,
               "step %d: kept %u of %u retired", step, game->retired.count + game->retired.pushed_out - kept,
               total);
    retired += total;
    for (uint32_t i = 0; i < total; ++i)
      retired_new_nodes += bodies[i].node >= tree.node_count;
    // As the game: made ready after the steps, uploaded before drawing. One
    // step in four is not made ready (the upload catches up by itself), and
    // one in four not uploaded (the next step's nodes join what is pending).
    const bool build = step % 4 != 1, upload = step % 4 != 2;
    uint32_t before = renderer_tree_node_count(renderer, trees[0]);
    if (build) {
      bool waiting = game->grown.pending[0] != NULL;
      double t0 = now_ms();
      uint32_t made = grown_trees_build(&game->grown, world, ids, 1);
      build_ms += now_ms() - t0;
      build_max_ms = fmax(build_max_ms, now_ms() - t0);
      merged += waiting && made > 0;
      built += made;
    }
    const bk_mesh_tree* now = bk_runtime_breakable_tree(bk_world_runtime(world), ids[0]);
    ENSURE(now != NULL);
    if (!upload) continue;
    bool ready = game->grown.pending[0] != NULL;
    // What is pending follows what was uploaded, so it is appended whole.
    ENSURE_MSG(!ready || game->grown.pending_first[0] == before, "step %d: pending from node %u, uploaded %u",
               step, game->grown.pending_first[0], before);
    double t0 = now_ms();
    uint32_t got = grown_trees_upload(&game->grown, renderer, world, ids, trees, 1);
    glFinish();
    upload_ms += now_ms() - t0;
    upload_max_ms = fmax(upload_max_ms, now_ms() - t0);
    ENSURE_MSG(renderer_tree_node_count(renderer, trees[0]) == now->node_count &&
                   got == now->node_count - before,
               "step %d: uploaded %u nodes (%u new), the tree has %u", step,
               renderer_tree_node_count(renderer, trees[0]), got, now->node_count);
    ENSURE(game->grown.pending[0] == NULL && game->grown.built[0] == now->node_count);
    caught_up += !ready && got > 0;
    uploads += got > 0;
    added += got;
    for (uint32_t b = 0; b < bk_world_body_count(world); ++b) {
      bk_body_view v = {0};
      ENSURE(bk_world_body_view(world, b, &v));
      ENSURE(v.tree == now);
      for (uint32_t k = 0; k < v.node_count; ++k)
        ENSURE_MSG(v.nodes[k] < renderer_tree_node_count(renderer, trees[0]),
                   "step %d: body %u names node %u", step, b, v.nodes[k]);
    }
  }
  const bk_mesh_tree* now = bk_runtime_breakable_tree(bk_world_runtime(world), ids[0]);
  bk_world_stats stats = bk_world_get_stats(world);
  ENSURE_MSG(stats.refined_leaves > 0 && now->node_count > tree.node_count, "refined %u, nodes %u",
             stats.refined_leaves, now->node_count);
  ENSURE(added == now->node_count - tree.node_count);
  // Each way was taken: nodes made ready, pending ones joined by more, and
  // new ones uploaded with none made ready.
  ENSURE_MSG(built > 0 && merged > 0 && caught_up > 0, "built %u, merged %u, caught up %u", built, merged,
             caught_up);
  ENSURE_MSG(retired_new_nodes > 0, "retired %u pieces, none of a refined fragment", retired);
  check_uploaded(trees[0], now);
  // The game draws them fading: without a GL error.
  app_camera camera = {.eye = bk_v3(0.0, 1.0, 3.0), .target = bk_v3(0.0, 0.6, 0.0)};
  renderer_begin_frame(renderer, &camera, 320, 240);
  game_draw_retired(game, 0.5);
  ENSURE(renderer_end_frame(renderer) == 0);
  fprintf(stderr,
          "    refined %u fragments: %u nodes to %u in %u uploads; made ready %.1f ms in all (%.2f at most a "
          "step), uploaded %.1f ms (%.2f); %u pieces retired, %u of them new nodes\n",
          stats.refined_leaves, tree.node_count, now->node_count, uploads, build_ms, build_max_ms, upload_ms,
          upload_max_ms, retired, retired_new_nodes);
  grown_trees_reset(&game->grown, NULL, 0);
  free(game);
  renderer_release_tree(renderer, trees[0]);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

// A wall that does not refine, and the game's switch (the panel's "Refine
// where hit"): on, its material refines at scene_refine's strength, live,
// and the same shots that broke it into its own fragments refine it;
// the strength follows a new bond strength; off, it is 0 again. Each time
// the options remember it for the next reload.
static void test_refine_switch(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_WALL, 64, 3000);
  uint32_t refined[2] = {0, 0}, leaves[2] = {0, 0};
  for (int on = 0; on < 2; ++on) {
    bk_world_def world_def = bk_default_world_def();
    world_def.physics_budget_ms = 0.0;
    bk_error err = {0};
    bk_world* world = bk_world_create(&world_def, &err);
    ENSURE_MSG(world, "%s", err.message);
    bk_world_breakable_def def = bk_default_world_breakable_def();
    def.breakable.tree = &tree;
    def.breakable.anchored = true;
    def.breakable.material = *bk_material_find("stone");
    bk_breakable_id id = bk_world_add_breakable(world, &def, &err);
    ENSURE_MSG(id.generation != 0, "%s", err.message);
    app_game* game = calloc(1, sizeof *game);
    ENSURE(game);
    game->options = default_scene_options();
    game->scene.world = world;
    game->scene.tree_count = 1;
    game->scene.ids[0] = id;
    ENSURE(!game_refine_live(game) && bk_world_material(world, id).refine_strength == 0.0);
    if (on) {
      game_set_refine(game, true);
      bk_breakable_def expected = {.material = def.breakable.material};
      scene_refine(&expected, &game->options);
      ENSURE(game_refine_live(game) && game->options.refine);
      ENSURE(expected.material.refine_strength > 0.0 &&
             bk_world_material(world, id).refine_strength == expected.material.refine_strength);
      ENSURE(bk_world_set_bond_strength(world, id, 2.0 * def.breakable.material.bond_strength) == BK_OK);
      game_refine_follow(game);
      ENSURE(bk_world_material(world, id).refine_strength == 2.0 * expected.material.refine_strength);
      ENSURE(bk_world_set_bond_strength(world, id, def.breakable.material.bond_strength) == BK_OK);
      game_refine_follow(game);
      ENSURE(bk_world_material(world, id).refine_strength == expected.material.refine_strength);
    } else {
      game_refine_follow(game); // off: nothing to follow
      ENSURE(!game_refine_live(game));
    }
    for (int step = 0; step < 60; ++step) {
      if (step == 5) {
        bk_projectile_def shot = {
            .position = bk_v3(0.0, 0.7, 2.0), .velocity = bk_v3(0, 0, -40.0), .radius = 0.14, .mass = 40.0};
        ENSURE(!bk_body_is_null(bk_world_fire(world, &shot, NULL)));
      }
      bk_world_step(world);
    }
    refined[on] = bk_world_get_stats(world).refined_leaves;
    leaves[on] = bk_runtime_breakable_tree(bk_world_runtime(world), id)->leaf_count;
    if (on) {
      game_set_refine(game, false);
      ENSURE(!game_refine_live(game) && !game->options.refine &&
             bk_world_material(world, id).refine_strength == 0.0);
    }
    free(game);
    bk_world_destroy(world);
  }
  fprintf(stderr, "    one shot: refined %u fragments (%u leaves) switched off, %u (%u leaves) on\n",
          refined[0], leaves[0], refined[1], leaves[1]);
  ENSURE(refined[0] == 0 && leaves[0] == 64);
  ENSURE(refined[1] > 0 && leaves[1] > 64);
  bk_mesh_tree_free(&tree);
}

// Runs this test again under a virtual display; returns its exit status.
static int run_under_xvfb(const char* self) {
  if (system("command -v xvfb-run >/dev/null 2>&1") != 0) {
    fprintf(stderr, "no display and no xvfb-run: scripts/setup.sh installs it\n");
    return 1;
  }
  char command[4096];
  snprintf(command, sizeof command, "BK_GAME_REFINE_CHILD=1 xvfb-run -a -s '-screen 0 1280x720x24' '%s'",
           self);
  int status = system(command);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

int main(int argc, char** argv) {
  (void)argc;
  if (!getenv("DISPLAY") && !getenv("BK_GAME_REFINE_CHILD")) return run_under_xvfb(argv[0]);
  ENSURE(glfwInit());
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
  GLFWwindow* window = glfwCreateWindow(320, 240, "test_game_refine", NULL, NULL);
  ENSURE_MSG(window, "no OpenGL 3.3 core context");
  glfwMakeContextCurrent(window);
  bk_error err = {0};
  renderer_def desc = {.get_proc_address = glfwGetProcAddress,
                       .shader_dir = BK_SHADER_DIR,
                       .texture_dir = BK_ASSET_DIR "/textures"};
  renderer = renderer_create(&desc, &err);
  ENSURE_MSG(renderer, "%s", err.message);
  RUN(test_grow_tree);
  RUN(test_world_growth);
  RUN(test_refine_switch);
  renderer_destroy(renderer);
  glfwDestroyWindow(window);
  // No glfwTerminate: it unloads the GL driver, whose never-freed
  // allocations LeakSanitizer could then name no library for (see test_ui).
  return 0;
}
