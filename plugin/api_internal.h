/* Private to libweft.so: the context behind the public handle and the helpers the facade's files
 * share. The public contract is include/weft/weft.h; nothing here is exported. A cloth is core's
 * wc_cloth (core/cloth.h); where it runs, the backend table it got (core/cloth_backend.h).
 *
 * Layout of the facade (validation, handles, ABI <-> core conversion; no physics):
 *   context.c          the helpers: statuses, last error, logger and diag bridges, handle table
 *   context_create.c   context def defaults, weft_context_create / destroy
 *   backend.c          the backend choice (AUTO / CPU / GPU): the device at context creation, each
 *                      cloth's table and reason at cloth creation, the def's DEFAULT choices
 *   transform.c        host transforms: the checks (finite, last row, rigid) and their messages
 *   cloth_def.c        defaults of the cloth/attachment/collider defs and the frame, validation
 *   cloth_create.c     weft_cloth_def -> wc_cloth_def, cloth create/destroy, attachments, info
 *   cloth_frame.c      weft_cloth_step: frame validation, the core frame, statistics
 *   context_step.c     weft_context_step: many cloths in one call (core's batch)
 *   cloth_output.c     vertices, triangles, GL buffers
 *   mesh_colliders.c   mesh collider def defaults and validation, new vertices for a frame
 *   collision_check.c  weft_cloth_check_collisions
 *   snapshot.c         weft_cloth_save / restore
 *   render.c           weft_render: preview pictures through gpu/'s renderer
 * Calls run one way: the API files call context.c's helpers, the validation (transform.c,
 * cloth_def.c, mesh_colliders.c), backend.c and core; nothing calls back up (weft_render reads
 * the vertices through the public weft_cloth_get_vertices). */
#ifndef WEFT_PLUGIN_API_INTERNAL_H
#define WEFT_PLUGIN_API_INTERNAL_H
#include <stdatomic.h>
#include <stdint.h>
#include "backend_auto.h"
#include "cloth.h"
#include "weft/weft.h"

/* Cookies the weft_default_*() functions put into internal_cookie: a def that skipped its
 * initialiser (zeroed, stack garbage, or a def of another type) is refused. */
#define WA_COOKIE_CONTEXT 0x57464331u    /* "WFC1" */
#define WA_COOKIE_CLOTH 0x57464c31u      /* "WFL1" */
#define WA_COOKIE_ATTACHMENT 0x57464131u /* "WFA1" */
#define WA_COOKIE_COLLIDER 0x57464f31u   /* "WFO1" */
#define WA_COOKIE_RENDER 0x57465231u     /* "WFR1" (weft_default_render_def, render code) */
#define WA_COOKIE_MESH_COLLIDER 0x57464d31u /* "WFM1" */

typedef struct wa_slot {
    uint32_t generation;        /* bumped at every destroy; never 0 */
    wc_cloth* cloth;            /* NULL when free */
    uint32_t batch_call;        /* weft_context_step: the call that took the cloth (== the
                                   context's batch_calls: the running one) */
    int batch_index;            /* ... at this index of its cloths array */
    weft_backend backend;       /* the cloth's backend (CPU or GPU) and why (backend.c) */
    char backend_reason[WEFT_BACKEND_REASON_LENGTH];
} wa_slot;

/* What AUTO chooses each cloth's backend with, found at context creation (backend.c). */
typedef struct wa_auto_device {
    char device[128];           /* the GPU device's GL renderer ("" when there is none) */
    char no_device[256];        /* why there is none */
    long crossover;             /* particles from which a cloth takes the GPU, or WC_AUTO_NEVER */
    wc_auto_source source;      /* where that figure comes from */
} wa_auto_device;

/* What one cloth of a weft_context_step logs while it steps, kept for the calling thread to pass
 * on (the logger is called from the calling thread only; the cloth may run on another). */
