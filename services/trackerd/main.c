/* trackerd — tracks from the MTI hits of every radar (`mti`, one radar scan
 * at a time, closed by `mti.scan`), identity from BCIS replies (`bcis`);
 * publishes every track of a radar after each of its scans (`track`) and
 * each turn the filter sees (`track.turn`). Tracks are checkpointed in the
 * state folder, so their ids outlive a restart. `trackerd --monte-carlo`
 * runs the tracker on synthetic targets instead. The tracker is in
 * trk_*.c; this file wires it to the bus. */
#include "cgs_lifecycle.h"
#include "cgs_log.h"
#include "cgs_service.h"
#include "cgs_util.h"
#include "cgs_state.h"
#include "trk_mc.h"
#include "trk_params.h"
#include "trk_tracker.h"

#include <errno.h>
#include <getopt.h>
#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_PI             3.14159265358979323846
#define S_BATCH_TRACKS   200        // tracks per `track` message
#define S_CHECKPOINT_S   1.0        // at most one checkpoint write per wall-clock second
#define S_CHECKPOINT_MAX (1u << 30) // a checkpoint file larger than this is refused
#define S_RADARS_MAX     64         // radars whose open scans are kept

/* The hits of one radar's scan in progress. */
typedef struct {
    uint32_t uav_id;
    uint32_t scan_number;
    bool open; // hits have come for scan_number and it has not ended
    trk_hit_t *hits;
    size_t count, cap;
    double platform[2];   // the radar's ground position (latest dwell)
    bool has_closed;      // a scan of it has been processed:
    uint32_t last_closed; // its number
    bool has_time;        // the latest simulation time heard from it:
    double last_time_s;
    bool full_revolution;                       // what its latest mti.scan covered (for a scan
    double sector_center_deg, sector_width_deg; // closed without its marker)
} s_radar_t;

typedef struct {
    cgs_service_t svc;
    trk_params_t params;
    trk_tracker_t *trk;
    bool fresh; // --fresh: ignore the checkpoint
    char checkpoint[4200];
    bool dirty; // tracks changed since the last checkpoint
    s_radar_t radars[S_RADARS_MAX];
    size_t radar_count;
    uint64_t scans, implicit_scans, stale_scans, hits, turns, bcis_marks;
    uint64_t born, deleted, time_resets;
    /* Output messages, reused. */
    Cgs__Track *tmsg;
    Cgs__Track **tptr;
    Cgs__Enu *tpos;
    Cgs__EnuVelocity *tvel;
    double *tcov;
    Cgs__TrackHistoryPoint *hpts;
    Cgs__TrackHistoryPoint **hptr;
    Cgs__Enu *hpos;
    size_t tcap, hcap;
} s_app_t;

/* A message the tracker cannot use: counted in health, logged the first time. */
static void s_bad (s_app_t *app, const char *what)
{
    cgs_service_bad_input (&app->svc, what);
}

static s_radar_t *s_radar (s_app_t *app, uint32_t uav_id)
{
    for (size_t i = 0; i < app->radar_count; i++)
        if (app->radars[i].uav_id == uav_id)
            return &app->radars[i];
    if (app->radar_count == S_RADARS_MAX)
        return NULL;
    s_radar_t *r = &app->radars[app->radar_count++];
    memset (r, 0, sizeof *r);
    r->uav_id = uav_id;
    r->full_revolution = true;
    return r;
}

/* Simulation time t from radar r: notes it, and says whether it went back by
 * more than two scans (a new exercise, or uavsim restarted from an older
 * checkpoint). Then the radar's open scan is of another time line: dropped. */
static bool s_time_went_back (s_app_t *app, s_radar_t *r, double t)
{
    bool back = r->has_time && t < r->last_time_s - 2 * app->params.filter.dt_s;
    if (back) {
        cgs_log (LOG_NOTICE,
                 "radar %u: simulation time went back from %.2f to %.2f s; its scan in progress "
                 "is dropped and its tracks from later times go at its next scan",
                 r->uav_id, r->last_time_s, t);
        r->open = false;
        r->count = 0;
        r->has_closed = false;
        r->last_time_s = t;
    } else if (!r->has_time || t > r->last_time_s) {
        r->last_time_s = t;
    }
    r->has_time = true;
    return back;
}

/* Whether scan number k of radar r is over already (its hits or marker came late). */
static bool s_stale (const s_radar_t *r, uint32_t k)
{
    if (r->open)
        return k < r->scan_number;
    return r->has_closed && k <= r->last_closed;
}

