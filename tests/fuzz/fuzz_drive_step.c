/*
 * Fuzz target: arbitrary ADC and QEP sequences into the control ISR
 * (drive_step of include/drive.h) after drive_init with a valid
 * configuration: the board's (g_board_config, generated from paper_motor.ini) or
 * one of three variants of it that reach the identification states sooner.
 *
 * Properties checked at every ISR (beyond "no undefined behaviour", which
 * ASan/UBSan check), and at each background call:
 *   - a STOP requested in a background period leaves an idle drive idle,
 *     whatever else came with it (stop wins over start, drive.h);
 *   - every compare value lies in [0, T1PR] (hal_pwm.h);
 *   - with the bridge off (telemetry pwm_on = 0) all three compares equal
 *     T1PR: upper switches off, the safe state;
 *   - a latched fault, or the hardware trip input, means pwm_on = 0 in the
 *     same ISR (reaction within one period);
 *   - drive_init accepts the configuration and T1PR is what the board's
 *     clock and PWM frequency give (150e6 / (2 * 15e3) = 5000).
 *
 * Input format (little-endian), chosen so that short inputs reach deep
 * states: a run of samples is one 8-byte record with a repeat count.
 *   byte 0       configuration variant (bits 0-1, see make_config; bit 2: the
 *                adaptive sequence on top); bit 3: commands are only
 *                requested (drive_command) and wait for the background
 *                loop's 1 kHz tick, as on the board, so that the commands of
 *                consecutive short records meet in one background period
 *                (several sources at once: reset, stop and start in any
 *                order); without it each command is handled at once
 *   records      [op][ia:2][ib:2][vdc:2][dq:1]
 *     op bits 0-1  command before the run: none, start, stop, reset fault
 *     op bit  2    PDPINTA (hardware trip) level during the run
 *     op bit  3    echo: the phase currents follow the drive's own current
 *                  references (an ideal current-controlled machine), and
 *                  ia, ib are signed perturbations in counts added to them;
 *                  without it ia, ib are the raw words themselves
 *     op bits 4-7  the run is 2^n ISR periods (1 .. 32768)
 *     ia, ib, vdc  raw ADCRESULT words (any 16 bits, also the low 4 that the
 *                  F2812 leaves 0)
 *     dq           signed QEP counts per period (T2CNT wraps modulo 2^16); with
 *                  echo, the speed the rotor goes to at a physical
 *                  acceleration (ECHO_ACCEL: a step of dq is not a motor,
 *                  and the encoder's count-step test refuses it, as it must)
 * Echo lets short inputs pass the current-plausibility protections and
 * reach acceleration, steady state and the parameter extraction, where
 * fixed ADC words would trip them within a few periods.  The echoed
 * currents are those of the motor the configuration believes in (the
 * fifth-order model of method §1 in the stationary frame, without its
 * mechanics: the rotor turns by dq counts per period), driven by the
 * voltage the drive's own compare values ask for at its measured bus (an
 * ideal bridge; off: the stator current is zero): the model-based current
 * check (current_model_check.h) refuses currents that no voltage explains,
 * as it must, and the sensor test (sensor_test.h) its pulses' answer.
 * At most MAX_STEPS periods per input; the background loop runs every 15th
 * period, as the firmware's main loop at 1 kHz does.  With FUZZ_TRACE set in
 * the environment each state and fault change is printed (to read a crash
 * input: FUZZ_TRACE=1 fuzz_drive_step_replay crash-...).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "board_config.h"
#include "drive_types.h"
#include "fuzz_target.h"

#define MAX_STEPS 16384u        /* ~1.1 s at 15 kHz: the seeds need ~13 900 */
#define BACKGROUND_DIV 15u      /* background at 1 kHz */
#define RECORD_LEN 8u
#define ECHO_ACCEL 0.002        /* counts per period per period: 0.2 s to 6 counts per
                                   period (1350 r/min on the paper motor), half its largest */

