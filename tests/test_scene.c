/* The scene file parser (plugin/cli/scene*.c): every kind of bad scene is refused with a message
 * naming the field; good scenes parse to the values written, with the documented defaults filled
 * in; the generated grid has the documented host vertex order, position and winding; selects,
 * transforms and relative mesh paths resolve; pins resolve to particles (duplicates and welded
 * vertices merge, conflicts are refused) and move with their velocity. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "scene.h"
#include "scene_mesh.h"
#include "test_support.h"

#define GRID "\"mesh\": {\"grid\": {\"n\": [4, 3], \"size\": [1.5, 1]}}"

static scene S;   /* static: large enough to keep off the stack */

static weft_status parse(const char* text, wc_diag* d) {
    memset(d, 0, sizeof *d);
    return scene_parse(&S, text, strlen(text), "scene.json", d);
}

/* text must be refused; the message must start with the file name and contain `field` (and
 * `detail` when not NULL). */
static void expect_bad(const char* text, const char* field, const char* detail) {
    wc_diag d;
    weft_status st = parse(text, &d);
    CHECK(st != WEFT_OK);
    CHECK(d.status == st);
    CHECK(strncmp(d.message, "scene.json: ", 12) == 0);
    CHECK(strstr(d.message, field) != NULL);
    if (detail) CHECK(strstr(d.message, detail) != NULL);
    CHECK(strchr(d.message, '\n') == NULL);
    CHECK(S.src.pos == NULL && S.pins == NULL && S.colliders == NULL);
    if (st == WEFT_OK || !strstr(d.message, field) || (detail && !strstr(d.message, detail)))
        fprintf(stderr, "  scene: %s\n  message: %s (wanted %s)\n", text, d.message, field);
    scene_free(&S);
}

static void test_bad_syntax_and_structure(void) {
    expect_bad("{\"mesh\": {\"grid\": {\"n\": [4, 3], \"size\": [1, 1]}},\n \"time\": {\"fps\": NaN}}", "line 2",
               "invalid JSON");
    expect_bad("{" GRID "} trailing", "line 1", "after the JSON");
    expect_bad("[1, 2]", "scene.json: ", "must be a JSON object");
    expect_bad("{}", "mesh", "missing");
    expect_bad("{\"mesh\": {}}", "mesh", "needs \"file\" or \"grid\"");
    expect_bad("{\"mesh\": {\"file\": \"a.obj\", \"grid\": {\"n\": [2, 2], \"size\": [1, 1]}}}", "mesh", "not both");
    expect_bad("{\"mesh\": \"a.obj\"}", "mesh", "must be an object");
    expect_bad("{" GRID ", \"gravty\": [0, -9.81, 0]}", "gravty", "unknown key");
    expect_bad("{" GRID ", \"material\": {\"k\": {\"strech\": 10}}}", "material.k.strech", "unknown key");
    expect_bad("{" GRID ", \"time\": {\"fps\": 30, \"fps\": 60}}", "time.fps", "duplicate");
    expect_bad("{" GRID ", \"description\": 3}", "description", "must be a string");
}

