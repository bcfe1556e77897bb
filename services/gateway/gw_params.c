/* gw_params — the gateway's parameter file (see gw_params.h). */
#include "gw_params.h"

#include "cgs_config.h"
#include "cgs_iface.h"

#include <arpa/inet.h>
#include <errno.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_GROUP     0xef010203u // 239.1.2.3, the default multicast group
#define S_BROADCAST 0xffffffffu // 255.255.255.255

static bool s_is_group (uint32_t a)
{
    return (a >> 28) == 0xe;
}

void gw_params_defaults (gw_params_t *p)
{
    memset (p, 0, sizeof *p);
    p->port = 3000;
    // Multicast on loopback with TTL 0: DIS tools on this machine hear it,
    // nothing leaves it (an exercise that wants a network names it).
    p->mode = GW_MODE_MULTICAST;
    p->address = S_GROUP;
    p->bind_address = S_GROUP;
    snprintf (p->interface, sizeof p->interface, "lo");
    p->ttl = 0;
    p->loopback = true;
    p->version = 7;
    p->site = 1;
    p->application = 1;
    p->absolute_time = true;
    p->route_action_id = 40; // SISO-REF-010: Send Plan Data
    p->position_threshold_m = 1;
    p->orientation_threshold_deg = 3;
    p->heartbeat_s = 5;
    p->timeout_s = 12;
    p->first_entity_id = 100000;
    p->max_entities = 10000;
    p->publish_rate_hz = 10;
    p->task_timeout_s = 1;
}

const char *gw_params_mode_name (gw_mode_t mode)
{
    return mode == GW_MODE_MULTICAST ? "multicast"
           : mode == GW_MODE_UNICAST ? "unicast"
                                     : "broadcast";
}

void gw_params_describe (const gw_params_t *p, char *buf, size_t len)
{
    char a[INET_ADDRSTRLEN];
    struct in_addr ia;
    if (p->mode == GW_MODE_UNICAST) {
        ia.s_addr = htonl (p->peers[0].addr);
        inet_ntop (AF_INET, &ia, a, sizeof a);
        int n = snprintf (buf, len, "unicast to %s:%u", a, p->peers[0].port);
        if (p->peer_count > 1 && n >= 0 && (size_t)n < len)
            snprintf (buf + n, len - (size_t)n, " and %zu more", p->peer_count - 1);
        return;
    }
    ia.s_addr = htonl (p->address);
    inet_ntop (AF_INET, &ia, a, sizeof a);
    const char *on = *p->interface ? p->interface : "the routing table's interface";
    if (p->mode == GW_MODE_MULTICAST)
        snprintf (buf, len, "multicast to %s:%u on %s, TTL %d", a, p->port, on, p->ttl);
    else
        snprintf (buf, len, "broadcast to %s:%u on %s", a, p->port, on);
}

bool gw_params_leaves_host (const gw_params_t *p, bool interface_is_loopback)
{
    switch (p->mode) {
    case GW_MODE_MULTICAST:
        return p->ttl > 0 && !interface_is_loopback;
    case GW_MODE_BROADCAST:
        return !interface_is_loopback && !cgs_iface_addr_is_loopback (p->address);
    case GW_MODE_UNICAST:
    default:
        for (size_t i = 0; i < p->peer_count; i++)
            if (!cgs_iface_addr_is_loopback (p->peers[i].addr))
                return true;
        return false;
    }
}

#define S_R(sec, k, field, lo, hi)                                                                 \
    {                                                                                              \
        sec, k, offsetof (gw_params_t, field), lo, hi                                              \
    }
static const cgs_config_real_t s_reals[] = {
    S_R ("dead_reckoning", "position_threshold_m", position_threshold_m, 0.01, 1000.0),
    S_R ("dead_reckoning", "orientation_threshold_deg", orientation_threshold_deg, 0.1, 180.0),
    S_R ("dead_reckoning", "heartbeat_s", heartbeat_s, 0.1, 3600.0),
    S_R ("dead_reckoning", "timeout_s", timeout_s, 0.2, 86400.0),
    S_R ("external", "publish_rate_hz", publish_rate_hz, 0.1, 100.0),
    S_R ("external", "task_timeout_s", task_timeout_s, 0.05, 30.0),
};
#undef S_R
#define S_I(sec, k, field, lo, hi)                                                                 \
    {                                                                                              \
        sec, k, offsetof (gw_params_t, field), lo, hi                                              \
    }
