#version 430 core
// The idle proof's pairs (wg_self_idle.h): invocation q, a query of core's stage (a particle
// q < u_np against the triangle tree, else the edge q - u_np against the edges above it), walks
// the tree refitted by self_idle_refit_groups.glsl (root node 0) with the box of its start
// positions grown by its largest displacement (and float ulps), and tests every pair whose leaf
// box meets it and that core's adjacency rules keep (no shared or sewn particle, not all four
// tangled at rest): the pair is idle when a lower bound L of its distance at the start (the
// support bound of self_walk_rules.glsl, less u_mu and 4e-6 of its extent for float's rounding)
// is at least the thickness times (1 + u_rel) and L less its relative motion bound (the largest
// |d_i - d_j| over a particle of each feature, d = x - xs, grown for rounding) exceeds eta times
// (1 + u_rel): core's proximity pass then gives it no impulse (distance >= thickness) and its
// too_far skips the CCD (self_pass.c). Every other pair adds one to the counter (image 1, r32i).
// A degenerate or non-finite case gives no bound (the pair acts).
// u_cap > 0 (the GPU's proximity pass, wg_self_prox.h): a pair that may act takes the counter's
// slot and, below u_cap, writes 13 texels of the list (image 0) from 13 slot: (q, element; floats,
// exact below 2^24), then x, xs and v of its 4 particles; a query with no bound (non-finite, too deep) adds
// u_cap + 1 (the host's stage). u_refined 1 (the proof after that pass): the thickness test is
// left out, a pair acts only where too_far may fail (its proximity impulse was given).
// u_margin (listing, wg_self_prox.h): too_far must hold with u_margin to spare, so that the pass's
// impulses (each particle moved by at most u_margin / 2) leave every unlisted pair too_far.
layout(local_size_x = 64, local_size_y = 1) in;
uniform sampler2D x;           // the substep's end positions
uniform sampler2D xs;          // its start positions
uniform sampler2D v;           // its end velocities (listed only)
uniform int u_shared, u_cap, u_refined;
uniform float u_th, u_eta, u_rel, u_mu, u_ulp, u_margin;
layout(binding = 0, rgba32f) writeonly uniform image2D wg_img0;
layout(binding = 1, r32i) uniform iimage2D wg_img1;

#pragma weft include self_walk_rules

// the largest |d_i - d_j|, i of the first feature (ids[0, split)), j of the second
float max_rel(ivec4 ids, int split) {
    vec3 d[4];
    float m = 0.0;
    for (int k = 0; k < 4; ++k) d[k] = ld(x, ids[k]).xyz - ld(xs, ids[k]).xyz;
    for (int i = 0; i < split; ++i)
        for (int j = split; j < 4; ++j) m = max(m, length(d[i] - d[j]) + 2.4e-7 * (length(d[i]) + length(d[j])));
    return m * 1.00001;
}

// 1 when the pair may act: lb the support bound of its start distance, ext its extent
int acts(float lb, float ext, ivec4 ids, int split) {
    float L = lb - u_mu - u_ulp * 4e-6 * ext;
    if (u_refined == 0 && !(L >= u_th * (1.0 + u_rel))) return 1;
    return L - max_rel(ids, split) > u_eta * (1.0 + u_rel) + u_margin ? 0 : 1;
}

// 1 when the pair may act: core's rules keep it and it is not proved idle (no bound: it acts)
int pair_acts(ivec4 ids, int split) {
    if (adjacent(ids, split, u_shared != 0)) return 0;
    float lb, ext;
    return support_bound(xs, ids, split, lb, ext) ? acts(lb, ext, ids, split) : 1;
}

int count;   // the query's pairs that may act

// self_walk_rules.glsl's walk meets a leaf: its pair counted when it may act
void visit(int q, int prim, ivec4 ids, int split) {
    if (pair_acts(ids, split) == 0) return;
    if (u_cap == 0) {
        count += 1;
        return;
    }
    int slot = imageAtomicAdd(wg_img1, ivec2(0), 1);
    if (slot >= u_cap) return;
    int b = 13 * slot;
    imageStore(wg_img0, tc(b), vec4(float(q), float(prim), 0.0, 0.0));
    for (int k = 0; k < 4; ++k) {
        imageStore(wg_img0, tc(b + 1 + k), ld(x, ids[k]));
        imageStore(wg_img0, tc(b + 5 + k), ld(xs, ids[k]));
        imageStore(wg_img0, tc(b + 9 + k), ld(v, ids[k]));
    }
}

// deeper than core's trees go: acts (listing: the host's stage)
bool too_deep() {
    count += u_cap + 1;
    return false;
}

void main() {
    int q = int(gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x);
    if (q >= u_n) return;
    ivec2 pq = query_particles(q);
    vec3 blo = vec3(3.0e38), bhi = vec3(-3.0e38);
    float delta = 0.0, mag = 0.0;
    for (int k = 0; k < 2; ++k) {
        if (pq[k] < 0) continue;
        vec3 p0 = ld(xs, pq[k]).xyz, p1 = ld(x, pq[k]).xyz;
        blo = min(blo, p0);
        bhi = max(bhi, p0);
        delta = max(delta, length(p1 - p0));
        mag = max(mag, max(max(abs(p0.x), abs(p0.y)), abs(p0.z)));
    }
    if (isnan(delta) || isinf(delta) || isnan(mag) || isinf(mag)) {   // no bound: core's stage decides
        imageAtomicAdd(wg_img1, ivec2(0), u_cap + 1);
        return;
    }
    float pad = delta * 1.0001 + (mag + delta) * 9.6e-7;
    blo -= pad;
    bhi += pad;
    count = 0;
    walk(q, blo, bhi);
    if (count > 0) imageAtomicAdd(wg_img1, ivec2(0), count);
}
