/* cgs_log — logging for the main programs (library code never logs). One line
 * per message on stderr with a syslog priority prefix ("<3>") that journald
 * understands, then the program's identity. */
#ifndef CGS_LOG_H
#define CGS_LOG_H

#include <syslog.h>

/* Set the identity printed with every line (e.g. "mtid.uav1"), and the most
 * verbose priority printed (LOG_INFO by default, LOG_DEBUG with -v). */
void cgs_log_init (const char *ident, int max_priority);
/* Log one line at priority (LOG_ERR, LOG_WARNING, LOG_NOTICE, LOG_INFO, LOG_DEBUG). */
void cgs_log (int priority, const char *fmt, ...) __attribute__ ((format (printf, 2, 3)));

#endif