static const cgs_config_int_t s_ints[] = {
    S_I ("network", "ttl", ttl, 0, 255),
    S_I ("dis", "version", version, 3, 7),
    S_I ("dis", "site", site, 1, 65534),
    S_I ("dis", "application", application, 1, 65534),
    S_I ("dis", "entity_id_base", entity_id_base, 0, 65533),
};
#undef S_I

/* An IPv4 address key; def when absent. */
static int s_addr (cgs_config_t *cfg, const char *sec, const char *key, uint32_t def, uint32_t *ret,
                   char *err, size_t errlen)
{
    char buf[INET_ADDRSTRLEN];
    struct in_addr a = {htonl (def)};
    inet_ntop (AF_INET, &a, buf, sizeof buf);
    const char *s;
    int rc = cgs_config_get_string (cfg, sec, key, buf, &s, err, errlen);
    if (rc < 0)
        return rc;
    if (inet_pton (AF_INET, s, &a) != 1)
        return cgs_config_error (cfg, sec, key, 0, err, errlen,
                                 "expected an IPv4 address (a.b.c.d), got '%s'", s);
    *ret = ntohl (a.s_addr);
    return 0;
}

/* The interface key: a name or a dotted IPv4 address; 0.0.0.0 (or "")
 * leaves the choice to the routing table. */
static int s_interface (cgs_config_t *cfg, gw_params_t *p, char *err, size_t errlen)
{
    const char *s;
    char def[GW_IFACE_MAX];
    snprintf (def, sizeof def, "%s", p->interface); // s may point at the default
    int rc = cgs_config_get_string (cfg, "network", "interface", def, &s, err, errlen);
    if (rc < 0)
        return rc;
    struct in_addr a;
    if (strcmp (s, "0.0.0.0") == 0 || !*s) {
        p->interface[0] = '\0';
        return 0;
    }
    if (inet_pton (AF_INET, s, &a) != 1 && !cgs_iface_name_valid (s))
        return cgs_config_error (cfg, "network", "interface", 0, err, errlen,
                                 "expected an interface name (lo, eth0: `ip -br link` lists "
                                 "them) or its IPv4 address, got '%s'",
                                 s);
    snprintf (p->interface, sizeof p->interface, "%s", s);
    return 0;
}

static int s_peers (cgs_config_t *cfg, gw_params_t *p, char *err, size_t errlen)
{
    size_t n = cgs_config_count (cfg, "network", "peer");
    if (n > GW_PEERS_MAX)
        return cgs_config_error (cfg, "network", "peer", GW_PEERS_MAX, err, errlen,
                                 "at most %d peers", GW_PEERS_MAX);
    for (size_t i = 0; i < n; i++) {
        const char *v = cgs_config_get_nth (cfg, "network", "peer", i);
        char host[64];
        const char *colon = strrchr (v, ':');
        struct in_addr a;
        long port = p->port;
        size_t hl = colon ? (size_t)(colon - v) : strlen (v);
        if (hl >= sizeof host)
            hl = sizeof host - 1;
        memcpy (host, v, hl);
        host[hl] = '\0';
        if (colon) {
            char *end;
            errno = 0;
            port = strtol (colon + 1, &end, 10);
            if (errno || end == colon + 1 || *end || port < 1 || port > 65535)
                return cgs_config_error (cfg, "network", "peer", i, err, errlen,
                                         "expected a port 1..65535 after ':', got '%s'", v);
        }
        if (inet_pton (AF_INET, host, &a) != 1)
            return cgs_config_error (cfg, "network", "peer", i, err, errlen,
                                     "expected IPV4[:PORT], got '%s'", v);
        p->peers[i] = (gw_peer_t){ntohl (a.s_addr), (uint16_t)port};
    }
    p->peer_count = n;
    return 0;
}

