/* gw_params — the gateway's parameter file (deploy/params/gateway.ini): the
 * DIS network (port, broadcast, multicast group or unicast peers, the
 * interface; by default multicast on loopback, which never leaves this
 * machine, and whether given parameters would send off it), the
 * protocol version sent, site and application ids, entity-id assignment,
 * dead-reckoning thresholds and the external entities' table. Every value is
 * range-checked; errors name the file, the line, the section and key. Pure. */
#ifndef GW_PARAMS_H
#define GW_PARAMS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define GW_PEERS_MAX 16
#define GW_IFACE_MAX 16 // an interface name (IF_NAMESIZE) or a dotted IPv4 address

typedef enum {
    GW_MODE_BROADCAST = 0,
    GW_MODE_MULTICAST = 1,
    GW_MODE_UNICAST = 2,
} gw_mode_t;

typedef struct {
    uint32_t addr; // IPv4, host byte order
    uint16_t port;
} gw_peer_t;

typedef struct {
    // [network]
    uint16_t port;         // UDP port bound and sent to (default 3000)
    gw_mode_t mode;        // default multicast
    uint32_t address;      // broadcast address or multicast group (host order; default 239.1.2.3)
    uint32_t bind_address; // local address bound (default: the group for multicast, 0.0.0.0
                           // for broadcast, 127.0.0.1 for unicast to loopback peers only)
    char interface[GW_IFACE_MAX];  // name or IPv4 address of the interface multicast and
                                   // broadcast go out on and are heard on (default "lo");
                                   // "" is the routing table's choice
    int ttl;                       // multicast TTL (default 0: never leaves this host)
    bool loopback;                 // multicast loopback (default yes)
    gw_peer_t peers[GW_PEERS_MAX]; // unicast peers
    size_t peer_count;
    // [dis]
    int version;           // sent: 3, 4, 5, 6 or 7 (default 7)
    int site, application; // our simulation address (default 1, 1)
    int entity_id_base;    // DIS entity number = base + internal id (default 0)
    bool absolute_time;    // timestamps absolute (UTC past the hour) or relative
    long route_action_id;  // Action Request action id of a route task (default 40)
    // [dead_reckoning]
    double position_threshold_m;      // default 1
    double orientation_threshold_deg; // default 3
    double heartbeat_s;               // default 5
    double timeout_s;                 // external entities silent this long are removed (12)
    // [external]
    long first_entity_id;   // internal ids of external entities start here (default 100000)
    long max_entities;      // at most this many at once (default 10000)
    double publish_rate_hz; // `entity` publications of them per wall second (default 10)
    double task_timeout_s;  // wait this long for uavsim's verdict on a route task (default 1)
} gw_params_t;

/* The defaults (deploy/params/gateway.ini documents each). */
void gw_params_defaults (gw_params_t *p);
/* Read a parameter file over *p; on error *p is unchanged. 0, or a negative
 * errno with err filled ("file:line: [section] key: ..."). */
int gw_params_load (const char *path, gw_params_t *p, char *err, size_t errlen);
/* The same from text (name stands for the file name in errors). */
int gw_params_load_string (const char *name, const char *text, gw_params_t *p, char *err,
                           size_t errlen);
/* The mode's name. */
const char *gw_params_mode_name (gw_mode_t mode);
/* Where DIS goes, in words ("multicast to 239.1.2.3:3000 on lo, TTL 0"),
 * into buf (always terminated). */
void gw_params_describe (const gw_params_t *p, char *buf, size_t len);
/* Whether these parameters can put DIS on a network rather than keep it on
 * this machine, given whether p->interface is a loopback interface (the
 * caller looks it up: cgs_iface_find). Multicast stays with TTL 0 or on a
 * loopback interface; broadcast on a loopback interface or to 127.0.0.0/8;
 * unicast when every peer is in 127.0.0.0/8. */
bool gw_params_leaves_host (const gw_params_t *p, bool interface_is_loopback);

#endif
