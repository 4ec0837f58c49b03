/* The drive's limits in words.  See sim_limits.h. */
#include "sim_limits.h"

#include <float.h>
#include <string.h>

/* Bases (base_values.h): I_base = board.current_full_scale_A, V_base =
 * board.vdc_nominal_V / sqrt(3), w_base = 2 pi nameplate.rated_freq_Hz,
 * Z_base = V_base / I_base, L_base = Z_base / w_base, psi_base = V_base /
 * w_base. */
static const char *const k_why[DRIVE_LD_COUNT] = {
    [DRIVE_LD_LLS] = "stator leakage: the believed Ls - Lm",
    [DRIVE_LD_LLR] = "rotor leakage: the believed Lr - Lm",
    [DRIVE_LD_IM_RATED] = "below the rated peak current sqrt(2) nameplate.rated_current_A",
    [DRIVE_LD_T1PR] = "the PWM period in EV-A timer counts, "
                      "board.sysclk_Hz / (2 board.pwm_freq_Hz)",
    [DRIVE_LD_VDC_FS] = "the bus reading below 64 V_base in Q24",
    [DRIVE_LD_QEP_RES] = "QEP speed scaling: one count a PWM period below 1 pu of speed, i.e. more "
                         "than nameplate.pole_pairs board.pwm_freq_Hz / "
                         "(4 nameplate.rated_freq_Hz) lines",
    [DRIVE_LD_SPEED_FILT] = "below half the slow task's rate, board.pwm_freq_Hz / (2 DRIVE_SLOTS)",
    [DRIVE_LD_LS_Q24] = "nameplate.Lm_H + nameplate.Lls_H in Q24: below 127 L_base",
    [DRIVE_LD_LR_Q24] = "nameplate.Lm_H + nameplate.Llr_H in Q24: below 127 L_base",
    [DRIVE_LD_WC_PU] = "in Q24: below 127 nameplate.rated_freq_Hz",
    [DRIVE_LD_CUR_KP] = "2 pi controller.current_bw_Hz sigma Ls / Z_base",
    [DRIVE_LD_CUR_KI] = "current-loop Kp nameplate.Rs_ohm / (sigma Ls board.pwm_freq_Hz)",
    [DRIVE_LD_IMAX] = "at most the current sensors' full scale board.current_full_scale_A",
    [DRIVE_LD_SPD_KP] = "2 pi controller.speed_bw_Hz controller.inertia_kgm2 w_base / "
                        "(p Kt I_base), Kt = 1.5 p Lm^2/Lr controller.magnetizing_current_A",
    [DRIVE_LD_SPD_KI] = "speed-loop Kp 2 pi controller.speed_bw_Hz Ts_slow / 4, Ts_slow = DRIVE_SLOTS / board.pwm_freq_Hz (the slow task)",
    [DRIVE_LD_RAMP] = "the speed reference's step a slow-task period (DRIVE_SLOTS PWM periods) between 2^-20 and 1 pu",
    [DRIVE_LD_IMR] = "the orientation's least flux current 0.2 i_M at most "
                     "board.current_full_scale_A",
    [DRIVE_LD_TR] = "the believed rotor time constant (nameplate.Lm_H + nameplate.Llr_H) / "
                    "nameplate.Rr_ohm: at least 10 PWM periods, at most 120/w_base (the Q24 "
                    "time base, w_base = 2 pi nameplate.rated_freq_Hz)",
    [DRIVE_LD_FTS] = "PWM periods per electrical period at rated frequency (the frame angle "
                     "step in Q30, its inverse in Q20)",
    [DRIVE_LD_SLIP] = "Tr w_base x 0.2 controller.magnetizing_current_A / "
                      "board.current_full_scale_A: the slip of 2 pu of torque current "
                      "within 64 pu",
    [DRIVE_LD_OBS_FBASE] = "with controller.orientation = 1: the observer's 3 Hz crossover "
                           "within 1 pu",
    [DRIVE_LD_OBS_PWM] = "with controller.orientation = 1: the observer steps every 8 PWM "
                         "periods (DRIVE_SLOTS); its 200 Hz low-pass at most 1 rad a step and "
                         "the believed Tr at least 10 steps",
    [DRIVE_LD_OBS_RS] = "with controller.orientation = 1: at most 4 Z_base",
    [DRIVE_LD_OBS_LM] = "with controller.orientation = 1: at most 16 L_base",
    [DRIVE_LD_OBS_LR] = "with controller.orientation = 1: (nameplate.Lm_H + nameplate.Llr_H) / "
                        "nameplate.Lm_H in (1, 4]",
    [DRIVE_LD_OBS_LS] = "with controller.orientation = 1: nameplate.Lm_H + nameplate.Lls_H "
                        "above nameplate.Lm_H, at most 32 L_base",
    [DRIVE_LD_OBS_SLS] = "with controller.orientation = 1: Ls - Lm^2/Lr of the nameplate in "
                         "(0, 4 L_base]",
    [DRIVE_LD_DEAD] = "at most a quarter of the PWM period",
    [DRIVE_LD_DROP] = "at most V_base = board.vdc_nominal_V / sqrt(3)",
    [DRIVE_LD_VI_GAINS] = "the bridge test's current PI (ident.vi_test = 1): its gains within "
                          "the PI's range (ki = 2 pi 50 Hz Ts_slow nameplate.Rs_ohm / Z_base "
                          "at most 1, kp at most 100)",
    [DRIVE_LD_VI_HOLD] = "the believed Tr at most 65535 slow periods / 6 (the bridge's curve "
                         "test holds a level 6 Tr in a 16-bit count)",
    [DRIVE_LD_BAND] = "with ident.vi_test = 0: the fallback zone (3 codes of the current channel, "
                      "at least 0.1 A) between 0.0005 and 1 times board.current_full_scale_A",
    [DRIVE_LD_FILT] = "the regression's Butterworth corner",
    [DRIVE_LD_FILT_WB] = "below 4 nameplate.rated_freq_Hz",
    [DRIVE_LD_FILT_STEP] = "the improved-Euler step 2 pi f DRIVE_SLOTS / board.pwm_freq_Hz at most 0.3 (the filters run in the slow task)",
    [DRIVE_LD_K1] = "-K1 of the believed motor (method §2), for the estimator guard, inside "
                    "the RLS's range",
    [DRIVE_LD_K2] = "K2 = 1/sigma Ls of the believed motor, for the estimator guard, inside "
                    "the RLS's range",
    [DRIVE_LD_K3] = "K3 (K3' with ident.paper_regressor) of the believed motor, for the "
                    "estimator guard, inside the RLS's range",
    [DRIVE_LD_K4] = "-K4 of the believed motor, for the estimator guard, inside the RLS's range",
    [DRIVE_LD_PE_RS] = "the extraction's plausibility range (x0.25 .. x4) in Q24: below 480 Z_base",
    [DRIVE_LD_PE_RR] = "the extraction's plausibility range (x0.25 .. x4) in Q24: below 480 Z_base",
    [DRIVE_LD_PE_LM] = "the extraction's plausibility range (x0.25 .. x4) in Q24: below 480 L_base",
    [DRIVE_LD_PE_LR] = "nameplate.Lm_H + nameplate.Llr_H: the extraction's plausibility range "
                       "(x0.25 .. x4) in Q24, below 480 L_base",
    [DRIVE_LD_PE_PSI] = "nameplate.Lm_H controller.magnetizing_current_A: the extraction's range "
                        "(x4) in Q24, below 31.75 psi_base",
    [DRIVE_LD_FEATURES] = "ident.passes > 1, ident.standstill and ident.track_rr need the "
                          "rotor-flux observer",
    [DRIVE_LD_STANDSTILL] = "the standstill test (ident.standstill = 1): its injection at "
                            "0.4 controller.current_bw_Hz (at most 400 Hz) of 15 % of i_M, and "
                            "the test with its pause in the second half of ident.magnetize_s",
    [DRIVE_LD_TRACKER] = "the Rr/Tr tracker (ident.track_rr = 1): its range Tr/4 .. 4 Tr within "
                         "30 pu of 1/Tr, and its guard",
    [DRIVE_LD_STATIC] = "the standstill sequence (ident.static_id = 1, [ident] sequence = "
                        "standstill): ident.standstill = 1, ident.passes = 1, ident.track_rr = 0, "
                        "and its multisine's period (4 pi Tr) within 64 .. 2^20 samples of the "
                        "slow task",
    [DRIVE_LD_PERIOD_MEAN] = "the period-mean regression (ident.period_mean = 1) regresses on "
                             "ifo's rotor flux: it needs controller.orientation = 0 and "
                             "ident.paper_regressor = 0",
    [DRIVE_LD_TARGET] = "what the identification can use: at least the largest of 20 % of "
                        "nameplate.rated_speed_rpm (the RLS's back-EMF excitation), 10 encoder "
                        "counts a time constant of the regression's filter (150 (2 pi "
                        "ident.filter_cutoff_Hz) / board.encoder_lines r/min) and, with "
                        "controller.orientation = 1, the RLS's 30 Hz stator-frequency gate "
                        "(1800 / nameplate.pole_pairs r/min); at most 1.2 "
                        "nameplate.rated_speed_rpm (-1 in the INI: the rated speed, or less "
                        "where the bus cannot carry it)",
    [DRIVE_LD_TARGET_PU] = "within the speed reference's 2 pu "
                           "(60 nameplate.rated_freq_Hz / nameplate.pole_pairs r/min a pu)",
    [DRIVE_LD_BUS] = "the no-load voltage |Rs + j w Ls| controller.magnetizing_current_A at "
                     "the target plus the bridge's loss (2 board.device_drop_V + vdc "
                     "board.dead_time_s board.pwm_freq_Hz) within 92 % of "
                     "board.vdc_nominal_V / sqrt(3); by default (-1) at the least target with Ls / "
                     "1.3 (a nameplate's Lm may be 30 % high): the drive lowers its target to "
                     "what the bus it measures gives",
    [DRIVE_LD_HEADROOM] = "the dead time against the voltage at the target speed: what the "
                          "bridge loses per leg, board.vdc_nominal_V board.dead_time_s "
                          "board.pwm_freq_Hz + board.device_drop_V, at most 30 % of the "
                          "believed motor's no-load phase voltage there, "
                          "|Rs + j w Ls| controller.magnetizing_current_A (beyond, the "
                          "compensated reference clips once the motor is loaded)",
    [DRIVE_LD_OC_FS] = "below the current sensors' full scale board.current_full_scale_A",
    [DRIVE_LD_TORQUE_OC] = "at most the trip level controller.overcurrent_A",
    [DRIVE_LD_VDC_MIN] = "below board.vdc_nominal_V",
    [DRIVE_LD_VDC_MAX] = "above board.vdc_nominal_V, below the bus reading's full scale "
                         "board.vdc_full_scale_V",
    [DRIVE_LD_ENC_JUMP] = "the encoder check's jump at 4 pu, 2 to 16384 counts a PWM period",
};