static void test_bad_mesh(void) {
    expect_bad("{\"mesh\": {\"grid\": {\"n\": [1, 3], \"size\": [1, 1]}}}", "mesh.grid.n[0]", NULL);
    expect_bad("{\"mesh\": {\"grid\": {\"n\": [4, 2.5], \"size\": [1, 1]}}}", "mesh.grid.n[1]", NULL);
    expect_bad("{\"mesh\": {\"grid\": {\"n\": \"4x4\", \"size\": [1, 1]}}}", "mesh.grid.n", NULL);
    expect_bad("{\"mesh\": {\"grid\": {\"n\": [4, 4, 4], \"size\": [1, 1]}}}", "mesh.grid.n", NULL);
    expect_bad("{\"mesh\": {\"grid\": {\"n\": [100000, 100000], \"size\": [1, 1]}}}", "mesh.grid.n", "more than");
    expect_bad("{\"mesh\": {\"grid\": {\"size\": [1, 1]}}}", "mesh.grid.n", "missing");
    expect_bad("{\"mesh\": {\"grid\": {\"n\": [4, 4]}}}", "mesh.grid.size", "missing");
    expect_bad("{\"mesh\": {\"grid\": {\"n\": [4, 4], \"size\": [0, 1]}}}", "mesh.grid.size[0]", "> 0");
    expect_bad("{\"mesh\": {\"grid\": {\"n\": [4, 4], \"size\": [1, -2]}}}", "mesh.grid.size[1]", "> 0");
    expect_bad("{\"mesh\": {\"grid\": {\"n\": [4, 4], \"size\": [1, 1e999]}}}", "mesh.grid.size[1]", "finite");
    expect_bad("{\"mesh\": {\"grid\": {\"n\": [4, 4], \"size\": [1, 1], \"scale\": 2}}}", "mesh.grid.scale",
               "unknown key");
    expect_bad("{\"mesh\": {\"grid\": {\"n\": [4, 4], \"size\": [1, 1]}, \"scale\": 2}}", "mesh.scale", NULL);
    expect_bad("{\"mesh\": {\"file\": \"\"}}", "mesh.file", "non-empty string");
    expect_bad("{\"mesh\": {\"file\": 7}}", "mesh.file", "string");
    expect_bad("{\"mesh\": {\"file\": \"x.obj\", \"scale\": 0}}", "mesh.scale", "> 0");
    expect_bad("{\"mesh\": {\"file\": \"x.obj\", \"scale\": -1}}", "mesh.scale", "> 0");
    expect_bad("{\"mesh\": {\"file\": \"x.obj\", \"weld_tolerance\": -1}}", "mesh.weld_tolerance", ">= 0");
    /* A mesh file that does not exist: the importer's status, the field and the file's name. */
    expect_bad("{\"mesh\": {\"file\": \"no_such_mesh_file.obj\"}}", "mesh.file", "no_such_mesh_file.obj");
    expect_bad("{" GRID ", \"transform\": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0]}", "transform", "16");
    expect_bad("{" GRID ", \"transform\": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, \"1\", 1]}", "transform[14]",
               NULL);
    expect_bad("{" GRID ", \"transform\": [1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}", "transform",
               "affine");
    expect_bad("{" GRID ", \"transform\": [1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}", "transform",
               "singular");
}

static void test_bad_material(void) {
    expect_bad("{" GRID ", \"material\": {\"k\": {\"stretch\": 0}}}", "material.k.stretch",
               "must be a finite number > 0");
    expect_bad("{" GRID ", \"material\": {\"k\": {\"stretch\": -5}}}", "material.k.stretch", "> 0");
    expect_bad("{" GRID ", \"material\": {\"k\": {\"stretch\": 1e999}}}", "material.k.stretch", "finite");
    expect_bad("{" GRID ", \"material\": {\"k\": {\"stretch\": \"stiff\"}}}", "material.k.stretch", "not a string");
    expect_bad("{" GRID ", \"material\": {\"k\": {\"bend\": -1}}}", "material.k.bend", ">= 0");
    expect_bad("{" GRID ", \"material\": {\"d\": {\"shear\": -0.1}}}", "material.d.shear", ">= 0");
    expect_bad("{" GRID ", \"material\": {\"density\": 0}}", "material.density", "> 0");
    expect_bad("{" GRID ", \"material\": {\"density\": null}}", "material.density", "null");
    expect_bad("{" GRID ", \"material\": {\"uniform_mass\": -1}}", "material.uniform_mass", ">= 0");
    expect_bad("{" GRID ", \"material\": {\"k\": [1, 2, 3]}}", "material.k", "must be an object");
    expect_bad("{" GRID ", \"material\": 5}", "material", "must be an object");
}