#define WA_BATCH_LOG_LINES 4
typedef struct wa_batch_log {
    const weft_context* ctx;    /* its logger's level filters what is kept */
    int n, dropped;             /* lines kept, lines beyond WA_BATCH_LOG_LINES */
    weft_log_level level[WA_BATCH_LOG_LINES];
    char line[WA_BATCH_LOG_LINES][256];
} wa_batch_log;

struct weft_context {
    weft_context_def def;       /* as given (logger, level, threads) */
    weft_backend backend;       /* the device it holds: GPU while gpu is set, else CPU (never AUTO) */
    const wc_cloth_backend* gpu;    /* the GPU's table while its device is open (GPU; AUTO on a device
                                   it may use), else NULL; the CPU's table is always there */
    void* gpu_device;
    wa_auto_device auto_device; /* def.backend AUTO: what each cloth's choice needs */
    wc_allocator alloc;         /* bridge of def.allocator (also gpu/'s allocator) */
    weft_status last_status;
    char last_error[512];
    uint32_t tag;               /* per-context handle tag (16 bits) */
    int n_slots, cap_slots;
    wa_slot* slots;
    /* weft_context_step's scratch, cap_slots of each (grown with the slots: a batch allocates
       nothing): core's items, and each item's kept log lines */
    wc_cloth_batch_item* batch_items;
    wa_batch_log* batch_logs;
    uint32_t batch_calls;       /* weft_context_step calls made */
    void* render_gl;            /* wg_gl_context* of weft_render when the backend's device has
                                   none (render.c): made by the first call */
    void* renderer;             /* wg_renderer* (in the device's GL context or render_gl) */
    _Atomic uintptr_t call_owner; /* in-call flag (call_guard.c): the calling thread's token, 0 idle */
    int call_depth;             /* nested calls of the owning thread */
};

/* ---- context.c: helpers ---------------------------------------------------------------------- */

/* Core's (and gpu/'s) status as the ABI's. */
weft_status wa_status(wc_status s);
/* Record a failed call (status, message, logger at ERROR); returns status. */
weft_status wa_fail(weft_context* ctx, weft_status status, const char* fmt, ...) __attribute__((format(printf, 3, 4)));
/* Record a failed core call: its status as the ABI's, "fn: <core's message>". */
weft_status wa_fail_core(weft_context* ctx, const char* fn, wc_status st, const wc_diag* d);
/* Record a successful call; returns WEFT_OK. */
weft_status wa_ok(weft_context* ctx);
/* Log at a level (filtered by the context's log_level). */
void wa_log(weft_context* ctx, weft_log_level level, const char* fmt, ...) __attribute__((format(printf, 3, 4)));
/* A core diag for one call (no logger for errors; warnings forwarded). */
wc_diag wa_core_diag(weft_context* ctx);
/* Core's (and gpu/'s) log level as the ABI's. */
weft_log_level wa_log_level(wc_log_level level);
/* The logger bridge of wa_core_diag, a wc_log_fn with user = the weft_context: core's and gpu/'s
 * DEBUG..WARN go to the context's logger (level mapped, filtered by def.log_level); ERRORs are
 * dropped (they come back as statuses and are reported once, prefixed, by wa_fail). */
void wa_core_log(wc_log_level level, const char* message, void* user);
/* The cloth a handle names, or NULL (then the failure is recorded, prefixed with fn). */
wc_cloth* wa_lookup(weft_context* ctx, weft_cloth h, const char* fn);
/* Register a cloth in a free slot (growing the slots and weft_context_step's scratch); 0 on
 * allocation failure. */
int wa_register(weft_context* ctx, wc_cloth* c, weft_cloth* out);
/* The slot of a handle that wa_lookup accepted. */
wa_slot* wa_slot_of(weft_context* ctx, weft_cloth h);
/* Release the slot of a handle that wa_lookup accepted. */
void wa_unregister(weft_context* ctx, weft_cloth h);
/* Destroy a cloth; objects its backend had to leave to the host's GL context are logged (WARN). */
void wa_cloth_free(weft_context* ctx, wc_cloth* c);

