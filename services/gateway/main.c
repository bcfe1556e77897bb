/* gateway — the bridge between the bus and the outside world.
 * DIS: our entities go out as Entity State PDUs (dead reckoned, with
 * heartbeats), guidanced's UAV tasking as Action Requests; other
 * simulations' Entity State PDUs of the same exercise come in as external
 * entities on `entity`, and Action Requests addressed to our UAVs become
 * route tasks for uavsim, answered with Action Responses.
 * STANAG 4607 (when on): the radars' dwells, hits and platforms as GMTI
 * packets, to a file and over UDP.
 * Cursor on Target (when on): tracks, UAVs, intercept routes and sensor
 * footprints as CoT events over UDP; a client's point or task designates.
 * The codecs are in gw_*.c; this file wires them to UDP and the bus. */
#include "cgs_cmd.h"
#include "cgs_iface.h"
#include "cgs_log.h"
#include "cgs_pcapng.h"
#include "cgs_service.h"
#include "cgs_util.h"
#include "gw_cot.h"
#include "gw_cotout.h"
#include "gw_gmti.h"
#include "gw_in.h"
#include "gw_out.h"
#include "gw_params.h"
#include "gw_pdu.h"
#include "gw_s4607.h"
#include "gw_udp.h"
#include "intercept.pb-c.h"
#include "sensors.pb-c.h"
#include "tracking.pb-c.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <limits.h>
#include <math.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#define S_QUEUE               256   // Entity State PDUs sent in one sendmmsg round
#define S_RECV_BATCH          32    // datagrams read in one recvmmsg call
#define S_RECV_ROUNDS         64    // recvmmsg calls at most per readable event
#define S_DGRAM_MAX           65536 // largest datagram read
#define S_BATCH_MAX           200   // entities in one `entity` message
#define S_UAV_MAX             64
#define S_TRANSLATOR_PERIOD_S 0.1 // STANAG 4607 and CoT: pending dwells, due events (wall time)
#define S_REFUSALS_LOGGED     20  // CoT designations refused that are logged (then only counted)
#define S_ANSWERED            64 // Action Requests remembered, so a retransmission is answered, not redone
// Route points in one Action Request: 32 bytes each, with the header, the
// mission and speed datums and a text datum of at most 200 characters inside
// GW_PDU_MAX.
#define S_ROUTE_POINTS_MAX 240
#define S_TASK_TEXT_MAX    200
_Static_assert(GW_ACTION_BASE_LEN + 2 * 8 + S_ROUTE_POINTS_MAX * 32 + 8 + S_TASK_TEXT_MAX <=
                   GW_PDU_MAX,
               "a route Action Request fits in one PDU");
// External entities further than these from the ellipsoid are not on the
// Earth (an all-zero location is the Earth's centre): rejected.
#define S_HEIGHT_MIN_M -12000.0
#define S_HEIGHT_MAX_M 1000000.0

/* Datum ids (SISO-REF-010 variable record types). */
#define S_DATUM_GEOCENTRIC 31200u  // Geocentric Coordinates: a route point, 3 float64 ECEF
#define S_DATUM_SPEED      36400u  // Speed: float32 m/s (fixed datum)
#define S_DATUM_MISSION_ID 42100u  // Mission ID: the designation number (fixed datum)
#define S_DATUM_TEXT       240092u // Text: ASCII, for a person

typedef struct {
    uint32_t entity_id;
    char name[64];
    uint64_t task_sent;   // the UAV's last task sent out as an Action Request (0: none)
    uint64_t designation; // its latest intercept (guidanced's), for the Action Requests'
    uint32_t track_id;    // mission id and text (0: none)
    uint32_t replans;
} s_uav_t;

typedef struct {
    gw_id_t originator;
    uint32_t request_id;
    uint32_t status;
    char text[128];
} s_answer_t;

typedef struct {
    char uid[96];
    double time_s;
    char type[16];
    char text[256];
} s_cot_answer_t; // a CoT designation answered

typedef struct {
    cgs_service_t *svc;
    gw_params_t p;
    cgs_geo_t *geo;
    int fd;
    struct sockaddr_in dest[GW_PEERS_MAX];
    size_t ndest;
    /* [dis] pcapng: every datagram sent and received, as captured. */
    cgs_pcapng_t *pcap;
    char pcap_path[PATH_MAX];
    struct sockaddr_in pcap_src[GW_PEERS_MAX]; // the source each destination sees
    struct sockaddr_in pcap_local;             // our address and port, for what comes in
    double pcap_flushed;                       // wall time of the last flush
    cgs_iface_t ifc; // the interface the parameters name (zeroed: none named)
    gw_out_t *out;
    gw_in_t *in;
    double sim_time_s; // newest simulation time heard
    bool sim_heard;    // any: the exercise clock may be anchored
    bool clock_set;    // absolute timestamps: the exercise clock's anchor is known:
    double utc_at_s;   // UTC, seconds, when the gateway first heard simulation time
    double sim_at_s;   // that simulation time
    // Outbound queue.
    uint8_t queue[S_QUEUE][GW_ESPDU_LEN];
    size_t queued;
    // Inbound.
    uint8_t (*rbuf)[S_DGRAM_MAX];
    gw_action_t action; // decoded in place (large)
    s_uav_t uavs[S_UAV_MAX];
    size_t nuav;
    s_answer_t answered[S_ANSWERED];
    size_t nanswered;
    uint32_t next_request_id;
    const cgs_instance_t *uavsim;
    cgs_cmd_client_t *client;
    // External entities' messages, reused.
    Cgs__Entity *msgs;
    Cgs__Entity **ptrs;
    gw_in_storage_t *storage;
    size_t msg_cap, nmsg;
    // STANAG 4607 and Cursor on Target.
    char out_dir[PATH_MAX - 64]; // --out: where the .4607 file goes (default the state folder)
    char s4607_path[PATH_MAX];
    int s4607_fd; // the .4607 file (-1: none): whole packets, appended
    gw_gmti_t *gmti;
    gw_udp_sock_t s4607_udp;
    gw_cotout_t *cotout;
    gw_udp_sock_t cot_udp;
    const cgs_instance_t *guidanced;
    cgs_cmd_client_t *guidance; // designations from CoT clients
    uint64_t s4607_bytes, s4607_file_errors, cot_in, cot_rejected, cot_ignored, cot_own,
        cot_designations, cot_refused, cot_replies, cot_unencodable;
    uint64_t next_reply, cot_repeats;
    s_cot_answer_t cot_answered[S_ANSWERED];
    size_t cot_nanswered;
    // Counts, in health.
    uint64_t espdu_out, action_out, response_out, send_errors, datagrams_in, pdus_in, espdu_in,
        foreign, own, other_types, rejected, not_for_us, table_full, unsendable, tasks_accepted,
        tasks_refused, responses_in;
} s_app_t;

/* ---- time ---------------------------------------------------------------------------------- */

