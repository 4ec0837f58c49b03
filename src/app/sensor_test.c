/* The current sensors' pulse test at standstill.  See sensor_test.h. */
#include "sensor_test.h"

#include <math.h>
#include <string.h>

#define ONE_OVER_SQRT3 0.57735026918962576451f
#define HALF_SQRT3 0.86602540378443864676f

/* The unit vector of phase a, b or c in alpha-beta (amplitude-invariant
 * Clarke), Q24 constants (no float at run time). */
static inline void phase_unit(uint16_t v, _iq *c, _iq *s)
{
    if (v == 0u) {
        *c = _IQ(1.0);
        *s = _IQ(0.0);
    } else if (v == 1u) {
        *c = _IQ(-0.5);
        *s = _IQ(HALF_SQRT3);
    } else {
        *c = _IQ(-0.5);
        *s = _IQ(-HALF_SQRT3);
    }
}

sensor_test_status_t sensor_test_init(sensor_test_t *t, float Ts_s, float sigma_ls_H,
                                      float v_base_V, float i_base_A, float vdc_V,
                                      float d_target_A, float tol_abs, float tol_dir)
{
    float u_max, n, u, d;
    memset(t, 0, sizeof *t);
    t->state = SENSOR_TEST_FAILED;
    if (!(Ts_s > 0.0f) || !(sigma_ls_H > 0.0f) || !(v_base_V > 0.0f) ||
        !(i_base_A > 0.0f) || !(vdc_V > 0.0f) || !(d_target_A > 0.0f) ||
        !(tol_abs > 0.0f) || !(tol_abs < 1.0f) || !(tol_dir > 0.0f) || !(tol_dir < 1.0f)) {
        return SENSOR_TEST_ERR_ARG;
    }
    /* a vector along a phase is at most (2/3) vdc long; keep 20 % for the
     * dead time and the bus ripple */
    u_max = 0.8f * (2.0f / 3.0f) * vdc_V;
    n = ceilf(d_target_A * sigma_ls_H / (u_max * Ts_s));
    if (n < 1.0f) {
        n = 1.0f;
    }
    if (n > (float)SENSOR_TEST_N_MAX) {
        n = (float)SENSOR_TEST_N_MAX;
        u = u_max;
    } else {
        u = d_target_A * sigma_ls_H / (n * Ts_s);
    }
    d = u * n * Ts_s / sigma_ls_H;   /* d_target_A, or less at N_MAX */
    if (!(d > 0.0f) || !(3.0f * d / i_base_A < 4.0f) || !(u / v_base_V < 2.0f)) {
        return SENSOR_TEST_ERR_ARG;
    }
    t->n = (uint16_t)n;
    t->z = 4u;
    t->u = _IQ(u / v_base_V);
    t->s_exp = _IQ(2.0f * d / i_base_A);
    t->tol_abs = _IQ(tol_abs);
    t->tol_dir = _IQ(tol_dir);
    t->i_abort = _IQ(3.0f * d / i_base_A);
    t->state = SENSOR_TEST_IDLE;
    return SENSOR_TEST_OK;
}

/* Vector v's response: par and perp of S (pu); both < 32. */
static void judge(sensor_test_t *t, uint16_t v)
{
    const _iq sa = t->sa[v];
    const _iq sb = t->sb[v];
    /* Clarke: alpha = a, beta = (a + 2 b) / sqrt(3); |sa + 2 sb| <= 48 */
    const _iq s_al = sa;
    const _iq s_be = _IQmpy(sa + sb + sb, _IQ(ONE_OVER_SQRT3));
    _iq c, s, par, perp, dev;
    phase_unit(v, &c, &s);
    par = _IQmpy(s_al, c) + _IQmpy(s_be, s);
    perp = _IQmpy(s_be, c) - _IQmpy(s_al, s);
    dev = par - t->s_exp;
    t->par[v] = par;
    t->perp[v] = perp;
    if (!(par > 0) || _IQabs(perp) > _IQmpy(t->tol_dir, par)) {
        t->judge_bits |= (uint16_t)(SENSOR_TEST_DIR_A << v);
    }
    if (_IQabs(dev) > _IQmpy(t->tol_abs, t->s_exp)) {
        t->judge_bits |= (uint16_t)(SENSOR_TEST_SIZE_A << v);
    }
}