static drive_t g_drive;         /* large: static, one input at a time */
static uint16_t g_states_seen;  /* bit n: id_state_t n was reached (corpus check) */
static int g_trace = -1;        /* FUZZ_TRACE set: print state and fault changes */
static int g_selftest;          /* FUZZ_SELFTEST set: corrupt one compare value (CTest
                                   fuzz_drive_step_check_can_fail) */
static int g_latched;           /* byte 0 bit 3: commands wait for the 1 kHz background */
static uint16_t g_multi_seen;   /* a background period handled two or more commands
                                   (corpus check) */

void fuzz_fail(const char *what, unsigned long step, long value, long limit)
{
    fprintf(stderr, "fuzz_drive_step: %s at ISR %lu: %ld (limit %ld)\n", what, step, value,
            limit);
    abort();
}

/* Variants of the board configuration, each valid (drive_init accepts it):
 *   0  g_board_config unchanged (paper motor, 0.3 s magnetisation, 0.7 s ramp)
 *   1  0.1 s magnetisation, a 0.1 s ramp to 1350 r/min (= 6 QEP counts per
 *      period: 6 * 15e3 / 4000 * 60), so that SETTLE and RUN come early
 *   2  as 1, with the paper's regressor (eq. 9) and forgetting 0.995
 *   3  as 1, without dead-time compensation and with a 0.5 s RLS tail
 *   + 4  (bit 2) any of them with orientation 1, standstill tests, two
 *        passes and tracking (0.3 s magnetisation: the standstill test) */
static void make_config(uint8_t variant, drive_config_t *c)
{
    *c = g_board_config;
    if ((variant & 4u) != 0u) {
        /* bit 2: the adaptive sequence on top of the variant
         * (observer, standstill tests, two passes, tracking); its
         * standstill test needs the 0.3 s magnetisation */
        c->control.orientation = DRIVE_ORIENT_FLUX_OBS;
        c->ident.standstill = 1u;
        c->ident.passes = 2u;
        c->ident.track_rr = 1u;
    }
    if ((variant & 3u) == 0u) {
        return;
    }
    variant = (uint8_t)(variant & 3u);
    c->ident.magnetize_time_s = (c->ident.standstill != 0u) ? 0.3f : 0.1f;   /* >= 5 Tr = 99 ms */
    c->ident.target_speed_rpm = 1350.0f;
    c->control.speed_ramp_rpm_s = 13500.0f;
    if (variant == 2u) {
        c->ident.paper_regressor = 1u;
        c->ident.forgetting = 0.995f;
    } else if (variant == 3u) {
        c->board.dead_time_comp = 0u;
        c->ident.rls_tail_s = 0.5f;
    } else {
        /* variant 1: nothing more */
    }
}

/* The background loop, with the stop-wins property: an idle drive that
 * was asked to stop in this period (whatever came with it) stays idle. */
static void background(unsigned long step)
{
    const uint16_t stop = (uint16_t)(g_drive.cmd_requests & DRIVE_CMD_BIT(DRIVE_CMD_STOP));
    const id_state_t before = g_drive.seq.state;
    const uint16_t req = g_drive.cmd_requests;
    if ((req & (uint16_t)(req - 1u)) != 0u) {
        g_multi_seen = 1u;   /* more than one bit */
    }
    drive_background(&g_drive);
    if (stop != 0u && before == ID_IDLE && g_drive.seq.state != ID_IDLE) {
        fuzz_fail("a stop request let an idle drive start", step, (long)g_drive.seq.state, 0L);
    }
}

static uint16_t get16(const uint8_t *p) { return (uint16_t)(p[0] | (p[1] << 8)); }

/* Raw ADC word of a phase current in pu (inverse of phase_current_step with
 * the calibrated offset and gain), plus a perturbation; clamped to 16 bits. */