static void test_bad_pins(void) {
    static const char big[] = "{\"mesh\": {\"grid\": {\"n\": [50, 50], \"size\": [1, 1]}}, "
                              "\"pins\": [{\"vertices\": [0]}, {\"vertices\": [1, 2, 3, 5000]}]}";
    expect_bad(big, "scene.json: pins[1].vertices[3]: 5000 is out of range (mesh has 2500 vertices)", NULL);
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": [-1]}]}", "pins[0].vertices[0]", "vertex index");
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": [0, 1.5]}]}", "pins[0].vertices[1]", "vertex index");
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": [\"0\"]}]}", "pins[0].vertices[0]", "not a string");
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": []}]}", "pins[0].vertices", "non-empty");
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": 3}]}", "pins[0].vertices", "non-empty array");
    expect_bad("{" GRID ", \"pins\": [{}]}", "pins[0]", "needs \"vertices\" or \"select\"");
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": [0], \"select\": {\"axis\": \"x\", \"side\": \"max\"}}]}",
               "pins[0]", "not both");
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": [0], \"vertex\": [1]}]}", "pins[0].vertex", "unknown key");
    expect_bad("{" GRID ", \"pins\": {\"vertices\": [0]}}", "pins", "must be an array");
    expect_bad("{" GRID ", \"pins\": [3]}", "pins[0]", "must be an object");
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": [0]}, {\"select\": {\"axis\": \"w\", \"side\": \"max\"}}]}",
               "pins[1].select.axis", "\"w\"");
    expect_bad("{" GRID ", \"pins\": [{\"select\": {\"side\": \"max\"}}]}", "pins[0].select.axis", "missing");
    expect_bad("{" GRID ", \"pins\": [{\"select\": {\"axis\": \"y\", \"side\": \"top\"}}]}", "pins[0].select.side",
               "\"top\"");
    expect_bad("{" GRID ", \"pins\": [{\"select\": {\"axis\": \"y\"}}]}", "pins[0].select.side", "missing");
    expect_bad("{" GRID ", \"pins\": [{\"select\": {\"axis\": \"y\", \"side\": \"min\", \"tolerance\": -1}}]}",
               "pins[0].select.tolerance", ">= 0");
    expect_bad("{" GRID ", \"pins\": [{\"select\": {\"axis\": \"y\", \"side\": \"min\", \"tol\": 1}}]}",
               "pins[0].select.tol", "unknown key");
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": [0], \"free_axis\": [0, 0, 0]}]}", "pins[0].free_axis",
               "nonzero");
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": [0], \"velocity\": [1, 2]}]}", "pins[0].velocity", "3");
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": [0], \"velocity\": [1, 2, 1e999]}]}", "pins[0].velocity[2]",
               "finite");
}

static void test_bad_colliders(void) {
    expect_bad("{" GRID ", \"colliders\": [{\"type\": \"cube\"}]}", "colliders[0].type", "unknown collider type");
    expect_bad("{" GRID ", \"colliders\": [{\"radius\": 1}]}", "colliders[0].type", "missing");
    expect_bad("{" GRID ", \"colliders\": [{\"type\": \"plane\", \"normal\": [0, 1, 0]}, "
               "{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 0}]}",
               "colliders[1].radius", "> 0");
    expect_bad("{" GRID ", \"colliders\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": -1}]}",
               "colliders[0].radius", "> 0");
    expect_bad("{" GRID ", \"colliders\": [{\"type\": \"sphere\", \"center\": [0, 0, 0]}]}", "colliders[0].radius",
               "missing");
    expect_bad("{" GRID ", \"colliders\": [{\"type\": \"sphere\", \"radius\": 1}]}", "colliders[0].center",
               "missing");
    expect_bad("{" GRID ", \"colliders\": [{\"type\": \"plane\", \"normal\": [0, 0, 0]}]}", "colliders[0].normal",
               "nonzero");
    expect_bad("{" GRID ", \"colliders\": [{\"type\": \"plane\"}]}", "colliders[0].normal", "missing");
    expect_bad("{" GRID ", \"colliders\": [{\"type\": \"plane\", \"normal\": [0, 1, 0], \"radius\": 1}]}",
               "colliders[0].radius", "unknown key");
    expect_bad("{" GRID ", \"colliders\": [{\"type\": \"capsule\", \"a\": [0, 0, 0], \"radius\": 0.1}]}",
               "colliders[0].b", "missing");
    expect_bad("{" GRID ", \"colliders\": [{\"type\": \"plane\", \"normal\": [0, 1, 0], \"thickness\": -0.1}]}",
               "colliders[0].thickness", ">= 0");
    expect_bad("{" GRID ", \"colliders\": [{\"type\": \"plane\", \"normal\": [0, 1, 0], \"friction\": -1}]}",
               "colliders[0].friction", ">= 0");
    expect_bad("{" GRID ", \"colliders\": [{\"type\": \"plane\", \"normal\": [0, 1, 0], \"offset\": \"0\"}]}",
               "colliders[0].offset", "finite number");
}

