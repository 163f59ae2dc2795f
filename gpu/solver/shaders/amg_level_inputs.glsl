// The inputs of the multigrid's passes over one level's operator and its smoother, amg_power.glsl
// and amg_smooth.glsl (an include of both, not a pass; wg_amg.c binds them in this order).
uniform isampler2D t0;  // rows (start, end, diagonal block, aggregate)
uniform isampler2D t1;  // cols
uniform sampler2D t2;   // blocks, row 0
uniform sampler2D t3;   // row 1
uniform sampler2D t4;   // row 2
uniform sampler2D t5;   // D^-1, row 0
uniform sampler2D t6;   // row 1
uniform sampler2D t7;   // row 2
