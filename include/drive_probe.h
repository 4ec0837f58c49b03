/**
 * @file drive_probe.h
 * A read-only view of one drive instance for what lives outside the
 * application layer: the simulator's observers and trace, the C API, the
 * cost model and the black-box tests.  They read the drive through const
 * pointers to its rooms (drive_types.h), never drive_t's members, so that
 * the application layer can move a field between rooms without touching
 * them; nothing can be written through the view.
 *
 * drive_probe fills the pointers (they stay valid as long as the instance;
 * the values read through them are live).  The firmware does not call it
 * (it reads the drive through drive_get_telemetry, drive.h); it is in the
 * image only as the rest of src/app is (a few words of flash).
 */
#ifndef DRIVE_PROBE_H
#define DRIVE_PROBE_H

#include "drive_types.h"

typedef struct {
    const base_values_t *base;
    const drive_consts_t *k;
    const drive_schedule_t *sched;
    const drive_sense_t *sense;
    const drive_loops_t *loop;
    const drive_frame_t *frame;
    const drive_pwm_t *pwm;
    const drive_protections_t *prot;
    const id_sequence_t *seq;
    const drive_target_t *target;
    const drive_bridge_test_t *vi;
    const drive_adaptation_t *adapt;
    const drive_ident_path_t *id;
    const drive_verdict_t *verdict;
    const drive_telemetry_t *telemetry;
} drive_probe_t;

/** Fills @p p with the rooms of @p d (no copy; both non-NULL). */
void drive_probe(const drive_t *d, drive_probe_t *p);

#endif /* DRIVE_PROBE_H */
