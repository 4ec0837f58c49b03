/**
 * @file dc_bus.h
 * DC-bus voltage from the ADC (resistive divider on ADCINA1).
 *
 * The divider is specified by the bus voltage V_fs that gives 3.0 V at the
 * ADC pin, i.e. ADC code 4095 (raw 0xFFF0, 12 bits left-justified):
 *
 *     vdc_pu = (raw + 8) / 65520 * V_fs / V_base
 *
 * The ADC truncates (F2812 datasheet: "fractional values are truncated"),
 * so code c stands for pin voltages in [c, c + 1) LSB: the + 8 (half a
 * code of 16 raw counts) reads the centre of that interval.  Without it
 * the bus read half a code low on average (0.12 V of a 600 V bus, -2e-4),
 * which the identification would see as a resistance-like voltage error
 * (about -0.04 V along the current on the 15 kW motor in steady state).
 * vdc is the instantaneous value (one raw LSB of 16 counts is
 * V_fs/4095 volts); vdc_filt is a first-order low-pass of it for the
 * protections and the display (the modulator uses vdc, which follows the
 * ripple).  The filter is the exact discretisation of 1/(1 + s/wc) for an
 * input held over the sample (ZOH):
 *
 *     vdc_filt(k) = vdc_filt(k-1) + a (vdc(k) - vdc_filt(k-1)),  a = 1 - exp(-wc Ts)
 *
 * so its step response at the sample instants is exactly 1 - exp(-wc k Ts).
 * The first step after init loads vdc_filt = vdc (a bus already charged at
 * power-up does not read as an undervoltage for several time constants).
 *
 * No 1/vdc helper: a division per sample is the modulator's business, where
 * it is needed.
 */
#ifndef DC_BUS_H
#define DC_BUS_H

#include <stdint.h>
#include "IQmathLib.h"
#include "base_values.h"
#include "iq_rmpy.h"

/** A raw value >= this is at the top rail (ADC code 4095): the bus may be
 *  higher than vdc says. */
#define DC_BUS_RAIL_HIGH 0xFFF0u
/** Largest accepted full-scale reading, pu of V_base (headroom in Q24). */
#define DC_BUS_FULL_SCALE_MAX_PU 64.0f
/** Smallest accepted filter coefficient a (see dc_bus_step on its bias). */
#define DC_BUS_FILTER_A_MIN 1.0e-4f

/* 2^-16: raw / 65536, exact in Q24 (2^8 LSB) and in float */
#define DC_BUS_RAW_TO_FRAC _IQ(1.52587890625e-5)

typedef enum {
    DC_BUS_OK = 0,
    DC_BUS_ERR_BASE,         /* bases NULL or not initialised */
    DC_BUS_ERR_FULL_SCALE,   /* V_fs not > 0, or V_fs/V_base >= 64 */
    DC_BUS_ERR_CUTOFF        /* fc not in (0, 1/(2 Ts)), or a < 1e-4 */
} dc_bus_status_t;

typedef struct {
    /* inputs */
    uint16_t vdc_raw;      /* ADCRESULT: 12 bits left-justified */
    /* parameters */
    _iq k_scale;           /* Q24: V_fs/V_base * 65536/65520, pu per (raw/65536) */
    _iq k_filt;            /* Q24: a = 1 - exp(-2 pi fc Ts) */
    /* outputs */
    _iq vdc;               /* Q24, pu of V_base, this sample */
    _iq vdc_filt;          /* Q24, pu of V_base, low-pass filtered */
    uint16_t rail;         /* 1 while vdc_raw >= 0xFFF0 (reading clipped); the
                              bottom rail is not flagged: 0 V is a legitimate
                              reading (a discharged bus) */
    /* state */
    uint16_t primed;       /* 0 until the first step has loaded vdc_filt */
} dc_bus_t;

/** dc_bus_init's check of its arguments alone (no struct), the status it
 *  would return: DC_BUS_ERR_BASE, then _FULL_SCALE (V_fs/V_base * 65536/65520
 *  not below DC_BUS_FULL_SCALE_MAX_PU), then _CUTOFF.  The configuration's
 *  table of limits calls it too (drive_limits.c).  Float: init only. */
dc_bus_status_t dc_bus_check(float vdc_full_scale_V, const base_values_t *b, float fc_Hz);

/** @p vdc_full_scale_V: bus voltage that reads 3.0 V at the ADC pin;
 *  @p fc_Hz: cut-off of vdc_filt. */
dc_bus_status_t dc_bus_init(dc_bus_t *d, float vdc_full_scale_V, const base_values_t *b,
                            float fc_Hz);

/**
 * The bus voltage of this sample alone (no filter): what the drive's
 * voltage reconstruction, modulation and protections need, every period.
 * Scaling: raw * 2^-16 is exact in Q24 ([0, 1)); times k_scale (< 64) it
 * stays below 64 pu: no overflow.
 */
static inline void dc_bus_measure(dc_bus_t *d)
{
    /* (raw + 8) * 2^-16, the centre of the code (dc_bus.h): exact Q24 in
     * [0, 1.0002); Q24*Q24 -> Q24 (< 64) */
    d->vdc = _IQmpy(d->k_scale, _IQmpyI32(DC_BUS_RAW_TO_FRAC, (int32_t)d->vdc_raw + 8));
    d->rail = (uint16_t)(d->vdc_raw >= DC_BUS_RAIL_HIGH);   /* 0/1, no branch */
}

/**
 * One sample: dc_bus_measure, then the low-pass vdc_filt.  Scaling: the
 * filter increment is a rounded product (_IQrmpy), so vdc_filt settles
 * within 0.5/a LSB of vdc (a = 0.041 for 100 Hz at 15 kHz: 12 LSB = 7e-7
 * pu); |vdc - vdc_filt| < 64 so nothing can overflow and nothing
 * saturates.
 */
static inline void dc_bus_step(dc_bus_t *d)
{
    dc_bus_measure(d);
    if (d->primed == 0u) {
        d->vdc_filt = d->vdc;
        d->primed = 1u;
    } else {
        /* Q24*Q24 -> Q24, rounded; |difference| < 64 */
        d->vdc_filt += _IQrmpy(d->k_filt, d->vdc - d->vdc_filt);
    }
}

#endif /* DC_BUS_H */
