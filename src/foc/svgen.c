/* Space-vector PWM by min-max zero-sequence injection.  See svgen.h. */
#include "svgen.h"
#include "foc_const.h"

#include <string.h>

svgen_status_t svgen_init(svgen_t *s, uint16_t t1pr)
{
    memset(s, 0, sizeof *s);
    if (t1pr == 0u) {
        return SVGEN_ERR_PERIOD;
    }
    s->t1pr = t1pr;
    s->t1pr_x2 = 2 * (int32_t)t1pr;
    s->vdc_min = _IQ(SVGEN_VDC_MIN_PU);
    s->da = _IQ(0.5);
    s->db = _IQ(0.5);
    s->dc = _IQ(0.5);
    s->cmpr[0] = svgen_compare(s, s->da);
    s->cmpr[1] = s->cmpr[0];
    s->cmpr[2] = s->cmpr[0];
    return SVGEN_OK;
}

/* 1/vdc (Q24 / Q24 -> Q24, vdc >= vdc_min: no saturation), divided only
 * when vdc changed since the last division: shared by svgen_set_vdc (the
 * slow task's) and svgen_step (a bus that moved since). */
static inline _iq svgen_inv_vdc(svgen_t *s, _iq vdc)
{
    if (vdc != s->vdc_seen) {
        s->inv_vdc = _IQdiv(_IQ(1.0), vdc);
        s->vdc_seen = vdc;
    }
    return s->inv_vdc;
}

void svgen_set_vdc(svgen_t *s, _iq vdc)
{
    s->vdc = vdc;
    if (vdc >= s->vdc_min) {
        (void)svgen_inv_vdc(s, vdc);
    }
}

void svgen_step(svgen_t *s)
{
    const _iq vdc = s->vdc;
    _iq va, vb, vc, vmax, vmin, span, inv, mid;

    if (!(vdc >= s->vdc_min)) {
        /* Bus fault: zero line-to-line voltage rather than a division by a
         * vanishing bus. */
        s->da = _IQ(0.5);
        s->db = _IQ(0.5);
        s->dc = _IQ(0.5);
        s->overmod = 0u;
        s->vdc_fault = 1u;
    } else {
        /* Phase references (inverse Clarke).  Q24*Q30 -> Q24, truncated,
         * and the exact-floor halving (_IQdiv2 = _IQmpy by 0.5 bit for
         * bit); |.| <= 16 + 27.7 = 43.7 for |u| <= 32.  An error of an LSB
         * common to all three phases cancels in the zero sequence. */
        const _iq ualpha = s->ualpha;
        const _iq half = _IQdiv2(ualpha);
        const _iq sb = _IQmpyIQX(s->ubeta, GLOBAL_Q, FOC_SQRT3_BY_TWO_Q30, 30);
        va = ualpha;
        vb = sb - half;
        vc = _IQ(0.0) - sb - half;

        /* largest and smallest of the three in at most three compares
         * (vc above the larger of va, vb cannot be below the smaller) */
        if (va > vb) {
            vmax = va;
            vmin = vb;
        } else {
            vmax = vb;
            vmin = va;
        }
        if (vc > vmax) {
            vmax = vc;
        } else if (vc < vmin) {
            vmin = vc;
        } else {
            /* vc between them */
        }
        span = vmax - vmin;              /* >= 0, <= 87.4 */
        /* Mid-point of the references: -v0.  Q24, |.| <= 43.7 */
        mid = _IQdiv2(vmax + vmin);

        /* Divisor max(vdc, span): the bus in the linear range, the span
         * (scaling the vector onto the hexagon, angle kept) beyond it.
         * 1/div, Q24, <= 1/0.05 = 20; 1/vdc only when vdc changed */
        s->vdc_fault = 0u;
        if (span > vdc) {
            s->overmod = 1u;
            inv = _IQdiv(_IQ(1.0), span);
        } else {
            s->overmod = 0u;
            inv = svgen_inv_vdc(s, vdc);
        }

        /* d_x = 1/2 + (v_x - mid)/div; |v_x - mid| <= span/2 <= div/2, so
         * the Q24*Q24 -> Q24 product is within [-1/2, 1/2]: no overflow.
         * The saturation only absorbs the last LSB of the reciprocal. */
        s->da = _IQsat(_IQ(0.5) + _IQmpy(va - mid, inv), _IQ(1.0), _IQ(0.0));
        s->db = _IQsat(_IQ(0.5) + _IQmpy(vb - mid, inv), _IQ(1.0), _IQ(0.0));
        s->dc = _IQsat(_IQ(0.5) + _IQmpy(vc - mid, inv), _IQ(1.0), _IQ(0.0));
    }
    s->cmpr[0] = svgen_compare(s, s->da);
    s->cmpr[1] = svgen_compare(s, s->db);
    s->cmpr[2] = svgen_compare(s, s->dc);
}
