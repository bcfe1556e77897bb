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

#define S_GROUP      0xef010203u // 239.1.2.3, the default multicast group
#define S_BROADCAST  0xffffffffu // 255.255.255.255
#define S_GROUP_4607 0xef010204u // 239.1.2.4, STANAG 4607 by default
#define S_GROUP_SA   0xef020301u // 239.2.3.1, TAK's situational-awareness group
#define S_LOOPBACK   0x7f000001u // 127.0.0.1

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
    // The translators: off, and on loopback with TTL 0 when turned on.
    p->s4607_udp = (gw_udp_t){.mode = GW_UDP_OFF,
                              .address = S_GROUP_4607,
                              .port = 4607,
                              .input_port = 4607,
                              .bind_address = S_GROUP_4607,
                              .interface = "lo",
                              .loopback = true};
    snprintf (p->s4607_nationality, sizeof p->s4607_nationality, "XN");
    snprintf (p->s4607_class_system, sizeof p->s4607_class_system, "XN");
    p->s4607_classification = 5;
    p->s4607_platform_rate_hz = 1;
    p->s4607_mdv_mps = 0.58;
    p->cot_udp = (gw_udp_t){.mode = GW_UDP_OFF,
                            .address = S_GROUP_SA,
                            .port = 6969,
                            .input_port = 6969,
                            .bind_address = S_GROUP_SA,
                            .interface = "lo",
                            .loopback = true};
    p->cot_stale_s = 15;
    p->cot_rate_hz = 1;
    snprintf (p->cot_uid_prefix, sizeof p->cot_uid_prefix, "mscgs");
    p->cot_designate = true;
    snprintf (p->cot_designate_types[0], GW_COT_TYPE_LEN, "b-m-p-s-p-i");
    p->cot_designate_type_count = 1;
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

void gw_params_describe_udp (const gw_udp_t *u, char *buf, size_t len)
{
    char a[INET_ADDRSTRLEN];
    struct in_addr ia;
    if (u->mode == GW_UDP_OFF) {
        snprintf (buf, len, "off");
    } else if (u->mode == GW_UDP_UNICAST) {
        ia.s_addr = htonl (u->peers[0].addr);
        inet_ntop (AF_INET, &ia, a, sizeof a);
        int n = snprintf (buf, len, "unicast to %s:%u", a, u->peers[0].port);
        if (u->peer_count > 1 && n >= 0 && (size_t)n < len)
            snprintf (buf + n, len - (size_t)n, " and %zu more", u->peer_count - 1);
    } else {
        ia.s_addr = htonl (u->address);
        inet_ntop (AF_INET, &ia, a, sizeof a);
        snprintf (buf, len, "multicast to %s:%u on %s, TTL %d", a, u->port,
                  *u->interface ? u->interface : "the routing table's interface", u->ttl);
    }
}

bool gw_params_udp_leaves_host (const gw_udp_t *u, bool interface_is_loopback)
{
    if (u->mode == GW_UDP_MULTICAST)
        return u->ttl > 0 && !interface_is_loopback;
    if (u->mode == GW_UDP_UNICAST)
        for (size_t i = 0; i < u->peer_count; i++)
            if (!cgs_iface_addr_is_loopback (u->peers[i].addr))
                return true;
    return false;
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
    S_R ("stanag4607", "platform_rate_hz", s4607_platform_rate_hz, 0.01, 100.0),
    S_R ("stanag4607", "mdv_mps", s4607_mdv_mps, 0.0, 25.0),
    S_R ("cot", "stale_s", cot_stale_s, 1.0, 86400.0),
    S_R ("cot", "rate_hz", cot_rate_hz, 0.01, 50.0),
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
    S_I ("stanag4607", "classification", s4607_classification, 1, 5),
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
static int s_interface (cgs_config_t *cfg, const char *sec, char interface[GW_IFACE_MAX], char *err,
                        size_t errlen)
{
    const char *s;
    char def[GW_IFACE_MAX];
    snprintf (def, sizeof def, "%s", interface); // s may point at the default
    int rc = cgs_config_get_string (cfg, sec, "interface", def, &s, err, errlen);
    if (rc < 0)
        return rc;
    struct in_addr a;
    if (strcmp (s, "0.0.0.0") == 0 || !*s) {
        interface[0] = '\0';
        return 0;
    }
    if (inet_pton (AF_INET, s, &a) != 1 && !cgs_iface_name_valid (s))
        return cgs_config_error (cfg, sec, "interface", 0, err, errlen,
                                 "expected an interface name (lo, eth0: `ip -br link` lists "
                                 "them) or its IPv4 address, got '%s'",
                                 s);
    snprintf (interface, GW_IFACE_MAX, "%s", s);
    return 0;
}

/* The `peer = IPV4[:PORT]` lines of a section (port defaults to port). */
static int s_peers (cgs_config_t *cfg, const char *sec, uint16_t port_def,
                    gw_peer_t peers[GW_PEERS_MAX], size_t *ret_count, char *err, size_t errlen)
{
    size_t n = cgs_config_count (cfg, sec, "peer");
    if (n > GW_PEERS_MAX)
        return cgs_config_error (cfg, sec, "peer", GW_PEERS_MAX, err, errlen, "at most %d peers",
                                 GW_PEERS_MAX);
    for (size_t i = 0; i < n; i++) {
        const char *v = cgs_config_get_nth (cfg, sec, "peer", i);
        char host[64];
        const char *colon = strrchr (v, ':');
        struct in_addr a;
        long port = port_def;
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
                return cgs_config_error (cfg, sec, "peer", i, err, errlen,
                                         "expected a port 1..65535 after ':', got '%s'", v);
        }
        if (inet_pton (AF_INET, host, &a) != 1)
            return cgs_config_error (cfg, sec, "peer", i, err, errlen,
                                     "expected IPV4[:PORT], got '%s'", v);
        peers[i] = (gw_peer_t){ntohl (a.s_addr), (uint16_t)port};
    }
    *ret_count = n;
    return 0;
}