static int s_read (cgs_config_t *cfg, void *arg, char *err, size_t errlen)
{
    gw_params_t *out = arg, p = *out;
    long port = p.port, action = p.route_action_id, first = p.first_entity_id, max = p.max_entities;
    int mode = (int)p.mode, timing = p.absolute_time ? 0 : 1;
    static const char *const modes[] = {"broadcast", "multicast", "unicast", NULL};
    static const char *const timings[] = {"absolute", "relative", NULL};
    int rc = cgs_config_check_repeated (cfg, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_table (cfg, s_reals, sizeof s_reals / sizeof s_reals[0], s_ints,
                                   sizeof s_ints / sizeof s_ints[0], &p, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_int (cfg, "network", "port", port, 1, 65535, &port, err, errlen);
    p.port = (uint16_t)port;
    if (rc == 0)
        rc = cgs_config_get_enum (cfg, "network", "mode", modes, mode, &mode, err, errlen);
    p.mode = (gw_mode_t)mode;
    // The address the mode takes when none is given: a group for multicast,
    // 255.255.255.255 for broadcast.
    uint32_t def_addr = p.address;
    if (p.mode == GW_MODE_MULTICAST && !s_is_group (p.address))
        def_addr = S_GROUP;
    else if (p.mode == GW_MODE_BROADCAST && s_is_group (p.address))
        def_addr = S_BROADCAST;
    if (rc == 0)
        rc = s_addr (cfg, "network", "address", def_addr, &p.address, err, errlen);
    if (rc == 0)
        rc = s_peers (cfg, &p, err, errlen);
    // Unicast peers name their own destinations: no interface unless given.
    if (p.mode == GW_MODE_UNICAST && !cgs_config_has (cfg, "network", "interface"))
        p.interface[0] = '\0';
    if (rc == 0)
        rc = s_interface (cfg, &p, err, errlen);
    // The address bound when none is given: what hears this mode's peers
    // and nothing else (the group; every address for broadcast; loopback
    // for unicast to loopback peers only).
    uint32_t def_bind = p.bind_address;
    if (!cgs_config_has (cfg, "network", "bind")) {
        def_bind = 0;
        if (p.mode == GW_MODE_MULTICAST)
            def_bind = p.address;
        else if (p.mode == GW_MODE_UNICAST && !gw_params_leaves_host (&p, false))
            def_bind = 0x7f000001u; // 127.0.0.1
    }
    if (rc == 0)
        rc = s_addr (cfg, "network", "bind", def_bind, &p.bind_address, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_bool (cfg, "network", "loopback", p.loopback, &p.loopback, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_enum (cfg, "dis", "timestamp", timings, timing, &timing, err, errlen);
    p.absolute_time = timing == 0;
    if (rc == 0)
        rc = cgs_config_get_int (cfg, "dis", "route_action_id", action, 0, 4294967295L, &action,
                                 err, errlen);
    p.route_action_id = action;
    if (rc == 0)
        rc = cgs_config_get_int (cfg, "external", "first_entity_id", first, 65535, 2000000000L,
                                 &first, err, errlen);
    p.first_entity_id = first;
    if (rc == 0)
        rc = cgs_config_get_int (cfg, "external", "max_entities", max, 1, 1000000, &max, err,
                                 errlen);
    p.max_entities = max;
    if (rc == 0 && p.mode == GW_MODE_MULTICAST && !s_is_group (p.address))
        rc = cgs_config_error (cfg, "network", "address", 0, err, errlen,
                               "multicast needs a group in 224.0.0.0/4");
    if (rc == 0 && p.mode == GW_MODE_UNICAST && p.peer_count == 0)
        rc = cgs_config_error (cfg, "network", "mode", 0, err, errlen,
                               "unicast needs at least one `peer = IPV4[:PORT]`");
    if (rc == 0 && p.mode != GW_MODE_UNICAST && p.peer_count > 0)
        rc = cgs_config_error (cfg, "network", "peer", 0, err, errlen,
                               "peers are for mode = unicast (mode is %s)",
                               gw_params_mode_name (p.mode));
    if (rc == 0 && p.timeout_s <= p.heartbeat_s) {
        // On the line of the key the file gave (timeout_s when it gave both).
        bool timeout_given = cgs_config_has (cfg, "dead_reckoning", "timeout_s");
        rc = timeout_given
                 ? cgs_config_error (cfg, "dead_reckoning", "timeout_s", 0, err, errlen,
                                     "must be longer than heartbeat_s (%g)", p.heartbeat_s)
                 : cgs_config_error (cfg, "dead_reckoning", "heartbeat_s", 0, err, errlen,
                                     "must be shorter than timeout_s (%g)", p.timeout_s);
    }
    if (rc == 0)
        rc = cgs_config_check_unused (cfg, err, errlen);
    if (rc < 0)
        return rc;
    *out = p;
    return 0;
}

int gw_params_load (const char *path, gw_params_t *p, char *err, size_t errlen)
{
    return cgs_config_read (path, NULL, s_read, p, err, errlen);
}

int gw_params_load_string (const char *name, const char *text, gw_params_t *p, char *err,
                           size_t errlen)
{
    return cgs_config_read (name, text, s_read, p, err, errlen);
}
