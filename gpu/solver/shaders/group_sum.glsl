// Sums over a work group of 256 invocations (an include of the *_groups.glsl passes that fold a
// sum, not a pass). Every invocation of the group calls them, in uniform control flow (they take
// barriers), and gets the same result, added in one fixed order.
shared vec4 wg_group_part[256];
shared vec4 wg_group_part16[16];

// the group's sum of every invocation's v: 16 runs of 16 summed by 16 invocations, then the 16
// sums by every invocation (two barriers, where a tree takes nine; a CPU driver such as llvmpipe
// runs the group's invocations as coroutines that switch at each barrier)
vec4 group_sum(vec4 v) {
    int t = int(gl_LocalInvocationIndex);
    wg_group_part[t] = v;
    memoryBarrierShared();
    barrier();
    if (t < 16) {
        vec4 run = vec4(0.0);
        for (int k = 0; k < 16; ++k) run += wg_group_part[16 * t + k];
        wg_group_part16[t] = run;
    }
    memoryBarrierShared();
    barrier();
    vec4 sum = vec4(0.0);
    for (int k = 0; k < 16; ++k) sum += wg_group_part16[k];
    return sum;   // a next call writes wg_group_part16 only after its first barrier, when all have read it
}

// the sum of texels tc(0) .. tc(n - 1) of src (per-group partials): strided runs, then group_sum
vec4 partials_sum(sampler2D src, int n) {
    vec4 acc = vec4(0.0);
    for (int k = int(gl_LocalInvocationIndex); k < n; k += 256) acc += ld(src, k);
    return group_sum(acc);
}
