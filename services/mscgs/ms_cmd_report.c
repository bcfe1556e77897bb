/* ms_cmd_report — `mscgs report FILE [--out DIR]`: the after-action review
 * of a recording (`mscgs record`, `mscgs run --record`).
 *
 * The recording is read once, in order, and every message goes where
 * `mscgs run` sends it live: the observer of the intercept (ms_icpt) and
 * the tracking metrics (ms_metrics), so the report's figures are the run
 * summary's, computed again from what was recorded. Beside them it keeps,
 * against simulation time: ground truth (a point per vehicle every 5 s), the
 * UAVs' paths, the radar's hits and what the radar saw of each vehicle
 * (mti.truth), the tracks, the intercept's states and marks, the
 * designated vehicle's track error and the footprint's distance to it,
 * each scan's GOSPA, completeness and false tracks; against the
 * recording's time, each service's health and the messages missed by
 * sequence number.
 *
 * It writes DIR/report.html (one XHTML file: the tables, and every chart as
 * inline SVG, no script, nothing fetched), DIR/fig-NAME.png (each chart,
 * rendered by librsvg) and DIR/report.json (the intercept and tracking
 * members of `mscgs run`'s summary.json, from the recording). */
#include "ms_cmd_report.h"

#include "cgs_footprint.h"
#include "cgs_mcap.h"
#include "cgs_msg.h"
#include "cgs_topics.h"
#include "health.pb-c.h"
#include "intercept.pb-c.h"
#include "ms_marks.h"
#include "ms_metrics.h"
#include "ms_observer.h"
#include "ms_opts.h"
#include "ms_plot.h"
#include "sensors.pb-c.h"
#include "tracking.pb-c.h"
#include "world.pb-c.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#define S_TRUTH_DT_S  5.0  // a vehicle's true position kept every this many seconds
#define S_UAV_DT_S    1.0  // a UAV's
#define S_VR_BIN      0.5  // radial velocity bins, m/s
#define S_VR_MAX      30.0 // ... over ±this
#define S_VR_BINS     120  // 2 · S_VR_MAX / S_VR_BIN
#define S_RANGE_BIN_M 1000.0
#define S_RANGE_BINS  120
#define S_HITS_DRAWN  20000 // hits drawn on the map at most (every k-th)
#define S_W           900   // a chart's size, pixels
#define S_H           360

/* ---- series -------------------------------------------------------------------------- */

typedef struct {
    double *x, *y;
    size_t n, cap;
} s_xy_t;

static int s_xy_add (s_xy_t *s, double x, double y)
{
    if (s->n == s->cap) {
        size_t cap = s->cap ? 2 * s->cap : 256;
        double *nx = realloc (s->x, cap * sizeof *nx);
        if (!nx)
            return -ENOMEM;
        s->x = nx;
        double *ny = realloc (s->y, cap * sizeof *ny);
        if (!ny)
            return -ENOMEM;
        s->y = ny;
        s->cap = cap;
    }
    s->x[s->n] = x;
    s->y[s->n++] = y;
    return 0;
}

static void s_xy_free (s_xy_t *s)
{
    free (s->x);
    free (s->y);
    memset (s, 0, sizeof *s);
}

/* A vehicle, a UAV or a track: its id and its path. */
typedef struct {
    uint32_t id;
    char marking[32];
    int force;
    bool ground;
    double last_kept_s;
    double t_s, e, n, ve, vn; // newest state
    s_xy_t path;
} s_thing_t;

typedef struct {
    s_thing_t *v;
    size_t n, cap;
} s_things_t;

static s_thing_t *s_thing (s_things_t *t, uint32_t id)
{
    for (size_t i = 0; i < t->n; i++)
        if (t->v[i].id == id)
            return &t->v[i];
    if (t->n == t->cap) {
        size_t cap = t->cap ? 2 * t->cap : 64;
        s_thing_t *v = realloc (t->v, cap * sizeof *v);
        if (!v)
            return NULL;
        t->v = v;
        t->cap = cap;
    }
    s_thing_t *x = &t->v[t->n++];
    memset (x, 0, sizeof *x);
    x->id = id;
    x->last_kept_s = -INFINITY;
    return x;
}

static void s_things_free (s_things_t *t)
{
    for (size_t i = 0; i < t->n; i++)
        s_xy_free (&t->v[i].path);
    free (t->v);
    memset (t, 0, sizeof *t);
}

/* A service's health over the recording. */
typedef struct {
    char instance[64];
    s_xy_t state; // (recording time, ServiceState) at each change
    int last_state;
    char last_error[160];
    uint64_t messages; // health messages
} s_service_t;

/* Sequence numbers of one source on one topic. */
typedef struct {
    char topic[32], source[64];
    uint64_t epoch, seq;
    uint64_t messages, gaps, restarts;
    uint64_t restarts_seen; // restarts when seq was last set
} s_stream_t;

/* An intercept state held from t0 until t1. */
typedef struct {
    double t0, t1;
    int state;
} s_phase_t;

typedef struct {
    const char *file;
    uint64_t t0_ns, t1_ns;
    uint64_t messages, undecoded;
    uint32_t exercise_id;
    double sim_first, sim_last;
    // What `mscgs run` computes.
    ms_icpt_t *icpt;
    ms_metrics_t *metrics;
    // Against simulation time.
    s_things_t vehicles, uavs, tracks;
    s_xy_t hits;
    uint64_t nhits;
    uint64_t range_hist[S_RANGE_BINS];
    uint64_t vr_hits[S_VR_BINS];                         // hits by measured radial velocity
    uint64_t vr_seen[S_VR_BINS], vr_detected[S_VR_BINS]; // mti.truth in beam and visible
    double max_range_m;
    ms_marks_t marks;
    uint32_t intercept_uav; // whose phases and distances are drawn (UINT32_MAX: id 0)
    s_phase_t *phases;
    size_t nphases, capphases;
    s_xy_t track_error, footprint_distance, inside;
    s_xy_t gospa, gospa_loc, gospa_missed, gospa_false, completeness, false_tracks, truths;
    // Against recording time.
    s_service_t services[64];
    size_t nservices;
    s_stream_t *streams;
    size_t nstreams, capstreams;
    s_xy_t gaps; // (recording time, messages missed so far)
    uint64_t gaps_total;
} s_report_t;

static double s_rec_s (const s_report_t *r, uint64_t log_ns)
{
    return ((double)log_ns - (double)r->t0_ns) / 1e9; // a clock stepped back: negative
}

/* ---- the messages ---------------------------------------------------------------------- */

static void s_on_scan (void *arg, const ms_metrics_scan_t *sc)
{
    s_report_t *r = arg;
    double t = sc->t_s, p = MS_METRICS_P;
    s_xy_add (&r->gospa, t, sc->gospa.distance);
    s_xy_add (&r->gospa_loc, t, pow (sc->gospa.localisation, 1 / p));
    s_xy_add (&r->gospa_missed, t, pow (sc->gospa.missed, 1 / p));
    s_xy_add (&r->gospa_false, t, pow (sc->gospa.false_, 1 / p));
    s_xy_add (&r->completeness, t,
              sc->truths ? 100.0 * (double)sc->tracked_truths / (double)sc->truths : NAN);
    s_xy_add (&r->false_tracks, t, (double)sc->unassociated);
    s_xy_add (&r->truths, t, (double)sc->truths);
}

