// Contacts, step 4 (core/collide.c wc_contacts_end), per particle: r = (A dv - b)_i (A with the
// penalty pairs' off-diagonal blocks, pairs_row.glsl); the normal
// impulse of each contact is r's component along its normal in the basis of the two normals; a
// negative one releases that contact (released = 1, the others compacted to the front).
// TR-BDF2 (core/bdf2.c wc_integ_contact_impulses): stage 1 (u_stage 1) releases nothing and holds
// the impulse r of each particle in contact (0 elsewhere) in o3; stage 2 (u_stage 2) adds the held
// one to its own r before the test, so a contact is released on the substep's impulse.
// Outputs: o0 = C0, o1 = C1 (in contact in w), o2 = C2, o3 = the held impulse (stage 1; else 0).
uniform isampler2D pblocks; // (block row start, end, diagonal block, -)
uniform isampler2D block;   // (row, column, -, -)
uniform sampler2D a_lo;
uniform sampler2D a_hi;
uniform sampler2D dv;
uniform sampler2D b;
uniform sampler2D c0;
uniform sampler2D c1;
uniform sampler2D c2;
uniform sampler2D held;     // stage 1's o3, read in stage 2
#pragma weft include pairs_row
uniform int u_nc;
uniform int u_stage;        // 0: backward Euler, BDF2; TR-BDF2's stage 1 or 2
out vec4 o0;
out vec4 o1;
out vec4 o2;
out vec4 o3;
#pragma weft include contact_geometry
#pragma weft include contact_friction_rules

vec3 residual(int i) {
    ivec4 pb = ldi(pblocks, i);
    vec3 r = -ld(b, i).xyz;
    for (int k = pb.x; k < pb.y; ++k) r += sym(ld(a_lo, k), ld(a_hi, k).xy) * ld(dv, ldi(block, k).y).xyz;
    return r + pairs_row(dv, i);   // the penalty pairs' off-diagonal blocks
}

void main() {
    int i = self_index();
    o3 = vec4(0.0);
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    vec4 c = ld(c0, i), c1i = ld(c1, i), c2i = ld(c2, i);
    int k0 = int(c.x), k1 = int(c.y);
    int cnt = (k0 >= 0 ? 1 : 0) + (k1 >= 0 ? 1 : 0);
    if (u_stage == 1) {
        o0 = c; o1 = c1i; o2 = c2i;
        if (k0 >= 0) o3 = vec4(residual(i), 0.0);
        return;
    }
    if (cnt == 0 || k0 >= u_nc || k1 >= u_nc) {
        o0 = vec4(-1.0, -1.0, 0.0, c.w); o1 = vec4(c1i.xyz, 0.0); o2 = vec4(c2i.xyz, 0.0);
        return;
    }
    vec3 r = residual(i);
    if (u_stage == 2) r += ld(held, i).xyz;
    vec2 imp = contact_impulses(r, c1i.xyz, c2i.xyz, cnt);
    float released = 0.0;
    int keep = 0;
    vec2 kid = vec2(-1.0);
    vec3 kn0 = vec3(0.0), kn1 = vec3(0.0);
    if (imp.x < 0.0) released = 1.0;
    else { kid.x = c.x; kn0 = c1i.xyz; keep = 1; }
    if (cnt > 1) {
        if (imp.y < 0.0) released = 1.0;
        else if (keep == 0) { kid.x = c.y; kn0 = c2i.xyz; keep = 1; }
        else { kid.y = c.y; kn1 = c2i.xyz; keep = 2; }
    }
    o0 = vec4(kid, released, c.w);
    o1 = vec4(kn0, keep > 0 ? 1.0 : 0.0);
    o2 = vec4(kn1, 0.0);
}
