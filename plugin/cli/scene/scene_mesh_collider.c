/* Scene "colliders" entries of type "mesh": the schema (sample_scenes/README.md, "Mesh
 * colliders"), the import of the body file and of the vertex-animation frames (a printf pattern
 * with one integer, first, count, fps; every frame must have the body's vertex count). Everything
 * is read and checked at load time, before anything runs. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_mesh.h"
#include "scene_parts.h"
#include "scene_path.h"
#include "scene_xform.h"

/* A pattern with exactly one integer conversion (%d, %Nd or %0Nd, N at most 3 digits) and no
 * other '%' but "%%". */
static int pattern_ok(const char* p) {
    int conv = 0;
    for (const char* q = p; *q; ++q) {
        if (*q != '%') continue;
        if (q[1] == '%') {
            ++q;
            continue;
        }
        ++q;
        int digits = 0;
        while (*q >= '0' && *q <= '9') ++q, ++digits;
        if (*q != 'd' || digits > 3) return 0;
        ++conv;
    }
    return conv == 1;
}

/* The file as the library will read it (weft_mesh_read): its vertices in metres. */
static int import_positions(const sj_ctx* c, const char* field, const char* file, const scene_mesh_collider* m,
                            scene_mesh* src) {
    cli_diag d = {0};
    if (scene_mesh_read(src, file, m->select, m->scale, &d) != WEFT_OK) return sj_fail(c, field, "%s", d.message);
    return 0;
}