/* ---- publishing ------------------------------------------------------------------- */

static int s_reserve (s_app_t *app, size_t tracks, size_t points)
{
    if (tracks > app->tcap) {
        size_t n = tracks * 2;
        void *a = realloc (app->tmsg, n * sizeof *app->tmsg);
        if (a)
            app->tmsg = a;
        void *b = realloc (app->tptr, n * sizeof *app->tptr);
        if (b)
            app->tptr = b;
        void *c = realloc (app->tpos, n * sizeof *app->tpos);
        if (c)
            app->tpos = c;
        void *d = realloc (app->tvel, n * sizeof *app->tvel);
        if (d)
            app->tvel = d;
        void *e = realloc (app->tcov, n * 16 * sizeof *app->tcov);
        if (e)
            app->tcov = e;
        if (!a || !b || !c || !d || !e)
            return -ENOMEM;
        app->tcap = n;
    }
    if (points > app->hcap) {
        size_t n = points * 2;
        void *a = realloc (app->hpts, n * sizeof *app->hpts);
        if (a)
            app->hpts = a;
        void *b = realloc (app->hptr, n * sizeof *app->hptr);
        if (b)
            app->hptr = b;
        void *c = realloc (app->hpos, n * sizeof *app->hpos);
        if (c)
            app->hpos = c;
        if (!a || !b || !c)
            return -ENOMEM;
        app->hcap = n;
    }
    return 0;
}

static Cgs__TrackStatus s_status (trk_status_t s)
{
    switch (s) {
    case TRK_CONFIRMED:
        return CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED;
    case TRK_COASTING:
        return CGS__TRACK_STATUS__TRACK_STATUS_COASTING;
    case TRK_DELETED:
        return CGS__TRACK_STATUS__TRACK_STATUS_DELETED;
    default:
        return CGS__TRACK_STATUS__TRACK_STATUS_TENTATIVE;
    }
}

/* Fill message slot i (history points from *hp on) from track t at time now. */
static void s_fill (s_app_t *app, size_t i, size_t *hp, const trk_track_t *t, double now)
{
    Cgs__Track *m = &app->tmsg[i];
    cgs__track__init (m);
    trk_estimate_t e = t->est;
    if (now > e.t_s)
        trk_tracker_predict (app->trk, t, now, &e);
    Cgs__Enu *p = &app->tpos[i];
    cgs__enu__init (p);
    p->east_m = e.x[0];
    p->north_m = e.x[1];
    p->up_m = t->up_m;
    Cgs__EnuVelocity *v = &app->tvel[i];
    cgs__enu_velocity__init (v);
    v->east_mps = e.x[2];
    v->north_mps = e.x[3];
    m->track_id = t->id;
    m->uav_id = t->uav_id;
    m->status = s_status (t->status);
    m->identity = t->friendly ? CGS__TRACK_IDENTITY__TRACK_IDENTITY_FRIENDLY
                              : CGS__TRACK_IDENTITY__TRACK_IDENTITY_UNKNOWN;
    m->friendly_id = t->friendly ? t->friendly_id : 0;
    m->position = p;
    m->velocity = v;
    m->speed_mps = hypot (e.x[2], e.x[3]);
    double hd = atan2 (e.x[2], e.x[3]) * 180 / S_PI;
    m->heading_deg = hd < 0 ? hd + 360 : hd;
    m->hit_count = t->hits;
    m->miss_count = t->misses;
    m->last_hit_time_s = t->last_hit_s;
    m->last_scan_number = t->last_scan;
    memcpy (&app->tcov[i * 16], e.P, sizeof e.P);
    m->n_covariance = 16;
    m->covariance = &app->tcov[i * 16];
    m->n_history = t->history_count;
    m->history = &app->hptr[*hp];
    for (uint32_t k = 0; k < t->history_count; k++, (*hp)++) {
        const trk_history_point_t *h = &t->history[k];
        Cgs__TrackHistoryPoint *q = &app->hpts[*hp];
        cgs__track_history_point__init (q);
        cgs__enu__init (&app->hpos[*hp]);
        app->hpos[*hp].east_m = h->e_m;
        app->hpos[*hp].north_m = h->n_m;
        app->hpos[*hp].up_m = h->u_m;
        q->position = &app->hpos[*hp];
        q->sim_time_s = h->t_s;
        q->scan_number = h->scan_number;
        q->hit_id = h->hit_id;
        app->hptr[*hp] = q;
    }
    app->tptr[i] = m;
}