static uint16_t raw_of_current(double i_pu, _iq gain, uint16_t offset, int16_t perturb)
{
    double g = (double)_IQtoF(gain);
    double raw = (double)offset + (double)perturb + ((g != 0.0) ? i_pu * 32768.0 / g : 0.0);
    if (raw < 0.0) {
        raw = 0.0;
    } else if (raw > 65535.0) {
        raw = 65535.0;
    } else {
        /* in range */
    }
    return (uint16_t)(raw + 0.5);
}

/* The believed motor behind the echo (see the file comment), SI. */
typedef struct {
    double rate;                /* counts per period (echo: follows dq at ECHO_ACCEL) */
    double pos;                 /* counts, the fraction of the rotor's position */
    double i_a, i_b;            /* stator current, alpha-beta, A */
    double psi_a, psi_b;        /* rotor flux, Wb */
    hal_pwm_compare_t out1, out2;   /* the compares of the last ISR and the one before */
    uint16_t on1;               /* the bridge after the last ISR */
} echo_motor_t;

/* The period that just ended: the bridge as the last ISR left it, the
 * compares of the ISR before (shadowed, hal_pwm.h), the drive's measured
 * bus; 8 Euler steps of
 *   sigma Ls di/dt = u - (Rs + Lm^2/(Lr Tr)) i + (Lm/Lr)(1/Tr - j w) psi
 *   dpsi/dt = (Lm/Tr) i - (1/Tr - j w) psi
 * (the bridge off: i = 0, the flux decays). */
static void echo_motor_period(echo_motor_t *e, const drive_t *d, const drive_config_t *c,
                              double dq)
{
    const drive_motor_t *m = &c->motor;
    const double Ts = 1.0 / (double)c->board.pwm_freq_Hz;
    const double h = Ts / 8.0;
    const double tr = (double)m->Lr_H / (double)m->Rr_ohm;
    const double lm_lr = (double)m->Lm_H / (double)m->Lr_H;
    const double sls = (double)m->Ls_H - (double)m->Lm_H * lm_lr;
    const double r_t = (double)m->Rs_ohm + (double)m->Lm_H * lm_lr / tr;
    const double w = (double)dq * 6.283185307179586 * (double)m->pole_pairs /
                     (4.0 * (double)c->board.encoder_lines * Ts);
    double u_a = 0.0, u_b = 0.0;
    int n;
    if (e->on1 != 0u) {
        const double vdc = (double)_IQtoF(d->sense.bus.vdc) * (double)d->base.V_base_V;
        double dx[3], mean;
        int x;
        for (x = 0; x < 3; x++) {
            dx[x] = (double)(d->k.t1pr - e->out2.cmpr[x]) / (double)d->k.t1pr;
        }
        mean = (dx[0] + dx[1] + dx[2]) / 3.0;
        u_a = (dx[0] - mean) * vdc;
        u_b = ((dx[1] - mean) - (dx[2] - mean)) * vdc / 1.7320508075688772;
    }
    for (n = 0; n < 8; n++) {
        const double fa = e->psi_a / tr + w * e->psi_b;   /* (1/Tr - j w) psi */
        const double fb = e->psi_b / tr - w * e->psi_a;
        if (e->on1 != 0u) {
            const double di_a = (u_a - r_t * e->i_a + lm_lr * fa) / sls;
            const double di_b = (u_b - r_t * e->i_b + lm_lr * fb) / sls;
            e->psi_a += h * ((double)m->Lm_H / tr * e->i_a - fa);
            e->psi_b += h * ((double)m->Lm_H / tr * e->i_b - fb);
            e->i_a += h * di_a;
            e->i_b += h * di_b;
        } else {
            e->i_a = e->i_b = 0.0;
            e->psi_a -= h * fa;
            e->psi_b -= h * fb;
        }
    }
}

static void echo_motor_after(echo_motor_t *e, const drive_t *d, const hal_pwm_compare_t *out)
{
    e->out2 = e->out1;
    e->out1 = *out;
    e->on1 = d->telemetry.pwm_on;
}

