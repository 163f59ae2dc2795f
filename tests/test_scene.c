/* The scene file parser (plugin/cli/scene/): every kind of bad scene is refused with a message
 * naming the field; good scenes parse to the values written, with the documented defaults filled
 * in; the generated grid has the documented host vertex order, position and winding; selects,
 * transforms and relative mesh paths resolve; pins group into attachments (duplicates merge,
 * conflicts are refused); motions match their closed form; object, teleport and camera settings
 * parse; collider placements follow the public API's local conventions. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "scene.h"
#include "scene_colliders.h"
#include "scene_mesh.h"
#include "scene_xform.h"
#include "test_support.h"

#define GRID "\"mesh\": {\"grid\": {\"n\": [4, 3], \"size\": [1.5, 1]}}"

static scene S;   /* static: large enough to keep off the stack */

static weft_status parse(const char* text, cli_diag* d) {
    memset(d, 0, sizeof *d);
    return scene_parse(&S, text, strlen(text), "scene.json", d);
}

/* text must be refused; the message must start with the file name and contain `field` (and
 * `detail` when not NULL). */
static void expect_bad(const char* text, const char* field, const char* detail) {
    cli_diag d;
    weft_status st = parse(text, &d);
    CHECK(st != WEFT_OK);
    CHECK(d.status == st);
    CHECK(strncmp(d.message, "scene.json: ", 12) == 0);
    CHECK(strstr(d.message, field) != NULL);
    if (detail) CHECK(strstr(d.message, detail) != NULL);
    CHECK(strchr(d.message, '\n') == NULL);
    CHECK(S.mesh.positions == NULL && S.pins == NULL && S.colliders == NULL);
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
    expect_bad("{\"mesh\": {\"file\": \"x.obj\", \"weld_tolerance\": 1.5}}", "mesh.weld_tolerance", "[0, 1]");
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
    expect_bad("{" GRID ", \"material\": {\"uniform_mass\": 0.01}}", "material.uniform_mass", "no longer supported");
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
    expect_bad("{" GRID ", \"solver\": {\"tolerance\": 1}}", "solver.tolerance", "[0, 1)");
    expect_bad("{" GRID ", \"solver\": {\"tolerance\": -1}}", "solver.tolerance", ">= 0");   /* "default" says it */
    expect_bad("{" GRID ", \"solver\": {\"tolerance\": \"tight\"}}", "solver.tolerance", "number");
    expect_bad("{" GRID ", \"solver\": {\"max_iterations\": 0}}", "solver.max_iterations", "integer");
    expect_bad("{" GRID ", \"solver\": {\"max_iterations\": 10.5}}", "solver.max_iterations", "integer");
    expect_bad("{" GRID ", \"solver\": \"pcg\"}", "solver", "must be an object");
    expect_bad("{" GRID ", \"solver\": {\"preconditioner\": \"ilu\"}}", "solver.preconditioner", "unknown preconditioner");
    expect_bad("{" GRID ", \"solver\": {\"preconditioner\": 1}}", "solver.preconditioner", "string");
    expect_bad("{" GRID ", \"solver\": {\"newton_iterations\": 0}}", "solver.newton_iterations", "integer");
    expect_bad("{" GRID ", \"solver\": {\"newton_iterations\": 101}}", "solver.newton_iterations", "integer");
    expect_bad("{" GRID ", \"solver\": {\"line_search\": 1}}", "solver.line_search", "true or false");
    expect_bad("{" GRID ", \"solver\": {\"newton_forcing\": 1}}", "solver.newton_forcing", "[0, 1) or \"default\"");
    expect_bad("{" GRID ", \"solver\": {\"newton_forcing\": \"tight\"}}", "solver.newton_forcing", "a number");
    expect_bad("{" GRID ", \"time\": {\"integrator\": \"rk4\"}}", "time.integrator", "unknown integrator");
    expect_bad("{" GRID ", \"time\": {\"integrator\": \"BDF2\"}}", "time.integrator", "unknown integrator");
    expect_bad("{" GRID ", \"time\": {\"fps\": 0}}", "time.fps", "> 0");
    expect_bad("{" GRID ", \"time\": {\"fps\": -30}}", "time.fps", "> 0");
    expect_bad("{" GRID ", \"time\": {\"substeps\": 0}}", "time.substeps", "integer");
    expect_bad("{" GRID ", \"time\": {\"frames\": -1}}", "time.frames", "integer");
    expect_bad("{" GRID ", \"time\": {\"frames\": 1e12}}", "time.frames", "integer");
    expect_bad("{" GRID ", \"time\": {\"seconds\": 3}}", "time.seconds", "unknown key");
    expect_bad("{" GRID ", \"threads\": -1}", "threads", "integer");
    expect_bad("{" GRID ", \"threads\": true}", "threads", "a boolean");
    expect_bad("{" GRID ", \"self_collision\": 1}", "self_collision", "true or false");
    expect_bad("{" GRID ", \"self_thickness\": 0}", "self_thickness", "> 0");
    expect_bad("{" GRID ", \"self_thickness\": -0.003}", "self_thickness", "> 0");
    expect_bad("{" GRID ", \"self_thickness\": \"3mm\"}", "self_thickness", "number");
}

