/* Shared helper of the tests that step the drive's ISR period by period
 * themselves (to set the host HAL's flags per ISR, or to watch the drive's
 * state between ISRs): the paper motor's drive, plant and host HAL, bound
 * and started; one sample before each drive_isr, one plant period after. */
#ifndef DRIVE_RIG_H
#define DRIVE_RIG_H

#include <stdint.h>
#include <string.h>

#include "drive_probe.h"
#include "hal_host.h"
#include "plant.h"
#include "sim_config.h"

typedef struct {
    drive_t drive;
    drive_probe_t pv;           /* what the rig reads of it */
    plant_t plant;
    hal_host_port_t port;
    hal_pwm_compare_t active;   /* the compares the plant runs this period */
    uint32_t k;                 /* ISRs */
} drive_rig_t;

/* Zeroed, the drive and the plant from @p ini, the host HAL bound, the
 * identification started.  0, or -1 if the file or either init fails. */
static inline int drive_rig_start(drive_rig_t *r, const char *ini)
{
    sim_config_t cfg;
    drive_config_t dc;
    char err[SIM_CONFIG_ERR_LEN];
    memset(r, 0, sizeof *r);
    if (sim_config_load(ini, &cfg, err, sizeof err) != 0) {
        return -1;
    }
    sim_config_to_drive(&cfg, &dc);
    drive_probe(&r->drive, &r->pv);
    if (drive_init(&r->drive, &dc) != DRIVE_CFG_OK ||
        plant_init(&r->plant, &cfg, r->pv.k->t1pr, err, sizeof err) != 0) {
        return -1;
    }
    hal_host_port_init(&r->port, r->pv.k->t1pr);
    hal_host_bind(&r->port);
    r->active = r->port.cmp;
    drive_command(&r->drive, DRIVE_CMD_START_IDENT);
    drive_background(&r->drive);
    return 0;
}

/* The period's start: the plant sampled into the host HAL, PDPINTA high. */
static inline void drive_rig_sample(drive_rig_t *r)
{
    plant_sample(&r->plant, &r->port);
    r->port.trip_input = 0u;
}

/* The period after the ISR: the plant runs it on the compares loaded at
 * its start; the ISR's new compares take effect at the next one. */
static inline void drive_rig_period(drive_rig_t *r)
{
    plant_period(&r->plant, &r->active, r->port.outputs_enabled);
    r->active = r->port.cmp;
    r->k++;
}

#endif /* DRIVE_RIG_H */