const char *sim_limit_why(unsigned which)
{
    return (which < (unsigned)DRIVE_LD_COUNT && k_why[which] != NULL) ? k_why[which] : "";
}

void sim_limit_range(char *buf, size_t len, float lo, float hi, unsigned open)
{
    char h[32];
    if (hi >= FLT_MAX) {
        snprintf(h, sizeof h, "inf)");
    } else {
        snprintf(h, sizeof h, "%g%c", (double)hi, (open & DRIVE_LIMIT_HI_OPEN) ? ')' : ']');
    }
    snprintf(buf, len, "%c%g, %s", (open & DRIVE_LIMIT_LO_OPEN) ? '(' : '[', (double)lo, h);
}

/* A key of the INI file ("section.key") or a derived quantity ("Tr"). */
static int is_ini_key(const char *key)
{
    return strchr(key, '.') != NULL && strchr(key, ' ') == NULL;
}

void sim_limit_message(char *buf, size_t len, const drive_limit_fail_t *f)
{
    sim_limit_message_value(buf, len, f, (double)f->value);
}

void sim_limit_message_value(char *buf, size_t len, const drive_limit_fail_t *f, double value)
{
    char range[80];
    const char *unit = (strcmp(f->unit, "-") == 0) ? "" : f->unit;
    const char *why = (f->limit != NULL && f->limit->kind == DRIVE_LIMIT_DERIVED)
                          ? sim_limit_why(f->limit->where) : "";
    sim_limit_range(range, sizeof range, f->lo, f->hi, f->open);
    snprintf(buf, len, "%s%s%s = %g%s%s is outside %s%s%s%s%s", is_ini_key(f->key) ? "key '" : "",
             f->key, is_ini_key(f->key) ? "'" : "", value, unit[0] ? " " : "", unit,
             range, unit[0] ? " " : "", unit, why[0] ? ": " : "", why);
}

void sim_limits_print(FILE *f)
{
    uint16_t i;
    fprintf(f, "derived limits (drive_init and the INI check; I_base = "
               "board.current_full_scale_A, V_base = board.vdc_nominal_V / sqrt(3),\n"
               "w_base = 2 pi nameplate.rated_freq_Hz, Z_base = V_base / I_base, "
               "L_base = Z_base / w_base):\n");
    for (i = 0u; i < drive_limits_count(); i++) {
        const drive_limit_t *l = drive_limit_get(i);
        char range[80] = "";
        if (l->kind != DRIVE_LIMIT_DERIVED) {
            continue;
        }
        if (l->lo <= l->hi) {
            sim_limit_range(range, sizeof range, l->lo, l->hi, l->open);
        }
        fprintf(f, "  %-32s %-16s %s\n", l->key, range, sim_limit_why(l->where));
    }
}
