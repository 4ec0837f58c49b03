/* Encoder angle and speed.  See qep_speed.h. */
#include "qep_speed.h"

#include <math.h>

#define QEP_TWO_PI 6.28318530717958647692f
/* Largest |speed_raw| allowed, pu.  63 so that speed_raw - speed (both
 * within +-63) stays inside Q24's +-128. */
#define QEP_SPEED_RAW_MAX 63.0f

/* pu of speed per count over @p n samples: pp / (n cpr Ts f_base) */
static float qep_k(uint16_t pole_pairs, uint16_t n, int32_t cpr, const base_values_t *b)
{
    return (float)pole_pairs / ((float)n * (float)cpr * b->Ts_s * b->f_base_Hz);
}

/* The speed filter's corner @p fc_Hz with a step of @p n samples: in
 * (0, 1/(2 n Ts)), its coefficient *a = 1 - exp(-2 pi fc n Ts) at least
 * QEP_SPEED_FILTER_A_MIN. */
static qep_speed_status_t qep_cutoff(float fc_Hz, const base_values_t *b, uint16_t n, float *a)
{
    if (!(fc_Hz > 0.0f) || !(fc_Hz < 0.5f / (b->Ts_s * (float)n))) {
        return QEP_SPEED_ERR_CUTOFF;
    }
    *a = 1.0f - expf(-QEP_TWO_PI * fc_Hz * b->Ts_s * (float)n);
    if (!(*a >= QEP_SPEED_FILTER_A_MIN)) {
        return QEP_SPEED_ERR_CUTOFF;
    }
    return QEP_SPEED_OK;
}

/* 1 if @p n is a power of two in [1, @p n_max] (exactly one bit set) */
static int16_t qep_pow2(uint16_t n, uint16_t n_max)
{
    return (int16_t)(n != 0u && n <= n_max && (n & (n - 1u)) == 0u);
}

qep_speed_status_t qep_speed_check(uint16_t encoder_lines, const base_values_t *b,
                                   float speed_filter_Hz, uint16_t window)
{
    int32_t cpr;
    float a;

    if (b == 0 || !(b->Ts_s > 0.0f) || !(b->f_base_Hz > 0.0f) || b->pole_pairs == 0u ||
        b->pole_pairs > QEP_SPEED_POLE_PAIRS_MAX) {
        return QEP_SPEED_ERR_BASE;
    }
    if (encoder_lines == 0u || encoder_lines > QEP_SPEED_LINES_MAX) {
        return QEP_SPEED_ERR_LINES;
    }
    if (qep_pow2(window, QEP_SPEED_WINDOW_MAX) == 0) {
        return QEP_SPEED_ERR_WINDOW;
    }
    cpr = 4 * (int32_t)encoder_lines;
    /* k <= k1: the one-sample speed needs the finer resolution as well */
    if (!(qep_k(b->pole_pairs, window, cpr, b) < 1.0f) ||
        !(qep_k(b->pole_pairs, 1u, cpr, b) < 1.0f)) {
        return QEP_SPEED_ERR_RESOLUTION;
    }
    return qep_cutoff(speed_filter_Hz, b, 1u, &a);
}

qep_speed_status_t qep_speed_init(qep_speed_t *q, uint16_t encoder_lines,
                                  const base_values_t *b, float speed_filter_Hz,
                                  uint16_t window)
{
    qep_speed_status_t st;
    float k;
    float k1;
    float a = 0.0f;

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

    st = qep_speed_check(encoder_lines, b, speed_filter_Hz, window);
    if (st != QEP_SPEED_OK) {
        return st;
    }
    q->cpr = 4 * (int32_t)encoder_lines;
    q->pole_pairs = (int32_t)b->pole_pairs;
    q->window = window;
    k = qep_k(b->pole_pairs, window, q->cpr, b);
    k1 = qep_k(b->pole_pairs, 1u, q->cpr, b);
    (void)qep_cutoff(speed_filter_Hz, b, 1u, &a);
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
    q->decim = 1u;
    q->hist_len = window;
    q->k_speedn = q->k_speed1;
    q->d_maxn = q->d_max1;
    return QEP_SPEED_OK;
}

qep_speed_status_t qep_speed_decim_check(uint16_t decim, uint16_t window,
                                         const base_values_t *b, float speed_filter_Hz)
{
    float a;

    if (qep_pow2(decim, window) == 0) {
        return QEP_SPEED_ERR_WINDOW;
    }
    if (b == 0 || !(b->Ts_s > 0.0f) || !(b->f_base_Hz > 0.0f)) {
        return QEP_SPEED_ERR_BASE;
    }
    return qep_cutoff(speed_filter_Hz, b, decim, &a);
}

qep_speed_status_t qep_speed_set_decim(qep_speed_t *q, uint16_t decim, const base_values_t *b,
                                       float speed_filter_Hz)
{
    float kn;
    float a = 0.0f;
    qep_speed_status_t st = qep_speed_decim_check(decim, q->window, b, speed_filter_Hz);

    if (st != QEP_SPEED_OK) {
        return st;
    }
    (void)qep_cutoff(speed_filter_Hz, b, decim, &a);
    /* the mean speed over decim samples: pp / (decim cpr Ts f_base) per count */
    kn = qep_k((uint16_t)q->pole_pairs, decim, q->cpr, b);
    q->decim = decim;
    q->hist_len = (uint16_t)(q->window / decim);
    q->k_filt = _IQ(a);
    q->k_speedn = _IQ(kn);
    q->d_maxn = (int32_t)(QEP_SPEED_RAW_MAX / kn);
    if (q->d_maxn > 32767) {
        q->d_maxn = 32767;
    }
    qep_speed_reset(q, q->prev_count);
    return QEP_SPEED_OK;
}

void qep_speed_reset(qep_speed_t *q, uint16_t count_now)
{
    uint16_t i;

    q->prev_count = count_now;
    q->count_speed = count_now;
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

void qep_speed_update(qep_speed_t *q)
{
    /* counts since the last update (decim samples), over the window */
    int32_t dn = qep_diff(q->count, q->count_speed);
    int32_t dw;

    q->count_speed = q->count;
    /* exact integer mechanical angle (|dn| <= 32768) */
    q->pos_mech = qep_wrap(q->pos_mech + dn, q->cpr);
    q->theta_mech = _IQ30toIQ(_IQ30mpyI32(q->k_angle, q->pos_mech));

    /* mean speed over the last decim samples: Q24 * count -> Q24, |.| <= 63
     * (for decim = 1 the one-sample speed) */
    q->speed_1 = _IQmpyI32(q->k_speedn, (dn > q->d_maxn) ? q->d_maxn
                                        : ((dn < -q->d_maxn) ? -q->d_maxn : dn));

    /* hist[head] holds the count of W samples ago; replace it by this one */
    dw = qep_diff(q->count, q->hist[q->head]);
    q->hist[q->head] = q->count;
    q->head = (uint16_t)(q->head + 1u);
    if (q->head >= q->hist_len) {
        q->head = 0u;
    }

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

void qep_speed_step(qep_speed_t *q)
{
    qep_angle_step(q);
    qep_speed_update(q);
}
