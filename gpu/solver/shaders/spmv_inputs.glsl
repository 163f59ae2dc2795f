// The inputs of the SpMV pass, spmv.glsl and spmv_groups.glsl (an include of both, not a pass).
uniform isampler2D pblocks; // (block row start, end, diagonal block, -)
uniform isampler2D block;   // (row, column, -, -)
uniform sampler2D a_lo;
uniform sampler2D a_hi;
uniform sampler2D x;
uniform sampler2D S0;
uniform sampler2D S1;
uniform int u_filter;
