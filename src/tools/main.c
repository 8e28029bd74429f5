// breakables: command-line entry point. Dispatches to the subcommands.
#include <stdio.h>
#include <string.h>

#include "app.h"
#include "commands.h"
#include "scene_run.h"

static const char* const usage_head =
    "usage: breakables [command] [options]\n"
    "\n"
    "Real-time destruction toolkit and demo game: closed meshes are fractured into\n"
    "mesh trees of watertight fragments that break apart as rigid bodies.\n"
    "\n"
    "commands:\n";
// The game's commands exist only in a build with the demo (BK_BUILD_DEMO
// defines BK_WITH_GAME); a headless build has the tools alone.
#ifdef BK_WITH_GAME
static const char* const usage_game =
    "  play       the demo game (the default when no command is given)\n"
    "  serve      the game as a server: its destruction streamed to watchers over TCP\n"
    "  watch      a window following a server's game (serve or sim --serve)\n"
    "  editor     preview the fragments of a mesh, pull them apart, export them\n";
#else
static const char* const usage_game = "";
#endif
static const char* const usage_tools =
    "  fracture   build a mesh tree of fragments from a mesh (headless)\n"
    "  sim        run a scene headless: fire projectiles, report breaks and costs\n"
    "  bench      run the thesis's benchmarks: Markdown report, CSV tables, plots\n"
    "\n"
    "Run 'breakables <command> --help' for the options of a command.\n";

#ifdef BK_WITH_GAME
static int play(int argc, char** argv) { return cmd_play(argc, argv); }
static int serve(int argc, char** argv) { return cmd_serve(argc, argv); }
static int watch(int argc, char** argv) { return cmd_watch(argc, argv); }
static int editor(int argc, char** argv) { return cmd_editor(argc, argv); }
#else
static int no_game(const char* command) {
  fprintf(stderr,
          "breakables: this build has no game ('%s' needs BK_BUILD_DEMO=ON); fracture, sim and bench work\n",
          command);
  return 2;
}
static int play(int argc, char** argv) {
  (void)argc;
  (void)argv;
  return no_game("play");
}
static int serve(int argc, char** argv) {
  (void)argc;
  (void)argv;
  return no_game("serve");
}
static int watch(int argc, char** argv) {
  (void)argc;
  (void)argv;
  return no_game("watch");
}
static int editor(int argc, char** argv) {
  (void)argc;
  (void)argv;
  return no_game("editor");
}
#endif

int main(int argc, char** argv) {
  // --pieces=64 is --pieces 64 for every command and option.
  argv = split_option_values(&argc, argv);
  if (argc >= 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
    fputs(usage_head, stdout);
    fputs(usage_game, stdout);
    fputs(usage_tools, stdout);
    return 0;
  }
  // No command, or only options: the game.
  if (argc < 2 || argv[1][0] == '-') return play(argc, argv);
  if (strcmp(argv[1], "play") == 0) return play(argc - 1, argv + 1);
  if (strcmp(argv[1], "serve") == 0) return serve(argc - 1, argv + 1);
  if (strcmp(argv[1], "watch") == 0) return watch(argc - 1, argv + 1);
  if (strcmp(argv[1], "editor") == 0) return editor(argc - 1, argv + 1);
  if (strcmp(argv[1], "fracture") == 0) return cmd_fracture(argc - 1, argv + 1);
  if (strcmp(argv[1], "sim") == 0) return cmd_sim(argc - 1, argv + 1);
  if (strcmp(argv[1], "bench") == 0) return cmd_bench(argc - 1, argv + 1);
  fprintf(stderr, "breakables: unknown command '%s' (see 'breakables --help')\n", argv[1]);
  return 2;
}
