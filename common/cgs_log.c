/* cgs_log — stderr logging with syslog priority prefixes. The identity is
 * process-wide state, set once by main. */
#include "cgs_log.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

static char s_ident[64] = "mscgs";
static int s_max = LOG_INFO;

void cgs_log_init (const char *ident, int max_priority)
{
    snprintf (s_ident, sizeof s_ident, "%s", ident ? ident : "mscgs");
    s_max = max_priority;
}

void cgs_log (int priority, const char *fmt, ...)
{
    if (priority > s_max)
        return;
    char line[2048];
    int n = snprintf (line, sizeof line, "<%d>%s: ", priority, s_ident);
    va_list ap;
    va_start (ap, fmt);
    if (n > 0 && (size_t)n < sizeof line)
        vsnprintf (line + n, sizeof line - (size_t)n, fmt, ap);
    va_end (ap);
    size_t len = strlen (line);
    if (len + 1 < sizeof line)
        line[len++] = '\n';
    else
        line[sizeof line - 2] = '\n', len = sizeof line - 1;
    // One write per line, so lines from many processes sharing a log do not interleave.
    ssize_t w = write (STDERR_FILENO, line, len);
    (void)w;
}