static void s_entities (s_report_t *r, const Cgs__EntityBatch *b, double t)
{
    for (size_t i = 0; i < b->n_entities; i++) {
        const Cgs__Entity *e = b->entities[i];
        if (!e->position || !isfinite (e->position->east_m) || !isfinite (e->position->north_m))
            continue;
        bool ground = e->kind != CGS__ENTITY_KIND__ENTITY_KIND_AIR;
        if (!ground)
            continue; // UAVs come on `uav`
        s_thing_t *v = s_thing (&r->vehicles, e->entity_id);
        if (!v)
            continue;
        v->ground = true;
        v->force = e->force;
        if (e->marking && *e->marking)
            snprintf (v->marking, sizeof v->marking, "%s", e->marking);
        v->t_s = t;
        v->e = e->position->east_m;
        v->n = e->position->north_m;
        v->ve = e->velocity && isfinite (e->velocity->east_mps) ? e->velocity->east_mps : 0;
        v->vn = e->velocity && isfinite (e->velocity->north_mps) ? e->velocity->north_mps : 0;
        if (t - v->last_kept_s >= S_TRUTH_DT_S) {
            s_xy_add (&v->path, v->e, v->n);
            v->last_kept_s = t;
        }
    }
}

static void s_uav (s_report_t *r, const Cgs__Uav *m, double t)
{
    if (!m->position || !isfinite (m->position->east_m) || !isfinite (m->position->north_m))
        return;
    s_thing_t *u = s_thing (&r->uavs, m->entity_id);
    if (!u)
        return;
    if (m->name)
        snprintf (u->marking, sizeof u->marking, "%s", m->name);
    if (t - u->last_kept_s >= S_UAV_DT_S) {
        s_xy_add (&u->path, m->position->east_m / 1000, m->position->north_m / 1000);
        u->last_kept_s = t;
    }
}

static int s_vr_bin (double vr)
{
    if (!isfinite (vr) || fabs (vr) >= S_VR_MAX)
        return -1;
    return (int)floor ((vr + S_VR_MAX) / S_VR_BIN);
}

static void s_mti (s_report_t *r, const Cgs__Mti *m)
{
    for (size_t i = 0; i < m->n_hits; i++) {
        const Cgs__MtiHit *h = m->hits[i];
        r->nhits++;
        if (h->position)
            s_xy_add (&r->hits, h->position->east_m / 1000, h->position->north_m / 1000);
        if (isfinite (h->range_m) && h->range_m >= 0) {
            double b = floor (h->range_m / S_RANGE_BIN_M);
            r->range_hist[b >= S_RANGE_BINS ? S_RANGE_BINS - 1 : (int)b]++;
            r->max_range_m = fmax (r->max_range_m, h->range_m);
        }
        int b = s_vr_bin (h->radial_velocity_mps);
        if (b >= 0)
            r->vr_hits[b]++;
    }
}

static void s_mti_truth (s_report_t *r, const Cgs__MtiTruth *m)
{
    for (size_t i = 0; i < m->n_items; i++) {
        const Cgs__MtiTruthItem *it = m->items[i];
        if (!it->in_beam || !it->visible || it->merged_into)
            continue;
        int b = s_vr_bin (it->radial_velocity_mps);
        if (b < 0)
            continue;
        r->vr_seen[b]++;
        r->vr_detected[b] += it->detected;
    }
}

static void s_tracks (s_report_t *r, const Cgs__TrackBatch *b)
{
    for (size_t i = 0; i < b->n_tracks; i++) {
        const Cgs__Track *tr = b->tracks[i];
        if ((tr->status != CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED &&
             tr->status != CGS__TRACK_STATUS__TRACK_STATUS_COASTING) ||
            !tr->position || !isfinite (tr->position->east_m))
            continue;
        s_thing_t *t = s_thing (&r->tracks, tr->track_id);
        if (t)
            s_xy_add (&t->path, tr->position->east_m / 1000, tr->position->north_m / 1000);
    }
}

static void s_intercept (s_report_t *r, const Cgs__Intercept *m, double t)
{
    ms_marks_add (&r->marks, m, t);
    // The phases and the target's distances are of the first UAV heard of.
    if (!r->intercept_uav)
        r->intercept_uav = m->uav_id ? m->uav_id : UINT32_MAX;
    if ((m->uav_id ? m->uav_id : UINT32_MAX) != r->intercept_uav)
        return;
    int state = (int)m->state;
    if (r->nphases && r->phases[r->nphases - 1].state == state) {
        r->phases[r->nphases - 1].t1 = t;
    } else {
        if (r->nphases == r->capphases) {
            size_t cap = r->capphases ? 2 * r->capphases : 32;
            s_phase_t *p = realloc (r->phases, cap * sizeof *p);
            if (!p)
                return;
            r->phases = p;
            r->capphases = cap;
        }
        if (r->nphases)
            r->phases[r->nphases - 1].t1 = t;
        r->phases[r->nphases++] = (s_phase_t){t, t, state};
    }
    // The designated vehicle, as the observer knows it by now.
    uint32_t id = r->icpt->entity_id;
    s_thing_t *v = NULL;
    for (size_t i = 0; id && i < r->vehicles.n && !v; i++)
        if (r->vehicles.v[i].id == id)
            v = &r->vehicles.v[i];
    if (!v || !m->track_id)
        return;
    double dt = t - v->t_s, te = v->e + v->ve * dt, tn = v->n + v->vn * dt;
    if (m->has_target && m->target)
        s_xy_add (&r->track_error, t, hypot (m->target->east_m - te, m->target->north_m - tn));
    if (m->footprint && m->footprint->center) {
        s_xy_add (&r->footprint_distance, t,
                  hypot (m->footprint->center->east_m - te, m->footprint->center->north_m - tn));
        if (m->target_in_footprint)
            s_xy_add (&r->inside, t, 0);
    }
}

static void s_health (s_report_t *r, const Cgs__Health *h, double trec)
{
    const char *name = h->instance && *h->instance ? h->instance : "?";
    s_service_t *s = NULL;
    for (size_t i = 0; i < r->nservices && !s; i++)
        if (strcmp (r->services[i].instance, name) == 0)
            s = &r->services[i];
    if (!s) {
        if (r->nservices == sizeof r->services / sizeof r->services[0])
            return;
        s = &r->services[r->nservices++];
        snprintf (s->instance, sizeof s->instance, "%s", name);
        s->last_state = -1;
    }
    s->messages++;
    if ((int)h->state != s->last_state) {
        s_xy_add (&s->state, trec, (double)h->state);
        s->last_state = (int)h->state;
    }
    if (h->last_error && *h->last_error)
        snprintf (s->last_error, sizeof s->last_error, "%s", h->last_error);
}

