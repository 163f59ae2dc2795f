// A whole PCG solve in one work group of 1,024 invocations (an include of pcg_group.glsl and
// pcg_group_amg.glsl, not a pass), whatever its preconditioner: the shader that includes it
// defines precondition_setup(k, i) (row i's preconditioner at the start, invocation row k) and
// precondition() (t = M^-1 r on the rows, and the group's (r.t, r.r)), then its main() calls
// pcg_group_main(). It runs what the multi-pass chain and its host loop run (wg_solve.c
// solve_pcg), in the same order: the guess projected, residual0 from z, the guess's residual,
// then iterations of SpMV, alpha, update, preconditioner, beta and direction with
// pcg_scalars_rules.glsl's steps; once the rules mark the solve done: the iterate projected and
// confirmed with its true residual against the float floor (restarting from it as the host
// does), and at the end the true residual. Needs pcg_scalars_rules.glsl and project_row.glsl.
//
// Invocation t owns rows t, t + 1024, t + 2048 and keeps their dv, r, c, q and t (the
// preconditioned residual) in registers; the vector an SpMV or a residual reads from its
// neighbours (c, or the iterate) is in shared memory, which the sums and the preconditioner
// reuse as scratch. Sums: each invocation's rows in order, then 32 runs of 32 invocations, then
// the 32 runs, the same order in every invocation (every invocation holds the same scalars, so
// the control flow is uniform for the barriers).
// Outputs: image 0 dv (zeros past u_n to u_texels), images 1..3 the scalars s0..s2 as the chain
// leaves them, image 4 (the true residual's square, converged (confirmed), what ended it (0: the
// rules; 1: a zero right-hand side; -1: more than GRP_MAX particles, nothing solved), restarts).
uniform isampler2D pblocks; // (block row start, end, diagonal block, -)
uniform isampler2D block;   // (row, column, -, -)
uniform sampler2D a_lo;
uniform sampler2D a_hi;
uniform sampler2D b;
uniform sampler2D S0;
uniform sampler2D S1;
uniform sampler2D z;
uniform sampler2D dv;       // the initial guess (projected here)
uniform int u_texels;
uniform int u_guard;        // the most iterations queued (the host loop's guard)
layout(binding = 0) writeonly uniform image2D wg_img0;
layout(binding = 1) writeonly uniform image2D wg_img1;
layout(binding = 2) writeonly uniform image2D wg_img2;
layout(binding = 3) writeonly uniform image2D wg_img3;
layout(binding = 4) writeonly uniform image2D wg_img4;

#define G 1024
#define R 3
#define GRP_MAX 2560        // wg_device.h's WG_GROUP_MAX_PARTICLES; 3 GRP_MAX floats of shared memory
shared float sh[3 * GRP_MAX];

int T;                      // this invocation
vec3 xdv[R], xr[R], xc[R], xq[R], xt[R];

void precondition_setup(int k, int i);
vec2 precondition();

int row(int k) { return T + G * k; }
void put(int i, vec3 v) { sh[3 * i] = v.x; sh[3 * i + 1] = v.y; sh[3 * i + 2] = v.z; }
vec3 get(int j) { return vec3(sh[3 * j], sh[3 * j + 1], sh[3 * j + 2]); }

// the group's sum of every invocation's v (barriers first and last: sh is free scratch in between)
vec2 sum2(vec2 v) {
    barrier();
    sh[2 * T] = v.x;
    sh[2 * T + 1] = v.y;
    memoryBarrierShared();
    barrier();
    if (T < 32) {   // run T: invocations 32 T .. 32 T + 31, kept in its first slot (read by T only)
        vec2 run = vec2(0.0);
        for (int k = 0; k < 32; ++k) run += vec2(sh[2 * (32 * T + k)], sh[2 * (32 * T + k) + 1]);
        sh[64 * T] = run.x;
        sh[64 * T + 1] = run.y;
    }
    memoryBarrierShared();
    barrier();
    vec2 s = vec2(0.0);
    for (int k = 0; k < 32; ++k) s += vec2(sh[64 * k], sh[64 * k + 1]);
    barrier();
    return s;
}

// row i of S (b - A x) and |A| |x| (residual.glsl), x in shared memory
vec3 residual_row(int i, out vec3 ya) {
    ivec4 rw = ldi(pblocks, i);
    vec3 y = vec3(0.0);
    ya = vec3(0.0);
    for (int k = rw.x; k < rw.y; ++k) {
        mat3 B = sym(ld(a_lo, k), ld(a_hi, k).xy);
        vec3 xj = get(ldi(block, k).y);
        y += B * xj;
        ya += mat3(abs(B[0]), abs(B[1]), abs(B[2])) * abs(xj);
    }
    return filter_apply(ld(S0, i), ld(S1, i), ld(b, i).xyz - y);
}

// row i of S (A x), x in shared memory
vec3 spmv_row(int i) {
    ivec4 rw = ldi(pblocks, i);
    vec3 y = vec3(0.0);
    for (int k = rw.x; k < rw.y; ++k) y += sym(ld(a_lo, k), ld(a_hi, k).xy) * get(ldi(block, k).y);
    return filter_apply(ld(S0, i), ld(S1, i), y);
}

// the rows' v into shared memory, then the barrier before it is read
void share_rows(vec3 v[R]) {
    barrier();
    for (int k = 0; k < R; ++k)
        if (row(k) < u_n) put(row(k), v[k]);
    memoryBarrierShared();
    barrier();
}

// c = S (t + beta c), or c = S t (first)
void direction(float beta, bool first) {
    for (int k = 0; k < R; ++k)
        if (row(k) < u_n) {
            int i = row(k);
            xc[k] = filter_apply(ld(S0, i), ld(S1, i), first ? xt[k] : xt[k] + beta * xc[k]);
        }
}

