/* The read-only view of a drive (drive_probe.h): what the simulator, the C
 * API and the tests may read. */
#include "drive_probe.h"

void drive_probe(const drive_t *d, drive_probe_t *p)
{
    p->base = &d->base;
    p->k = &d->k;
    p->sched = &d->sched;
    p->sense = &d->sense;
    p->loop = &d->loop;
    p->frame = &d->frame;
    p->pwm = &d->pwm;
    p->prot = &d->prot;
    p->seq = &d->seq;
    p->target = &d->target;
    p->vi = &d->vi;
    p->adapt = &d->adapt;
    p->id = &d->id;
    p->verdict = &d->verdict;
    p->telemetry = &d->telemetry;
}
