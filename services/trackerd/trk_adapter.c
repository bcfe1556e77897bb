/* trk_adapter — trackerd's scans per radar, input validation and output
 * messages (see trk_adapter.h). */
#include "trk_adapter.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <syslog.h>

#define S_PI 3.14159265358979323846

const char *const trk_adapter_topics[] = {"mti", "mti.scan", "bcis", NULL};

/* The hits of one radar's scan in progress. */
typedef struct {
    uint32_t uav_id;
    uint32_t scan_number;
    bool open; // hits have come for scan_number and it has not ended
    trk_hit_t *hits;
    size_t count, cap;
    double platform[3];   // the radar's position (latest dwell)
    double platform_v[2]; // its ground velocity, from its positions a second or more apart
    bool has_ref;         // the earlier position that velocity is measured from:
    double ref_p[2], ref_t;
    bool has_closed;      // a scan of it has been processed:
    uint32_t last_closed; // its number
    bool has_time;        // the latest simulation time heard from it:
    double last_time_s;
    bool full_revolution;                       // what its latest mti.scan covered (for a scan
    double sector_center_deg, sector_width_deg; // closed without its marker)
    bool revisit_known;                         // its revisit has been given to the tracker
    uint32_t scans_seen;                        // its mti.scan markers taken
} s_radar_t;

struct trk_adapter {
    trk_tracker_t *trk;
    cgs_port_t port;
    bool verbose;          // a log line per scan, not only the first
    char params_path[256]; // where the parameters came from ("": the defaults)
    bool dirty;            // tracks changed since the last trk_adapter_take_dirty
    bool greedy_said;      // the warning of a greedily assigned cluster was logged
    s_radar_t radars[TRK_ADAPTER_RADARS_MAX];
    size_t radar_count;
    trk_adapter_stats_t stats;
    /* Output messages, reused. */
    Cgs__Track *tmsg;
    Cgs__Track **tptr;
    Cgs__Enu *tpos;
    Cgs__EnuVelocity *tvel;
    double *tcov; // 16 per track, then 3 mode probabilities
    Cgs__TrackHistoryPoint *hpts;
    Cgs__TrackHistoryPoint **hptr;
    Cgs__Enu *hpos;
    size_t tcap, hcap; // tracks, history points they hold
};

trk_adapter_t *trk_adapter_new (const trk_params_t *params, const cgs_port_t *port)
{
    trk_adapter_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->trk = trk_tracker_new (params);
    if (!self->trk)
        goto fail;
    if (port)
        self->port = *port;
    return self;
fail:
    trk_adapter_destroy (&self);
    return NULL;
}

void trk_adapter_destroy (trk_adapter_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    trk_adapter_t *self = *self_p;
    trk_tracker_destroy (&self->trk);
    for (size_t i = 0; i < self->radar_count; i++)
        free (self->radars[i].hits);
    free (self->tmsg);
    free (self->tptr);
    free (self->tpos);
    free (self->tvel);
    free (self->tcov);
    free (self->hpts);
    free (self->hptr);
    free (self->hpos);
    free (self);
    *self_p = NULL;
}

void trk_adapter_set_params_path (trk_adapter_t *self, const char *path)
{
    snprintf (self->params_path, sizeof self->params_path, "%s", path ? path : "");
}

void trk_adapter_set_verbose (trk_adapter_t *self, bool verbose)
{
    self->verbose = verbose;
}

trk_tracker_t *trk_adapter_tracker (trk_adapter_t *self)
{
    return self->trk;
}

const trk_adapter_stats_t *trk_adapter_stats (const trk_adapter_t *self)
{
    return &self->stats;
}

bool trk_adapter_take_dirty (trk_adapter_t *self)
{
    bool dirty = self->dirty;
    self->dirty = false;
    return dirty;
}

/* ---- radars ------------------------------------------------------------------------ */

/* The scan state of radar uav_id, new when first heard; NULL when there are
 * TRK_ADAPTER_RADARS_MAX others already. */