/* ---- cloth_frame.c: one frame's conversion (weft_cloth_step, weft_context_step) -------------- */

/* Validate a frame for cloth c (nothing changes); messages "fn: <name>dt ..." where name is how
 * the frame is spelt ("fr->", "frames[3]."). */
weft_status wa_validate_frame(weft_context* ctx, const wc_cloth* c, const weft_frame* fr, const char* fn,
                              const char* name);
/* The frame as core's. */
wc_cloth_frame wa_core_frame(const weft_frame* fr);
/* Core's statistics (and the state's clock) as the ABI's; ms_total is the caller's. */
void wa_fill_stats(weft_frame_stats* o, const wc_step_stats* st, const wc_state* s, double ms_total);

/* ---- backend.c ------------------------------------------------------------------------------- */

/* The context's device from def.backend: none (CPU); the GPU's, which must work (GPU: else the
 * status, with why); AUTO: the GPU's on a hardware device, or on any device with
 * WEFT_AUTO_CROSSOVER set (a bad value: INVALID_ARGUMENT), and the device's crossover. Logged at
 * INFO. A failure's message, naming what failed, goes into why. */
weft_status wa_backend_choose(weft_context* ctx, char* why, size_t why_len);

/* A cloth's backend: the table it runs on and the table's device. */
typedef struct wa_cloth_backend {
    const wc_cloth_backend* table;
    void* device;
    weft_backend backend;       /* CPU or GPU */
    char reason[WEFT_BACKEND_REASON_LENGTH];   /* "asked for (...)", "AUTO: ..." */
} wa_cloth_backend;
/* The backend of a new cloth of def whose model m is built: the context's (CPU or GPU asked
 * for) or AUTO's choice for this cloth (core/backend_auto.h: what the GPU table's `supports`
 * says of it, its particle count against the device's crossover); and the def's DEFAULT / 0 / -1
 * choices resolved into sim from the chosen table (docs/design/cloth.md "Defaults"). */
void wa_backend_for_cloth(const weft_context* ctx, const weft_cloth_def* def, const wc_model* m, wc_sim_def* sim,
                          wa_cloth_backend* out);
/* Release the device (after the cloths and the renderer). */
void wa_backend_release(weft_context* ctx);
/* The device's GL context (a wg_gl_context*, shared with the renderer), or NULL. */
void* wa_backend_gl_context(const weft_context* ctx);

/* ---- transform.c ----------------------------------------------------------------------------- */

/* Validate a host transform: every element finite (else NONFINITE), last row (0, 0, 0, 1) and
 * R rigid (|det R - 1| < 1e-3, max |R^T R - I| < 1e-3; else INVALID_ARGUMENT). On failure `why`
 * receives the reason ("[7] is NaN", "is not rigid: det 2"). */
weft_status wa_check_transform(const float* m, char* why, size_t why_size);

/* ---- cloth_def.c / mesh_colliders.c: validation ---------------------------------------------- */

/* Validate everything of the def that can be checked before the mesh is read; status + message
 * (naming the field) into msg. */
weft_status wa_validate_cloth_def(const weft_cloth_def* def, char* msg, size_t msg_size);
/* Validate attachment defs (cookie, counts, transforms, axis); vertex indices against n_host
 * when n_host >= 0. prefix names the array ("def->attachments", "attachments"). */
weft_status wa_validate_attachments(const weft_attachment_def* a, int n, int n_host, const char* prefix, char* msg,
                                    size_t msg_size);
weft_status wa_validate_colliders(const weft_collider_def* c, int n, const char* prefix, char* msg, size_t msg_size);
weft_status wa_validate_mesh_colliders(const weft_mesh_collider_def* m, int n, char* msg, size_t msg_size);

/* ---- render.c -------------------------------------------------------------------------------- */

/* Release the context's renderer and its own GL context (nothing when it never rendered). */
void wa_render_release(weft_context* ctx);

#endif
