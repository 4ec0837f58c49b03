/* The drive side of the INI file as the firmware's drive_config_t: the one
 * conversion the simulator runs the firmware with and board_config_gen
 * writes into the board's board_config.c.  See sim_config.h. */
#include "sim_config.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* Saturating conversions: a value the INI check would refuse (a test may
 * set one directly) still converts without undefined behaviour, and the
 * drive's table of limits then refuses it. */
static float f32(double v)
{
    if (v > FLT_MAX) {
        return FLT_MAX;
    }
    return (v < -FLT_MAX) ? -FLT_MAX : (float)v;
}

static uint16_t u16(double v)
{
    if (!(v >= 0.0)) {
        return 0u;   /* also NaN */
    }
    if (v > 65535.0) {
        return 65535u;
    }
    return (uint16_t)v;
}

void sim_config_to_drive(const sim_config_t *c, drive_config_t *d)
{
    const sim_nameplate_t *n = &c->nameplate;
    const sim_board_t *b = &c->board;
    const sim_controller_t *k = &c->controller;
    const sim_ident_t *id = &c->ident;

    memset(d, 0, sizeof *d);
    d->motor.Rs_ohm = f32(n->Rs_ohm);
    d->motor.Rr_ohm = f32(n->Rr_ohm);
    d->motor.Lm_H = f32(n->Lm_H);
    d->motor.Ls_H = f32(n->Lm_H + n->Lls_H);
    d->motor.Lr_H = f32(n->Lm_H + n->Llr_H);
    d->motor.pole_pairs = u16(n->pole_pairs);
    d->motor.rated_speed_rpm = f32(n->rated_speed_rpm);
    d->motor.rated_current_A_rms = f32(n->rated_current_A);
    d->motor.rated_freq_Hz = f32(n->rated_freq_Hz);
    d->motor.magnetizing_current_A = f32(k->magnetizing_current_A);

    d->board.sysclk_Hz = f32(b->sysclk_Hz);
    d->board.pwm_freq_Hz = f32(b->pwm_freq_Hz);
    d->board.dead_time_s = f32(b->dead_time_s);
    d->board.device_drop_V = f32(b->device_drop_V);
    d->board.dead_time_comp = u16(k->dead_time_comp);
    /* the linear zone is measured (ident.vi_test, the default) and set by
     * nobody; with the test switched off the drive falls back to 3 codes of
     * the current channel (the zone a sensor can resolve), at least 0.1 A
     * (a small bridge's: its output capacitance swings the pole within a
     * 1 us dead time above ~0.1 A, inverter_model.h) */
    d->board.dead_time_band_A =
        f32(fmax(3.0 * 2.0 * b->current_full_scale_A / 4096.0, SIM_FALLBACK_BAND_A));
    d->board.vdc_nominal_V = f32(b->vdc_nominal_V);
    d->board.vdc_adc_full_scale_V = f32(b->vdc_full_scale_V);
    d->board.current_full_scale_A = f32(b->current_full_scale_A);
    d->board.encoder_lines = u16(b->encoder_lines);
    d->board.overcurrent_A = f32(k->overcurrent_A);
    d->board.vdc_max_V = f32(k->vdc_max_V);
    d->board.vdc_min_V = f32(k->vdc_min_V);

    d->control.current_bw_Hz = f32(k->current_bw_Hz);
    d->control.speed_bw_Hz = f32(k->speed_bw_Hz);
    d->control.inertia_kgm2 = f32(k->inertia_kgm2);
    d->control.max_torque_current_A = f32(k->max_torque_current_A);
    d->control.speed_ramp_rpm_s = f32(k->speed_ramp_rpm_s);
    d->control.speed_filter_Hz = f32(k->speed_filter_Hz);
    d->control.orientation = u16(k->orientation);

    d->ident.filter_wc_rad_s = f32(2.0 * M_PI * id->filter_cutoff_Hz);
    d->ident.euler_passes = u16(id->euler_passes);
    d->ident.paper_regressor = u16(id->paper_regressor);
    d->ident.period_mean = u16(id->period_mean);
    d->ident.rls_p0 = f32(id->rls_p0);
    d->ident.forgetting = f32(id->forgetting);
    d->ident.magnetize_time_s = f32(id->magnetize_s);
    /* the default, the rated speed within the bus: the drive's 0 (drive_target.h) */
    d->ident.target_speed_rpm =
        (id->target_speed_rpm == SIM_TARGET_RATED) ? 0.0f : f32(id->target_speed_rpm);
    d->ident.rls_tail_s = f32(id->rls_tail_s);
    d->ident.passes = u16(id->passes);
    d->ident.standstill = u16(id->standstill);
    d->ident.vi_test = u16(id->vi_test);
    d->ident.track_rr = u16(id->track_rr);
    d->ident.static_id = u16(id->static_id);
    d->ident.track_memory_s = f32(id->track_memory_s);
}
