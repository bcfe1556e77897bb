/* gw_udp — a translator's UDP endpoint (see gw_udp.h). */
#include "gw_udp.h"

#include <arpa/inet.h>
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

int gw_udp_multicast (int fd, unsigned ifindex, uint32_t ifaddr, uint32_t group, int ttl,
                      bool loopback, bool join, const char **ret_step)
{
    // On failure errno stays as setsockopt left it (the callers report it).
    // The interface, and its address as the source of what we send (else
    // the kernel takes the host's main address, even on lo).
    struct ip_mreqn mreq = {.imr_ifindex = (int)ifindex};
    mreq.imr_multiaddr.s_addr = htonl (group);
    mreq.imr_address.s_addr = htonl (ifaddr);
    unsigned char t = (unsigned char)ttl, loop = loopback;
    int zero = 0;
    *ret_step = "join the group";
    if (join && setsockopt (fd, IPPROTO_IP, IP_ADD_MEMBERSHIP, &mreq, sizeof mreq) < 0)
        return -1;
    *ret_step = "multicast options";
    if (setsockopt (fd, IPPROTO_IP, IP_MULTICAST_ALL, &zero, sizeof zero) < 0 ||
        setsockopt (fd, IPPROTO_IP, IP_MULTICAST_TTL, &t, sizeof t) < 0 ||
        setsockopt (fd, IPPROTO_IP, IP_MULTICAST_LOOP, &loop, sizeof loop) < 0 ||
        setsockopt (fd, IPPROTO_IP, IP_MULTICAST_IF, &mreq, sizeof mreq) < 0)
        return -1;
    return 0;
}

void gw_udp_init (gw_udp_sock_t *s)
{
    memset (s, 0, sizeof *s);
    s->fd = s->rfd = -1;
}

int gw_udp_interface (gw_udp_sock_t *s, const gw_udp_t *u, const char *section, char *err,
                      size_t errlen)
{
    memset (&s->ifc, 0, sizeof s->ifc);
    if (u->mode == GW_UDP_OFF || !*u->interface)
        return 0;
    int rc = cgs_iface_find (u->interface, &s->ifc);
    if (rc < 0)
        snprintf (err, errlen, "[%s] interface %s: %s (`ip -br link` lists this host's)", section,
                  u->interface, rc == -ENODEV ? "no such interface on this host" : strerror (-rc));
    return rc;
}

/* One socket: bound to hear (receive) or to send from an ephemeral port;
 * the fd, or -errno with the reason in err. */
static int s_socket (const gw_udp_sock_t *s, const gw_udp_t *u, bool receive, const char *section,
                     char *err, size_t errlen)
{
    int fd = socket (AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        int e = errno;
        snprintf (err, errlen, "[%s]: cannot make a UDP socket: %s", section, strerror (e));
        return -e;
    }
    int one = 1, size = 4 << 20;
    const char *step = "bind";
    setsockopt (fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    struct sockaddr_in sa = {.sin_family = AF_INET};
    if (receive) {
        setsockopt (fd, SOL_SOCKET, SO_RCVBUF, &size, sizeof size);
        sa.sin_port = htons (u->mode == GW_UDP_MULTICAST ? u->port : u->input_port);
        sa.sin_addr.s_addr = htonl (u->bind_address);
    } else {
        // Send only, from a port of its own: what comes back from it is ours.
        setsockopt (fd, SOL_SOCKET, SO_SNDBUF, &size, sizeof size);
        sa.sin_addr.s_addr = htonl (u->mode == GW_UDP_MULTICAST ? INADDR_ANY : u->bind_address);
    }
    if (u->mode == GW_UDP_UNICAST && *u->interface &&
        setsockopt (fd, SOL_SOCKET, SO_BINDTODEVICE, s->ifc.name, (socklen_t)strlen (s->ifc.name)) <
            0) {
        step = "SO_BINDTODEVICE";
        goto fail;
    }
    if (bind (fd, (struct sockaddr *)&sa, sizeof sa) < 0)
        goto fail;
    if (u->mode == GW_UDP_MULTICAST && gw_udp_multicast (fd, s->ifc.index, s->ifc.addr, u->address,
                                                         u->ttl, u->loopback, receive, &step) < 0)
        goto fail;
    return fd;
fail:;
    int e = errno;
    char addr[INET_ADDRSTRLEN], where[160];
    inet_ntop (AF_INET, &sa.sin_addr, addr, sizeof addr);
    gw_params_describe_udp (u, where, sizeof where);
    snprintf (err, errlen, "[%s] socket (%s, bound to %s:%u): %s: %s", section, where, addr,
              ntohs (sa.sin_port), step, strerror (e));
    close (fd);
    return -e;
}

int gw_udp_open (gw_udp_sock_t *s, const gw_udp_t *u, bool receive, const char *section, char *err,
                 size_t errlen)
{
    if (u->mode == GW_UDP_OFF)
        return 0;
    int fd = s_socket (s, u, false, section, err, errlen);
    if (fd < 0)
        return fd;
    socklen_t sl = sizeof s->local;
    if (getsockname (fd, (struct sockaddr *)&s->local, &sl) < 0)
        memset (&s->local, 0, sizeof s->local);
    if (receive) {
        int rfd = s_socket (s, u, true, section, err, errlen);
        if (rfd < 0) {
            close (fd);
            return rfd;
        }
        s->rfd = rfd;
    }
    s->ndest = 0;
    if (u->mode == GW_UDP_UNICAST) {
        for (size_t i = 0; i < u->peer_count; i++) {
            struct sockaddr_in *d = &s->dest[s->ndest++];
            *d = (struct sockaddr_in){.sin_family = AF_INET, .sin_port = htons (u->peers[i].port)};
            d->sin_addr.s_addr = htonl (u->peers[i].addr);
        }
    } else {
        struct sockaddr_in *d = &s->dest[s->ndest++];
        *d = (struct sockaddr_in){.sin_family = AF_INET, .sin_port = htons (u->port)};
        d->sin_addr.s_addr = htonl (u->address);
    }
    s->fd = fd;
    return 0;
}

void gw_udp_close (gw_udp_sock_t *s)
{
    if (s->fd >= 0)
        close (s->fd);
    if (s->rfd >= 0)
        close (s->rfd);
    s->fd = s->rfd = -1;
}

bool gw_udp_from_self (const gw_udp_sock_t *s, const struct sockaddr_in *from)
{
    if (s->fd < 0 || from->sin_port != s->local.sin_port)
        return false;
    uint32_t a = ntohl (from->sin_addr.s_addr);
    return (s->ifc.addr && a == s->ifc.addr) || cgs_iface_addr_is_loopback (a) ||
           (s->local.sin_addr.s_addr != 0 && from->sin_addr.s_addr == s->local.sin_addr.s_addr);
}

static void s_sendto (gw_udp_sock_t *s, const void *buf, size_t len, const struct sockaddr_in *to)
{
    ssize_t n;
    do
        n = sendto (s->fd, buf, len, 0, (const struct sockaddr *)to, sizeof *to);
    while (n < 0 && errno == EINTR);
    if (n == (ssize_t)len) {
        s->sent++;
        return;
    }
    s->errors++;
    if (!s->error_pending) {
        s->error_pending = true;
        s->last_errno = n < 0 ? errno : EMSGSIZE;
    }
}

void gw_udp_send (gw_udp_sock_t *s, const void *buf, size_t len, const struct sockaddr_in *also)
{
    if (s->fd < 0)
        return;
    for (size_t i = 0; i < s->ndest; i++)
        s_sendto (s, buf, len, &s->dest[i]);
    if (also)
        s_sendto (s, buf, len, also);
}
