/* Co-simulation harness of the whole ISR core: drive_init with the target's
 * own board configuration (board_config.c, generated from the INI), then a fixed sequence of
 * raw ADC samples and QEP counts through drive_step, built for the host and
 * for the AVR (16-bit int) from the same sources.
 *
 * What is compared: the init status and the published telemetry after init
 * (category I: float arithmetic in drive_init, where avr-libc and glibc may
 * differ in the last bit of expf/sqrtf: reported as an INIT mismatch), then
 * per step the three compare values and, every 8th step, the telemetry
 * signals (category S: fixed point only, must be bit-identical).
 * The raw inputs are generated with integer arithmetic only. */
#include <stdint.h>

#include "board_config.h"
#include "cosim_io.h"
#include "drive_types.h"

#if MATH_TYPE != IQ_MATH
#error "the co-simulation compares the fixed-point build"
#endif

#define STEPS 1200u

/* The HAL is not used by drive_step; drive_isr references it. */
void hal_adc_read(hal_adc_sample_t *s) { s->ia_raw = 0x8000u; s->ib_raw = 0x8000u; s->vdc_raw = 0x8000u; }
void hal_pwm_write(const hal_pwm_compare_t *c) { (void)c; }
void hal_pwm_enable(void) {}
void hal_pwm_disable(void) {}
uint16_t hal_pwm_tripped(void) { return 0u; }
uint16_t hal_isr_overrun(void) { return 0u; }
void hal_slow_isr_request(void) {}
uint16_t hal_qep_read_count(void) { return 0u; }

static uint16_t s_rng = 0x1D2Bu;
static uint16_t rng16(void)
{
    s_rng ^= (uint16_t)(s_rng << 7);
    s_rng ^= (uint16_t)(s_rng >> 9);
    s_rng ^= (uint16_t)(s_rng << 8);
    return s_rng;
}

/* A triangle wave of integer period, amplitude +-a ADC codes, phase p. */
static int32_t tri(uint16_t n, uint16_t period, uint16_t p, int32_t a)
{
    uint16_t k = (uint16_t)((uint16_t)(n + p) % period);
    int32_t half = (int32_t)(period / 2u);
    int32_t x = (k < period / 2u) ? (int32_t)k : (int32_t)(period - k);
    return (a * (2 * x - half)) / half;
}

static drive_t s_drive;

static void print_telemetry(char tag, uint16_t n)
{
    drive_telemetry_t t;
    int32_t v[8];
    drive_get_telemetry(&s_drive, &t);
    v[0] = (int32_t)t.state | ((int32_t)t.fault << 16);
    v[1] = (int32_t)t.pwm_on | ((int32_t)t.params_valid << 16);
    v[2] = (int32_t)t.speed; v[3] = (int32_t)t.i_m; v[4] = (int32_t)t.i_t;
    v[5] = (int32_t)t.vdc;   v[6] = (int32_t)t.Rs;  v[7] = (int32_t)t.Tr;
    cosim_print(tag, n, v, 8u);
}

int main(void)
{
    hal_adc_sample_t adc;
    hal_pwm_compare_t cmp;
    int32_t v[4];
    uint16_t n, qep = 0u;

    cosim_io_init();
    v[0] = (int32_t)drive_init(&s_drive, &g_board_config);
    cosim_print('I', 0u, v, 1u);
    print_telemetry('I', 1u);

    drive_command(&s_drive, DRIVE_CMD_START_IDENT);
    drive_background(&s_drive);

    for (n = 0u; n < STEPS; n++) {
        /* ~10 A peak currents at ~50 Hz (300 samples), 12-bit codes left-
         * justified as the F2812 ADC leaves them; the DC bus at ~60 V */
        int32_t ia = 2048 + tri(n, 300u, 0u, 1000) + (int32_t)(rng16() & 7u) - 4;
        int32_t ib = 2048 + tri(n, 300u, 100u, 1000) + (int32_t)(rng16() & 7u) - 4;
        int32_t vd = 2457 + (int32_t)(rng16() & 15u) - 8;
        adc.ia_raw = (uint16_t)((uint16_t)ia << 4);
        adc.ib_raw = (uint16_t)((uint16_t)ib << 4);
        adc.vdc_raw = (uint16_t)((uint16_t)vd << 4);
        qep = (uint16_t)(qep + (uint16_t)(n / 100u));   /* accelerating encoder */

        drive_step(&s_drive, &adc, qep, &cmp);
        v[0] = (int32_t)cmp.cmpr[0]; v[1] = (int32_t)cmp.cmpr[1]; v[2] = (int32_t)cmp.cmpr[2];
        cosim_print('S', n, v, 3u);
        if ((n & 7u) == 0u) {
            print_telemetry('T', n);
        }
        if ((n % 15u) == 0u) {
            drive_background(&s_drive);
        }
    }
    cosim_io_end();
    return 0;
}
