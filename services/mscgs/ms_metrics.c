/* ms_metrics — tracking quality against ground truth (see ms_metrics.h). */
#include "ms_metrics.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define S_RADARS_MAX 8

/* What is known of one ground vehicle. */
typedef struct {
    uint32_t id;
    bool ground, active;
    bool friendly, hostile;   // its force
    bool transponder;         // can answer a BCIS interrogation
    double e, n, ve, vn, t_s; // latest true state
    bool detected;            // some radar has had a hit from it
    uint32_t visible_radar;   // the radar that last saw it in its beam, visible
    uint32_t visible_scan;    // in that radar's scan of this number
} s_truth_t;

/* One radar's scan being assembled from its `track` batches. */
typedef struct {
    uint32_t uav_id;
    uint32_t scan;
    uint32_t batches; // received of the scan
    ms_siap_track_t *tracks;
    size_t ntracks, cap;
} s_radar_t;

struct ms_metrics {
    ms_icpt_t *ic;
    s_truth_t *truths;
    size_t ntruths, truthcap;
    s_radar_t radars[S_RADARS_MAX];
    size_t nradars;
    ms_siap_t *siap;
    ms_gospa_mean_t gospa;
    uint64_t failures;
    ms_metrics_scan_fn *scan_fn;
    void *scan_arg;
    // Scratch.
    ms_siap_truth_t *st;
    ms_point_t *x, *y;
    size_t scratch;
};

ms_metrics_t *ms_metrics_new (ms_icpt_t *ic)
{
    ms_metrics_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->ic = ic;
    if (!(self->siap = ms_siap_new ()))
        ms_metrics_destroy (&self); // NULL
    return self;
}

void ms_metrics_destroy (ms_metrics_t **self_p)
{
    ms_metrics_t *self = *self_p;
    if (!self)
        return;
    ms_siap_destroy (&self->siap);
    free (self->truths);
    for (size_t i = 0; i < self->nradars; i++)
        free (self->radars[i].tracks);
    free (self->st);
    free (self->x);
    free (self->y);
    free (self);
    *self_p = NULL;
}

ms_siap_t *ms_metrics_siap (ms_metrics_t *self)
{
    return self->siap;
}

const ms_gospa_mean_t *ms_metrics_gospa (const ms_metrics_t *self)
{
    return &self->gospa;
}

uint64_t ms_metrics_failures (const ms_metrics_t *self)
{
    return self->failures;
}

static s_truth_t *s_truth (ms_metrics_t *self, uint32_t id, bool create)
{
    for (size_t i = 0; i < self->ntruths; i++)
        if (self->truths[i].id == id)
            return &self->truths[i];
    if (!create)
        return NULL;
    if (self->ntruths == self->truthcap) {
        size_t cap = self->truthcap ? self->truthcap * 2 : 64;
        s_truth_t *n = realloc (self->truths, cap * sizeof *n);
        if (!n)
            return NULL;
        self->truths = n;
        self->truthcap = cap;
    }
    s_truth_t *t = &self->truths[self->ntruths++];
    memset (t, 0, sizeof *t);
    t->id = id;
    return t;
}

void ms_metrics_on_entity (void *arg, const char *topic, const ProtobufCMessage *msg,
                           const Cgs__Header *hdr)
{
    (void)topic;
    ms_metrics_t *self = arg;
    const Cgs__EntityBatch *b = (const Cgs__EntityBatch *)msg;
    for (size_t i = 0; i < b->n_entities; i++) {
        const Cgs__Entity *en = b->entities[i];
        if (!en->entity_id || !en->position || !en->velocity || !isfinite (en->position->east_m) ||
            !isfinite (en->position->north_m) || !isfinite (en->velocity->east_mps) ||
            !isfinite (en->velocity->north_mps) || !isfinite (hdr->sim_time_s))
            continue;
        s_truth_t *t = s_truth (self, en->entity_id, true);
        if (!t) {
            self->failures++;
            continue;
        }
        t->ground = en->kind != CGS__ENTITY_KIND__ENTITY_KIND_AIR;
        t->active = en->active;
        t->friendly = en->force == CGS__FORCE__FORCE_FRIENDLY;
        t->hostile = en->force == CGS__FORCE__FORCE_HOSTILE;
        t->transponder = en->bcis_transponder;
        t->e = en->position->east_m;
        t->n = en->position->north_m;
        t->ve = en->velocity->east_mps;
        t->vn = en->velocity->north_mps;
        t->t_s = hdr->sim_time_s;
    }
}

void ms_metrics_on_mti_truth (void *arg, const char *topic, const ProtobufCMessage *msg,
                              const Cgs__Header *hdr)
{
    (void)topic, (void)hdr;
    ms_metrics_t *self = arg;
    const Cgs__MtiTruth *m = (const Cgs__MtiTruth *)msg;
    for (size_t i = 0; i < m->n_items; i++) {
        const Cgs__MtiTruthItem *it = m->items[i];
        if (!it->entity_id)
            continue;
        s_truth_t *t = s_truth (self, it->entity_id, true);
        if (!t) {
            self->failures++;
            continue;
        }
        if (it->detected && it->hit_id)
            t->detected = true;
        if (it->in_beam && it->visible) {
            t->visible_radar = m->uav_id;
            t->visible_scan = m->scan_number;
        }
    }
}

