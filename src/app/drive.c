/* CONTRACT STUB of the drive application: compiles, does nothing useful yet. */
#include "drive_types.h"

#include <string.h>

int16_t drive_init(drive_t *d, const drive_config_t *cfg)
{
    (void)cfg;
    memset(d, 0, sizeof *d);
    return 0;
}

void drive_step(drive_t *d, const hal_adc_sample_t *adc, uint16_t qep_count,
                hal_pwm_compare_t *out)
{
    (void)adc;
    (void)qep_count;
    *out = d->cmp;
}

void drive_isr(drive_t *d)
{
    hal_adc_sample_t adc;
    hal_pwm_compare_t cmp;
    hal_adc_read(&adc);
    drive_step(d, &adc, hal_qep_read_count(), &cmp);
    hal_pwm_write(&cmp);
}

void drive_background(drive_t *d) { d->pending_cmd = DRIVE_CMD_NONE; }
void drive_command(drive_t *d, drive_cmd_t cmd) { d->pending_cmd = cmd; }
void drive_get_telemetry(const drive_t *d, drive_telemetry_t *t) { *t = d->telemetry; }
