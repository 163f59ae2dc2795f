/* Scene JSON -> struct scene: the schema (keys, types, ranges, defaults). The mesh itself is
 * made in scene_mesh.c and the pin vertices are checked against it there. */
#include "scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "names.h"
#include "scene_mesh.h"
#include "scene_parts.h"
#include "scene_path.h"

/* Largest counts a scene may ask for (guards against typos such as 1e9 frames). */
enum { MAX_FRAMES = 100000000, MAX_SUBSTEPS = 100000, MAX_ITERATIONS = 100000000, MAX_THREADS = 1024 };

static int parse_mesh(const sj_ctx* c, const cJSON* root, scene* s) {
    const cJSON* mesh = sj_get(root, "mesh");
    if (!mesh) return sj_fail(c, "mesh", "missing (a scene needs {\"file\": ...} or {\"grid\": ...})");
    static const char* const keys[] = {"file", "scale", "select", "grid", "weld_tolerance", "sew_distance", "seams",
                                       "seam_close_time"};
    if (sj_check_object(c, mesh, "mesh", keys, COUNT(keys)) < 0) return -1;
    if (scene_parse_seams(c, mesh, s) < 0) return -1;
    const int has_file = sj_get(mesh, "file") != NULL, has_grid = sj_get(mesh, "grid") != NULL;
    if (has_file == has_grid)
        return sj_fail(c, "mesh", has_file ? "give either \"file\" or \"grid\", not both"
                                           : "needs \"file\" or \"grid\"");
    if (sj_number(c, mesh, "mesh", "weld_tolerance", SJ_NONNEGATIVE, &s->def.weld_tolerance) < 0)
        return -1;
    if (s->def.weld_tolerance > 1)
        return sj_fail(c, "mesh.weld_tolerance", "must be in [0, 1] (a fraction of the bounding-box diagonal), not %g",
                       s->def.weld_tolerance);
    if (has_file) {
        const char* file = NULL;
        const char* select = NULL;
        if (sj_string(c, mesh, "mesh", "file", &file) < 0) return -1;
        if (sj_number(c, mesh, "mesh", "scale", SJ_POSITIVE, &s->mesh_scale) < 0) return -1;
        if (sj_string(c, mesh, "mesh", "select", &select) < 0) return -1;
        s->mesh_file = scene_resolve_path(c->file, file);
        if (select) s->mesh_select = scene_strdup(select);
        if (!s->mesh_file || (select && !s->mesh_select))
            return cli_fail(c->diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", c->file), -1;
        return 0;
    }
    if (sj_get(mesh, "scale")) return sj_fail(c, "mesh.scale", "applies to \"file\" meshes only (a grid is in metres)");
    if (sj_get(mesh, "select")) return sj_fail(c, "mesh.select", "applies to \"file\" meshes only");
    s->mesh_is_grid = 1;
    const cJSON* grid = sj_get(mesh, "grid");
    static const char* const gkeys[] = {"n", "size"};
    if (sj_check_object(c, grid, "mesh.grid", gkeys, COUNT(gkeys)) < 0) return -1;
    const cJSON* n = sj_get(grid, "n");
    if (sj_require(c, grid, "mesh.grid", "n", "([NX, NZ] vertices along X and Z)") < 0) return -1;
    if (!cJSON_IsArray(n) || cJSON_GetArraySize(n) != 2)
        return sj_fail(c, "mesh.grid.n", "must be an array of 2 integers >= 2, not %s", sj_type_name(n));
    for (int k = 0; k < 2; ++k) {
        const cJSON* item = cJSON_GetArrayItem(n, k);
        double v = cJSON_IsNumber(item) ? item->valuedouble : NAN;
        if (!isfinite(v) || v != floor(v) || v < 2 || v > SCENE_GRID_MAX_SIDE) {
            char path[64];
            snprintf(path, sizeof path, "mesh.grid.n[%d]", k);
            return sj_fail(c, path, "must be an integer in [2, %d]", SCENE_GRID_MAX_SIDE);
        }
        s->grid_n[k] = (int)v;
    }
    if ((long long)s->grid_n[0] * s->grid_n[1] > SCENE_GRID_MAX_VERTICES)
        return sj_fail(c, "mesh.grid.n", "%d x %d vertices is more than %d", s->grid_n[0], s->grid_n[1],
                       SCENE_GRID_MAX_VERTICES);
    if (sj_require(c, grid, "mesh.grid", "size", "([SX, SZ] metres)") < 0) return -1;
    if (sj_numbers(c, grid, "mesh.grid", "size", 2, s->grid_size) < 0) return -1;
    for (int k = 0; k < 2; ++k)
        if (!(s->grid_size[k] > 0)) {
            char path[64];
            snprintf(path, sizeof path, "mesh.grid.size[%d]", k);
            return sj_fail(c, path, "must be a finite number > 0, not %g", s->grid_size[k]);
        }
    return 0;
}

static int parse_transform(const sj_ctx* c, const cJSON* root, scene* s) {
    int r = sj_numbers(c, root, "", "transform", 16, s->transform);
    if (r <= 0) return r;
    s->has_transform = 1;
    const double* t = s->transform;
    if (t[3] != 0 || t[7] != 0 || t[11] != 0 || t[15] != 1)
        return sj_fail(c, "transform", "the last row (elements 3, 7, 11, 15 in column-major order) must be "
                                       "0 0 0 1: only affine transforms are allowed");
    double det = t[0] * (t[5] * t[10] - t[9] * t[6]) - t[4] * (t[1] * t[10] - t[9] * t[2]) +
                 t[8] * (t[1] * t[6] - t[5] * t[2]);
    if (!(fabs(det) > 0)) return sj_fail(c, "transform", "is singular (determinant 0)");
    return 0;
}

static int parse_spring_values(const sj_ctx* c, const cJSON* mat, const char* key, double* values) {
    const cJSON* obj = NULL;
    int r = sj_object(c, mat, "material", key, &obj);
    if (r <= 0) return r;
    char path[64];
    sj_join(path, sizeof path, "material", key);
    static const char* const keys[] = {"stretch", "shear", "bend"};
    if (sj_check_object(c, obj, path, keys, COUNT(keys)) < 0) return -1;
    /* Stiffness: stretch > 0 (a sheet without it has no shape); shear and bend may be 0.
     * Damping: >= 0 for every type. */
    for (int t = 0; t < 3; ++t) {   /* keys[] in weft_spring_type's order */
        sj_range range = (key[0] == 'k' && t == WEFT_SPRING_STRETCH) ? SJ_POSITIVE : SJ_NONNEGATIVE;
        if (sj_number(c, obj, path, keys[t], range, &values[t]) < 0) return -1;
    }
    return 0;
}

static int parse_material(const sj_ctx* c, const cJSON* root, scene* s) {
    const cJSON* mat = NULL;
    int r = sj_object(c, root, "", "material", &mat);
    if (r <= 0) return r;
    static const char* const keys[] = {"density", "uniform_mass", "k", "d"};
    if (sj_check_object(c, mat, "material", keys, COUNT(keys)) < 0) return -1;
    if (sj_get(mat, "uniform_mass"))   /* the public API lumps mass by area only */
        return sj_fail(c, "material.uniform_mass", "is no longer supported (the public API has no per-particle "
                                                   "mass): give material.density in kg/m^2");
    weft_material* m = &s->def.material;
    if (sj_number(c, mat, "material", "density", SJ_POSITIVE, &m->density) < 0) return -1;
    if (parse_spring_values(c, mat, "k", m->stiffness) < 0) return -1;
    if (parse_spring_values(c, mat, "d", m->damping) < 0) return -1;
    return 0;
}

static int parse_wind(const sj_ctx* c, const cJSON* root, scene* s) {
    const cJSON* wind = NULL;
    int r = sj_object(c, root, "", "wind", &wind);
    if (r <= 0) return r;
    static const char* const keys[] = {"velocity", "normal_drag", "tangent_drag"};
    if (sj_check_object(c, wind, "wind", keys, COUNT(keys)) < 0) return -1;
    if (sj_numbers(c, wind, "wind", "velocity", 3, s->def.wind) < 0) return -1;
    if (sj_number(c, wind, "wind", "normal_drag", SJ_NONNEGATIVE, &s->def.air_drag_normal) < 0) return -1;
    if (sj_number(c, wind, "wind", "tangent_drag", SJ_NONNEGATIVE, &s->def.air_drag_tangent) < 0) return -1;
    return 0;
}

static int parse_solver(const sj_ctx* c, const cJSON* root, scene* s) {
    const cJSON* solver = NULL;
    int r = sj_object(c, root, "", "solver", &solver);
    if (r <= 0) return r;
    static const char* const keys[] = {"type", "tolerance", "max_iterations", "preconditioner", "newton_iterations",
                                       "line_search", "newton_forcing"};
    if (sj_check_object(c, solver, "solver", keys, COUNT(keys)) < 0) return -1;
    const char* type = NULL;
    if (sj_string(c, solver, "solver", "type", &type) < 0) return -1;
    if (type) {
        int t = cli_solver_from_name(type);
        if (t < 0)
            return sj_fail(c, "solver.type", "unknown solver \"%s\" (expected pcg, jacobi, chebyshev or direct)",
                           type);
        s->def.solver = (weft_solver)t;
    }
    const cJSON* tol = cJSON_GetObjectItemCaseSensitive(solver, "tolerance");
    if (tol && !(cJSON_IsString(tol) && strcmp(tol->valuestring, "default") == 0)) {   /* "default": the library's */
        if (sj_number(c, solver, "solver", "tolerance", SJ_NONNEGATIVE, &s->def.tolerance) < 0) return -1;
        if (!(s->def.tolerance < 1))
            return sj_fail(c, "solver.tolerance", "must be in [0, 1) (a relative residual) or \"default\", not %g",
                           s->def.tolerance);
    }
    if (sj_int(c, solver, "solver", "max_iterations", 1, MAX_ITERATIONS, &s->def.max_iterations) < 0) return -1;
    const char* pre = NULL;
    if (sj_string(c, solver, "solver", "preconditioner", &pre) < 0) return -1;
    if (pre) {
        int p = strcmp(pre, "default") == 0 ? WEFT_PRECOND_DEFAULT : cli_precond_from_name(pre);
        if (p < 0)
            return sj_fail(c, "solver.preconditioner",
                           "unknown preconditioner \"%s\" (expected block_jacobi, amg, ic0 or default)", pre);
        s->def.preconditioner = (weft_preconditioner)p;
    }
    if (sj_int(c, solver, "solver", "newton_iterations", 1, 100, &s->def.newton_iterations) < 0) return -1;
    const cJSON* nf = cJSON_GetObjectItemCaseSensitive(solver, "newton_forcing");
    if (nf && !(cJSON_IsString(nf) && strcmp(nf->valuestring, "default") == 0)) {
        if (!cJSON_IsNumber(nf) || !(nf->valuedouble >= 0 && nf->valuedouble < 1))
            return sj_fail(c, "solver.newton_forcing", "must be a number in [0, 1) or \"default\"");
        s->def.newton_forcing = nf->valuedouble;
    }
    const cJSON* ls = cJSON_GetObjectItemCaseSensitive(solver, "line_search");
    if (ls) {
        if (!cJSON_IsBool(ls))
            return sj_fail(c, "solver.line_search", "must be true or false, not %s", sj_type_name(ls));
        s->def.line_search = cJSON_IsTrue(ls) ? 1 : 0;
    }
    return 0;
}

static int parse_time(const sj_ctx* c, const cJSON* root, scene* s) {
    const cJSON* time = NULL;
    int r = sj_object(c, root, "", "time", &time);
    if (r <= 0) return r;
    static const char* const keys[] = {"fps", "substeps", "frames", "integrator"};
    if (sj_check_object(c, time, "time", keys, COUNT(keys)) < 0) return -1;
    const char* integ = NULL;
    if (sj_string(c, time, "time", "integrator", &integ) < 0) return -1;
    if (integ) {
        int t = strcmp(integ, "default") == 0 ? WEFT_INTEGRATOR_DEFAULT : cli_integrator_from_name(integ);
        if (t < 0)
            return sj_fail(c, "time.integrator", "unknown integrator \"%s\" (expected be, bdf2, trbdf2 or default)", integ);
        s->def.integrator = (weft_integrator)t;
    }
    if (sj_number(c, time, "time", "fps", SJ_POSITIVE, &s->fps) < 0) return -1;
    if (sj_int(c, time, "time", "substeps", 1, MAX_SUBSTEPS, &s->def.substeps) < 0) return -1;
    if (sj_int(c, time, "time", "frames", 0, MAX_FRAMES, &s->frames) < 0) return -1;
    return 0;
}

/* "self_collision": true / false (absent: the library's default), "self_thickness": m, > 0. */
static int parse_self_collision(const sj_ctx* c, const cJSON* root, scene* s) {
    const cJSON* on = sj_get(root, "self_collision");
    if (on) {
        if (!cJSON_IsBool(on))
            return sj_fail(c, "self_collision", "must be true or false, not %s", sj_type_name(on));
        s->def.self_collision = cJSON_IsTrue(on) ? 1 : 0;
    }
    return sj_number(c, root, "", "self_thickness", SJ_POSITIVE, &s->def.self_collision_thickness) < 0 ? -1 : 0;
}

/* Everything except the mesh contents and the pin ranges. */
static int parse_root(const sj_ctx* c, const cJSON* root, scene* s) {
    static const char* const keys[] = {"description", "mesh", "transform", "material", "pins", "colliders",
                                       "object", "camera", "gravity", "wind", "strain_limit", "solver",
                                       "time", "threads", "self_collision", "self_thickness"};
    if (!cJSON_IsObject(root)) return sj_fail(c, NULL, "the scene must be a JSON object, not %s", sj_type_name(root));
    if (sj_check_object(c, root, "", keys, COUNT(keys)) < 0) return -1;
    if (sj_get(root, "description") && !cJSON_IsString(sj_get(root, "description")))
        return sj_fail(c, "description", "must be a string, not %s", sj_type_name(sj_get(root, "description")));
    if (parse_mesh(c, root, s) < 0 || parse_transform(c, root, s) < 0 || parse_material(c, root, s) < 0 ||
        scene_parse_pins(c, root, s) < 0 || scene_parse_colliders(c, root, s) < 0 ||
        scene_parse_object(c, root, s) < 0 || scene_parse_camera(c, root, s) < 0)
        return -1;
    if (sj_numbers(c, root, "", "gravity", 3, s->def.gravity) < 0 || parse_wind(c, root, s) < 0) return -1;
    if (sj_number(c, root, "", "strain_limit", SJ_NONNEGATIVE, &s->def.strain_limit) < 0) return -1;
    if (parse_solver(c, root, s) < 0 || parse_time(c, root, s) < 0) return -1;
    if (sj_int(c, root, "", "threads", 0, MAX_THREADS, &s->threads) < 0) return -1;
    return parse_self_collision(c, root, s);
}

/* 1-based line and column of offset in text. */
static void line_column(const char* text, size_t offset, int* line, int* column) {
    *line = 1;
    *column = 1;
    for (size_t i = 0; i < offset && text[i]; ++i) {
        if (text[i] == '\n') {
            ++*line;
            *column = 1;
        } else {
            ++*column;
        }
    }
}

weft_status scene_parse(scene* out, const char* text, size_t len, const char* name, cli_diag* diag) {
    memset(out, 0, sizeof *out);
    cli_diag local = {0};
    if (!diag) diag = &local;
    if (!name) name = "scene";
    if (!text) return cli_fail(diag, WEFT_ERROR_INVALID_ARGUMENT, "%s: no text", name);
    const char* end = NULL;
    cJSON* root = cJSON_ParseWithLengthOpts(text, len, &end, 0);
    if (!root) {
        int line, column;
        size_t at = end && end >= text ? (size_t)(end - text) : 0;
        line_column(text, at, &line, &column);
        return cli_fail(diag, WEFT_ERROR_SCENE, "%s: invalid JSON near line %d, column %d", name, line, column);
    }
    for (size_t i = (size_t)(end - text); i < len; ++i)
        if (text[i] != ' ' && text[i] != '\t' && text[i] != '\n' && text[i] != '\r') {
            int line, column;
            line_column(text, i, &line, &column);
            cJSON_Delete(root);
            return cli_fail(diag, WEFT_ERROR_SCENE, "%s: unexpected text after the JSON object at line %d, column %d",
                           name, line, column);
        }

    scene* s = out;
    s->mesh_scale = 1.0;
    s->def = weft_default_cloth_def();   /* the library's defaults where the scene says nothing */
    s->fps = SCENE_DEFAULT_FPS;
    s->frames = SCENE_DEFAULT_FRAMES;
    sj_ctx c = {name, diag};
    int rc = parse_root(&c, root, s);
    cJSON_Delete(root);
    if (rc == 0) rc = scene_mesh_make(s, name, diag) == WEFT_OK ? 0 : -1;
    if (rc == 0) rc = scene_mesh_check_pins(s, name, diag) == WEFT_OK ? 0 : -1;
    if (rc == 0) rc = scene_check_seams(s, name, diag) == WEFT_OK ? 0 : -1;
    if (rc == 0) rc = scene_group_pins(s, name, diag) == WEFT_OK ? 0 : -1;
    if (rc != 0) {
        weft_status st = diag->status != WEFT_OK ? diag->status : WEFT_ERROR_SCENE;
        scene_free(s);
        diag->status = st;
        return st;
    }
    return WEFT_OK;
}

weft_status scene_load(scene* out, const char* path, cli_diag* diag) {
    memset(out, 0, sizeof *out);
    cli_diag local = {0};
    if (!diag) diag = &local;
    if (!path) return cli_fail(diag, WEFT_ERROR_INVALID_ARGUMENT, "scene: path is NULL");
    FILE* f = fopen(path, "rb");
    if (!f) return cli_fail(diag, WEFT_ERROR_IO, "%s: cannot open the scene file", path);
    size_t cap = 4096, len = 0;
    char* text = malloc(cap);
    while (text) {
        if (len + 1 >= cap) {
            if (cap >= SCENE_MAX_FILE_BYTES) {
                free(text);
                fclose(f);
                return cli_fail(diag, WEFT_ERROR_SCENE, "%s: the scene file is larger than %d bytes", path,
                               SCENE_MAX_FILE_BYTES);
            }
            char* grown = realloc(text, cap * 2);
            if (!grown) {
                free(text);
                text = NULL;
                break;
            }
            text = grown;
            cap *= 2;
        }
        size_t got = fread(text + len, 1, cap - 1 - len, f);
        len += got;
        if (got == 0) break;
    }
    int read_error = ferror(f);
    fclose(f);
    if (!text) return cli_fail(diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    if (read_error) {
        free(text);
        return cli_fail(diag, WEFT_ERROR_IO, "%s: cannot read the scene file", path);
    }
    text[len] = '\0';
    weft_status st = scene_parse(out, text, len, path, diag);
    free(text);
    return st;
}

void scene_free(scene* s) {
    if (!s) return;
    free(s->mesh_file);
    free(s->mesh_select);
    scene_mesh_free(&s->mesh);
    for (int i = 0; i < s->n_pins; ++i) free(s->pins[i].vertices);
    free(s->pins);
    for (int i = 0; i < s->n_pin_groups; ++i) free(s->pin_groups[i].vertices);
    free(s->pin_groups);
    free(s->colliders);
    scene_free_mesh_colliders(s);
    free(s->object.teleports);
    free(s->seam_a);
    free(s->seam_b);
    memset(s, 0, sizeof *s);
}
