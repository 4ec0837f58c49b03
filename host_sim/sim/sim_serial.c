/* The board's serial link over a pseudo-terminal.  See sim_serial.h. */
#ifndef _XOPEN_SOURCE
#define _XOPEN_SOURCE 700   /* posix_openpt, grantpt, unlockpt, ptsname */
#endif
#include "sim_serial.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include "bg_loop.h"
#include "board_config.h"   /* BOARD_SCI_BAUD */
#include "hal_host.h"

#define RX_CHUNK 256u
#define TX_CHUNK 64u
#define TX_BUDGET_MAX 64.0   /* characters a UART may owe after a pause */

struct sim_serial {
    bg_loop_t bg;                 /* the board's protocol rings and frame timer */
    int master;
    char slave[128];
    char link[1024];
    int have_link;
    double factor;
    double chars_per_s;
    double tx_budget;             /* characters the nominal UART may send now */
    double t_last;                /* simulated time of the last call */
    int started;
    double t0;                    /* simulated time at the first call */
    struct timespec wall0;        /* wall clock then */
    unsigned char rx[RX_CHUNK];
    size_t rx_len, rx_pos;        /* read from the pty, not yet parsed */
    unsigned char tx[TX_CHUNK];
    size_t tx_len;                /* taken from the ring, not yet written */
    int connected, ever_connected, keep_open;
    const char *end_reason;
    uint32_t cmds, frames;
};

static volatile sig_atomic_t g_stop;

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

static void set_err(char *err, size_t len, const char *what, const char *detail)
{
    if (err != NULL && len > 0u) {
        (void)snprintf(err, len, "%s%s%s", what, detail != NULL ? ": " : "",
                       detail != NULL ? detail : "");
    }
}

static speed_t baud_constant(uint32_t baud)
{
    switch (baud) {
    case 9600u: return B9600;
    case 19200u: return B19200;
    case 38400u: return B38400;
    case 57600u: return B57600;
    case 230400u: return B230400;
    default: return B115200;
    }
}

/* Raw 8N1 at the nominal rate on the slave side (the termios of a pty pair
 * lives while the master is open; a client such as pyserial sets its own). */
static int configure_slave(const char *name, uint32_t baud, char *err, size_t err_len)
{
    struct termios tio;
    int fd = open(name, O_RDWR | O_NOCTTY);
    if (fd < 0) {
        set_err(err, err_len, name, strerror(errno));
        return -1;
    }
    if (tcgetattr(fd, &tio) != 0) {
        set_err(err, err_len, "tcgetattr", strerror(errno));
        (void)close(fd);
        return -1;
    }
    cfmakeraw(&tio);
    tio.c_cflag |= (tcflag_t)(CLOCAL | CREAD);
    (void)cfsetispeed(&tio, baud_constant(baud));
    (void)cfsetospeed(&tio, baud_constant(baud));
    if (tcsetattr(fd, TCSANOW, &tio) != 0) {
        set_err(err, err_len, "tcsetattr", strerror(errno));
        (void)close(fd);
        return -1;
    }
    /* closing it leaves the master in the "no client" state until one opens */
    (void)close(fd);
    return 0;
}

/* PATH -> /dev/pts/N.  An old symlink (a previous run) is replaced; anything
 * else at PATH is left alone and refused. */
static int make_link(sim_serial_t *s, const char *path, char *err, size_t err_len)
{
    struct stat st;
    size_t n = strlen(path);
    if (n == 0u || n >= sizeof s->link) {
        set_err(err, err_len, "--serial path empty or too long", NULL);
        return -1;
    }
    if (lstat(path, &st) == 0) {
        if (!S_ISLNK(st.st_mode)) {
            set_err(err, err_len, path, "exists and is not a symlink (not replaced)");
            return -1;
        }
        if (unlink(path) != 0) {
            set_err(err, err_len, path, strerror(errno));
            return -1;
        }
    }
    if (symlink(s->slave, path) != 0) {
        set_err(err, err_len, path, strerror(errno));
        return -1;
    }
    memcpy(s->link, path, n + 1u);
    s->have_link = 1;
    return 0;
}

