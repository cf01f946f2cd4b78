#pragma once
// GMWM_VECTOR_CLONES: a hot loop compiled twice, for AVX2 and for baseline x86-64, the
// dynamic loader choosing one for the running processor (GCC's and Clang's target_clones,
// a glibc ifunc). The portable build stays portable and an AVX2 machine runs its four-wide
// code: the level passes of the Haar transform 5.0 -> 3.8 ms at 1e6 samples (issue 44).
//
// Results do not depend on the clone taken: "avx2" does not enable FMA, so no multiply-add
// is contracted, and the loops so marked either work element by element or keep explicit
// partial sums (four lanes) whose order is the same at either width; no reduction is
// reassociated (no -ffast-math). tests/engine/vector_clones_test.cc checks it on this
// machine by comparing each clone's output bit for bit.
//
// Elsewhere (another architecture or C library, or GMWM_NO_VECTOR_CLONES defined) it is
// empty and the loop is compiled once.
#include <cstddef>  // glibc's features.h, which defines __GLIBC__

#if defined(__x86_64__) && defined(__GLIBC__) && (defined(__GNUC__) || defined(__clang__)) && \
    !defined(GMWM_NO_VECTOR_CLONES)
#define GMWM_VECTOR_CLONES [[gnu::target_clones("avx2", "default")]]
#else
#define GMWM_VECTOR_CLONES
#endif
