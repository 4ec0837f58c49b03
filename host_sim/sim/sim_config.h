/**
 * @file sim_config.h
 * The simulator's configuration, read from one INI file (parsed by inih,
 * Debian's libinih) that serves two consumers:
 *
 *   drive side  [nameplate] [board] [controller] [ident]: what the firmware
 *               is told; sim_config_to_drive() turns it into the
 *               drive_config_t, and board_config_gen writes the same
 *               drive_config_t as the board's board_config.c;
 *   simulated   [plant] [inverter] [sensors] [load] [drift] [simulation]:
 *   world       the true motor, the bridge, the sensors' errors, the load,
 *               the drift scenario, the integration.  A wrong nameplate is a
 *               [plant] that differs from [nameplate].
 *
 * Every key is declared once (sim_config.c) with its section, unit, default,
 * range and side; the ranges of the drive-side keys are the drive's own
 * (drive_limits.h, the table drive_init validates through), so the INI check
 * and drive_init refuse the same values and name the same key.  An unknown
 * section or key, a missing required key, a value that is not a finite
 * number or is outside its range, and unphysical combinations are errors
 * that name the key, its value and the limit.  No partial configuration is
 * ever used.
 */
#ifndef SIM_CONFIG_H
#define SIM_CONFIG_H

#include <stddef.h>
#include <stdint.h>
#include "drive_config.h"

/** The drive's linear zone of the dead-time compensation when [ident]
 *  vi_test = 0 (no key sets it: the test measures it): 3 codes of the
 *  current channel, at least this (sim_config_to_drive). */
#define SIM_FALLBACK_BAND_A 0.1

/* Every member is a double named as its key, one struct per section (the
 * fuzz target reads sim_config_t as an array of doubles). */

/** [nameplate] (drive): the motor as the firmware believes it. */
typedef struct {
    double Rs_ohm, Rr_ohm, Lm_H, Lls_H, Llr_H;
    double pole_pairs;
    double rated_current_A, rated_speed_rpm, rated_freq_Hz;
    double rated_voltage_V, rated_power_W;   /* informative; 0 when not given */
} sim_nameplate_t;

/** [board] (drive): the power stage and the sensor scaling as the firmware
 *  knows them (the simulated sensors share the scaling). */
typedef struct {
    double pwm_freq_Hz, sysclk_Hz;
    double dead_time_s;      /* programmed dead band */
    double device_drop_V;    /* the compensation's drop */
    double vdc_nominal_V, vdc_full_scale_V, current_full_scale_A, encoder_lines;
} sim_board_t;

/** [controller] (drive): design targets and protection levels. */
typedef struct {
    double current_bw_Hz, speed_bw_Hz, inertia_kgm2, max_torque_current_A;
    double speed_ramp_rpm_s, speed_filter_Hz, magnetizing_current_A;
    double overcurrent_A, vdc_max_V, vdc_min_V, dead_time_comp;
    double orientation;      /* 0: indirect (IFO), 1: rotor-flux observer (drive_config.h) */
} sim_controller_t;

/** [ident] (drive): the identification. */
typedef struct {
    double filter_cutoff_Hz, euler_passes, paper_regressor, period_mean, rls_p0, forgetting;
    double magnetize_s, rls_tail_s, target_speed_rpm;
    /* beyond the paper: each but the defaults needs orientation 1 */
    double passes;           /* identification passes 1..4 */
    double standstill;       /* 1: Rs and sigma Ls measured at standstill */
    double track_rr;         /* 1: Rr tracked in RUN */
    double track_memory_s;   /* the tracker's forgetting time constant */
    double vi_test;          /* 1: the bridge's voltage error measured at standstill */
    double static_id;        /* 1: the standstill sequence (drive_config.h) */
    double sequence;         /* sim_sequence_t, or SIM_SEQ_NONE: the keys above decide */
} sim_ident_t;

/** [plant] (sim): the true motor, each parameter the nameplate's unless given. */
typedef struct {
    double Rs_ohm, Rr_ohm, Lm_H, Lls_H, Llr_H;
    double J_kgm2, B_Nm_s;
} sim_plant_t;

/** [inverter] (sim): the simulated bridge. */
typedef struct {
    double vdc_V, source_resistance_ohm, ripple_V, ripple_Hz;
    double dead_time_s, device_drop_V, r_on_ohm, dead_time_band_A;
    /* the bridge's own overcurrent comparator on the true leg currents
     * (plant.h): its level (-1 in the file: 1.25 x controller.overcurrent_A,
     * resolved when loaded; 0: none) and its response time to the outputs off */
    double overcurrent_hw_A, overcurrent_hw_delay_s;
} sim_inverter_t;

/** [sensors] (sim): the simulated sensors' errors. */
typedef struct {
    double hall_gain_error_pct, hall_offset_a_A, hall_offset_b_A, hall_noise_A_rms;
    double adc_noise_lsb, seed;
    double encoder_offset;   /* the encoder's edge grid past the rotor's start, pitch [0, 1) */
} sim_sensors_t;

