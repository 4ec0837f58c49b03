/**
 * @file telemetry.c
 * The $T / $C frame protocol (see telemetry.h).
 */
#include <string.h>

#include "telemetry.h"

#define TLM_FRAME_MAX 160u   /* 2 + 6*5 + 11*9 + 5 = 136 characters, margin */

static const char k_hex[16] = {
    '0', '1', '2', '3', '4', '5', '6', '7', '8', '9', 'A', 'B', 'C', 'D', 'E', 'F'
};

/* The wire format is Q24 whatever the build: on the target (IQ_MATH) an _iq
 * is the raw Q GLOBAL_Q integer; FLOAT_MATH (host tests) scales the float. */
static uint32_t tlm_q24(_iq v)
{
#if MATH_TYPE == IQ_MATH
    return (uint32_t)_IQtoIQ24(v);
#else
    return (uint32_t)(int32_t)(v * 16777216.0f);
#endif
}

/* Tr and Tr_track (Q20 pu time: large motors exceed Q24's 128 pu) go on
 * the wire in Q20: as the _iq whose Q24 word is Tr's Q20 word, Tr / 16 (the
 * raw integer as it is in IQ_MATH; the float divided by 16 exactly). */
static _iq tlm_tr(_iq20 tr)
{
#if MATH_TYPE == IQ_MATH
    return (_iq)tr;
#else
    return tr * 0.0625f;
#endif
}

static uint16_t put_hex(uint16_t *f, uint16_t n, uint32_t v, uint16_t digits)
{
    uint16_t i;
    f[n++] = (uint16_t)',';
    for (i = digits; i > 0u; i--) {
        f[n++] = (uint16_t)k_hex[(v >> (4u * (i - 1u))) & 0xFu];
    }
    return n;
}

static uint16_t tx_free(const telemetry_t *t)
{
    /* one slot stays empty to tell full from empty */
    return (uint16_t)((t->tail + TLM_TX_SIZE - t->head - 1u) % TLM_TX_SIZE);
}

/* character i of the TX ring (0 <= i < TLM_TX_SIZE), packed two per word */
static void tx_put(telemetry_t *t, uint16_t i, uint16_t c)
{
    uint16_t *w = &t->tx[i >> 1];
    c = (uint16_t)(c & 0x00FFu);   /* ASCII: the high byte of a 16-bit char is always 0 here */
    if ((i & 1u) == 0u) {
        *w = (uint16_t)((*w & 0xFF00u) | c);
    } else {
        *w = (uint16_t)((*w & 0x00FFu) | (uint16_t)(c << 8));
    }
}

static uint16_t tx_get(const telemetry_t *t, uint16_t i)
{
    const uint16_t w = t->tx[i >> 1];
    return (uint16_t)(((i & 1u) == 0u) ? (w & 0x00FFu) : (w >> 8));
}

void telemetry_init(telemetry_t *t)
{
    memset(t, 0, sizeof *t);
}

/* One frame: '$', the type letter, the 16-bit fields (4 hex digits each),
 * the Q24 fields (8 each), '*', the XOR checksum of the characters between
 * '$' and '*', CR LF.  Queued whole or dropped (counted). */
static uint16_t send_frame(telemetry_t *t, uint16_t type, const uint16_t *u, uint16_t nu,
                           const _iq *q, uint16_t nq)
{
    uint16_t f[TLM_FRAME_MAX];
    uint16_t n = 0u, i, ck = 0u;

    f[n++] = (uint16_t)'$';
    f[n++] = type;
    for (i = 0u; i < nu; i++) {
        n = put_hex(f, n, u[i], 4u);
    }
    for (i = 0u; i < nq; i++) {
        n = put_hex(f, n, tlm_q24(q[i]), 8u);
    }
    for (i = 1u; i < n; i++) {
        ck ^= f[i];
    }
    f[n++] = (uint16_t)'*';
    f[n++] = (uint16_t)k_hex[(ck >> 4) & 0xFu];
    f[n++] = (uint16_t)k_hex[ck & 0xFu];
    f[n++] = (uint16_t)'\r';
    f[n++] = (uint16_t)'\n';

    if (tx_free(t) < n) {
        t->dropped++;
        return 0u;
    }
    for (i = 0u; i < n; i++) {
        tx_put(t, t->head, f[i]);
        t->head = (uint16_t)((t->head + 1u) % TLM_TX_SIZE);
    }
    t->seq++;
    return 1u;
}

uint16_t telemetry_send(telemetry_t *t, const drive_telemetry_t *s, uint16_t isr_load)
{
    const uint16_t u[6] = {t->seq, s->state, s->fault, s->pwm_on, s->params_valid, isr_load};
    const _iq q[TLM_Q24_FIELDS] = {
        s->speed, s->speed_ref, s->i_m, s->i_t, s->vdc,
        s->Rs, s->Rr, s->Lm, s->Lr, s->psi_r, tlm_tr(s->Tr)
    };
    return send_frame(t, (uint16_t)'T', u, 6u, q, TLM_Q24_FIELDS);
}

