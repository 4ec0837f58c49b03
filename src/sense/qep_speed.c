/* Encoder angle and speed.  See qep_speed.h. */
#include "qep_speed.h"

#include <math.h>

#define QEP_TWO_PI 6.28318530717958647692f
/* Largest |speed_raw| allowed, pu.  63 so that speed_raw - speed (both
 * within +-63) stays inside Q24's +-128. */
#define QEP_SPEED_RAW_MAX 63.0f

/* a - b modulo 2^16, read as a signed number in [-32768, 32767].  Written
 * without the implementation-defined uint16 -> int16 conversion. */
static int32_t qep_diff(uint16_t a, uint16_t b)
{
    int32_t d = (int32_t)(uint16_t)(a - b);   /* [0, 65535] */
    if (d >= 32768) {
        d -= 65536;
    }
    return d;
}

/* p modulo n into [0, n).  The common case (|step| < n) costs two compares;
 * the division runs only after a step of more than one revolution. */
static int32_t qep_wrap(int32_t p, int32_t n)
{
    if (p >= n) {
        p -= n;
        if (p >= n) {
            p %= n;
        }
    } else if (p < 0) {
        p += n;
        if (p < 0) {
            p %= n;          /* C99: in (-n, 0] */
            if (p < 0) {
                p += n;
            }
        }
    }
    return p;
}

qep_speed_status_t qep_speed_init(qep_speed_t *q, uint16_t encoder_lines,
                                  const base_values_t *b, float speed_filter_Hz,
                                  uint16_t window)
{
    float k;
    float k1;
    float a;

    q->cpr = 4;
    q->pole_pairs = 1;
    q->window = 1u;
    q->d_max = 0;
    q->k_angle = _IQ30(0.0);
    q->k_speed = _IQ(0.0);
    q->k_filt = _IQ(0.0);
    q->d_max1 = 0;
    q->k_speed1 = _IQ(0.0);
    q->count = 0u;
    qep_speed_reset(q, 0u);

    if (b == 0 || !(b->Ts_s > 0.0f) || !(b->f_base_Hz > 0.0f) || b->pole_pairs == 0u ||
        b->pole_pairs > QEP_SPEED_POLE_PAIRS_MAX) {
        return QEP_SPEED_ERR_BASE;
    }
    if (encoder_lines == 0u || encoder_lines > QEP_SPEED_LINES_MAX) {
        return QEP_SPEED_ERR_LINES;
    }
    /* power of two: exactly one bit set */
    if (window == 0u || window > QEP_SPEED_WINDOW_MAX || (window & (window - 1u)) != 0u) {
        return QEP_SPEED_ERR_WINDOW;
    }
    q->cpr = 4 * (int32_t)encoder_lines;
    q->pole_pairs = (int32_t)b->pole_pairs;
    q->window = window;
    k = (float)b->pole_pairs /
        ((float)window * (float)q->cpr * b->Ts_s * b->f_base_Hz);
    k1 = (float)b->pole_pairs / ((float)q->cpr * b->Ts_s * b->f_base_Hz);
    /* k <= k1: the one-sample speed needs the finer resolution as well */
    if (!(k < 1.0f) || !(k1 < 1.0f)) {
        return QEP_SPEED_ERR_RESOLUTION;
    }
    if (!(speed_filter_Hz > 0.0f) || !(speed_filter_Hz < 0.5f / b->Ts_s)) {
        return QEP_SPEED_ERR_CUTOFF;
    }
    a = 1.0f - expf(-QEP_TWO_PI * speed_filter_Hz * b->Ts_s);
    if (!(a >= QEP_SPEED_FILTER_A_MIN)) {
        return QEP_SPEED_ERR_CUTOFF;
    }
    /* d_max * k <= 63 pu; the window difference never exceeds 32768 */
    q->d_max = (int32_t)(QEP_SPEED_RAW_MAX / k);
    if (q->d_max > 32767) {
        q->d_max = 32767;
    }
    q->d_max1 = (int32_t)(QEP_SPEED_RAW_MAX / k1);
    if (q->d_max1 > 32767) {
        q->d_max1 = 32767;
    }
    q->k_angle = _IQ30(1.0f / (float)q->cpr);
    q->k_speed1 = _IQ(k1);
    q->k_speed = _IQ(k);
    q->k_filt = _IQ(a);
    return QEP_SPEED_OK;
}

void qep_speed_reset(qep_speed_t *q, uint16_t count_now)
{
    uint16_t i;

    q->prev_count = count_now;
    for (i = 0u; i < QEP_SPEED_WINDOW_MAX; i++) {
        q->hist[i] = count_now;
    }
    q->head = 0u;
    q->pos_mech = 0;
    q->pos_elec = 0;
    q->theta_mech = _IQ(0.0);
    q->theta_elec = _IQ(0.0);
    q->speed_raw = _IQ(0.0);
    q->speed_1 = _IQ(0.0);
    q->speed = _IQ(0.0);
    q->dir = 0;
}

void qep_speed_step(qep_speed_t *q)
{
    int32_t d1 = qep_diff(q->count, q->prev_count);   /* this sample, counts */
    int32_t dw;                                        /* over the window */

    q->prev_count = q->count;

    /* exact integer angles; |pole_pairs * d1| <= 64 * 32768 = 2^21 */
    q->pos_mech = qep_wrap(q->pos_mech + d1, q->cpr);
    q->pos_elec = qep_wrap(q->pos_elec + q->pole_pairs * d1, q->cpr);
    /* Q30 * count -> Q30 in [0, 1) (cpr <= 32768, see header), -> Q24 */
    q->theta_mech = _IQ30toIQ(_IQ30mpyI32(q->k_angle, q->pos_mech));
    q->theta_elec = _IQ30toIQ(_IQ30mpyI32(q->k_angle, q->pos_elec));

    /* one-sample speed: Q24 * count -> Q24, |.| <= 63 */
    q->speed_1 = _IQmpyI32(q->k_speed1, (d1 > q->d_max1) ? q->d_max1
                                        : ((d1 < -q->d_max1) ? -q->d_max1 : d1));

    /* hist[head] holds count(k - W); replace it by count(k) */
    dw = qep_diff(q->count, q->hist[q->head]);
    q->hist[q->head] = q->count;
    q->head = (uint16_t)((q->head + 1u) & (q->window - 1u));

    q->dir = (int16_t)((dw > 0) ? 1 : ((dw < 0) ? -1 : 0));
    if (dw > q->d_max) {
        dw = q->d_max;
    } else if (dw < -q->d_max) {
        dw = -q->d_max;
    }
    /* Q24 * count -> Q24, |.| <= 63 */
    q->speed_raw = _IQmpyI32(q->k_speed, dw);
    /* Q24*Q24 -> Q24, rounded.  speed is a convex combination of past
     * speed_raw values, so both are within +-63 and the difference within
     * +-126: no overflow. */
    q->speed += _IQrmpy(q->k_filt, q->speed_raw - q->speed);
}
