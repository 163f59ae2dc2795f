// Sums over a work group of 256 invocations (an include of the *_groups.glsl passes that fold a
// sum, not a pass). Every invocation of the group calls them, in uniform control flow (they take
// barriers), and gets the same result, added in one fixed order.
shared vec4 wg_group_part[256];

// the group's sum of every invocation's v (a shared-memory tree)
vec4 group_sum(vec4 v) {
    int t = int(gl_LocalInvocationIndex);
    wg_group_part[t] = v;
    memoryBarrierShared();
    barrier();
    for (int s = 128; s > 0; s >>= 1) {
        if (t < s) wg_group_part[t] += wg_group_part[t + s];
        memoryBarrierShared();
        barrier();
    }
    vec4 sum = wg_group_part[0];
    barrier();   // read by every invocation before a next call writes the array
    return sum;
}

// the sum of texels tc(0) .. tc(n - 1) of src (per-group partials): strided runs, then the tree
vec4 partials_sum(sampler2D src, int n) {
    vec4 acc = vec4(0.0);
    for (int k = int(gl_LocalInvocationIndex); k < n; k += 256) acc += ld(src, k);
    return group_sum(acc);
}
