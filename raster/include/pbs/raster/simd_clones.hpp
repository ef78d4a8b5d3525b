// Hot loops compiled twice, for baseline x86-64 (SSE2) and for AVX2, the better one picked at load
// time: the portable build cannot assume AVX2, yet AVX2 gives blends, three-operand forms and
// vectorised conversions and rounding. PBS_AVX512_CLONES adds a version for x86-64-v4 (AVX-512
// with the VL, BW and DQ extensions: twice the lanes, and mask registers and 32 vector registers
// also for 8-lane vectors) for the loops that gain from it. No version contracts to FMA (the
// modules using them are built with -ffp-contract=off, since x86-64-v4 includes the FMA extension),
// and all round every operation as IEEE single or double precision, so they produce bit-identical
// results. Public, so that hot loops outside the rasterizer (surfels' colour filter) clone alike.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__)
#define PBS_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#define PBS_AVX512_CLONES __attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#else
#define PBS_AVX2_CLONES
#define PBS_AVX512_CLONES
#endif

// For the helpers of a cloned function: inlined into it, they are compiled for each clone too (a
// call would reach the baseline version only).
#define PBS_CLONE_INLINE [[gnu::always_inline]] inline
