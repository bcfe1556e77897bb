/* ms_siap — SIAP-style figures over runs of scans (see ms_siap.h).
 *
 * Per-truth and per-track memory of the run under way lives in two
 * open-addressing hash tables keyed by id (0 marks an empty slot, which is
 * why ids must be non-zero), grown before a scan changes anything so a
 * failed scan leaves the accumulator as it was. */
#include "ms_siap.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

/* A truth or a track of the run under way. */
typedef struct {
    uint32_t id;           // 0: empty slot
    uint32_t last_primary; // truths: primary track at its last tracked scan, 0: none yet
    uint32_t lowest;       // truths, this scan: lowest associated track id
    uint32_t n_assoc;      // truths, this scan: tracks associated to it
    uint64_t stamp;        // truths: serial of the last scan it was present at
    size_t at;             // truths, this scan: its index in the caller's array
    bool tracked;          // truths: had a track at its last presence; tracks: ever associated
    bool keep_last;        // truths, this scan: last_primary is associated again
} s_rec_t;

typedef struct {
    s_rec_t *slots;
    size_t cap;   // slots, a power of two (or 0), at most half full
    size_t count; // slots in use
} s_table_t;

/* The sums merge pools. */
typedef struct {
    size_t scans, truth_scans, tracked_truth_scans, track_scans, associated_track_scans;
    size_t unknown_truth_scans, unseen_track_scans, swaps, breaks;
    size_t runs, tracks, false_tracks; // of closed runs only
    double position_error_m, truth_time_s, run_time_s;
    ms_siap_id_t id;
} s_sums_t;

struct ms_siap {
    s_table_t truths, tracks; // the run under way
    uint32_t *ids;            // one scan's ids, sorted to find repeats
    size_t ids_cap;
    uint64_t serial;  // scans fed over the accumulator's life (the stamps)
    size_t run_scans; // scans of the run under way
    double last_t_s;  // time of the run's last scan, seconds
    s_sums_t sums;    // every scan and run, the run under way included
};

// Murmur3's finaliser: sequential ids spread over the table.
static size_t s_hash (uint32_t id)
{
    id ^= id >> 16;
    id *= 0x85ebca6bu;
    id ^= id >> 13;
    id *= 0xc2b2ae35u;
    id ^= id >> 16;
    return id;
}

static s_rec_t *s_slot (const s_table_t *t, uint32_t id)
{
    size_t mask = t->cap - 1;
    for (size_t i = s_hash (id) & mask;; i = (i + 1) & mask)
        if (t->slots[i].id == id || t->slots[i].id == 0)
            return &t->slots[i];
}

static s_rec_t *s_find (const s_table_t *t, uint32_t id)
{
    if (t->cap == 0)
        return NULL;
    s_rec_t *r = s_slot (t, id);
    return r->id ? r : NULL;
}

// The record of id, added zeroed if new; room must have been reserved.
static s_rec_t *s_insert (s_table_t *t, uint32_t id)
{
    s_rec_t *r = s_slot (t, id);
    if (r->id == 0) {
        assert ((t->count + 1) * 2 <= t->cap);
        *r = (s_rec_t){.id = id};
        t->count++;
    }
    return r;
}

// Room for `more` new ids; the table is unchanged on failure.
static int s_reserve (s_table_t *t, size_t more)
{
    size_t need = t->count + more;
    if (need * 2 <= t->cap)
        return 0;
    size_t cap = t->cap ? t->cap : 64;
    while (need * 2 > cap) {
        if (cap > SIZE_MAX / 2 / sizeof (s_rec_t))
            return -ENOMEM;
        cap *= 2;
    }
    s_table_t grown = {.slots = calloc (cap, sizeof (s_rec_t)), .cap = cap};
    if (!grown.slots)
        return -ENOMEM;
    for (size_t i = 0; i < t->cap; i++)
        if (t->slots[i].id)
            *s_insert (&grown, t->slots[i].id) = t->slots[i];
    grown.count = t->count;
    free (t->slots);
    *t = grown;
    return 0;
}

static void s_clear (s_table_t *t)
{
    if (t->slots)
        memset (t->slots, 0, t->cap * sizeof (s_rec_t));
    t->count = 0;
}

static size_t s_never_associated (const s_table_t *t)
{
    size_t n = 0;
    for (size_t i = 0; i < t->cap; i++)
        if (t->slots[i].id && !t->slots[i].tracked)
            n++;
    return n;
}

ms_siap_t *ms_siap_new (void)
{
    return calloc (1, sizeof (ms_siap_t));
}

void ms_siap_destroy (ms_siap_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    ms_siap_t *self = *self_p;
    free (self->truths.slots);
    free (self->tracks.slots);
    free (self->ids);
    free (self);
    *self_p = NULL;
}