/* Every track of the radar, and those deleted in the scan, in batches. */
static void s_publish_tracks (s_app_t *app, const trk_scan_t *scan, const trk_scan_out_t *out)
{
    size_t n = 0, points = 0, total = trk_tracker_count (app->trk);
    for (size_t i = 0; i < total; i++) {
        const trk_track_t *t = trk_tracker_at (app->trk, i);
        if (t->uav_id == scan->uav_id) {
            n++;
            points += t->history_count;
        }
    }
    for (size_t i = 0; i < out->deleted_count; i++)
        points += out->deleted_tracks[i].history_count;
    n += out->deleted_count;
    if (s_reserve (app, n, points) < 0) {
        cgs_health_set_error (app->svc.health, "out of memory: a scan's tracks were not published");
        return;
    }
    size_t k = 0, hp = 0;
    for (size_t i = 0; i < total; i++) {
        const trk_track_t *t = trk_tracker_at (app->trk, i);
        if (t->uav_id == scan->uav_id)
            s_fill (app, k++, &hp, t, scan->end_s);
    }
    for (size_t i = 0; i < out->deleted_count; i++)
        s_fill (app, k++, &hp, &out->deleted_tracks[i], scan->end_s);
    size_t batches = n ? (n + S_BATCH_TRACKS - 1) / S_BATCH_TRACKS : 1;
    app->svc.sim_time_s = scan->end_s;
    for (size_t b = 0; b < batches; b++) {
        Cgs__TrackBatch m = CGS__TRACK_BATCH__INIT;
        m.uav_id = scan->uav_id;
        m.scan_number = scan->scan_number;
        m.batch_index = (uint32_t)b;
        m.batch_count = (uint32_t)batches;
        size_t lo = b * S_BATCH_TRACKS;
        m.n_tracks = n - lo < S_BATCH_TRACKS ? n - lo : S_BATCH_TRACKS;
        m.tracks = n ? &app->tptr[lo] : NULL;
        cgs_service_publish (&app->svc, "track", &m.base);
    }
}

static void s_publish_turn (s_app_t *app, const trk_turn_t *ev, uint32_t uav_id)
{
    Cgs__Enu pos = CGS__ENU__INIT;
    Cgs__EnuVelocity before = CGS__ENU_VELOCITY__INIT, after = CGS__ENU_VELOCITY__INIT;
    pos.east_m = ev->position[0];
    pos.north_m = ev->position[1];
    before.east_mps = ev->v_before[0];
    before.north_mps = ev->v_before[1];
    after.east_mps = ev->v_after[0];
    after.north_mps = ev->v_after[1];
    const trk_track_t *t = trk_tracker_find (app->trk, ev->track_id);
    if (t)
        pos.up_m = t->up_m;
    Cgs__TrackTurn m = CGS__TRACK_TURN__INIT;
    m.track_id = ev->track_id;
    m.uav_id = uav_id;
    m.dot = ev->dot;
    m.turn_angle_deg = ev->angle_deg;
    m.position = &pos;
    m.velocity_before = &before;
    m.velocity_after = &after;
    m.scan_number = ev->scan_number;
    m.complete = ev->complete;
    m.sim_time_s = ev->t_s;
    cgs_service_publish (&app->svc, "track.turn", &m.base);
}

/* ---- scans -------------------------------------------------------------------------- */

static void s_run_scan (s_app_t *app, s_radar_t *r, const trk_scan_t *scan)
{
    trk_scan_out_t out;
    size_t given = r->count;
    int rc = trk_tracker_scan (app->trk, scan, r->hits, given, &out);
    r->count = 0;
    r->open = false;
    r->has_closed = true;
    r->last_closed = scan->scan_number;
    if (rc < 0) {
        cgs_health_set_error (app->svc.health, "out of memory: a scan's hits were dropped");
        cgs_log (LOG_ERR, "out of memory: scan %u of radar %u was dropped", scan->scan_number,
                 scan->uav_id);
        return;
    }
    for (size_t i = out.hits; i < given; i++)
        s_bad (app, "an MTI hit whose time lies outside its scan");
    app->scans++;
    app->hits += out.hits;
    app->born += out.born;
    app->deleted += out.deleted;
    app->turns += out.turn_count;
    if (out.time_reset) {
        app->time_resets += out.time_reset;
        cgs_log (LOG_NOTICE,
                 "simulation time went back to %.2f s: %zu tracks of radar %u from later times "
                 "were deleted",
                 scan->end_s, out.time_reset, scan->uav_id);
    }
    s_publish_tracks (app, scan, &out);
    for (size_t i = 0; i < out.turn_count; i++)
        s_publish_turn (app, &out.turns[i], scan->uav_id);
    app->dirty = true;
    if (app->scans == 1 || app->svc.verbose)
        cgs_log (LOG_INFO,
                 "radar %u scan %u: %zu hits, %zu updated, %zu missed, %zu new, %zu confirmed, "
                 "%zu deleted, %zu clusters (largest %zu); %zu tracks",
                 scan->uav_id, scan->scan_number, out.hits, out.updated, out.missed, out.born,
                 out.confirmed, out.deleted, out.clusters, out.largest_cluster,
                 trk_tracker_count (app->trk));
}

