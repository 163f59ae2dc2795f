/* The immutable cloth model: particles (welded host vertices), triangles, winged edge, springs,
 * material and masses, plus the map back to the host's vertex order and the import report.
 * Built once from a wc_source_mesh; never modified by a simulation step (state lives in
 * wc_state). */
#ifndef WEFT_CORE_MODEL_H
#define WEFT_CORE_MODEL_H
#include "alloc.h"
#include "bsr.h"
#include "diag.h"
#include "sew.h"
#include "source_mesh.h"
#include "winged_edge.h"

typedef enum wc_spring_type {
    WC_SPRING_STRETCH = 0,
    WC_SPRING_SHEAR = 1,
    WC_SPRING_BEND = 2,
    WC_SPRING_SEAM = 3,      /* zero-rest-length sewing springs (sew.h), weighted by spring.w */
    WC_SPRING_TYPE_COUNT = 4
} wc_spring_type;
#define WC_SPRING_MESH_TYPES 3 /* stretch, shear, bend: the types built from the mesh */

typedef struct wc_spring {
    int a, b;             /* particle indices, a < b */
    int type;             /* wc_spring_type */
    double rest;          /* rest length (m); seam springs: 0, or for a host pair its start distance,
                             the ramp's start (sew.h) */
    double w;             /* stiffness and damping weight: 1, or a seam spring's weight (sew.h),
                             which may be negative (the set of a seam's springs is PSD) */
} wc_spring;

typedef struct wc_material {
    double density;                   /* kg/m^2, lumped to particles by triangle area */
    double k[WC_SPRING_TYPE_COUNT];   /* spring stiffness per type (N/m); k[WC_SPRING_SEAM]: the
                                         sewing stiffness, default 5000 (the stretch default) */
    double d[WC_SPRING_TYPE_COUNT];   /* spring damping per type (N s/m) */
    double uniform_mass;              /* kg per particle; > 0 overrides density */
} wc_material;

wc_material wc_default_material(void);

#define WC_MAX_WARNINGS 16
#define WC_MAX_POLY_SIDES 8   /* polygons[k] counts k-gons; polygons[8] counts 8 or more */

typedef struct wc_import_report {
    int source_vertices;        /* host vertices */
    int unused_vertices;        /* host vertices referenced by no polygon (map to -1) */
    int welded_vertices;        /* host vertices merged into another one's particle */
    int particles;
    int polygons[WC_MAX_POLY_SIDES + 1]; /* count by number of sides; [1] points, [2] lines */
    int triangles;              /* kept for simulation */
    int degenerate_triangles;   /* zero area or repeated particle: dropped */
    int duplicate_faces;        /* same three particles as an earlier triangle: dropped */
    int flipped_faces;          /* winding made consistent per component */
    int non_orientable_components;
    int edges;                  /* winged-edge edges */
    int boundary_edges;
    int non_manifold_edges;     /* vertex pairs shared by more than two triangles */
    int boundary_loops;
    int components;             /* connected components of the triangle mesh */
    int springs[WC_SPRING_TYPE_COUNT];
    int seams;                  /* seams sewn (sew.h): by sew_distance plus host pairs */
    int panels;                 /* components left once seams join them */
    double bbox_min[3], bbox_max[3]; /* metres, over particles */
    double unit_scale;          /* metres per source unit */
    double weld_distance;       /* absolute weld distance used (m) */
    struct {                    /* wall time of each build stage (ms) */
        double weld, triangulate, clean, orient, topology, springs, pattern, total;
    } ms;
    int n_warnings;
    int warnings_dropped;       /* warnings beyond WC_MAX_WARNINGS */
    char warnings[WC_MAX_WARNINGS][256];
} wc_import_report;

typedef struct wc_model_def {
    double weld_tolerance;      /* relative to the bounding-box diagonal; 0 disables; 1e-6 */
    double degenerate_area;     /* triangle area below this x diagonal^2 is degenerate; 1e-14 */
    double bend_min_angle_deg;  /* rest angle a-v-b at least this makes a bend spring; 150 */
    int reorder;                /* 1: number particles by reverse Cuthill-McKee for locality (default);
                                   0: by first appearance in host order */
    wc_material material;
    /* sewing (sew.h) */
    double sew_distance;        /* m: boundary vertices sew to other panels' boundary within it; 0 off */
    int n_seam_pairs;           /* host-supplied vertex pairs, >= 0 */
    const int* seam_a;          /* (n_seam_pairs) host vertex indices; seam_a[i] sews to seam_b[i] */
    const int* seam_b;          /* (n_seam_pairs) host vertex indices */
    double seam_close_time;     /* s (0.5): a host pair's rest length shrinks linearly from its
                                   start distance to 0 over this simulated time (sew.h); 0: at once */
} wc_model_def;

wc_model_def wc_default_model_def(void);

typedef struct wc_model {
    int n_particles;
    double* rest_pos;           /* (n_particles x 3) metres */
    double* mass;               /* (n_particles) kg */
    double* inv_mass;           /* (n_particles) 1/kg */

    int n_tris;
    int* tris;                  /* (n_tris x 3) particle indices, consistently wound */
    int* tri_poly;              /* (n_tris) source polygon each triangle came from */
    unsigned char* tri_quad;    /* (n_tris) 1 when the source polygon was a quad */
    double* tri_rest_area;      /* (n_tris) m^2 */

    wc_winged_edge we;          /* over particles and tris */

    int n_springs;
    wc_spring* springs;         /* (n_springs) sorted by type, then (a, b) */
    int spring_type_start[WC_SPRING_TYPE_COUNT + 1]; /* springs of type t: [start[t], start[t+1]) */

    int n_host_verts;
    int* host_to_particle;      /* (n_host_verts) particle of each host vertex, -1 if unused */
    int* particle_to_host;      /* (n_particles) first host vertex of each particle */
    int* particle_component;    /* (n_particles) component id */
    int n_components;

    int n_seams;
    wc_seam* seams;             /* (n_seams) sewn points; their springs are the WC_SPRING_SEAM springs */
    int n_panels;               /* components left once seams join them */
    double seam_close_time;     /* s: host pairs' rest-length ramp (wc_model_def) */
    int n_host_seams;           /* the last n_host_seams seams are host pairs */

    wc_bsr_pattern pattern;     /* block pattern of the implicit system + per-row spring/triangle lists */

    wc_material material;
    wc_import_report report;
    wc_allocator alloc;
} wc_model;

/* Build the model. On failure *out is left zeroed and diag says why. */
wc_status wc_model_build(wc_model* out, const wc_source_mesh* src, const wc_model_def* def,
                           const wc_allocator* alloc, wc_diag* diag);
void wc_model_free(wc_model* m);

/* Build stage (sew_springs.c): finds m's seams (def's sew_distance and host pairs, mapped through
 * host_to_particle; a pair on an unused vertex or on one particle is refused) and appends their
 * WC_SPRING_SEAM springs to m->springs. Needs particles, components and the winged edge. */
wc_status wc_model_sew(wc_model* m, const wc_model_def* def, wc_diag* diag);

/* Append a warning to the report (printf-style; truncated, counted when the list is full). */
void wc_report_warn(wc_import_report* r, const char* fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