/* A minimal grid scene: every default in place, and the documented grid layout. */
static void test_defaults_and_grid(void) {
    cli_diag d;
    weft_status st = parse("{" GRID "}", &d);
    CHECK_EQ_INT(st, WEFT_OK);
    if (st != WEFT_OK) {
        fprintf(stderr, "  %s\n", d.message);
        return;
    }
    const weft_cloth_def dd = weft_default_cloth_def();   /* the library's defaults */
    CHECK(memcmp(&S.def.material, &dd.material, sizeof dd.material) == 0);
    CHECK(S.def.weld_tolerance == dd.weld_tolerance);
    CHECK(memcmp(S.def.gravity, dd.gravity, sizeof dd.gravity) == 0);
    CHECK(memcmp(S.def.wind, dd.wind, sizeof dd.wind) == 0);
    CHECK(S.def.air_drag_normal == dd.air_drag_normal && S.def.air_drag_tangent == dd.air_drag_tangent);
    CHECK_EQ_INT(S.def.solver, dd.solver);
    CHECK(S.def.tolerance == dd.tolerance);
    CHECK_EQ_INT(S.def.max_iterations, dd.max_iterations);
    CHECK_EQ_INT(S.def.substeps, dd.substeps);
    CHECK(S.def.strain_limit == dd.strain_limit);
    CHECK_EQ_INT(S.threads, 0);
    CHECK_EQ_INT(S.def.preconditioner, WEFT_PRECOND_DEFAULT);
    CHECK_EQ_INT(S.def.integrator, WEFT_INTEGRATOR_DEFAULT);
    CHECK_EQ_INT(S.def.newton_iterations, 0);
    CHECK_EQ_INT(S.def.line_search, -1);
    CHECK(S.def.newton_forcing == -1.0);
    CHECK_EQ_INT(S.def.self_collision, -1);
    CHECK(S.def.self_collision_thickness == dd.self_collision_thickness);
    scene_free(&S);
    st = parse("{" GRID ", \"self_collision\": true, \"self_thickness\": 0.005}", &d);
    CHECK_EQ_INT(st, WEFT_OK);
    CHECK_EQ_INT(S.def.self_collision, 1);
    CHECK(S.def.self_collision_thickness == 0.005);
    scene_free(&S);
    st = parse("{" GRID ", \"self_collision\": false}", &d);
    CHECK_EQ_INT(st, WEFT_OK);
    CHECK_EQ_INT(S.def.self_collision, 0);
    scene_free(&S);
    st = parse("{" GRID ", \"solver\": {\"preconditioner\": \"amg\", \"newton_iterations\": 3, \"line_search\": true},"
               " \"time\": {\"integrator\": \"bdf2\"}}", &d);
    CHECK_EQ_INT(st, WEFT_OK);
    CHECK_EQ_INT(S.def.preconditioner, WEFT_PRECOND_AMG);
    CHECK_EQ_INT(S.def.integrator, WEFT_INTEGRATOR_BDF2);
    CHECK_EQ_INT(S.def.newton_iterations, 3);
    CHECK_EQ_INT(S.def.line_search, 1);
    scene_free(&S);
    st = parse("{" GRID ", \"solver\": {\"preconditioner\": \"ic0\", \"newton_forcing\": 0}}", &d);
    CHECK_EQ_INT(st, WEFT_OK);
    CHECK_EQ_INT(S.def.preconditioner, WEFT_PRECOND_IC0);
    CHECK(S.def.newton_forcing == 0.0);
    scene_free(&S);
    st = parse("{" GRID ", \"solver\": {\"newton_forcing\": \"default\"}}", &d);
    CHECK_EQ_INT(st, WEFT_OK);
    CHECK(S.def.newton_forcing == -1.0);
    scene_free(&S);
    st = parse("{" GRID ", \"solver\": {\"tolerance\": \"default\"}}", &d);
    CHECK_EQ_INT(st, WEFT_OK);
    CHECK(S.def.tolerance == -1.0);
    scene_free(&S);
    st = parse("{" GRID ", \"time\": {\"integrator\": \"trbdf2\"}}", &d);
    CHECK_EQ_INT(st, WEFT_OK);
    CHECK_EQ_INT(S.def.integrator, WEFT_INTEGRATOR_TRBDF2);
    scene_free(&S);
    st = parse("{" GRID ", \"time\": {\"integrator\": \"tr-bdf2\"}}", &d);
    CHECK(st != WEFT_OK);
    CHECK(strstr(d.message, "expected be, bdf2, trbdf2 or default") != NULL);
    st = parse("{" GRID "}", &d);
    CHECK_NEAR(S.fps, 30.0, 0.0);
    CHECK_EQ_INT(S.frames, 60);
    CHECK_EQ_INT(S.n_pins, 0);
    CHECK_EQ_INT(S.n_colliders, 0);
    CHECK_EQ_INT(S.has_transform, 0);
    CHECK_EQ_INT(S.mesh_is_grid, 1);

    /* 4 x 3 vertices over 1.5 m (X) x 1 m (Z): vertex i + 4 j at (-0.75 + 0.5 i, 0, -0.5 + 0.5 j). */
    CHECK_EQ_INT(S.mesh.n_vertices, 12);
    CHECK_EQ_INT(S.mesh.n_faces, 6);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) {
            const double* p = S.mesh.positions + 3 * (i + 4 * j);
            CHECK_NEAR(p[0], -0.75 + 0.5 * i, 1e-15);
            CHECK_NEAR(p[1], 0.0, 0.0);
            CHECK_NEAR(p[2], -0.5 + 0.5 * j, 1e-15);
        }
    /* Every quad has 4 corners, the four grid neighbours, and its normal along +Y. */
    for (int q = 0; q < S.mesh.n_faces; ++q) {
        CHECK_EQ_INT(S.mesh.face_start[q + 1] - S.mesh.face_start[q], 4);
        CHECK_EQ_INT(S.mesh.face_sizes[q], 4);
        const int* c = S.mesh.indices + S.mesh.face_start[q];
        const double *a = S.mesh.positions + 3 * c[0], *b = S.mesh.positions + 3 * c[1], *e = S.mesh.positions + 3 * c[2];
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
        " \"material\": {\"density\": 0.2,\n"
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
    cli_diag d;
    weft_status st = parse(text, &d);
    CHECK_EQ_INT(st, WEFT_OK);
    if (st != WEFT_OK) {
        fprintf(stderr, "  %s\n", d.message);
        return;
    }
    const weft_material* m = &S.def.material;
    CHECK(m->density == 0.2);
    CHECK(m->stiffness[WEFT_SPRING_STRETCH] == 4000 && m->stiffness[WEFT_SPRING_SHEAR] == 400 &&
          m->stiffness[WEFT_SPRING_BEND] == 0);
    CHECK(m->damping[WEFT_SPRING_STRETCH] == 1 && m->damping[WEFT_SPRING_SHEAR] == 0.25 &&
          m->damping[WEFT_SPRING_BEND] == 0);
    CHECK(S.def.weld_tolerance == 0);
    CHECK_EQ_INT(S.n_pins, 2);
    CHECK_EQ_INT(S.pins[0].n_vertices, 2);
    CHECK_EQ_INT(S.pins[0].vertices[1], 4);
    CHECK_NEAR(S.pins[0].free_axis[0], 0.6, 1e-15);
    CHECK_NEAR(S.pins[0].free_axis[2], 0.8, 1e-15);
    CHECK_NEAR(S.pins[0].motion.velocity[1], 0.5, 0.0);
    CHECK_NEAR(S.pins[0].motion.velocity[0], 0.0, 0.0);
    CHECK(scene_motion_is_still(&S.pins[1].motion));
    CHECK_EQ_INT(S.n_pin_groups, 2);
    CHECK_EQ_INT(S.pins[1].from_select, 1);
    CHECK_EQ_INT(S.pins[1].n_vertices, 5);   /* the row j = 3: vertices 15..19 */
    for (int k = 0; k < S.pins[1].n_vertices; ++k) CHECK_EQ_INT(S.pins[1].vertices[k], 15 + k);
    CHECK_EQ_INT(S.n_colliders, 3);
    const scene_collider* c = S.colliders;
    CHECK_EQ_INT(c[0].type, WEFT_COLLIDER_PLANE);
    CHECK_NEAR(c[0].normal[1], 1.0, 0.0);
    CHECK_NEAR(c[0].offset, -1.0, 0.0);
    CHECK_NEAR(c[0].thickness, 0.005, 0.0);
    CHECK_NEAR(c[0].friction, 0.3, 0.0);
    CHECK_EQ_INT(c[1].type, WEFT_COLLIDER_SPHERE);
    CHECK(c[1].center[1] == -0.5 && c[1].radius == 0.25 && c[1].thickness == 0.01 && c[1].friction == 0.5);
    CHECK_EQ_INT(c[2].type, WEFT_COLLIDER_CAPSULE);
    CHECK(c[2].a[0] == -1 && c[2].b[0] == 1 && c[2].b[1] == -1 && c[2].radius == 0.1);
    CHECK(scene_motion_is_still(&c[2].motion));
    CHECK(S.def.gravity[0] == 0 && S.def.gravity[1] == -3.7 && S.def.gravity[2] == 0);
    CHECK(S.def.wind[0] == 2 && S.def.wind[2] == 1);
    CHECK(S.def.air_drag_normal == 0.7 && S.def.air_drag_tangent == 0);
    CHECK(S.def.strain_limit == 0.1);
    CHECK_EQ_INT(S.def.solver, WEFT_SOLVER_CHEBYSHEV);
    CHECK(S.def.tolerance == 1e-6);
    CHECK_EQ_INT(S.def.max_iterations, 50);
    CHECK(S.fps == 24);
    CHECK_EQ_INT(S.def.substeps, 4);
    CHECK_EQ_INT(S.frames, 0);
    CHECK_EQ_INT(S.threads, 2);
    scene_free(&S);

    /* Many colliders: the library takes them all (its capacity is the count given). */
    char many[4096] = "{" GRID ", \"colliders\": [";
    for (int i = 0; i < 20; ++i)
        strcat(many, i ? ", {\"type\": \"plane\", \"normal\": [0, 1, 0]}" : "{\"type\": \"plane\", \"normal\": [0, 1, 0]}");
    strcat(many, "]}");
    CHECK_EQ_INT(parse(many, &d), WEFT_OK);
    CHECK_EQ_INT(S.n_colliders, 20);
    scene_free(&S);
}

