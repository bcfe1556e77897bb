/* cgs_lifecycle — signals, clean stop, and systemd notification (READY,
 * STATUS, WATCHDOG, STOPPING) through libsystemd, which does nothing when the
 * process is not run by systemd. The stop flag is process-wide state, as a
 * signal handler needs. */
#ifndef CGS_LIFECYCLE_H
#define CGS_LIFECYCLE_H

#include <stdbool.h>
#include <stdint.h>

/* Catch SIGINT and SIGTERM (stop) and SIGHUP (noted for the program to act on:
 * services log that there is nothing to reload, `mscgs run` stops); ignore
 * SIGPIPE. 0 or -errno. */
int cgs_lifecycle_init (void);
/* True once a stop was asked for, by a signal or cgs_lifecycle_request_stop. */
bool cgs_lifecycle_stopping (void);
/* The signal that asked to stop, 0 if none. */
int cgs_lifecycle_stop_signal (void);
/* Ask the process to stop (from code). */
void cgs_lifecycle_request_stop (void);
/* True once per SIGHUP received since the last call. */
bool cgs_lifecycle_take_reload (void);

/* Tell systemd the service is ready, with a status line. */
void cgs_notify_ready (const char *status);
/* Tell systemd a status line ("running: 3 tracks"). */
void cgs_notify_status (const char *fmt, ...) __attribute__ ((format (printf, 1, 2)));
/* Ping the watchdog (call from the event loop, so a wedged loop stops pinging). */
void cgs_notify_watchdog (void);
/* Tell systemd the service is stopping. */
void cgs_notify_stopping (void);
/* The watchdog interval systemd asked for, microseconds; 0 when none. */
uint64_t cgs_notify_watchdog_usec (void);

#endif
