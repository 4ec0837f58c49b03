/* Co-simulation harness: a fixed input sequence through the chain of the
 * real FOC modules (clarke -> park -> PI d/q -> ipark -> svgen, the angle
 * from _IQsinPU/_IQcosPU), built for the host and for the AVR (16-bit int)
 * from the same sources; tools/target/avr_cosim.py compares the output.
 *
 * Only dyadic constants (k / 2^n) are used here, so that _IQ() of them is
 * exact whatever the width of double; the inputs are generated with integer
 * arithmetic only.  IQ_MATH only: the values are printed as their Q24 raw
 * integers. */
#include <stdint.h>

#include "IQmathLib.h"
#include "clarke.h"
#include "cosim_io.h"
#include "ipark.h"
#include "park.h"
#include "pi_ctrl.h"
#include "svgen.h"

#if MATH_TYPE != IQ_MATH
#error "the co-simulation compares the fixed-point build"
#endif

#define STEPS 1500u

/* xorshift16: integer noise identical on every target */
static uint16_t s_rng = 0xACE1u;
static uint16_t rng16(void)
{
    s_rng ^= (uint16_t)(s_rng << 7);
    s_rng ^= (uint16_t)(s_rng >> 9);
    s_rng ^= (uint16_t)(s_rng << 8);
    return s_rng;
}

int main(void)
{
    clarke_t cl;
    park_t pk;
    ipark_t ip;
    pi_ctrl_t pid, piq;
    svgen_t sv;
    int32_t v[8];
    uint16_t n;
    _iq angle = _IQ(0.0);
    const _iq dangle = _IQ(0.0009765625);     /* 2^-10 rev per step */

    cosim_io_init();
    clarke_init(&cl);
    park_init(&pk);
    ipark_init(&ip);
    v[0] = (int32_t)pi_init(&pid, 0.5f, 0.0625f, -1.0f, 1.0f);
    v[1] = (int32_t)pi_init(&piq, 2.0f, 0.125f, -1.0f, 1.0f);
    v[2] = (int32_t)svgen_init(&sv, 5000u);
    cosim_print('I', 0u, v, 3u);
    /* the init constants (float arithmetic in *_init): compared separately */
    v[0] = (int32_t)pid.kp; v[1] = (int32_t)pid.ki; v[2] = (int32_t)pid.e_max;
    v[3] = (int32_t)piq.kp; v[4] = (int32_t)piq.ki; v[5] = (int32_t)piq.e_max;
    v[6] = (int32_t)sv.vdc_min; v[7] = (int32_t)sv.t1pr_x2;
    cosim_print('I', 1u, v, 8u);

    pid.ref = _IQ(0.25);
    for (n = 0u; n < STEPS; n++) {
        _iq s = _IQsinPU(angle);
        _iq c = _IQcosPU(angle);
        /* phase currents: 0.5 pu, b lagging by 682/1024 rev (~240 deg), plus
         * +-2^-10 pu integer noise */
        _iq noise_a = _IQmpyI32(_IQ(0.00000762939453125), (int32_t)(rng16() >> 8) - 128);
        _iq noise_b = _IQmpyI32(_IQ(0.00000762939453125), (int32_t)(rng16() >> 8) - 128);
        cl.as = _IQmpy(_IQ(0.5), s) + noise_a;
        cl.bs = _IQmpy(_IQ(0.5), _IQsinPU(angle + _IQ(0.666015625))) + noise_b;
        clarke_step(&cl);

        pk.alpha = cl.alpha; pk.beta = cl.beta; pk.sine = s; pk.cosine = c;
        park_step(&pk);

        /* a torque-reference step at 1/3 of the run, a reversal at 2/3 */
        piq.ref = (n < STEPS / 3u) ? _IQ(0.125) : ((n < 2u * STEPS / 3u) ? _IQ(0.75) : _IQ(-0.5));
        pid.fbk = pk.ds; pid.ff = _IQ(0.0);
        piq.fbk = pk.qs; piq.ff = _IQ(0.0);
        pi_step(&pid);
        pi_step(&piq);

        ip.ds = pid.out; ip.qs = piq.out; ip.sine = s; ip.cosine = c;
        ipark_step(&ip);

        sv.ualpha = ip.alpha; sv.ubeta = ip.beta;
        sv.vdc = _IQ(1.75) + _IQmpyI32(_IQ(0.0001220703125), (int32_t)(rng16() >> 10) - 32);
        svgen_step(&sv);

        v[0] = (int32_t)cl.alpha; v[1] = (int32_t)cl.beta;
        v[2] = (int32_t)pk.ds;    v[3] = (int32_t)pk.qs;
        v[4] = (int32_t)pid.out;  v[5] = (int32_t)piq.out;
        v[6] = (int32_t)sv.cmpr[0] | ((int32_t)sv.cmpr[1] << 16);
        v[7] = (int32_t)sv.cmpr[2] | ((int32_t)(sv.overmod | (uint16_t)(pid.sat << 1) | (uint16_t)(piq.sat << 2)) << 16);
        cosim_print('S', n, v, 8u);

        angle += dangle;
        if (angle >= _IQ(1.0)) {
            angle -= _IQ(1.0);
        }
    }
    cosim_io_end();
    return 0;
}