/* Selects on each side, with a tolerance taking two rows, and after a transform. */
static void test_select_and_transform(void) {
    cli_diag d;
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
    for (int v = 0; v < S.mesh.n_vertices; ++v) {
        int i = v % 5, j = v / 5;
        CHECK_NEAR(S.mesh.positions[3 * v + 0], -1.0 + 0.5 * i, 1e-15);
        CHECK_NEAR(S.mesh.positions[3 * v + 1], 2.0 - (-1.5 + j), 1e-15);
        CHECK_NEAR(S.mesh.positions[3 * v + 2], 0.0, 1e-15);
    }
    CHECK_EQ_INT(S.n_pins, 1);
    if (S.n_pins == 1) {
        CHECK_EQ_INT(S.pins[0].n_vertices, 5);   /* the former z min row j = 0, now at y = 3.5 */
        for (int k = 0; k < S.pins[0].n_vertices; ++k) CHECK_EQ_INT(S.pins[0].vertices[k], k);
    }
    scene_free(&S);
}

/* A mesh file next to the scene file, found relative to it, scaled. Two triangles with their own
 * copies (own UVs) of the shared edge's vertices (1 = 4, 2 = 3 in position). Pin entries with the
 * same free_axis and motion form one group (one attachment), each host vertex once, ascending
 * (welded twins are merged later, by the library). */