/* A translator's UDP output: `udp` (or `mode`) = off | multicast | unicast,
 * address, port, input_port, interface, ttl, loopback, bind, peer. */
static int s_udp (cgs_config_t *cfg, const char *sec, const char *mode_key, gw_udp_t *u, char *err,
                  size_t errlen)
{
    static const char *const modes[] = {"off", "multicast", "unicast", NULL};
    int mode = (int)u->mode;
    long port = u->port, ttl = u->ttl;
    int rc = cgs_config_get_enum (cfg, sec, mode_key, modes, mode, &mode, err, errlen);
    u->mode = (gw_udp_mode_t)mode;
    if (rc == 0)
        rc = cgs_config_get_int (cfg, sec, "port", port, 1, 65535, &port, err, errlen);
    u->port = (uint16_t)port;
    long input = cgs_config_has (cfg, sec, "port") ? u->port : u->input_port;
    if (rc == 0)
        rc = cgs_config_get_int (cfg, sec, "input_port", input, 1, 65535, &input, err, errlen);
    u->input_port = (uint16_t)input;
    if (rc == 0)
        rc = s_addr (cfg, sec, "address", u->address, &u->address, err, errlen);
    if (rc == 0)
        rc = s_peers (cfg, sec, u->port, u->peers, &u->peer_count, err, errlen);
    if (u->mode == GW_UDP_UNICAST && !cgs_config_has (cfg, sec, "interface"))
        u->interface[0] = '\0';
    if (rc == 0)
        rc = s_interface (cfg, sec, u->interface, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_int (cfg, sec, "ttl", ttl, 0, 255, &ttl, err, errlen);
    u->ttl = (int)ttl;
    if (rc == 0)
        rc = cgs_config_get_bool (cfg, sec, "loopback", u->loopback, &u->loopback, err, errlen);
    uint32_t def_bind = u->mode == GW_UDP_MULTICAST            ? u->address
                        : u->mode == GW_UDP_OFF                ? u->bind_address
                        : gw_params_udp_leaves_host (u, false) ? 0
                                                               : S_LOOPBACK;
    if (rc == 0)
        rc = s_addr (cfg, sec, "bind", def_bind, &u->bind_address, err, errlen);
    if (rc == 0 && u->mode == GW_UDP_MULTICAST && !s_is_group (u->address))
        rc = cgs_config_error (cfg, sec, "address", 0, err, errlen,
                               "multicast needs a group in 224.0.0.0/4");
    if (rc == 0 && u->mode == GW_UDP_UNICAST && u->peer_count == 0)
        rc = cgs_config_error (cfg, sec, mode_key, 0, err, errlen,
                               "unicast needs at least one `peer = IPV4[:PORT]`");
    if (rc == 0 && u->mode != GW_UDP_UNICAST && u->peer_count > 0)
        rc = cgs_config_error (cfg, sec, "peer", 0, err, errlen, "peers are for %s = unicast",
                               mode_key);
    return rc;
}

/* A fixed-length text key: at most len - 1 characters of printable ASCII. */
static int s_text (cgs_config_t *cfg, const char *sec, const char *key, char *buf, size_t len,
                   size_t min, char *err, size_t errlen)
{
    const char *s;
    char def[128];
    snprintf (def, sizeof def, "%s", buf);
    int rc = cgs_config_get_string (cfg, sec, key, def, &s, err, errlen);
    if (rc < 0)
        return rc;
    size_t n = strlen (s);
    if (n < min || n >= len)
        return cgs_config_error (cfg, sec, key, 0, err, errlen,
                                 "expected %zu to %zu characters, got '%s'", min, len - 1, s);
    for (size_t i = 0; i < n; i++)
        if (s[i] < 0x21 || s[i] > 0x7e || s[i] == '"' || s[i] == '<' || s[i] == '&')
            return cgs_config_error (cfg, sec, key, 0, err, errlen,
                                     "expected printable ASCII without spaces, quotes, < or &, "
                                     "got '%s'",
                                     s);
    snprintf (buf, len, "%s", s);
    return 0;
}

/* [cot] designate_type lines: CoT types (letters, digits, '-', '.'). */
static int s_cot_types (cgs_config_t *cfg, gw_params_t *p, char *err, size_t errlen)
{
    size_t n = cgs_config_count (cfg, "cot", "designate_type");
    if (n == 0)
        return 0;
    if (n > GW_COT_TYPES_MAX)
        return cgs_config_error (cfg, "cot", "designate_type", GW_COT_TYPES_MAX, err, errlen,
                                 "at most %d types", GW_COT_TYPES_MAX);
    for (size_t i = 0; i < n; i++) {
        const char *v = cgs_config_get_nth (cfg, "cot", "designate_type", i);
        size_t len = strlen (v);
        bool ok = len > 0 && len < GW_COT_TYPE_LEN;
        for (size_t k = 0; ok && k < len; k++)
            ok = (v[k] >= 'a' && v[k] <= 'z') || (v[k] >= 'A' && v[k] <= 'Z') ||
                 (v[k] >= '0' && v[k] <= '9') || v[k] == '-' || v[k] == '.';
        if (!ok)
            return cgs_config_error (cfg, "cot", "designate_type", i, err, errlen,
                                     "expected a CoT type such as b-m-p-s-p-i, got '%s'", v);
        snprintf (p->cot_designate_types[i], GW_COT_TYPE_LEN, "%s", v);
    }
    p->cot_designate_type_count = n;
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
        rc = s_peers (cfg, "network", p.port, p.peers, &p.peer_count, err, errlen);
    // Unicast peers name their own destinations: no interface unless given.
    if (p.mode == GW_MODE_UNICAST && !cgs_config_has (cfg, "network", "interface"))
        p.interface[0] = '\0';
    if (rc == 0)
        rc = s_interface (cfg, "network", p.interface, err, errlen);
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
        rc = cgs_config_get_bool (cfg, "dis", "pcapng", p.dis_pcapng, &p.dis_pcapng, err, errlen);
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
        rc = cgs_config_get_bool (cfg, "stanag4607", "file", p.s4607_file, &p.s4607_file, err,
                                  errlen);
    if (rc == 0)
        rc = s_udp (cfg, "stanag4607", "udp", &p.s4607_udp, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_bool (cfg, "stanag4607", "truth_tag", p.s4607_truth_tag,
                                  &p.s4607_truth_tag, err, errlen);
    if (rc == 0)
        rc = s_text (cfg, "stanag4607", "nationality", p.s4607_nationality,
                     sizeof p.s4607_nationality, 2, err, errlen);
    if (rc == 0)
        rc = s_text (cfg, "stanag4607", "class_system", p.s4607_class_system,
                     sizeof p.s4607_class_system, 2, err, errlen);
    if (rc == 0 && p.s4607_truth_tag && p.application > 255)
        rc = cgs_config_error (cfg, "stanag4607", "truth_tag", 0, err, errlen,
                               "a truth tag's application is one byte: [dis] application %d is "
                               "over 255",
                               p.application);
    if (rc == 0)
        rc = s_udp (cfg, "cot", "mode", &p.cot_udp, err, errlen);
    int format = p.cot_protobuf ? 1 : 0;
    static const char *const formats[] = {"xml", "protobuf", NULL};
    if (rc == 0)
        rc = cgs_config_get_enum (cfg, "cot", "format", formats, format, &format, err, errlen);
    p.cot_protobuf = format == 1;
    if (rc == 0)
        rc = s_text (cfg, "cot", "uid_prefix", p.cot_uid_prefix, sizeof p.cot_uid_prefix, 1, err,
                     errlen);
    if (rc == 0)
        rc = cgs_config_get_bool (cfg, "cot", "designate", p.cot_designate, &p.cot_designate, err,
                                  errlen);
    if (rc == 0)
        rc = s_cot_types (cfg, &p, err, errlen);
    if (rc == 0 && (cgs_config_has (cfg, "cot", "designate_uav") || *p.cot_designate_uav))
        rc = s_text (cfg, "cot", "designate_uav", p.cot_designate_uav, sizeof p.cot_designate_uav,
                     1, err, errlen);
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