sim_serial_t *sim_serial_open(const sim_serial_options_t *o, char *err, size_t err_len)
{
    sim_serial_t *s;
    struct sigaction sa;
    const char *name;
    int flags;

    uint32_t baud;

    if (o == NULL || o->link_path == NULL || !(o->realtime_factor >= 0.0)) {
        set_err(err, err_len, "bad serial options", NULL);
        return NULL;
    }
    s = (sim_serial_t *)calloc(1u, sizeof *s);
    if (s == NULL) {
        set_err(err, err_len, "out of memory", NULL);
        return NULL;
    }
    baud = (o->baud != 0u) ? o->baud : (uint32_t)BOARD_SCI_BAUD;
    bg_loop_init(&s->bg, BG_TLM_PERIOD_TICKS);
    s->factor = o->realtime_factor;
    s->chars_per_s = (double)baud / 10.0;   /* 8N1: 10 bits a character */
    s->keep_open = (o->keep_open != 0u);
    s->end_reason = "duration";
    s->master = posix_openpt(O_RDWR | O_NOCTTY);
    if (s->master < 0) {
        set_err(err, err_len, "posix_openpt", strerror(errno));
        free(s);
        return NULL;
    }
    name = (grantpt(s->master) == 0 && unlockpt(s->master) == 0) ? ptsname(s->master) : NULL;
    if (name == NULL || strlen(name) >= sizeof s->slave) {
        set_err(err, err_len, "cannot unlock the pty", strerror(errno));
        sim_serial_close(s);
        return NULL;
    }
    memcpy(s->slave, name, strlen(name) + 1u);
    flags = fcntl(s->master, F_GETFL);
    if (flags < 0 || fcntl(s->master, F_SETFL, flags | O_NONBLOCK) != 0 ||
        configure_slave(s->slave, baud, err, err_len) != 0 ||
        make_link(s, o->link_path, err, err_len) != 0) {
        if (flags < 0) {
            set_err(err, err_len, "fcntl", strerror(errno));
        }
        sim_serial_close(s);
        return NULL;
    }
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    (void)sigemptyset(&sa.sa_mask);
    g_stop = 0;
    (void)sigaction(SIGINT, &sa, NULL);
    (void)sigaction(SIGTERM, &sa, NULL);
    return s;
}

const char *sim_serial_slave_name(const sim_serial_t *s) { return s->slave; }

const char *sim_serial_end_reason(const sim_serial_t *s) { return s->end_reason; }

void sim_serial_counts(const sim_serial_t *s, uint32_t *cmds, uint32_t *frames, uint16_t *dropped,
                       uint16_t *rx_errors)
{
    *cmds = s->cmds;
    *frames = s->frames;
    *dropped = s->bg.tlm.dropped;
    *rx_errors = s->bg.tlm.rx_errors;
}

/* Hold the wall clock at (t - t0) / factor from the first call. */
static void pace(sim_serial_t *s, double t)
{
    struct timespec target;
    double dt;
    if (s->factor <= 0.0) {
        return;
    }
    if (!s->started) {
        (void)clock_gettime(CLOCK_MONOTONIC, &s->wall0);
        s->t0 = t;
        s->started = 1;
        return;
    }
    dt = (t - s->t0) / s->factor;
    target.tv_sec = s->wall0.tv_sec + (time_t)dt;
    target.tv_nsec = s->wall0.tv_nsec + (long)((dt - (double)(time_t)dt) * 1e9);
    if (target.tv_nsec >= 1000000000L) {
        target.tv_sec++;
        target.tv_nsec -= 1000000000L;
    }
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &target, NULL) == EINTR) {
        if (g_stop) {
            return;
        }
    }
}

/* The UART side of sci_f2812_poll: characters from the ring to the pty at
 * the nominal rate.  A full pty (a client that does not read) keeps them
 * here; the ring then fills and drops whole frames, counted, as on the board. */
