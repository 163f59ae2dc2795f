/* Running a cloth's passes (see wg_runner.h). */
#include "wg_runner.h"

#include <string.h>

#include "gpu_error.h"
#include "wg_compute.h"

void wg_runner_init(wg_runner* r, wg_device* dev, const wg_layout* layout) {
    memset(r, 0, sizeof *r);
    r->dev = dev;
    r->layout = layout;
}

void wg_runner_destroy(wg_runner* r) { wg_fbo_cache_destroy(&r->fbo); }

void wg_use_pass(wg_runner* r, wg_pass_id p, const void* in, size_t in_size) {
    const wg_pass_info* pass = &wg_passes[p];
    r->prog = &r->dev->prog[p];
    glUseProgram(r->prog->id);
    if (in_size != pass->in_size) {
        if (!r->fault[0])
            wg_errorf(r->fault, sizeof r->fault, "pass '%s' given an input struct of %zu bytes, not its %zu",
                      pass->name, in_size, pass->in_size);
        return;
    }
    for (int k = 0; k < pass->n_in; ++k) {
        const wg_tex* t = *(const wg_tex* const*)((const char*)in + pass->in[k].field);
        if (!t && !r->fault[0])
            wg_errorf(r->fault, sizeof r->fault, "pass '%s': input '%s' not given", pass->name, pass->in[k].name);
        glActiveTexture(GL_TEXTURE0 + (GLenum)k);
        glBindTexture(GL_TEXTURE_2D, t ? t->id : 0);
    }
}

void wg_u1i(wg_runner* r, const char* name, int v) { glUniform1i(wg_program_loc(r->prog, name), v); }
void wg_u1f(wg_runner* r, const char* name, double v) { glUniform1f(wg_program_loc(r->prog, name), (float)v); }
void wg_u2f(wg_runner* r, const char* name, double a, double b) {
    glUniform2f(wg_program_loc(r->prog, name), (float)a, (float)b);
}
void wg_u3f(wg_runner* r, const char* name, const double* v) {
    glUniform3f(wg_program_loc(r->prog, name), (float)v[0], (float)v[1], (float)v[2]);
}
void wg_u4f(wg_runner* r, const char* name, const double* v) {
    glUniform4f(wg_program_loc(r->prog, name), (float)v[0], (float)v[1], (float)v[2], (float)v[3]);
}
void wg_u2i(wg_runner* r, const char* name, int a, int b) { glUniform2i(wg_program_loc(r->prog, name), a, b); }
void wg_u4i(wg_runner* r, const char* name, int a, int b, int c, int d) {
    glUniform4i(wg_program_loc(r->prog, name), a, b, c, d);
}
void wg_umat3(wg_runner* r, const char* name, const double* rm) {
    float m[9];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m[3 * j + i] = (float)rm[3 * i + j];   /* column-major */
    glUniformMatrix3fv(wg_program_loc(r->prog, name), 1, GL_FALSE, m);
}

/* u_n and the layout's u_shift, which every pass reads */
static void set_size(wg_runner* r, int count) {
    glUniform1i(wg_program_loc(r->prog, "u_n"), count);
    glUniform1i(wg_program_loc(r->prog, "u_shift"), r->layout->shift);
}

/* A fragment pass over the w x h texels at (x0, 0). */
static void draw(wg_runner* r, int count, const wg_tex* const* out, int n_out, int x0, int w, int h) {
    wg_fbo_bind(&r->fbo, out, n_out);
    glViewport(x0, 0, w, h);
    set_size(r, count);
    glBindVertexArray(r->dev->vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    ++r->passes;
}

/* A compute pass (wg_compute.h) over the w x h texels at (x0, 0). */
static void dispatch(wg_runner* r, int count, const wg_tex* const* out, int n_out, int x0, int w, int h) {
    set_size(r, count);
    wg_compute_dispatch(r->prog, out, n_out, x0, w, h);
    ++r->passes;
}

void wg_run(wg_runner* r, int count, const wg_tex* const* out, int n_out) {
    if (r->dev->compute) dispatch(r, count, out, n_out, 0, out[0]->w, out[0]->h);
    else draw(r, count, out, n_out, 0, out[0]->w, out[0]->h);
}

void wg_run_texel(wg_runner* r, const wg_tex* out, int x) {
    const wg_tex* const o[1] = {out};
    if (r->dev->compute) dispatch(r, 1, o, 1, x, 1, 1);
    else draw(r, 1, o, 1, x, 1, 1);
}

void wg_run_groups(wg_runner* r, int count, const wg_tex* out, int groups) {
    const wg_tex* const o[1] = {out};
    wg_run_groups_into(r, count, groups, o, 1);
}

void wg_run_groups_into(wg_runner* r, int count, int groups, const wg_tex* const* out, int n_out) {
    set_size(r, count);
    wg_compute_dispatch_groups(out, n_out, groups, r->dev->max_groups_x);
    ++r->passes;
}

void wg_run_groups_scratch(wg_runner* r, int count, int groups, const wg_tex* const* out, int n_out,
                           const wg_tex* scratch) {
    set_size(r, count);
    wg_compute_dispatch_groups_scratch(out, n_out, scratch, groups, r->dev->max_groups_x);
    ++r->passes;
}

void wg_run_groups_rw(wg_runner* r, int count, int groups, const wg_tex* img) {
    set_size(r, count);
    wg_compute_dispatch_groups_rw(img, groups, r->dev->max_groups_x);
    ++r->passes;
}

void wg_run_by_height(wg_runner* r, const int* first, int n_heights, const wg_tex* img) {
    for (int ht = 0; ht < n_heights; ++ht) {
        int count = first[ht + 1] - first[ht];
        if (count == 0) continue;
        wg_u1i(r, "u_first", first[ht]);
        wg_u1i(r, "u_count", count);
        wg_run_groups_rw(r, count, (count + 63) / 64, img);
    }
}

void wg_run_in_place(wg_runner* r, int count, const wg_tex* img) {
    set_size(r, count);
    wg_compute_dispatch_in_place(img);
    ++r->passes;
}

void wg_copy(wg_runner* r, const wg_tex* dst, const wg_tex* src) {
    WG_USE(r, WGP_COPY, &(wg_src_in){.src = src});
    WG_RUN(r, dst->w * dst->h, dst);
}
