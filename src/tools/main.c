// breakables: command-line entry point. Dispatches to the subcommands.
#include <stdio.h>
#include <string.h>

#include "app.h"

static const char* const usage =
    "usage: breakables [command] [options]\n"
    "\n"
    "Real-time destruction toolkit and demo game: closed meshes are fractured into\n"
    "mesh trees of watertight fragments that break apart as rigid bodies.\n"
    "\n"
    "commands:\n"
    "  play       the demo game (the default when no command is given)\n"
    "  editor     preview the fragments of a mesh, pull them apart, export them\n"
    "  fracture   build a mesh tree of fragments from a mesh (headless)\n"
    "  sim        run a scene headless: fire projectiles, report breaks and costs\n"
    "  bench      run the thesis's benchmarks: Markdown report, CSV tables, plots\n"
    "\n"
    "Run 'breakables <command> --help' for the options of a command.\n";

int main(int argc, char** argv) {
  // --pieces=64 is --pieces 64 for every command and option.
  argv = split_option_values(&argc, argv);
  if (argc >= 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
    fputs(usage, stdout);
    return 0;
  }
  // No command, or only options: the game.
  if (argc < 2 || argv[1][0] == '-') return cmd_play(argc, argv);
  if (strcmp(argv[1], "play") == 0) return cmd_play(argc - 1, argv + 1);
  if (strcmp(argv[1], "editor") == 0) return cmd_editor(argc - 1, argv + 1);
  if (strcmp(argv[1], "fracture") == 0) return cmd_fracture(argc - 1, argv + 1);
  if (strcmp(argv[1], "sim") == 0) return cmd_sim(argc - 1, argv + 1);
  if (strcmp(argv[1], "bench") == 0) return app_cmd_bench(argc - 1, argv + 1);
  fprintf(stderr, "breakables: unknown command '%s' (see 'breakables --help')\n", argv[1]);
  return 2;
}
