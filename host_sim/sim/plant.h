/**
 * @file plant.h
 * The simulated power stage around the firmware: induction motor + load,
 * inverter, current/bus sensors through the F2812 ADC, encoder into T2.
 * Built from a sim_config_t.  Timing as on the F2812 (hal_pwm.h):
 *   plant_sample()  at the period start (T1 underflow): what the ADC
 *                   converts and T2CNT holds;
 *   plant_period()  one PWM period with the compare values that became
 *                   active at this underflow (written by the previous ISR)
 *                   and the output-enable state the ISR left.
 *
 * The bridge's overcurrent comparator ([inverter] overcurrent_hw_A,
 * overcurrent_hw_delay_s): one per leg, on the TRUE leg current (the
 * motor's phase current, plus the a-b short's current in legs a and b),
 * independent of the Hall sensors and of the firmware, as a desaturation
 * detector or a shunt comparator on the board.  When a leg's |current|
 * crosses the level, the outputs go to high impedance overcurrent_hw_delay_s
 * later (comparator, filter, gate driver) and PDPINTA is pulled low: the
 * F2812 disables its outputs in hardware and latches the trip
 * (hal_pwm_f2812.c), the firmware reads it in its next ISR
 * (FAULT_HW_TRIP).  The averaged model carries the current as smooth
 * within a period, so the crossing is found by linear interpolation
 * between the period's two ends, and the period is redone: bridge on up to
 * the crossing plus the delay, open for the rest (a delay that ends beyond
 * the period carries into the next one).
 */
#ifndef PLANT_H
#define PLANT_H

#include <stdint.h>

#include "adc_f2812.h"
#include "encoder_model.h"
#include "hall_sensor.h"
#include "hal_host.h"
#include "inverter_model.h"
#include "motor_model.h"
#include "sim_config.h"

typedef enum {
    PLANT_FAULT_NONE = 0,
    PLANT_FAULT_HALL_GAIN,    /* phase-a sensor gain error (value: relative) */
    PLANT_FAULT_HALL_LOST,    /* phase-b sensor output stuck at its zero-current level */
    PLANT_FAULT_BUS_SAG,      /* source voltage drops (value: relative) */
    PLANT_FAULT_ENCODER_LOST, /* T2 stops counting */
    PLANT_FAULT_OVERVOLTAGE,  /* source voltage rises (value: relative) */
    PLANT_FAULT_SHORT,        /* phase-to-phase short a-b at the inverter output (value:
                                 loop inductance, uH): a current rising at vdc/L while the
                                 bridge switches, seen by both sensors */
    PLANT_FAULT_ADC_RAIL,     /* bus-voltage divider's low side open: the ADC pin at its
                                 3.3 V clamp, the result at the top rail */
    PLANT_FAULT_CURRENT_OFFSET,/* phase-a sensor offset shifted (value: fraction of full
                                 scale); before calibration it must be refused there */
    PLANT_FAULT_ENCODER_JUMP, /* T2 jumps once by `value` counts (noise on A/B) */
    PLANT_FAULT_HW_TRIP,      /* PDPINTA pulled low by the power stage (value: for how
                                 long, s) */
    PLANT_FAULT_CLEAR         /* every injected fault removed (the cause has gone) */
} plant_fault_t;

typedef struct {
    motor_t motor;
    inverter_t inv;
    hall_t hall_a, hall_b;
    sig_cond_t cond_i, cond_v;
    adc_f2812_t adc_a, adc_b, adc_v;
    encoder_t enc;
    load_t load;
    double Ts_s;
    double J_kgm2;            /* the rotor's and load's inertia (stiction: plant.c) */
    double i_per_V;           /* the motor's current change over a period per phase volt
                                 (inverter_current_gain: the implicit bridge) */
    uint16_t t1pr;
    uint16_t substeps;        /* RK4 steps a period (the fallback integrator only) */
    uint16_t exact;           /* 1: motor_step_exact (the mechanical time constant is at
                                 least a period); 0: RK4 in `substeps` steps */
    double load_const_Nm, load_prop_Nm_s, load_fan_Nm, w_rated_m_rad_s;
    double extra_load_Nm;     /* scenario load steps */
    double i_dc_A;            /* last DC-link current */
    double t_s;
    /* injected faults */
    double hall_a_gain_fault; /* multiplies the phase-a measurement */
    uint16_t hall_b_lost;
    uint16_t encoder_frozen;
    uint16_t frozen_count;
    double vdc_scale;         /* multiplies the source voltage */
    double short_L_H;         /* > 0: the a-b short is present */
    double i_short_A;         /* its current (out of leg a, into leg b) */
    uint16_t vdc_rail;        /* bus feedback at 0 V */
    double offset_a_A;        /* added phase-a sensor offset */
    uint16_t qep_jump;        /* counts added to T2 from now on */
    double hw_trip_until_s;   /* PDPINTA low while t < this */
    double i_fs_A;            /* current-sensor full scale */
    double i_trip_A;          /* the drive's overcurrent level (for t_visible_s) */
    double t_visible_s;       /* first sample an injected fault changed (-1: none yet) */
    /* the bridge's overcurrent comparator */
    double hw_oc_A;           /* level on |leg current|, A (0: no comparator) */
    double hw_delay_s;        /* crossing to outputs off */
    double hw_pending_s;      /* >= 0: crossed, the outputs go off this far into the next period */
    uint16_t hw_fired;        /* the outputs went off in the last plant_period (PDPINTA fell) */
    uint32_t hw_trips;        /* times the comparator turned the bridge off */
    double t_hw_first_s;      /* the first time it did (-1: never) */
    /* the true currents' extremes over the periods (the ends of each period
     * and the instant the comparator turned the outputs off) */
    double i_phase_peak_A;    /* largest |motor phase current| */
    double i_leg_peak_A;      /* largest |leg current| (with the short's) */
    /* [load] locked: the rotor held at rest, the holding (reaction) torque */
    uint16_t locked;
    double te_hold_peak_Nm;   /* largest |torque| the lock held */
    double theta_m0_rad;      /* the rotor's angle at the start */
    double turn_peak_rad;     /* largest |theta_m - theta_m0|, locked or not */
} plant_t;

/** Returns 0 or a message-worthy non-zero status (the sub-model that refused). */
int plant_init(plant_t *p, const sim_config_t *c, uint16_t t1pr, char *err, unsigned err_len);
/** Fill the ADC results and T2CNT the F2812 would see now. */
void plant_sample(plant_t *p, hal_host_port_t *port);
/** Apply an injected fault (or PLANT_FAULT_CLEAR) from now on. */
void plant_inject(plant_t *p, plant_fault_t kind, double value);
/** 1 while the power stage holds PDPINTA low (the simulator copies it to the
 *  port; a comparator trip is a pulse: plant_t.hw_fired, latched by the
 *  host HAL as by the F2812, hal_host.h). */
uint16_t plant_trip_line(const plant_t *p);
/** 1 while the motor's state (speed, angle, currents, rotor flux) and the
 *  short's current are finite numbers; 0 once the integration diverged. */
int plant_finite(const plant_t *p);
/** Advance one PWM period. */
void plant_period(plant_t *p, const hal_pwm_compare_t *active, uint16_t outputs_enabled);
/** The load torque (N m) at the present state: const + prop w + fan (w/w_rated)^2 + steps. */
double plant_load_Nm(const plant_t *p, double w_m_rad_s);

#endif /* PLANT_H */
