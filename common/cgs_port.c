/* cgs_port — an adapter's outputs (see cgs_port.h). */
#include "cgs_port.h"

#include <errno.h>
#include <stdio.h>

int cgs_port_publish (const cgs_port_t *port, const char *topic, ProtobufCMessage *msg,
                      double sim_time_s)
{
    if (!port || !port->publish)
        return -ENOTCONN;
    return port->publish (port->arg, topic, msg, sim_time_s);
}

void cgs_port_log (const cgs_port_t *port, int priority, const char *fmt, ...)
{
    if (!port || !port->log)
        return;
    char line[1024];
    va_list ap;
    va_start (ap, fmt);
    vsnprintf (line, sizeof line, fmt, ap);
    va_end (ap);
    port->log (port->arg, priority, line);
}

void cgs_port_bad_input (const cgs_port_t *port, const char *what)
{
    if (port && port->bad_input)
        port->bad_input (port->arg, what);
}

void cgs_port_error (const cgs_port_t *port, const char *fmt, ...)
{
    if (!port || !port->error)
        return;
    char why[512];
    va_list ap;
    va_start (ap, fmt);
    vsnprintf (why, sizeof why, fmt, ap);
    va_end (ap);
    port->error (port->arg, why);
}
