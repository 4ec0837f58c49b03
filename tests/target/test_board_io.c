/* target_board_io: the board's own pins and the reset path, run on the
 * host against the shim's registers as memory (firmware/gpio_mux.c and
 * firmware/sysctrl.c through tests/target/reg_seam.h, which logs what each
 * register held at every access of the firmware):
 *
 *  - the fault LED on GPIOF14 is active low (the pin is XPLLDIS at reset:
 *    the LED goes from 3.3 V to the pin, docs/board.md): on = GPFCLEAR,
 *    off = GPFSET, and gpio_mux_init sets the latch high (LED off) before
 *    the pin becomes an output;
 *  - sysctrl_reset_now (an unexpected interrupt, pie.c) enables the watchdog
 *    at its fastest with the right check bits, then writes WDCR with wrong
 *    ones: a reset at once, or at the latest at the watchdog's overflow,
 *    whether or not the watchdog was enabled before. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#define REG_SEAM_NO_MACROS
#include "reg_seam.h"
#include "gpio_mux.h"
#include "sysctrl.h"

/* what the firmware reaches directly, and through the seam */
volatile struct GPIO_MUX_REGS GpioMuxRegs;
static volatile struct GPIO_DATA_REGS s_gpio_data;
static volatile struct SYS_CTRL_REGS s_sysctrl;
static volatile struct EVA_REGS s_eva;

#define LOG_N 16u
static uint16_t s_wdcr_log[LOG_N];    /* WDCR at each SysCtrlRegs access */
static uint16_t s_n_sys;
static uint16_t s_dir_at[LOG_N];      /* GPFDIR.14 at each GpioDataRegs access */
static uint16_t s_n_gpio;

volatile struct EVA_REGS *reg_seam_eva(void)
{
    return &s_eva;
}

volatile struct SYS_CTRL_REGS *reg_seam_sysctrl(void)
{
    if (s_n_sys < LOG_N) {
        s_wdcr_log[s_n_sys] = s_sysctrl.WDCR;
    }
    s_n_sys++;
    return &s_sysctrl;
}

volatile struct GPIO_DATA_REGS *reg_seam_gpio_data(void)
{
    /* is the pin still an input at this access (the latch's write)? */
    if (s_n_gpio < LOG_N) {
        s_dir_at[s_n_gpio] = GpioMuxRegs.GPFDIR.bit.GPIOF14;
    }
    s_n_gpio++;
    return &s_gpio_data;
}

static void clear_regs(void)
{
    memset((void *)&GpioMuxRegs, 0, sizeof GpioMuxRegs);
    memset((void *)&s_gpio_data, 0, sizeof s_gpio_data);
    memset((void *)&s_sysctrl, 0, sizeof s_sysctrl);
    memset(s_wdcr_log, 0, sizeof s_wdcr_log);
    s_n_sys = 0u;
    memset(s_dir_at, 0, sizeof s_dir_at);
    s_n_gpio = 0u;
}

static void test_led_off_before_output(void **state)
{
    (void)state;
    clear_regs();
    gpio_mux_init();
    assert_int_equal(GpioMuxRegs.GPFMUX.bit.XF_GPIOF14, 0u);   /* GPIO, not XF */
    assert_int_equal(GpioMuxRegs.GPFDIR.bit.GPIOF14, 1u);
    assert_int_equal(s_gpio_data.GPFSET.bit.GPIOF14, 1u);      /* latch high: off */
    assert_int_equal(s_gpio_data.GPFCLEAR.bit.GPIOF14, 0u);    /* never driven low */
    /* one data access, the latch's, made while the pin was an input */
    assert_int_equal(s_n_gpio, 1u);
    assert_int_equal(s_dir_at[0], 0u);
    /* the SCI-A pins stay the SCI's (GPIOF4 is also a boot-mode pin) */
    assert_int_equal(GpioMuxRegs.GPFMUX.bit.SCITXDA_GPIOF4, 1u);
}

static void test_led_active_low(void **state)
{
    (void)state;
    clear_regs();
    gpio_fault_led(1u);
    assert_int_equal(s_gpio_data.GPFCLEAR.all, 0x4000u);   /* GPIOF14 low: on */
    assert_int_equal(s_gpio_data.GPFSET.all, 0u);
    clear_regs();
    gpio_fault_led(0u);
    assert_int_equal(s_gpio_data.GPFSET.all, 0x4000u);     /* high: off */
    assert_int_equal(s_gpio_data.GPFCLEAR.all, 0u);
}

/* WDCR (SPRU078): WDDIS bit 6, WDCHK bits 5:3 (101 on every valid write),
 * WDPS bits 2:0 */
#define WDCR_WDDIS 0x0040u
#define WDCR_CHK_MASK 0x0038u
#define WDCR_CHK_OK 0x0028u

static void test_reset_now(void **state)
{
    (void)state;
    clear_regs();
    s_sysctrl.WDCR = 0x0068u;            /* disabled, as during the start-up */
    sysctrl_reset_now();
    /* the value before the last access is the first write: enabled, right
     * check bits, fastest prescale */
    assert_true(s_n_sys >= 2u);
    assert_int_equal(s_wdcr_log[s_n_sys - 1u] & WDCR_WDDIS, 0u);
    assert_int_equal(s_wdcr_log[s_n_sys - 1u] & WDCR_CHK_MASK, WDCR_CHK_OK);
    assert_int_equal(s_wdcr_log[s_n_sys - 1u] & 0x0007u, 0u);
    /* the last write: wrong check bits */
    assert_int_not_equal(s_sysctrl.WDCR & WDCR_CHK_MASK, WDCR_CHK_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_led_off_before_output),
        cmocka_unit_test(test_led_active_low),
        cmocka_unit_test(test_reset_now),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
