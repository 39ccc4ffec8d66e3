/* vec4.h — four doubles at a time in GCC's vector extension: the types and the exact helpers
 * (broadcast, bitwise select, lane mask) that ct_span.c, ct_points.c and ct_fast.h share. */
#ifndef TC_CORE_VEC4_H
#define TC_CORE_VEC4_H

#include <stdint.h>
#include <string.h>

#include "core/cpu.h"

/* Vectors pass only between always-inline functions of one translation unit and one target,
 * never across a call: the Makefile silences GCC's -Wpsabi note for the files using them. */
#define TC__V4_INLINE static inline __attribute__((always_inline))

typedef double tc__v4d __attribute__((vector_size(32)));
typedef int64_t tc__v4i __attribute__((vector_size(32)));

TC__V4_INLINE tc__v4d tc__splat(double x) {
    return (tc__v4d){x, x, x, x};
}

TC__V4_INLINE tc__v4i tc__splat_i(int64_t x) {
    return (tc__v4i){x, x, x, x};
}

/* m ? a : b, lane by lane (m all ones or all zeros): exact. */
TC__V4_INLINE tc__v4d tc__sel(tc__v4i m, tc__v4d a, tc__v4d b) {
    tc__v4i ia, ib;
    memcpy(&ia, &a, sizeof ia);
    memcpy(&ib, &b, sizeof ib);
    tc__v4i r = (ia & m) | (ib & ~m);
    tc__v4d out;
    memcpy(&out, &r, sizeof out);
    return out;
}

/* Bit l set when lane l of m is set (m all ones or all zeros per lane): SSE2's movmskpd on
 * each half, so it builds for the portable and the AVX2 variants alike; in a file built with
 * AVX throughout (raster_cover_avx2.o) one vmovmskpd on the whole, instead of five instructions;
 * off x86, the lanes' sign bits one by one. */
TC__V4_INLINE unsigned tc__mask4(tc__v4i m) {
#if !TC__X86
    return (unsigned)((uint64_t)m[0] >> 63 | (uint64_t)m[1] >> 63 << 1 | (uint64_t)m[2] >> 63 << 2 |
                      (uint64_t)m[3] >> 63 << 3);
#elif defined(__AVX__)
    return (unsigned)__builtin_ia32_movmskpd256((tc__v4d)m);
#else
    typedef double v2d __attribute__((vector_size(16)));
    v2d lo, hi;
    memcpy(&lo, &m, sizeof lo);
    memcpy(&hi, (const char *)&m + sizeof lo, sizeof hi);
    return (unsigned)__builtin_ia32_movmskpd(lo) | (unsigned)__builtin_ia32_movmskpd(hi) << 2;
#endif
}

#endif
