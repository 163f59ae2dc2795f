/* `weft inspect FILE`: import a mesh, build the cloth model and print the import report.
 * Exit codes: 0 ok, 1 the file could not be imported or modelled (one line on stderr, nothing
 * on stdout), 2 bad command line. */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "model.h"
#include "report.h"
#include "source_mesh.h"
#include "weft/weft.h"

typedef struct inspect_args {
    const char* file;
    int json;
    wc_import_opts import;
    wc_model_def model;
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
            if (cli_parse_double(value, &a->import.scale) != 0 || !(a->import.scale > 0))
                return usage_error("--scale must be a finite number > 0, not '%s'", value);
        } else if ((m = cli_option_value(argc, argv, &i, "--weld-tolerance", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            if (cli_parse_double(value, &a->model.weld_tolerance) != 0 ||
                !(a->model.weld_tolerance >= 0))
                return usage_error("--weld-tolerance must be a finite number >= 0, not '%s'", value);
        } else if ((m = cli_option_value(argc, argv, &i, "--sew-distance", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            if (cli_parse_double(value, &a->model.sew_distance) != 0 || !(a->model.sew_distance >= 0))
                return usage_error("--sew-distance must be a finite number >= 0, not '%s'", value);
        } else if ((m = cli_option_value(argc, argv, &i, "--select", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            a->import.select = value;
        } else {
            return usage_error("unknown option '%s'", arg);
        }
    }
    if (!a->file) return usage_error("missing FILE");
    return -1;
}

/* One line on stderr. Import errors already name the file; model errors get it prefixed. */
static int fail(const char* file, const wc_diag* diag, wc_status status) {
    const char* what = diag->message[0] ? diag->message : wc_status_string(status);
    char line[1024];
    if (file) snprintf(line, sizeof line, "%s: %s", file, what);
    cli_error(file ? line : what);
    return CLI_EXIT_FAILURE;
}

int cli_inspect_run(int argc, char** argv) {
    inspect_args a = {NULL, 0, wc_default_import_opts(), wc_default_model_def()};
    int rc = parse_args(argc, argv, &a);
    if (rc >= 0) return rc;

    const wc_allocator alloc = {0};   /* malloc/free */
    wc_diag diag = {0};
    wc_source_mesh src = {0};
    wc_status st = wc_import_file(&src, &alloc, a.file, &a.import, &diag);
    if (st != WC_OK) return fail(NULL, &diag, st);

    wc_model model = {0};
    st = wc_model_build(&model, &src, &a.model, &alloc, &diag);
    wc_source_mesh_free(&src);
    if (st != WC_OK) return fail(a.file, &diag, st);

    if (a.json) {
        if (cli_report_json(stdout, a.file, &model.report) != 0) {
            cli_error("out of memory while writing the JSON report");
            rc = CLI_EXIT_FAILURE;
        } else {
            rc = CLI_EXIT_OK;
        }
    } else {
        cli_report_text(stdout, a.file, &model.report);
        rc = CLI_EXIT_OK;
    }
    wc_model_free(&model);
    return rc;
}