/* Sequence numbers, as a subscriber counts them: a jump is messages missed,
 * a new epoch a restart. */
static void s_sequence (s_report_t *r, const char *topic, const Cgs__Header *h, double trec)
{
    const char *src = h->source ? h->source : "";
    s_stream_t *s = NULL;
    for (size_t i = 0; i < r->nstreams && !s; i++)
        if (strcmp (r->streams[i].source, src) == 0 && strcmp (r->streams[i].topic, topic) == 0)
            s = &r->streams[i];
    if (!s) {
        if (r->nstreams == r->capstreams) {
            size_t cap = r->capstreams ? 2 * r->capstreams : 32;
            s_stream_t *n = realloc (r->streams, cap * sizeof *n);
            if (!n)
                return;
            r->streams = n;
            r->capstreams = cap;
        }
        s = &r->streams[r->nstreams++];
        memset (s, 0, sizeof *s);
        snprintf (s->topic, sizeof s->topic, "%s", topic);
        snprintf (s->source, sizeof s->source, "%s", src);
        s->epoch = h->epoch;
        s->seq = h->seq;
        s->messages = 1;
        return;
    }
    s->messages++;
    uint64_t missed = 0;
    if (h->epoch != s->epoch) {
        s->restarts++;
        s->epoch = h->epoch;
    } else if (h->seq > s->seq + 1) {
        missed = h->seq - s->seq - 1;
    }
    if (h->seq > s->seq || s->restarts_seen != s->restarts) // a repeat leaves it
        s->seq = h->seq;
    s->restarts_seen = s->restarts;
    if (missed) {
        s->gaps += missed;
        r->gaps_total += missed;
        s_xy_add (&r->gaps, trec, (double)r->gaps_total);
    }
}

static void s_take (s_report_t *r, const cgs_topic_t *t, const cgs_mcap_record_t *rec)
{
    ProtobufCMessage *m = protobuf_c_message_unpack (t->message, NULL, rec->len, rec->data);
    const Cgs__Header *h = m ? cgs_msg_header (m) : NULL;
    if (!h) {
        r->undecoded++;
        if (m)
            protobuf_c_message_free_unpacked (m, NULL);
        return;
    }
    double trec = s_rec_s (r, rec->log_time_ns), ts = h->sim_time_s;
    if (!r->exercise_id)
        r->exercise_id = h->exercise_id;
    if (isfinite (ts) && ts > 0 && strcmp (t->name, "health") != 0) {
        if (!(r->sim_first > 0) || ts < r->sim_first)
            r->sim_first = ts;
        r->sim_last = fmax (r->sim_last, ts);
    }
    s_sequence (r, t->name, h, trec);
    const char *n = t->name;
    // As `mscgs run` feeds them: the observer first, then the metrics.
    if (strcmp (n, "intercept") == 0) {
        ms_icpt_on_intercept (r->icpt, n, m, h);
        s_intercept (r, (const Cgs__Intercept *)m, ts);
    } else if (strcmp (n, "track") == 0) {
        ms_icpt_on_track (r->icpt, n, m, h);
        ms_metrics_on_track (r->metrics, n, m, h);
        s_tracks (r, (const Cgs__TrackBatch *)m);
    } else if (strcmp (n, "mti.truth") == 0) {
        ms_icpt_on_mti_truth (r->icpt, n, m, h);
        ms_metrics_on_mti_truth (r->metrics, n, m, h);
        s_mti_truth (r, (const Cgs__MtiTruth *)m);
    } else if (strcmp (n, "entity") == 0) {
        ms_icpt_on_entity (r->icpt, n, m, h);
        ms_metrics_on_entity (r->metrics, n, m, h);
        s_entities (r, (const Cgs__EntityBatch *)m, ts);
    } else if (strcmp (n, "uav") == 0) {
        s_uav (r, (const Cgs__Uav *)m, ts);
    } else if (strcmp (n, "mti") == 0) {
        s_mti (r, (const Cgs__Mti *)m);
    } else if (strcmp (n, "health") == 0) {
        s_health (r, (const Cgs__Health *)m, trec);
    }
    protobuf_c_message_free_unpacked (m, NULL);
}

static int s_read (s_report_t *r)
{
    char err[512];
    cgs_mcap_reader_t *rd = cgs_mcap_reader_open (r->file, err, sizeof err);
    if (!rd) {
        fprintf (stderr, "mscgs report: %s\n", err);
        return -1;
    }
    static const cgs_topic_t *topic_of[65536];
    memset (topic_of, 0, sizeof topic_of);
    cgs_mcap_record_t rec;
    int rc;
    double next_progress = 0;
    while ((rc = cgs_mcap_reader_next (rd, &rec, err, sizeof err)) == 1) {
        if (rec.kind == CGS_MCAP_CHANNEL) {
            const cgs_topic_t *t = cgs_topics_find (rec.name);
            topic_of[rec.id] = t && strcmp (rec.encoding, "protobuf") == 0 ? t : NULL;
            continue;
        }
        if (rec.kind != CGS_MCAP_MESSAGE)
            continue;
        if (!r->messages)
            r->t0_ns = rec.log_time_ns;
        r->t1_ns = rec.log_time_ns > r->t1_ns ? rec.log_time_ns : r->t1_ns;
        r->messages++;
        if (topic_of[rec.id])
            s_take (r, topic_of[rec.id], &rec);
        else
            r->undecoded++;
        double tr = s_rec_s (r, rec.log_time_ns);
        if (tr >= next_progress) {
            if (tr > 0)
                fprintf (stderr, "mscgs report: read %.0f s of the recording, %llu messages\n", tr,
                         (unsigned long long)r->messages);
            next_progress = tr + 600;
        }
    }
    if (rc < 0)
        fprintf (stderr, "mscgs report: %s: %s (the report covers what came before)\n", r->file,
                 err);
    else if (!cgs_mcap_reader_complete (rd))
        fprintf (stderr,
                 "mscgs report: %s has no footer (its recorder was stopped hard): the "
                 "report covers its whole chunks\n",
                 r->file);
    cgs_mcap_reader_destroy (&rd);
    if (!r->messages) {
        fprintf (stderr, "mscgs report: %s holds no messages\n", r->file);
        return -1;
    }
    return 0;
}

/* ---- the charts ------------------------------------------------------------------------ */

typedef struct {
    ms_str_t *html;
    const char *dir;
    int figure;
    int failed;
} s_out_t;

