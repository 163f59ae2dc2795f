/* The backend choice, in one place. At context creation, from def.backend: CPU is core's table
 * (wc_cloth_cpu) for every cloth; GPU is gpu/'s (wg_cloth_backend, built with WEFT_GPU), whose
 * device (a GL context and the solver's programs) must work now, for every cloth; AUTO opens the
 * GPU's device where it may help (a hardware device; any device under WEFT_AUTO_CROSSOVER) and
 * keeps both tables. At cloth creation, once the model is built, each cloth gets its table, its
 * device and a reason: under AUTO, core's rule (core/backend_auto.h) on what the GPU table's
 * `supports` says of the cloth, its particle count and the device's crossover. The cloth keeps
 * its table and device (core calls through them); nothing else in the facade knows which backend
 * a cloth has. The def's DEFAULT choices are resolved here too, from the chosen table. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "api_internal.h"
#include "backend_auto.h"

#ifdef WEFT_HAVE_GPU
#include "wg_backend.h"
#endif

/* The GPU's table, or NULL in a build without it. */
static const wc_cloth_backend* gpu_table(void) {
#ifdef WEFT_HAVE_GPU
    return &wg_cloth_backend;
#else
    return NULL;
#endif
}

/* The renderer of a device the GPU table made. */
static const char* renderer_of(const void* device, int* software) {
#ifdef WEFT_HAVE_GPU
    return wg_backend_renderer(device, software);
#else
    (void)device;
    *software = 0;
    return "";
#endif
}

/* AUTO: the override of the crossover, when the environment sets one (0: unset; -1: bad). */
static int crossover_override(long* out, char* why, size_t why_len) {
    const char* text = getenv("WEFT_AUTO_CROSSOVER");
    if (!text || !*text) return 0;
    if (wc_auto_parse_crossover(text, out)) return 1;
    snprintf(why, why_len, "WEFT_AUTO_CROSSOVER='%.40s' is not a particle count (a whole number from 0 to 10^9, or unset)",
             text);
    return -1;
}

weft_status wa_backend_choose(weft_context* ctx, char* why, size_t why_len) {
    const weft_context_def* def = &ctx->def;
    wa_auto_device* a = &ctx->auto_device;
    ctx->backend = WEFT_BACKEND_CPU;
    ctx->gpu = NULL;
    ctx->gpu_device = NULL;
    memset(a, 0, sizeof *a);
    if (def->backend == WEFT_BACKEND_CPU) {
        wa_log(ctx, WEFT_LOG_INFO, "weft_context_create: CPU backend (asked for)");
        return WEFT_OK;
    }
    const int automatic = def->backend == WEFT_BACKEND_AUTO;
    int overridden = 0;
    if (automatic) {
        overridden = crossover_override(&a->crossover, why, why_len);
        if (overridden < 0) return WEFT_ERROR_INVALID_ARGUMENT;
    }
    const wc_cloth_backend* gpu = gpu_table();
    void* device = NULL;
    int software = 0;
    weft_status st = WEFT_ERROR_UNSUPPORTED;
    if (gpu) {
        /* AUTO leaves a software device closed unless the host set the crossover itself */
        wc_device_desc dd = {def->gl_mode == WEFT_GL_HOST_CURRENT, automatic && !overridden, wa_core_log, ctx,
                             ctx->alloc};
        st = wa_status(gpu->device_create(&dd, &device, &software, why, why_len));
    } else {
        snprintf(why, why_len, "this libweft.so was built without WEFT_GPU");
    }
    if (st != WEFT_OK && !automatic) {
        char device_why[512];
        snprintf(device_why, sizeof device_why, "%s", why);
        snprintf(why, why_len, "def->backend GPU: %.480s", device_why);
        return st;
    }
    if (st == WEFT_OK && device) {
        ctx->backend = WEFT_BACKEND_GPU;
        ctx->gpu = gpu;
        ctx->gpu_device = device;
        if (automatic) {
            snprintf(a->device, sizeof a->device, "%s", renderer_of(device, &software));
            if (overridden)
                a->source = WC_AUTO_OVERRIDE;
            else
                a->crossover = wc_auto_crossover(a->device, software, &a->source);
            wa_log(ctx, WEFT_LOG_INFO,
                   "weft_context_create: GPU backend (AUTO: %s%s): %s; a cloth takes it where the GPU runs all the "
                   "cloth uses and the cloth has %ld particles or more (%s), else the CPU backend",
                   software ? "a software device, kept for WEFT_AUTO_CROSSOVER" : "hardware device",
                   def->gl_mode == WEFT_GL_HOST_CURRENT ? ", host's GL context" : ", headless EGL", why, a->crossover,
                   overridden ? "WEFT_AUTO_CROSSOVER" : "the crossover table");
        } else {
            wa_log(ctx, WEFT_LOG_INFO, "weft_context_create: GPU backend (asked for%s): %s",
                   def->gl_mode == WEFT_GL_HOST_CURRENT ? ", host's GL context" : ", headless EGL", why);
        }
    } else if (st == WEFT_OK) {
        snprintf(a->device, sizeof a->device, "%s", why);
        a->crossover = WC_AUTO_NEVER;
        a->source = WC_AUTO_SOFTWARE;
        wa_log(ctx, WEFT_LOG_INFO, "weft_context_create: CPU backend (AUTO: the GPU device is a software rasteriser: %s)",
               why);
    } else {
        snprintf(a->no_device, sizeof a->no_device, "%s", why);
        wa_log(ctx, WEFT_LOG_INFO, "weft_context_create: CPU backend (AUTO: no GPU backend: %s)", why);
    }
    return WEFT_OK;
}

