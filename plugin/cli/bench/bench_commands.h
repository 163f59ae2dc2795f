/* The `weft bench` subcommands, one file each (cmd_bench_*.c), dispatched by cmd_bench.c:
 *   accuracy    run time against error                      cmd_bench_accuracy.c
 *   iterations  solver iterations per solve                 cmd_bench_iterations.c
 *   stability   the step/stiffness/mass/solver grid         cmd_bench_stability.c
 *   peers       Weft beside Blender's cloth                 cmd_bench_peers.c
 *   torture     random host inputs                          cmd_bench_torture.c
 *   skip        the cost of unused features, sleeping       cmd_bench_skip.c
 *   collide     collision detection's cost                  cmd_bench_collide.c
 *   crowd       many cloths: batched against unbatched      cmd_bench_crowd.c
 * Each takes its own arguments (argv[0] its name) and returns a CLI exit code. */
#ifndef WEFT_CLI_BENCH_COMMANDS_H
#define WEFT_CLI_BENCH_COMMANDS_H
#include <stdio.h>

int bench_accuracy_run(int argc, char** argv);
void bench_accuracy_usage(FILE* out);
int bench_iterations_run(int argc, char** argv);
void bench_iterations_usage(FILE* out);
int bench_stability_run(int argc, char** argv);
void bench_stability_usage(FILE* out);
int bench_peers_run(int argc, char** argv);
void bench_peers_usage(FILE* out);
int bench_torture_run(int argc, char** argv);
void bench_torture_usage(FILE* out);
int bench_skip_run(int argc, char** argv);
void bench_skip_usage(FILE* out);
int bench_collide_run(int argc, char** argv);
void bench_collide_usage(FILE* out);
int bench_crowd_run(int argc, char** argv);
void bench_crowd_usage(FILE* out);

#endif
