/* The RLS covariance for the background.  See rls_cov.h. */
#include "rls_cov.h"

void rls_cov_save(rls_cov_t *c, const rls_t *r)
{
    uint16_t i, j;
    for (i = 0u; i < RLS_N; i++) {
        for (j = 0u; j < RLS_N; j++) {
            c->Pn[i][j] = r->Pn[i][j];
        }
        c->Pe[i] = r->Pe[i];
    }
}

void rls_cov_factor(const rls_cov_t *c, _iq30 sd_m[RLS_N], int16_t sd_e[RLS_N],
                    _iq30 rho[RLS_N][RLS_N])
{
    uint16_t i, j;
    for (i = 0u; i < RLS_N; i++) {
        _iq30 d = c->Pn[i][i];
        /* the band [0.25, 1) holds while P is positive definite (rls.h) */
        sd_m[i] = (d >= _IQ30(0.25) && d < _IQ30(1.0)) ? _IQ30sqrt(d) : _IQ30(0.0);
        sd_e[i] = c->Pe[i];
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
}
