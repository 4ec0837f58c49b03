/**
 * @file drive_types.h
 * The full drive_t, so that the application can own an instance
 * (`static drive_t g_drive;` in firmware/main.c, one per instance on the host).
 * (CONTRACT STUB: the members are filled in by the integration work.)
 */
#ifndef DRIVE_TYPES_H
#define DRIVE_TYPES_H

#include "drive.h"

struct drive {
    drive_telemetry_t telemetry;
    drive_cmd_t pending_cmd;
    hal_pwm_compare_t cmp;
};

#endif /* DRIVE_TYPES_H */
