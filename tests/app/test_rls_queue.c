/* The RLS in the background on the ISR's queue (drive_rls_bg.c): every
 * sample reaches it once and in order, so that its estimate is bit for bit
 * the one of an RLS stepped in the ISR on the regression's rows; a
 * background that falls behind loses samples by count, never the events.
 *
 * The reference is independent of the queue: an rls_t of its own, stepped
 * right after each ISR whose slow slot formed the rows (FILTERS_C) with the
 * regressor's outputs (d->id.reg) and the sequence's enable, restarted from
 * drive_init's state where the sequence asks for a new pass.  The closed loop runs
 * the paper motor from the start of the identification through the
 * acceleration into RUN (3 s), the background called at irregular
 * intervals of 1 to DRIVE_RLSQ_LEN - 2 slow periods. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "drive_rig.h"

#define PAPER MC_CONFIG_DIR "/paper_motor.ini"

typedef struct {
    drive_rig_t rig;           /* the drive, plant and host HAL (drive_rig.h) */
    rls_t ref;                 /* the reference RLS */
    rls_t start;               /* the RLS as drive_init left it (drive_rls_start's state) */
    uint32_t updates;          /* samples the reference took */
} loop_t;

static loop_t g_loop;

/* One ISR; then the reference takes the same rows the ISR formed. */
static void isr(loop_t *l)
{
    drive_t *d = &l->rig.drive;
    const uint16_t slot = d->sched.slot;   /* the slot this ISR runs */
    drive_rig_sample(&l->rig);
    drive_isr(d);
    drive_slow_isr(d);
    drive_rig_period(&l->rig);
    if (slot == DRIVE_SLOT_SEQUENCE && d->seq.rls_restart != 0u) {
        l->ref = l->start;          /* a new pass (the adaptive sequence only) */
    }
    if (slot == DRIVE_SLOT_FILTERS_C && d->seq.rls_on != 0u) {
        const ident_regressor_t *r = &d->id.reg;
        l->ref.y1 = r->y1;
        l->ref.y2 = r->y2;
        l->ref.i_mf = r->i_mf;
        l->ref.u_mf = r->u_mf;
        l->ref.i_tf = r->i_tf;
        l->ref.u_tf = r->u_tf;
        l->ref.wr_f = r->wr_f;
        l->ref.enable = 1u;
        rls_step(&l->ref);
        l->updates++;
    }
}

static int setup(void **state)
{
    loop_t *l = &g_loop;
    (void)state;
    memset(l, 0, sizeof *l);
    if (drive_rig_start(&l->rig, PAPER) != 0) {
        return -1;
    }
    l->start = l->rig.drive.id.rls;   /* as drive_init left it: each pass's start */
    l->ref = l->start;
    return 0;
}

static void test_every_sample_once_in_order(void **state)
{
    loop_t *l = &g_loop;
    drive_t *d = &l->rig.drive;
    uint32_t next_bg = 15u, lcg = 12345u;
    uint16_t i;
    (void)state;
    while (l->rig.k < 70000u) {   /* 4.67 s: 3 s and the bridge's curve test's 1.65 s */
        isr(l);
        if (l->rig.k >= next_bg) {
            drive_background(d);
            /* 1 .. LEN-2 slow periods until the next call */
            lcg = lcg * 1103515245u + 12345u;
            next_bg = l->rig.k + DRIVE_SLOTS * (1u + (lcg >> 16) % (DRIVE_RLSQ_LEN - 2u));
        }
    }
    drive_background(d);
    /* the identification ran: hundreds of samples, in RUN now */
    assert_true(l->updates > 1000u);
    assert_int_equal(d->seq.state, ID_RUN);
    assert_int_equal(d->id.rlsq.dropped, 0u);
    assert_int_equal(d->telemetry.rls_dropped, 0u);
    assert_true(d->id.rlsq.max_fill <= DRIVE_RLSQ_LEN - 2u);
    for (i = 0u; i < RLS_N; i++) {
        assert_true(d->id.rls.theta[i] == l->ref.theta[i]);   /* bit for bit */
    }
    /* the published set came from the background's snapshot */
    assert_int_equal(d->telemetry.params_valid, 1u);
}

/* A background that stops for longer than the queue: the samples beyond
 * DRIVE_RLSQ_LEN - 1 are dropped and counted; an event raised meanwhile is
 * kept and acts once the background runs again. */
static void test_full_queue_counts_and_keeps_events(void **state)
{
    loop_t *l = &g_loop;
    drive_t *d = &l->rig.drive;
    uint32_t pushes0, pushes;
    uint16_t fill;
    (void)state;
    /* into the acceleration (at 2.02 s, after the bridge's curve test),
     * background at 1 kHz */
    while (d->seq.state != ID_ACCELERATE && l->rig.k < 45000u) {
        isr(l);
        if ((l->rig.k % 15u) == 0u) {
            drive_background(d);
        }
    }
    assert_int_equal(d->seq.state, ID_ACCELERATE);
    drive_background(d);
    assert_int_equal(d->id.rlsq.head, d->id.rlsq.tail);
    pushes0 = l->updates;
    /* no background for 3 queues' worth of slow periods */
    while (l->updates - pushes0 < 3u * DRIVE_RLSQ_LEN) {
        isr(l);
    }
    pushes = l->updates - pushes0;
    fill = (uint16_t)((d->id.rlsq.head - d->id.rlsq.tail) & (DRIVE_RLSQ_LEN - 1u));
    assert_int_equal(fill, DRIVE_RLSQ_LEN - 1u);
    assert_int_equal(d->id.rlsq.dropped, pushes - (DRIVE_RLSQ_LEN - 1u));
    /* an event while full waits for the next free entry */
    d->id.rlsq.pending |= DRIVE_RLSQ_EXTRACT;
    while (d->sched.slot != DRIVE_SLOT_FILTERS_C) {
        isr(l);
    }
    isr(l);   /* FILTERS_B with the queue still full */
    assert_int_equal(d->id.rlsq.pending & DRIVE_RLSQ_EXTRACT, DRIVE_RLSQ_EXTRACT);
    drive_background(d);   /* empties it (the extraction is not due: snap read here) */
    assert_int_equal(d->telemetry.rls_dropped, d->id.rlsq.dropped);
    while (d->sched.slot != DRIVE_SLOT_FILTERS_C) {
        isr(l);
    }
    isr(l);
    assert_int_equal(d->id.rlsq.pending, 0u);   /* rode with this entry */
    drive_background(d);
    assert_int_equal(d->id.rlsq.head, d->id.rlsq.tail);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_every_sample_once_in_order, setup),
        cmocka_unit_test_setup(test_full_queue_counts_and_keeps_events, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
