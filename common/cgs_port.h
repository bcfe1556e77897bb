/* cgs_port — where a service's adapter sends what it makes: topic messages
 * (stamped and carried by the transport), lines for a person, input it
 * could not use, and problems for the health's last error. An adapter is
 * the pure layer between a service's core and its transport: decoded
 * catalogue messages and commands in, the simulation time, catalogue
 * messages out through a port. The daemon's port (cgs_service_port)
 * publishes on the bus and logs; the mscgs tool's lockstep engine routes
 * the same messages in-process. Every function pointer may be NULL (that
 * output is dropped). */
#ifndef CGS_PORT_H
#define CGS_PORT_H

#include <protobuf-c/protobuf-c.h>
#include <stdarg.h>

typedef struct {
    void *arg;
    /* Publish msg (a catalogue topic message; its header is ignored and
     * stamped by the transport) on topic at simulation time sim_time_s. The
     * message is copied before this returns. 0 or a negative errno. */
    int (*publish) (void *arg, const char *topic, ProtobufCMessage *msg, double sim_time_s);
    /* One line for a person, at a syslog priority (LOG_NOTICE, ...). */
    void (*log) (void *arg, int priority, const char *line);
    /* Input the service could not use: counted, logged the first time. */
    void (*bad_input) (void *arg, const char *what);
    /* A problem that becomes the health's last error. */
    void (*error) (void *arg, const char *why);
} cgs_port_t;

/* The port's publish; -ENOTCONN when it has none. */
int cgs_port_publish (const cgs_port_t *port, const char *topic, ProtobufCMessage *msg,
                      double sim_time_s);
/* A formatted line through the port's log. */
void cgs_port_log (const cgs_port_t *port, int priority, const char *fmt, ...)
    __attribute__ ((format (printf, 3, 4)));
/* The port's bad_input. */
void cgs_port_bad_input (const cgs_port_t *port, const char *what);
/* A formatted problem through the port's error. */
void cgs_port_error (const cgs_port_t *port, const char *fmt, ...)
    __attribute__ ((format (printf, 2, 3)));

#endif