/* Close a chart: into the page (with its caption), and into DIR/fig-NAME.png. */
static void s_figure (s_out_t *o, ms_str_t *svg, const ms_plot_t *p, const char *caption)
{
    ms_plot_end (svg, p);
    o->figure++;
    ms_str_printf (o->html, "<figure id=\"figure-%d\">\n", o->figure);
    if (svg->s)
        ms_str_printf (o->html, "%s", svg->s);
    ms_str_printf (o->html, "<figcaption>Figure %d. ", o->figure);
    ms_str_escaped (o->html, caption);
    ms_str_printf (o->html, " <a href=\"%s.png\">PNG</a></figcaption>\n</figure>\n", p->id);
    char path[PATH_MAX], err[512];
    snprintf (path, sizeof path, "%s/%s.png", o->dir, p->id);
    if (svg->oom ||
        ms_plot_png (svg->s, svg->len, p->width, p->height, path, err, sizeof err) < 0) {
        fprintf (stderr, "mscgs report: %s\n", svg->oom ? "out of memory" : err);
        o->failed++;
    }
    ms_str_free (svg);
}

static void s_range (const s_xy_t *s, double *lo, double *hi, bool x)
{
    for (size_t i = 0; i < s->n; i++) {
        double v = x ? s->x[i] : s->y[i];
        if (isfinite (v)) {
            *lo = fmin (*lo, v);
            *hi = fmax (*hi, v);
        }
    }
}

static const char *s_force_color (int force)
{
    switch (force) {
    case CGS__FORCE__FORCE_FRIENDLY:
        return "#2f6fd0";
    case CGS__FORCE__FORCE_HOSTILE:
        return "#d03030";
    default:
        return "#888888";
    }
}

static void s_fig_map (s_out_t *o, s_report_t *r)
{
    double lo_x = INFINITY, hi_x = -INFINITY, lo_y = INFINITY, hi_y = -INFINITY;
    for (size_t i = 0; i < r->uavs.n; i++) {
        s_range (&r->uavs.v[i].path, &lo_x, &hi_x, true);
        s_range (&r->uavs.v[i].path, &lo_y, &hi_y, false);
    }
    for (size_t i = 0; i < r->vehicles.n; i++)
        for (size_t k = 0; k < r->vehicles.v[i].path.n; k++) {
            lo_x = fmin (lo_x, r->vehicles.v[i].path.x[k] / 1000);
            hi_x = fmax (hi_x, r->vehicles.v[i].path.x[k] / 1000);
            lo_y = fmin (lo_y, r->vehicles.v[i].path.y[k] / 1000);
            hi_y = fmax (hi_y, r->vehicles.v[i].path.y[k] / 1000);
        }
    ms_str_t svg = {0};
    ms_plot_t p = {.id = "fig-map",
                   .title = "Map: ground truth, radar hits, tracks and the UAV's path",
                   .xlabel = "east of the exercise origin (km)",
                   .ylabel = "north (km)",
                   .x0 = lo_x - 1,
                   .x1 = hi_x + 1,
                   .y0 = lo_y - 1,
                   .y1 = hi_y + 1,
                   .width = S_W,
                   .height = 680,
                   .equal = true};
    ms_plot_begin (&svg, &p);
    // Hits first (under everything), every k-th when there are many.
    size_t step = r->hits.n > S_HITS_DRAWN ? r->hits.n / S_HITS_DRAWN + 1 : 1;
    s_xy_t drawn = {0};
    for (size_t i = 0; i < r->hits.n; i += step)
        s_xy_add (&drawn, r->hits.x[i], r->hits.y[i]);
    ms_plot_points (&svg, &p, drawn.x, drawn.y, drawn.n, "#e0b000", 1.0, 0.5);
    s_xy_free (&drawn);
    for (size_t i = 0; i < r->tracks.n; i++) {
        const s_xy_t *t = &r->tracks.v[i].path;
        bool desig = r->tracks.v[i].id == r->icpt->desig_track_id ||
                     r->tracks.v[i].id == r->icpt->first_track_id;
        ms_plot_line (&svg, &p, t->x, t->y, t->n, desig ? "#00a000" : "#f08000", desig ? 2.5 : 1.0,
                      NULL);
    }
    for (size_t i = 0; i < r->vehicles.n; i++) {
        s_thing_t *v = &r->vehicles.v[i];
        for (size_t k = 0; k < v->path.n; k++)
            v->path.x[k] /= 1000, v->path.y[k] /= 1000; // km from here on
        bool target = v->id == r->icpt->entity_id;
        ms_plot_line (&svg, &p, v->path.x, v->path.y, v->path.n, s_force_color (v->force),
                      target ? 2.0 : 1.0, target ? NULL : "4 3");
        if (v->path.n && (target || r->vehicles.n <= 40))
            ms_plot_text (&svg, &p, v->path.x[v->path.n - 1], v->path.y[v->path.n - 1], "start",
                          v->marking);
    }
    for (size_t i = 0; i < r->uavs.n; i++) {
        const s_xy_t *u = &r->uavs.v[i].path;
        ms_plot_line (&svg, &p, u->x, u->y, u->n, "#6030c0", 1.5, NULL);
    }
    const char *names[] = {"radar hits",     "tracks",          "designated track",
                           "truth: hostile", "truth: friendly", "truth: unknown",
                           "UAV path"};
    const char *colors[] = {"#e0b000", "#f08000", "#00a000", "#d03030",
                            "#2f6fd0", "#888888", "#6030c0"};
    ms_plot_legend (&svg, &p, names, colors, 7);
    char cap[400];
    snprintf (cap, sizeof cap,
              "The exercise from above: %zu ground vehicles' true paths (dashed; the designated "
              "one solid), %llu MTI radar hits%s, the confirmed and coasting tracks (the "
              "designated track in green) and the UAV's path.",
              r->vehicles.n, (unsigned long long)r->nhits,
              step > 1 ? " (a sample of them drawn)" : "");
    s_figure (o, &svg, &p, cap);
}

static const char *s_state_color (int state)
{
    static const char *const c[] = {"#cccccc", "#8fb8ff", "#5d8fe8", "#f0b040", "#e07020",
                                    "#30a040", "#208030", "#c04040", "#803030"};
    return state >= 0 && state < 9 ? c[state] : "#cccccc";
}