static void test_file_mesh_and_pins(void) {
    ts_write_tmp("scene_mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nv 0 0 1\nv 1 0 0\nv 1 0 1\n"
                                   "vt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\nf 1/1 2/2 3/3\nf 4/4 5/4 6/4\n");
    const char* scene_path = ts_write_tmp("scene_file.json",
                                          "{\"mesh\": {\"file\": \"scene_mesh.obj\", \"scale\": 0.5},"
                                          " \"pins\": [{\"vertices\": [1, 4, 1]}, {\"vertices\": [0]},"
                                          "            {\"select\": {\"axis\": \"x\", \"side\": \"min\"}}]}");
    cli_diag d = {0};
    weft_status st = scene_load(&S, scene_path, &d);
    CHECK_EQ_INT(st, WEFT_OK);
    if (st != WEFT_OK) {
        fprintf(stderr, "  %s\n", d.message);
        return;
    }
    CHECK_EQ_INT(S.mesh_is_grid, 0);
    CHECK_EQ_INT(S.mesh.n_vertices, 6);
    CHECK_NEAR(S.mesh.positions[3 * 5 + 0], 0.5, 1e-12);
    CHECK_NEAR(S.mesh.positions[3 * 5 + 2], 0.5, 1e-12);
    CHECK_EQ_INT(S.pins[2].n_vertices, 3);   /* x = 0: vertices 0, 2, 3 */
    CHECK_EQ_INT(S.n_pin_groups, 1);
    if (S.n_pin_groups == 1) {
        const scene_pin_group* g = &S.pin_groups[0];
        CHECK_EQ_INT(g->n_vertices, 5);      /* 0, 1, 2, 3, 4 */
        for (int k = 0; k < g->n_vertices && k < 5; ++k) CHECK_EQ_INT(g->vertices[k], k);
        CHECK(g->free_axis[0] == 0 && g->free_axis[1] == 0 && g->free_axis[2] == 0);
        CHECK(scene_motion_is_still(&g->motion));
        CHECK_EQ_INT(g->first_pin, 0);
    }
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
    cli_diag d = {0};
    CHECK_EQ_INT(scene_mesh_from_arrays(&S.mesh, pos, 4, sizes, 1, idx, &d), WEFT_OK);
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

/* Moving pins group by motion; the shorthand velocity is a motion; one vertex in two entries
 * with different values is refused, naming both entries. */
static void test_pin_groups_and_conflicts(void) {
    cli_diag d;
    CHECK_EQ_INT(parse("{" GRID ", \"pins\": [{\"vertices\": [3], \"velocity\": [0, 1, -2]},"
                       " {\"vertices\": [0], \"free_axis\": [0, 0, 2]},"
                       " {\"vertices\": [3, 7], \"motion\": {\"velocity\": [0, 1, -2]}}]}",
                       &d),
                 WEFT_OK);
    CHECK_EQ_INT(S.n_pin_groups, 2);
    if (S.n_pin_groups == 2) {
        const scene_pin_group* g = S.pin_groups;
        CHECK_EQ_INT(g[0].n_vertices, 2);   /* 3 (twice) and 7 */
        CHECK_EQ_INT(g[0].vertices[0], 3);
        CHECK_EQ_INT(g[0].vertices[1], 7);
        CHECK_EQ_INT(g[1].n_vertices, 1);
        CHECK_EQ_INT(g[1].vertices[0], 0);
        CHECK_EQ_INT(g[1].first_pin, 1);
        CHECK_NEAR(g[1].free_axis[2], 1.0, 0.0);
        /* vertex 3 = (i 3, j 0) at (0.75, 0, -0.5) moves to rest + velocity t */
        double m[16], p[3];
        scene_motion_at(&g[0].motion, 0.25, m);
        const double* r = S.mesh.positions + 3 * 3;
        for (int k = 0; k < 3; ++k) p[k] = m[k] * r[0] + m[4 + k] * r[1] + m[8 + k] * r[2] + m[12 + k];
        CHECK_NEAR(p[0], 0.75, 1e-15);
        CHECK_NEAR(p[1], 0.25, 1e-15);
        CHECK_NEAR(p[2], -1.0, 1e-15);
    }
    scene_free(&S);

    expect_bad("{" GRID ", \"pins\": [{\"select\": {\"axis\": \"x\", \"side\": \"max\"}},"
               " {\"vertices\": [0, 11], \"velocity\": [0, 1, 0]}]}",
               "scene.json: pins[1].vertices[1]: vertex 11 is already pinned by pins[0]", "motion");
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": [5], \"free_axis\": [1, 0, 0]},"
               " {\"select\": {\"axis\": \"x\", \"side\": \"min\", \"tolerance\": 0.6}}]}",
               "scene.json: pins[1].select: vertex 5 is already pinned by pins[0]", NULL);
}

