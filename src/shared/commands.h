// The commands of the breakables program, each in its own folder (tools:
// fracture, sim; bench; game: play, serve, watch, editor): argv[0] is the command name.
// Each returns the exit code.
#pragma once

int cmd_fracture(int argc, char** argv);
int cmd_sim(int argc, char** argv);
int cmd_play(int argc, char** argv);
int cmd_serve(int argc, char** argv);
int cmd_watch(int argc, char** argv);
int cmd_editor(int argc, char** argv);
int cmd_bench(int argc, char** argv);