static void test_bad_settings(void) {
    expect_bad("{" GRID ", \"gravity\": [0, \"down\", 0]}", "gravity[1]", "finite number");
    expect_bad("{" GRID ", \"gravity\": -9.81}", "gravity", "array of 3");
    expect_bad("{" GRID ", \"wind\": {\"normal_drag\": -1}}", "wind.normal_drag", ">= 0");
    expect_bad("{" GRID ", \"wind\": {\"tangent_drag\": -1}}", "wind.tangent_drag", ">= 0");
    expect_bad("{" GRID ", \"wind\": {\"speed\": [1, 0, 0]}}", "wind.speed", "unknown key");
    expect_bad("{" GRID ", \"strain_limit\": -0.1}", "strain_limit", ">= 0");
    expect_bad("{" GRID ", \"solver\": {\"type\": \"bogus\"}}", "solver.type", "unknown solver");
    expect_bad("{" GRID ", \"solver\": {\"type\": \"PCG\"}}", "solver.type", "unknown solver");
    expect_bad("{" GRID ", \"solver\": {\"tolerance\": -1e-4}}", "solver.tolerance", ">= 0");
    expect_bad("{" GRID ", \"solver\": {\"max_iterations\": 0}}", "solver.max_iterations", "integer");
    expect_bad("{" GRID ", \"solver\": {\"max_iterations\": 10.5}}", "solver.max_iterations", "integer");
    expect_bad("{" GRID ", \"solver\": \"pcg\"}", "solver", "must be an object");
    expect_bad("{" GRID ", \"time\": {\"fps\": 0}}", "time.fps", "> 0");
    expect_bad("{" GRID ", \"time\": {\"fps\": -30}}", "time.fps", "> 0");
    expect_bad("{" GRID ", \"time\": {\"substeps\": 0}}", "time.substeps", "integer");
    expect_bad("{" GRID ", \"time\": {\"frames\": -1}}", "time.frames", "integer");
    expect_bad("{" GRID ", \"time\": {\"frames\": 1e12}}", "time.frames", "integer");
    expect_bad("{" GRID ", \"time\": {\"seconds\": 3}}", "time.seconds", "unknown key");
    expect_bad("{" GRID ", \"threads\": -1}", "threads", "integer");
    expect_bad("{" GRID ", \"threads\": true}", "threads", "a boolean");
}

/* A minimal grid scene: every default in place, and the documented grid layout. */
static void test_defaults_and_grid(void) {
    wc_diag d;
    weft_status st = parse("{" GRID "}", &d);
    CHECK_EQ_INT(st, WEFT_OK);
    if (st != WEFT_OK) {
        fprintf(stderr, "  %s\n", d.message);
        return;
    }
    const wc_material dm = wc_default_material();
    const wc_model_def dd = wc_default_model_def();
    const wc_sim_def ds = wc_default_sim_def();
    CHECK(memcmp(&S.model_def.material, &dm, sizeof dm) == 0);
    CHECK(S.model_def.weld_tolerance == dd.weld_tolerance);
    CHECK(memcmp(S.sim.gravity, ds.gravity, sizeof ds.gravity) == 0);
    CHECK(memcmp(&S.sim.air, &ds.air, sizeof ds.air) == 0);
    CHECK_EQ_INT(S.sim.solver.type, ds.solver.type);
    CHECK(S.sim.solver.tolerance == ds.solver.tolerance);
    CHECK_EQ_INT(S.sim.solver.max_iterations, ds.solver.max_iterations);
    CHECK_EQ_INT(S.sim.solver.check_every, ds.solver.check_every);
    CHECK(S.sim.solver.chebyshev_gamma == ds.solver.chebyshev_gamma);
    CHECK_EQ_INT(S.sim.substeps, ds.substeps);
    CHECK(S.sim.strain_limit == ds.strain_limit);
    CHECK_EQ_INT(S.sim.threads, ds.threads);
    CHECK_EQ_INT(S.sim.max_colliders, ds.max_colliders);
    CHECK_NEAR(S.fps, 30.0, 0.0);
    CHECK_EQ_INT(S.frames, 60);
    CHECK_EQ_INT(S.n_pins, 0);
    CHECK_EQ_INT(S.n_colliders, 0);
    CHECK_EQ_INT(S.has_transform, 0);
    CHECK_EQ_INT(S.mesh_is_grid, 1);

    /* 4 x 3 vertices over 1.5 m (X) x 1 m (Z): vertex i + 4 j at (-0.75 + 0.5 i, 0, -0.5 + 0.5 j). */
    CHECK_EQ_INT(S.src.n_verts, 12);
    CHECK_EQ_INT(S.src.n_polys, 6);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) {
            const double* p = S.src.pos + 3 * (i + 4 * j);
            CHECK_NEAR(p[0], -0.75 + 0.5 * i, 1e-15);
            CHECK_NEAR(p[1], 0.0, 0.0);
            CHECK_NEAR(p[2], -0.5 + 0.5 * j, 1e-15);
        }
    /* Every quad has 4 corners, the four grid neighbours, and its normal along +Y. */
    for (int q = 0; q < S.src.n_polys; ++q) {
        CHECK_EQ_INT(S.src.poly_start[q + 1] - S.src.poly_start[q], 4);
        const int* c = S.src.poly_verts + S.src.poly_start[q];
        const double *a = S.src.pos + 3 * c[0], *b = S.src.pos + 3 * c[1], *e = S.src.pos + 3 * c[2];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {e[0] - a[0], e[1] - a[1], e[2] - a[2]};
        CHECK(u[2] * v[0] - u[0] * v[2] > 0);   /* y component of u x v */
        CHECK_EQ_INT(c[0], (q % 3) + 4 * (q / 3));
    }
    scene_free(&S);
}