static void s_fig_timeline (s_out_t *o, s_report_t *r)
{
    ms_str_t svg = {0};
    ms_plot_t p = {.id = "fig-timeline",
                   .title = "The intercept: its phases, designations, re-plans and hand-overs",
                   .xlabel = "simulation time (s)",
                   .ylabel = "phase",
                   .x0 = r->sim_first,
                   .x1 = r->sim_last,
                   .y0 = 0,
                   .y1 = 4,
                   .width = S_W,
                   .height = 300,
                   .no_yticks = true};
    ms_plot_begin (&svg, &p);
    for (size_t i = 0; i < r->nphases; i++) {
        const s_phase_t *ph = &r->phases[i];
        double t1 = i + 1 < r->nphases ? r->phases[i + 1].t0 : ph->t1;
        const char *name = cgs_msg_enum_short (&cgs__intercept_state__descriptor, ph->state, "?");
        char title[96];
        snprintf (title, sizeof title, "%s from %.1f s to %.1f s", name, ph->t0, t1);
        ms_plot_band (&svg, &p, ph->t0, t1, 0.2, 1.2, s_state_color (ph->state), title);
        if (ms_plot_px (&p, t1) - ms_plot_px (&p, ph->t0) > 60)
            ms_plot_text (&svg, &p, (ph->t0 + t1) / 2, 0.55, "middle", name);
    }
    for (size_t i = 0; i < r->marks.n; i++) {
        const ms_mark_t *m = &r->marks.marks[i];
        if (strcmp (m->kind, "phase") == 0)
            continue; // the bands show them
        const char *c = strcmp (m->kind, "designate") == 0  ? "#c09000"
                        : strcmp (m->kind, "replan") == 0   ? "#8040c0"
                        : strcmp (m->kind, "handover") == 0 ? "#e07000"
                                                            : "#c03030";
        ms_plot_vmark (&svg, &p, m->t_s, c, m->text);
    }
    ms_plot_text (&svg, &p, r->sim_first, 1.35, "start", "phases (bands); marks (lines)");
    // A legend of the phases there were, in the order they came.
    const char *names[9], *colors[9];
    size_t nl = 0;
    for (size_t i = 0; i < r->nphases; i++) {
        const char *name =
            cgs_msg_enum_short (&cgs__intercept_state__descriptor, r->phases[i].state, "?");
        bool seen = false;
        for (size_t k = 0; k < nl && !seen; k++)
            seen = strcmp (names[k], name) == 0;
        if (!seen && nl < 9) {
            names[nl] = name;
            colors[nl++] = s_state_color (r->phases[i].state);
        }
    }
    if (nl)
        ms_plot_legend (&svg, &p, names, colors, nl);
    char cap[300];
    snprintf (cap, sizeof cap,
              "The intercept's state against simulation time (a band per phase, its name when "
              "there is room), with its %zu marks: designations (yellow), re-plans (violet), "
              "hand-overs to another track (orange), cancels (red).",
              r->marks.n);
    s_figure (o, &svg, &p, cap);
}

static void s_fig_target (s_out_t *o, s_report_t *r)
{
    double lo = INFINITY, hi = -INFINITY, ylo = 0, yhi = 1;
    s_range (&r->track_error, &lo, &hi, true);
    s_range (&r->footprint_distance, &lo, &hi, true);
    s_range (&r->track_error, &ylo, &yhi, false);
    s_range (&r->footprint_distance, &ylo, &yhi, false);
    ms_str_t svg = {0};
    ms_plot_t p = {.id = "fig-target",
                   .title = "The designated vehicle: track error and the footprint's distance",
                   .xlabel = "simulation time (s)",
                   .ylabel = "distance to the vehicle's true position (m)",
                   .x0 = isfinite (lo) ? lo : r->sim_first,
                   .x1 = isfinite (hi) ? hi : r->sim_last,
                   .y0 = 0,
                   .y1 = fmin (yhi * 1.05, 30000),
                   .width = S_W,
                   .height = S_H};
    ms_plot_begin (&svg, &p);
    ms_plot_line (&svg, &p, r->footprint_distance.x, r->footprint_distance.y,
                  r->footprint_distance.n, "#6030c0", 1.5, NULL);
    ms_plot_line (&svg, &p, r->track_error.x, r->track_error.y, r->track_error.n, "#d03030", 1.5,
                  NULL);
    ms_plot_points (&svg, &p, r->inside.x, r->inside.y, r->inside.n, "#30a040", 3, 1);
    const char *names[] = {"track error (guidanced's estimate)", "footprint centre",
                           "vehicle in the footprint"};
    const char *colors[] = {"#d03030", "#6030c0", "#30a040"};
    ms_plot_legend (&svg, &p, names, colors, 3);
    char cap[400];
    if (r->icpt->entity_id)
        snprintf (cap, sizeof cap,
                  "Vehicle %s (entity %u), designated as track %u: the distance from its true "
                  "position to guidanced's estimate of it, and to the centre of the sensor's "
                  "footprint; green marks the moments the footprint held it.",
                  r->icpt->marking, r->icpt->entity_id, r->icpt->first_track_id);
    else
        snprintf (cap, sizeof cap,
                  "No vehicle was designated (or its true vehicle is not known): "
                  "nothing to show.");
    s_figure (o, &svg, &p, cap);
}

static void s_fig_gospa (s_out_t *o, s_report_t *r)
{
    double lo = INFINITY, hi = -INFINITY, yhi = 1, ylo = 0;
    s_range (&r->gospa, &lo, &hi, true);
    s_range (&r->gospa, &ylo, &yhi, false);
    ms_str_t svg = {0};
    ms_plot_t p = {.id = "fig-gospa",
                   .title = "Tracking: GOSPA and its parts at each radar scan",
                   .xlabel = "simulation time (s)",
                   .ylabel = "GOSPA and parts, (Σ d^2)^(1/2) (m)",
                   .x0 = lo,
                   .x1 = hi,
                   .y0 = 0,
                   .y1 = yhi * 1.05,
                   .width = S_W,
                   .height = S_H};
    ms_plot_begin (&svg, &p);
    ms_plot_line (&svg, &p, r->gospa_missed.x, r->gospa_missed.y, r->gospa_missed.n, "#d03030", 1.0,
                  "4 2");
    ms_plot_line (&svg, &p, r->gospa_false.x, r->gospa_false.y, r->gospa_false.n, "#f08000", 1.0,
                  "4 2");
    ms_plot_line (&svg, &p, r->gospa_loc.x, r->gospa_loc.y, r->gospa_loc.n, "#2f6fd0", 1.0, "4 2");
    ms_plot_line (&svg, &p, r->gospa.x, r->gospa.y, r->gospa.n, "#000000", 1.5, NULL);
    const char *names[] = {"GOSPA", "localisation", "missed vehicles", "false tracks"};
    const char *colors[] = {"#000000", "#2f6fd0", "#d03030", "#f08000"};
    ms_plot_legend (&svg, &p, names, colors, 4);
    const ms_gospa_mean_t *g = ms_metrics_gospa (r->metrics);
    (void)g;
    char cap[400];
    snprintf (cap, sizeof cap,
              "GOSPA (p = 2, α = 2, cut-off %.0f m) of each of %zu radar scans, with its "
              "parts: the localisation error of the vehicles tracked, the missed vehicles "
              "and the false tracks, each as the square root of its share of GOSPA².",
              MS_METRICS_C_M, r->gospa.n);
    s_figure (o, &svg, &p, cap);
}

