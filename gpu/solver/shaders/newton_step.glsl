// Per particle, a Newton step (core/newton.c): the trial iterate w + alpha d, and g.d for the
// descent test (reduced: grad Phi . d = -sum g.d must be negative).
// Outputs: o0 = w + alpha d, o1 = (g.d, -, -, -).
uniform sampler2D w;
uniform sampler2D d;
uniform sampler2D g;
uniform float u_alpha;
out vec4 o0;
out vec4 o1;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    vec3 di = ld(d, i).xyz;
    o0 = vec4(ld(w, i).xyz + u_alpha * di, 0.0);
    o1 = vec4(dot(ld(g, i).xyz, di), 0.0, 0.0, 0.0);
}