static s_radar_t *s_radar (trk_adapter_t *self, uint32_t uav_id)
{
    for (size_t i = 0; i < self->radar_count; i++)
        if (self->radars[i].uav_id == uav_id)
            return &self->radars[i];
    if (self->radar_count == TRK_ADAPTER_RADARS_MAX)
        return NULL;
    s_radar_t *r = &self->radars[self->radar_count++];
    memset (r, 0, sizeof *r);
    r->uav_id = uav_id;
    r->full_revolution = true;
    return r;
}

/* Simulation time t from radar r: notes it, and says whether it went back by
 * more than two scans (a new exercise, or uavsim restarted from an older
 * checkpoint). Then the radar's open scan is of another time line: dropped. */
static bool s_time_went_back (trk_adapter_t *self, s_radar_t *r, double t)
{
    double dt = trk_tracker_params (self->trk)->filter.dt_s;
    bool back = r->has_time && t < r->last_time_s - 2 * dt;
    if (back) {
        cgs_port_log (&self->port, LOG_NOTICE,
                      "radar %u: simulation time went back from %.2f to %.2f s; its scan in "
                      "progress is dropped and its tracks from later times go at its next scan",
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

/* ---- publishing -------------------------------------------------------------------- */

/* Room in the reused buffers for this many tracks and history points;
 * 0 or -ENOMEM (what was grown stays). */
static int s_reserve (trk_adapter_t *self, size_t tracks, size_t points)
{
    if (tracks > self->tcap) {
        size_t n = tracks * 2;
        void *a = realloc (self->tmsg, n * sizeof *self->tmsg);
        if (a)
            self->tmsg = a;
        void *b = realloc (self->tptr, n * sizeof *self->tptr);
        if (b)
            self->tptr = b;
        void *c = realloc (self->tpos, n * sizeof *self->tpos);
        if (c)
            self->tpos = c;
        void *d = realloc (self->tvel, n * sizeof *self->tvel);
        if (d)
            self->tvel = d;
        void *e = realloc (self->tcov, n * 19 * sizeof *self->tcov);
        if (e)
            self->tcov = e;
        if (!a || !b || !c || !d || !e)
            return -ENOMEM;
        self->tcap = n;
    }
    if (points > self->hcap) {
        size_t n = points * 2;
        void *a = realloc (self->hpts, n * sizeof *self->hpts);
        if (a)
            self->hpts = a;
        void *b = realloc (self->hptr, n * sizeof *self->hptr);
        if (b)
            self->hptr = b;
        void *c = realloc (self->hpos, n * sizeof *self->hpos);
        if (c)
            self->hpos = c;
        if (!a || !b || !c)
            return -ENOMEM;
        self->hcap = n;
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
static void s_fill (trk_adapter_t *self, size_t i, size_t *hp, const trk_track_t *t, double now)
{
    Cgs__Track *m = &self->tmsg[i];
    cgs__track__init (m);
    trk_estimate_t e = t->est;
    if (now > e.t_s)
        trk_tracker_predict (self->trk, t, now, &e);
    Cgs__Enu *p = &self->tpos[i];
    cgs__enu__init (p);
    p->east_m = e.x[0];
    p->north_m = e.x[1];
    p->up_m = t->up_m;
    Cgs__EnuVelocity *v = &self->tvel[i];
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
    double *c = &self->tcov[i * 19];
    memcpy (c, e.P, sizeof e.P);
    m->n_covariance = 16;
    m->covariance = c;
    m->continues = t->continues;
    m->continues_probability = t->continues_p;
    if (trk_tracker_params (self->trk)->filter.mode == TRK_FILTER_IMM) {
        m->existence_probability = t->existence;
        m->detection_probability = t->pd;
        if (t->hits >= 2) {
            memcpy (c + 16, t->imm.mu, sizeof t->imm.mu);
            m->n_mode_probabilities = TRK_IMM_MODELS;
            m->mode_probabilities = c + 16;
        }
    }
    m->n_history = t->history_count;
    m->history = &self->hptr[*hp];
    for (uint32_t k = 0; k < t->history_count; k++, (*hp)++) {
        const trk_history_point_t *h = &t->history[k];
        Cgs__TrackHistoryPoint *q = &self->hpts[*hp];
        cgs__track_history_point__init (q);
        cgs__enu__init (&self->hpos[*hp]);
        self->hpos[*hp].east_m = h->e_m;
        self->hpos[*hp].north_m = h->n_m;
        self->hpos[*hp].up_m = h->u_m;
        q->position = &self->hpos[*hp];
        q->sim_time_s = h->t_s;
        q->scan_number = h->scan_number;
        q->hit_id = h->hit_id;
        self->hptr[*hp] = q;
    }
    self->tptr[i] = m;
}

/* Every track of the radar, and those deleted in the scan, in batches. */
static void s_publish_tracks (trk_adapter_t *self, const trk_scan_t *scan,
                              const trk_scan_out_t *out)
{
    size_t n = 0, points = 0, total = trk_tracker_count (self->trk);
    for (size_t i = 0; i < total; i++) {
        const trk_track_t *t = trk_tracker_at (self->trk, i);
        if (t->uav_id == scan->uav_id) {
            n++;
            points += t->history_count;
        }
    }
    for (size_t i = 0; i < out->deleted_count; i++)
        points += out->deleted_tracks[i].history_count;
    n += out->deleted_count;
    if (s_reserve (self, n, points) < 0) {
        cgs_port_error (&self->port, "out of memory: a scan's tracks were not published");
        return;
    }
    size_t k = 0, hp = 0;
    for (size_t i = 0; i < total; i++) {
        const trk_track_t *t = trk_tracker_at (self->trk, i);
        if (t->uav_id == scan->uav_id)
            s_fill (self, k++, &hp, t, scan->end_s);
    }
    for (size_t i = 0; i < out->deleted_count; i++)
        s_fill (self, k++, &hp, &out->deleted_tracks[i], scan->end_s);
    size_t batches = n ? (n + TRK_ADAPTER_BATCH_TRACKS - 1) / TRK_ADAPTER_BATCH_TRACKS : 1;
    for (size_t b = 0; b < batches; b++) {
        Cgs__TrackBatch m = CGS__TRACK_BATCH__INIT;
        m.uav_id = scan->uav_id;
        m.scan_number = scan->scan_number;
        m.batch_index = (uint32_t)b;
        m.batch_count = (uint32_t)batches;
        m.links_continuation = trk_tracker_params (self->trk)->filter.mode == TRK_FILTER_IMM;
        size_t lo = b * TRK_ADAPTER_BATCH_TRACKS;
        m.n_tracks = n - lo < TRK_ADAPTER_BATCH_TRACKS ? n - lo : TRK_ADAPTER_BATCH_TRACKS;
        m.tracks = n ? &self->tptr[lo] : NULL;
        cgs_port_publish (&self->port, "track", &m.base, scan->end_s);
    }
}

static void s_publish_turn (trk_adapter_t *self, const trk_turn_t *ev, uint32_t uav_id,
                            double sim_time_s)
{
    Cgs__Enu pos = CGS__ENU__INIT;
    Cgs__EnuVelocity before = CGS__ENU_VELOCITY__INIT, after = CGS__ENU_VELOCITY__INIT;
    pos.east_m = ev->position[0];
    pos.north_m = ev->position[1];
    before.east_mps = ev->v_before[0];
    before.north_mps = ev->v_before[1];
    after.east_mps = ev->v_after[0];
    after.north_mps = ev->v_after[1];
    const trk_track_t *t = trk_tracker_find (self->trk, ev->track_id);
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
    cgs_port_publish (&self->port, "track.turn", &m.base, sim_time_s);
}

/* ---- scans ------------------------------------------------------------------------- */

/* Radar r's scan (with the hits it holds) through the tracker, then its
 * tracks and turns out; the radar's scan is closed. */
static void s_run_scan (trk_adapter_t *self, s_radar_t *r, const trk_scan_t *scan)
{
    trk_scan_out_t out;
    size_t given = r->count;
    int rc = trk_tracker_scan (self->trk, scan, r->hits, given, &out);
    r->count = 0;
    r->open = false;
    r->has_closed = true;
    r->last_closed = scan->scan_number;
    if (rc < 0) {
        cgs_port_error (&self->port, "out of memory: a scan's hits were dropped");
        cgs_port_log (&self->port, LOG_ERR, "out of memory: scan %u of radar %u was dropped",
                      scan->scan_number, scan->uav_id);
        return;
    }
    for (size_t i = out.hits; i < given; i++)
        cgs_port_bad_input (&self->port, "an MTI hit whose time lies outside its scan");
    trk_adapter_stats_t *st = &self->stats;
    st->scans++;
    st->hits += out.hits;
    st->born += out.born;
    st->deleted += out.deleted;
    st->turns += out.turn_count;
    if (out.time_reset) {
        st->time_resets += out.time_reset;
        cgs_port_log (&self->port, LOG_NOTICE,
                      "simulation time went back to %.2f s: %zu tracks of radar %u from later "
                      "times were deleted",
                      scan->end_s, out.time_reset, scan->uav_id);
    }
    s_publish_tracks (self, scan, &out);
    for (size_t i = 0; i < out.turn_count; i++)
        s_publish_turn (self, &out.turns[i], scan->uav_id, scan->end_s);
    self->dirty = true;
    if (out.greedy_clusters && !self->greedy_said) {
        // Said once: crowding is a property of the scene, not of one scan.
        cgs_port_log (&self->port, LOG_WARNING,
                      "radar %u scan %u: %zu clusters of more than %d tracks (largest %zu) "
                      "assigned greedily, not optimally: the targets are too crowded for the "
                      "gates",
                      scan->uav_id, scan->scan_number, out.greedy_clusters, TRK_CLUSTER_MAX,
                      out.largest_cluster);
        self->greedy_said = true;
    }
    if (st->scans == 1 || self->verbose)
        cgs_port_log (&self->port, LOG_INFO,
                      "radar %u scan %u: %zu hits, %zu updated, %zu missed, %zu new, %zu "
                      "confirmed, %zu deleted, %zu continued (%zu of a coasting track), %zu "
                      "clusters (largest %zu), %zu branched, %zu switched branch; %zu tracks",
                      scan->uav_id, scan->scan_number, out.hits, out.updated, out.missed, out.born,
                      out.confirmed, out.deleted, out.continued, out.reacquired, out.clusters,
                      out.largest_cluster, out.branched, out.alt_swaps,
                      trk_tracker_count (self->trk));
}

/* A scan whose end marker never came (lost, or its radar restarted): closed
 * with what is known. */
static void s_close_implicit (trk_adapter_t *self, s_radar_t *r)
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
        .platform_up_m = r->platform[2],
        .platform_velocity = {r->platform_v[0], r->platform_v[1]},
    };
    self->stats.implicit_scans++;
    if (r->count)
        s_run_scan (self, r, &scan);
    r->open = false;
    r->count = 0;
}

static bool s_enu_ok (const Cgs__Enu *p)
{
    return p && isfinite (p->east_m) && isfinite (p->north_m) && isfinite (p->up_m);
}

/* ---- inputs ------------------------------------------------------------------------ */

/* Hits of one dwell: into their radar's open scan. */
static void s_on_mti (trk_adapter_t *self, const Cgs__Mti *m, const Cgs__Header *hdr)
{
    if (!m->uav_id || !s_enu_ok (m->platform_position)) {
        cgs_port_bad_input (&self->port, "an mti message without a radar id or platform position");
        return;
    }
    s_radar_t *r = s_radar (self, m->uav_id);
    if (!r) {
        cgs_port_bad_input (&self->port, "hits of more radars than trackerd keeps scans for");
        return;
    }
    if (hdr && isfinite (hdr->sim_time_s))
        s_time_went_back (self, r, hdr->sim_time_s);
    if (s_stale (r, m->scan_number)) {
        self->stats.stale_scans++;
        return; // hits of a scan already closed
    }
    if (r->open && r->scan_number != m->scan_number)
        s_close_implicit (self, r); // its end marker was lost
    r->open = true;
    r->scan_number = m->scan_number;
    const Cgs__Enu *pl = m->platform_position;
    r->platform[0] = pl->east_m;
    r->platform[1] = pl->north_m;
    r->platform[2] = pl->up_m;
    double t_now = hdr && isfinite (hdr->sim_time_s) ? hdr->sim_time_s : NAN;
    if (isfinite (t_now)) {
        double dt = r->has_ref ? t_now - r->ref_t : -1;
        if (dt >= 1 && dt <= 60) {
            r->platform_v[0] = (pl->east_m - r->ref_p[0]) / dt;
            r->platform_v[1] = (pl->north_m - r->ref_p[1]) / dt;
        }
        if (!(dt >= 0 && dt < 1)) { // a new reference a second or more on (or after a jump)
            r->has_ref = true;
            r->ref_p[0] = pl->east_m;
            r->ref_p[1] = pl->north_m;
            r->ref_t = t_now;
        }
    }
    if (r->count + m->n_hits > r->cap) {
        size_t cap = (r->count + m->n_hits) * 2;
        trk_hit_t *h = realloc (r->hits, cap * sizeof *h);
        if (!h) {
            cgs_port_error (&self->port, "out of memory: hits dropped");
            return;
        }
        r->hits = h;
        r->cap = cap;
    }
    for (size_t i = 0; i < m->n_hits; i++) {
        const Cgs__MtiHit *h = m->hits[i];
        if (!s_enu_ok (h->position) || !isfinite (h->sim_time_s) ||
            !isfinite (h->radial_velocity_mps) || !isfinite (h->azimuth_deg)) {
            cgs_port_bad_input (
                &self->port,
                "an MTI hit without a valid position, time, azimuth or radial velocity");
            continue;
        }
        const Cgs__Enu *q = h->position;
        r->hits[r->count++] =
            trk_hit_from_mti (h->hit_id, h->sim_time_s, (cgs_enu_t){q->east_m, q->north_m, q->up_m},
                              (cgs_enu_t){pl->east_m, pl->north_m, pl->up_m}, h->azimuth_deg,
                              h->range_sigma_m, h->azimuth_sigma_deg, h->radial_velocity_mps);
    }
}

/* The end of a radar scan: the scan through the tracker. */
static void s_on_mti_scan (trk_adapter_t *self, const Cgs__MtiScan *m)
{
    if (!m->uav_id || !isfinite (m->scan_start_s) || !isfinite (m->scan_end_s) ||
        m->scan_end_s < m->scan_start_s || !isfinite (m->sector_center_deg) ||
        (!m->full_revolution && !(m->sector_width_deg > 0 && m->sector_width_deg <= 360))) {
        cgs_port_bad_input (&self->port,
                            "an mti.scan message without a radar id, times in order or a sector");
        return;
    }
    s_radar_t *r = s_radar (self, m->uav_id);
    if (!r) {
        cgs_port_bad_input (&self->port, "a scan of more radars than trackerd keeps scans for");
        return;
    }
    s_time_went_back (self, r, m->scan_end_s);
    if (s_stale (r, m->scan_number)) {
        self->stats.stale_scans++;
        return;
    }
    if (r->open && r->scan_number != m->scan_number)
        s_close_implicit (self, r); // its own end marker was lost
    // The radar's revisit of a cell: one scan (a revolution, or one pass of
    // a sector, which revisits its cells once a pass on average), from its
    // second scan heard: the first may be partial (a radar starts, or
    // restarts, at the dwell of the time it is at).
    double revisit = m->scan_end_s - m->scan_start_s;
    if (!r->revisit_known && ++r->scans_seen >= 2 && revisit > 0) {
        r->revisit_known = true;
        double fixed = trk_tracker_params (self->trk)->filter.dt_s;
        if (!trk_tracker_radar_revisit (self->trk, revisit))
            cgs_port_error (&self->port,
                            "%s: [filter] scan_period_s = %g refused: radar %u revisits a cell "
                            "every %.2f s (its scan %u, %.2f to %.2f s); the paper's gains follow "
                            "each update's own interval (scan_period_s = auto) from now on",
                            *self->params_path ? self->params_path : "the built-in parameters",
                            fixed, m->uav_id, revisit, m->scan_number, m->scan_start_s,
                            m->scan_end_s);
    }
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
        .expected_false_alarms = isfinite (m->expected_false_alarms) && m->expected_false_alarms > 0
                                     ? m->expected_false_alarms
                                     : 0,
        .platform = {r->platform[0], r->platform[1]},
        .platform_up_m = r->platform[2],
        .platform_velocity = {r->platform_v[0], r->platform_v[1]},
    };
    r->scan_number = m->scan_number;
    s_run_scan (self, r, &scan);
}

/* BCIS replies: each may mark a track of each radar friendly. A reply puts
 * its responder where its range and the beam's azimuth meet the ground,
 * with their uncertainty about the interrogator, or gives a position fix. */
static void s_on_bcis (trk_adapter_t *self, const Cgs__Bcis *m)
{
    for (size_t i = 0; i < m->n_replies; i++) {
        const Cgs__BcisReply *r = m->replies[i];
        if (!s_enu_ok (r->position) || !isfinite (r->sim_time_s)) {
            cgs_port_bad_input (&self->port, "a BCIS reply without a valid position or time");
            continue;
        }
        double z[2] = {r->position->east_m, r->position->north_m};
        trk_bcis_reply_t reply;
        if (r->position_fix) {
            double s = r->position_sigma_m > 0 && isfinite (r->position_sigma_m)
                           ? r->position_sigma_m
                           : trk_tracker_params (self->trk)->bcis_sigma_m;
            reply = (trk_bcis_reply_t){.t_s = r->sim_time_s,
                                       .z = {z[0], z[1]},
                                       .R = {s * s, 0, 0, s * s},
                                       .responder_id = r->responder_id};
        } else if (!s_enu_ok (m->interrogator) ||
                   trk_bcis_reply_geometry (r->sim_time_s, z, r->range_m, r->range_sigma_m,
                                            m->interrogator->up_m - r->position->up_m,
                                            r->azimuth_deg, r->azimuth_sigma_deg, r->responder_id,
                                            &reply) < 0) {
            cgs_port_bad_input (&self->port,
                                "a BCIS reply without a valid range, azimuth or interrogator");
            continue;
        }
        size_t marked = trk_tracker_bcis (self->trk, &reply);
        if (marked) {
            self->stats.bcis_marks += marked;
            self->dirty = true;
        }
    }
}

void trk_adapter_on_message (trk_adapter_t *self, const char *topic, const ProtobufCMessage *msg,
                             const Cgs__Header *hdr)
{
    assert (self && topic && msg);
    // The transport delivers each catalogue topic with its own type only.
    if (strcmp (topic, "mti") == 0) {
        assert (msg->descriptor == &cgs__mti__descriptor);
        s_on_mti (self, (const Cgs__Mti *)msg, hdr);
    } else if (strcmp (topic, "mti.scan") == 0) {
        assert (msg->descriptor == &cgs__mti_scan__descriptor);
        s_on_mti_scan (self, (const Cgs__MtiScan *)msg);
    } else if (strcmp (topic, "bcis") == 0) {
        assert (msg->descriptor == &cgs__bcis__descriptor);
        s_on_bcis (self, (const Cgs__Bcis *)msg);
    }
}
