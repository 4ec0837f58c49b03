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

