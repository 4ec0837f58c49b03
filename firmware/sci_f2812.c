/**
 * @file sci_f2812.c
 * SCI-A FIFO pump (SPRU051).  Polled: at 115200 baud a 16-character FIFO
 * drains in 1.4 ms, and the background loop runs far more often than that,
 * so no interrupt is needed and the ISR timing is untouched.
 */
#include "DSP281x_Device.h"
#include "sci_f2812.h"

#define SCI_FIFO_DEPTH 16u

void sci_f2812_init(uint16_t brr)
{
    SciaRegs.SCICCR.all = 0x0007u;        /* 1 stop, no parity, 8 bits, async */
    SciaRegs.SCICTL1.all = 0x0003u;       /* TXENA, RXENA, held in reset */
    SciaRegs.SCICTL2.all = 0x0000u;       /* no SCI interrupts */
    SciaRegs.SCIHBAUD = (uint16_t)(brr >> 8);
    SciaRegs.SCILBAUD = (uint16_t)(brr & 0x00FFu);
    /* FIFO enhancements on, both FIFOs reset then released */
    SciaRegs.SCIFFTX.all = 0xC000u;       /* SCIRST = 1, SCIFFENA = 1, TX FIFO in reset */
    SciaRegs.SCIFFRX.all = 0x0000u;       /* RX FIFO in reset */
    SciaRegs.SCIFFCT.all = 0x0000u;
    SciaRegs.SCIFFTX.bit.TXFIFOXRESET = 1u;
    SciaRegs.SCIFFRX.bit.RXFIFORESET = 1u;
    SciaRegs.SCIPRI.bit.FREE = 1u;        /* keep running on an emulator halt */
    SciaRegs.SCICTL1.bit.SWRESET = 1u;    /* out of reset */
}

/* A receive error (framing, parity, overrun or a break: RXERROR is their
 * OR, SCIRXST) stops the SCI receiver until the SCI is reset: a line break
 * or noise on the cable would otherwise end every command, $C,X (stop)
 * included.  SWRESET 0 -> 1 clears the flags and the receiver state (the
 * configuration stays), and the RX FIFO is flushed; the characters lost
 * belong to a frame the checksum would have rejected. */
static void sci_recover(telemetry_t *t)
{
    SciaRegs.SCICTL1.bit.SWRESET = 0u;
    SciaRegs.SCIFFRX.bit.RXFIFORESET = 0u;
    SciaRegs.SCIFFRX.bit.RXFIFORESET = 1u;
    SciaRegs.SCICTL1.bit.SWRESET = 1u;
    if (t->rx_errors < 0xFFFFu) {
        t->rx_errors++;
    }
    t->rx_len = 0u;   /* the frame under way is lost */
}

tlm_cmd_t sci_f2812_poll(telemetry_t *t)
{
    tlm_cmd_t last = TLM_CMD_NONE;
    uint16_t c;

    if (SciaRegs.SCIRXST.bit.RXERROR != 0u || SciaRegs.SCIRXST.bit.BRKDT != 0u) {
        sci_recover(t);
    }

    while (SciaRegs.SCIFFTX.bit.TXFFST < SCI_FIFO_DEPTH && telemetry_tx_pop(t, &c) != 0u) {
        SciaRegs.SCITXBUF = c;
    }
    while (SciaRegs.SCIFFRX.bit.RXFFST != 0u) {
        tlm_cmd_t cmd = telemetry_rx_byte(t, SciaRegs.SCIRXBUF.all);
        if (cmd != TLM_CMD_NONE) {
            last = cmd;
        }
    }
    if (SciaRegs.SCIFFRX.bit.RXFFOVF != 0u) {
        SciaRegs.SCIFFRX.bit.RXFFOVRCLR = 1u;   /* lost characters: the
                                                   checksum rejects the frame */
    }
    return last;
}