void sensor_test_judge(sensor_test_t *t)
{
    uint16_t v;
    for (v = 0u; v < 3u; v++) {
        if (t->judge_due[v] != 0u) {
            judge(t, v);
            t->judge_due[v] = 0u;   /* last: the bits are written */
        }
    }
}

void sensor_test_step(sensor_test_t *t)
{
    /* no clamp needed: a current is used only after the limit check below
     * (|.| <= i_abort < 4 pu), which compares without _IQabs (no overflow
     * at the Q24 range's end) */
    const _iq ia = t->ia, ib = t->ib;
    const uint16_t n = t->n;
    uint16_t j;

    t->u_alpha = _IQ(0.0);
    t->u_beta = _IQ(0.0);
    t->off = 0u;
    if (t->armed == 0u) {
        /* re-armed for the next run (an init error stays FAILED); the last
         * run's verdict stays readable until the next one starts */
        t->state = (t->n != 0u) ? SENSOR_TEST_IDLE : SENSOR_TEST_FAILED;
        return;
    }
    if (t->state == SENSOR_TEST_IDLE && t->run != 0u) {
        t->state = SENSOR_TEST_RUNNING;
        t->vec = 0u;
        t->j = 0u;
        t->fail_bits = 0u;
        t->judge_bits = 0u;
        t->judge_due[0] = t->judge_due[1] = t->judge_due[2] = 0u;
    }
    if (t->state == SENSOR_TEST_JUDGING && sensor_test_judge_due(t) == 0u) {
        /* every vector judged (judge_bits written before the last flag fell) */
        t->fail_bits |= t->judge_bits;
        t->state = (t->fail_bits != 0u) ? SENSOR_TEST_FAILED : SENSOR_TEST_PASSED;
    }
    if (t->state != SENSOR_TEST_RUNNING) {
        return;   /* idle, passed or failed: the zero vector (the drive may switch off) */
    }
    if (ia > t->i_abort || ia < -t->i_abort || ib > t->i_abort || ib < -t->i_abort) {
        t->fail_bits |= SENSOR_TEST_LIMIT;
        t->state = SENSOR_TEST_FAILED;
        return;
    }
    j = t->j;
    /* samples: start of + at j = 1, its end at j = n + 1, the end of - at
     * j = 2n + 1 (the voltage of ISR j acts over period j + 1) */
    if (j == 1u) {
        t->i0a = ia;
        t->i0b = ib;
    } else if (j == n + 1u) {
        t->i1a = ia;
        t->i1b = ib;
    } else if (j == 2u * n + 1u) {
        /* the vector's response, judged at the slow rate: S first, then
         * its flag */
        t->sa[t->vec] = (t->i1a - t->i0a) - (ia - t->i1a);
        t->sb[t->vec] = (t->i1b - t->i0b) - (ib - t->i1b);
        t->judge_due[t->vec] = 1u;
    } else {
        /* between samples */
    }
    if (j < 2u * n) {
        const _iq u = (j < n) ? t->u : -t->u;
        _iq c, s;
        phase_unit(t->vec, &c, &s);
        t->u_alpha = _IQmpy(u, c);
        t->u_beta = _IQmpy(u, s);
    } else if (j > 2u * n) {
        /* the current freewheels to zero before the next vector.  (Not at
         * j = 2n: turning the outputs off acts at once, on the period under
         * way, which is the - half's last; the voltage asked there is for
         * a period that will be off anyway.) */
        t->off = 1u;
    } else {
        /* j = 2n: zero */
    }
    t->j = (uint16_t)(j + 1u);
    if (t->j >= 2u * n + t->z) {
        t->j = 0u;
        t->vec++;
        if (t->vec >= 3u) {
            t->state = SENSOR_TEST_JUDGING;   /* the verdict when every vector is judged */
        }
    }
}
