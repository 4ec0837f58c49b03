/* The RLS covariance for the background.  See rls_cov.h. */
#include "rls_cov.h"

/* rls_t keeps the upper triangle of Pn, row by row (rls.c) */
static const uint16_t k_ix[RLS_N][RLS_N] = {
    {0u, 1u, 2u, 3u}, {1u, 4u, 5u, 6u}, {2u, 5u, 7u, 8u}, {3u, 6u, 8u, 9u}};

void rls_cov_save(rls_cov_t *c, const rls_t *r)
{
    uint16_t i, j;
    for (i = 0u; i < RLS_N; i++) {
        for (j = 0u; j < RLS_N; j++) {
            c->Pn[i][j] = r->Pn[k_ix[i][j]];
        }
        c->Pe[i] = r->Pe[i];
    }
    c->w = r->w;
}

void rls_cov_factor(const rls_cov_t *c, _iq30 sd_m[RLS_N], int16_t sd_e[RLS_N],
                    _iq30 rho[RLS_N][RLS_N])
{
    uint16_t i, j;
    /* 0.5 / sqrt(w): w in [0.25, 1] (rls.h), sqrt(w) in [0.5, 1] */
    const _iq30 w = (c->w >= _IQ30(0.25) && c->w <= _IQ30(1.0)) ? c->w : _IQ30(1.0);
    const _iq30 w_fac = _IQ30div(_IQ30(0.5), _IQ30sqrt(w));
    for (i = 0u; i < RLS_N; i++) {
        _iq30 d = c->Pn[i][i];
        /* the band [0.25, 1) holds while P is positive definite (rls.h) */
        sd_m[i] = (d >= _IQ30(0.25) && d < _IQ30(1.0)) ? _IQ30sqrt(d) : _IQ30(0.0);
    }
    for (i = 0u; i < RLS_N; i++) {
        for (j = 0u; j < RLS_N; j++) {
            _iq30 den = _IQ30mpy(sd_m[i], sd_m[j]);   /* [0.25, 1) or 0 */
            _iq30 r;
            if (i == j) {
                r = (sd_m[i] != _IQ30(0.0)) ? _IQ30(1.0) : _IQ30(0.0);
            } else if (den == _IQ30(0.0)) {
                r = _IQ30(0.0);
            } else {
                /* |Pn_ij| <= den up to rounding: the quotient stays below 2 */
                _iq30 n = c->Pn[i][j];
                if (_IQabs(n) >= den) {
                    r = (n > 0) ? _IQ30(1.0) : -_IQ30(1.0);
                } else {
                    r = _IQ30div(n, den);
                }
            }
            rho[i][j] = r;
        }
    }
    /* w cancels in rho; the deviations: P_ii = 4^Pe_i Pn_ii / w, so sd =
     * sqrt(Pn_ii) (0.5 / sqrt(w)) 2^(Pe_i + 1), the factor in [0.5, 1]
     * (Q30 * Q30 -> Q30: sd_m in [0.25, 1)) */
    for (i = 0u; i < RLS_N; i++) {
        sd_m[i] = _IQ30mpy(sd_m[i], w_fac);
        sd_e[i] = (int16_t)(c->Pe[i] + 1);
    }
}