/* Every field given: the values land where they belong, vectors normalised, defaults of the
 * fields left out (collider thickness and friction) filled in. */
static void test_full_scene(void) {
    static const char text[] =
        "{\"description\": \"everything\",\n"
        " \"mesh\": {\"grid\": {\"n\": [5, 4], \"size\": [2, 3]}, \"weld_tolerance\": 0},\n"
        " \"material\": {\"density\": 0.2, \"uniform_mass\": 0.01,\n"
        "   \"k\": {\"stretch\": 4000, \"shear\": 400, \"bend\": 0}, \"d\": {\"stretch\": 1, \"shear\": 0.25, \"bend\": 0}},\n"
        " \"pins\": [{\"vertices\": [0, 4], \"free_axis\": [3, 0, 4], \"velocity\": [0, 0.5, 0]},\n"
        "          {\"select\": {\"axis\": \"z\", \"side\": \"max\"}}],\n"
        " \"colliders\": [{\"type\": \"plane\", \"normal\": [0, 2, 0], \"offset\": -1},\n"
        "   {\"type\": \"sphere\", \"center\": [0, -0.5, 0], \"radius\": 0.25, \"thickness\": 0.01, \"friction\": 0.5},\n"
        "   {\"type\": \"capsule\", \"a\": [-1, -1, 0], \"b\": [1, -1, 0], \"radius\": 0.1}],\n"
        " \"gravity\": [0, -3.7, 0],\n"
        " \"wind\": {\"velocity\": [2, 0, 1], \"normal_drag\": 0.7, \"tangent_drag\": 0},\n"
        " \"strain_limit\": 0.1,\n"
        " \"solver\": {\"type\": \"chebyshev\", \"tolerance\": 1e-6, \"max_iterations\": 50},\n"
        " \"time\": {\"fps\": 24, \"substeps\": 4, \"frames\": 0},\n"
        " \"threads\": 2}\n";
    wc_diag d;
    weft_status st = parse(text, &d);
    CHECK_EQ_INT(st, WEFT_OK);
    if (st != WEFT_OK) {
        fprintf(stderr, "  %s\n", d.message);
        return;
    }
    const wc_material* m = &S.model_def.material;
    CHECK(m->density == 0.2 && m->uniform_mass == 0.01);
    CHECK(m->k[WC_SPRING_STRETCH] == 4000 && m->k[WC_SPRING_SHEAR] == 400 && m->k[WC_SPRING_BEND] == 0);
    CHECK(m->d[WC_SPRING_STRETCH] == 1 && m->d[WC_SPRING_SHEAR] == 0.25 && m->d[WC_SPRING_BEND] == 0);
    CHECK(S.model_def.weld_tolerance == 0);
    CHECK_EQ_INT(S.n_pins, 2);
    CHECK_EQ_INT(S.pins[0].n_vertices, 2);
    CHECK_EQ_INT(S.pins[0].vertices[1], 4);
    CHECK_NEAR(S.pins[0].free_axis[0], 0.6, 1e-15);
    CHECK_NEAR(S.pins[0].free_axis[2], 0.8, 1e-15);
    CHECK_NEAR(S.pins[0].velocity[1], 0.5, 0.0);
    CHECK_EQ_INT(S.pins[1].from_select, 1);
    CHECK_EQ_INT(S.pins[1].n_vertices, 5);   /* the row j = 3: vertices 15..19 */
    for (int k = 0; k < S.pins[1].n_vertices; ++k) CHECK_EQ_INT(S.pins[1].vertices[k], 15 + k);
    CHECK_EQ_INT(S.n_colliders, 3);
    const wc_collider* c = S.colliders;
    CHECK_EQ_INT(c[0].type, WC_COLLIDER_PLANE);
    CHECK_NEAR(c[0].normal[1], 1.0, 0.0);
    CHECK_NEAR(c[0].offset, -1.0, 0.0);
    CHECK_NEAR(c[0].thickness, 0.005, 0.0);
    CHECK_NEAR(c[0].friction, 0.3, 0.0);
    CHECK_EQ_INT(c[1].type, WC_COLLIDER_SPHERE);
    CHECK(c[1].center[1] == -0.5 && c[1].radius == 0.25 && c[1].thickness == 0.01 && c[1].friction == 0.5);
    CHECK_EQ_INT(c[2].type, WC_COLLIDER_CAPSULE);
    CHECK(c[2].a[0] == -1 && c[2].b[0] == 1 && c[2].b[1] == -1 && c[2].radius == 0.1);
    CHECK(c[2].velocity[0] == 0 && c[2].velocity[1] == 0 && c[2].velocity[2] == 0);
    CHECK(S.sim.gravity[0] == 0 && S.sim.gravity[1] == -3.7 && S.sim.gravity[2] == 0);
    CHECK(S.sim.air.wind[0] == 2 && S.sim.air.wind[2] == 1);
    CHECK(S.sim.air.normal_drag == 0.7 && S.sim.air.tangent_drag == 0);
    CHECK(S.sim.strain_limit == 0.1);
    CHECK_EQ_INT(S.sim.solver.type, WC_SOLVER_CHEBYSHEV);
    CHECK(S.sim.solver.tolerance == 1e-6);
    CHECK_EQ_INT(S.sim.solver.max_iterations, 50);
    CHECK(S.fps == 24);
    CHECK_EQ_INT(S.sim.substeps, 4);
    CHECK_EQ_INT(S.frames, 0);
    CHECK_EQ_INT(S.sim.threads, 2);
    scene_free(&S);

    /* More colliders than the default capacity raise it. */
    char many[4096] = "{" GRID ", \"colliders\": [";
    for (int i = 0; i < 20; ++i)
        strcat(many, i ? ", {\"type\": \"plane\", \"normal\": [0, 1, 0]}" : "{\"type\": \"plane\", \"normal\": [0, 1, 0]}");
    strcat(many, "]}");
    CHECK_EQ_INT(parse(many, &d), WEFT_OK);
    CHECK_EQ_INT(S.n_colliders, 20);
    CHECK(S.sim.max_colliders >= 20);
    scene_free(&S);
}

