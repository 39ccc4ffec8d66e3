/* recon.h — struct tc_recon, what every method's build (method.h's rows) fills
 * and the evaluators read. */
#ifndef TC_CORE_RECON_H
#define TC_CORE_RECON_H

#include "core/ct.h"
#include "core/deadline.h"
#include "core/method.h"

/* Invariants once tc_recon_new returns TC_OK: method is the row of opt.method;
 * ncoef, labels and eval are its; coef holds nt * nc * ncoef finite numbers of
 * magnitude <= 1e300; planes is NULL or holds 3nt * nc of them. */
struct tc_recon {
    const struct tc_mesh *m;
    tc_options opt;
    const tc__method *method;  /* the row of opt.method; ncoef, labels, eval are its */
    int ncoef;
    const char *const *labels; /* [ncoef] */
    tc__piece_eval eval;
    double *coef;              /* [nt][nc][ncoef] */
    double *planes;            /* [3nt][nc][2] each corner's (wedge's) plane, the ones the
                                * coefficients were built from, or NULL */
    /* Per channel: its data are all >= 0 and the range is restricted, so its
     * ordinates are >= 0 to within rounding (range.h); the evaluators return
     * the few values a rounding puts below 0 as 0 (never more than ~1e-12 of
     * the channel's scale: the limiter, not this, keeps the function up). */
    uint8_t floor0[TC_MAX_CHANNELS];
};

/* Past r's build deadline (opt.deadline_ms): a build checks it between its stages and
 * returns TC_ETIMEOUT, leaving what it made to tc_recon_free. */
static inline int tc__recon_late(const struct tc_recon *r) { return tc__past(r->opt.deadline_ms); }

/* Whether r is the Clough-Tocher cubic (19 ordinates per channel): what the four-lane paths
 * (tc__ct_points4, the renderer's queue and fast form) evaluate. */
static inline int tc__recon_is_ct(const struct tc_recon *r) {
    return r->eval == tc__ct_eval && r->ncoef == TC_CT_ORDINATES;
}

/* Value v of channel ch as a point or a pixel of r gets it. */
static inline double tc__floored(const struct tc_recon *r, int ch, double v) {
    TC_ASSERT(ch >= 0 && ch < r->m->nc);
    return r->floor0[ch] && v < 0 ? 0 : v;
}

#endif
