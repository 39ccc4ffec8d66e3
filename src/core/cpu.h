/* cpu.h — which instruction-set variants this build has and this CPU can run: the one place that
 * asks, so that the AVX2 variants (ct_span.c, ct_points.c, raster_cover_avx2.o) exist on x86 only.
 *
 * TC__X86 is 1 where the compiler targets x86 (the Makefile then also builds raster_cover_avx2.o),
 * else 0: then every caller takes its portable variant, which gives the same bytes (the tests
 * compare the two builds on x86), and only x86's builtins are left out of the compilation. */
#ifndef TC_CORE_CPU_H
#define TC_CORE_CPU_H

#if defined(__x86_64__) || defined(__i386__)
#define TC__X86 1
#else
#define TC__X86 0
#endif

/* AVX2 (ct_span.c's and ct_points.c's lanes). */
static inline int tc__cpu_avx2(void) {
#if TC__X86
    return __builtin_cpu_supports("avx2");
#else
    return 0;
#endif
}

/* AVX2 and FMA (raster_cover_avx2.o, whose fast form fuses multiply-adds). */
static inline int tc__cpu_avx2_fma(void) {
#if TC__X86
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
    return 0;
#endif
}

#endif
