/**
 * @file sim_config.h
 * The simulator's configuration: the simulated (true) motor, its load, the
 * inverter, the sensors, and the firmware's drive_config_t, read from an INI
 * file (parsed by inih, Debian's libinih).
 *
 * Every key is declared once in a table (sim_config.c) with its section,
 * unit, valid range and whether it is required.  An unknown section or key,
 * a missing required key, a value that is not a finite number, or one outside
 * its range is an error that names the key; cross-checks (Lm < Ls, a bus high
 * enough for rated speed, ...) run after parsing.  No partial configuration
 * is ever used.
 */
#ifndef SIM_CONFIG_H
#define SIM_CONFIG_H

#include <stddef.h>
#include <stdint.h>
#include "drive_config.h"


typedef struct {
    /* [motor]: the simulated machine (the truth the identification must find) */
    double Rs_ohm, Rr_ohm, Lm_H, Lls_H, Llr_H;
    double pole_pairs;
    double J_kgm2, B_Nm_s;
    double rated_power_W, rated_voltage_V, rated_current_A, rated_speed_rpm, rated_freq_Hz;
    /* [load]: T_load = const + k_prop*w_m + fan*(w_m/w_rated)^2 (sign of w_m) */
    double load_const_Nm, load_prop_Nm_s, load_fan_Nm;
    /* [inverter] */
    double vdc_V, source_resistance_ohm, ripple_V, ripple_Hz;
    double dead_time_s, device_drop_V, r_on_ohm, dead_time_band_A_plant;
    /* [sensors] */
    double hall_full_scale_A, hall_gain_error_pct, hall_offset_a_A, hall_offset_b_A;
    double hall_noise_A_rms, adc_noise_lsb, vdc_full_scale_V, encoder_lines;
    double seed;
    /* [controller]: what the firmware believes, and its design targets.
     * The believed motor values default to the true ones; *_error_pct keys
     * scale them (a wrong nameplate). */
    double ctl_Rs_error_pct, ctl_Rr_error_pct, ctl_Lm_error_pct;
    double current_bw_Hz, speed_bw_Hz, inertia_kgm2, max_torque_current_A;
    double speed_ramp_rpm_s, speed_filter_Hz, magnetizing_current_A;
    double overcurrent_A, vdc_max_V, vdc_min_V, dead_time_comp, dead_time_band_A;
    double orientation;     /* 0: indirect (IFO), 1: rotor-flux observer (drive_config.h) */
    /* [ident] */
    double filter_cutoff_Hz, euler_passes, paper_regressor, rls_p0, forgetting;
    double magnetize_s, target_speed_rpm, rls_tail_s;
    /* beyond the paper (issue 8), each but the defaults needs orientation 1 */
    double ident_passes;    /* identification passes 1..4 */
    double standstill;   /* 1: Rs measured at standstill before the first acceleration */
    double track_rr;        /* 1: Rr tracked in RUN */
    double track_memory_s;  /* the tracker's forgetting time constant */
    /* [drift]: the thermal-drift scenario (sim_run.h, SCEN_DRIFT) */
    double drift_rr_rise_pct, drift_ramp_s, drift_start_s, drift_load_period_s;
    /* [simulation] */
    double pwm_freq_Hz, sysclk_Hz, substeps;
} sim_config_t;

/** Error text buffer size for sim_config_load. */
#define SIM_CONFIG_ERR_LEN 256

/** Load @p path.  Returns 0 on success; otherwise non-zero with a message
 *  naming the file, the line or key, and the reason in @p err. */
int sim_config_load(const char *path, sim_config_t *cfg, char *err, size_t err_len);

/** Fill the firmware's configuration from the simulator's (what the drive
 *  believes; the nameplate errors applied). */
void sim_config_to_drive(const sim_config_t *cfg, drive_config_t *dc);

/** Print every key with its value, unit and range (for --help / docs). */
void sim_config_print_keys(void);

#endif /* SIM_CONFIG_H */
