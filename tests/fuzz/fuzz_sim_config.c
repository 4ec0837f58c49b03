/*
 * Fuzz target: the simulator's INI parser (sim_config_load) on arbitrary
 * bytes, through a temporary file (sim_config_load takes a path, as
 * motor_sim does).
 *
 * Properties (beyond "no undefined behaviour", checked by ASan/UBSan):
 *   - a rejected file gives a non-empty message that names the file, and
 *     never says that drive_init refused what the table of limits
 *     (drive_limits.h) let through: each refusal names a key and a limit;
 *   - an accepted file gives a configuration whose every value is finite,
 *     and sim_config_to_drive + drive_init accept it (the INI check and
 *     drive_init share the table: they agree), and the drive then runs 64
 *     ISR periods with compare values in [0, T1PR].
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "drive_probe.h"
#include "fuzz_target.h"
#include "sim_config.h"

static char g_path[64];
static FILE *g_file;
static drive_t g_drive;
static unsigned long g_accepted, g_rejected;      /* by the parser */

void fuzz_fail(const char *what, unsigned long step, long value, long limit)
{
    fprintf(stderr, "fuzz_sim_config: %s (%lu: %ld, limit %ld); input left in %s\n", what, step,
            value, limit, g_path);
    abort();
}

static void remove_temp(void)
{
    if (g_file != NULL) {
        (void)fclose(g_file);
        (void)unlink(g_path);
    }
}

/* One temporary file per process, rewritten for each input. */
static const char *write_temp(const uint8_t *data, size_t size)
{
    if (g_file == NULL) {
        const char *dir = getenv("TMPDIR");
        int fd;
        snprintf(g_path, sizeof g_path, "%s/fuzz_ini_XXXXXX",
                 (dir != NULL && strlen(dir) < 40u) ? dir : "/tmp");
        fd = mkstemp(g_path);
        if (fd < 0 || (g_file = fdopen(fd, "w+b")) == NULL) {
            perror("fuzz_sim_config: temporary file");
            abort();
        }
        atexit(remove_temp);
    }
    if (fseek(g_file, 0L, SEEK_SET) != 0 || ftruncate(fileno(g_file), 0) != 0 ||
        (size > 0u && fwrite(data, 1, size, g_file) != size) || fflush(g_file) != 0) {
        perror("fuzz_sim_config: write");
        abort();
    }
    return g_path;
}

static void check_accepted(const sim_config_t *cfg)
{
    const double *v = (const double *)(const void *)cfg;
    size_t i, n = sizeof *cfg / sizeof(double);
    drive_config_t dc;
    hal_adc_sample_t adc = {0x8000u, 0x8000u, 0x9990u};   /* zero current, 60 V of 100 V */
    hal_pwm_compare_t out;
    drive_probe_t pv;
    int16_t st;

    for (i = 0; i < n; i++) {
        if (!isfinite(v[i])) {
            fuzz_fail("accepted configuration holds a non-finite value", i, 0L, 0L);
        }
    }
    sim_config_to_drive(cfg, &dc);
    st = drive_init(&g_drive, &dc);
    if (st != DRIVE_CFG_OK) {
        fuzz_fail("drive_init refused what the INI check accepted", 0, (long)st, 0L);
    }
    drive_command(&g_drive, DRIVE_CMD_START_IDENT);
    drive_background(&g_drive);
    drive_probe(&g_drive, &pv);
    for (i = 0; i < 64u; i++) {
        unsigned j;
        drive_step(&g_drive, &adc, (uint16_t)i, &out);
        for (j = 0; j < 3u; j++) {
            if (out.cmpr[j] > pv.k->t1pr) {
                fuzz_fail("compare value above T1PR", i, (long)out.cmpr[j], (long)pv.k->t1pr);
            }
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sim_config_t cfg;
    char err[SIM_CONFIG_ERR_LEN];
    const char *path = write_temp(data, size);
    int rc;

    err[0] = '\0';
    rc = sim_config_load(path, &cfg, err, sizeof err);
    if (rc == SIM_CONFIG_ERR_UNLISTED) {
        fuzz_fail("drive_init refused a file no limit of the table names", 0, 0L, 0L);
    }
    if (rc == 0) {
        g_accepted++;
        check_accepted(&cfg);
    } else {
        g_rejected++;
        if (strncmp(err, path, strlen(path)) != 0 || strlen(err) <= strlen(path) + 2u) {
            fuzz_fail("an error message must name the file and say what is wrong", 0,
                      (long)strlen(err), 0L);
        }
    }
    return 0;
}

int fuzz_corpus_check(void)
{
    printf("fuzz_sim_config: parser (and drive_init) accepted %lu, rejected %lu\n", g_accepted,
           g_rejected);
    if (g_accepted == 0u || g_rejected == 0u) {
        fprintf(stderr, "fuzz_sim_config: the corpus must hold accepted and rejected files\n");
        return 1;
    }
    return 0;
}