/* The echoed phase currents: the believed motor's, plus the record's
 * perturbations (raw counts). */
static void echo_currents(const echo_motor_t *e, const drive_t *d, hal_adc_sample_t *adc,
                          int16_t pa, int16_t pb)
{
    const double ib_base = (double)d->base.I_base_A;
    const double ia = e->i_a / ib_base;
    const double ib = (-0.5 * e->i_a + 0.8660254037844386 * e->i_b) / ib_base;
    adc->ia_raw = raw_of_current(ia, d->sense.phase.gain_a, d->sense.phase.offset_a, pa);
    adc->ib_raw = raw_of_current(ib, d->sense.phase.gain_b, d->sense.phase.offset_b, pb);
}

static void check_outputs(const drive_t *d, const hal_pwm_compare_t *out, uint16_t hw_trip,
                          unsigned long step)
{
    unsigned i;
    for (i = 0; i < 3u; i++) {
        if (out->cmpr[i] > d->k.t1pr) {
            fuzz_fail("compare value above T1PR", step, (long)out->cmpr[i], (long)d->k.t1pr);
        }
        if (d->telemetry.pwm_on == 0u && out->cmpr[i] != d->k.t1pr) {
            fuzz_fail("bridge off but a compare value is not T1PR", step, (long)out->cmpr[i],
                      (long)d->k.t1pr);
        }
    }
    if (d->prot.trip.fault != FAULT_NONE && d->telemetry.pwm_on != 0u) {
        fuzz_fail("PWM on with a latched fault", step, (long)d->prot.trip.fault, 0L);
    }
    if (hw_trip != 0u && d->telemetry.pwm_on != 0u) {
        fuzz_fail("PWM on while the hardware trip input is active", step, 1L, 0L);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    drive_config_t cfg;
    hal_pwm_compare_t out;
    unsigned long step = 0;
    uint16_t qep = 0u;
    size_t pos;
    int16_t st;
    id_state_t last_state = ID_IDLE;
    fault_code_t last_fault = FAULT_NONE;
    echo_motor_t motor;

    if (size < 1u) {
        return 0;
    }
    if (g_trace < 0) {
        g_trace = (getenv("FUZZ_TRACE") != NULL) ? 1 : 0;
        g_selftest = (getenv("FUZZ_SELFTEST") != NULL) ? 1 : 0;
    }
    memset(&motor, 0, sizeof motor);
    make_config((uint8_t)(data[0] & 7u), &cfg);
    g_latched = (data[0] & 8u) != 0u;
    /* garbage first, as in the F2812's .ebss (not zeroed by _c_int00):
     * nothing may depend on memory drive_init did not set */
    memset(&g_drive, 0xA5, sizeof g_drive);
    st = drive_init(&g_drive, &cfg);
    if (st != DRIVE_CFG_OK) {
        fuzz_fail("drive_init rejected a valid configuration", 0, (long)st, 0L);
    }
    if (g_drive.k.t1pr != 5000u) {
        fuzz_fail("T1PR is not 150 MHz / (2 * 15 kHz)", 0, (long)g_drive.k.t1pr, 5000L);
    }

    for (pos = 1; pos + RECORD_LEN <= size && step < MAX_STEPS; pos += RECORD_LEN) {
        const uint8_t *r = data + pos;
        uint8_t op = r[0];
        hal_adc_sample_t adc;
        uint16_t hw_trip = (uint16_t)((op >> 2) & 1u);
        uint16_t echo = (uint16_t)((op >> 3) & 1u);
        unsigned long n = 1ul << (op >> 4);
        int16_t dq = (int16_t)(int8_t)r[7];
        unsigned long k;

        if ((op & 3u) != 0u) {
            static const drive_cmd_t cmds[4] = {DRIVE_CMD_NONE, DRIVE_CMD_START_IDENT,
                                                DRIVE_CMD_STOP, DRIVE_CMD_RESET_FAULT};
            drive_command(&g_drive, cmds[op & 3u]);
            if (!g_latched) {
                background(step);
            }
        }
        for (k = 0; k < n && step < MAX_STEPS; k++, step++) {
            adc.vdc_raw = get16(r + 5);
            if (echo != 0u) {
                /* the rotor accelerates towards dq counts per period */
                const double err = (double)dq - motor.rate;
                motor.rate += (err > ECHO_ACCEL) ? ECHO_ACCEL
                                                 : ((err < -ECHO_ACCEL) ? -ECHO_ACCEL : err);
                motor.pos += motor.rate;
                {
                    const double whole = floor(motor.pos);
                    qep = (uint16_t)(qep + (uint16_t)(int16_t)whole);
                    motor.pos -= whole;
                }
            } else {
                motor.rate = (double)dq;
                qep = (uint16_t)(qep + (uint16_t)dq);
            }
            echo_motor_period(&motor, &g_drive, &cfg, motor.rate);
            if (echo != 0u) {
                echo_currents(&motor, &g_drive, &adc, (int16_t)get16(r + 1),
                              (int16_t)get16(r + 3));
            } else {
                adc.ia_raw = get16(r + 1);
                adc.ib_raw = get16(r + 3);
            }
            g_drive.prot.trip.hw_trip = hw_trip;   /* as drive_isr does from hal_pwm_tripped() */
            drive_step(&g_drive, &adc, qep, &out);
            echo_motor_after(&motor, &g_drive, &out);
            if (g_selftest != 0 && step == 100u) {
                out.cmpr[0] = (uint16_t)(g_drive.k.t1pr + 1u);   /* the check must catch it */
            }
            check_outputs(&g_drive, &out, hw_trip, step);
            g_states_seen |= (uint16_t)(1u << ((unsigned)g_drive.seq.state & 15u));
            if (g_trace != 0 &&
                (g_drive.seq.state != last_state || g_drive.prot.trip.fault != last_fault)) {
                last_state = g_drive.seq.state;
                last_fault = g_drive.prot.trip.fault;
                printf("ISR %lu: state %u fault %u (i_M ref %.3f, i_T ref %.3f, ia %.3f, "
                       "ib %.3f, vdc %.3f pu)\n", step, (unsigned)last_state,
                       (unsigned)last_fault, (double)_IQtoF(g_drive.loop.pi_id.ref),
                       (double)_IQtoF(g_drive.loop.pi_iq.ref), (double)_IQtoF(g_drive.sense.phase.ia),
                       (double)_IQtoF(g_drive.sense.phase.ib), (double)_IQtoF(g_drive.sense.bus.vdc));
            }
            if ((step % BACKGROUND_DIV) == 0u) {
                background(step);
            }
        }
    }
    return 0;
}

int fuzz_corpus_check(void)
{
    static const char *const names[] = {"IDLE", "CALIBRATE", "MAGNETIZE", "ACCELERATE",
                                        "SETTLE", "RUN", "FAULT"};
    unsigned i;
    int missing = 0;
    printf("fuzz_drive_step: states reached by the corpus:");
    for (i = 0; i < sizeof names / sizeof names[0]; i++) {
        if ((g_states_seen & (1u << i)) != 0u) {
            printf(" %s", names[i]);
        } else {
            missing = 1;
        }
    }
    printf("\n");
    if (missing != 0) {
        fprintf(stderr, "fuzz_drive_step: the corpus must reach every state of the sequence\n");
    }
    printf("fuzz_drive_step: commands meeting in one background period: %s\n",
           g_multi_seen ? "yes" : "no");
    if (g_multi_seen == 0u) {
        fprintf(stderr, "fuzz_drive_step: the corpus must give several commands in one "
                        "background period\n");
        missing = 1;
    }
    return missing;
}
