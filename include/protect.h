/**
 * @file protect.h
 * Drive protections: each fault has its own code, is latched on the sample it
 * is seen, and turns the PWM off in the same ISR (the drive forces the
 * outputs inactive before it returns).  A latched fault is cleared only by an
 * explicit command, and only once its cause has gone (protect_clear).
 */
#ifndef PROTECT_H
#define PROTECT_H

#include <stdint.h>
#include "IQmathLib.h"

/** Fault codes (stable numbers: they go out over telemetry and into reports). */
typedef enum {
    FAULT_NONE = 0,
    FAULT_OVERCURRENT = 1,     /* |i_x| above the trip level, any phase */
    FAULT_BUS_OVERVOLTAGE = 2,
    FAULT_BUS_UNDERVOLTAGE = 3,/* while the bridge switches */
    FAULT_ENCODER = 4,         /* counts frozen with torque current, or implausible speed */
    FAULT_CURRENT_OFFSET = 5,  /* current-sensor offset out of range at calibration */
    FAULT_ADC_RAIL = 6,        /* an ADC result at a rail */
    FAULT_HW_TRIP = 7,         /* PDPINTA: the power stage tripped itself */
    FAULT_CONFIG = 8,          /* drive_init rejected the configuration */
    FAULT_CURRENT_SENSOR = 9,  /* measured currents do not follow their references
                                  (a phase-current sensor lost: current_check.h) or
                                  disagree with the current the applied voltage makes
                                  (current_model_check.h) */
    FAULT_ISR_OVERRUN = 10,    /* the control ISR ran past its period several times in a
                                  row (isr_monitor.h) */
    FAULT_SENSOR_TEST = 11,    /* the current sensors failed their pulse test before the
                                  magnetisation (sensor_test.h) */
    FAULT_STALL = 12,          /* encoder frozen with torque current while the standstill
                                  model holds: a locked rotor (stall_check.h) */
    FAULT_VI_CURVE = 13        /* the bridge's voltage-error test at standstill failed:
                                  a current level not reached or the curve implausible
                                  (vi_curve.h) */
} fault_code_t;

typedef struct {
    /* inputs (pu, Q24) */
    _iq ia, ib, ic;
    _iq vdc;
    uint16_t pwm_on;           /* undervoltage is checked only while switching */
    uint16_t adc_rail;         /* a raw result at 0 or full scale */
    uint16_t encoder_fault;    /* from the encoder plausibility check */
    uint16_t current_fault;    /* from the current-feedback check */
    uint16_t hw_trip;          /* PDPINTA */
    /* parameters */
    _iq i_trip;                /* pu */
    _iq vdc_max, vdc_min;      /* pu */
    _iq i_span;                /* 2 i_trip, pu (protect_check's range test) */
    /* outputs */
    fault_code_t fault;        /* latched; FAULT_NONE when healthy */
    uint16_t trip;             /* 1 while a fault is latched */
} protect_t;

/** protect_init's levels refused, the first one named (protect_args_ok). */
typedef enum {
    PROTECT_ARGS_OK = 0,
    PROTECT_ERR_TRIP,       /* i_trip not in (0, 32) pu */
    PROTECT_ERR_VDC_MIN,    /* vdc_min not > 0 */
    PROTECT_ERR_VDC_MAX     /* vdc_max not > vdc_min */
} protect_args_t;

/** protect_init's check of its levels alone (no struct), in that order
 *  (a level not yet known may be passed as 0: the ones before it are judged
 *  first).  The configuration's table of limits calls it too
 *  (drive_limits.c). */
protect_args_t protect_args_ok(_iq i_trip, _iq vdc_max, _iq vdc_min);

/** Levels in pu.  Returns 1 if a level is not positive, i_trip >= 32 pu or
 *  vdc_min >= vdc_max (protect_args_ok). */