void wa_backend_release(weft_context* ctx) {
    wc_diag d = wa_core_diag(ctx);
    if (ctx->gpu && ctx->gpu->device_destroy(ctx->gpu_device, &d) != WC_OK)
        wa_log(ctx, WEFT_LOG_WARN, "weft_context_destroy: %s", d.message);
    ctx->gpu = NULL;
    ctx->gpu_device = NULL;
}

void* wa_backend_gl_context(const weft_context* ctx) {
#ifdef WEFT_HAVE_GPU
    if (ctx->gpu) return wg_backend_gl_context(ctx->gpu_device);
#else
    (void)ctx;
#endif
    return NULL;
}

/* The def's DEFAULT / 0 / -1 choices from table b (docs/design/cloth.md "Defaults"). */
static void resolve_defaults(const wc_cloth_backend* b, const void* device, const weft_cloth_def* def,
                             const wc_model* m, wc_sim_def* s) {
    wc_backend_defaults o;
    const wc_defaults_query q = {m->n_particles, def->preconditioner != WEFT_PRECOND_DEFAULT, s->integrator};
    b->defaults(device, &q, &o);
    s->solver.preconditioner = def->preconditioner == WEFT_PRECOND_AMG            ? WC_PRECOND_AMG
                               : def->preconditioner == WEFT_PRECOND_BLOCK_JACOBI ? WC_PRECOND_BLOCK_JACOBI
                               : def->preconditioner == WEFT_PRECOND_IC0          ? WC_PRECOND_IC0
                                                                                  : o.preconditioner;
    s->newton_iterations = def->newton_iterations > 0 ? def->newton_iterations : o.newton_iterations;
    s->newton_forcing = def->newton_forcing >= 0 ? def->newton_forcing : o.newton_forcing;
    s->solver.tolerance = def->tolerance >= 0 ? def->tolerance : o.tolerance;
    s->line_search = def->line_search >= 0 ? def->line_search : o.line_search;
    /* a garment: a cloth with a body (a mesh collider) or with seams */
    int garment = def->n_mesh_colliders > 0 || def->sew_distance > 0 || def->n_seams > 0;
    s->self_collision = def->self_collision >= 0 ? def->self_collision : garment && o.garment_self_collision;
}

/* AUTO: core's rule on this cloth (the GPU table asked where its device is open and may win). */
static int auto_gpu(const weft_context* ctx, const weft_cloth_def* def, const wc_model* m, const wc_sim_def* sim,
                    char* reason, size_t reason_len) {
    const wa_auto_device* a = &ctx->auto_device;
    wc_auto_input in;
    memset(&in, 0, sizeof in);
    in.device = a->device[0] ? a->device : NULL;
    in.no_device = a->no_device;
    in.crossover = a->crossover;
    in.source = a->source;
    in.particles = m->n_particles;
    in.gpu_status = WC_OK;
    wc_diag d;
    memset(&d, 0, sizeof d);
    if (ctx->gpu && a->crossover != WC_AUTO_NEVER) {
        wc_sim_def gs = *sim;   /* the cloth as the GPU would run it: its defaults */
        resolve_defaults(ctx->gpu, ctx->gpu_device, def, m, &gs);
        wc_backend_query q = {m, &gs, def->n_mesh_colliders};
        in.gpu_status = ctx->gpu->supports(ctx->gpu_device, &q, &d);
        in.gpu_refusal = d.message;
    }
    wc_auto_choice choice;
    wc_auto_choose(&in, &choice);
    snprintf(reason, reason_len, "%s", choice.reason);
    return choice.gpu && ctx->gpu;
}

void wa_backend_for_cloth(const weft_context* ctx, const weft_cloth_def* def, const wc_model* m, wc_sim_def* sim,
                          wa_cloth_backend* out) {
    int gpu;
    if (ctx->def.backend == WEFT_BACKEND_AUTO) {
        gpu = auto_gpu(ctx, def, m, sim, out->reason, sizeof out->reason);
    } else {
        gpu = ctx->def.backend == WEFT_BACKEND_GPU;
        snprintf(out->reason, sizeof out->reason, "asked for (weft_context_def.backend %s)", gpu ? "GPU" : "CPU");
    }
    out->backend = gpu ? WEFT_BACKEND_GPU : WEFT_BACKEND_CPU;
    out->table = gpu ? ctx->gpu : &wc_cloth_cpu;
    out->device = gpu ? ctx->gpu_device : NULL;
    resolve_defaults(out->table, out->device, def, m, sim);
}