static int parse_frames(const sj_ctx* c, const cJSON* fr, const char* path, scene_mesh_collider* m, int has_file) {
    char field[128];
    sj_join(field, sizeof field, path, "frames");
    static const char* const keys[] = {"pattern", "first", "count", "fps"};
    if (sj_check_object(c, fr, field, keys, COUNT(keys)) < 0) return -1;
    const char* pattern = NULL;
    int first = 0, count = 0;
    m->frames_fps = 0.0;
    if (sj_require(c, fr, field, "pattern", "(a printf pattern such as \"body_%04d.obj\")") < 0) return -1;
    if (sj_require(c, fr, field, "count", NULL) < 0) return -1;
    if (sj_require(c, fr, field, "fps", NULL) < 0) return -1;
    if (sj_string(c, fr, field, "pattern", &pattern) < 0) return -1;
    if (sj_int(c, fr, field, "first", 0, 100000000, &first) < 0) return -1;
    if (sj_int(c, fr, field, "count", 1, 100000, &count) < 0) return -1;
    if (sj_number(c, fr, field, "fps", SJ_POSITIVE, &m->frames_fps) < 0) return -1;
    char pf[160];
    sj_join(pf, sizeof pf, field, "pattern");
    if (!pattern_ok(pattern))
        return sj_fail(c, pf, "\"%s\" must hold exactly one integer conversion (%%d, %%4d, %%04d)", pattern);
    for (int k = 0; k < count; ++k) {
        char name[1024], where[1400];
        snprintf(name, sizeof name, pattern, first + k);
        char* file = scene_resolve_path(c->file, name);
        if (!file) return cli_fail(c->diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", c->file), -1;
        snprintf(where, sizeof where, "%s (frame file %s)", pf, name);
        scene_mesh src;
        if (import_positions(c, where, file, m, &src) < 0) {
            free(file);
            return -1;
        }
        if (k == 0 && !has_file) {
            m->file = file;
            file = NULL;
            m->n_verts = src.n_vertices;
        }
        free(file);
        if (src.n_vertices != m->n_verts) {
            int nv = src.n_vertices;
            scene_mesh_free(&src);
            return sj_fail(c, where, "has %d vertices, the collider's mesh %d (every frame needs the same vertices)", nv,
                           m->n_verts);
        }
        if (!m->frames) {
            m->frames = malloc(sizeof(double) * 3 * (size_t)m->n_verts * (size_t)count);
            if (!m->frames) {
                scene_mesh_free(&src);
                return cli_fail(c->diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", c->file), -1;
            }
        }
        memcpy(m->frames + 3 * (size_t)m->n_verts * k, src.positions, sizeof(double) * 3 * (size_t)m->n_verts);
        m->n_frames = k + 1;
        scene_mesh_free(&src);
    }
    return 0;
}

int scene_parse_mesh_collider(const sj_ctx* c, const cJSON* item, const char* path, scene* s, int room) {
    static const char* const keys[] = {"type", "file", "select", "scale", "transform", "thickness", "friction",
                                       "push_speed", "motion", "frames"};
    if (sj_check_object(c, item, path, keys, COUNT(keys)) < 0) return -1;
    if (!s->mesh_colliders) {
        s->mesh_colliders = calloc((size_t)room, sizeof(scene_mesh_collider));
        if (!s->mesh_colliders) return cli_fail(c->diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", c->file), -1;
    }
    scene_mesh_collider* m = &s->mesh_colliders[s->n_mesh_colliders++];
    m->scale = 1.0;
    xf_identity(m->transform);
    m->thickness = SCENE_DEFAULT_THICKNESS;
    m->friction = SCENE_DEFAULT_FRICTION;
    m->push_speed = -1.0;
    m->motion = scene_motion_still();
    char field[128];
    const char *file = NULL, *select = NULL;
    if (sj_string(c, item, path, "file", &file) < 0) return -1;
    if (sj_string(c, item, path, "select", &select) < 0) return -1;
    if (sj_number(c, item, path, "scale", SJ_POSITIVE, &m->scale) < 0) return -1;
    if (sj_number(c, item, path, "thickness", SJ_NONNEGATIVE, &m->thickness) < 0) return -1;
    if (sj_number(c, item, path, "friction", SJ_NONNEGATIVE, &m->friction) < 0) return -1;
    if (sj_number(c, item, path, "push_speed", SJ_NONNEGATIVE, &m->push_speed) < 0) return -1;
    if (select && !(m->select = scene_strdup(select)))
        return cli_fail(c->diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", c->file), -1;
    if (sj_numbers(c, item, path, "transform", 16, m->transform) < 0) return -1;
    double rigid[16], scale = 0.0;
    sj_join(field, sizeof field, path, "transform");
    if (!xf_split_uniform_scale(m->transform, rigid, &scale) || fabs(scale - 1.0) > 1e-6)
        return sj_fail(c, field, "must be rigid (a rotation and a translation, column-major, last row 0 0 0 1): "
                                 "use \"scale\" for the units");
    const cJSON* mo = sj_get(item, "motion");
    if (mo) {
        sj_join(field, sizeof field, path, "motion");
        if (scene_motion_parse(c, mo, field, &m->motion) < 0) return -1;
    }
    const cJSON* fr = sj_get(item, "frames");
    if (!file && !fr) return sj_fail(c, path, "a mesh collider needs \"file\" or \"frames\" (or both)");
    if (file) {
        sj_join(field, sizeof field, path, "file");
        if (!(m->file = scene_resolve_path(c->file, file)))
            return cli_fail(c->diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", c->file), -1;
        scene_mesh src;
        if (import_positions(c, field, m->file, m, &src) < 0) return -1;
        m->n_verts = src.n_vertices;
        scene_mesh_free(&src);
    }
    if (fr) {
        if (!cJSON_IsObject(fr)) {
            sj_join(field, sizeof field, path, "frames");
            return sj_fail(c, field, "must be an object {\"pattern\", \"first\", \"count\", \"fps\"}, not %s",
                           sj_type_name(fr));
        }
        if (parse_frames(c, fr, path, m, file != NULL) < 0) return -1;
    }
    return 0;
}

void scene_free_mesh_colliders(scene* s) {
    for (int i = 0; i < s->n_mesh_colliders; ++i) {
        free(s->mesh_colliders[i].file);
        free(s->mesh_colliders[i].select);
        free(s->mesh_colliders[i].frames);
    }
    free(s->mesh_colliders);
    s->mesh_colliders = NULL;
    s->n_mesh_colliders = 0;
}
