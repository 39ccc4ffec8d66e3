/* ct_lanes.h — tc__ct_eval_sub's difference-form cubic four lanes at a time, the one copy that
 * ct_span.c (pixels of a row) and ct_points.c (scattered points) both perform bit for bit. */
#ifndef TC_CORE_CT_LANES_H
#define TC_CORE_CT_LANES_H

#include "core/vec4.h"

/* g: each lane's ten ordinates of its subtriangle (tc__ct_sub's order: b300 b030 b003 b210
 * b120 b201 b021 b102 b012 b111); r0 / r1: the lanes whose reference ordinate is b300 / b030
 * (else b003); A, B, C as in tc__ct_eval_sub. The value, and in q the quadratics qa, qb, qc
 * the gradient needs — the scalar path's operations, in its order. */
TC__V4_INLINE tc__v4d tc__ct_lanes_cubic(const tc__v4d g[10], tc__v4i r0, tc__v4i r1, tc__v4d A, tc__v4d B, tc__v4d C,
                                         tc__v4d q[3]) {
    tc__v4d ref = tc__sel(r0, g[0], tc__sel(r1, g[1], g[2]));
    tc__v4d b300 = g[0] - ref, b030 = g[1] - ref, b003 = g[2] - ref, b210 = g[3] - ref;
    tc__v4d b120 = g[4] - ref, b201 = g[5] - ref, b021 = g[6] - ref, b102 = g[7] - ref;
    tc__v4d b012 = g[8] - ref, b111 = g[9] - ref;
    q[0] = A * A * b300 + B * B * b120 + C * C * b102 + 2 * (A * B * b210 + A * C * b201 + B * C * b111);
    q[1] = A * A * b210 + B * B * b030 + C * C * b012 + 2 * (A * B * b120 + A * C * b111 + B * C * b021);
    q[2] = A * A * b201 + B * B * b021 + C * C * b003 + 2 * (A * B * b111 + A * C * b102 + B * C * b012);
    return ref + (A * q[0] + B * q[1] + C * q[2]);
}

#endif