// the iterate projected (project.glsl), and |S (b - A dv)|^2 with |(|A| |dv|)|^2 (y); r = the
// true residual
vec2 true_residual() {
    for (int k = 0; k < R; ++k)
        if (row(k) < u_n) xdv[k] = project_row(xdv[k], ld(z, row(k)).xyz, ld(S0, row(k)), ld(S1, row(k)), false);
    share_rows(xdv);
    vec2 acc = vec2(0.0);
    for (int k = 0; k < R; ++k)
        if (row(k) < u_n) {
            vec3 ya;
            xr[k] = residual_row(row(k), ya);
            acc += vec2(dot(xr[k], xr[k]), dot(ya, ya));
        }
    return sum2(acc);
}

void pcg_group_main() {
    T = int(gl_LocalInvocationIndex);
    if (u_n > GRP_MAX) {   // the host never runs such a cloth here; a mismatch of limits shows
        if (T == 0) imageStore(wg_img4, ivec2(0), vec4(0.0, 0.0, -1.0, 0.0));
        return;
    }
    // the guess projected (wg_solve's project pass), the preconditioner's rows, z shared
    for (int k = 0; k < R; ++k)
        if (row(k) < u_n) {
            int i = row(k);
            precondition_setup(k, i);
            xdv[k] = project_row(ld(dv, i).xyz, ld(z, i).xyz, ld(S0, i), ld(S1, i), false);
            xc[k] = ld(z, i).xyz;
        }
    share_rows(xc);
    // residual0^2 = |S (b - A z)|^2
    float acc0 = 0.0;
    for (int k = 0; k < R; ++k)
        if (row(k) < u_n) {
            vec3 ya, rz = residual_row(row(k), ya);
            acc0 += dot(rz, rz);
        }
    float res0sq = sum2(vec2(acc0, 0.0)).x;
    // the guess's residual; then, from the top of the loop: t = M^-1 r and (r.t, r.r) (at one
    // place: a shader compiler inlines every call, and the multigrid's is long), the scalars'
    // step that takes them (mode: 0, the start; 2, beta; 3, a restart) and the direction
    share_rows(xdv);
    for (int k = 0; k < R; ++k)
        if (row(k) < u_n) {
            vec3 ya;
            xr[k] = residual_row(row(k), ya);
        }
    vec4 s0 = vec4(0.0), s1 = vec4(0.0), s2 = vec4(0.0);
    bool converged = false, zero_rhs = false;
    float rt = -1.0;
    int queued = 0, restarts = 0, mode = 0;
    for (;;) {
        pcg_scalars_step(mode, s0, s1, s2, res0sq, precondition());   // sum: read by mode 0 only
        if (mode != 2) direction(0.0, true);   // c = S t
        else if (s1.x == 0.0) direction(s0.z, false);
        if (s1.x != 0.0) {   // done: the host loop's rules
            if (s1.y != 0.0) break;   // diverged
            if (s1.w == 0.0) break;   // the iteration cap
            if (s2.x == 0.0) {        // zero right-hand side: dv = z
                zero_rhs = true;
                for (int k = 0; k < R; ++k)
                    if (row(k) < u_n) xdv[k] = ld(z, row(k)).xyz;
                break;
            }
            vec2 tr = true_residual();
            rt = tr.x;
            float fl = ldexp(sqrt(tr.y), -24);
            if (sqrt(rt) <= max(s2.y, min(fl, 100.0 * s2.y))) {
                converged = true;
                break;
            }
            if (s1.z >= u_max_iterations) break;
            mode = 3;   // restart from the true residual
            ++restarts;
            rt = -1.0;
            continue;
        }
        if (queued++ > u_guard) break;   // a solve that never sets done: stop anyway
        // q = S (A c), alpha
        share_rows(xc);
        float cq = 0.0;
        for (int k = 0; k < R; ++k)
            if (row(k) < u_n) {
                xq[k] = spmv_row(row(k));
                cq += dot(xc[k], xq[k]);
            }
        pcg_scalars_step(1, s0, s1, s2, sum2(vec2(cq, 0.0)).x, vec2(0.0));
        // dv += alpha c, r -= alpha q (pcg_update_row.glsl); the loop's top: t, (r.t, r.r), beta
        float alpha = s1.x != 0.0 ? 0.0 : s0.y;
        if (alpha != 0.0)
            for (int k = 0; k < R; ++k)
                if (row(k) < u_n) {
                    xdv[k] += alpha * xc[k];
                    xr[k] -= alpha * xq[k];
                }
        mode = 2;
    }
    if (!converged && !zero_rhs) rt = true_residual().x;
    if (pcg_bad(s2.x))   // residual0 not finite: dv = z
        for (int k = 0; k < R; ++k)
            if (row(k) < u_n) xdv[k] = ld(z, row(k)).xyz;
    for (int i = T; i < u_texels; i += G) {
        int k = (i - T) / G;
        vec3 o = vec3(0.0);
        for (int j = 0; j < R; ++j)   // constant indices: the arrays stay in registers
            if (j == k && i < u_n) o = xdv[j];
        imageStore(wg_img0, tc(i), vec4(o, 0.0));
    }
    if (T == 0) {
        imageStore(wg_img1, ivec2(0), s0);
        imageStore(wg_img2, ivec2(0), s1);
        imageStore(wg_img3, ivec2(0), s2);
        imageStore(wg_img4, ivec2(0), vec4(rt, converged ? 1.0 : 0.0, zero_rhs ? 1.0 : 0.0, float(restarts)));
    }
}