/* T(t) against the vector form of the same motion, p' = pivot + Rodrigues(p - pivot) + velocity
 * tau + amplitude sin(2 pi hz tau), computed here independently of the matrices. */
static void test_motion_closed_form(void) {
    cli_diag d;
    CHECK_EQ_INT(parse("{" GRID ", \"pins\": [{\"vertices\": [0], \"motion\": {\"pivot\": [1, 2, 3],"
                       " \"velocity\": [0.5, -1, 0.25], \"spin_axis\": [0, 3, 4], \"spin_deg_per_s\": 90,"
                       " \"oscillate\": {\"amplitude\": [0.1, 0.2, -0.3], \"hz\": 1.5}, \"start\": 0.5}}]}",
                       &d),
                 WEFT_OK);
    if (S.n_pins != 1) return;
    const scene_motion* m = &S.pins[0].motion;
    CHECK_NEAR(m->spin_axis[1], 0.6, 1e-15);
    CHECK_NEAR(m->spin_axis[2], 0.8, 1e-15);
    const double pi = 3.14159265358979323846, k[3] = {0, 0.6, 0.8};
    const double pts[3][3] = {{0, 0, 0}, {1, 2, 3}, {-2, 0.5, 4}};
    const double times[] = {0.0, 0.3, 0.5, 0.75, 1.9};
    for (int ti = 0; ti < 5; ++ti)
        for (int pi_ = 0; pi_ < 3; ++pi_) {
            const double t = times[ti], tau = t > 0.5 ? t - 0.5 : 0.0, th = 90.0 * tau * pi / 180.0;
            const double* p = pts[pi_];
            const double r[3] = {p[0] - 1, p[1] - 2, p[2] - 3};
            const double kxr[3] = {k[1] * r[2] - k[2] * r[1], k[2] * r[0] - k[0] * r[2], k[0] * r[1] - k[1] * r[0]};
            const double kr = k[0] * r[0] + k[1] * r[1] + k[2] * r[2];
            const double v[3] = {0.5, -1, 0.25}, a[3] = {0.1, 0.2, -0.3}, piv[3] = {1, 2, 3};
            double xf[16];
            scene_motion_at(m, t, xf);
            for (int c = 0; c < 3; ++c) {
                const double want = piv[c] + r[c] * cos(th) + kxr[c] * sin(th) + k[c] * kr * (1 - cos(th)) +
                                    v[c] * tau + a[c] * sin(2 * pi * 1.5 * tau);
                const double got = xf[c] * p[0] + xf[4 + c] * p[1] + xf[8 + c] * p[2] + xf[12 + c];
                CHECK_NEAR(got, want, 1e-12);
            }
            CHECK(xf[3] == 0 && xf[7] == 0 && xf[11] == 0 && xf[15] == 1);
        }
    scene_free(&S);
    const scene_motion still = scene_motion_still();
    CHECK(scene_motion_is_still(&still));
    double xf[16];
    scene_motion_at(&still, 12.5, xf);
    for (int i = 0; i < 16; ++i) CHECK(xf[i] == (i % 5 == 0 ? 1.0 : 0.0));
}

