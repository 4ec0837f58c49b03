/* Per-unit angle helpers.  See angle.h. */
#include "angle.h"

_iq angle_wrap_pu(_iq angle_pu)
{
    /* _IQfrac keeps the sign of its argument (TI: A - integer part, the
     * integer part truncated toward zero), so negative angles come out in
     * (-1, 0] and need one revolution added. */
    _iq f = _IQfrac(angle_pu);
    if (f < _IQ(0.0)) {
        f += _IQ(1.0);
    }
    /* Only reachable in FLOAT_MATH: -1e-9 + 1.0f rounds to 1.0f. */
    if (f >= _IQ(1.0)) {
        f = _IQ(0.0);
    }
    return f;
}

void angle_sincos(_iq angle_pu, _iq *s, _iq *c)
{
    const _iq a = angle_wrap_pu(angle_pu);
    *s = _IQsinPU(a);
    *c = _IQcosPU(a);
}

_iq angle_diff_pu(_iq b, _iq a)
{
    _iq d = b - a;   /* both in [0, 1): the raw difference is in (-1, 1), no overflow */

    if (d >= _IQ(0.5)) {
        d -= _IQ(1.0);
    } else if (d < _IQ(-0.5)) {
        d += _IQ(1.0);
    }
    return d;
}

void angle_sincos_step(_iq s, _iq c, _iq a_pu, _iq d_pu, _iq *s2, _iq *c2)
{
    _iq x;
    _iq x2;
    _iq cx;
    _iq sx;

    if (d_pu > _IQ(ANGLE_STEP_MAX_PU) || d_pu < -_IQ(ANGLE_STEP_MAX_PU)) {
        angle_sincos(a_pu + d_pu, s2, c2);   /* |a| < 1, |d| < 1: no overflow */
        return;
    }
    x = _IQmpy(d_pu, _IQ(6.28318530717958647692));      /* rad, |x| <= 0.197 */
    x2 = _IQmpy(x, x);                                    /* <= 0.039 */
    /* Horner; every factor in (0.99, 1]: no overflow, < 1 LSB each */
    cx = _IQ(1.0) - _IQmpy(_IQmpy(x2, _IQ(0.5)), _IQ(1.0) - _IQmpy(x2, _IQ(1.0 / 12.0)));
    sx = _IQmpy(x, _IQ(1.0) - _IQmpy(_IQmpy(x2, _IQ(1.0 / 6.0)),
                                      _IQ(1.0) - _IQmpy(x2, _IQ(0.05))));
    /* |s|, |c| <= 1.01: each sum <= 1.01 (|cx| + |sx|) < 1.3 */
    *s2 = _IQmpy(s, cx) + _IQmpy(c, sx);
    *c2 = _IQmpy(c, cx) - _IQmpy(s, sx);
}
