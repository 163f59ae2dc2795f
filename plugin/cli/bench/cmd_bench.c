/* `weft bench SUBCOMMAND`: dispatch to `accuracy`, `iterations`, `stability`, `peers`, `torture`,
 * `skip`, `collide` or `crowd` (bench_commands.h), then close the backends' contexts they opened. */
#include <string.h>

#include "bench_backend.h"
#include "bench_commands.h"
#include "cli.h"

void cli_bench_usage(FILE* out) {
    fputs("usage: weft bench accuracy [OPTIONS]    run time against error, for every solver\n"
          "       weft bench iterations [OPTIONS]  solver iterations per solve over sizes and stiffnesses\n"
          "       weft bench stability [OPTIONS]   survival over step length x stiffness x mass x solver\n"
          "       weft bench peers [OPTIONS]       Weft beside Blender's cloth solver (needs blender)\n"
          "       weft bench torture [OPTIONS]     random host inputs: crashes, hangs, NaN outputs\n"
          "       weft bench skip [OPTIONS]        per-stage cost of unused features, and of a sleeping cloth\n"
          "       weft bench collide [OPTIONS]     collision detection's cost over cloth and body sizes\n"
          "       weft bench crowd [OPTIONS]       N cloths: one call each against one weft_context_step\n"
          "       weft bench SUBCOMMAND --help     a subcommand's options\n"
          "\n"
          "Benchmarks of the simulator, through the public API (libweft.so) as a host runs it.\n"
          "accuracy, stability, skip and peers take --backend LIST (cpu, gpu or cpu,gpu; default cpu):\n"
          "each configuration runs on every backend listed, weft_cloth_step on a CPU or a GPU context\n"
          "(a headless GL context, llvmpipe where there is no GPU), side by side in one table with a\n"
          "`backend` column; torture takes --backend cpu|gpu|auto.\n"
          "Each writes a Markdown table (stdout or --md FILE), a CSV (--csv FILE) and a PNG plot\n"
          "(--plot FILE); --quick runs a seconds-long version (what CI runs).\n",
          out);
}

int cli_bench_run(int argc, char** argv) {
    if (argc < 2) return cli_usage_error("weft bench", cli_bench_usage, "missing subcommand");
    const char* sub = argv[1];
    if (!strcmp(sub, "--help") || !strcmp(sub, "-h") || !strcmp(sub, "help")) {
        cli_bench_usage(stdout);
        return CLI_EXIT_OK;
    }
    int rc = -1;
    if (!strcmp(sub, "accuracy")) rc = bench_accuracy_run(argc - 1, argv + 1);
    else if (!strcmp(sub, "iterations")) rc = bench_iterations_run(argc - 1, argv + 1);
    else if (!strcmp(sub, "stability")) rc = bench_stability_run(argc - 1, argv + 1);
    else if (!strcmp(sub, "peers")) rc = bench_peers_run(argc - 1, argv + 1);
    else if (!strcmp(sub, "torture")) rc = bench_torture_run(argc - 1, argv + 1);
    else if (!strcmp(sub, "skip")) rc = bench_skip_run(argc - 1, argv + 1);
    else if (!strcmp(sub, "collide")) rc = bench_collide_run(argc - 1, argv + 1);
    else if (!strcmp(sub, "crowd")) rc = bench_crowd_run(argc - 1, argv + 1);
    else return cli_usage_error("weft bench", cli_bench_usage, "unknown subcommand '%s'", sub);
    bench_close_backends(); /* the contexts the subcommand opened */
    return rc;
}

