/* Withdraw what was published while a fault developed.  See publish_guard.h. */
#include "publish_guard.h"

#include <string.h>

int16_t publish_guard_init(publish_guard_t *g, uint32_t window_ticks)
{
    memset(g, 0, sizeof *g);
    if (window_ticks < 2u || window_ticks > 0x10000000u) {
        return 1;
    }
    g->window = window_ticks;
    return 0;
}

static uint16_t same(const publish_set_t *a, const publish_set_t *b)
{
    return (uint16_t)(a->Rs == b->Rs && a->Rr == b->Rr && a->Lm == b->Lm && a->Lr == b->Lr &&
                      a->psi_r == b->psi_r && a->Tr == b->Tr && a->valid == b->valid &&
                      a->tracked == b->tracked);
}

/* The newest checkpoint taken at or before t (ticks), or NULL. */
static const publish_set_t *checkpoint_before(const publish_guard_t *g, uint32_t t)
{
    uint16_t i;
    for (i = 0u; i < g->n_cp; i++) {
        if ((int32_t)(t - g->t_cp[i]) >= 0) {
            return &g->cp[i];
        }
    }
    return NULL;
}

uint16_t publish_guard_pass(publish_guard_t *g, publish_set_t *s)
{
    const uint32_t now = g->now;
    const uint16_t code = g->fault_code;
    const uint32_t t_f = g->t_fault;
    uint16_t i;

    if (same(s, &g->last) == 0u) {
        g->last = *s;
        g->t_change = now;
        g->changed_once = 1u;
    }
    if (code == 0u) {
        /* no fault: a checkpoint every window / 2 */
        if (g->n_cp == 0u || (uint32_t)(now - g->t_cp[0]) >= g->window / 2u) {
            for (i = PUBLISH_GUARD_CHECKPOINTS - 1u; i > 0u; i--) {
                g->cp[i] = g->cp[i - 1u];
                g->t_cp[i] = g->t_cp[i - 1u];
            }
            g->cp[0] = *s;
            g->t_cp[0] = now;
            if (g->n_cp < PUBLISH_GUARD_CHECKPOINTS) {
                g->n_cp++;
            }
        }
        return 0u;
    }
    if (g->handled != 0u) {
        return 0u;
    }
    g->handled = 1u;
    /* published within the window before the fault (or after it)? */
    if (g->changed_once != 0u && (int32_t)(g->t_change - (t_f - g->window)) >= 0 &&
        s->valid != 0u) {
        const publish_set_t *back = checkpoint_before(g, t_f - g->window);
        if (back != NULL && back->valid != 0u) {
            *s = *back;
        } else {
            memset(s, 0, sizeof *s);   /* nothing good before: nothing published */
        }
        g->last = *s;
        g->changed_once = 0u;   /* what is back is a checkpoint: nothing new to judge */
        g->reason = code;
        if (g->withdrawn < 0xFFFFu) {
            g->withdrawn++;
        }
        return 1u;
    }
    return 0u;
}

void publish_guard_rearm(publish_guard_t *g)
{
    g->handled = 0u;
    g->fault_code = 0u;
}