/* A scan whose end marker never came (lost, or its radar restarted): closed
 * with what is known. */
static void s_close_implicit (s_app_t *app, s_radar_t *r)
{
    double lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < r->count; i++) {
        lo = fmin (lo, r->hits[i].t_s);
        hi = fmax (hi, r->hits[i].t_s);
    }
    trk_scan_t scan = {
        .uav_id = r->uav_id,
        .scan_number = r->scan_number,
        .start_s = r->count ? lo : 0,
        .end_s = r->count ? hi : 0,
        .full_revolution = r->full_revolution, // as its last scan was
        .sector_center_deg = r->sector_center_deg,
        .sector_width_deg = r->sector_width_deg,
        .platform = {r->platform[0], r->platform[1]},
    };
    app->implicit_scans++;
    if (r->count)
        s_run_scan (app, r, &scan);
    r->open = false;
    r->count = 0;
}

static bool s_enu_ok (const Cgs__Enu *p)
{
    return p && isfinite (p->east_m) && isfinite (p->north_m) && isfinite (p->up_m);
}

static void s_on_mti (void *arg, const char *topic, const ProtobufCMessage *msg,
                      const Cgs__Header *hdr)
{
    (void)topic;
    (void)hdr;
    s_app_t *app = arg;
    const Cgs__Mti *m = (const Cgs__Mti *)msg;
    if (!m->uav_id || !s_enu_ok (m->platform_position)) {
        s_bad (app, "an mti message without a radar id or platform position");
        return;
    }
    s_radar_t *r = s_radar (app, m->uav_id);
    if (!r) {
        s_bad (app, "hits of more radars than trackerd keeps scans for");
        return;
    }
    if (isfinite (hdr->sim_time_s))
        s_time_went_back (app, r, hdr->sim_time_s);
    if (s_stale (r, m->scan_number)) {
        app->stale_scans++;
        return; // hits of a scan already closed
    }
    if (r->open && r->scan_number != m->scan_number)
        s_close_implicit (app, r); // its end marker was lost
    r->open = true;
    r->scan_number = m->scan_number;
    const Cgs__Enu *pl = m->platform_position;
    r->platform[0] = pl->east_m;
    r->platform[1] = pl->north_m;
    if (r->count + m->n_hits > r->cap) {
        size_t cap = (r->count + m->n_hits) * 2;
        trk_hit_t *h = realloc (r->hits, cap * sizeof *h);
        if (!h) {
            cgs_health_set_error (app->svc.health, "out of memory: hits dropped");
            return;
        }
        r->hits = h;
        r->cap = cap;
    }
    for (size_t i = 0; i < m->n_hits; i++) {
        const Cgs__MtiHit *h = m->hits[i];
        if (!s_enu_ok (h->position) || !isfinite (h->sim_time_s) ||
            !isfinite (h->radial_velocity_mps) || !isfinite (h->azimuth_deg)) {
            s_bad (app, "an MTI hit without a valid position, time, azimuth or radial velocity");
            continue;
        }
        const Cgs__Enu *q = h->position;
        r->hits[r->count++] =
            trk_hit_from_mti (h->hit_id, h->sim_time_s, (cgs_enu_t){q->east_m, q->north_m, q->up_m},
                              (cgs_enu_t){pl->east_m, pl->north_m, pl->up_m}, h->azimuth_deg,
                              h->range_sigma_m, h->azimuth_sigma_deg, h->radial_velocity_mps);
    }
}