static s_radar_t *s_radar (ms_metrics_t *self, uint32_t uav_id)
{
    for (size_t i = 0; i < self->nradars; i++)
        if (self->radars[i].uav_id == uav_id)
            return &self->radars[i];
    if (self->nradars == S_RADARS_MAX)
        return NULL;
    s_radar_t *r = &self->radars[self->nradars++];
    memset (r, 0, sizeof *r);
    r->uav_id = uav_id;
    return r;
}

static int s_reserve (ms_metrics_t *self, size_t n)
{
    if (n <= self->scratch)
        return 0;
    size_t cap = n * 2;
    ms_siap_truth_t *st = realloc (self->st, cap * sizeof *st);
    if (st)
        self->st = st;
    ms_point_t *x = realloc (self->x, cap * sizeof *x);
    if (x)
        self->x = x;
    ms_point_t *y = realloc (self->y, cap * sizeof *y);
    if (y)
        self->y = y;
    if (!st || !x || !y)
        return -ENOMEM;
    self->scratch = cap;
    return 0;
}

/* The vehicle tr follows is present but the radar could not see it in this
 * scan (outside the swept beam, or hidden by the terrain), and tr lies
 * within the gate of it: a track holding an unseen vehicle. */
static bool s_unseen (ms_metrics_t *self, const s_radar_t *r, const ms_siap_track_t *tr, double t_s)
{
    const s_truth_t *t = s_truth (self, tr->truth_id, false);
    if (!t || !t->ground || !t->active || !t->detected ||
        (t->visible_radar == r->uav_id && t->visible_scan == r->scan))
        return false;
    double dt = t_s - t->t_s;
    return hypot (t->e + t->ve * dt - tr->pos.e, t->n + t->vn * dt - tr->pos.n) <= MS_METRICS_C_M;
}

/* The radar's scan is complete: its truths and tracks to the figures. */
static void s_scan (ms_metrics_t *self, s_radar_t *r, double t_s)
{
    if (s_reserve (self, self->ntruths > r->ntracks ? self->ntruths : r->ntracks) < 0) {
        self->failures++;
        return;
    }
    size_t nx = 0;
    for (size_t i = 0; i < self->ntruths; i++) {
        const s_truth_t *t = &self->truths[i];
        if (!t->ground || !t->active || !t->detected || t->visible_radar != r->uav_id ||
            t->visible_scan != r->scan)
            continue;
        double dt = t_s - t->t_s;
        ms_point_t p = {t->e + t->ve * dt, t->n + t->vn * dt};
        // Only a friend with a transponder can be identified (by its entity id,
        // which its BCIS responder reports).
        self->st[nx] = (ms_siap_truth_t){
            .id = t->id,
            .pos = p,
            .identity = t->friendly && t->transponder ? t->id : 0,
            .hostile = t->hostile,
        };
        self->x[nx++] = p;
    }
    for (size_t k = 0; k < r->ntracks; k++) {
        ms_siap_track_t *tr = &r->tracks[k];
        self->y[k] = tr->pos;
        // The association holds only for a truth of this scan within the gate.
        bool ok = false;
        for (size_t i = 0; tr->truth_id && i < nx && !ok; i++)
            ok = self->st[i].id == tr->truth_id &&
                 hypot (self->st[i].pos.e - tr->pos.e, self->st[i].pos.n - tr->pos.n) <=
                     MS_METRICS_C_M;
        tr->truth_unseen = !ok && tr->truth_id && s_unseen (self, r, tr, t_s);
        if (!ok)
            tr->truth_id = 0;
    }
    ms_gospa_t g;
    if (ms_gospa (self->x, nx, self->y, r->ntracks, MS_METRICS_C_M, MS_METRICS_P, &g, NULL) < 0 ||
        ms_gospa_mean_add (&self->gospa, &g) < 0 ||
        ms_siap_add (self->siap, t_s, self->st, nx, r->tracks, r->ntracks) < 0) {
        self->failures++;
        return;
    }
    if (!self->scan_fn)
        return;
    ms_metrics_scan_t sc = {
        .uav_id = r->uav_id, .t_s = t_s, .gospa = g, .truths = nx, .tracks = r->ntracks};
    for (size_t i = 0; i < nx; i++) {
        bool tracked = false;
        for (size_t k = 0; k < r->ntracks && !tracked; k++)
            tracked = r->tracks[k].truth_id == self->st[i].id;
        sc.tracked_truths += tracked;
    }
    for (size_t k = 0; k < r->ntracks; k++)
        sc.unassociated += r->tracks[k].truth_id == 0;
    self->scan_fn (self->scan_arg, &sc);
}

void ms_metrics_on_scan (ms_metrics_t *self, ms_metrics_scan_fn *fn, void *arg)
{
    self->scan_fn = fn;
    self->scan_arg = arg;
}

