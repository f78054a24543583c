// Hints that let the runtime's per-object and per-tile loops vectorise. Internal to scheduler/.
#pragma once

// The loop after it writes arrays that none of its inputs overlap (GCC would otherwise give up on the
// run-time overlap checks of many streams; Clang vectorises such loops by itself).
#if defined(__GNUC__) && !defined(__clang__)
#define ACUITY_NO_ALIAS _Pragma("GCC ivdep")
#else
#define ACUITY_NO_ALIAS
#endif

// The vectorised loops are also compiled for AVX2 and picked at load time where the CPU has it (GCC
// on x86-64 ELF: an ifunc; Clang wants the attribute on the class's declaration); the baseline build
// has 4-wide SSE2 only. The same IEEE operations without FMA contraction: the same bits on every CPU.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__ELF__)
#define ACUITY_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define ACUITY_SIMD_CLONES
#endif