/* Selects on each side, with a tolerance taking two rows, and after a transform. */
static void test_select_and_transform(void) {
    wc_diag d;
    CHECK_EQ_INT(parse("{\"mesh\": {\"grid\": {\"n\": [5, 4], \"size\": [2, 3]}}, \"pins\": ["
                       "{\"select\": {\"axis\": \"x\", \"side\": \"min\"}},"
                       "{\"select\": {\"axis\": \"z\", \"side\": \"min\", \"tolerance\": 1.01}},"
                       "{\"select\": {\"axis\": \"y\", \"side\": \"max\"}}]}",
                       &d),
                 WEFT_OK);
    if (S.n_pins == 3) {
        static const int xmin[] = {0, 5, 10, 15};
        CHECK_EQ_INT(S.pins[0].n_vertices, 4);
        for (int k = 0; k < 4 && k < S.pins[0].n_vertices; ++k) CHECK_EQ_INT(S.pins[0].vertices[k], xmin[k]);
        CHECK_EQ_INT(S.pins[1].n_vertices, 10);   /* z = -1.5 and z = -0.5: rows 0 and 1 */
        for (int k = 0; k < 10 && k < S.pins[1].n_vertices; ++k) CHECK_EQ_INT(S.pins[1].vertices[k], k);
        CHECK_EQ_INT(S.pins[2].n_vertices, 20);   /* flat: every vertex is at the top */
    }
    scene_free(&S);

    /* Rotate +90 degrees about X (y' = -z, z' = y) and move up 2 m: the sheet hangs in the XY
     * plane, its former z max row (j = 3) at the bottom, y = 2 - 1.5. */
    CHECK_EQ_INT(parse("{\"mesh\": {\"grid\": {\"n\": [5, 4], \"size\": [2, 3]}},"
                       " \"transform\": [1, 0, 0, 0,  0, 0, 1, 0,  0, -1, 0, 0,  0, 2, 0, 1],"
                       " \"pins\": [{\"select\": {\"axis\": \"y\", \"side\": \"max\"}}]}",
                       &d),
                 WEFT_OK);
    CHECK_EQ_INT(S.has_transform, 1);
    for (int v = 0; v < S.src.n_verts; ++v) {
        int i = v % 5, j = v / 5;
        CHECK_NEAR(S.src.pos[3 * v + 0], -1.0 + 0.5 * i, 1e-15);
        CHECK_NEAR(S.src.pos[3 * v + 1], 2.0 - (-1.5 + j), 1e-15);
        CHECK_NEAR(S.src.pos[3 * v + 2], 0.0, 1e-15);
    }
    CHECK_EQ_INT(S.n_pins, 1);
    if (S.n_pins == 1) {
        CHECK_EQ_INT(S.pins[0].n_vertices, 5);   /* the former z min row j = 0, now at y = 3.5 */
        for (int k = 0; k < S.pins[0].n_vertices; ++k) CHECK_EQ_INT(S.pins[0].vertices[k], k);
    }
    scene_free(&S);
}

