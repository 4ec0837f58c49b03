/**
 * @file drive_limits.h
 * One table of the limits a drive_config_t must meet: the range of every
 * field, then the derived limits the drive's modules need (the PWM period in
 * timer counts, Tr within the Q24 time base, the QEP scaling, the loop
 * gains, the sensor scaling, ...).  drive_init() validates through it before
 * it initialises anything; the simulator's INI check (host_sim/sim) reads the
 * same table for the drive-side keys.  So both refuse the same values and
 * name the same key, its value and the limit.
 *
 * Keys are those of the INI file the board configuration is generated from
 * ("section.key", e.g. "nameplate.Rs_ohm"); a derived limit is named by its
 * quantity ("Tr", "T1PR", ...) and says in `why` which keys make it.
 *
 * Float: configuration and initialisation code only, never the ISR.
 */
#ifndef DRIVE_LIMITS_H
#define DRIVE_LIMITS_H

#include <stdint.h>
#include "drive_config.h"

/** Where a limit's value comes from (drive_limit_t.kind). */
#define DRIVE_LIMIT_F32 0u       /* a float field of drive_config_t */
#define DRIVE_LIMIT_U16 1u       /* a uint16_t field (whole numbers only) */
#define DRIVE_LIMIT_DERIVED 2u   /* a quantity computed from several fields */

/** Open ends (drive_limit_t.open, drive_limit_fail_t.open). */
#define DRIVE_LIMIT_LO_OPEN 1u
#define DRIVE_LIMIT_HI_OPEN 2u

/** The derived limits (drive_limit_t.where of a DRIVE_LIMIT_DERIVED entry),
 *  in the order drive_init meets them (drive_limits.c: how each is checked).
 *  What each is, in words, and which keys make it: host_sim/sim/sim_limits.c
 *  (the text stays off the target). */
typedef enum {
    DRIVE_LD_LLS = 0, DRIVE_LD_LLR, DRIVE_LD_IM_RATED,
    DRIVE_LD_T1PR,
    DRIVE_LD_VDC_FS, DRIVE_LD_QEP_RES, DRIVE_LD_SPEED_FILT,
    DRIVE_LD_LS_Q24, DRIVE_LD_LR_Q24, DRIVE_LD_WC_PU, DRIVE_LD_CUR_KP, DRIVE_LD_CUR_KI,
    DRIVE_LD_IMAX, DRIVE_LD_SPD_KP, DRIVE_LD_SPD_KI, DRIVE_LD_RAMP,
    DRIVE_LD_IMR, DRIVE_LD_TR, DRIVE_LD_FTS, DRIVE_LD_SLIP,
    DRIVE_LD_OBS_FBASE, DRIVE_LD_OBS_PWM, DRIVE_LD_OBS_RS, DRIVE_LD_OBS_LM, DRIVE_LD_OBS_LR,
    DRIVE_LD_OBS_LS, DRIVE_LD_OBS_SLS,
    DRIVE_LD_DEAD, DRIVE_LD_DROP, DRIVE_LD_VI_HOLD, DRIVE_LD_VI_GAINS,
    DRIVE_LD_BAND,
    DRIVE_LD_FILT, DRIVE_LD_FILT_WB, DRIVE_LD_FILT_STEP,
    DRIVE_LD_K1, DRIVE_LD_K2, DRIVE_LD_K3, DRIVE_LD_K4,
    DRIVE_LD_PE_RS, DRIVE_LD_PE_RR, DRIVE_LD_PE_LM, DRIVE_LD_PE_LR, DRIVE_LD_PE_PSI,
    DRIVE_LD_FEATURES, DRIVE_LD_STANDSTILL, DRIVE_LD_TRACKER, DRIVE_LD_STATIC,
    DRIVE_LD_PERIOD_MEAN,
    DRIVE_LD_TARGET, DRIVE_LD_TARGET_PU, DRIVE_LD_BUS, DRIVE_LD_HEADROOM,
    DRIVE_LD_OC_FS, DRIVE_LD_TORQUE_OC, DRIVE_LD_VDC_MIN, DRIVE_LD_VDC_MAX, DRIVE_LD_ENC_JUMP,
    DRIVE_LD_COUNT
} drive_derived_limit_t;

/* The limits' names and units: DRIVE_LIMITS_NAMES 0 builds them as ""
 * (a small target without the room for the text: refusals keep their
 * status, value and range, not the key's name; the 8 KB AVR co-simulation). */
#ifndef DRIVE_LIMITS_NAMES
#define DRIVE_LIMITS_NAMES 1
#endif
#if DRIVE_LIMITS_NAMES
#define DRIVE_LT(s) (s)
#else
#define DRIVE_LT(s) ""
#endif

typedef struct {
    const char *key;     /* INI key or derived quantity */
    const char *unit;    /* of lo, hi (and of the value reported) */
    int16_t status;      /* the drive_cfg_status_t drive_init returns when it fails */
    uint16_t kind;       /* DRIVE_LIMIT_F32, _U16, _DERIVED */
    uint16_t where;      /* fields: offset in drive_config_t; derived: drive_derived_limit_t */
    uint16_t open;       /* DRIVE_LIMIT_LO_OPEN | DRIVE_LIMIT_HI_OPEN */
    float lo, hi;        /* fields: the range; derived: the range where it is a constant,
                            otherwise computed from the configuration (lo > hi here) */
} drive_limit_t;

/** The first limit a configuration fails, as the user should read it. */
typedef struct {
    const drive_limit_t *limit;   /* the entry that failed */
    const char *key;     /* its key, or the key a derived limit found at fault */
    const char *unit;
    float value;         /* the value found, in unit */
    float lo, hi;        /* the range it must lie in, in unit */
    uint16_t open;
    int16_t status;      /* drive_cfg_status_t; 0 when nothing failed */
} drive_limit_fail_t;

/** Number of entries; entry @p i (NULL beyond the end). */
uint16_t drive_limits_count(void);
const drive_limit_t *drive_limit_get(uint16_t i);

/** The first entry named @p key, or NULL: a field's own range comes first;
 *  a key that is not a field (nameplate.Lls_H, ident.filter_cutoff_Hz, T1PR,
 *  ...) finds its first derived limit. */
const drive_limit_t *drive_limit_find(const char *key);

/** 1 if @p v lies in field limit @p l's range (NaN does not). */
int16_t drive_limit_field_ok(const drive_limit_t *l, float v);

/**
 * Check @p c against every limit: the field ranges first, then the derived
 * limits in the order drive_init meets them.  Returns 0 (DRIVE_CFG_OK), or
 * the status of the first failed limit with @p fail (may be NULL) filled.
 */
int16_t drive_config_check(const drive_config_t *c, drive_limit_fail_t *fail);

#endif /* DRIVE_LIMITS_H */
