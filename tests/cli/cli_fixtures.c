/*
 * Writes the hostile inputs of the motor_sim CLI tests (tests/cli) into one
 * directory: binary and textual garbage, over-long lines, 10 000 keys,
 * output directories that cannot be written, and configurations whose
 * identified set the drive refuses (one per reason).  Everything is deterministic
 * (a fixed LCG, no /dev/urandom), so a failure reproduces.
 *
 *   cli_fixtures OUT_DIR BASE_CONFIG MOTOR_15KW
 *
 * Re-runnable: existing files are overwritten, existing directories kept.
 */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define BASE_MAX 16384
#define N_KEYS 10000

static char g_base[BASE_MAX];
static const char *g_dir;

static void die(const char *what, const char *path)
{
    fprintf(stderr, "cli_fixtures: %s %s: %s\n", what, path, strerror(errno));
    exit(1);
}

static const char *in_dir(const char *name)
{
    static char path[4096];
    if ((size_t)snprintf(path, sizeof path, "%s/%s", g_dir, name) >= sizeof path) {
        fprintf(stderr, "cli_fixtures: path too long\n");
        exit(1);
    }
    return path;
}

static FILE *create(const char *name)
{
    const char *path = in_dir(name);
    FILE *f = fopen(path, "wb");
    if (f == NULL) {
        die("cannot create", path);
    }
    return f;
}

static void finish(FILE *f, const char *name)
{
    if (ferror(f) != 0 || fclose(f) != 0) {
        die("cannot write", in_dir(name));
    }
}

static void make_dir(const char *path)
{
    if (mkdir(path, 0777) != 0 && errno != EEXIST) {
        die("cannot create directory", path);
    }
}

static void make_symlink(const char *target, const char *name)
{
    const char *path = in_dir(name);
    if (unlink(path) != 0 && errno != ENOENT) {
        die("cannot remove", path);
    }
    if (symlink(target, path) != 0) {
        die("cannot link", path);
    }
}

/* A file or an empty directory left by an earlier run, gone. */
static void remove_if_there(const char *name)
{
    const char *path = in_dir(name);
    if (remove(path) != 0 && errno != ENOENT) {
        die("cannot remove", path);
    }
}

/* Numerical Recipes LCG: deterministic bytes for the garbage files. */
static uint32_t g_rng = 12345u;
static unsigned char next_byte(void)
{
    g_rng = g_rng * 1664525u + 1013904223u;
    return (unsigned char)(g_rng >> 24);
}

/* The base configuration with @p len bytes of @p text inserted right after
 * its @p section header line ("[nameplate]\n"). */
static void base_with_after(const char *section, const char *name, const char *text, size_t len)
{
    const char *m = strstr(g_base, section);
    FILE *f;
    size_t head;
    if (m == NULL) {
        fprintf(stderr, "cli_fixtures: no %s line in the base configuration\n", section);
        exit(1);
    }
    head = (size_t)(m - g_base) + strlen(section);
    f = create(name);
    fwrite(g_base, 1, head, f);
    fwrite(text, 1, len, f);
    fputs(g_base + head, f);
    finish(f, name);
}

/* The base configuration with its line that starts with @p key replaced by
 * @p line (a valid file with one value changed). */
static void base_with_line(const char *key, const char *name, const char *line)
{
    const char *m = strstr(g_base, key);
    const char *eol;
    FILE *f;
    if (m == NULL || (eol = strchr(m, '\n')) == NULL) {
        fprintf(stderr, "cli_fixtures: no %s line in the base configuration\n", key);
        exit(1);
    }
    f = create(name);
    fwrite(g_base, 1, (size_t)(m - g_base), f);
    fputs(line, f);
    fputs(eol, f);
    finish(f, name);
}

/* Values inside their keys' own ranges that the plant or the identification
 * cannot use: refused at load, naming the key and the limit. */
static void write_unusable_values(void)
{
    base_with_line("J_kgm2", "tiny_inertia.ini", "J_kgm2 = 1e-7");
    base_with_line("dead_time_s", "dead_time_10us.ini", "dead_time_s = 1e-5");
    base_with_line("dead_time_s", "dead_time_5us_50khz.ini",
                   "dead_time_s = 5e-6\npwm_freq_Hz = 50000");
    base_with_line("magnetize_s", "target_1rpm.ini", "magnetize_s = 0.3\ntarget_speed_rpm = 1");
    base_with_line("magnetize_s", "target_0rpm.ini", "magnetize_s = 0.3\ntarget_speed_rpm = 0");
    base_with_line("Rs_ohm", "subnormal_rs.ini", "Rs_ohm = 1e-320");
    base_with_line("Rs_ohm", "colon_key.ini", "Rs_ohm : 1.031");
}

/* The identification's sequence by name: one that is not a sequence, one the
 * file's own keys contradict; an older file's [inverter] dead_time_s alone
 * (the [board] line dropped, the base's [inverter] given one): a note. */
