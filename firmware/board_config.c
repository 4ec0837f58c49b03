/**
 * @file board_config.c
 * The const drive configuration for the paper's motor on this board.  Read
 * once, by drive_init() and by the peripheral set-up (T1PR, dead band);
 * nothing in the ISR path reads it.
 */
#include "board_config.h"

const drive_config_t g_board_config = {
    .motor = {
        .Rs_ohm = 1.031f,              /* method §6, Table 1 reference */
        .Rr_ohm = 0.465f,
        .Lm_H = 6.4e-3f,
        .Ls_H = 9.2e-3f,
        .Lr_H = 9.2e-3f,
        .pole_pairs = 2u,
        .rated_speed_rpm = 1400.0f,
        .rated_current_A_rms = 9.0f,
        .rated_freq_Hz = 50.0f,
        .magnetizing_current_A = 6.5625f,  /* psi_r / Lm = 0.042 Wb / 6.4 mH */
    },
    .board = {
        .sysclk_Hz = 150.0e6f,
        .pwm_freq_Hz = 15.0e3f,        /* T1PR = 150e6 / (2 * 15e3) = 5000 */
        .dead_time_s = 1.0e-6f,        /* DBTCONA: DBTPS = /16, DBT = 10 -> 1.067 us */
        .device_drop_V = 0.3f,
        .dead_time_comp = 1u,
        .dead_time_band_A = 0.1f,      /* measured on the bridge at commissioning */
        .vdc_nominal_V = 60.0f,
        .vdc_adc_full_scale_V = 100.0f,/* divider: 100 V reads 3.0 V */
        .current_full_scale_A = 20.0f, /* Hall: +-20 A -> 0..3 V */
        .encoder_lines = 1000u,        /* x4 in the QEP: 4000 counts/rev */
        .overcurrent_A = 18.0f,
        .vdc_max_V = 80.0f,
        .vdc_min_V = 40.0f,
    },
    .control = {
        .current_bw_Hz = 500.0f,
        .speed_bw_Hz = 8.0f,
        .max_torque_current_A = 10.0f,
        .inertia_kgm2 = 1.0e-3f,
        .speed_ramp_rpm_s = 1400.0f,
        .speed_filter_Hz = 100.0f,
        .orientation = DRIVE_ORIENT_IFO,   /* the paper's; DRIVE_ORIENT_FLUX_OBS for a
                                              nameplate that is not trusted (README, issue 8) */
    },
    .ident = {
        .filter_wc_rad_s = 62.831853f, /* 2 pi 10 Hz (method §5) */
        .euler_passes = 10u,
        .paper_regressor = 0u,         /* constant regressor (method §7.3) */
        .rls_p0 = 1.0e6f,
        .forgetting = 1.0f,
        .magnetize_time_s = 0.3f,      /* >= 5 Tr = 99 ms */
        .target_speed_rpm = 1400.0f,
        /* the paper's sequence; with .orientation = DRIVE_ORIENT_FLUX_OBS the adaptive one
         * is .standstill = 1u, .passes = 2u, .track_rr = 1u (README: within 3 % from a
         * nameplate 30 % off, Rr tracked as the rotor warms) */
        .passes = 1u,
        .standstill = 0u,
        .track_rr = 0u,
        .track_memory_s = 1.0f,
    },
};