static double s_wall (void)
{
    struct timespec ts;
    clock_gettime (CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* The exercise clock's anchor: UTC when the gateway first heard simulation
 * time, that simulation time (the DIS timestamps and the STANAG 4607 times
 * run from it). */
static void s_anchor (s_app_t *app, double t_s)
{
    if (app->clock_set || !isfinite (t_s))
        return;
    app->clock_set = true;
    app->utc_at_s = s_wall ();
    app->sim_at_s = t_s;
    if (app->gmti)
        gw_gmti_set_clock (app->gmti, app->utc_at_s, app->sim_at_s);
}

/* A PDU's timestamp: the simulation time t_s of what it says, past the hour,
 * so that a receiver dead-reckoning by the timestamps moves our entities at
 * their velocities (simulation metres per second) at any time scale.
 * Relative: the exercise's simulation time. Absolute: the exercise clock,
 * UTC when the gateway first heard simulation time plus the simulation
 * time since: UTC itself at time scale 1, running at the scale otherwise. */
static uint32_t s_timestamp (s_app_t *app, double t_s)
{
    if (!isfinite (t_s))
        t_s = isfinite (app->sim_time_s) ? app->sim_time_s : 0;
    if (!app->p.absolute_time)
        return gw_pdu_timestamp (t_s, false);
    if (!app->clock_set && !app->sim_heard) // nothing of the simulation yet: UTC
        return gw_pdu_timestamp (fmod (s_wall (), 3600.0), true);
    s_anchor (app, t_s);
    return gw_pdu_timestamp (fmod (app->utc_at_s, 3600.0) + (t_s - app->sim_at_s), true);
}

static gw_header_t s_header (s_app_t *app, double t_s)
{
    gw_header_t h = {0};
    h.version = (uint8_t)app->p.version;
    h.exercise = (uint8_t)cgs_exercise_id (cgs_service_exercise (app->svc));
    h.timestamp = s_timestamp (app, t_s);
    h.status = GW_STATUS_LVC_CONSTRUCTIVE;
    return h;
}

/* ---- sending ------------------------------------------------------------------------------- */

/* The datagrams of mm just sent, into the pcapng file; written out at
 * least every 0.5 s (and each second by s_counters). */
static void s_capture (s_app_t *app, const struct mmsghdr *mm, size_t n)
{
    struct timespec ts;
    clock_gettime (CLOCK_REALTIME, &ts);
    uint64_t now_ns = (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
    for (size_t i = 0; i < n; i++) {
        const struct sockaddr_in *to = mm[i].msg_hdr.msg_name;
        size_t d = (size_t)(to - app->dest);
        const struct iovec *v = mm[i].msg_hdr.msg_iov;
        if (cgs_pcapng_udp (app->pcap, now_ns, &app->pcap_src[d < app->ndest ? d : 0], to,
                            v->iov_base, v->iov_len) == -EIO)
            break;
    }
    double now = cgs_loop_now ();
    if (now - app->pcap_flushed >= 0.5) {
        cgs_pcapng_flush (app->pcap);
        app->pcap_flushed = now;
    }
    if (*cgs_pcapng_error (app->pcap) && app->send_errors == 0) {
        cgs_health_set_error (cgs_service_health (app->svc), cgs_pcapng_error (app->pcap));
    }
}

/* The datagrams just received, into the pcapng file: from their sender to
 * the address each came to (IP_PKTINFO: a multicast group's, or ours), at
 * our port; a datagram cut short is written as far as it was read. */
static void s_capture_in (s_app_t *app, const struct mmsghdr *mm, const struct sockaddr_in *from,
                          int n)
{
    struct timespec ts;
    clock_gettime (CLOCK_REALTIME, &ts);
    uint64_t now_ns = (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
    for (int i = 0; i < n; i++) {
        struct sockaddr_in to = app->pcap_local;
        struct msghdr *h = (struct msghdr *)&mm[i].msg_hdr;
        for (struct cmsghdr *c = CMSG_FIRSTHDR (h); c; c = CMSG_NXTHDR (h, c))
            if (c->cmsg_level == IPPROTO_IP && c->cmsg_type == IP_PKTINFO) {
                struct in_pktinfo pi;
                memcpy (&pi, CMSG_DATA (c), sizeof pi);
                to.sin_addr = pi.ipi_addr;
            }
        size_t len = mm[i].msg_len < S_DGRAM_MAX ? mm[i].msg_len : S_DGRAM_MAX;
        if (cgs_pcapng_udp (app->pcap, now_ns, &from[i], &to, app->rbuf[i], len) == -EIO)
            break;
    }
}

/* Send n PDUs (bufs/lens) to every destination. */
static void s_send (s_app_t *app, uint8_t *const *bufs, const size_t *lens, size_t n)
{
    struct mmsghdr mm[S_QUEUE];
    struct iovec iov[S_QUEUE];
    size_t k = 0;
    for (size_t d = 0; d < app->ndest; d++) {
        for (size_t i = 0; i < n; i++) {
            iov[k] = (struct iovec){bufs[i], lens[i]};
            memset (&mm[k], 0, sizeof mm[k]);
            mm[k].msg_hdr.msg_name = &app->dest[d];
            mm[k].msg_hdr.msg_namelen = sizeof app->dest[d];
            mm[k].msg_hdr.msg_iov = &iov[k];
            mm[k].msg_hdr.msg_iovlen = 1;
            if (++k == S_QUEUE || (d + 1 == app->ndest && i + 1 == n)) {
                size_t at = 0;
                while (at < k) {
                    int sent = sendmmsg (app->fd, mm + at, (unsigned)(k - at), 0);
                    if (sent <= 0) {
                        if (sent < 0 && errno == EINTR)
                            continue;
                        app->send_errors += k - at; // full buffer or no route: DIS is lossy
                        if (app->send_errors == k - at) {
                            char why[160];
                            snprintf (why, sizeof why, "DIS send failed: %s",
                                      sent < 0 ? strerror (errno) : "nothing sent");
                            cgs_log (LOG_WARNING, "%s (counted in health, logged once)", why);
                            cgs_health_set_error (cgs_service_health (app->svc), why);
                        }
                        break;
                    }
                    if (app->pcap)
                        s_capture (app, mm + at, (size_t)sent);
                    at += (size_t)sent;
                }
                k = 0;
            }
        }
    }
}

static void s_flush (s_app_t *app)
{
    if (!app->queued)
        return;
    uint8_t *bufs[S_QUEUE];
    size_t lens[S_QUEUE];
    for (size_t i = 0; i < app->queued; i++) {
        bufs[i] = app->queue[i];
        lens[i] = GW_ESPDU_LEN;
    }
    // Each destination gets every PDU: send in rounds that fit the message array.
    size_t per = S_QUEUE / (app->ndest ? app->ndest : 1);
    for (size_t at = 0; at < app->queued; at += per) {
        size_t n = app->queued - at < per ? app->queued - at : per;
        s_send (app, bufs + at, lens + at, n);
    }
    app->espdu_out += app->queued;
    app->queued = 0;
}

static void s_send_one (s_app_t *app, uint8_t *buf, size_t len)
{
    uint8_t *bufs[1] = {buf};
    s_send (app, bufs, &len, 1);
}

/* ---- outbound entities --------------------------------------------------------------------- */

static gw_id_t s_dis_id (const s_app_t *app, uint32_t entity_id)
{
    return (gw_id_t){(uint16_t)app->p.site, (uint16_t)app->p.application,
                     (uint16_t)(app->p.entity_id_base + entity_id)};
}

static void s_on_entity (void *arg, const char *topic, const ProtobufCMessage *msg,
                         const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    const Cgs__EntityBatch *b = (const Cgs__EntityBatch *)msg;
    if (hdr->source && strcmp (hdr->source, cgs_service_instance_name (app->svc)) == 0)
        return; // our own external entities, back from the bus
    if (!isfinite (hdr->sim_time_s)) {
        cgs_service_bad_input (app->svc, "an entity batch with a non-finite time");
        return;
    }
    if (hdr->sim_time_s > app->sim_time_s)
        app->sim_time_s = hdr->sim_time_s;
    app->sim_heard = true;
    double now = cgs_loop_now ();
    for (size_t i = 0; i < b->n_entities; i++) {
        const Cgs__Entity *e = b->entities[i];
        if (e->external)
            continue; // came from DIS: its own simulation sends it
        gw_truth_t t;
        if (gw_out_truth (app->geo, e, &t) < 0) {
            cgs_service_bad_input (app->svc, "an entity without a usable position, velocity "
                                             "or attitude");
            continue;
        }
        if ((long)app->p.entity_id_base + (long)e->entity_id > 65534) {
            if (app->unsendable++ == 0)
                cgs_log (LOG_WARNING,
                         "entity %u: DIS entity number %ld is beyond 65534: not sent (counted, "
                         "logged once)",
                         e->entity_id, (long)app->p.entity_id_base + (long)e->entity_id);
            continue;
        }
        gw_send_t send;
        gw_dr_t dr;
        if (gw_out_update (app->out, &t, hdr->sim_time_s, now, &send, &dr) < 0) {
            cgs_health_set_error (cgs_service_health (app->svc),
                                  "out of memory for outbound entities");
            continue;
        }
        if (send == GW_SEND_NONE)
            continue;
        gw_espdu_t pdu;
        pdu.hdr = s_header (app, hdr->sim_time_s);
        gw_out_fill (&t, &dr, s_dis_id (app, e->entity_id), &pdu);
        if (gw_pdu_encode_espdu (&pdu, app->queue[app->queued], GW_ESPDU_LEN) == 0)
            continue; // cannot happen: a fixed-size PDU of a checked version
        if (++app->queued == S_QUEUE)
            s_flush (app);
    }
    s_flush (app);
}

/* ---- outbound tasking ---------------------------------------------------------------------- */

static s_uav_t *s_uav (s_app_t *app, uint32_t entity_id)
{
    for (size_t i = 0; i < app->nuav; i++)
        if (app->uavs[i].entity_id == entity_id)
            return &app->uavs[i];
    return NULL;
}

/* A text datum: the string, its length in bits (padded to 64 on the wire). */
static gw_var_datum_t s_text_datum (const char *text)
{
    return (gw_var_datum_t){S_DATUM_TEXT, (uint32_t)strlen (text) * 8, (const uint8_t *)text};
}

/* The task the UAV flies now (its `uav` message), out as an Action Request:
 * the route's points (or the loiter centre), the mission id (the latest
 * designation), the commanded airspeed, and a text that says which task. */
static void s_send_task (s_app_t *app, s_uav_t *s, const Cgs__Uav *u, double t_s)
{
    static uint8_t points[S_ROUTE_POINTS_MAX][24];
    gw_action_t *a = &app->action;
    memset (&a->hdr, 0, sizeof a->hdr);
    a->hdr = s_header (app, t_s);
    a->hdr.type = GW_PDU_ACTION_REQUEST;
    a->originator = (gw_id_t){(uint16_t)app->p.site, (uint16_t)app->p.application, 0};
    a->receiver = s_dis_id (app, u->entity_id);
    a->request_id = ++app->next_request_id;
    a->action_or_status = (uint32_t)app->p.route_action_id;
    a->n_fixed = 0;
    a->fixed[a->n_fixed++] = (gw_fixed_datum_t){S_DATUM_MISSION_ID, (uint32_t)s->designation};
    if (isfinite (u->commanded_airspeed_mps) && u->commanded_airspeed_mps > 0) {
        float v = (float)u->commanded_airspeed_mps;
        uint32_t bits;
        memcpy (&bits, &v, sizeof bits);
        a->fixed[a->n_fixed++] = (gw_fixed_datum_t){S_DATUM_SPEED, bits};
    }
    // The route's points, or the loiter orbit's centre; a long route is cut
    // to what one PDU holds, and the text says so.
    bool route = u->mode == CGS__UAV_MODE__UAV_MODE_ROUTE && u->n_route > 0;
    Cgs__Enu *const *pts = route ? u->route : (u->loiter ? &u->loiter->center : NULL);
    size_t total = route ? u->n_route : (u->loiter && u->loiter->center ? 1 : 0);
    size_t n = total < S_ROUTE_POINTS_MAX ? total : S_ROUTE_POINTS_MAX;
    a->n_var = 0;
    for (size_t k = 0; k < n; k++) {
        const Cgs__Enu *p = pts[k];
        cgs_ecef_t x;
        if (!p ||
            cgs_geo_enu_to_ecef (app->geo, (cgs_enu_t){p->east_m, p->north_m, p->up_m}, &x) < 0) {
            cgs_service_bad_input (app->svc, "a uav message with a route point that is not finite");
            s->task_sent = u->task_number; // said once, not on every uav message
            return;
        }
        gw_pdu_put_f64x3 (points[k], (double[3]){x.x_m, x.y_m, x.z_m});
        a->var[a->n_var++] = (gw_var_datum_t){S_DATUM_GEOCENTRIC, 192, points[k]};
    }
    char text[S_TASK_TEXT_MAX];
    int used;
    if (route)
        used = snprintf (text, sizeof text, "mscgs task %" PRIu64 " of %s: route of %zu points",
                         u->task_number, s->name, total);
    else
        used =
            snprintf (text, sizeof text, "mscgs task %" PRIu64 " of %s: loiter, radius %.0f m, %s",
                      u->task_number, s->name, u->loiter ? u->loiter->radius_m : 0.0,
                      u->loiter && u->loiter->clockwise ? "clockwise" : "anticlockwise");
    if (n < total && used > 0 && (size_t)used < sizeof text)
        used += snprintf (text + used, sizeof text - (size_t)used, ", first %zu", n);
    if (s->track_id && used > 0 && (size_t)used < sizeof text)
        snprintf (text + used, sizeof text - (size_t)used,
                  "; intercept of track %u, designation %" PRIu64 ", replan %u", s->track_id,
                  s->designation, s->replans);
    a->var[a->n_var++] = s_text_datum (text);
    static uint8_t buf[GW_PDU_MAX];
    size_t len = gw_pdu_encode_action (a, buf, sizeof buf);
    if (len == 0) {
        cgs_health_set_error (cgs_service_health (app->svc), "a UAV task too long for one PDU");
        s->task_sent = u->task_number; // said once, not on every uav message
        return;
    }
    s_send_one (app, buf, len);
    app->action_out++;
    s->task_sent = u->task_number;
    cgs_log (LOG_INFO, "%s: task %" PRIu64 " (%s, %zu points) out as Action Request %u", s->name,
             u->task_number, route ? "route" : "loiter", n, a->request_id);
}

static void s_on_uav (void *arg, const char *topic, const ProtobufCMessage *msg,
                      const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    const Cgs__Uav *u = (const Cgs__Uav *)msg;
    if (u->entity_id == 0) {
        cgs_service_bad_input (app->svc, "a uav message without an entity id");
        return;
    }
    s_uav_t *s = s_uav (app, u->entity_id);
    if (!s) {
        if (app->nuav == S_UAV_MAX)
            return;
        s = &app->uavs[app->nuav++];
        memset (s, 0, sizeof *s);
        s->entity_id = u->entity_id;
        cgs_log (LOG_INFO, "UAV %s is entity %u, DIS %u:%u:%u", u->name ? u->name : "?",
                 u->entity_id, app->p.site, app->p.application,
                 app->p.entity_id_base + u->entity_id);
    }
    snprintf (s->name, sizeof s->name, "%s", u->name ? u->name : "");
    if (hdr && isfinite (hdr->sim_time_s)) {
        s_anchor (app, hdr->sim_time_s);
        if (app->gmti)
            gw_gmti_on_uav (app->gmti, u, hdr->sim_time_s);
    }
    if (app->cotout)
        gw_cotout_on_uav (app->cotout, u, s_wall ());
    // Every task the UAV takes (route, loiter, altitude, speed: each new
    // task number) goes out once, as it flies it.
    if (u->task_number != 0 && u->task_number != s->task_sent)
        s_send_task (app, s, u, hdr ? hdr->sim_time_s : NAN);
}

/* guidanced's intercept: what the next tasks of its UAV are for. */
static void s_on_intercept (void *arg, const char *topic, const ProtobufCMessage *msg,
                            const Cgs__Header *hdr)
{
    (void)topic;
    (void)hdr;
    s_app_t *app = arg;
    const Cgs__Intercept *m = (const Cgs__Intercept *)msg;
    if (app->cotout)
        gw_cotout_on_intercept (app->cotout, m, s_wall ());
    s_uav_t *u = s_uav (app, m->uav_id);
    if (!u)
        return; // no UAV heard of yet
    u->designation = m->designation_number;
    u->track_id = m->track_id;
    u->replans = m->replans;
}

/* ---- STANAG 4607 --------------------------------------------------------------------------- */

/* Open the .4607 file to append. A file that ends in part of a packet (the
 * disk filled, or the gateway was killed in a write) is cut back to its
 * last whole packet first, so the packets appended after it are read. The
 * fd, or -errno with the reason in err. */
static int s_open_4607 (const char *path, char *err, size_t errlen)
{
    int fd = open (path, O_RDWR | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (fd < 0) {
        int e = errno;
        snprintf (err, errlen, "cannot open %s: %s (the STANAG 4607 file)", path, strerror (e));
        return -e;
    }
    off_t end = lseek (fd, 0, SEEK_END), at = 0;
    uint8_t h[GW_S4607_HEADER_LEN];
    while (at < end) {
        if (pread (fd, h, sizeof h, at) != (ssize_t)sizeof h)
            break;
        uint32_t size = (uint32_t)h[2] << 24 | (uint32_t)h[3] << 16 | (uint32_t)h[4] << 8 | h[5];
        if (size < GW_S4607_HEADER_LEN || at + (off_t)size > end)
            break;
        at += size;
    }
    if (at < end) {
        cgs_log (LOG_WARNING,
                 "%s ends in part of a packet (%lld bytes from %lld): cut back to "
                 "its last whole packet",
                 path, (long long)(end - at), (long long)at);
        if (ftruncate (fd, at) < 0) {
            int e = errno;
            snprintf (err, errlen, "cannot cut %s back to its last whole packet: %s", path,
                      strerror (e));
            close (fd);
            return -e;
        }
    }
    return fd;
}

/* A finished 4607 packet: to the file and over UDP. */
static void s_on_packet (void *arg, const uint8_t *packet, size_t len)
{
    s_app_t *app = arg;
    app->s4607_bytes += len;
    if (app->s4607_fd >= 0 && cgs_write_all (app->s4607_fd, packet, len) < 0) {
        if (app->s4607_file_errors++ == 0) {
            char why[PATH_MAX + 64];
            snprintf (why, sizeof why, "cannot write %s: %s", app->s4607_path, strerror (errno));
            cgs_log (LOG_ERR, "%s (counted in health, logged once)", why);
            cgs_health_set_error (cgs_service_health (app->svc), why);
        }
    }
    gw_udp_send (&app->s4607_udp, packet, len, NULL);
}

static void s_on_mti (void *arg, const char *topic, const ProtobufCMessage *msg,
                      const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    if (hdr && isfinite (hdr->sim_time_s))
        s_anchor (app, hdr->sim_time_s);
    int rc = gw_gmti_on_mti (app->gmti, (const Cgs__Mti *)msg);
    if (rc == -ENOMEM)
        cgs_health_set_error (cgs_service_health (app->svc),
                              "out of memory for a dwell's STANAG 4607 reports");
    else if (rc < 0)
        cgs_service_bad_input (app->svc, "an mti message without a radar (uav id), a platform "
                                         "position on the Earth or finite dwell times: no "
                                         "STANAG 4607 dwell");
}

static void s_on_mti_truth (void *arg, const char *topic, const ProtobufCMessage *msg,
                            const Cgs__Header *hdr)
{
    (void)topic;
    (void)hdr;
    s_app_t *app = arg;
    gw_gmti_on_truth (app->gmti, (const Cgs__MtiTruth *)msg);
}

/* ---- Cursor on Target ---------------------------------------------------------------------- */

static void s_cot_send (s_app_t *app, const gw_cot_event_t *e, const struct sockaddr_in *also)
{
    static uint8_t buf[GW_COT_ENCODED_MAX];
    size_t len = app->p.cot_protobuf ? gw_cot_encode_proto (e, buf, sizeof buf)
                                     : gw_cot_encode_xml (e, (char *)buf, sizeof buf);
    if (len == 0) {
        if (app->cot_unencodable++ == 0)
            cgs_log (LOG_WARNING, "CoT event %s (%s) cannot be encoded (counted, logged once)",
                     e->uid, e->type);
        return;
    }
    gw_udp_send (&app->cot_udp, buf, len, also);
}

static void s_on_cot_event (void *arg, const gw_cot_event_t *e)
{
    s_cot_send (arg, e, NULL);
}

static void s_on_track (void *arg, const char *topic, const ProtobufCMessage *msg,
                        const Cgs__Header *hdr)
{
    (void)topic;
    (void)hdr;
    s_app_t *app = arg;
    gw_cotout_on_tracks (app->cotout, (const Cgs__TrackBatch *)msg, s_wall ());
}

/* What a client's event is to us: a point of one of the parameters' types
 * (for the parameters' UAV), a task (t-x-..., not TAK's control, delete or
 * protocol messages) addressed to one of our UAVs, or nothing (false). For
 * a point, *ret_uav may be 0: the parameters' UAV is not in the exercise,
 * or none is heard yet (answered with that reason). */
static bool s_designation (const s_app_t *app, const gw_cot_event_t *e, uint32_t *ret_uav)
{
    *ret_uav = 0;
    if (strcmp (e->type, "t-x") == 0 || strncmp (e->type, "t-x-", 4) == 0) {
        if (strncmp (e->type, "t-x-c", 5) == 0 || strncmp (e->type, "t-x-d", 5) == 0 ||
            strncmp (e->type, "t-x-takp", 8) == 0)
            return false;
        if (*e->dest_callsign)
            *ret_uav = gw_cotout_uav_id (app->cotout, e->dest_callsign);
        if (!*ret_uav && *e->dest_uid)
            *ret_uav = gw_cotout_uav_id (app->cotout, e->dest_uid);
        return *ret_uav != 0; // a task for somebody else is not ours
    }
    for (size_t i = 0; i < app->p.cot_designate_type_count; i++)
        if (strcmp (e->type, app->p.cot_designate_types[i]) == 0) {
            *ret_uav = gw_cotout_uav_id (app->cotout, app->p.cot_designate_uav);
            return true;
        }
    return false;
}

/* Answer a client's designation (CoT reply types): y-a-w (will comply),
 * y-a-r (received: guidanced did not answer in time, and may still act),
 * y-c-f-r (rejected), y-c-f-s (stale); at its point, with the reason, to
 * the client and to the CoT destinations; remembered, so that the same
 * event again gets the same answer and is not done twice. */
static void s_cot_reply (s_app_t *app, const gw_cot_event_t *req, const struct sockaddr_in *from,
                         const char *type, const char *text)
{
    gw_cot_event_t r;
    gw_cot_event_init (&r);
    double now = s_wall ();
    snprintf (r.uid, sizeof r.uid, "%s-%u.reply.%" PRIu64, app->p.cot_uid_prefix,
              cgs_exercise_id (cgs_service_exercise (app->svc)), ++app->next_reply);
    snprintf (r.type, sizeof r.type, "%s", type);
    snprintf (r.how, sizeof r.how, "m-g");
    snprintf (r.opex, sizeof r.opex, "s-%s", app->p.cot_uid_prefix);
    r.time_s = r.start_s = now;
    r.stale_s = now + app->p.cot_stale_s;
    r.point = req->point;
    snprintf (r.callsign, sizeof r.callsign, "mscgs");
    snprintf (r.remarks, sizeof r.remarks, "re %s (%s): %s", req->uid, req->type, text);
    s_cot_send (app, &r, from);
    app->cot_replies++;
    s_cot_answer_t *a = &app->cot_answered[app->cot_nanswered++ % S_ANSWERED];
    snprintf (a->uid, sizeof a->uid, "%s", req->uid);
    a->time_s = req->time_s;
    snprintf (a->type, sizeof a->type, "%s", type);
    snprintf (a->text, sizeof a->text, "%s", text);
}

/* A designation's outcome in the log: every one taken, the first 20
 * refused (a network sender must not fill the log), then only counted. */
static void s_cot_log (s_app_t *app, const gw_cot_event_t *e, bool taken, const cgs_enu_t *p,
                       const char *text)
{
    if (taken)
        cgs_log (LOG_NOTICE, "CoT %s %s at %.7f %.7f (local %.2f %.2f) designates: %s", e->type,
                 e->uid, e->point.lat_deg, e->point.lon_deg, p->e_m, p->n_m, text);
    else if (app->cot_refused <= S_REFUSALS_LOGGED)
        cgs_log (LOG_NOTICE, "CoT %s %s at %.7f %.7f does not designate: %s%s", e->type, e->uid,
                 e->point.lat_deg, e->point.lon_deg, text,
                 app->cot_refused == S_REFUSALS_LOGGED ? " (further refusals are only counted)"
                                                       : "");
}

/* A client's designation: the track whose newest hit is nearest its point,
 * for that UAV. */
static void s_cot_designate (s_app_t *app, const gw_cot_event_t *e, uint32_t uav,
                             const struct sockaddr_in *from)
{
    // The same event again (a client resends, ATAK repeats its points):
    // answered as it was, not done twice.
    for (size_t i = 0; i < app->cot_nanswered && i < S_ANSWERED; i++) {
        const s_cot_answer_t *a = &app->cot_answered[i];
        if (a->time_s == e->time_s && strcmp (a->uid, e->uid) == 0) {
            app->cot_repeats++;
            s_cot_reply (app, e, from, a->type, a->text);
            return;
        }
    }
    char text[256];
    const char *type = "y-c-f-r";
    cgs_enu_t p = {0, 0, 0};
    cgs_geodetic_t g = {e->point.lat_deg, e->point.lon_deg, e->point.hae_m};
    if (e->stale_s < s_wall ()) {
        type = "y-c-f-s";
        snprintf (text, sizeof text, "the event was stale when it came");
    } else if (!uav) {
        if (*app->p.cot_designate_uav)
            snprintf (text, sizeof text, "no UAV %s in this exercise ([cot] designate_uav)",
                      app->p.cot_designate_uav);
        else
            snprintf (text, sizeof text, "no UAV heard yet");
    } else if (cgs_geo_geodetic_to_enu (app->geo, g, &p) < 0 || hypot (p.e_m, p.n_m) > 1e6) {
        snprintf (text, sizeof text, "the point is not within 1000 km of the exercise");
    } else if (!app->guidance) {
        snprintf (text, sizeof text, "no guidanced command endpoint in the exercise");
    } else {
        Cgs__Enu at = CGS__ENU__INIT;
        at.east_m = p.e_m, at.north_m = p.n_m, at.up_m = p.u_m;
        Cgs__Designate d = CGS__DESIGNATE__INIT;
        d.uav_id = uav;
        d.target_case = CGS__DESIGNATE__TARGET_POINT;
        d.point = &at;
        Cgs__Command cmd = CGS__COMMAND__INIT;
        cmd.body_case = CGS__COMMAND__BODY_DESIGNATE;
        cmd.designate = &d;
        Cgs__Reply *reply = NULL;
        char err[256];
        // Blocks the loop for at most task_timeout_s, as a DIS route task does.
        int rc = cgs_cmd_client_call (app->guidance, &cmd, (int)(app->p.task_timeout_s * 1000), 1,
                                      &reply, err, sizeof err);
        if (rc < 0) {
            type = "y-a-r";
            snprintf (text, sizeof text, "guidanced did not answer in time: it may still act");
            cgs_health_set_error (cgs_service_health (app->svc), err);
        } else if (reply->status == CGS__REPLY_STATUS__REPLY_STATUS_OK ||
                   reply->status == CGS__REPLY_STATUS__REPLY_STATUS_NOT_SAVED) {
            snprintf (text, sizeof text, "%s",
                      reply->detail && *reply->detail ? reply->detail : "designated");
            app->cot_designations++;
            cgs_cmd_reply_free (&reply);
            s_cot_log (app, e, true, &p, text);
            s_cot_reply (app, e, from, "y-a-w", text);
            return;
        } else {
            snprintf (text, sizeof text, "guidanced refused: %s",
                      reply->error ? reply->error : "no reason");
        }
        cgs_cmd_reply_free (&reply);
    }
    app->cot_refused++;
    s_cot_log (app, e, false, &p, text);
    s_cot_reply (app, e, from, type, text);
}

static void s_on_cot_udp (void *arg)
{
    s_app_t *app = arg;
    for (int round = 0; round < S_RECV_BATCH; round++) {
        struct sockaddr_in from;
        socklen_t fl = sizeof from;
        ssize_t n = recvfrom (app->cot_udp.rfd, app->rbuf[0], S_DGRAM_MAX, MSG_DONTWAIT | MSG_TRUNC,
                              (struct sockaddr *)&from, &fl);
        if (n < 0)
            return;
        if (gw_udp_from_self (&app->cot_udp, &from)) {
            app->cot_own++; // our own, back over multicast loopback: not even decoded
            continue;
        }
        app->cot_in++;
        gw_cot_event_t e;
        char why[256] = "";
        int rc = n > S_DGRAM_MAX
                     ? -EMSGSIZE
                     : gw_cot_decode (app->rbuf[0], (size_t)n, &e, NULL, why, sizeof why);
        if (rc == -ENOMSG) { // a TAK control announcement: nothing to do
            app->cot_ignored++;
            continue;
        }
        if (rc < 0) {
            char what[400], addr[INET_ADDRSTRLEN] = "?";
            inet_ntop (AF_INET, &from.sin_addr, addr, sizeof addr);
            snprintf (what, sizeof what, "a CoT datagram from %s:%u: %s", addr,
                      ntohs (from.sin_port), rc == -EMSGSIZE ? "larger than 65536 bytes" : why);
            // Logged the first time here (the service logs only its first
            // bad input of any kind), counted in health as malformed too.
            if (app->cot_rejected++ == 0)
                cgs_log (LOG_WARNING, "rejected %s (further ones are only counted)", what);
            cgs_service_bad_input (app->svc, what);
            continue;
        }
        if (gw_cotout_is_ours (app->cotout, e.uid)) {
            app->cot_own++; // our own, relayed back by another host
            continue;
        }
        uint32_t uav;
        if (!app->p.cot_designate || !s_designation (app, &e, &uav)) {
            app->cot_ignored++;
            continue;
        }
        s_cot_designate (app, &e, uav, &from);
    }
}

/* A translator's failed sends: counted, logged once, the health's last error. */
static void s_udp_errors (s_app_t *app, gw_udp_sock_t *s, const char *what)
{
    if (!s->error_pending)
        return;
    s->error_pending = false;
    if (s->errors > 1)
        return; // logged the first time
    char why[160];
    snprintf (why, sizeof why, "%s send failed: %s", what, strerror (s->last_errno));
    cgs_log (LOG_WARNING, "%s (counted in health, logged once)", why);
    cgs_health_set_error (cgs_service_health (app->svc), why);
}

static void s_on_translators (void *arg)
{
    s_app_t *app = arg;
    if (app->gmti) {
        gw_gmti_tick (app->gmti);
        s_udp_errors (app, &app->s4607_udp, "STANAG 4607");
    }
    if (app->cotout) {
        gw_cotout_tick (app->cotout, s_wall ());
        s_udp_errors (app, &app->cot_udp, "CoT");
    }
}

/* ---- inbound ------------------------------------------------------------------------------- */

static bool s_ours (const s_app_t *app, gw_id_t id)
{
    return id.site == app->p.site && id.application == app->p.application;
}

static void s_reject (s_app_t *app, const struct sockaddr_in *from, const char *why)
{
    app->rejected++;
    char what[256];
    char addr[INET_ADDRSTRLEN] = "?";
    if (from)
        inet_ntop (AF_INET, &from->sin_addr, addr, sizeof addr);
    snprintf (what, sizeof what, "a DIS datagram from %s:%u: %s", addr,
              from ? ntohs (from->sin_port) : 0, why);
    cgs_service_bad_input (app->svc, what);
}

/* Answer an Action Request. */
static void s_respond (s_app_t *app, const gw_action_t *req, uint32_t status, const char *text)
{
    static gw_action_t response; // large: kept off the stack, and not allocated per answer
    gw_action_t *r = &response;
    memset (r, 0, sizeof *r);
    r->hdr = s_header (app, app->sim_time_s);
    r->hdr.type = GW_PDU_ACTION_RESPONSE;
    r->originator = req->receiver;
    r->receiver = req->originator;
    r->request_id = req->request_id;
    r->action_or_status = status;
    r->n_var = 1;
    r->var[0] = s_text_datum (text);
    uint8_t buf[1024];
    size_t len = gw_pdu_encode_action (r, buf, sizeof buf);
    if (len) {
        s_send_one (app, buf, len);
        app->response_out++;
    }
}

/* A route task from an Action Request: uavsim's verdict as a request status and text. */
static uint32_t s_route_task (s_app_t *app, const gw_action_t *a, const s_uav_t *u, char *text,
                              size_t textlen)
{
    static Cgs__Enu pts[GW_DATUM_MAX];
    static Cgs__Enu *ptr[GW_DATUM_MAX];
    size_t n = 0;
    double speed = 0;
    for (uint32_t i = 0; i < a->n_var; i++) {
        const gw_var_datum_t *d = &a->var[i];
        if (d->id != S_DATUM_GEOCENTRIC)
            continue;
        if (d->length_bits != 192) {
            snprintf (text, textlen, "route point %u: %u bits, expected 192 (3 float64 ECEF)",
                      i + 1, d->length_bits);
            return GW_STATUS_REJECTED;
        }
        double v[3];
        gw_pdu_get_f64x3 (d->value, v);
        cgs_ecef_t x = {v[0], v[1], v[2]};
        cgs_enu_t p;
        if (!isfinite (x.x_m) || !isfinite (x.y_m) || !isfinite (x.z_m) ||
            cgs_geo_ecef_to_enu (app->geo, x, &p) < 0 || hypot (p.e_m, p.n_m) > 1e6) {
            snprintf (text, textlen, "route point %zu is not within 1000 km of the exercise",
                      n + 1);
            return GW_STATUS_REJECTED;
        }
        cgs__enu__init (&pts[n]);
        pts[n].east_m = p.e_m, pts[n].north_m = p.n_m, pts[n].up_m = p.u_m;
        ptr[n] = &pts[n];
        n++;
    }
    for (uint32_t i = 0; i < a->n_fixed; i++)
        if (a->fixed[i].id == S_DATUM_SPEED) {
            float f;
            uint32_t bits = a->fixed[i].value;
            memcpy (&f, &bits, sizeof f);
            speed = f;
        }
    if (n == 0) {
        snprintf (text, textlen, "no route points (variable datums %u, 3 float64 ECEF each)",
                  S_DATUM_GEOCENTRIC);
        return GW_STATUS_REJECTED;
    }
    if (!isfinite (speed) || speed < 0) {
        snprintf (text, textlen, "speed datum is not a usable number");
        return GW_STATUS_REJECTED;
    }
    if (!app->client) {
        snprintf (text, textlen, "no uavsim command endpoint in the exercise");
        return GW_STATUS_REJECTED;
    }
    Cgs__TaskRoute route = CGS__TASK_ROUTE__INIT;
    route.uav_id = u->entity_id;
    route.waypoints = ptr;
    route.n_waypoints = n;
    route.airspeed_mps = speed;
    route.loiter_at_end = true;
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_TASK_ROUTE;
    cmd.task_route = &route;
    Cgs__Reply *reply = NULL;
    char err[256];
    int rc = cgs_cmd_client_call (app->client, &cmd, (int)(app->p.task_timeout_s * 1000), 1, &reply,
                                  err, sizeof err);
    if (rc < 0) {
        snprintf (text, textlen, "uavsim did not answer: retry later");
        cgs_health_set_error (cgs_service_health (app->svc), err);
        // The client's next call resends under a new number; a late task is still one task.
        return GW_STATUS_RETRANSMIT_LATER;
    }
    uint32_t status;
    if (reply->status == CGS__REPLY_STATUS__REPLY_STATUS_OK ||
        reply->status == CGS__REPLY_STATUS__REPLY_STATUS_NOT_SAVED) {
        snprintf (text, textlen, "%s: route of %zu points: %s", u->name, n,
                  reply->detail && *reply->detail ? reply->detail : "accepted");
        status = GW_STATUS_EXECUTING;
        app->tasks_accepted++;
    } else {
        snprintf (text, textlen, "uavsim refused: %s", reply->error ? reply->error : "no reason");
        status = GW_STATUS_REJECTED;
        app->tasks_refused++;
    }
    cgs_cmd_reply_free (&reply);
    return status;
}

static void s_on_action_request (s_app_t *app, const gw_action_t *a)
{
    if (!s_ours (app, a->receiver)) {
        app->not_for_us++;
        return;
    }
    // A retransmission is answered as the first was, never done twice.
    for (size_t i = 0; i < app->nanswered; i++) {
        const s_answer_t *s = &app->answered[i];
        if (gw_pdu_id_eq (s->originator, a->originator) && s->request_id == a->request_id) {
            s_respond (app, a, s->status, s->text);
            return;
        }
    }
    char text[128];
    uint32_t status;
    long number = (long)a->receiver.entity - app->p.entity_id_base;
    s_uav_t *u = number > 0 ? s_uav (app, (uint32_t)number) : NULL;
    if (!u) {
        snprintf (text, sizeof text, "entity %u:%u:%u is not a UAV of this exercise",
                  a->receiver.site, a->receiver.application, a->receiver.entity);
        status = GW_STATUS_REJECTED;
    } else if (a->action_or_status != (uint32_t)app->p.route_action_id) {
        snprintf (text, sizeof text, "action %u is not taken (route tasks are action %ld)",
                  a->action_or_status, app->p.route_action_id);
        status = GW_STATUS_REJECTED;
    } else {
        status = s_route_task (app, a, u, text, sizeof text);
    }
    cgs_log (status == GW_STATUS_EXECUTING ? LOG_INFO : LOG_NOTICE,
             "Action Request %u from %u:%u:%u: status %u, %s", a->request_id, a->originator.site,
             a->originator.application, a->originator.entity, status, text);
    if (status != GW_STATUS_RETRANSMIT_LATER) {
        if (app->nanswered == S_ANSWERED) { // forget the oldest
            memmove (app->answered, app->answered + 1, (S_ANSWERED - 1) * sizeof app->answered[0]);
            app->nanswered--;
        }
        s_answer_t *s = &app->answered[app->nanswered++];
        s->originator = a->originator;
        s->request_id = a->request_id;
        s->status = status;
        snprintf (s->text, sizeof s->text, "%s", text);
    }
    s_respond (app, a, status, text);
}

typedef struct {
    s_app_t *app;
    const struct sockaddr_in *from;
    double now;
} s_walk_t;

static void s_on_pdu (void *arg, const uint8_t *pdu, size_t len)
{
    s_walk_t *w = arg;
    s_app_t *app = w->app;
    gw_header_t h;
    const char *why = NULL;
    app->pdus_in++;
    if (gw_pdu_decode_header (pdu, len, &h, &why) < 0) {
        s_reject (app, w->from, why);
        return;
    }
    if (h.exercise != cgs_exercise_id (cgs_service_exercise (app->svc))) {
        app->foreign++;
        return;
    }
    if (h.type == GW_PDU_ENTITY_STATE) {
        gw_espdu_t e;
        if (gw_pdu_decode_espdu (pdu, len, &e, &why) < 0) {
            s_reject (app, w->from, why);
            return;
        }
        if (s_ours (app, e.id)) {
            app->own++;
            return;
        }
        cgs_geodetic_t g;
        if (cgs_geo_ecef_to_geodetic ((cgs_ecef_t){e.location[0], e.location[1], e.location[2]},
                                      &g) < 0 ||
            g.height_m < S_HEIGHT_MIN_M || g.height_m > S_HEIGHT_MAX_M) {
            s_reject (app, w->from,
                      "Entity State PDU location is not within 1000 km of the Earth's surface");
            return;
        }
        app->espdu_in++;
        bool fresh = false;
        int rc = gw_in_take (app->in, &e, w->now, &fresh);
        if (rc == -ENOSPC) {
            if (app->table_full++ == 0)
                cgs_log (LOG_WARNING,
                         "more than %ld external entities: the rest are ignored (counted)",
                         app->p.max_entities);
        } else if (rc < 0) {
            cgs_health_set_error (cgs_service_health (app->svc),
                                  "out of memory for external entities");
        } else if (fresh) {
            char marking[GW_MARKING_LEN + 1]; // printable: it came off the network
            for (size_t i = 0; i < sizeof marking; i++)
                marking[i] = e.marking[i] && (e.marking[i] < 0x20 || e.marking[i] > 0x7e)
                                 ? '?'
                                 : e.marking[i];
            cgs_log (LOG_INFO, "external entity %u:%u:%u '%s' joined as entity %u", e.id.site,
                     e.id.application, e.id.entity, marking, gw_in_find (app->in, e.id)->entity_id);
        }
        return;
    }
    if (h.type == GW_PDU_ACTION_REQUEST || h.type == GW_PDU_ACTION_RESPONSE) {
        if (gw_pdu_decode_action (pdu, len, &app->action, &why) < 0) {
            s_reject (app, w->from, why);
            return;
        }
        if (s_ours (app, app->action.originator)) {
            app->own++;
            return;
        }
        if (h.type == GW_PDU_ACTION_REQUEST) {
            s_on_action_request (app, &app->action);
        } else if (s_ours (app, app->action.receiver)) {
            app->responses_in++;
            cgs_log (LOG_INFO, "Action Response to request %u from %u:%u:%u: status %u",
                     app->action.request_id, app->action.originator.site,
                     app->action.originator.application, app->action.originator.entity,
                     app->action.action_or_status);
        }
        return;
    }
    app->other_types++;
}

static void s_on_udp (void *arg)
{
    s_app_t *app = arg;
    struct mmsghdr mm[S_RECV_BATCH];
    struct iovec iov[S_RECV_BATCH];
    struct sockaddr_in from[S_RECV_BATCH];
    _Alignas(struct cmsghdr) uint8_t cmsg[S_RECV_BATCH][CMSG_SPACE (sizeof (struct in_pktinfo))];
    for (int round = 0; round < S_RECV_ROUNDS; round++) {
        for (int i = 0; i < S_RECV_BATCH; i++) {
            iov[i] = (struct iovec){app->rbuf[i], S_DGRAM_MAX};
            memset (&mm[i], 0, sizeof mm[i]);
            mm[i].msg_hdr.msg_name = &from[i];
            mm[i].msg_hdr.msg_namelen = sizeof from[i];
            mm[i].msg_hdr.msg_iov = &iov[i];
            mm[i].msg_hdr.msg_iovlen = 1;
            if (app->pcap) { // the address each came to (IP_PKTINFO)
                mm[i].msg_hdr.msg_control = cmsg[i];
                mm[i].msg_hdr.msg_controllen = sizeof cmsg[i];
            }
        }
        int n = recvmmsg (app->fd, mm, S_RECV_BATCH, MSG_DONTWAIT, NULL);
        if (n <= 0)
            return;
        double now = cgs_loop_now ();
        if (app->pcap)
            s_capture_in (app, mm, from, n);
        for (int i = 0; i < n; i++) {
            app->datagrams_in++;
            s_walk_t w = {app, &from[i], now};
            const char *why = NULL;
            if (mm[i].msg_hdr.msg_flags & MSG_TRUNC)
                s_reject (app, &from[i], "datagram larger than 65536 bytes");
            else if (mm[i].msg_len == 0)
                s_reject (app, &from[i], "empty datagram");
            else if (gw_pdu_walk (app->rbuf[i], mm[i].msg_len, s_on_pdu, &w, &why) < 0)
                s_reject (app, &from[i], why);
        }
        if (n < S_RECV_BATCH)
            return;
    }
}

/* ---- external entities on the bus ---------------------------------------------------------- */

static Cgs__Entity *s_next_msg (s_app_t *app)
{
    if (app->nmsg == app->msg_cap) {
        size_t cap = app->msg_cap ? app->msg_cap * 2 : 256;
        Cgs__Entity *m = realloc (app->msgs, cap * sizeof *m);
        if (!m)
            return NULL;
        app->msgs = m;
        gw_in_storage_t *s = realloc (app->storage, cap * sizeof *s);
        if (!s)
            return NULL;
        app->storage = s;
        Cgs__Entity **p = realloc (app->ptrs, cap * sizeof *p);
        if (!p)
            return NULL;
        app->ptrs = p;
        app->msg_cap = cap;
    }
    return &app->msgs[app->nmsg];
}

static void s_add_msg (s_app_t *app, const gw_in_entity_t *e, double now, bool leaving)
{
    Cgs__Entity *m = s_next_msg (app);
    if (!m) {
        cgs_health_set_error (cgs_service_health (app->svc),
                              "out of memory for external entity messages");
        return;
    }
    if (gw_in_entity_msg (app->geo, e, now, &app->storage[app->nmsg], m) < 0) {
        cgs_service_bad_input (app->svc, "an external entity whose state cannot be placed in "
                                         "the exercise's frame");
        return;
    }
    if (leaving)
        m->active = false;
    app->nmsg++;
}

static void s_on_expired (void *arg, const gw_in_entity_t *e)
{
    s_app_t *app = arg;
    cgs_log (LOG_INFO, "external entity %u:%u:%u (entity %u) %s", e->dis_id.site,
             e->dis_id.application, e->dis_id.entity, e->entity_id,
             e->deactivated ? "deactivated" : "timed out");
    s_add_msg (app, e, cgs_loop_now (), true);
}

static void s_counters (s_app_t *app)
{
    cgs_health_t *h = cgs_service_health (app->svc);
    cgs_health_set_counter (h, "espdu_out", app->espdu_out);
    cgs_health_set_counter (h, "action_out", app->action_out + app->response_out);
    cgs_health_set_counter (h, "pdus_in", app->pdus_in);
    cgs_health_set_counter (h, "external", gw_in_count (app->in));
    cgs_health_set_counter (h, "other_exercise", app->foreign);
    cgs_health_set_counter (h, "own_echo", app->own);
    cgs_health_set_counter (h, "rejected", app->rejected);
    cgs_health_set_counter (h, "other_pdu_types", app->other_types);
    cgs_health_set_counter (h, "tasks_accepted", app->tasks_accepted);
    cgs_health_set_counter (h, "tasks_refused", app->tasks_refused);
    cgs_health_set_counter (h, "send_errors", app->send_errors);
    if (app->pcap) {
        cgs_pcapng_flush (app->pcap);
        app->pcap_flushed = cgs_loop_now ();
        cgs_health_set_counter (h, "pcapng_packets", cgs_pcapng_packets (app->pcap));
        if (*cgs_pcapng_error (app->pcap))
            cgs_health_set_error (h, cgs_pcapng_error (app->pcap));
    }
    cgs_health_set_counter (h, "table_full", app->table_full);
    if (app->gmti) {
        const gw_gmti_stats_t *g = gw_gmti_stats (app->gmti);
        cgs_health_set_counter (h, "s4607_packets", g->packets);
        cgs_health_set_counter (h, "s4607_dwells", g->dwells);
        cgs_health_set_counter (h, "s4607_reports", g->reports);
        cgs_health_set_counter (h, "s4607_bytes", app->s4607_bytes);
        cgs_health_set_counter (h, "s4607_untagged", g->untagged);
        cgs_health_set_counter (h, "s4607_unplaceable", g->unplaceable);
        cgs_health_set_counter (h, "s4607_file_errors", app->s4607_file_errors);
        cgs_health_set_counter (h, "s4607_send_errors", app->s4607_udp.errors);
    }
    if (app->cotout) {
        const gw_cotout_stats_t *c = gw_cotout_stats (app->cotout);
        cgs_health_set_counter (h, "cot_out", c->events + app->cot_replies);
        cgs_health_set_counter (h, "cot_in", app->cot_in);
        cgs_health_set_counter (h, "cot_rejected", app->cot_rejected);
        cgs_health_set_counter (h, "cot_ignored", app->cot_ignored);
        cgs_health_set_counter (h, "cot_own_echo", app->cot_own);
        cgs_health_set_counter (h, "cot_designations", app->cot_designations);
        cgs_health_set_counter (h, "cot_refused", app->cot_refused);
        cgs_health_set_counter (h, "cot_repeats", app->cot_repeats);
        cgs_health_set_counter (h, "cot_send_errors", app->cot_udp.errors);
        cgs_health_set_counter (h, "cot_unencodable", app->cot_unencodable);
    }
}

static void s_on_publish (void *arg)
{
    s_app_t *app = arg;
    double now = cgs_loop_now ();
    app->nmsg = 0;
    gw_in_expire (app->in, now, app->p.timeout_s, s_on_expired, app);
    size_t cursor = 0;
    const gw_in_entity_t *e;
    while ((e = gw_in_next (app->in, &cursor)))
        s_add_msg (app, e, now, false);
    s_counters (app);
    if (app->nmsg == 0)
        return;
    for (size_t i = 0; i < app->nmsg; i++)
        app->ptrs[i] = &app->msgs[i];
    size_t count = (app->nmsg + S_BATCH_MAX - 1) / S_BATCH_MAX;
    cgs_service_set_sim_time (app->svc, app->sim_time_s);
    for (size_t b = 0; b < count; b++) {
        Cgs__EntityBatch batch = CGS__ENTITY_BATCH__INIT;
        batch.entities = app->ptrs + b * S_BATCH_MAX;
        batch.n_entities = b + 1 < count ? S_BATCH_MAX : app->nmsg - b * S_BATCH_MAX;
        batch.batch_index = (uint32_t)b;
        batch.batch_count = (uint32_t)count;
        cgs_service_publish (app->svc, "entity", &batch.base);
    }
}

/* ---- setup --------------------------------------------------------------------------------- */

/* The UDP socket of the parameters' mode. Multicast joins its group on the
 * interface and hears only that membership (IP_MULTICAST_ALL off); broadcast
 * on a named interface is tied to it (SO_BINDTODEVICE), so are unicast
 * peers when an interface is given. */
/* The interface the parameters name, looked up on this host (none named:
 * the routing table's choice, app->ifc zeroed). */
static int s_interface (s_app_t *app, char *err, size_t errlen)
{
    const gw_params_t *p = &app->p;
    memset (&app->ifc, 0, sizeof app->ifc);
    if (!*p->interface)
        return 0;
    int rc = cgs_iface_find (p->interface, &app->ifc);
    const char *params = cgs_service_params_path (app->svc);
    if (rc < 0)
        snprintf (err, errlen, "%s: [network] interface %s: %s (`ip -br link` lists this host's)",
                  *params ? params : "gateway parameters", p->interface,
                  rc == -ENODEV ? "no such interface on this host" : strerror (-rc));
    return rc;
}

static int s_socket (s_app_t *app, char *err, size_t errlen)
{
    const gw_params_t *p = &app->p;
    const cgs_iface_t ifc = app->ifc;
    int fd = socket (AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        snprintf (err, errlen, "cannot make a UDP socket: %s", strerror (errno));
        return -errno;
    }
    int one = 1, size = 4 << 20;
    const char *step = "bind";
    // Several DIS applications on one host share the port (broadcast and multicast).
    setsockopt (fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    setsockopt (fd, SOL_SOCKET, SO_RCVBUF, &size, sizeof size);
    setsockopt (fd, SOL_SOCKET, SO_SNDBUF, &size, sizeof size);
    struct sockaddr_in sa = {.sin_family = AF_INET, .sin_port = htons (p->port)};
    sa.sin_addr.s_addr = htonl (p->bind_address);
    if (p->mode == GW_MODE_BROADCAST &&
        setsockopt (fd, SOL_SOCKET, SO_BROADCAST, &one, sizeof one) < 0) {
        step = "SO_BROADCAST";
        goto fail;
    }
    if (p->mode != GW_MODE_MULTICAST && *p->interface &&
        setsockopt (fd, SOL_SOCKET, SO_BINDTODEVICE, ifc.name, (socklen_t)strlen (ifc.name)) < 0) {
        step = "SO_BINDTODEVICE";
        goto fail;
    }
    if (bind (fd, (struct sockaddr *)&sa, sizeof sa) < 0)
        goto fail;
    if (p->mode == GW_MODE_MULTICAST && gw_udp_multicast (fd, ifc.index, ifc.addr, p->address,
                                                          p->ttl, p->loopback, true, &step) < 0)
        goto fail;
    app->ndest = 0;
    if (p->mode == GW_MODE_UNICAST) {
        for (size_t i = 0; i < p->peer_count; i++) {
            struct sockaddr_in *d = &app->dest[app->ndest++];
            *d = (struct sockaddr_in){.sin_family = AF_INET, .sin_port = htons (p->peers[i].port)};
            d->sin_addr.s_addr = htonl (p->peers[i].addr);
        }
    } else {
        struct sockaddr_in *d = &app->dest[app->ndest++];
        *d = (struct sockaddr_in){.sin_family = AF_INET, .sin_port = htons (p->port)};
        d->sin_addr.s_addr = htonl (p->address);
    }
    app->fd = fd;
    return 0;
fail:;
    int e = errno;
    char addr[INET_ADDRSTRLEN], where[160];
    inet_ntop (AF_INET, &sa.sin_addr, addr, sizeof addr);
    gw_params_describe (p, where, sizeof where);
    snprintf (err, errlen, "DIS socket (%s, bound to %s:%u): %s: %s", where, addr, p->port, step,
              strerror (e));
    close (fd);
    return -e;
}

/* STANAG 4607 and Cursor on Target, as the parameters turn them on: the
 * file, the sockets, guidanced's command client for designations. */
static int s_translators (s_app_t *app, char *err, size_t errlen)
{
    const gw_params_t *p = &app->p;
    uint32_t ex = cgs_exercise_id (cgs_service_exercise (app->svc));
    const char *params = cgs_service_params_path (app->svc);
    char where[160];
    if (p->dis_pcapng) {
        const char *dir = *app->out_dir ? app->out_dir : cgs_service_state_dir (app->svc);
        snprintf (app->pcap_path, sizeof app->pcap_path, "%s/%s.pcapng", dir,
                  cgs_service_instance_name (app->svc));
        // A restarted gateway appends a section (a partial block cut off first).
        if (!(app->pcap = cgs_pcapng_open (app->pcap_path, "mscgs gateway", true, err, errlen)))
            return -EIO;
        // The source each destination sees: our port, and the address the
        // socket is bound to; unbound, the multicast interface's, else the
        // route's to that destination (unicast).
        struct sockaddr_in local = {0};
        socklen_t ll = sizeof local;
        if (getsockname (app->fd, (struct sockaddr *)&local, &ll) < 0)
            local.sin_family = AF_INET;
        app->pcap_local = local;
        int on = 1;
        if (setsockopt (app->fd, IPPROTO_IP, IP_PKTINFO, &on, sizeof on) < 0)
            cgs_log (LOG_WARNING,
                     "DIS capture: no IP_PKTINFO (%s): what comes in is written as "
                     "sent to the socket's own address",
                     strerror (errno));
        for (size_t d = 0; d < app->ndest; d++) {
            app->pcap_src[d] = local;
            uint32_t bound = ntohl (local.sin_addr.s_addr);
            if (p->mode == GW_MODE_MULTICAST && app->ifc.addr) {
                app->pcap_src[d].sin_addr.s_addr = htonl (app->ifc.addr);
                continue;
            }
            if (bound != INADDR_ANY && !(bound >= 0xe0000000u && bound <= 0xefffffffu))
                continue; // bound to an address of ours: it is the source
            int t = socket (AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
            struct sockaddr_in via = {0};
            socklen_t vl = sizeof via;
            int on = 1;
            if (t >= 0 && p->mode == GW_MODE_BROADCAST)
                setsockopt (t, SOL_SOCKET, SO_BROADCAST, &on, sizeof on);
            if (t >= 0 && *p->interface && p->mode != GW_MODE_MULTICAST)
                setsockopt (t, SOL_SOCKET, SO_BINDTODEVICE, app->ifc.name,
                            (socklen_t)strlen (app->ifc.name));
            if (t >= 0 &&
                connect (t, (const struct sockaddr *)&app->dest[d], sizeof app->dest[d]) == 0 &&
                getsockname (t, (struct sockaddr *)&via, &vl) == 0)
                app->pcap_src[d].sin_addr = via.sin_addr;
            else if (app->ifc.addr)
                app->pcap_src[d].sin_addr.s_addr = htonl (app->ifc.addr);
            if (t >= 0)
                close (t);
        }
        cgs_log (LOG_INFO, "DIS capture: %s (pcapng)", app->pcap_path);
    }
    if (p->s4607_file || p->s4607_udp.mode != GW_UDP_OFF) {
        if (!(app->gmti = gw_gmti_new (p, app->geo, ex, s_on_packet, app))) {
            snprintf (err, errlen, "out of memory");
            return -ENOMEM;
        }
        if (p->s4607_file) {
            const char *dir = *app->out_dir ? app->out_dir : cgs_service_state_dir (app->svc);
            snprintf (app->s4607_path, sizeof app->s4607_path, "%s/%s.4607", dir,
                      cgs_service_instance_name (app->svc));
            // A restarted gateway goes on with the same file.
            if ((app->s4607_fd = s_open_4607 (app->s4607_path, err, errlen)) < 0)
                return app->s4607_fd;
        }
        int rc = gw_udp_open (&app->s4607_udp, &p->s4607_udp, false, "stanag4607", err, errlen);
        if (rc < 0)
            return rc;
        gw_params_describe_udp (&p->s4607_udp, where, sizeof where);
        cgs_log (LOG_INFO, "STANAG 4607: file %s; UDP %s; truth tags %s",
                 app->s4607_fd >= 0 ? app->s4607_path : "none", where,
                 p->s4607_truth_tag ? "on" : "off");
        if (gw_params_udp_leaves_host (&p->s4607_udp, app->s4607_udp.ifc.loopback))
            cgs_log (LOG_NOTICE, "STANAG 4607 leaves this machine: %s (%s)", where,
                     *params ? params : "the built-in parameters");
    }
    if (p->cot_udp.mode != GW_UDP_OFF) {
        if (!(app->cotout = gw_cotout_new (p, app->geo, ex, s_on_cot_event, app))) {
            snprintf (err, errlen, "out of memory");
            return -ENOMEM;
        }
        int rc = gw_udp_open (&app->cot_udp, &p->cot_udp, true, "cot", err, errlen);
        if (rc < 0)
            return rc;
        app->guidanced = cgs_exercise_first_of (cgs_service_exercise (app->svc), "guidanced");
        if (app->guidanced && *app->guidanced->command && p->cot_designate) {
            app->guidance = cgs_cmd_client_new (cgs_service_ctx (app->svc), app->guidanced->command,
                                                "gateway-cot");
            int crc = app->guidance
                          ? cgs_curve_protect_client (cgs_service_curve (app->svc), app->guidance,
                                                      app->guidanced->public_key)
                          : -ENOMEM;
            if (crc < 0) {
                snprintf (err, errlen, "cannot make a command client for %s: %s",
                          app->guidanced->command, strerror (-crc));
                return crc;
            }
        }
        gw_params_describe_udp (&p->cot_udp, where, sizeof where);
        cgs_log (LOG_INFO, "Cursor on Target: %s, %s; designations %s", where,
                 p->cot_protobuf ? "TAK protobuf" : "XML",
                 !p->cot_designate ? "off"
                 : app->guidance   ? "to guidanced"
                                   : "refused (no guidanced command endpoint)");
        if (gw_params_udp_leaves_host (&p->cot_udp, app->cot_udp.ifc.loopback))
            cgs_log (LOG_NOTICE, "Cursor on Target leaves this machine: %s (%s)", where,
                     *params ? params : "the built-in parameters");
    }
    return 0;
}

static int s_setup (s_app_t *app, char *err, size_t errlen)
{
    gw_params_defaults (&app->p);
    const char *params = cgs_service_params_path (app->svc);
    if (*params) {
        int rc = gw_params_load (params, &app->p, err, errlen);
        if (rc < 0)
            return rc;
        cgs_log (LOG_INFO, "gateway parameters from %s", params);
    }
    uint32_t ex = cgs_exercise_id (cgs_service_exercise (app->svc));
    if (ex < 1 || ex > 255) {
        snprintf (err, errlen, "%s: exercise id %u is not a DIS exercise id (1..255)",
                  cgs_service_exercise_path (app->svc), ex);
        return -EINVAL;
    }
    cgs_geodetic_t o = cgs_exercise_origin (cgs_service_exercise (app->svc));
    if (!(app->geo = cgs_geo_new (o.lat_deg, o.lon_deg, o.height_m))) {
        snprintf (err, errlen, "the exercise origin is not usable");
        return -EINVAL;
    }
    gw_out_params_t op = {app->p.position_threshold_m, app->p.orientation_threshold_deg,
                          app->p.heartbeat_s};
    app->out = gw_out_new (&op);
    app->in = gw_in_new ((uint32_t)app->p.first_entity_id, (size_t)app->p.max_entities);
    app->rbuf = malloc (S_RECV_BATCH * sizeof *app->rbuf);
    if (!app->out || !app->in || !app->rbuf) {
        snprintf (err, errlen, "out of memory");
        return -ENOMEM;
    }
    app->fd = -1;
    app->uavsim = cgs_exercise_first_of (cgs_service_exercise (app->svc), "uavsim");
    if (app->uavsim && !*app->uavsim->command)
        app->uavsim = NULL; // it takes no tasks
    int rc = s_interface (app, err, errlen);
    if (rc == 0)
        rc = gw_udp_interface (&app->s4607_udp, &app->p.s4607_udp, "stanag4607", err, errlen);
    if (rc == 0)
        rc = gw_udp_interface (&app->cot_udp, &app->p.cot_udp, "cot", err, errlen);
    if (rc < 0 || cgs_service_check_only (app->svc))
        return rc;
    rc = s_socket (app, err, errlen);
    if (rc < 0)
        return rc;
    if (app->uavsim) {
        app->client =
            cgs_cmd_client_new (cgs_service_ctx (app->svc), app->uavsim->command, "gateway");
        int crc = app->client ? cgs_curve_protect_client (cgs_service_curve (app->svc), app->client,
                                                          app->uavsim->public_key)
                              : -ENOMEM;
        if (crc < 0) {
            snprintf (err, errlen, "cannot make a command client for %s: %s", app->uavsim->command,
                      strerror (-crc));
            return crc;
        }
    }
    if ((rc = s_translators (app, err, errlen)) < 0)
        return rc;
    char where[160];
    gw_params_describe (&app->p, where, sizeof where);
    cgs_log (LOG_INFO, "DIS version %d, exercise %u, site %d application %d, %s; uavsim at %s",
             app->p.version, ex, app->p.site, app->p.application, where,
             app->uavsim ? app->uavsim->command : "(none)");
    // Once, at start: an exercise whose parameters put DIS on a network.
    if (gw_params_leaves_host (&app->p, app->ifc.loopback))
        cgs_log (LOG_NOTICE, "DIS leaves this machine: %s (%s)", where,
                 *params ? params : "the built-in parameters");
    return 0;
}

static int s_on_option (void *arg, const char *name, const char *value, char *why, size_t whylen)
{
    s_app_t *app = arg;
    if (strcmp (name, "out") == 0) {
        if (!*value || strlen (value) >= sizeof app->out_dir) {
            snprintf (why, whylen, "--out needs a folder name under %zu bytes",
                      sizeof app->out_dir);
            return -EINVAL;
        }
        snprintf (app->out_dir, sizeof app->out_dir, "%s", value);
    }
    return 0;
}

int main (int argc, char **argv)
{
    static s_app_t app;
    app.fd = -1;
    app.s4607_fd = -1;
    gw_udp_init (&app.s4607_udp);
    gw_udp_init (&app.cot_udp);
    static const cgs_service_option_t options[] = {
        {"out", true, "DIR", "folder of the STANAG 4607 file (default: the state folder)"},
        {NULL, false, NULL, NULL},
    };
    cgs_service_info_t info = {
        .program = "gateway",
        .summary = "Bridge to the outside world: DIS in and out; STANAG 4607 GMTI and Cursor "
                   "on Target out, CoT designations in.",
        .options = options,
        .on_option = s_on_option,
        .option_arg = &app,
    };
    int rc = cgs_service_new (&info, argc, argv, &app.svc);
    if (rc != 0)
        return rc > 0 ? 0 : 1;
    int exit_code = 1;
    char err[1024] = "";
    if (s_setup (&app, err, sizeof err) < 0) {
        cgs_log (LOG_ERR, "%s", err);
        goto done;
    }
    if (cgs_service_check_only (app.svc)) {
        char where[160];
        gw_params_describe (&app.p, where, sizeof where);
        printf ("%s: parameters are good (DIS version %d, %s: %s)\n",
                cgs_service_instance_name (app.svc), app.p.version, where,
                gw_params_leaves_host (&app.p, app.ifc.loopback) ? "leaves this machine"
                                                                 : "this machine only");
        exit_code = 0;
        goto done;
    }
    cgs_loop_t *loop = cgs_service_loop (app.svc);
    if (cgs_loop_add_fd (loop, app.fd, s_on_udp, &app) < 0 ||
        cgs_loop_add_timer (loop, 1.0 / app.p.publish_rate_hz, s_on_publish, &app) < 0 ||
        ((app.gmti || app.cotout) &&
         cgs_loop_add_timer (loop, S_TRANSLATOR_PERIOD_S, s_on_translators, &app) < 0) ||
        (app.cot_udp.rfd >= 0 && cgs_loop_add_fd (loop, app.cot_udp.rfd, s_on_cot_udp, &app) < 0)) {
        cgs_log (LOG_ERR, "out of memory");
        goto done;
    }
    if (cgs_service_subscribe (app.svc, "entity", s_on_entity, &app) < 0 ||
        cgs_service_subscribe (app.svc, "uav", s_on_uav, &app) < 0 ||
        cgs_service_subscribe (app.svc, "intercept", s_on_intercept, &app) < 0 ||
        (app.gmti && (cgs_service_subscribe (app.svc, "mti", s_on_mti, &app) < 0 ||
                      (app.p.s4607_truth_tag &&
                       cgs_service_subscribe (app.svc, "mti.truth", s_on_mti_truth, &app) < 0))) ||
        (app.cotout && cgs_service_subscribe (app.svc, "track", s_on_track, &app) < 0))
        goto done;
    exit_code = cgs_service_run (app.svc);
    cgs_log (LOG_INFO,
             "%" PRIu64 " Entity State PDUs and %" PRIu64 " Action Requests out; %" PRIu64
             " PDUs in (%" PRIu64 " Entity State, %" PRIu64 " of other exercises, %" PRIu64
             " rejected); %" PRIu64 " route tasks taken, %" PRIu64 " refused",
             app.espdu_out, app.action_out, app.pdus_in, app.espdu_in, app.foreign, app.rejected,
             app.tasks_accepted, app.tasks_refused);
    if (app.gmti) {
        gw_gmti_flush (app.gmti);
        const gw_gmti_stats_t *g = gw_gmti_stats (app.gmti);
        cgs_log (LOG_INFO,
                 "STANAG 4607: %" PRIu64 " packets, %" PRIu64 " dwells, %" PRIu64
                 " target reports (%" PRIu64 " bytes)%s%s",
                 g->packets, g->dwells, g->reports, app.s4607_bytes,
                 app.s4607_fd >= 0 ? " to " : "", app.s4607_fd >= 0 ? app.s4607_path : "");
    }
    if (app.cotout)
        cgs_log (LOG_INFO,
                 "Cursor on Target: %" PRIu64 " events out; %" PRIu64 " in (%" PRIu64
                 " rejected, %" PRIu64 " ignored); %" PRIu64 " designations, %" PRIu64 " refused",
                 gw_cotout_stats (app.cotout)->events + app.cot_replies, app.cot_in,
                 app.cot_rejected, app.cot_ignored, app.cot_designations, app.cot_refused);
done:
    if (app.pcap) {
        char perr[320] = "";
        uint64_t n = cgs_pcapng_packets (app.pcap);
        if (cgs_pcapng_close (&app.pcap, perr, sizeof perr) < 0)
            cgs_log (LOG_ERR, "%s", perr);
        else
            cgs_log (LOG_INFO, "DIS capture: %" PRIu64 " datagrams in %s", n, app.pcap_path);
    }
    if (app.s4607_fd >= 0 && close (app.s4607_fd) != 0)
        cgs_log (LOG_ERR, "cannot write %s: %s", app.s4607_path, strerror (errno));
    gw_udp_close (&app.s4607_udp);
    gw_udp_close (&app.cot_udp);
    gw_gmti_destroy (&app.gmti);
    gw_cotout_destroy (&app.cotout);
    cgs_cmd_client_destroy (&app.guidance);
    if (app.fd >= 0)
        close (app.fd);
    cgs_cmd_client_destroy (&app.client);
    gw_out_destroy (&app.out);
    gw_in_destroy (&app.in);
    cgs_geo_destroy (&app.geo);
    free (app.rbuf);
    free (app.msgs);
    free (app.ptrs);
    free (app.storage);
    cgs_service_destroy (&app.svc);
    return exit_code;
}
