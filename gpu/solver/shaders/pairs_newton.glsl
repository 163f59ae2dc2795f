// Per pair: the penalty pairs' state in a Newton system at the iterate w (wg_pairs.h; core's
// wc_penalty_pairs_newton): the gap at x(w) = xb + h (v + w),
// g = (n . sum w_a xb_a - off) + h (n . sum w_a v_a + n . sum w_a w_a), from the two parts the
// host computed in double at the substep's start (gk.xy) and the iterate's, so that float keeps
// the gap's digits; the pair is active when g < 0.
// Outputs: o0 = (n, c), c = h^2 k while active, else 0 (what pairs_row.glsl reads); o1 = (the
// force's factor -h k g while active, else 0, -, -): b_a += o1.x w_a n.
uniform isampler2D pp;      // pairs: their particles
uniform sampler2D pw;       // pairs: their weights (0 past the pair's count)
uniform sampler2D pnc;      // pairs: (n, c)
uniform sampler2D pgk;      // pairs: (n . sum w xb - off, n . sum w v, k, count)
uniform sampler2D w;        // particles: the iterate
uniform float u_h;
out vec4 o0;
out vec4 o1;

void main() {
    int j = self_index();
    if (j >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    ivec4 p = ldi(pp, j);
    vec4 wt = ld(pw, j), gk = ld(pgk, j);
    vec3 n = ld(pnc, j).xyz;
    int cnt = int(gk.w);
    float s = 0.0;
    for (int a = 0; a < cnt; ++a) s += wt[a] * dot(n, ld(w, p[a]).xyz);
    float g = gk.x + u_h * (gk.y + s);
    bool on = g < 0.0;
    o0 = vec4(n, on ? u_h * u_h * gk.z : 0.0);
    o1 = vec4(on ? -u_h * gk.z * g : 0.0, 0.0, 0.0, 0.0);
}
