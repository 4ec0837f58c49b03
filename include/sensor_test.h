/**
 * @file sensor_test.h
 * The current sensors' test before the first magnetisation: a short
 * voltage pulse along each phase in turn, at standstill, open loop (no
 * current loop: a reversed sensor would make a closed loop run away), whose
 * current the two phase sensors must report with the right direction and
 * size.  A dead, reversed or mis-scaled sensor is refused before the
 * bridge drives any real current through the motor.
 *
 * Each of the three vectors (along phase a, b, c: angle phi = 0, 120, 240
 * deg in alpha-beta) is applied as +u for N periods, then -u for N periods
 * (the current returns near zero), then the bridge is off for Z periods
 * (the current freewheels to zero through the diodes, so that the next
 * vector starts from none).  At standstill, over N Ts much shorter than
 * the stator transient time constant sigma Ls / (Rs + Rr Lm^2/Lr^2) and
 * than Tr (the rotor flux has no time to change), each half changes the
 * current by about D = u N Ts / sigma Ls along the vector.  From the
 * measured changes S = (i(+ end) - i(start)) - (i(- end) - i(+ end)) of
 * both sensors (S_c = -S_a - S_b: the star is floating) the alpha-beta
 * response S is split along the vector (par) and across it (perp).  The
 * current keeps its sign through both halves, so what the bridge's dead
 * time and drops and the Rs i drop take from the + half they add to the -
 * half: in S they cancel to first order, S = 2 u N Ts / sigma Ls, and so
 * does an offset.
 *
 *   direction   |perp| <= tol_dir par: the two sensors agree with each
 *               other and with the geometry.  A gain error e on one sensor
 *               turns S by up to e/sqrt(3) rad (vector b: perp/par =
 *               e/sqrt(3)), a dead sensor by 90 deg or more, a reversed one
 *               by more: the test needs no motor parameter.
 *   size        par within (1 +- tol_abs) 2 D: the absolute scale, through
 *               the nameplate's sigma Ls (the only model-dependent part; it
 *               catches a common gain error of both sensors, which the
 *               direction test cannot see).
 *   limit       |i| of either sensor above i_abort (3 D) at any sample of
 *               the test: stop at once (a short, a sensor reading wildly).
 *
 * Tolerances and the resulting detection limits are set in drive_safety.c.
 *
 * Timing (hal_pwm.h): the voltage asked in ISR k is applied over period
 * k+1, so the current at the start of a half-pulse is sampled one ISR
 * after it is asked for, and at its end N ISRs later; turning the outputs
 * off acts at once, on period k itself, so the bridge goes off one ISR
 * after the last half-pulse's voltage was asked for.
 *
 * Cost on the C28x (tools/bench_isr.py): while the test runs (3 (2N + Z)
 * periods, 2.4-4.4 ms on the three motors) the test's step and the SVPWM
 * of its voltage; the current loops' modulation, which it replaces, is not
 * computed then (drive_step.c), so an ISR runs one SVPWM as in MAGNETIZE;
 * idle: one compare.  The evaluation (8 multiplies) once per vector.
 *
 * Scaling and overflow: a sample is taken only after the limit check
 * (|i| <= i_abort < 4 pu, compared without _IQabs) so |S| <= 16 ( Clarke components <= 16 x 1.2), constants below 2;
 * the products par, perp < 32; the thresholds < 32.  No division.
 */
#ifndef SENSOR_TEST_H
#define SENSOR_TEST_H

#include <stdint.h>
#include "IQmathLib.h"

/** Result bits (fail_bits): which check failed, and for which vector
 *  (bits 0-2: direction of a, b, c; 3-5: size of a, b, c; 6: limit). */
#define SENSOR_TEST_DIR_A 0x01u
#define SENSOR_TEST_SIZE_A 0x08u
#define SENSOR_TEST_LIMIT 0x40u

#define SENSOR_TEST_N_MAX 64u   /* periods per half-pulse (more: a smaller current) */

typedef enum {
    SENSOR_TEST_OK = 0,
    SENSOR_TEST_ERR_ARG
} sensor_test_status_t;

typedef enum {
    SENSOR_TEST_IDLE = 0,   /* waiting for run */
    SENSOR_TEST_RUNNING,
    SENSOR_TEST_PASSED,
    SENSOR_TEST_FAILED,
    SENSOR_TEST_JUDGING     /* the pulses are over, a vector's verdict is still due
                               (sensor_test_judge); then PASSED or FAILED */
} sensor_test_state_t;