static void s_fig_completeness (s_out_t *o, s_report_t *r)
{
    double lo = INFINITY, hi = -INFINITY, yhi = 1, ylo = 0;
    s_range (&r->completeness, &lo, &hi, true);
    s_range (&r->false_tracks, &ylo, &yhi, false);
    s_range (&r->truths, &ylo, &yhi, false);
    ms_str_t svg = {0};
    ms_plot_t p = {.id = "fig-completeness",
                   .title = "Tracking: completeness and false tracks at each scan",
                   .xlabel = "simulation time (s)",
                   .ylabel = "completeness (%) · vehicles · tracks (count)",
                   .x0 = lo,
                   .x1 = hi,
                   .y0 = 0,
                   .y1 = fmax (105, yhi * 1.05),
                   .width = S_W,
                   .height = S_H};
    ms_plot_begin (&svg, &p);
    ms_plot_line (&svg, &p, r->truths.x, r->truths.y, r->truths.n, "#888888", 1.0, "4 2");
    ms_plot_line (&svg, &p, r->false_tracks.x, r->false_tracks.y, r->false_tracks.n, "#f08000", 1.5,
                  NULL);
    ms_plot_line (&svg, &p, r->completeness.x, r->completeness.y, r->completeness.n, "#2f6fd0", 1.5,
                  NULL);
    const char *names[] = {"completeness (%)", "false tracks (count)",
                           "vehicles the radar saw (count)"};
    const char *colors[] = {"#2f6fd0", "#f08000", "#888888"};
    ms_plot_legend (&svg, &p, names, colors, 3);
    s_figure (o, &svg, &p,
              "At each radar scan: the share of the vehicles the radar saw that have a track "
              "(completeness), the tracks that stand for no such vehicle (false tracks), and "
              "how many vehicles the radar saw.");
}

static void s_fig_hist (s_out_t *o, const char *id, const char *title, const char *xlabel,
                        const char *ylabel, double x0, double bin, const uint64_t *counts,
                        int nbins, double xmax, const char *caption)
{
    double yhi = 1;
    for (int i = 0; i < nbins; i++)
        yhi = fmax (yhi, (double)counts[i]);
    ms_str_t svg = {0};
    ms_plot_t p = {.id = id,
                   .title = title,
                   .xlabel = xlabel,
                   .ylabel = ylabel,
                   .x0 = x0,
                   .x1 = xmax,
                   .y0 = 0,
                   .y1 = yhi * 1.05,
                   .width = S_W,
                   .height = S_H};
    ms_plot_begin (&svg, &p);
    for (int i = 0; i < nbins; i++)
        ms_plot_bar (&svg, &p, x0 + i * bin, x0 + (i + 1) * bin, (double)counts[i], "#e0a000");
    s_figure (o, &svg, &p, caption);
}

static void s_fig_pd (s_out_t *o, s_report_t *r)
{
    ms_str_t svg = {0};
    ms_plot_t p = {.id = "fig-pd",
                   .title = "Radar: detected share against true radial velocity",
                   .xlabel = "true radial velocity of the vehicle (m/s)",
                   .ylabel = "detected (%)",
                   .x0 = -S_VR_MAX,
                   .x1 = S_VR_MAX,
                   .y0 = 0,
                   .y1 = 105,
                   .width = S_W,
                   .height = S_H};
    ms_plot_begin (&svg, &p);
    uint64_t seen = 0;
    for (int i = 0; i < S_VR_BINS; i++) {
        seen += r->vr_seen[i];
        if (r->vr_seen[i])
            ms_plot_bar (&svg, &p, -S_VR_MAX + i * S_VR_BIN, -S_VR_MAX + (i + 1) * S_VR_BIN,
                         100.0 * (double)r->vr_detected[i] / (double)r->vr_seen[i], "#2f6fd0");
    }
    char cap[300];
    snprintf (cap, sizeof cap,
              "Of the %llu times a vehicle was in the beam and in view (mti.truth), the share "
              "detected, in %.1f m/s bins of its true radial velocity: the clutter notch is the "
              "dip about 0.",
              (unsigned long long)seen, S_VR_BIN);
    s_figure (o, &svg, &p, cap);
}

static void s_fig_health (s_out_t *o, s_report_t *r)
{
    double span = s_rec_s (r, r->t1_ns);
    ms_str_t svg = {0};
    int lanes = (int)r->nservices + 1;
    ms_plot_t p = {.id = "fig-health",
                   .title = "Services: health state, and messages missed on the bus",
                   .xlabel = "time of the recording (wall-clock s)",
                   .ylabel = "service",
                   .x0 = 0,
                   .x1 = span > 0 ? span : 1,
                   .y0 = 0,
                   .y1 = lanes,
                   .width = S_W,
                   .height = 80 + 26 * lanes,
                   .no_yticks = true};
    ms_plot_begin (&svg, &p);
    static const char *const colors[] = {"#cccccc", "#f0d060", "#30a040", "#e07020", "#888888"};
    for (size_t i = 0; i < r->nservices; i++) {
        const s_service_t *s = &r->services[i];
        double y = (double)(lanes - (int)i); // the lane from y - 1 to y
        for (size_t k = 0; k < s->state.n; k++) {
            double t0 = s->state.x[k], t1 = k + 1 < s->state.n ? s->state.x[k + 1] : span;
            int st = (int)s->state.y[k];
            const char *name = cgs_msg_enum_short (&cgs__service_state__descriptor, st, "?");
            char title[128];
            snprintf (title, sizeof title, "%s %s from %.1f s", s->instance, name, t0);
            ms_plot_band (&svg, &p, t0, t1, y - 0.8, y - 0.2, colors[st >= 0 && st < 5 ? st : 0],
                          title);
        }
        ms_plot_text (&svg, &p, 0, y - 0.65, "start", s->instance);
    }
    // Messages missed so far, scaled into the bottom lane.
    double most = fmax (1, (double)r->gaps_total);
    s_xy_t g = {0};
    s_xy_add (&g, 0, 0);
    for (size_t i = 0; i < r->gaps.n; i++)
        s_xy_add (&g, r->gaps.x[i], 0.1 + 0.7 * r->gaps.y[i] / most);
    s_xy_add (&g, p.x1, g.y[g.n - 1]);
    ms_plot_line (&svg, &p, g.x, g.y, g.n, "#d03030", 1.5, NULL);
    s_xy_free (&g);
    char lab[96];
    snprintf (lab, sizeof lab, "messages missed (%llu in all)", (unsigned long long)r->gaps_total);
    ms_plot_text (&svg, &p, p.x1, 0.85, "end", lab);
    const char *names[] = {"running", "degraded", "starting", "stopping"};
    const char *cs[] = {"#30a040", "#e07020", "#f0d060", "#888888"};
    ms_plot_legend (&svg, &p, names, cs, 4);
    s_figure (o, &svg, &p,
              "Each service's state as its health messages said (a lane each), and at the "
              "bottom the messages missed so far, counted from the sequence numbers of every "
              "publisher on every topic as the recorder received them.");
}

/* ---- the page -------------------------------------------------------------------------- */

static void s_row (ms_str_t *h, const char *key, const char *fmt, ...)
    __attribute__ ((format (printf, 3, 4)));
static void s_row (ms_str_t *h, const char *key, const char *fmt, ...)
{
    char v[512];
    va_list ap;
    va_start (ap, fmt);
    vsnprintf (v, sizeof v, fmt, ap);
    va_end (ap);
    ms_str_printf (h, "<tr><th>");
    ms_str_escaped (h, key);
    ms_str_printf (h, "</th><td>");
    ms_str_escaped (h, v);
    ms_str_printf (h, "</td></tr>\n");
}