uint16_t telemetry_send_adapt(telemetry_t *t, const drive_telemetry_t *s)
{
    const uint16_t u[4] = {t->seq, s->pass, s->track_valid, s->params_tracked};
    const _iq q[TLM_ADAPT_Q24_FIELDS] = {s->Rs_dc, s->sigma_ls_dc, s->Rr_track,
                                           tlm_tr(s->Tr_track)};
    return send_frame(t, (uint16_t)'A', u, 4u, q, TLM_ADAPT_Q24_FIELDS);
}

uint16_t telemetry_send_status(telemetry_t *t, const drive_telemetry_t *s, uint16_t isr_load)
{
    const uint16_t u[5] = {t->seq, s->isr_overruns, isr_load, t->dropped, t->rx_errors};
    return send_frame(t, (uint16_t)'S', u, 5u, 0, 0u);
}

uint16_t telemetry_send_quality(telemetry_t *t, const drive_telemetry_t *s)
{
    const uint16_t u[2] = {t->seq, s->publish_reason};
    const _iq q[TLM_QUALITY_Q24_FIELDS] = {s->conf[0], s->conf[1], s->conf[2], s->conf[3],
                                           s->conf[4], s->conf[5], s->conf_residual,
                                           s->conf_amp};
    return send_frame(t, (uint16_t)'Q', u, 2u, q, TLM_QUALITY_Q24_FIELDS);
}

uint16_t telemetry_tx_pop(telemetry_t *t, uint16_t *c)
{
    if (t->tail == t->head) {
        return 0u;
    }
    *c = tx_get(t, t->tail);
    t->tail = (uint16_t)((t->tail + 1u) % TLM_TX_SIZE);
    return 1u;
}

static int16_t hex_val(uint16_t c)
{
    if (c >= (uint16_t)'0' && c <= (uint16_t)'9') { return (int16_t)(c - (uint16_t)'0'); }
    if (c >= (uint16_t)'A' && c <= (uint16_t)'F') { return (int16_t)(c - (uint16_t)'A' + 10u); }
    return -1;
}

static tlm_cmd_t parse_command(telemetry_t *t)
{
    /* rx holds "$C,x*HH" (7 characters) */
    uint16_t ck;
    int16_t hi, lo;
    if (t->rx_len != 7u || t->rx[1] != (uint16_t)'C' || t->rx[2] != (uint16_t)','
        || t->rx[4] != (uint16_t)'*') {
        return TLM_CMD_NONE;
    }
    hi = hex_val(t->rx[5]);
    lo = hex_val(t->rx[6]);
    ck = (uint16_t)(t->rx[1] ^ t->rx[2] ^ t->rx[3]);
    if (hi < 0 || lo < 0 || (uint16_t)((uint16_t)hi * 16u + (uint16_t)lo) != ck) {
        return TLM_CMD_NONE;
    }
    switch (t->rx[3]) {
    case (uint16_t)'S': return TLM_CMD_START;
    case (uint16_t)'X': return TLM_CMD_STOP;
    case (uint16_t)'R': return TLM_CMD_RESET_FAULT;
    case (uint16_t)'D': return TLM_CMD_DLOG_ARM;
    case (uint16_t)'Z': return TLM_CMD_SELECT_STANDSTILL;
    case (uint16_t)'M': return TLM_CMD_SELECT_ROTATING;
    default: return TLM_CMD_NONE;
    }
}

tlm_cmd_t telemetry_rx_byte(telemetry_t *t, uint16_t c)
{
    tlm_cmd_t cmd;
    c &= 0x00FFu;   /* SCIRXBUF carries error flags above bit 7 */
    if (c == (uint16_t)'$') {
        t->rx_len = 0u;
        t->rx[t->rx_len++] = c;
        return TLM_CMD_NONE;
    }
    if (t->rx_len == 0u) {
        return TLM_CMD_NONE;            /* outside a frame */
    }
    if (c == (uint16_t)'\r' || c == (uint16_t)'\n') {
        cmd = parse_command(t);
        if (cmd == TLM_CMD_NONE) {
            t->rx_errors++;
        }
        t->rx_len = 0u;
        return cmd;
    }
    if (t->rx_len >= TLM_RX_SIZE) {
        t->rx_errors++;                 /* too long: drop, wait for '$' */
        t->rx_len = 0u;
        return TLM_CMD_NONE;
    }
    t->rx[t->rx_len++] = c;
    return TLM_CMD_NONE;
}
