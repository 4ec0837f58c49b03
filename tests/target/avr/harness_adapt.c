/* Co-simulation harness of the adaptation's modules on a 16-bit-int CPU: the
 * standstill lock-in (standstill_z), the Tr tracker (tr_track), the small-
 * angle sin/cos step (angle_sincos_step) and the observer's DC re-seat
 * (flux_obs_set_rs_dc), each driven by integer-generated inputs, built for
 * the host and for the AVR from the same sources; every output printed
 * must be bit-identical (category S).  The init functions use float
 * (category I: reported apart, as harness_drive.c). */
#include <stdint.h>

#include "angle.h"
#include "base_values.h"
#include "cosim_io.h"
#include "flux_obs.h"
#include "standstill_z.h"
#include "tr_track.h"

#if MATH_TYPE != IQ_MATH
#error "the co-simulation compares the fixed-point build"
#endif

static uint16_t s_rng = 0x4A3Bu;
static uint16_t rng16(void)
{
    s_rng ^= (uint16_t)(s_rng << 7);
    s_rng ^= (uint16_t)(s_rng >> 9);
    s_rng ^= (uint16_t)(s_rng << 8);
    return s_rng;
}

/* A pseudo-random Q24 value in [-2^(b-1), 2^(b-1)) LSB. */
static _iq noise(uint16_t bits)
{
    int32_t r = (int32_t)(((uint32_t)rng16() << 16) | rng16());
    return (_iq)(r / ((int32_t)1 << (31 - bits)));
}

static void run_standstill_z(void)
{
    standstill_z_t z;
    int32_t v[4];
    uint16_t k;
    _iq i_prev = _IQ(0.33);
    v[0] = (int32_t)standstill_z_init(&z, 1.0f / 15000.0f, 50.0f, 200.0f, 8u, 0.05f, 0.001f);
    cosim_print('I', 0u, v, 1u);
    standstill_z_start(&z);
    for (k = 0u; k < standstill_z_samples(&z); k++) {
        /* an R-L branch driven by the injection: i follows i_add with a lag
         * of one sample, u = R i + L di/dt (pu), plus a few LSB of noise */
        _iq i = _IQ(0.33) + z.i_add + noise(6);
        z.i_m = i;
        z.u_m = _IQmpy(_IQ(0.6), i) + _IQmpy(_IQ(3.5), i - i_prev) * 4 + noise(8);
        i_prev = i;
        standstill_z_step(&z);
    }
    standstill_z_finish(&z);   /* the result from the sums (the drive's background) */
    v[0] = (int32_t)z.done | ((int32_t)z.valid << 16);
    v[1] = (int32_t)z.x;
    v[2] = (int32_t)z.r;
    v[3] = (int32_t)z.sigma_ls;
    cosim_print('S', 1u, v, 4u);
}

static void run_tr_track(void)
{
    tr_track_t t;
    int32_t v[4];
    uint16_t k;
    v[0] = (int32_t)tr_track_init(&t, 1.0f / 15000.0f, 15u, 10.0f, 0.2f, 0.01f, 0.04f, 0.64f,
                                  0.2f);
    cosim_print('I', 2u, v, 1u);
    t.enable = 1u;
    for (k = 0u; k < 6000u; k++) {
        /* flux on alpha, i_T stepping between two levels, slip = 0.16 i_T / i_M */
        _iq it = ((k / 500u) & 1u) ? _IQ(0.3) : _IQ(0.12);
        t.psi_alpha = _IQ(0.8) + noise(10);
        t.psi_beta = noise(10);
        t.i_alpha = _IQ(0.33) + noise(12);
        t.i_beta = it + noise(12);
        t.w_sl = _IQmpy(_IQ(0.4848), it) + noise(14);   /* 0.16 / 0.33 */
        tr_track_step(&t);
        if ((k % 500u) == 499u) {
            v[0] = (int32_t)t.theta;
            v[1] = (int32_t)t.p;
            v[2] = (int32_t)t.n_updates;
            v[3] = (int32_t)t.sat_count;
            cosim_print('S', (uint16_t)(100u + k / 500u), v, 4u);
        }
    }
}

static void run_angle_step(void)
{
    int32_t v[4];
    uint16_t k;
    for (k = 0u; k < 64u; k++) {
        _iq a = (_iq)((int32_t)k * 262144);          /* k / 64 rev */
        _iq d = noise(20);                           /* |d| < 2^19 LSB = 0.031 rev */
        _iq s, c, s2, c2;
        angle_sincos(a, &s, &c);
        angle_sincos_step(s, c, a, d, &s2, &c2);
        v[0] = (int32_t)s2;
        v[1] = (int32_t)c2;
        angle_sincos_step(s, c, a, (k & 1u) ? _IQ(0.2) : -_IQ(0.2), &s2, &c2);   /* fallback */
        v[2] = (int32_t)s2;
        v[3] = (int32_t)c2;
        cosim_print('S', (uint16_t)(200u + k), v, 4u);
    }
}

static void run_flux_obs_reseat(void)
{
    base_values_t b;
    flux_obs_t o;
    int32_t v[4];
    uint16_t k;
    v[0] = (int32_t)base_values_init(&b, 20.0f, 34.64f, 50.0f, 2u, 1.0f / 15000.0f);
    v[1] = (int32_t)flux_obs_init(&o, &b, 1.3f, 0.0092f, 0.0092f, 0.0064f, 0.0198f, 3.0f,
                                  200.0f);
    cosim_print('I', 3u, v, 2u);
    for (k = 0u; k < 3000u; k++) {
        o.i_alpha = _IQ(0.33) + noise(10);
        o.i_beta = noise(10);
        o.u_alpha = _IQ(0.196) + noise(10);
        o.u_beta = noise(10);
        o.theta_r = _IQ(0.0);
        flux_obs_step(&o);
    }
    v[0] = (int32_t)flux_obs_set_rs_dc(&o, _IQ(0.595), _IQ(0.196), _IQ(0.0), _IQ(0.33),
                                       _IQ(0.0));
    v[1] = (int32_t)o.psis_alpha;
    v[2] = (int32_t)o.y_alpha;
    v[3] = (int32_t)o.theta;
    cosim_print('S', 300u, v, 4u);
    for (k = 0u; k < 1000u; k++) {
        o.u_alpha = _IQ(0.196) + noise(10);
        flux_obs_step(&o);
    }
    v[0] = (int32_t)o.psi_alpha;
    v[1] = (int32_t)o.psi_beta;
    v[2] = (int32_t)o.z_alpha;
    v[3] = (int32_t)o.ws_f;
    cosim_print('S', 301u, v, 4u);
}

int main(void)
{
    cosim_io_init();
    run_standstill_z();
    run_tr_track();
    run_angle_step();
    run_flux_obs_reseat();
    cosim_io_end();
    return 0;
}