static const char s_style[] =
    "body{font:14px/1.4 'DejaVu Sans',Verdana,sans-serif;margin:24px auto;max-width:960px;"
    "color:#222}h1{font-size:22px}h2{font-size:18px;margin-top:28px;border-bottom:1px solid "
    "#ccc}table{border-collapse:collapse;margin:8px 0}th,td{padding:2px 10px;text-align:left;"
    "border-bottom:1px solid #eee;vertical-align:top}th{font-weight:600}figure{margin:16px 0}"
    "figcaption{font-size:13px;color:#444;max-width:900px}td.n{text-align:right}"
    ".imaged{color:#208030;font-weight:bold}.missed{color:#b02020;font-weight:bold}";

static void s_json_member (ms_str_t *h, json_object *o, const char *key, const char *label,
                           const char *unit)
{
    json_object *v = NULL;
    if (!json_object_object_get_ex (o, key, &v))
        return;
    const char *text = v ? json_object_get_string (v) : "—";
    char buf[160];
    snprintf (buf, sizeof buf, "%s%s%s", text ? text : "—", unit && v ? " " : "",
              unit && v ? unit : "");
    s_row (h, label, "%s", buf);
}

static int s_write (s_report_t *r, const char *dir, json_object *summary)
{
    ms_str_t h = {0};
    s_out_t o = {.html = &h, .dir = dir};
    const ms_icpt_t *ic = r->icpt;
    ms_str_printf (&h, "<!DOCTYPE html>\n<html xmlns=\"http://www.w3.org/1999/xhtml\" "
                       "lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n<title>After-action "
                       "report: ");
    ms_str_escaped (&h, r->file);
    ms_str_printf (&h, "</title>\n<style>%s</style>\n</head>\n<body>\n", s_style);
    ms_str_printf (&h, "<h1>After-action report</h1>\n<table id=\"recording\">\n");
    s_row (&h, "recording", "%s", r->file);
    time_t t0 = (time_t)(r->t0_ns / 1000000000u);
    char when[64];
    strftime (when, sizeof when, "%Y-%m-%d %H:%M:%S UTC", gmtime (&t0));
    s_row (&h, "recorded", "%s, %.1f s of wall-clock time", when, s_rec_s (r, r->t1_ns));
    s_row (&h, "exercise", "%u", r->exercise_id);
    s_row (&h, "simulation time", "%.1f s to %.1f s", r->sim_first, r->sim_last);
    s_row (&h, "messages", "%llu (%llu not decoded)", (unsigned long long)r->messages,
           (unsigned long long)r->undecoded);
    ms_str_printf (&h, "</table>\n");

    // The intercept, in words, then its figures.
    ms_str_printf (&h, "<h2 id=\"intercept\">The intercept</h2>\n<p>");
    if (!ic->designated) {
        ms_str_printf (&h, "Nothing was designated in this recording.");
    } else {
        const char *state =
            cgs_msg_enum_short (&cgs__intercept_state__descriptor, (int)ic->desig_state, "?");
        char buf[600];
        snprintf (buf, sizeof buf,
                  "Track %u was designated at %.1f s of simulation time%s%s%s. The intercept "
                  "ended %s%s after %u re-plan%s. ",
                  ic->first_track_id, ic->score.designation_s, ic->entity_id ? ": it was " : "",
                  ic->entity_id ? ic->marking : "",
                  ic->entity_id ? " (the vehicle its hits came from)" : "", state,
                  ic->final ? "" : " (still under way when the recording ended)", ic->replans,
                  ic->replans == 1 ? "" : "s");
        ms_str_escaped (&h, buf);
        if (ic->other_entity_id) {
            snprintf (buf, sizeof buf,
                      "From %.1f s the designated track, or one that took over from it, "
                      "followed another vehicle: %s. ",
                      ic->other_since_s, ic->other_marking);
            ms_str_escaped (&h, buf);
        }
        if (ic->score.imaged)
            ms_str_printf (&h,
                           "<span class=\"imaged\">The vehicle was imaged</span>: it entered "
                           "the sensor's footprint at %.1f s and stayed in it %.1f s in all.",
                           ic->score.first_inside_s, ic->score.inside_s);
        else
            ms_str_printf (&h,
                           "<span class=\"missed\">The vehicle was not imaged</span>: it came "
                           "no closer than %.0f m to the footprint's centre.",
                           ic->score.closest_m);
    }
    ms_str_printf (&h, "</p>\n<table id=\"intercept-figures\">\n");
    json_object *icj = summary;
    s_json_member (&h, icj, "designated", "designated", NULL);
    s_json_member (&h, icj, "track_id", "track", NULL);
    s_json_member (&h, icj, "target_marking", "vehicle", NULL);
    s_json_member (&h, icj, "target_entity_id", "vehicle's entity id", NULL);
    s_json_member (&h, icj, "follows_entity_id", "another vehicle followed", NULL);
    s_json_member (&h, icj, "designation_time_s", "designated at", "s");
    s_json_member (&h, icj, "final_state", "final state", NULL);
    s_json_member (&h, icj, "replans", "re-plans", NULL);
    s_json_member (&h, icj, "imaged", "imaged", NULL);
    s_json_member (&h, icj, "time_in_footprint_s", "time in the footprint", "s");
    s_json_member (&h, icj, "closest_approach_m", "closest to the footprint's centre", "m");
    s_json_member (&h, icj, "designation_to_overflight_s", "designation to overflight", "s");
    ms_str_printf (&h, "</table>\n");
    if (r->marks.n) {
        ms_str_printf (&h, "<table id=\"marks\">\n<tr><th>time (s)</th><th>UAV</th><th>what</th>"
                           "<th></th></tr>\n");
        for (size_t i = 0; i < r->marks.n; i++) {
            const ms_mark_t *m = &r->marks.marks[i];
            ms_str_printf (&h, "<tr><td class=\"n\">%.1f</td><td class=\"n\">%u</td><td>", m->t_s,
                           m->uav_id);
            ms_str_escaped (&h, m->kind);
            ms_str_printf (&h, "</td><td>");
            ms_str_escaped (&h, m->text);
            ms_str_printf (&h, "</td></tr>\n");
        }
        ms_str_printf (&h, "</table>\n");
    }
    s_fig_timeline (&o, r);
    s_fig_target (&o, r);
    s_fig_map (&o, r);

    ms_str_printf (&h, "<h2 id=\"tracking\">Tracking</h2>\n<table id=\"tracking-figures\">\n");
    json_object *tr = NULL;
    if (json_object_object_get_ex (summary, "tracking", &tr) && tr) {
        json_object_object_foreach (tr, k, v)
        {
            s_row (&h, k, "%s", v ? json_object_get_string (v) : "—");
        }
    }
    ms_str_printf (&h, "</table>\n");
    s_fig_gospa (&o, r);
    s_fig_completeness (&o, r);

    ms_str_printf (&h, "<h2 id=\"radar\">The radar</h2>\n");
    char cap[300];
    snprintf (cap, sizeof cap, "The %llu MTI hits by measured slant range, in 1 km bins.",
              (unsigned long long)r->nhits);
    s_fig_hist (&o, "fig-range", "Radar: hits against range", "slant range (km)", "hits (count)", 0,
                1, r->range_hist, S_RANGE_BINS,
                fmin (S_RANGE_BINS, ceil (r->max_range_m / S_RANGE_BIN_M) + 1), cap);
    snprintf (cap, sizeof cap,
              "The MTI hits by measured radial velocity, in %.1f m/s bins: none about 0, where "
              "the clutter notch removes them.",
              S_VR_BIN);
    s_fig_hist (&o, "fig-velocity", "Radar: hits against radial velocity",
                "measured radial velocity (m/s)", "hits (count)", -S_VR_MAX, S_VR_BIN, r->vr_hits,
                S_VR_BINS, S_VR_MAX, cap);
    s_fig_pd (&o, r);

    ms_str_printf (&h, "<h2 id=\"health\">Services and the bus</h2>\n");
    s_fig_health (&o, r);
    ms_str_printf (&h, "<table id=\"streams\">\n<tr><th>publisher</th><th>topic</th><th>messages"
                       "</th><th>missed</th><th>restarts</th></tr>\n");
    for (size_t i = 0; i < r->nstreams; i++) {
        const s_stream_t *s = &r->streams[i];
        ms_str_printf (&h, "<tr><td>");
        ms_str_escaped (&h, s->source);
        ms_str_printf (&h, "</td><td>");
        ms_str_escaped (&h, s->topic);
        ms_str_printf (&h,
                       "</td><td class=\"n\">%llu</td><td class=\"n\">%llu</td><td "
                       "class=\"n\">%llu</td></tr>\n",
                       (unsigned long long)s->messages, (unsigned long long)s->gaps,
                       (unsigned long long)s->restarts);
    }
    ms_str_printf (&h, "</table>\n<table id=\"errors\">\n");
    for (size_t i = 0; i < r->nservices; i++)
        if (*r->services[i].last_error)
            s_row (&h, r->services[i].instance, "last error: %s", r->services[i].last_error);
    ms_str_printf (&h, "</table>\n<p>Made by <code>mscgs report</code> from the recording "
                       "alone; the numbers are those <code>mscgs run</code> writes in "
                       "summary.json, computed again from the recorded messages.</p>\n"
                       "</body>\n</html>\n");
    char path[PATH_MAX];
    snprintf (path, sizeof path, "%s/report.html", dir);
    FILE *f = h.oom ? NULL : fopen (path, "w");
    bool written = f && fwrite (h.s, 1, h.len, f) == h.len;
    if (f && fclose (f) != 0)
        written = false;
    if (!written) {
        fprintf (stderr, "mscgs report: cannot write %s: %s\n", path,
                 h.oom ? "out of memory" : strerror (errno));
        ms_str_free (&h);
        return -1;
    }
    ms_str_free (&h);
    fprintf (stderr, "mscgs report: %s: %d figures (PNG beside it)\n", path, o.figure);
    return o.failed ? -1 : 0;
}

