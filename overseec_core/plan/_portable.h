/*
 * overseec planner kernel: the few things ISO C cannot say, one spelling per compiler.
 *
 * _kernel.c is ISO C99 everywhere else, so MSVC, clang and gcc all build it (pip builds it from
 * the sdist on any platform). This header needs no Python and is compiled on its own by
 * tests/plan/test_kernel_portable.py: the plain-C clz64 against the builtin and Python, and the
 * MSVC branch in clang's MSVC mode (x64 and ARM64 Windows targets).
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

/* A hint to fetch the cache line holding *p (read); a no-op where the compiler has none. */
#if defined(OVERSEEC_PLAIN_C)
#define OVERSEEC_PREFETCH(p) ((void)(p))
#elif defined(_MSC_VER) && (defined(_M_X64) || defined(_M_IX86))
#include <xmmintrin.h>
#define OVERSEEC_PREFETCH(p) _mm_prefetch((const char *)(p), _MM_HINT_T0)
#elif defined(__GNUC__) || defined(__clang__)
#define OVERSEEC_PREFETCH(p) __builtin_prefetch((p), 0, 3)
#else
#define OVERSEEC_PREFETCH(p) ((void)(p))
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
    /* binary search over the word, six halvings without branches (each a compare and a shift) */
    int n = 0, t;
    t = !(x >> 32) << 5; n += t; x <<= t;
    t = !(x >> 48) << 4; n += t; x <<= t;
    t = !(x >> 56) << 3; n += t; x <<= t;
    t = !(x >> 60) << 2; n += t; x <<= t;
    t = !(x >> 62) << 1; n += t; x <<= t;
    n += !(x >> 63);
    return n;
#endif
}

#endif /* OVERSEEC_PORTABLE_H */
