/* `weft bench peers --matched` (cmd_bench_peers_matched.c): Weft beside Blender's cloth at
 * matched accuracy. Each simulator is measured against its own converged run of the same scene
 * (Blender at a high quality, Weft at TR-BDF2 Newton 3, tolerance 1e-8 and many substeps), each
 * run's error is its trajectory's RMS distance to that reference, and the verdict compares
 * Blender at a quality with the fastest Weft setting whose error is no larger. */
#ifndef WEFT_CLI_BENCH_MATCHED_H
#define WEFT_CLI_BENCH_MATCHED_H
#include <stdio.h>

#include "bench_args.h"
#include "bench_blender.h"
#include "bench_scene.h"

/* Weft's settings of the matched mode, by name (--settings): the library's defaults at 1, 2 and
 * 4 substeps, one Baraff-Witkin step, TR-BDF2 Newton 2 and 3 at 1 and 2 substeps; then BDF2 and
 * TR-BDF2 at Newton 1 and 2, and the linear solves' tolerance and forcing (_f0: every solve to
 * the tolerance; _tight: to 1e-6). Names and order: k_settings in cmd_bench_peers_matched.c. */
#define BENCH_MATCHED_SETTING_NAMES \
    "defaults,defaults_s2,defaults_s4,newton1,trbdf2_n2,trbdf2_n2_s2,trbdf2_n3,trbdf2_n3_s2,\n" \
    "                   defaults_f0,defaults_tight,bdf2_n1,bdf2_n1_s2,bdf2_n2,bdf2_n2_f0,bdf2_n2_s2,\n" \
    "                   trbdf2_n1,trbdf2_n1_tight,trbdf2_n1_s2,trbdf2_n2_f0,trbdf2_n2_tight,\n" \
    "                   trbdf2_n3_f0,trbdf2_n3_tight,trbdf2_n6,trbdf2_n6_tight"

/* A --settings list into a bit mask (bit k: the k-th name above; "all": every one). The count,
 * or -1 on an unknown name. */
int bench_matched_parse_settings(const char* list, unsigned* mask);

typedef struct bench_matched_opts {
    const char* const* scenes;
    int n_scenes;
    int frames;
    double fps;             /* Weft's */
    double timeout;         /* s, for a Blender run at quality 5 (scaled by quality / 5 above) */
    const char* blender;    /* the executable, NULL: none here (missing says why) */
    const char* missing;
    const char* script;
    int qualities[BENCH_MAX_LIST];  /* Blender's qualities measured */
    int n_qualities;
    int ref_quality;        /* Blender's reference (its check: half of it) */
    int ref_substeps;       /* Weft's reference (its check: half of it) */
    unsigned settings;      /* Weft's settings measured (bench_matched_parse_settings) */
    const bench_common* com;
} bench_matched_opts;

/* Run every scene, write the tables (com's --md / --csv). An exit code. */
int bench_peers_matched(const bench_matched_opts* o);

#endif
