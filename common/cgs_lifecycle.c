/* cgs_lifecycle — signals and systemd notification. */
#include "cgs_lifecycle.h"

#include <errno.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <systemd/sd-daemon.h>

static volatile sig_atomic_t s_stop_signal;
static volatile sig_atomic_t s_stop;
static volatile sig_atomic_t s_reload;

static void s_on_signal (int sig)
{
    if (sig == SIGHUP) {
        s_reload = 1;
        return;
    }
    s_stop_signal = sig;
    s_stop = 1;
}

int cgs_lifecycle_init (void)
{
    struct sigaction sa;
    memset (&sa, 0, sizeof sa);
    sa.sa_handler = s_on_signal;
    sigemptyset (&sa.sa_mask);
    // No SA_RESTART: a blocking zmq_poll returns EINTR and the loop sees the flag.
    if (sigaction (SIGINT, &sa, NULL) < 0 || sigaction (SIGTERM, &sa, NULL) < 0 ||
        sigaction (SIGHUP, &sa, NULL) < 0)
        return -errno;
    signal (SIGPIPE, SIG_IGN);
    return 0;
}

bool cgs_lifecycle_stopping (void)
{
    return s_stop != 0;
}
int cgs_lifecycle_stop_signal (void)
{
    return (int)s_stop_signal;
}
void cgs_lifecycle_request_stop (void)
{
    s_stop = 1;
}

bool cgs_lifecycle_take_reload (void)
{
    if (!s_reload)
        return false;
    s_reload = 0;
    return true;
}

void cgs_notify_ready (const char *status)
{
    sd_notifyf (0, "READY=1\nSTATUS=%s", status ? status : "running");
}

void cgs_notify_status (const char *fmt, ...)
{
    char buf[512];
    va_list ap;
    va_start (ap, fmt);
    vsnprintf (buf, sizeof buf, fmt, ap);
    va_end (ap);
    sd_notifyf (0, "STATUS=%s", buf);
}

void cgs_notify_watchdog (void)
{
    sd_notify (0, "WATCHDOG=1");
}
void cgs_notify_stopping (void)
{
    sd_notify (0, "STOPPING=1");
}

uint64_t cgs_notify_watchdog_usec (void)
{
    uint64_t usec = 0;
    return sd_watchdog_enabled (0, &usec) > 0 ? usec : 0;
}