void ms_metrics_on_track (void *arg, const char *topic, const ProtobufCMessage *msg,
                          const Cgs__Header *hdr)
{
    (void)topic;
    ms_metrics_t *self = arg;
    const Cgs__TrackBatch *b = (const Cgs__TrackBatch *)msg;
    s_radar_t *r = s_radar (self, b->uav_id);
    if (!r || !isfinite (hdr->sim_time_s))
        return;
    if (b->batch_index == 0 || b->scan_number != r->scan) {
        r->scan = b->scan_number;
        r->batches = 0;
        r->ntracks = 0;
    }
    r->batches++;
    for (size_t i = 0; i < b->n_tracks; i++) {
        const Cgs__Track *tr = b->tracks[i];
        if ((tr->status != CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED &&
             tr->status != CGS__TRACK_STATUS__TRACK_STATUS_COASTING) ||
            !tr->position || !isfinite (tr->position->east_m) || !isfinite (tr->position->north_m))
            continue;
        if (r->ntracks == r->cap) {
            size_t cap = r->cap ? r->cap * 2 : 64;
            ms_siap_track_t *n = realloc (r->tracks, cap * sizeof *n);
            if (!n) {
                self->failures++;
                return;
            }
            r->tracks = n;
            r->cap = cap;
        }
        r->tracks[r->ntracks++] = (ms_siap_track_t){
            .id = tr->track_id,
            .truth_id = ms_icpt_track_entity (self->ic, b->uav_id, tr),
            .pos = {tr->position->east_m, tr->position->north_m},
            .claimed_id = tr->friendly_id,
        };
    }
    if (r->batches == (b->batch_count ? b->batch_count : 1))
        s_scan (self, r, hdr->sim_time_s);
}

void ms_metrics_print (ms_metrics_t *self, FILE *f)
{
    ms_siap_result_t r;
    ms_siap_result (self->siap, &r);
    ms_gospa_avg_t g;
    ms_gospa_mean_finish (&self->gospa, &g);
    fprintf (f, "Tracking (against ground truth, %zu radar scans)\n", r.scans);
    if (r.scans == 0) {
        fprintf (f, "  no radar scan with tracks was seen\n");
        return;
    }
    fprintf (f,
             "  GOSPA             %.1f m mean per scan (c = %.0f m, p = 2): localisation %.0f, "
             "missed %.0f, false %.0f m^2\n",
             g.distance, MS_METRICS_C_M, g.localisation, g.missed, g.false_);
    fprintf (f,
             "  completeness      %.3f  ambiguity %.3f  spuriousness %.3f (%.3f tracks of "
             "vehicles the radar could not see)\n",
             r.completeness, r.ambiguity, r.spuriousness, r.spuriousness_unseen);
    fprintf (f, "  position accuracy %.1f m (mean, associated tracks)\n", r.position_accuracy_m);
    fprintf (f,
             "  continuity        %.2f id swaps and %.2f breaks per truth-hour; %.2f false "
             "confirmed tracks per hour\n",
             r.swaps_per_truth_hour, r.breaks_per_truth_hour, r.false_tracks_per_hour);
    fprintf (f,
             "  identification    ID completeness %.3f  ID correctness %.3f  ID wrong %.3f; "
             "hostile marked friendly %zu (track-scans)\n",
             r.id_completeness, r.id_correctness, r.id_wrong_fraction, r.id.hostile_marked);
}

json_object *ms_metrics_json (ms_metrics_t *self)
{
    ms_siap_result_t r;
    ms_siap_result (self->siap, &r);
    ms_gospa_avg_t g;
    ms_gospa_mean_finish (&self->gospa, &g);
    json_object *o = json_object_new_object ();
    if (!o)
        return NULL;
    cgs_json_add (o, "scans", json_object_new_uint64 (r.scans));
    const struct {
        const char *key;
        double v;
    } f[] = {
        {"gospa_m", g.distance},
        {"gospa_localisation_m2", g.localisation},
        {"gospa_missed_m2", g.missed},
        {"gospa_false_m2", g.false_},
        {"completeness", r.completeness},
        {"ambiguity", r.ambiguity},
        {"spuriousness", r.spuriousness},
        {"spuriousness_unseen", r.spuriousness_unseen},
        {"position_accuracy_m", r.position_accuracy_m},
        {"swaps_per_truth_hour", r.swaps_per_truth_hour},
        {"breaks_per_truth_hour", r.breaks_per_truth_hour},
        {"false_tracks_per_hour", r.false_tracks_per_hour},
        {"id_completeness", r.id_completeness},
        {"id_correctness", r.id_correctness},
        {"id_wrong_fraction", r.id_wrong_fraction},
    };
    for (size_t i = 0; i < sizeof f / sizeof f[0]; i++)
        cgs_json_add (o, f[i].key, cgs_json_fixed (f[i].v, 4));
    cgs_json_add (o, "id_hostile_marked", json_object_new_uint64 (r.id.hostile_marked));
    return o;
}