int16_t protect_init(protect_t *p, _iq i_trip, _iq vdc_max, _iq vdc_min);
/* 1 if |i| > i_trip.  IQ_MATH: i + i_trip outside [0, 2 i_trip] as one
 * unsigned compare, the sum taken in uint32_t (defined wrap): every i in
 * [-i_trip, i_trip] maps to [0, 2 i_trip], every other int32_t value beyond
 * it (i_trip < 32 pu keeps 2 i_trip < 2^31). */
static inline uint16_t protect_over(const protect_t *p, _iq i)
{
#if MATH_TYPE == IQ_MATH
    return (uint16_t)(((uint32_t)i + (uint32_t)p->i_trip) > (uint32_t)p->i_span);
#else
    return (uint16_t)(_IQabs(i) > p->i_trip);
#endif
}

/* The first fault among this sample's inputs, in the priority order of
 * protect_step; strict: check the undervoltage also with the bridge off
 * (protect_clear). */
static inline fault_code_t protect_check(const protect_t *p, uint16_t strict)
{
    /* the healthy case first, without a branch per condition: every test
     * as a 0/1 value, OR-ed; only a sample with a cause goes on to find
     * which, in priority order */
    const uint16_t uv = (uint16_t)((p->pwm_on | strict) != 0u) & (uint16_t)(p->vdc < p->vdc_min);
    const uint16_t any = (uint16_t)(p->hw_trip | p->adc_rail | p->encoder_fault |
                                    p->current_fault | uv) |
                         protect_over(p, p->ia) | protect_over(p, p->ib) |
                         protect_over(p, p->ic) | (uint16_t)(p->vdc > p->vdc_max);
    if (any == 0u) {
        return FAULT_NONE;
    }
    if (p->hw_trip != 0u) {
        return FAULT_HW_TRIP;
    }
    if (_IQabs(p->ia) > p->i_trip || _IQabs(p->ib) > p->i_trip || _IQabs(p->ic) > p->i_trip) {
        return FAULT_OVERCURRENT;
    }
    if (p->vdc > p->vdc_max) {
        return FAULT_BUS_OVERVOLTAGE;
    }
    if (p->adc_rail != 0u) {
        return FAULT_ADC_RAIL;
    }
    if ((p->pwm_on != 0u || strict != 0u) && p->vdc < p->vdc_min) {
        return FAULT_BUS_UNDERVOLTAGE;
    }
    if (p->encoder_fault != 0u) {
        return FAULT_ENCODER;
    }
    if (p->current_fault != 0u) {
        return FAULT_CURRENT_SENSOR;
    }
    return FAULT_NONE;
}

/** Latch a fault found elsewhere (calibration, configuration). */
static inline void protect_latch(protect_t *p, fault_code_t code)
{
    if (p->fault == FAULT_NONE && code != FAULT_NONE) {
        p->fault = code;
        p->trip = 1u;
    }
}

/** Check this sample's inputs; latch the first fault seen, in this priority:
 *  hardware trip, overcurrent (a phase reading at a rail is also beyond the
 *  trip level, which is below full scale: a clipped real overcurrent reports
 *  as overcurrent), bus overvoltage (a bus reading at its top rail is at
 *  least the full scale, above the trip level (drive_limits.h: vdc_max below
 *  the full scale): the bus is at least that high, or its divider is open,
 *  and the drive cannot tell which; it reports what it must assume, an
 *  overvoltage), ADC rail (a reading at a rail that no level explains),
 *  bus undervoltage, encoder, current feedback. */
static inline void protect_step(protect_t *p)
{
    const fault_code_t code = protect_check(p, 0u);
    if (code != FAULT_NONE) {   /* the healthy sample: one test */
        protect_latch(p, code);
    }
}

/** Clear the latch if the inputs of this sample are healthy; returns 1 if
 *  cleared.  Stricter than protect_step: the bus must be above vdc_min even
 *  with the bridge off (a restart onto a sagging bus would trip at once),
 *  and the encoder and current checks must have been reset by the caller. */
uint16_t protect_clear(protect_t *p);

#endif /* PROTECT_H */