/* A mesh file next to the scene file, found relative to it, scaled. Two triangles with their own
 * copies (own UVs) of the shared edge's vertices (1 = 4, 2 = 3 in position): welding merges them,
 * and pins naming both copies merge into one pin per particle. */
static void test_file_mesh_and_pins(void) {
    ts_write_tmp("scene_mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nv 0 0 1\nv 1 0 0\nv 1 0 1\n"
                                   "vt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\nf 1/1 2/2 3/3\nf 4/4 5/4 6/4\n");
    const char* scene_path = ts_write_tmp("scene_file.json",
                                          "{\"mesh\": {\"file\": \"scene_mesh.obj\", \"scale\": 0.5},"
                                          " \"pins\": [{\"vertices\": [1, 4, 1]}, {\"vertices\": [0]},"
                                          "            {\"select\": {\"axis\": \"x\", \"side\": \"min\"}}]}");
    wc_diag d = {0};
    weft_status st = scene_load(&S, scene_path, &d);
    CHECK_EQ_INT(st, WEFT_OK);
    if (st != WEFT_OK) {
        fprintf(stderr, "  %s\n", d.message);
        return;
    }
    CHECK_EQ_INT(S.mesh_is_grid, 0);
    CHECK_EQ_INT(S.src.n_verts, 6);
    CHECK_NEAR(S.src.pos[3 * 5 + 0], 0.5, 1e-12);
    CHECK_NEAR(S.src.pos[3 * 5 + 2], 0.5, 1e-12);
    CHECK_EQ_INT(S.pins[2].n_vertices, 3);   /* x = 0: vertices 0, 2, 3 */

    wc_model model = {0};
    wc_diag md = {0};
    CHECK_EQ_INT(wc_model_build(&model, &S.src, &S.model_def, NULL, &md), WEFT_OK);
    CHECK_EQ_INT(model.n_particles, 4);
    scene_pins p = {0};
    CHECK_EQ_INT(scene_pins_resolve(&p, &S, &model, "scene_file.json", &d), WEFT_OK);
    /* particles of vertices {1,4}, {0}, {2,3}: three distinct pins */
    CHECK_EQ_INT(p.n, 3);
    for (int i = 0; i < p.n; ++i) {
        const double* r = model.rest_pos + 3 * p.pins[i].particle;
        for (int k = 0; k < 3; ++k) CHECK(p.pins[i].target[k] == r[k]);
        CHECK(p.pins[i].free_axis[0] == 0 && p.pins[i].free_axis[1] == 0 && p.pins[i].free_axis[2] == 0);
        for (int j = 0; j < i; ++j) CHECK(p.pins[i].particle != p.pins[j].particle);
    }
    if (p.n == 3) CHECK_EQ_INT(p.pins[0].particle, model.host_to_particle[1]);
    CHECK_EQ_INT(p.moving, 0);
    scene_pins_free(&p);
    wc_model_free(&model);
    scene_free(&S);

    st = scene_load(&S, ts_tmp_path("no_such_scene.json"), &d);
    CHECK(st == WEFT_ERROR_IO);
    CHECK(strstr(d.message, "no_such_scene.json") != NULL);
}

/* A host vertex that no polygon uses (files cannot carry one through assimp; host arrays can)
 * cannot be pinned by index, and is not chosen by a select. */