typedef struct {
    /* inputs (every ISR) */
    uint16_t armed;         /* 0: reset to IDLE (the sequence is not in its test's state) */
    uint16_t run;           /* 1: run the test (the sequence waits for it) */
    _iq ia, ib;             /* Q24 pu: this ISR's phase currents */
    /* parameters (sensor_test_init) */
    _iq u;                  /* Q24 pu of V_base: the pulse's voltage */
    uint16_t n;             /* periods per half-pulse */
    uint16_t z;             /* bridge-off periods after each vector */
    _iq s_exp;              /* Q24 pu: the expected par, 2 D */
    _iq tol_abs;            /* Q24: relative tolerance of the size */
    _iq tol_dir;            /* Q24: largest |perp| / par */
    _iq i_abort;            /* Q24 pu: the limit */
    /* outputs */
    sensor_test_state_t state;
    _iq u_alpha, u_beta;    /* Q24 pu: the voltage to apply over the next period */
    uint16_t off;           /* 1: the bridge off over the next period */
    uint16_t fail_bits;     /* SENSOR_TEST_x bits (kept until the next run starts): the
                               limit's from sensor_test_step, the vectors' from
                               sensor_test_judge, merged at the verdict */
    _iq par[3], perp[3];    /* Q24 pu: each vector's response (diagnostic) */
    /* state */
    uint16_t vec;           /* 0..2 */
    uint16_t j;             /* ISR within the vector's schedule */
    _iq i0a, i0b, i1a, i1b; /* samples at the start and at the end of the + half */
    /* the vectors' verdicts, judged at the slow rate (sensor_test_judge):
     * each vector's response S per sensor, taken by sensor_test_step, and
     * its flag; the step sets a flag (1) only after writing the S, the
     * judge clears it (0) only after writing judge_bits: one writer each
     * way per word, no read-modify-write across the two contexts */
    _iq sa[3], sb[3];       /* Q24 pu: S = (i1 - i0) - (i2 - i1) per sensor, |.| <= 16 */
    volatile uint16_t judge_due[3];
    uint16_t judge_bits;    /* SENSOR_TEST_DIR_x, _SIZE_x bits of the judged vectors */
} sensor_test_t;

/**
 * Float, once.  Ts_s: PWM period; sigma_ls_H: the nameplate's sigma Ls;
 * v_base_V, i_base_A: the bases; vdc_V: the nominal bus; d_target_A: the
 * current each half-pulse should reach; tol_abs, tol_dir: tolerances.
 * N is the least number of periods that reaches d_target_A with at most
 * 80 % of the (2/3) vdc a vector can have, u is then set to reach it
 * exactly; where that takes more than SENSOR_TEST_N_MAX periods (a large
 * sigma Ls, a fast PWM) the test runs N_MAX periods at that 80 % and a
 * smaller current.  On error: zeroed, state FAILED.
 */
sensor_test_status_t sensor_test_init(sensor_test_t *t, float Ts_s, float sigma_ls_H,
                                      float v_base_V, float i_base_A, float vdc_V,
                                      float d_target_A, float tol_abs, float tol_dir);

/** Every ISR: advance the test with this ISR's currents; sets u_alpha,
 *  u_beta for the next period.  A vector's response is judged later, by
 *  sensor_test_judge; after the last vector the state is JUDGING until every
 *  verdict is in, then PASSED or FAILED (set here, the next ISR). */
void sensor_test_step(sensor_test_t *t);

/** 1 while a vector's verdict is due (the drive calls sensor_test_judge
 *  only then). */
static inline uint16_t sensor_test_judge_due(const sensor_test_t *t)
{
    return (uint16_t)(t->judge_due[0] | t->judge_due[1] | t->judge_due[2]);
}

/** The slow rate (it may be preempted by sensor_test_step): judge every
 *  vector whose response is due: its par and perp (diagnostic) and its
 *  SENSOR_TEST_DIR_x / SIZE_x bits.  The samples of a vector are its own, so
 *  a verdict may come any time before the test's end. */
void sensor_test_judge(sensor_test_t *t);

#endif /* SENSOR_TEST_H */
