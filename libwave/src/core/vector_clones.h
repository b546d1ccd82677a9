// Per-vertex kernels vectorised for the CPU at hand, with the same bits everywhere.
//
// The library is built for baseline x86-64 (SSE2), where GCC cannot vectorise a loop
// that reads xyz triples of floats into double arithmetic. A function marked
// LIBWAVE_VECTOR_CLONES is compiled twice, for AVX2 and for the baseline, and the
// loader picks one by the CPU (an ifunc). AVX2 brings no fused multiply–add (that is
// the separate FMA extension, never enabled), and vector add, multiply, divide and
// square root round as their scalar forms do, so both clones compute the same bits;
// a loop's operations keep their order (no reassociation without -ffast-math).
// The kernels' loops must be free of calls and of branches the compiler cannot turn
// into selects (hence -fno-math-errno -fno-trapping-math on libwave's targets).
// Other compilers (clang builds the fuzzers) get the baseline function alone.
#pragma once

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(LIBWAVE_NO_VECTOR_CLONES)
#define LIBWAVE_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define LIBWAVE_VECTOR_CLONES
#endif