static void s_on_mti_scan (void *arg, const char *topic, const ProtobufCMessage *msg,
                           const Cgs__Header *hdr)
{
    (void)topic;
    (void)hdr;
    s_app_t *app = arg;
    const Cgs__MtiScan *m = (const Cgs__MtiScan *)msg;
    if (!m->uav_id || !isfinite (m->scan_start_s) || !isfinite (m->scan_end_s) ||
        m->scan_end_s < m->scan_start_s || !isfinite (m->sector_center_deg) ||
        (!m->full_revolution && !(m->sector_width_deg > 0 && m->sector_width_deg <= 360))) {
        s_bad (app, "an mti.scan message without a radar id, times in order or a sector");
        return;
    }
    s_radar_t *r = s_radar (app, m->uav_id);
    if (!r) {
        s_bad (app, "a scan of more radars than trackerd keeps scans for");
        return;
    }
    s_time_went_back (app, r, m->scan_end_s);
    if (s_stale (r, m->scan_number)) {
        app->stale_scans++;
        return;
    }
    if (r->open && r->scan_number != m->scan_number)
        s_close_implicit (app, r); // its own end marker was lost
    r->full_revolution = m->full_revolution;
    r->sector_center_deg = m->sector_center_deg;
    r->sector_width_deg = m->sector_width_deg;
    trk_scan_t scan = {
        .uav_id = m->uav_id,
        .scan_number = m->scan_number,
        .start_s = m->scan_start_s,
        .end_s = m->scan_end_s,
        .full_revolution = m->full_revolution,
        .sector_center_deg = m->sector_center_deg,
        .sector_width_deg = m->sector_width_deg,
        .platform = {r->platform[0], r->platform[1]},
    };
    r->scan_number = m->scan_number;
    s_run_scan (app, r, &scan);
}

static void s_on_bcis (void *arg, const char *topic, const ProtobufCMessage *msg,
                       const Cgs__Header *hdr)
{
    (void)topic;
    (void)hdr;
    s_app_t *app = arg;
    const Cgs__Bcis *m = (const Cgs__Bcis *)msg;
    for (size_t i = 0; i < m->n_replies; i++) {
        const Cgs__BcisReply *r = m->replies[i];
        if (!s_enu_ok (r->position) || !isfinite (r->sim_time_s)) {
            s_bad (app, "a BCIS reply without a valid position or time");
            continue;
        }
        double z[2] = {r->position->east_m, r->position->north_m};
        size_t marked = trk_tracker_bcis (app->trk, r->sim_time_s, z, r->responder_id);
        if (marked) {
            app->bcis_marks += marked;
            app->dirty = true;
        }
    }
}

/* ---- checkpoint ----------------------------------------------------------------------- */

static int s_checkpoint (s_app_t *app)
{
    uint8_t *buf;
    size_t len;
    int rc = trk_tracker_save (app->trk, &buf, &len);
    if (rc == 0) {
        rc = cgs_state_write (app->checkpoint, buf, len);
        free (buf);
    }
    if (rc < 0) {
        char why[4400];
        snprintf (why, sizeof why, "cannot write %s: %s", app->checkpoint, strerror (-rc));
        cgs_health_set_error (app->svc.health, why);
        return rc;
    }
    app->dirty = false;
    return 0;
}

static void s_on_checkpoint_timer (void *arg)
{
    s_app_t *app = arg;
    if (app->dirty && s_checkpoint (app) < 0)
        cgs_log (LOG_WARNING, "checkpoint not written (see health)");
    cgs_notify_status ("%zu tracks, %llu scans, %llu hits", trk_tracker_count (app->trk),
                       (unsigned long long)app->scans, (unsigned long long)app->hits);
}

static void s_restore (s_app_t *app)
{
    void *data = NULL;
    size_t len = 0;
    int rc = cgs_state_read (app->checkpoint, S_CHECKPOINT_MAX, &data, &len);
    if (rc == -ENOENT) {
        cgs_log (LOG_INFO, "no checkpoint at %s: starting with no tracks", app->checkpoint);
        return;
    }
    char err[512] = "";
    uint32_t next_id = 0;
    if (rc == 0 && app->fresh) {
        cgs_log (LOG_NOTICE, "--fresh: the checkpoint %s is ignored", app->checkpoint);
    } else if (rc == 0 && trk_tracker_restore (app->trk, data, len, err, sizeof err) == 0) {
        cgs_log (LOG_NOTICE, "resumed %zu tracks from %s (next track id %u)",
                 trk_tracker_count (app->trk), app->checkpoint, trk_tracker_next_id (app->trk));
    } else {
        char why[1024];
        snprintf (why, sizeof why, "checkpoint %s ignored: %s", app->checkpoint,
                  rc < 0 ? strerror (-rc) : err);
        cgs_log (LOG_WARNING, "%s; starting with no tracks", why);
        cgs_health_set_error (app->svc.health, why);
        // Keep the damaged file for a look; the next checkpoint takes its name.
        char aside[4300];
        snprintf (aside, sizeof aside, "%s.damaged", app->checkpoint);
        if (rc == 0 && rename (app->checkpoint, aside) == 0)
            cgs_log (LOG_NOTICE, "the damaged checkpoint is kept as %s", aside);
    }
    // Whatever was refused, ids it had given are not given again.
    if (rc == 0 && trk_tracker_count (app->trk) == 0 &&
        trk_tracker_checkpoint_next_id (data, len, &next_id) == 0) {
        trk_tracker_raise_next_id (app->trk, next_id);
        cgs_log (LOG_INFO, "new track ids start at %u", trk_tracker_next_id (app->trk));
    }
    free (data);
}

