/* `weft inspect FILE`: a cloth made of the file through the public API (weft_cloth_create on a
 * CPU context: import, weld, winged edge, springs) and its import report (weft_cloth_get_report).
 * Exit codes: 0 ok, 1 the file could not be imported or modelled (one line on stderr, nothing
 * on stdout), 2 bad command line. */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "report.h"
#include "weft/weft.h"

typedef struct inspect_args {
    const char* file;
    int json;
    weft_cloth_def def;     /* mesh.select, unit_scale, weld_tolerance, sew_distance from the options */
} inspect_args;

void cli_inspect_usage(FILE* out) {
    fputs("usage: weft inspect FILE [--json] [--scale S] [--weld-tolerance T] [--select NAME]\n"
          "                    [--sew-distance D]\n"
          "\n"
          "Import FILE (any format assimp reads: OBJ, FBX, glTF, PLY, ...), weld it, build the\n"
          "winged edge and springs, and print the import report.\n"
          "\n"
          "options:\n"
          "  --json                 print the report as one JSON object\n"
          "  --scale S              metres per file unit (> 0; default 1); for FBX a factor\n"
          "                         on top of the file's UnitScaleFactor\n"
          "  --weld-tolerance T     weld distance relative to the bounding-box diagonal\n"
          "                         (>= 0; 0 disables welding; default 1e-6)\n"
          "  --select NAME          import only the mesh or node (with children) called NAME\n"
          "  --sew-distance D       sew boundary vertices to other panels' boundaries within\n"
          "                         D metres (>= 0; default 0: off); reports seams and panels\n"
          "  -h, --help             show this help\n",
          out);
}

#define usage_error(...) cli_usage_error("weft inspect", cli_inspect_usage, __VA_ARGS__)

/* Returns -1 to continue, or an exit code (help printed, or a usage error). */
static int parse_args(int argc, char** argv, inspect_args* a) {
    int only_files = 0;
    for (int i = 1; i < argc; ++i) {
        const char* arg = argv[i];
        const char* value = NULL;
        int m;
        if (only_files || arg[0] != '-' || strcmp(arg, "-") == 0) {
            if (a->file) return usage_error("more than one FILE ('%s')", arg);
            a->file = arg;
        } else if (strcmp(arg, "--") == 0) {
            only_files = 1;
        } else if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            cli_inspect_usage(stdout);
            return CLI_EXIT_OK;
        } else if (strcmp(arg, "--json") == 0) {
            a->json = 1;
        } else if ((m = cli_option_value(argc, argv, &i, "--scale", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            if (cli_parse_double(value, &a->def.unit_scale) != 0 || !(a->def.unit_scale > 0))
                return usage_error("--scale must be a finite number > 0, not '%s'", value);
        } else if ((m = cli_option_value(argc, argv, &i, "--weld-tolerance", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            if (cli_parse_double(value, &a->def.weld_tolerance) != 0 || !(a->def.weld_tolerance >= 0))
                return usage_error("--weld-tolerance must be a finite number >= 0, not '%s'", value);
        } else if ((m = cli_option_value(argc, argv, &i, "--sew-distance", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            if (cli_parse_double(value, &a->def.sew_distance) != 0 || !(a->def.sew_distance >= 0))
                return usage_error("--sew-distance must be a finite number >= 0, not '%s'", value);
        } else if ((m = cli_option_value(argc, argv, &i, "--select", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            a->def.mesh.select = value;
        } else {
            return usage_error("unknown option '%s'", arg);
        }
    }
    if (!a->file) return usage_error("missing FILE");
    return -1;
}

/* One line on stderr: the library's message without the call's prefix, the file's name in front
 * unless the message names it already. */
static int fail(const char* file, const char* message) {
    static const char* const prefixes[] = {"weft_cloth_create: ", "def->mesh: "};
    for (int k = 0; k < 2; ++k)
        if (strncmp(message, prefixes[k], strlen(prefixes[k])) == 0) message += strlen(prefixes[k]);
    char line[1024];
    if (strstr(message, file)) snprintf(line, sizeof line, "%s", message);
    else snprintf(line, sizeof line, "%s: %s", file, message);
    cli_error(line);
    return CLI_EXIT_FAILURE;
}

int cli_inspect_run(int argc, char** argv) {
    inspect_args a = {NULL, 0, weft_default_cloth_def()};
    int rc = parse_args(argc, argv, &a);
    if (rc >= 0) return rc;

    weft_context_def cd = weft_default_context_def();
    cd.backend = WEFT_BACKEND_CPU;
    weft_context* ctx = NULL;
    weft_status st = weft_context_create(WEFT_ABI, &cd, &ctx);
    if (st != WEFT_OK) return fail(a.file, weft_status_string(st));
    a.def.mesh.path = a.file;
    weft_cloth cloth = {0};
    weft_import_report report;
    st = weft_cloth_create(ctx, &a.def, &cloth);
    if (st == WEFT_OK) st = weft_cloth_get_report(ctx, cloth, &report);
    if (st != WEFT_OK) {
        rc = fail(a.file, weft_context_last_error(ctx));
    } else if (a.json) {
        rc = CLI_EXIT_OK;
        if (cli_report_json(stdout, a.file, &report) != 0) {
            cli_error("out of memory while writing the JSON report");
            rc = CLI_EXIT_FAILURE;
        }
    } else {
        cli_report_text(stdout, a.file, &report);
        rc = CLI_EXIT_OK;
    }
    weft_context_destroy(ctx);
    return rc;
}