static void test_bad_motion(void) {
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": [0], \"motion\": {\"speed\": [1, 0, 0]}}]}",
               "pins[0].motion.speed", "unknown key");
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": [0], \"motion\": [1, 0, 0]}]}", "pins[0].motion",
               "must be an object");
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": [0], \"velocity\": [1, 0, 0], \"motion\": {}}]}",
               "pins[0].velocity", "not both");
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": [0], \"motion\": {\"spin_axis\": [0, 0, 0]}}]}",
               "pins[0].motion.spin_axis", "nonzero");
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": [0], \"motion\": {\"spin_deg_per_s\": \"fast\"}}]}",
               "pins[0].motion.spin_deg_per_s", "finite number");
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": [0], \"motion\": {\"pivot\": [0, 1e999, 0]}}]}",
               "pins[0].motion.pivot[1]", "finite");
    expect_bad("{" GRID ", \"pins\": [{\"vertices\": [0], \"motion\": {\"start\": -1}}]}",
               "pins[0].motion.start", ">= 0");
    expect_bad("{" GRID ", \"colliders\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1,"
               " \"motion\": {\"oscillate\": {\"amplitude\": [0, 1, 0]}}}]}",
               "colliders[0].motion.oscillate.hz", "missing");
    expect_bad("{" GRID ", \"colliders\": [{\"type\": \"plane\", \"normal\": [0, 1, 0],"
               " \"motion\": {\"oscillate\": {\"hz\": 2}}}]}",
               "colliders[0].motion.oscillate.amplitude", "missing");
    expect_bad("{" GRID ", \"colliders\": [{\"type\": \"plane\", \"normal\": [0, 1, 0],"
               " \"motion\": {\"oscillate\": {\"amplitude\": [0, 1, 0], \"hz\": 0}}}]}",
               "colliders[0].motion.oscillate.hz", "> 0");
    expect_bad("{" GRID ", \"colliders\": [{\"type\": \"plane\", \"normal\": [0, 1, 0],"
               " \"motion\": {\"oscillate\": {\"amplitude\": [0, 1, 0], \"hz\": 1, \"phase\": 0}}}]}",
               "colliders[0].motion.oscillate.phase", "unknown key");
    expect_bad("{" GRID ", \"object\": {\"motion\": {\"velocity\": [1, 0]}}}", "object.motion.velocity",
               "array of 3");
    expect_bad("{" GRID ", \"object\": {\"linear_inertia\": 1.5}}", "object.linear_inertia", "[0, 1]");
    expect_bad("{" GRID ", \"object\": {\"angular_inertia\": -0.5}}", "object.angular_inertia", ">= 0");
    expect_bad("{" GRID ", \"object\": {\"inertia\": 1}}", "object.inertia", "unknown key");
    expect_bad("{" GRID ", \"object\": 1}", "object", "must be an object");
    expect_bad("{" GRID ", \"object\": {\"teleport\": [{\"frame\": 0, \"translate\": [1, 0, 0]}]}}",
               "object.teleport[0].frame", "integer in [1,");
    expect_bad("{" GRID ", \"object\": {\"teleport\": [{\"frame\": 3}]}}", "object.teleport[0].translate",
               "missing");
    expect_bad("{" GRID ", \"object\": {\"teleport\": [{\"frame\": 3, \"translate\": [1, 0, 0]},"
               " {\"frame\": 3, \"translate\": [1, 0, 0]}]}}",
               "object.teleport[1].frame", "increase");
    expect_bad("{" GRID ", \"object\": {\"teleport\": {\"frame\": 3}}}", "object.teleport", "must be an array");
}

