// Per particle, a rigid change of the whole state (teleports, inertia): x' = Rx x + tx,
// v' = Rv v + dv; the solver's warm start (a velocity change) turns with the velocities:
// dv' = Rd dv (Rd = Rv, or I when falling asleep zeroes only the velocities). Outputs: o0 = x, o1 = v, o2 = dv.
uniform sampler2D x;
uniform sampler2D v;
uniform sampler2D dv;   // the solver's warm start
uniform mat3 u_rx;
uniform vec3 u_tx;
uniform mat3 u_rv;
uniform vec3 u_dv;
uniform mat3 u_rd;
out vec4 o0;
out vec4 o1;
out vec4 o2;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    o0 = vec4(u_rx * ld(x, i).xyz + u_tx, 0.0);
    o1 = vec4(u_rv * ld(v, i).xyz + u_dv, 0.0);
    o2 = vec4(u_rd * ld(dv, i).xyz, 0.0);
}