/** [load] (sim): T_load = const + prop w_m + fan (w_m/w_rated)^2 (sign of w_m). */
typedef struct {
    double const_Nm, prop_Nm_s, fan_Nm;
    double locked;           /* 1: the rotor held at rest (a load that cannot turn; its
                                reaction torque reported) */
} sim_load_t;

/** [drift] (sim): the thermal-drift scenario (sim_run.h, SCEN_DRIFT). */
typedef struct {
    double rr_rise_pct, ramp_s, start_s, load_period_s;
} sim_drift_t;

/** [simulation] (sim): numerics only. */
typedef struct {
    double substeps;
} sim_numerics_t;

#define SIM_CONFIG_NOTE_LEN 320

typedef struct {
    sim_nameplate_t nameplate;
    sim_board_t board;
    sim_controller_t controller;
    sim_ident_t ident;
    sim_plant_t plant;
    sim_inverter_t inverter;
    sim_sensors_t sensors;
    sim_load_t load;
    sim_drift_t drift;
    sim_numerics_t simulation;
    /* what the file says that a reader of an older layout may not mean (one
     * sentence, "" if nothing): motor_sim prints it as a note, never an error */
    char note[SIM_CONFIG_NOTE_LEN];
} sim_config_t;

/** The bridge's comparator level by default, per unit of the firmware's
 *  trip (inverter.overcurrent_hw_A = -1): far enough above it that the
 *  firmware, which sees the current every period, trips first whenever it
 *  can; low enough for the devices' short-circuit rating. */
#define SIM_HW_OC_OF_TRIP 1.25

/** ident.target_speed_rpm's default: the rated speed, which the drive lowers
 *  to what the bus it measures gives (drive_target.h; the drive gets 0). */
#define SIM_TARGET_RATED (-1.0)

/** The configured identification target, r/min: ident.target_speed_rpm, or
 *  the rated speed for SIM_TARGET_RATED.  An upper bound: the drive lowers
 *  it to what the bus gives at the start and in the acceleration
 *  (sim_result_t.target_rpm: the one it ran at). */
double sim_config_target_rpm(const sim_config_t *c);

/** The identification sequences (the keys each implies: docs/method.md). */
typedef enum {
    SIM_SEQ_NONE = -1,   /* [ident] sequence not given: the keys it would set decide */
    SIM_SEQ_PAPER = 0,   /* orientation 0, standstill 0, passes 1, track_rr 0: the paper's */
    SIM_SEQ_ADAPTIVE,    /* orientation 1, standstill 1, passes 2, track_rr 1: the default */
    SIM_SEQ_STANDSTILL   /* orientation 1, standstill 1, passes 1, track_rr 0, static_id 1:
                            nothing turns (drive_static.h) */
} sim_sequence_t;

/** The sequence's name in a file ("paper", "adaptive", "standstill"), or NULL. */
const char *sim_sequence_name(sim_sequence_t seq);

/** Set the keys of sequence @p seq in a loaded configuration (for tests and
 *  studies that run a shipped motor file with the other sequence). */
void sim_config_set_sequence(sim_config_t *c, sim_sequence_t seq);

/** Error text buffer size for sim_config_load. */
#define SIM_CONFIG_ERR_LEN 512

/** sim_config_load's status when drive_init refused a file that every limit
 *  of its table (drive_limits.h) accepted: a limit missing from the table
 *  (the fuzz target of the parser looks for it). */
#define SIM_CONFIG_ERR_UNLISTED 2

/** Load @p path.  Returns 0 on success; otherwise 1 (or
 *  SIM_CONFIG_ERR_UNLISTED) with a message naming the file, the line or key,
 *  the value and the limit in @p err. */
int sim_config_load(const char *path, sim_config_t *cfg, char *err, size_t err_len);

/** Load the drive side only (board_config_gen, the co-simulation API): every
 *  key is still parsed and range-checked, but the simulated world's
 *  sections may be absent (their required keys are not required) and the
 *  world is not checked against the drive: [plant], [inverter], [sensors],
 *  [load] never block a board's configuration. */
int sim_config_load_drive(const char *path, sim_config_t *cfg, char *err, size_t err_len);

/** Set key @p key ("section.key") of a loaded configuration, unchecked (for
 *  tests and studies; a default that follows another key is not redone).
 *  Returns 0, or -1 for an unknown key. */
int sim_config_set(sim_config_t *c, const char *key, double v);

/** The firmware's configuration from the drive-side sections. */
void sim_config_to_drive(const sim_config_t *cfg, drive_config_t *dc);

/** Print every key once: section, unit, default or required, range, and the
 *  side that reads it; then the derived limits (for --keys and the docs). */
void sim_config_print_keys(void);

#endif /* SIM_CONFIG_H */
