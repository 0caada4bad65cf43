/*
 * overseec planner kernel: the few things ISO C cannot say, one spelling per compiler.
 *
 * _kernel.c is ISO C99 everywhere else, so MSVC, clang and gcc all build it (pip builds it from
 * the sdist on any platform). This header needs no Python and is compiled on its own by
 * tests/plan/test_kernel_portable.py, which checks clz64's plain-C fallback against the builtin.
 *
 * OVERSEEC_PLAIN_C: define it to use the plain-C fallbacks even where a builtin exists (the
 * tests use it to prove the fallbacks compile and agree; no build sets it).
 */
#ifndef OVERSEEC_PORTABLE_H
#define OVERSEEC_PORTABLE_H

#include <stdint.h>

#if defined(_MSC_VER) && !defined(OVERSEEC_PLAIN_C)
#include <intrin.h>
#endif

/* A function the compiler must inline (search_loop is instantiated twice with a constant flag;
   inlining lets each copy drop the other's branches). */
#if defined(OVERSEEC_PLAIN_C)
#define OVERSEEC_FORCE_INLINE static inline
#elif defined(_MSC_VER)
#define OVERSEEC_FORCE_INLINE static __forceinline
#elif defined(__GNUC__) || defined(__clang__)
#define OVERSEEC_FORCE_INLINE static inline __attribute__((always_inline))
#else
#define OVERSEEC_FORCE_INLINE static inline
#endif

/* Leading zero bits of a 64-bit word; x must not be 0 (the radix heap never asks for it). */
#if !defined(OVERSEEC_PLAIN_C) && defined(_MSC_VER) && (defined(_M_X64) || defined(_M_ARM64))
#define OVERSEEC_CLZ_MSVC 1
#elif !defined(OVERSEEC_PLAIN_C) && (defined(__GNUC__) || defined(__clang__))
#define OVERSEEC_CLZ_GNU 1
#endif

static inline int clz64(uint64_t x) {
#if defined(OVERSEEC_CLZ_MSVC)
    unsigned long i;
    _BitScanReverse64(&i, x);
    return 63 - (int)i;
#elif defined(OVERSEEC_CLZ_GNU)
    return __builtin_clzll((unsigned long long)x);
#else
    /* binary search over the word: six halvings */
    int n = 0;
    if (!(x & UINT64_C(0xFFFFFFFF00000000))) { n += 32; x <<= 32; }
    if (!(x & UINT64_C(0xFFFF000000000000))) { n += 16; x <<= 16; }
    if (!(x & UINT64_C(0xFF00000000000000))) { n += 8; x <<= 8; }
    if (!(x & UINT64_C(0xF000000000000000))) { n += 4; x <<= 4; }
    if (!(x & UINT64_C(0xC000000000000000))) { n += 2; x <<= 2; }
    if (!(x & UINT64_C(0x8000000000000000))) n += 1;
    return n;
#endif
}

#endif /* OVERSEEC_PORTABLE_H */
