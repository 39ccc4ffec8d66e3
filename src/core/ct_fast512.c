/* ct_fast512.c — the fast cubic (ct_fast.h) of a run of pixels, eight at a time with AVX-512,
 * stored as the tile stores it; the same bits as tc__ct_fast_lanes gives each pixel alone.
 *
 * Why a file of its own: AVX-512's comparisons give bit masks, not lanes of ones, and GCC's
 * vector extensions turn those back into lanes through scalar moves; written with the
 * intrinsics, in a function of its own target, the masks stay masks. The operations per lane
 * are tc__ct_fast_lanes's, in its order, none fused (-std=c11: no contraction), so a pixel's
 * value does not depend on which path or lane computed it. */
#include "core/ct_fast.h"

#include <float.h>

#include "core/alloc.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

#define TC__AVX512 __attribute__((target("avx512f,avx512dq,avx512vl")))

int tc__ct_fast_run8_ok(void) {
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
           __builtin_cpu_supports("avx512vl");
}

/* Values at the eight centres x (lanes in `live` only are stored) into out, nc floats a pixel. */
TC__AVX512 static void group8(const tc__ct_fast *ff, const double R[3], __m512d x, __mmask8 live,
                              const uint8_t *floor0, float *out) {
    __m512d zero = _mm512_setzero_pd(), t = _mm512_sub_pd(x, _mm512_set1_pd(ff->x0));
    __m512d d01 = _mm512_add_pd(_mm512_set1_pd(R[0]), _mm512_mul_pd(_mm512_set1_pd(ff->gx[0]), t));
    __m512d d02 = _mm512_add_pd(_mm512_set1_pd(R[1]), _mm512_mul_pd(_mm512_set1_pd(ff->gx[1]), t));
    __m512d d12 = _mm512_add_pd(_mm512_set1_pd(R[2]), _mm512_mul_pd(_mm512_set1_pd(ff->gx[2]), t));
    /* tc__ct_eval's choice: sub = l0 <= l1 ? (l0 <= l2 ? 0 : 2) : (l1 <= l2 ? 1 : 2) */
    __mmask8 m01 = _mm512_cmp_pd_mask(d01, zero, _CMP_LE_OQ), m02 = _mm512_cmp_pd_mask(d02, zero, _CMP_LE_OQ);
    __mmask8 m12 = _mm512_cmp_pd_mask(d12, zero, _CMP_LE_OQ);
    __mmask8 is0 = m01 & m02, is1 = (__mmask8)(~m01 & m12);
    /* (a, b): subtriangle 0 reads (D01, D02), 1 (D12, D01), 2 (D02, D12) */
    __m512d a = _mm512_mask_blend_pd(is0, _mm512_mask_blend_pd(is1, d02, d12), d01);
    __m512d b = _mm512_mask_blend_pd(is0, _mm512_mask_blend_pd(is1, d12, d01), d02);
    int s = is0 == 0xff ? 0 : is1 == 0xff ? 1 : (is0 | is1) == 0 ? 2 : -1;
    __m512i sub = _mm512_mask_blend_epi64(is0, _mm512_mask_blend_epi64(is1, _mm512_set1_epi64(2), _mm512_set1_epi64(1)),
                                          _mm512_setzero_si512());
    __m256 big = _mm256_set1_ps(FLT_MAX), nbig = _mm256_set1_ps(-FLT_MAX);
    for (int ch = 0; ch < ff->nc; ch++) {
        __m512d h[TC__NH];
        for (int k = 0; k < TC__NH; k++) {
            const double *hk = (const double *)&ff->h[ch][k];
            /* one subtriangle for all eight: its coefficient; else each lane's own, moved into place */
            h[k] = s >= 0 ? _mm512_set1_pd(hk[s]) : _mm512_permutexvar_pd(sub, _mm512_broadcast_f64x4(_mm256_loadu_pd(hk)));
        }
        /* tc__ct_fast_horner, operation for operation */
        __m512d pa = _mm512_add_pd(h[TC__H10], _mm512_mul_pd(a, _mm512_add_pd(h[TC__H20], _mm512_mul_pd(a, h[TC__H30]))));
        __m512d pb = _mm512_add_pd(h[TC__H01], _mm512_mul_pd(b, _mm512_add_pd(h[TC__H02], _mm512_mul_pd(b, h[TC__H03]))));
        __m512d pab = _mm512_add_pd(_mm512_add_pd(h[TC__H11], _mm512_mul_pd(a, h[TC__H21])), _mm512_mul_pd(b, h[TC__H12]));
        __m512d v = _mm512_add_pd(_mm512_add_pd(h[TC__H00], _mm512_mul_pd(a, pa)),
                                  _mm512_mul_pd(b, _mm512_add_pd(pb, _mm512_mul_pd(a, pab))));
        /* as raster.c's store_lanes: max(c, f) and min(c, f) let a NaN through; -0 kept */
        __m256 f = _mm256_min_ps(big, _mm256_max_ps(nbig, _mm512_cvtpd_ps(v)));
        if (floor0[ch]) f = _mm256_max_ps(_mm256_setzero_ps(), f);
        if (ff->nc == 1) {
            _mm256_mask_storeu_ps(out, live, f);
            continue;
        }
        float lane[8];
        _mm256_storeu_ps(lane, f);
        for (int l = 0; l < 8; l++)
            if (live >> l & 1u) out[tc__ix(l, ff->nc, ch)] = lane[l];
    }
}

TC__AVX512 void tc__ct_fast_run8(const tc__ct_fast *ff, const double R[3], const double *xs, int32_t n,
                                 const uint8_t *floor0, float *out) {
    int32_t i = 0;
    for (; i + 8 <= n; i += 8) group8(ff, R, _mm512_loadu_pd(xs + i), 0xff, floor0, out + tc__ix(i, ff->nc, 0));
    if (i < n) {
        /* the lanes past the run repeat its last centre: they never make it straddle an edge */
        __mmask8 live = (__mmask8)((1u << (n - i)) - 1);
        __m512d x = _mm512_mask_loadu_pd(_mm512_set1_pd(xs[n - 1]), live, xs + i);
        group8(ff, R, x, live, floor0, out + tc__ix(i, ff->nc, 0));
    }
}

#else

int tc__ct_fast_run8_ok(void) {
    return 0;
}

void tc__ct_fast_run8(const tc__ct_fast *ff, const double R[3], const double *xs, int32_t n, const uint8_t *floor0,
                      float *out) {
    (void)ff, (void)R, (void)xs, (void)n, (void)floor0, (void)out;
}

#endif
