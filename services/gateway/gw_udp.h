/* gw_udp — a translator's UDP endpoint (STANAG 4607, Cursor on Target):
 * the socket a gw_udp_t describes, the destinations it sends to and, when
 * asked, what it hears. Multicast joins its group on the interface (and
 * hears only that membership: IP_MULTICAST_ALL off), with the TTL and
 * loopback given; unicast binds bind_address:input_port and sends to each
 * peer. Sending is best effort: failures are counted. */
#ifndef GW_UDP_H
#define GW_UDP_H

#include "cgs_iface.h"
#include "gw_params.h"

#include <netinet/in.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    int fd;                                // sends, from a port of its own (-1: off)
    int rfd;                               // hears (-1: none asked)
    struct sockaddr_in dest[GW_PEERS_MAX]; // where datagrams go
    size_t ndest;
    cgs_iface_t ifc;          // the interface named (zeroed: none)
    struct sockaddr_in local; // the address fd is bound to (getsockname)
    uint64_t sent;            // datagrams sent (to each destination: counted once per destination)
    uint64_t errors;          // datagrams not sent
    int last_errno;           // of the first failure since the last gw_udp_take_error
    bool error_pending;       // a failure not yet reported
} gw_udp_sock_t;

/* Multicast on a bound socket: join group (host order) on interface
 * ifindex (its address ifaddr, the source of what is sent; 0: the kernel's
 * choice) when join, hear only the groups joined (IP_MULTICAST_ALL off),
 * send on that interface with ttl and loopback. 0, or -1 with errno set
 * (as setsockopt, whose failure it is) and *ret_step the step that failed
 * ("join the group", "multicast options"). The DIS socket uses it too. */
int gw_udp_multicast (int fd, unsigned ifindex, uint32_t ifaddr, uint32_t group, int ttl,
                      bool loopback, bool join, const char **ret_step);
/* Off: nothing to open (fd -1). */
void gw_udp_init (gw_udp_sock_t *s);
/* Look up the interface the parameters name: 0, or -errno with the reason
 * ("[SECTION] interface X: no such interface on this host") in err. */
int gw_udp_interface (gw_udp_sock_t *s, const gw_udp_t *u, const char *section, char *err,
                      size_t errlen);
/* Open it (after gw_udp_interface): a socket that sends from an ephemeral
 * port (fd) and, with receive, one bound to hear datagrams (rfd: the
 * group's port for multicast, input_port for unicast). 0 (also when off),
 * or -errno with the reason in err. */
int gw_udp_open (gw_udp_sock_t *s, const gw_udp_t *u, bool receive, const char *section, char *err,
                 size_t errlen);
void gw_udp_close (gw_udp_sock_t *s);
/* Whether a datagram from there is one of our own, back over multicast
 * loopback: from fd's port and an address of this host's interface. */
bool gw_udp_from_self (const gw_udp_sock_t *s, const struct sockaddr_in *from);
/* Send one datagram to every destination (and to also when not NULL). */
void gw_udp_send (gw_udp_sock_t *s, const void *buf, size_t len, const struct sockaddr_in *also);

#endif
