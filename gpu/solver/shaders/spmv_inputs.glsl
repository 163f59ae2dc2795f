// The inputs of the SpMV pass, spmv.glsl and spmv_groups.glsl (an include of both, not a pass).
uniform isampler2D t0;  // particle blocks (row start, row end, diagonal block, -)
uniform isampler2D t1;  // block (row, column, -, -)
uniform sampler2D t2;   // A lo
uniform sampler2D t3;   // A hi
uniform sampler2D t4;   // x
uniform sampler2D t5;   // S0
uniform sampler2D t6;   // S1
uniform int u_filter;
