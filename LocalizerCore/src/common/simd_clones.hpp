// Function multiversioning for the per-particle kernels: on x86-64 Linux with GCC, a function marked
// WF_SIMD_CLONES is compiled twice, for baseline x86-64 (SSE2) and for AVX2, and the dynamic loader picks
// the AVX2 copy once at start-up on a CPU that has it (an ifunc resolver; no per-call cost beyond the PLT).
// The loops the compiler already vectorises then run 8 floats wide instead of 4.
//
// The results are the same values bit for bit: AVX2 adds wider registers and integer lanes, not new
// rounding. FMA is deliberately not enabled (it would let -ffp-contract fuse a * b + c into one rounding);
// the clones are "avx2" alone, not an architecture level such as x86-64-v3, which includes FMA. Float sums
// are not reassociated by vectorisation without -ffast-math, so sums keep their order.
//
// Everywhere else (Apple clang for the iPhone, arm64, other compilers, or WF_NO_SIMD_CLONES defined) the
// macro is empty and the function is compiled once, as before.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__) && \
    !defined(WF_NO_SIMD_CLONES)
#define WF_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define WF_SIMD_CLONES
#endif