/* The object: motion, inertia and teleports as written; defaults when absent. */
static void test_object(void) {
    cli_diag d;
    CHECK_EQ_INT(parse("{" GRID "}", &d), WEFT_OK);
    CHECK(scene_motion_is_still(&S.object.motion));
    CHECK(S.object.linear_inertia == 1 && S.object.angular_inertia == 1 && S.object.n_teleports == 0);
    CHECK(S.colliders == NULL);
    scene_free(&S);
    CHECK_EQ_INT(parse("{" GRID ", \"object\": {\"motion\": {\"spin_deg_per_s\": 45, \"spin_axis\": [2, 0, 0]},"
                       " \"linear_inertia\": 0.25, \"angular_inertia\": 0,"
                       " \"teleport\": [{\"frame\": 2, \"translate\": [1, 0, 0]},"
                       " {\"frame\": 9, \"translate\": [0, 0, -3]}]},"
                       " \"colliders\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1,"
                       " \"motion\": {\"velocity\": [0, 2, 0]}}]}",
                       &d),
                 WEFT_OK);
    CHECK(S.object.motion.spin_deg_per_s == 45 && S.object.motion.spin_axis[0] == 1);
    CHECK(S.object.linear_inertia == 0.25 && S.object.angular_inertia == 0);
    CHECK_EQ_INT(S.object.n_teleports, 2);
    if (S.object.n_teleports == 2) {
        CHECK(S.object.teleports[0].frame == 2 && S.object.teleports[0].translate[0] == 1);
        CHECK(S.object.teleports[1].frame == 9 && S.object.teleports[1].translate[2] == -3);
    }
    CHECK(S.colliders && S.colliders[0].motion.velocity[1] == 2);
    scene_free(&S);
}

static void test_camera(void) {
    cli_diag d;
    CHECK_EQ_INT(parse("{" GRID "}", &d), WEFT_OK);
    CHECK_EQ_INT(S.camera.framed, 0);
    CHECK_EQ_INT(S.camera.width, 640);
    CHECK_EQ_INT(S.camera.height, 480);
    CHECK(S.camera.fov_deg == 40 && S.camera.up[1] == 1 && S.camera.up[0] == 0 && S.camera.up[2] == 0);
    scene_free(&S);
    CHECK_EQ_INT(parse("{" GRID ", \"camera\": {\"eye\": [0, 1, 3], \"target\": [0, 0.5, 0], \"up\": [0, 0, 2],"
                       " \"fov_deg\": 55, \"width\": 320, \"height\": 200}}",
                       &d),
                 WEFT_OK);
    CHECK_EQ_INT(S.camera.framed, 1);
    CHECK(S.camera.eye[2] == 3 && S.camera.target[1] == 0.5 && S.camera.up[2] == 1 && S.camera.fov_deg == 55);
    CHECK_EQ_INT(S.camera.width, 320);
    CHECK_EQ_INT(S.camera.height, 200);
    scene_free(&S);
    CHECK_EQ_INT(parse("{" GRID ", \"camera\": {\"width\": 8192, \"height\": 1}}", &d), WEFT_OK);
    CHECK_EQ_INT(S.camera.framed, 0);
    CHECK_EQ_INT(S.camera.width, 8192);
    scene_free(&S);
    expect_bad("{" GRID ", \"camera\": {\"eye\": [0, 1, 3]}}", "camera.target", "missing");
    expect_bad("{" GRID ", \"camera\": {\"target\": [0, 1, 3]}}", "camera.eye", "missing");
    expect_bad("{" GRID ", \"camera\": {\"eye\": [0, 1, 3], \"target\": [0, 1, 3]}}", "camera.target", "differ");
    expect_bad("{" GRID ", \"camera\": {\"eye\": [0, 3, 0], \"target\": [0, 1, 0]}}", "camera.up", "parallel");
    expect_bad("{" GRID ", \"camera\": {\"up\": [0, 0, 0]}}", "camera.up", "nonzero");
    expect_bad("{" GRID ", \"camera\": {\"fov_deg\": 180}}", "camera.fov_deg", "(0, 180)");
    expect_bad("{" GRID ", \"camera\": {\"fov_deg\": 0}}", "camera.fov_deg", "> 0");
    expect_bad("{" GRID ", \"camera\": {\"width\": 0}}", "camera.width", "[1, 8192]");
    expect_bad("{" GRID ", \"camera\": {\"height\": 8193}}", "camera.height", "[1, 8192]");
    expect_bad("{" GRID ", \"camera\": {\"width\": 64.5}}", "camera.width", "integer");
    expect_bad("{" GRID ", \"camera\": {\"fov\": 30}}", "camera.fov", "unknown key");
    expect_bad("{" GRID ", \"camera\": \"front\"}", "camera", "must be an object");
}

/* x -> T x of the placement, for a local point. */
static void place(const double t[16], const double* p, double* out) {
    for (int r = 0; r < 3; ++r) out[r] = t[r] * p[0] + t[4 + r] * p[1] + t[8 + r] * p[2] + t[12 + r];
}

/* The rotation part is orthonormal with determinant +1. */
static void check_rigid(const double t[16]) {
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
            double dot = 0;
            for (int r = 0; r < 3; ++r) dot += t[4 * a + r] * t[4 * b + r];
            CHECK_NEAR(dot, a == b ? 1.0 : 0.0, 1e-14);
        }
    const double det = t[0] * (t[5] * t[10] - t[9] * t[6]) - t[4] * (t[1] * t[10] - t[9] * t[2]) +
                       t[8] * (t[1] * t[6] - t[5] * t[2]);
    CHECK_NEAR(det, 1.0, 1e-14);
    CHECK(t[3] == 0 && t[7] == 0 && t[11] == 0 && t[15] == 1);
}