static void write_sequences(void)
{
    static const char bad[] = "sequence = spinning\n";
    static const char contra[] = "sequence = standstill\npasses = 2\n";
    static const char inv[] = "dead_time_s = 2e-6\n";
    const char *m = strstr(g_base, "dead_time_s");
    const char *eol = (m != NULL) ? strchr(m, '\n') : NULL;
    const char *sec = strstr(g_base, "[inverter]\n");
    FILE *f;
    base_with_after("[ident]\n", "sequence_bad.ini", bad, sizeof bad - 1u);
    base_with_after("[ident]\n", "sequence_contradicted.ini", contra, sizeof contra - 1u);
    if (m == NULL || eol == NULL || sec == NULL || sec < eol) {
        fprintf(stderr, "cli_fixtures: no [board] dead_time_s before [inverter] in the base\n");
        exit(1);
    }
    f = create("old_inverter_dead_time.ini");
    fwrite(g_base, 1, (size_t)(m - g_base), f);
    sec += strlen("[inverter]\n");
    fwrite(eol + 1, 1, (size_t)(sec - (eol + 1)), f);
    fputs(inv, f);
    fputs(sec, f);
    finish(f, "old_inverter_dead_time.ini");
}

static void write_garbage(void)
{
    FILE *f = create("garbage_binary.ini");
    int i;
    for (i = 0; i < 4096; i++) {
        fputc(next_byte(), f);
    }
    fputc('\0', f);   /* at least one NUL whatever the generator gives */
    finish(f, "garbage_binary.ini");

    /* text-like garbage: no NUL, lines of printable and high bytes */
    f = create("garbage_text.ini");
    for (i = 0; i < 4096; i++) {
        unsigned char c = next_byte();
        if (c == 0u) {
            c = 0xFFu;
        }
        fputc((i % 61 == 60) ? '\n' : (int)c, f);
    }
    finish(f, "garbage_text.ini");
}

static void write_long_lines(void)
{
    static char line[100010];
    size_t i;

    /* a 100 000-character comment */
    line[0] = ';';
    for (i = 1; i < 100000; i++) {
        line[i] = 'x';
    }
    line[100000] = '\n';
    line[100001] = '\0';
    base_with_after("[nameplate]\n", "long_comment.ini", line, strlen(line));

    /* a value of 300 characters (trailing zeros of a valid number) */
    snprintf(line, sizeof line, "Rs_ohm = 1.");
    for (i = strlen(line); i < 300; i++) {
        line[i] = '0';
    }
    line[300] = '\n';
    line[301] = '\0';
    base_with_after("[nameplate]\n", "long_value.ini", line, strlen(line));

    /* a comment whose tail, beyond inih's 199-character line buffer, reads as
     * a key that the base file leaves at its default: inih's own reader
     * would silently set load.prop_Nm_s = 5 from a comment */
    line[0] = ';';
    for (i = 1; i < 199; i++) {
        line[i] = '-';
    }
    snprintf(line + 199, sizeof line - 199u, "prop_Nm_s = 5\n");
    base_with_after("[load]\n", "smuggled_key.ini", line, strlen(line));
}

/* A NUL inside a value: a reader that stops at the NUL would take "0". */
static void write_nul_in_value(void)
{
    static const char text[] = "prop_Nm_s = 0\0.5\n";
    base_with_after("[load]\n", "nul_in_value.ini", text, sizeof text - 1u);
}

static void write_many_keys(void)
{
    FILE *f;
    int i;

    f = create("keys_10000_unknown.ini");
    fputs(g_base, f);
    fputs("\n[nameplate]\n", f);
    for (i = 0; i < N_KEYS; i++) {
        fprintf(f, "key%05d = %d\n", i, i);
    }
    finish(f, "keys_10000_unknown.ini");

    f = create("keys_10000_same.ini");
    fputs("[nameplate]\n", f);
    for (i = 0; i < N_KEYS; i++) {
        fputs("Rs_ohm = 1.0\n", f);
    }
    finish(f, "keys_10000_same.ini");

    /* 10 000 comment lines before a valid file: must load */
    f = create("comments_10000.ini");
    for (i = 0; i < N_KEYS; i++) {
        fprintf(f, "; comment %d\n", i);
    }
    fputs(g_base, f);
    finish(f, "comments_10000.ini");
}

