// Hot loops compiled twice, for baseline x86-64 (SSE2) and for AVX2, the better one picked at load
// time: the portable build cannot assume AVX2, yet AVX2 gives blends, three-operand forms and
// vectorised conversions and rounding. PBS_AVX512_CLONES adds an AVX-512 version (twice the lanes,
// mask registers, 32 vector registers) for loops that gain from it. No version contracts to FMA
// (AVX-512's target implies the FMA extension, so pbs_raster is built with -ffp-contract=off), and
// all round every operation as IEEE single or double precision, so they produce bit-identical results.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__)
#define PBS_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#define PBS_AVX512_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define PBS_AVX2_CLONES
#define PBS_AVX512_CLONES
#endif

// For the helpers of a cloned function: inlined into it, they are compiled for each clone too (a
// call would reach the baseline version only).
#define PBS_CLONE_INLINE [[gnu::always_inline]] inline
