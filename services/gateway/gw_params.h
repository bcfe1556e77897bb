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

/* A translator's UDP output ([stanag4607], [cot]): off, multicast to a group
 * on an interface (TTL 0 by default: this host only), or unicast to peers. */
typedef enum {
    GW_UDP_OFF = 0,
    GW_UDP_MULTICAST = 1,
    GW_UDP_UNICAST = 2,
} gw_udp_mode_t;

typedef struct {
    gw_udp_mode_t mode;           // default off
    uint32_t address;             // multicast group (host order)
    uint16_t port;                // sent to (and, multicast, bound)
    uint16_t input_port;          // unicast: the local port bound (default port)
    uint32_t bind_address;        // local address bound (default: the group for multicast,
                                  // 127.0.0.1 for unicast to loopback peers only, else 0.0.0.0)
    char interface[GW_IFACE_MAX]; // multicast: joined and sent on (default "lo")
    int ttl;                      // multicast TTL (default 0)
    bool loopback;                // multicast loopback (default yes)
    gw_peer_t peers[GW_PEERS_MAX];
    size_t peer_count;
} gw_udp_t;

#define GW_COT_TYPES_MAX 8
#define GW_COT_TYPE_LEN  48

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
    bool dis_pcapng;       // write the DIS sent to OUT/INSTANCE.pcapng (default no)
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
    // [stanag4607]
    bool s4607_file;               // write OUT/INSTANCE.4607 (default no)
    gw_udp_t s4607_udp;            // and send each packet (default off; 239.1.2.4:4607 on lo)
    bool s4607_truth_tag;          // target reports carry the DIS id of the entity (default no)
    char s4607_nationality[3];     // packet header (default "XN": NATO)
    int s4607_classification;      // 1 top secret .. 5 unclassified (default 5)
    char s4607_class_system[3];    // (default "XN")
    double s4607_platform_rate_hz; // platform location segments per simulated second (1)
    double s4607_mdv_mps;          // minimum detectable velocity in dwell and job (0.58)
    // [cot]
    gw_udp_t cot_udp;        // events out, and designations in (default off;
                             // 239.2.3.1:6969 on lo, the TAK SA group)
    bool cot_protobuf;       // TAK protobuf version 1 instead of XML (default no)
    double cot_stale_s;      // an event is stale this long after it is sent (default 15)
    double cot_rate_hz;      // events per wall-clock second, of each object (default 1)
    char cot_uid_prefix[32]; // every uid starts with it (default "mscgs")
    bool cot_designate;      // a client's point or task designates (default yes)
    char cot_designate_types[GW_COT_TYPES_MAX][GW_COT_TYPE_LEN]; // default b-m-p-s-p-i
    size_t cot_designate_type_count;
    char cot_designate_uav[64]; // UAV a point designates for ("" the first heard)
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
/* The same for a translator's UDP output (off never leaves). */
bool gw_params_udp_leaves_host (const gw_udp_t *u, bool interface_is_loopback);
/* Where it goes, in words ("off", "multicast to 239.2.3.1:6969 on lo, TTL 0",
 * "unicast to 127.0.0.1:4242 and 1 more"). */
void gw_params_describe_udp (const gw_udp_t *u, char *buf, size_t len);

#endif