static void test_unused_vertex(void) {
    static const double pos[] = {0, 0, 0, 1, 0, 0, 0, 0, 1, 9, 0, 0};
    static const int sizes[] = {3}, idx[] = {0, 1, 2};
    memset(&S, 0, sizeof S);
    wc_diag d = {0};
    CHECK_EQ_INT(wc_source_mesh_from_arrays(&S.src, NULL, pos, 4, sizes, 1, idx, 1.0, &d), WEFT_OK);
    S.n_pins = 2;
    S.pins = calloc(2, sizeof(scene_pin));
    S.pins[0].from_select = 1;   /* x max: vertex 1, not the unused vertex 3 at x = 9 */
    S.pins[0].select_axis = 0;
    S.pins[0].select_max = 1;
    S.pins[0].select_tolerance = 1e-6;
    CHECK_EQ_INT(scene_mesh_check_pins(&S, "scene.json", &d), WEFT_OK);
    CHECK_EQ_INT(S.pins[0].n_vertices, 1);
    if (S.pins[0].n_vertices == 1) CHECK_EQ_INT(S.pins[0].vertices[0], 1);
    S.pins[1].n_vertices = 2;
    S.pins[1].vertices = malloc(2 * sizeof(int));
    S.pins[1].vertices[0] = 2;
    S.pins[1].vertices[1] = 3;
    CHECK(scene_mesh_check_pins(&S, "scene.json", &d) == WEFT_ERROR_SCENE);
    CHECK(strstr(d.message, "scene.json: pins[1].vertices[1]: vertex 3 ") != NULL);
    scene_free(&S);
}

/* Moving pins, and conflicting pins of one particle. */
static void test_pin_motion_and_conflicts(void) {
    wc_diag d;
    CHECK_EQ_INT(parse("{" GRID ", \"pins\": [{\"vertices\": [3], \"velocity\": [0, 1, -2]},"
                       " {\"vertices\": [0], \"free_axis\": [0, 0, 2]}, {\"vertices\": [3], \"velocity\": [0, 1, -2]}]}",
                       &d),
                 WEFT_OK);
    wc_model model = {0};
    CHECK_EQ_INT(wc_model_build(&model, &S.src, &S.model_def, NULL, &d), WEFT_OK);
    scene_pins p = {0};
    CHECK_EQ_INT(scene_pins_resolve(&p, &S, &model, "scene.json", &d), WEFT_OK);
    CHECK_EQ_INT(p.n, 2);
    CHECK_EQ_INT(p.moving, 1);
    if (p.n == 2) {
        CHECK_NEAR(p.pins[1].free_axis[2], 1.0, 0.0);
        scene_pins_at(&p, 0.25);
        const double* r = model.rest_pos + 3 * model.host_to_particle[3];
        CHECK_NEAR(p.pins[0].target[0], r[0], 0.0);
        CHECK_NEAR(p.pins[0].target[1], r[1] + 0.25, 1e-15);
        CHECK_NEAR(p.pins[0].target[2], r[2] - 0.5, 1e-15);
        CHECK_NEAR(p.pins[0].target[0], 0.75, 1e-15);   /* vertex 3 = (i 3, j 0) */
        CHECK_NEAR(p.pins[0].target[2], -1.0, 1e-15);
        const double* r0 = model.rest_pos + 3 * model.host_to_particle[0];
        for (int k = 0; k < 3; ++k) CHECK(p.pins[1].target[k] == r0[k]);
    }
    scene_pins_free(&p);
    wc_model_free(&model);
    scene_free(&S);

    CHECK_EQ_INT(parse("{" GRID ", \"pins\": [{\"select\": {\"axis\": \"x\", \"side\": \"max\"}},"
                       " {\"vertices\": [0, 11], \"velocity\": [0, 1, 0]}]}",
                       &d),
                 WEFT_OK);
    CHECK_EQ_INT(wc_model_build(&model, &S.src, &S.model_def, NULL, &d), WEFT_OK);
    weft_status st = scene_pins_resolve(&p, &S, &model, "scene.json", &d);
    CHECK(st == WEFT_ERROR_SCENE);
    CHECK(strstr(d.message, "scene.json: pins[1].vertices[1]: vertex 11") != NULL);
    CHECK(strstr(d.message, "pins[0]") != NULL);
    CHECK(p.pins == NULL && p.n == 0);
    wc_model_free(&model);
    scene_free(&S);
}

int main(void) {
    RUN_TEST(test_bad_syntax_and_structure);
    RUN_TEST(test_bad_mesh);
    RUN_TEST(test_bad_material);
    RUN_TEST(test_bad_pins);
    RUN_TEST(test_bad_colliders);
    RUN_TEST(test_bad_settings);
    RUN_TEST(test_defaults_and_grid);
    RUN_TEST(test_full_scene);
    RUN_TEST(test_select_and_transform);
    RUN_TEST(test_file_mesh_and_pins);
    RUN_TEST(test_unused_vertex);
    RUN_TEST(test_pin_motion_and_conflicts);
    return TEST_SUMMARY();
}
