/* Space-vector PWM by min-max zero-sequence injection.  See svgen.h. */
#include "svgen.h"
#include "foc_const.h"

#include <string.h>

/* CMPR = T1PR - round(d T1PR), d in [0, 1] (Q24).
 * round(d N) = floor(d N + 1/2) = floor((floor(2 d N) + 1) / 2), because
 * floor(y/2) = floor(floor(y)/2) for any real y; floor(2 d N) is the
 * integer part of an IQ times an integer (_IQmpyI32int), in [0, 2N]. */
static uint16_t svgen_compare(const svgen_t *s, _iq d)
{
    const int32_t twice = (int32_t)_IQmpyI32int(d, s->t1pr_x2);   /* [0, 2 T1PR] */
    const int32_t on = (twice + 1) / 2;                            /* [0, T1PR] */
    return (uint16_t)((int32_t)s->t1pr - on);
}

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

void svgen_step(svgen_t *s)
{
    _iq va, vb, vc, vmax, vmin, span, div, inv, mid;

    if (!(s->vdc >= s->vdc_min)) {
        /* Bus fault: zero line-to-line voltage rather than a division by a
         * vanishing bus. */
        s->da = _IQ(0.5);
        s->db = _IQ(0.5);
        s->dc = _IQ(0.5);
        s->overmod = 0u;
        s->vdc_fault = 1u;
    } else {
        /* Phase references (inverse Clarke).  Q24*Q24 and Q24*Q30 -> Q24,
         * truncated; |.| <= 16 + 27.7 = 43.7 for |u| <= 32.  An error of an
         * LSB common to all three phases cancels in the zero sequence. */
        const _iq half = _IQmpy(s->ualpha, _IQ(0.5));
        const _iq sb = _IQmpyIQX(s->ubeta, GLOBAL_Q, FOC_SQRT3_BY_TWO_Q30, 30);
        va = s->ualpha;
        vb = sb - half;
        vc = _IQ(0.0) - sb - half;

        vmax = (va > vb) ? va : vb;
        vmax = (vc > vmax) ? vc : vmax;
        vmin = (va < vb) ? va : vb;
        vmin = (vc < vmin) ? vc : vmin;
        span = vmax - vmin;              /* >= 0, <= 87.4 */
        /* Mid-point of the references: -v0.  Q24, |.| <= 43.7 */
        mid = _IQmpy(vmax + vmin, _IQ(0.5));

        /* Divisor max(vdc, span): the bus in the linear range, the span
         * (scaling the vector onto the hexagon, angle kept) beyond it. */
        if (span > s->vdc) {
            div = span;
            s->overmod = 1u;
        } else {
            div = s->vdc;
            s->overmod = 0u;
        }
        s->vdc_fault = 0u;
        /* 1/div, Q24, <= 1/0.05 = 20; 1/vdc only when vdc changed */
        if (s->overmod != 0u) {
            inv = _IQdiv(_IQ(1.0), div);
        } else {
            if (s->vdc != s->vdc_seen) {
                s->inv_vdc = _IQdiv(_IQ(1.0), s->vdc);
                s->vdc_seen = s->vdc;
            }
            inv = s->inv_vdc;
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