/* ---- --monte-carlo ------------------------------------------------------------------- */

static int s_number (const char *opt, const char *s, double lo, double hi, double *ret)
{
    char *end;
    double v = strtod (s, &end);
    if (end == s || *end || !(v >= lo && v <= hi)) {
        fprintf (stderr, "trackerd: --%s: expected a number in [%g, %g], got '%s'\n", opt, lo, hi,
                 s);
        return -EINVAL;
    }
    *ret = v;
    return 0;
}

/* A whole number lo..hi in decimal digits; -EINVAL after saying why. */
static int s_count (const char *what, const char *text, uint64_t lo, uint64_t hi, uint64_t *ret)
{
    uint64_t v = 0;
    if (cgs_parse_u64 (text, hi, &v) < 0 || v < lo) {
        fprintf (stderr, "trackerd: --%s: expected a whole number %llu..%llu, got '%s'\n", what,
                 (unsigned long long)lo, (unsigned long long)hi, text);
        return -EINVAL;
    }
    *ret = v;
    return 0;
}

static int s_monte_carlo (int argc, char **argv)
{
    static const struct option opts[] = {
        {"monte-carlo", no_argument, NULL, 'M'},
        {"params", required_argument, NULL, 'p'},
        {"speed", required_argument, NULL, 'v'},
        {"turn-deg", required_argument, NULL, 'a'},
        {"sigma-meas", required_argument, NULL, 'm'},
        {"targets", required_argument, NULL, 'n'},
        {"scans", required_argument, NULL, 'k'},
        {"seed", required_argument, NULL, 'S'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    trk_params_t p;
    trk_params_defaults (&p);
    const char *params = NULL;
    double speed = 15, turn = 90, sigma = NAN;
    uint64_t targets = 3000, scans = 32, seed = 1;
    int o;
    optind = 1;
    while ((o = getopt_long (argc, argv, "h", opts, NULL)) != -1) {
        int rc = 0;
        switch (o) {
        case 'M':
            break;
        case 'p':
            params = optarg;
            break;
        case 'v':
            rc = s_number ("speed", optarg, 0, 1000, &speed);
            break;
        case 'a':
            rc = s_number ("turn-deg", optarg, 0, 180, &turn);
            break;
        case 'm':
            rc = s_number ("sigma-meas", optarg, 0.01, 1e5, &sigma);
            break;
        case 'n':
            rc = s_count ("targets", optarg, 1, 1000000, &targets);
            break;
        case 'k':
            rc = s_count ("scans", optarg, 12, 1000000, &scans);
            break;
        case 'S':
            rc = s_count ("seed", optarg, 0, UINT64_MAX, &seed);
            break;
        case 'h':
            printf ("usage: trackerd --monte-carlo [--params F] [--speed MPS] [--turn-deg A]\n"
                    "                [--sigma-meas M] [--targets N] [--scans N] [--seed S]\n"
                    "Runs the tracker on N synthetic targets, 5 km apart on one heading at\n"
                    "--speed, hit once a scan with Gaussian noise of --sigma-meas per axis\n"
                    "(default: the parameters' sigma_meas_x_m) and no false alarms. With\n"
                    "--turn-deg A > 0 each target turns A degrees (left or right at random)\n"
                    "between its hits of scans --scans - 6 and --scans - 5, and the result\n"
                    "gives the turns flagged within 2 scans and the false turns per\n"
                    "straight-leg scan; with --turn-deg 0 the targets go straight and the\n"
                    "result gives the RMSE of position and velocity beside the constant-gain\n"
                    "filter's steady-state values. Prints one line of JSON. Defaults: speed\n"
                    "15, turn 90, 3000 targets, 32 scans, seed 1.\n");
            return 0;
        default:
            return 2;
        }
        if (rc < 0)
            return 2;
    }
    if (optind < argc) {
        fprintf (stderr, "trackerd: unexpected argument '%s'\n", argv[optind]);
        return 2;
    }
    char err[1024];
    if (params && trk_params_load (params, &p, err, sizeof err) < 0) {
        fprintf (stderr, "trackerd: %s\n", err);
        return 2;
    }
    if (!isfinite (sigma))
        sigma = p.filter.sigma_meas_m[0];
    trk_mc_config_t c = {
        .targets = (size_t)targets,
        .scans = (size_t)scans,
        .settle_scans = 8,
        .speed_mps = speed,
        .sigma_meas_m = {sigma, sigma},
        .turn_scan = turn > 0 ? (size_t)scans - 6 : 0,
        .turn_deg = turn,
        .seed = seed,
    };
    trk_mc_result_t r;
    int rc = trk_mc_run (&p, &c, &r);
    if (rc < 0) {
        fprintf (stderr, "trackerd: --monte-carlo: %s\n",
                 rc == -ENOMEM ? "out of memory" : "invalid configuration");
        return 2;
    }
    trk_gains_t g;
    trk_gains_paper (p.filter.sigma_meas_m[0], p.filter.sigma_mod_mps2[0], p.filter.dt_s, &g);
    double pv = NAN, vv = NAN;
    trk_filter_steady_error (&g, p.filter.dt_s, sigma, &pv, &vv);
    printf ("{\"mode\":\"%s\",\"sigma_meas_m\":%g,\"sigma_mod_mps2\":%g,\"scan_period_s\":%g,"
            "\"r\":%.6g,\"g\":%.6f,\"g_d_hz\":%.6f,\"threshold_deg\":%g,\"speed_mps\":%g,"
            "\"turn_deg\":%g,\"targets\":%zu,\"scans\":%zu,\"seed\":%llu,\"lost\":%zu,",
            p.filter.mode == TRK_FILTER_KALMAN ? "kalman" : "paper", sigma,
            p.filter.sigma_mod_mps2[0], p.filter.dt_s, g.r, g.g, g.gd_hz, p.turn_threshold_deg,
            speed, turn, c.targets, c.scans, (unsigned long long)c.seed, r.lost);
    if (turn > 0)
        printf ("\"turns\":%zu,\"detected_within_2_scans\":%zu,\"detection_rate\":%.5f,"
                "\"straight_scans\":%zu,\"false_turns\":%zu,\"false_turn_rate\":%.6f,"
                "\"completed\":%zu,\"right_side\":%zu,\"angle_mean_deg\":%.2f,"
                "\"angle_sd_deg\":%.2f}\n",
                r.turns, r.detected, r.turns ? (double)r.detected / (double)r.turns : 0,
                r.straight_scans, r.false_turns,
                r.straight_scans ? (double)r.false_turns / (double)r.straight_scans : 0,
                r.completed, r.right_side, r.angle_mean_deg, r.angle_sd_deg);
    else
        printf ("\"samples\":%zu,\"rmse_position_m\":[%.3f,%.3f],\"rmse_velocity_mps\":[%.4f,"
                "%.4f],\"theory_position_m\":%.3f,\"theory_velocity_mps\":%.4f}\n",
                r.samples, r.rmse_pos_m[0], r.rmse_pos_m[1], r.rmse_vel_mps[0], r.rmse_vel_mps[1],
                sqrt (pv), sqrt (vv));
    return 0;
}

/* ---- main ---------------------------------------------------------------------------- */

static const cgs_service_option_t s_options[] = {
    {"fresh", false, NULL, "start with no tracks, ignoring the checkpoint"},
    {"monte-carlo", false, NULL, "run the tracker on synthetic targets (see --monte-carlo --help)"},
    {NULL, false, NULL, NULL},
};

static int s_on_option (void *arg, const char *name, const char *value, char *why, size_t whylen)
{
    (void)value;
    s_app_t *app = arg;
    if (strcmp (name, "fresh") == 0) {
        app->fresh = true;
        return 0;
    }
    snprintf (why, whylen, "unknown option --%s", name);
    return -EINVAL;
}

static int s_setup (s_app_t *app, char *err, size_t errlen)
{
    trk_params_defaults (&app->params);
    const char *params = app->svc.params;
    if (*params) {
        int rc = trk_params_load (params, &app->params, err, errlen);
        if (rc < 0)
            return rc;
        cgs_log (LOG_INFO, "tracker parameters from %s", params);
    } else {
        cgs_log (LOG_INFO, "tracker parameters: the built-in defaults (no parameter file named)");
    }
    app->trk = trk_tracker_new (&app->params);
    if (!app->trk) {
        snprintf (err, errlen, "out of memory");
        return -ENOMEM;
    }
    if (cgs_state_path (app->checkpoint, sizeof app->checkpoint, app->svc.state_dir,
                        app->svc.instance_name) < 0 ||
        strlen (app->checkpoint) + 8 > sizeof app->checkpoint) {
        snprintf (err, errlen, "state folder path too long");
        return -ENAMETOOLONG;
    }
    strcat (app->checkpoint, ".tracks");
    const trk_params_t *p = &app->params;
    const trk_gains_t *g = trk_tracker_gains (app->trk);
    cgs_log (LOG_INFO,
             "filter %s: sigma_meas %g/%g m, sigma_mod %g/%g m/s2, scan %g s: r %.4g/%.4g, "
             "g %.4f/%.4f, g_d %.5f/%.5f 1/s; gate %.3f (%.1f), M/N %d/%d, delete after %d "
             "misses, turn threshold %g deg",
             p->filter.mode == TRK_FILTER_KALMAN ? "kalman" : "paper", p->filter.sigma_meas_m[0],
             p->filter.sigma_meas_m[1], p->filter.sigma_mod_mps2[0], p->filter.sigma_mod_mps2[1],
             p->filter.dt_s, g[0].r, g[1].r, g[0].g, g[1].g, g[0].gd_hz, g[1].gd_hz,
             p->gate_probability, trk_params_gate (p), p->confirm_m, p->confirm_n, p->delete_misses,
             p->turn_threshold_deg);
    return 0;
}

int main (int argc, char **argv)
{
    gsl_set_error_handler_off (); // GSL reports through return codes; its handler would abort
    for (int i = 1; i < argc; i++)
        if (strcmp (argv[i], "--monte-carlo") == 0)
            return s_monte_carlo (argc, argv);
    static s_app_t app;
    cgs_service_info_t info = {
        .program = "trackerd",
        .summary = "Tracks from MTI hits, BCIS identity, the paper's Track & Update filter, "
                   "turn detection.",
        .options = s_options,
        .on_option = s_on_option,
        .option_arg = &app,
    };
    int rc = cgs_service_init (&app.svc, &info, argc, argv);
    if (rc != 0) {
        cgs_service_fini (&app.svc);
        return rc > 0 ? 0 : 1;
    }
    int exit_code = 1;
    char err[1024] = "";
    if (s_setup (&app, err, sizeof err) < 0) {
        cgs_log (LOG_ERR, "%s", err);
        goto done;
    }
    if (app.svc.check_only) {
        printf ("%s: parameters are good\n", app.svc.instance_name);
        exit_code = 0;
        goto done;
    }
    s_restore (&app);
    if (cgs_service_subscribe (&app.svc, "mti", s_on_mti, &app) < 0 ||
        cgs_service_subscribe (&app.svc, "mti.scan", s_on_mti_scan, &app) < 0 ||
        cgs_service_subscribe (&app.svc, "bcis", s_on_bcis, &app) < 0)
        goto done;
    cgs_loop_add_timer (app.svc.loop, S_CHECKPOINT_S, s_on_checkpoint_timer, &app);
    exit_code = cgs_service_run (&app.svc);
    if (s_checkpoint (&app) == 0)
        cgs_log (LOG_INFO, "saved %zu tracks to %s", trk_tracker_count (app.trk), app.checkpoint);
    cgs_log (LOG_INFO,
             "%llu scans (%llu closed without their end marker, %llu stale ignored), %llu hits, "
             "%llu tracks started, %llu deleted, %llu turns, %llu BCIS replies matched a track",
             (unsigned long long)app.scans, (unsigned long long)app.implicit_scans,
             (unsigned long long)app.stale_scans, (unsigned long long)app.hits,
             (unsigned long long)app.born, (unsigned long long)app.deleted,
             (unsigned long long)app.turns, (unsigned long long)app.bcis_marks);
done:
    trk_tracker_destroy (&app.trk);
    for (size_t i = 0; i < app.radar_count; i++)
        free (app.radars[i].hits);
    free (app.tmsg);
    free (app.tptr);
    free (app.tpos);
    free (app.tvel);
    free (app.tcov);
    free (app.hpts);
    free (app.hptr);
    free (app.hpos);
    cgs_service_fini (&app.svc);
    return exit_code;
}