static void transmit(sim_serial_t *s)
{
    uint16_t c;
    ssize_t n;
    if (s->tx_len == 0u) {
        while (s->tx_len < TX_CHUNK && (double)s->tx_len + 1.0 <= s->tx_budget &&
               telemetry_tx_pop(&s->bg.tlm, &c) != 0u) {
            s->tx[s->tx_len++] = (unsigned char)c;
        }
    }
    if (s->tx_len == 0u) {
        return;
    }
    n = write(s->master, s->tx, s->tx_len);
    if (n > 0) {
        s->tx_len -= (size_t)n;
        memmove(s->tx, s->tx + n, s->tx_len);
        s->tx_budget -= (double)n;
    }
}

/* With nobody on the port the characters leave the UART all the same. */
static void discard_tx(sim_serial_t *s)
{
    uint16_t c;
    while (telemetry_tx_pop(&s->bg.tlm, &c) != 0u) {
    }
    s->tx_len = 0u;
    s->tx_budget = 0.0;
}

/* The RX side: bytes into the firmware's parser up to the first complete
 * command, which is applied; the rest waits for the next pass (after the next
 * drive_background, which acts on the command), so no command overwrites
 * another before the drive has seen it.  Returns 0, or -1 when the pty has
 * nothing more to give and no client (read: EIO). */
static int receive(sim_serial_t *s, drive_t *d)
{
    if (s->rx_pos == s->rx_len) {
        ssize_t n = read(s->master, s->rx, sizeof s->rx);
        s->rx_pos = 0u;
        s->rx_len = (n > 0) ? (size_t)n : 0u;
        if (n < 0 && errno != EAGAIN && errno != EINTR) {
            return -1;   /* EIO: every slave descriptor closed, nothing left */
        }
    }
    while (s->rx_pos < s->rx_len) {
        tlm_cmd_t cmd = telemetry_rx_byte(&s->bg.tlm, (uint16_t)s->rx[s->rx_pos++]);
        if (cmd != TLM_CMD_NONE) {
            if (cmd == TLM_CMD_RESET_FAULT) {
                (void)hal_host_clear_trip(NULL);   /* the board's latch first (main.c) */
            }
            bg_loop_apply(d, NULL, cmd);   /* no data log on the host: $C,D arms nothing */
            s->cmds++;
            break;
        }
    }
    return 0;
}

int sim_serial_hook(void *ctx, drive_t *d, uint64_t isr_count, double t_s)
{
    sim_serial_t *s = (sim_serial_t *)ctx;
    struct pollfd pfd;
    int hup, gone;
    drive_telemetry_t tl;

    if (g_stop) {
        s->end_reason = "signal";
        return 1;
    }
    pace(s, t_s);
    s->tx_budget += (t_s - s->t_last) * s->chars_per_s;
    if (s->tx_budget > TX_BUDGET_MAX) {
        s->tx_budget = TX_BUDGET_MAX;
    }
    s->t_last = t_s;

    pfd.fd = s->master;
    pfd.events = POLLIN;
    pfd.revents = 0;
    (void)poll(&pfd, 1u, 0);
    hup = (pfd.revents & POLLHUP) != 0;
    if (!hup) {
        s->connected = 1;
        s->ever_connected = 1;
        transmit(s);
    }
    /* what a client wrote just before it closed is still read (and its
     * commands applied) before the close counts */
    gone = receive(s, d) != 0;
    if (hup) {
        discard_tx(s);
        if (s->connected && gone) {
            s->connected = 0;
            if (!s->keep_open) {
                s->end_reason = "port closed by the client";
                return 1;
            }
        }
    }
    if (bg_loop_frame_due(&s->bg, (uint16_t)isr_count) != 0u) {
        bg_loop_send(&s->bg, d, 0u, &tl);   /* no ISR load measurement on the host */
        s->frames++;
    }
    return 0;
}

void sim_serial_close(sim_serial_t *s)
{
    char target[sizeof s->slave];
    ssize_t n;
    if (s == NULL) {
        return;
    }
    if (s->have_link) {
        /* only our own link: another run may have taken the name since */
        n = readlink(s->link, target, sizeof target - 1u);
        if (n > 0) {
            target[n] = '\0';
            if (strcmp(target, s->slave) == 0) {
                (void)unlink(s->link);
            }
        }
    }
    if (s->master >= 0) {
        (void)close(s->master);
    }
    free(s);
}