/* Scene colliders in the API's local conventions: the local plane y = 0 lands on normal.x =
 * offset with local +Y along the normal; a sphere's origin at its centre; a capsule's local
 * (0, -h, 0) and (0, h, 0) at a and b. Normals include -Y and nearly -Y. */
static void test_collider_placement(void) {
    static const double normals[][3] = {{0, 1, 0}, {0, -1, 0}, {1e-9, -1, 0}, {0.6, 0, 0.8}, {-0.48, -0.6, 0.64}};
    for (int i = 0; i < 5; ++i) {
        scene_collider c;
        memset(&c, 0, sizeof c);
        c.type = WEFT_COLLIDER_PLANE;
        const double* n0 = normals[i];
        const double len = sqrt(n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2]);
        for (int k = 0; k < 3; ++k) c.normal[k] = n0[k] / len;
        c.offset = -0.7;
        double t[16], h = -1;
        scene_collider_placement(&c, t, &h);
        check_rigid(t);
        CHECK(h == 0);
        for (int k = 0; k < 3; ++k) CHECK_NEAR(t[4 + k], c.normal[k], 1e-14);   /* local +Y */
        static const double local[3][3] = {{0, 0, 0}, {2, 0, -1}, {-0.5, 0, 3}};
        for (int p = 0; p < 3; ++p) {
            double w[3];
            place(t, local[p], w);
            CHECK_NEAR(c.normal[0] * w[0] + c.normal[1] * w[1] + c.normal[2] * w[2], -0.7, 1e-13);
        }
    }
    scene_collider s;
    memset(&s, 0, sizeof s);
    s.type = WEFT_COLLIDER_SPHERE;
    s.center[0] = 1;
    s.center[1] = -2;
    s.center[2] = 0.5;
    double t[16], h;
    scene_collider_placement(&s, t, &h);
    check_rigid(t);
    CHECK(t[12] == 1 && t[13] == -2 && t[14] == 0.5 && h == 0);

    static const double ends[][6] = {{-0.5, 0.4, 0, 0.5, 0.4, 0}, {0, 1, 0, 0, -1, 0}, {1, 2, 3, 1, 2, 3},
                                     {0.1, 0.2, 0.3, -0.7, 1.1, 0.9}};
    for (int i = 0; i < 4; ++i) {
        scene_collider c;
        memset(&c, 0, sizeof c);
        c.type = WEFT_COLLIDER_CAPSULE;
        memcpy(c.a, ends[i], sizeof c.a);
        memcpy(c.b, ends[i] + 3, sizeof c.b);
        scene_collider_placement(&c, t, &h);
        check_rigid(t);
        const double la[3] = {0, -h, 0}, lb[3] = {0, h, 0};
        double wa[3], wb[3];
        place(t, la, wa);
        place(t, lb, wb);
        for (int k = 0; k < 3; ++k) {
            CHECK_NEAR(wa[k], c.a[k], 1e-14);
            CHECK_NEAR(wb[k], c.b[k], 1e-14);
        }
    }
}

/* Splitting a scene transform into a rigid placement and a uniform scale (file meshes go to the
 * library by path with unit_scale and a rigid transform); anything else is refused. */
static void test_split_uniform_scale(void) {
    static const double axis[3] = {0.48, 0.6, 0.64};
    double r[16], m[16], rigid[16], s = 0;
    xf_axis_angle(axis, 0.7, r);
    memcpy(m, r, sizeof m);
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) m[4 * c + k] *= 2.5;
    m[12] = 1;
    m[13] = -2;
    m[14] = 3;
    CHECK_EQ_INT(xf_split_uniform_scale(m, rigid, &s), 1);
    CHECK_NEAR(s, 2.5, 1e-14);
    for (int i = 0; i < 12; ++i) CHECK_NEAR(rigid[i], r[i], 1e-14);
    CHECK(rigid[12] == 1 && rigid[13] == -2 && rigid[14] == 3);
    double bad[16];
    memcpy(bad, m, sizeof bad);
    bad[0] *= 1.1;   /* non-uniform */
    CHECK_EQ_INT(xf_split_uniform_scale(bad, rigid, &s), 0);
    memcpy(bad, m, sizeof bad);
    for (int k = 0; k < 3; ++k) bad[k] = -bad[k];   /* reflection */
    CHECK_EQ_INT(xf_split_uniform_scale(bad, rigid, &s), 0);
    xf_identity(bad);
    bad[4] = 0.3;   /* shear */
    CHECK_EQ_INT(xf_split_uniform_scale(bad, rigid, &s), 0);
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
    RUN_TEST(test_pin_groups_and_conflicts);
    RUN_TEST(test_motion_closed_form);
    RUN_TEST(test_bad_motion);
    RUN_TEST(test_object);
    RUN_TEST(test_camera);
    RUN_TEST(test_collider_placement);
    RUN_TEST(test_split_uniform_scale);
    return TEST_SUMMARY();
}