int ms_report_main (int argc, char **argv)
{
    const char *out = NULL;
    const ms_opt_t opts[] = {
        {.name = "out",
         .letter = 'o',
         .value = "DIR",
         .help = "the report's folder (default FILE's folder/report)",
         .str = &out},
        MS_OPTS_HELP,
        MS_OPTS_END,
    };
    const ms_cmd_t spec = {
        .name = "report",
        .operands = "FILE",
        .missing = "which recording? (an MCAP file of `mscgs record`)",
        .about = "The after-action review of a recording: DIR/report.html (one file, the charts\n"
                 "inline, opens offline), DIR/fig-*.png (each chart) and DIR/report.json (the\n"
                 "intercept and tracking figures of `mscgs run`'s summary.json, from the\n"
                 "recording).\n",
        .opts = opts,
    };
    int nargs = ms_opts_parse (&spec, argc, argv);
    if (nargs < 0)
        return ms_opts_exit_code (nargs);
    if (nargs > 1) {
        fprintf (stderr, "mscgs report: one recording at a time\n");
        return 2;
    }
    static s_report_t r;
    memset (&r, 0, sizeof r);
    r.file = argv[1];
    char dirbuf[PATH_MAX];
    if (!out) {
        const char *slash = strrchr (r.file, '/');
        snprintf (dirbuf, sizeof dirbuf, "%.*sreport", slash ? (int)(slash - r.file + 1) : 0,
                  r.file);
        out = dirbuf;
    }
    if (mkdir (out, 0755) < 0 && errno != EEXIST) {
        fprintf (stderr, "mscgs report: cannot make %s: %s\n", out, strerror (errno));
        return 1;
    }
    int rc = 1;
    r.icpt = calloc (1, sizeof *r.icpt);
    if (!r.icpt)
        return 1;
    ms_icpt_init (r.icpt);
    if (!(r.metrics = ms_metrics_new (r.icpt))) {
        free (r.icpt);
        return 1;
    }
    ms_metrics_on_scan (r.metrics, s_on_scan, &r);
    json_object *summary = NULL;
    if (s_read (&r) < 0)
        goto done;
    summary = ms_icpt_json (r.icpt);
    json_object *tracking = summary ? ms_metrics_json (r.metrics) : NULL;
    if (!summary || !tracking) {
        fprintf (stderr, "mscgs report: out of memory\n");
        goto done;
    }
    cgs_json_add (summary, "tracking", tracking);
    char path[PATH_MAX];
    snprintf (path, sizeof path, "%s/report.json", out);
    FILE *f = fopen (path, "w");
    bool written =
        f &&
        cgs_json_print (f, summary, JSON_C_TO_STRING_PRETTY | JSON_C_TO_STRING_SPACED, "\n") >= 0;
    if (f && fclose (f) != 0)
        written = false;
    if (!written) {
        fprintf (stderr, "mscgs report: cannot write %s: %s\n", path, strerror (errno));
        goto done;
    }
    rc = s_write (&r, out, summary) < 0 ? 1 : 0;
done:
    json_object_put (summary);
    ms_metrics_destroy (&r.metrics);
    free (r.icpt);
    s_things_free (&r.vehicles);
    s_things_free (&r.uavs);
    s_things_free (&r.tracks);
    s_xy_t *all[] = {&r.hits,         &r.track_error, &r.footprint_distance,
                     &r.inside,       &r.gospa,       &r.gospa_loc,
                     &r.gospa_missed, &r.gospa_false, &r.completeness,
                     &r.false_tracks, &r.truths,      &r.gaps};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        s_xy_free (all[i]);
    for (size_t i = 0; i < r.nservices; i++)
        s_xy_free (&r.services[i].state);
    free (r.streams);
    free (r.phases);
    ms_marks_clear (&r.marks);
    return rc;
}
