/* The bundled scenes at the defaults (`weft run`, 1 thread) over the frames that stress a
 * recovery rule; each run must end with 0 rollbacks and no solve at its iteration cap:
 *   - tablecloth.json, frames 1-8: the landing on the sphere (frame 7), where two Newton
 *     iterations leave energy the step's judge would roll back; Newton's energy guard
 *     (core/newton.h) iterates on;
 *   - suit_on_body.json, frames 1-5: the body pushes the suit out of itself (frames 2-4); the
 *     energy judge does not charge the colliders' position corrections (core/step.c);
 *   - suit_on_body.json, frames 1-82: at frame 80 the multigrid's coarse 6x6-pair levels need an
 *     eigenvalue estimate that does not fall short (core/amg.h, amg_eigen.c), or PCG breaks down;
 *   - hanging_sheet.json and sweeping_sphere.json with TR-BDF2 (--integrator trbdf2), frames
 *     1-21: in frame 20 the sheet swings through its lowest point, where the trapezoidal stage
 *     alone ends above the substep's start energy and the whole substep does not; the energy
 *     judge spans both stages (step.h "TR-BDF2's energy").
 * docs/design/solver.md explains each rule. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "test_support.h"

static int stats_int(const cJSON* o, const char* key) {
    const cJSON* v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsNumber(v) ? v->valueint : -1;
}

static void run_scene(const char* scene, int frames, const char* extra) {
    static ts_cli_result r;
    static char text[1 << 16];
    char stats[1024], args[4096];
    snprintf(stats, sizeof stats, "%s", ts_tmp_path("sample_rollbacks.json"));
    remove(stats);
    snprintf(args, sizeof args, "run '%s/sample_scenes/%s' --frames %d --threads 1 --stats '%s' --quiet %s",
             WEFT_SOURCE_DIR, scene, frames, stats, extra);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    if (r.rc != 0) fprintf(stderr, "  %s: %s\n", scene, r.err);
    ts_read_text(stats, text, sizeof text);
    cJSON* o = cJSON_Parse(text);
    CHECK(o != NULL);
    if (!o) return;
    int rollbacks = stats_int(o, "rollbacks"), capped = stats_int(o, "not_converged");
    CHECK_EQ_INT(rollbacks, 0);
    CHECK_EQ_INT(capped, 0);
    CHECK_EQ_INT(stats_int(o, "failures"), 0);
    if (rollbacks != 0 || capped != 0) fprintf(stderr, "  %s: %d rollbacks, %d solves not converged\n", scene, rollbacks, capped);
    cJSON_Delete(o);
}

static void test_tablecloth_landing(void) { run_scene("tablecloth.json", 8, ""); }
static void test_suit_to_frame_82(void) { run_scene("suit_on_body.json", 82, ""); }
static void test_trbdf2_swing(void) {
    run_scene("hanging_sheet.json", 21, "--integrator trbdf2");
    run_scene("sweeping_sphere.json", 21, "--integrator trbdf2");
}

int main(void) {
    RUN_TEST(test_tablecloth_landing);
    RUN_TEST(test_suit_to_frame_82);
    RUN_TEST(test_trbdf2_swing);
    return TEST_SUMMARY();
}