static int s_cmp_id (const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

// Whether ids[n] (in self->ids, sorted here) has no 0 and no repeat.
static bool s_ids_valid (uint32_t *ids, size_t n)
{
    if (n == 0)
        return true; // (ids may be NULL then: qsort must not see it)
    qsort (ids, n, sizeof *ids, s_cmp_id);
    for (size_t i = 0; i < n; i++)
        if (ids[i] == 0 || (i > 0 && ids[i] == ids[i - 1]))
            return false;
    return true;
}

static bool s_finite (ms_point_t p)
{
    return isfinite (p.e) && isfinite (p.n);
}

// Count a track claiming `claimed` (0: nothing) associated to truth t.
static void s_identity (ms_siap_id_t *c, const ms_siap_truth_t *t, uint32_t claimed)
{
    if (t->identity) {
        c->identifiable++;
        c->identifiable_marked += claimed != 0;
    }
    if (!claimed)
        return;
    c->marked++;
    if (claimed == t->identity) {
        c->correct++;
    } else {
        c->wrong++;
        c->hostile_marked += t->hostile;
    }
}

static void s_identity_pool (ms_siap_id_t *d, const ms_siap_id_t *s)
{
    d->identifiable += s->identifiable;
    d->identifiable_marked += s->identifiable_marked;
    d->marked += s->marked;
    d->correct += s->correct;
    d->wrong += s->wrong;
    d->hostile_marked += s->hostile_marked;
}

int ms_siap_add (ms_siap_t *self, double t_s, const ms_siap_truth_t *truths, size_t n_truths,
                 const ms_siap_track_t *tracks, size_t n_tracks)
{
    assert (self);
    if ((n_truths && !truths) || (n_tracks && !tracks) || !isfinite (t_s))
        return -EINVAL;
    if (self->run_scans > 0 && !(t_s > self->last_t_s))
        return -EINVAL;
    for (size_t i = 0; i < n_truths; i++)
        if (!s_finite (truths[i].pos))
            return -EINVAL;
    for (size_t j = 0; j < n_tracks; j++)
        if (!s_finite (tracks[j].pos))
            return -EINVAL;
    size_t n_ids = n_truths > n_tracks ? n_truths : n_tracks;
    if (n_ids > self->ids_cap) {
        uint32_t *ids = realloc (self->ids, n_ids * sizeof *ids);
        if (!ids)
            return -ENOMEM;
        self->ids = ids;
        self->ids_cap = n_ids;
    }
    for (size_t i = 0; i < n_truths; i++)
        self->ids[i] = truths[i].id;
    if (!s_ids_valid (self->ids, n_truths))
        return -EINVAL;
    for (size_t j = 0; j < n_tracks; j++)
        self->ids[j] = tracks[j].id;
    if (!s_ids_valid (self->ids, n_tracks))
        return -EINVAL;
    if (s_reserve (&self->truths, n_truths) < 0 || s_reserve (&self->tracks, n_tracks) < 0)
        return -ENOMEM;

    // Nothing fails from here.
    s_sums_t *s = &self->sums;
    const uint64_t serial = ++self->serial;
    for (size_t i = 0; i < n_truths; i++) {
        s_rec_t *r = s_insert (&self->truths, truths[i].id);
        r->stamp = serial;
        r->at = i;
        r->n_assoc = 0;
        r->lowest = 0;
        r->keep_last = false;
    }
    for (size_t j = 0; j < n_tracks; j++) {
        const ms_siap_track_t *k = &tracks[j];
        s_rec_t *r = k->truth_id ? s_find (&self->truths, k->truth_id) : NULL;
        bool associated = r && r->stamp == serial;
        if (associated) {
            const ms_point_t *tp = &truths[r->at].pos;
            s->position_error_m += hypot (k->pos.e - tp->e, k->pos.n - tp->n);
            s->associated_track_scans++;
            if (r->n_assoc == 0 || k->id < r->lowest)
                r->lowest = k->id;
            r->n_assoc++;
            if (k->id == r->last_primary)
                r->keep_last = true;
            s_identity (&s->id, &truths[r->at], k->claimed_id);
        } else if (k->truth_id) {
            s->unknown_truth_scans++;
        }
        if (!associated && k->truth_unseen)
            s->unseen_track_scans++;
        s_rec_t *tr = s_insert (&self->tracks, k->id);
        tr->tracked = tr->tracked || associated;
    }
    for (size_t i = 0; i < n_truths; i++) {
        s_rec_t *r = s_find (&self->truths, truths[i].id);
        if (r->n_assoc == 0) {
            if (r->tracked)
                s->breaks++;
            r->tracked = false;
            continue;
        }
        s->tracked_truth_scans++;
        uint32_t primary = r->keep_last ? r->last_primary : r->lowest;
        if (r->last_primary != 0 && primary != r->last_primary)
            s->swaps++;
        r->last_primary = primary;
        r->tracked = true;
    }
    double dt_s = self->run_scans > 0 ? t_s - self->last_t_s : 0;
    s->scans++;
    s->truth_scans += n_truths;
    s->track_scans += n_tracks;
    s->truth_time_s += dt_s * (double)n_truths;
    s->run_time_s += dt_s;
    self->run_scans++;
    self->last_t_s = t_s;
    return 0;
}

void ms_siap_end_run (ms_siap_t *self)
{
    assert (self);
    if (self->run_scans > 0)
        self->sums.runs++;
    self->sums.tracks += self->tracks.count;
    self->sums.false_tracks += s_never_associated (&self->tracks);
    s_clear (&self->truths);
    s_clear (&self->tracks);
    self->run_scans = 0;
}

int ms_siap_merge (ms_siap_t *dst, const ms_siap_t *src)
{
    assert (dst && src);
    if (dst == src)
        return -EINVAL;
    s_sums_t *d = &dst->sums;
    const s_sums_t *s = &src->sums;
    d->scans += s->scans;
    d->truth_scans += s->truth_scans;
    d->tracked_truth_scans += s->tracked_truth_scans;
    d->track_scans += s->track_scans;
    d->associated_track_scans += s->associated_track_scans;
    d->unknown_truth_scans += s->unknown_truth_scans;
    d->unseen_track_scans += s->unseen_track_scans;
    d->swaps += s->swaps;
    d->breaks += s->breaks;
    s_identity_pool (&d->id, &s->id);
    d->position_error_m += s->position_error_m;
    d->truth_time_s += s->truth_time_s;
    d->run_time_s += s->run_time_s;
    // src's closed runs, and its run under way closed here.
    d->runs += s->runs + (src->run_scans > 0);
    d->tracks += s->tracks + src->tracks.count;
    d->false_tracks += s->false_tracks + s_never_associated (&src->tracks);
    return 0;
}

// a / b, NaN when b is 0.
static double s_ratio (double a, double b)
{
    return b != 0 ? a / b : NAN;
}

/* The figures of r from its raw counts. */
static void s_figures (ms_siap_result_t *r)
{
    const double truth_h = r->truth_time_s / 3600, run_h = r->run_time_s / 3600;
    r->completeness = s_ratio ((double)r->tracked_truth_scans, (double)r->truth_scans);
    r->ambiguity = s_ratio ((double)r->associated_track_scans, (double)r->tracked_truth_scans);
    r->spuriousness =
        s_ratio ((double)(r->track_scans - r->associated_track_scans), (double)r->track_scans);
    r->spuriousness_unseen = s_ratio ((double)r->unseen_track_scans, (double)r->track_scans);
    r->position_accuracy_m = s_ratio (r->position_error_m, (double)r->associated_track_scans);
    r->swaps_per_truth_hour = s_ratio ((double)r->swaps, truth_h);
    r->breaks_per_truth_hour = s_ratio ((double)r->breaks, truth_h);
    r->false_tracks_per_hour = s_ratio ((double)r->false_tracks, run_h);
    r->id_completeness = s_ratio ((double)r->id.identifiable_marked, (double)r->id.identifiable);
    r->id_correctness = s_ratio ((double)r->id.correct, (double)r->id.marked);
    r->id_wrong_fraction = s_ratio ((double)r->id.wrong, (double)r->id.marked);
}

void ms_siap_result_pool (ms_siap_result_t *dst, const ms_siap_result_t *src)
{
    dst->runs += src->runs;
    dst->scans += src->scans;
    dst->truth_scans += src->truth_scans;
    dst->tracked_truth_scans += src->tracked_truth_scans;
    dst->track_scans += src->track_scans;
    dst->associated_track_scans += src->associated_track_scans;
    dst->unknown_truth_scans += src->unknown_truth_scans;
    dst->unseen_track_scans += src->unseen_track_scans;
    dst->position_error_m += src->position_error_m;
    dst->truth_time_s += src->truth_time_s;
    dst->run_time_s += src->run_time_s;
    dst->swaps += src->swaps;
    dst->breaks += src->breaks;
    dst->tracks += src->tracks;
    dst->false_tracks += src->false_tracks;
    s_identity_pool (&dst->id, &src->id);
    s_figures (dst);
}

void ms_siap_result (const ms_siap_t *self, ms_siap_result_t *ret)
{
    assert (self && ret);
    const s_sums_t *s = &self->sums;
    ms_siap_result_t r = {
        .runs = s->runs + (self->run_scans > 0),
        .scans = s->scans,
        .truth_scans = s->truth_scans,
        .tracked_truth_scans = s->tracked_truth_scans,
        .track_scans = s->track_scans,
        .associated_track_scans = s->associated_track_scans,
        .unknown_truth_scans = s->unknown_truth_scans,
        .unseen_track_scans = s->unseen_track_scans,
        .position_error_m = s->position_error_m,
        .truth_time_s = s->truth_time_s,
        .run_time_s = s->run_time_s,
        .swaps = s->swaps,
        .breaks = s->breaks,
        .tracks = s->tracks + self->tracks.count,
        .false_tracks = s->false_tracks + s_never_associated (&self->tracks),
        .id = s->id,
    };
    s_figures (&r);
    *ret = r;
}