static void write_outputs(void)
{
    FILE *f;
    char path[4096];
    int level;

    f = create("empty.ini");
    finish(f, "empty.ini");
    /* an earlier run's results in the --out of a run that fails */
    make_dir(in_dir("out_stale"));
    f = create("out_stale/report.json");
    fputs("{\"config\": \"an earlier run\"}\n", f);
    finish(f, "out_stale/report.json");
    f = create("out_stale/trace.csv");
    fputs("t_s\n0\n", f);
    finish(f, "out_stale/trace.csv");
    f = create("regular_file");
    fputs("not a directory\n", f);
    finish(f, "regular_file");

    /* the config under a name that needs escaping in report.json */
    f = create("quote\"name.ini");
    fputs(g_base, f);
    finish(f, "quote\"name.ini");

    /* --out under a parent that does not exist: motor_sim creates both */
    remove_if_there("no_such_dir/sub/trace.csv");
    remove_if_there("no_such_dir/sub/report.json");
    remove_if_there("no_such_dir/sub");
    remove_if_there("no_such_dir");

    /* trace.csv cannot be created: it is a directory */
    make_dir(in_dir("out_trace_is_dir"));
    make_dir(in_dir("out_trace_is_dir/trace.csv"));

    /* disk full (Linux /dev/full: every write fails with ENOSPC) */
    make_dir(in_dir("out_full_trace"));
    make_symlink("/dev/full", "out_full_trace/trace.csv");
    make_dir(in_dir("out_full_report"));
    make_symlink("/dev/full", "out_full_report/report.json");

    /* an existing directory whose path is longer than motor_sim's buffers */
    snprintf(path, sizeof path, "%s", in_dir("deep"));
    make_dir(path);
    for (level = 0; level < 6; level++) {
        size_t len = strlen(path);
        path[len] = '/';
        memset(path + len + 1, 'd', 200);
        path[len + 201] = '\0';
        make_dir(path);
    }
}

/* The base configuration with @p text appended (keys it does not have; a
 * repeated section continues the first). */
static void base_plus(const char *name, const char *text)
{
    FILE *f = create(name);
    fputs(g_base, f);
    fputs(text, f);
    finish(f, name);
}

/* Runs whose set the drive refuses, one per reason (tests/cli: reason_*) */
static void write_reasons(void)
{
    /* 280 r/min of 1400, the lowest target the INI check accepts (20 % of
     * rated): the excitation 0.18, below the verdict's limit */
    base_plus("reason_low_excitation.ini",
              "\n[ident]\ntarget_speed_rpm = 280\n[sensors]\nhall_noise_A_rms = 0.04\n");
    /* P(0) = 0.001: the RLS hardly leaves theta(0) = 0, the guard never takes it */
    base_plus("reason_not_converged.ini", "\n[ident]\nrls_p0 = 0.001\n");
    /* a viscous load of 2.9 N m at 1400 r/min, beyond the 10 A torque limit: the
     * speed never reaches the target, steady state never comes, the speed loop
     * at its limit (a SETTLE that runs out of time otherwise, timeout:
     * tests/app/test_id_sequence.c) */
    base_plus("reason_torque_limit.ini", "\n[load]\nprop_Nm_s = 0.02\n");
    /* the motor's Rs 0.2 ohm, the nameplate's 1.031: the extraction finds
     * 0.2 ohm, beyond its plausibility range (x0.25 .. x4 of the
     * nameplate), and the set is refused as implausible; nothing trips (a
     * model error refuses a set, it is no fault) */
    {
        static const char rs[] = "Rs_ohm = 0.2\n";
        base_with_after("\n[plant]\n", "reason_implausible.ini", rs, sizeof rs - 1u);
    }
}

/* The 15 kW motor's file with the paper's sequence instead of its own (the
 * adaptive one): w_r Tr 81, Tr's bound above 3 %, low_confidence (each key
 * line of the adaptive sequence replaced). */
static void write_paper_15kw(const char *path)
{
    static char text[BASE_MAX];
    static const char *const from[4] = {"orientation = 1", "standstill = 1", "passes = 2",
                                        "track_rr = 1"};
    static const char *const to[4] = {"orientation = 0", "standstill = 0", "passes = 1",
                                      "track_rr = 0"};
    FILE *f = fopen(path, "rb");
    size_t n;
    unsigned i;
    if (f == NULL) {
        die("cannot open", path);
    }
    n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    for (i = 0; i < 4u; i++) {
        char *m = strstr(text, from[i]);
        if (m == NULL) {
            fprintf(stderr, "cli_fixtures: no '%s' line in %s\n", from[i], path);
            exit(1);
        }
        memcpy(m, to[i], strlen(to[i]));   /* the same length */
    }
    f = create("reason_low_confidence.ini");
    fputs(text, f);
    finish(f, "reason_low_confidence.ini");
}

int main(int argc, char **argv)
{
    FILE *f;
    size_t n;

    if (argc != 4) {
        fprintf(stderr, "usage: cli_fixtures OUT_DIR BASE_CONFIG MOTOR_15KW\n");
        return 2;
    }
    g_dir = argv[1];
    make_dir(g_dir);
    f = fopen(argv[2], "rb");
    if (f == NULL) {
        die("cannot open", argv[2]);
    }
    n = fread(g_base, 1, sizeof g_base - 1, f);
    fclose(f);
    if (n == 0 || n >= sizeof g_base - 1) {
        fprintf(stderr, "cli_fixtures: %s is empty or too large\n", argv[2]);
        return 1;
    }
    g_base[n] = '\0';

    write_garbage();
    write_long_lines();
    write_nul_in_value();
    write_many_keys();
    write_outputs();
    write_unusable_values();
    write_sequences();
    write_reasons();
    write_paper_15kw(argv[3]);
    return 0;
}
