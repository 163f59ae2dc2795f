/* `weft`: entry point. Global options, then a table-driven dispatch to one subcommand. */
#include "cli.h"

#include <string.h>

#include "weft/weft.h"

static const cli_command commands[] = {
    {"inspect", "import a mesh and print the import report", cli_inspect_run, cli_inspect_usage},
    {"run", "simulate a scene file, writing OBJ frames and stats", cli_run_run, cli_run_usage},
    {"bench", "benchmarks: run time against error, numerical stability", cli_bench_run, cli_bench_usage},
};
enum { N_COMMANDS = sizeof commands / sizeof commands[0] };

static void usage(FILE* out) {
    fputs("usage: weft COMMAND [ARGS...]\n"
          "       weft --help | --version\n"
          "       weft help COMMAND\n"
          "\ncommands:\n",
          out);
    for (int i = 0; i < N_COMMANDS; ++i)
        fprintf(out, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fputs("\nRun 'weft COMMAND --help' for a command's options.\n", out);
}

static const cli_command* find_command(const char* name) {
    for (int i = 0; i < N_COMMANDS; ++i)
        if (strcmp(commands[i].name, name) == 0) return &commands[i];
    return NULL;
}

static int print_version(void) {
    weft_version_info v = weft_version();
    printf("weft %d.%d.%d (ABI %d)\n", v.major, v.minor, v.patch, v.abi);
    return CLI_EXIT_OK;
}

static int help(int argc, char** argv) {
    if (argc < 3) {
        usage(stdout);
        return CLI_EXIT_OK;
    }
    const cli_command* cmd = find_command(argv[2]);
    if (!cmd) {
        fprintf(stderr, "weft: unknown command '%s'\n", argv[2]);
        usage(stderr);
        return CLI_EXIT_USAGE;
    }
    cmd->usage(stdout);
    return CLI_EXIT_OK;
}

static int dispatch(int argc, char** argv) {
    if (argc < 2) {
        usage(stderr);
        return CLI_EXIT_USAGE;
    }
    const char* first = argv[1];
    if (strcmp(first, "--help") == 0 || strcmp(first, "-h") == 0 || strcmp(first, "help") == 0)
        return help(argc, argv);
    if (strcmp(first, "--version") == 0 || strcmp(first, "-V") == 0) return print_version();

    const cli_command* cmd = find_command(first);
    if (!cmd) {
        fprintf(stderr, "weft: unknown command '%s'\n", first);
        usage(stderr);
        return CLI_EXIT_USAGE;
    }
    return cmd->run(argc - 1, argv + 1);
}

int main(int argc, char** argv) {
    int rc = dispatch(argc, argv);
    if (fflush(stdout) != 0 || ferror(stdout)) {
        cli_error("error writing to standard output");
        return CLI_EXIT_FAILURE;
    }
    return rc;
}
