/* Phase currents from the Hall sensors.  See phase_current.h. */
#include "phase_current.h"

phase_current_status_t phase_current_init(phase_current_t *pc, float gain_a, float gain_b,
                                          int16_t polarity, float offset_window_fs)
{
    float sign;

    pc->ia_raw = PHASE_CURRENT_OFFSET_NOMINAL;
    pc->ib_raw = PHASE_CURRENT_OFFSET_NOMINAL;
    pc->offset_a = PHASE_CURRENT_OFFSET_NOMINAL;
    pc->offset_b = PHASE_CURRENT_OFFSET_NOMINAL;
    pc->gain_a = _IQ(0.0);
    pc->gain_b = _IQ(0.0);
    pc->offset_window = 0u;
    pc->ia = _IQ(0.0);
    pc->ib = _IQ(0.0);
    pc->ic = _IQ(0.0);
    pc->rail = 0u;
    pc->cal_fault = 0u;
    pc->cal_sum_a = 0u;
    pc->cal_sum_b = 0u;
    pc->cal_n = 0u;
    pc->cal_left = 0u;
    pc->cal_recip = 0u;
    pc->cal_rshift = 0u;
    pc->cal_recip_n = 0u;

    /* "!(x >= lo && x <= hi)" also rejects NaN */
    if (!(gain_a >= PHASE_CURRENT_GAIN_MIN && gain_a <= PHASE_CURRENT_GAIN_MAX) ||
        !(gain_b >= PHASE_CURRENT_GAIN_MIN && gain_b <= PHASE_CURRENT_GAIN_MAX)) {
        return PHASE_CURRENT_ERR_GAIN;
    }
    if (polarity != 1 && polarity != -1) {
        return PHASE_CURRENT_ERR_POLARITY;
    }
    if (!(offset_window_fs > 0.0f && offset_window_fs <= PHASE_CURRENT_WINDOW_MAX)) {
        return PHASE_CURRENT_ERR_WINDOW;
    }
    sign = (polarity > 0) ? 1.0f : -1.0f;
    pc->gain_a = _IQ(sign * gain_a);
    pc->gain_b = _IQ(sign * gain_b);
    /* <= 0.25 * 65536 + 0.5 = 16384.5: fits uint16_t */
    pc->offset_window = (uint16_t)(offset_window_fs * 65536.0f + 0.5f);
    if (pc->offset_window == 0u) {
        pc->offset_window = 1u;
    }
    return PHASE_CURRENT_OK;
}

phase_current_status_t phase_current_cal_start(phase_current_t *pc, uint16_t n_samples)
{
    if (n_samples == 0u || pc->cal_recip == 0u || n_samples != pc->cal_recip_n) {
        pc->cal_left = 0u;
        return PHASE_CURRENT_ERR_SAMPLES;   /* not the count phase_current_cal_design made */
    }
    pc->cal_sum_a = 0u;
    pc->cal_sum_b = 0u;
    pc->cal_fault = 0u;
    pc->cal_n = n_samples;
    pc->cal_left = n_samples;
    return PHASE_CURRENT_OK;
}

phase_current_status_t phase_current_cal_design(phase_current_t *pc, uint16_t n_samples)
{
    /* floor(x / n) = floor(x m / 2^s) for every x < 2^N with
     * m = ceil(2^s / n) and s >= N + ceil(log2 n) (Granlund & Montgomery 1994,
     * "Division by invariant integers using multiplication", theorem 4.2:
     * m n - 2^s < n <= 2^(s - N)); x = sum + n/2 <= 65535 n + n/2 sets N.
     * s at least 32, so that the ISR takes the product's high word (a
     * 32 x 32 -> 64-bit multiply) and shifts it by s - 32 in 32 bits */
    uint64_t x_max, m;
    uint16_t n_bits = 0u, l = 0u, s;
    pc->cal_recip = 0u;
    pc->cal_rshift = 0u;
    pc->cal_recip_n = 0u;
    if (n_samples == 0u) {
        return PHASE_CURRENT_ERR_SAMPLES;
    }
    x_max = (uint64_t)65535u * n_samples + (n_samples >> 1);
    while (n_bits < 63u && ((uint64_t)1u << n_bits) <= x_max) {
        n_bits++;
    }
    while (((uint32_t)1u << l) < n_samples) {
        l++;
    }
    s = (uint16_t)((n_bits + l > 32u) ? n_bits + l : 32u);
    if (s > 63u) {
        return PHASE_CURRENT_ERR_SAMPLES;
    }
    m = (((uint64_t)1u << s) + n_samples - 1u) / n_samples;
    if (m > 0xFFFFFFFFu) {
        return PHASE_CURRENT_ERR_SAMPLES;   /* the mean divides (pc_load_offset) */
    }
    pc->cal_recip = (uint32_t)m;
    pc->cal_rshift = (uint16_t)(s - 32u);   /* 0..31 */
    pc->cal_recip_n = n_samples;
    return PHASE_CURRENT_OK;
}

/* Rounded mean of n readings; accept it if within the window of 32768.
 * Returns 1 if accepted (offset loaded), 0 if rejected (nominal loaded). */
static uint16_t pc_load_offset(const phase_current_t *pc, uint32_t sum, uint16_t window,
                               uint16_t *offset)
{
    /* sum <= 65535 * 65535 < 2^32 - n/2: no wrap in the rounding */
    const uint32_t x = sum + ((uint32_t)pc->cal_n >> 1);
    /* the designed count (cal_start accepts no other): a 32 x 32 -> 64-bit
     * product's high word and a 32-bit shift, the rounded division's result
     * (phase_current_cal_design), which the C28x has only as a
     * run-time-library call (~140 cycles from flash each) */
    const uint64_t p = (uint64_t)x * pc->cal_recip;
    uint32_t mean = (uint32_t)(p >> 32) >> pc->cal_rshift;   /* <= 65535 */
    int32_t dev = (int32_t)mean - (int32_t)PHASE_CURRENT_OFFSET_NOMINAL;

    if (dev > (int32_t)window || dev < -(int32_t)window) {
        *offset = PHASE_CURRENT_OFFSET_NOMINAL;
        return 0u;
    }
    *offset = (uint16_t)mean;
    return 1u;
}

phase_current_cal_t phase_current_cal_step(phase_current_t *pc)
{
    if (pc->cal_left == 0u) {
        return PHASE_CURRENT_CAL_IDLE;
    }
    pc->rail = phase_current_rail_bits(pc->ia_raw, pc->ib_raw);
    pc->cal_sum_a += pc->ia_raw;
    pc->cal_sum_b += pc->ib_raw;
    pc->cal_left--;
    if (pc->cal_left != 0u) {
        return PHASE_CURRENT_CAL_BUSY;
    }
    if (pc_load_offset(pc, pc->cal_sum_a, pc->offset_window, &pc->offset_a) == 0u) {
        pc->cal_fault |= PHASE_CURRENT_PHASE_A;
    }
    if (pc_load_offset(pc, pc->cal_sum_b, pc->offset_window, &pc->offset_b) == 0u) {
        pc->cal_fault |= PHASE_CURRENT_PHASE_B;
    }
    return (pc->cal_fault == 0u) ? PHASE_CURRENT_CAL_DONE : PHASE_CURRENT_CAL_REJECTED;
}
