/* ms_observer — an intercept judged from ground truth (see ms_observer.h). */
#include "ms_observer.h"

#include <math.h>
#include <string.h>

void ms_icpt_init (ms_icpt_t *ic)
{
    memset (ic, 0, sizeof *ic);
    ic->final_s = NAN;
    ic->other_since_s = ic->other_unseen_s = ic->other_gap_m = NAN;
    cgs_score_init (&ic->score);
}

/* The state's name without its prefix ("DONE"). */
const char *ms_icpt_state_name (Cgs__InterceptState state)
{
    return cgs_msg_enum_short (&cgs__intercept_state__descriptor, state, "UNKNOWN");
}

static bool s_icpt_state_final (Cgs__InterceptState state)
{
    return state == CGS__INTERCEPT_STATE__INTERCEPT_STATE_DONE ||
           state == CGS__INTERCEPT_STATE__INTERCEPT_STATE_LOST ||
           state == CGS__INTERCEPT_STATE__INTERCEPT_STATE_CANCELLED;
}

/* The hits of radar uav_id; a new slot when create (NULL when full). */
static ms_icpt_hits_t *s_icpt_radar (ms_icpt_t *ic, uint32_t uav_id, bool create)
{
    for (size_t i = 0; i < ic->nradars; i++)
        if (ic->radars[i].uav_id == uav_id)
            return &ic->radars[i];
    if (!create || ic->nradars == MS_ICPT_RADARS_MAX)
        return NULL;
    ms_icpt_hits_t *h = &ic->radars[ic->nradars++];
    h->uav_id = uav_id;
    return h;
}

static void s_hits_add (ms_icpt_hits_t *h, uint32_t hit_id, uint32_t entity_id)
{
    h->hit_id[h->next] = hit_id;
    h->entity_id[h->next] = entity_id;
    h->next = (h->next + 1) % MS_ICPT_HITS_MAX;
    if (h->count < MS_ICPT_HITS_MAX)
        h->count++;
}

/* The entity that produced hit_id (the newest such hit), 0 if not remembered. */
static uint32_t s_hits_entity (const ms_icpt_hits_t *h, uint32_t hit_id)
{
    for (size_t k = 1; k <= h->count; k++) {
        size_t i = (h->next + MS_ICPT_HITS_MAX - k) % MS_ICPT_HITS_MAX;
        if (h->hit_id[i] == hit_id)
            return h->entity_id[i];
    }
    return 0;
}

uint32_t ms_icpt_track_entity (ms_icpt_t *ic, uint32_t radar, const Cgs__Track *tr)
{
    const ms_icpt_hits_t *h = s_icpt_radar (ic, radar, false);
    if (!h)
        return 0;
    uint32_t entity[MS_ICPT_VOTES_MAX];
    size_t votes[MS_ICPT_VOTES_MAX], n = 0, best = 0;
    for (size_t i = 0; i < tr->n_history; i++) {
        uint32_t e = tr->history[i]->hit_id ? s_hits_entity (h, tr->history[i]->hit_id) : 0;
        if (e == 0)
            continue;
        size_t k = 0;
        while (k < n && entity[k] != e)
            k++;
        if (k == n) {
            if (n == MS_ICPT_VOTES_MAX)
                continue;
            entity[n] = e;
            votes[n++] = 0;
        }
        votes[k]++;
        if (votes[k] > votes[best])
            best = k;
    }
    return n ? entity[best] : 0;
}

/* The track follows the designated vehicle (again), or nothing is known yet. */
static void s_other_clear (ms_icpt_t *ic)
{
    ic->other_entity_id = 0;
    ic->other_marking[0] = '\0';
    ic->other_since_s = ic->other_unseen_s = ic->other_gap_m = NAN;
}

/* The designated vehicle's remembered position nearest in time to t_s
 * (within MS_ICPT_TRAIL_DT_S); false when none is. */
static bool s_trail_at (const ms_icpt_t *ic, double t_s, double *e, double *n)
{
    double best = MS_ICPT_TRAIL_DT_S;
    bool found = false;
    for (size_t k = 0; k < ic->trail_count; k++)
        if (fabs (ic->trail_t[k] - t_s) <= best) {
            best = fabs (ic->trail_t[k] - t_s);
            *e = ic->trail_e[k];
            *n = ic->trail_n[k];
            found = true;
        }
    return found;
}

/* The entity of the i-th hit of tr's history (0: not known). */
static uint32_t s_history_entity (const ms_icpt_hits_t *h, const Cgs__Track *tr, size_t i)
{
    return h && tr->history[i]->hit_id ? s_hits_entity (h, tr->history[i]->hit_id) : 0;
}

/* The track tr now follows entity e of radar h, not the designated one: when
 * its hits of e began (the latest run of its hits that are e's, back to the
 * first that is not; later hits of others may follow it), and how long it
 * had gone without a hit before. */
static void s_other_begin (ms_icpt_t *ic, const ms_icpt_hits_t *h, const Cgs__Track *tr, uint32_t e,
                           double t_s)
{
    s_other_clear (ic);
    ic->other_entity_id = e;
    ic->other_since_s = t_s;
    size_t end = tr->n_history;
    while (end > 0 && s_history_entity (h, tr, end - 1) != e)
        end--;
    size_t k = end;
    while (k > 0 && s_history_entity (h, tr, k - 1) == e)
        k--;
    if (k < end) {
        const Cgs__TrackHistoryPoint *hp = tr->history[k];
        ic->other_since_s = hp->sim_time_s;
        if (k > 0)
            ic->other_unseen_s = hp->sim_time_s - tr->history[k - 1]->sim_time_s;
        double de, dn;
        if (hp->position && s_trail_at (ic, hp->sim_time_s, &de, &dn))
            ic->other_gap_m = hypot (hp->position->east_m - de, hp->position->north_m - dn);
    }
}

/* A new designation: the score starts again. */
static void s_icpt_designate (ms_icpt_t *ic, const Cgs__Intercept *m, double t_s)
{
    ic->designated = true;
    ic->designation_number = m->designation_number;
    ic->desig_track_id = m->track_id;
    ic->first_track_id = m->track_id;
    ic->desig_state = m->state;
    ic->replans = 0;
    ic->final = false;
    ic->final_s = NAN;
    ic->entity_id = 0;
    ic->marking[0] = '\0';
    s_other_clear (ic);
    ic->trail_next = ic->trail_count = 0;
    cgs_score_init (&ic->score);
    cgs_score_designated (&ic->score, t_s);
}

/* The footprint of an intercept message; false when it shows none. */
static bool s_icpt_footprint (const Cgs__Footprint *f, cgs_footprint_t *ret)
{
    if (!f || f->n_corners < 4)
        return false;
    for (size_t i = 0; i < 4; i++)
        if (!isfinite (f->corners[i]->east_m) || !isfinite (f->corners[i]->north_m))
            return false;
    if (f->center && (!isfinite (f->center->east_m) || !isfinite (f->center->north_m)))
        return false;
    memset (ret, 0, sizeof *ret);
    double e = 0, n = 0;
    for (size_t i = 0; i < 4; i++) {
        ret->corner[i] = (cgs_v2_t){f->corners[i]->east_m, f->corners[i]->north_m};
        ret->corner_up_m[i] = f->corners[i]->up_m;
        e += f->corners[i]->east_m / 4;
        n += f->corners[i]->north_m / 4;
    }
    ret->center = f->center ? (cgs_v2_t){f->center->east_m, f->center->north_m} : (cgs_v2_t){e, n};
    ret->center_up_m = f->center ? f->center->up_m : 0;
    return true;
}

void ms_icpt_on_intercept (void *arg, const char *topic, const ProtobufCMessage *msg,
                           const Cgs__Header *hdr)
{
    (void)topic;
    ms_icpt_t *ic = arg;
    const Cgs__Intercept *m = (const Cgs__Intercept *)msg;
    double t = hdr->sim_time_s;
    if (!isfinite (t)) {
        ic->malformed++;
        return;
    }
    ic->seen = true;
    ic->state = m->state;
    ic->track_id = m->track_id;
    ic->latest_s = fmax (ic->latest_s, t);
    if (m->track_id != 0 && (!ic->designated || m->designation_number != ic->designation_number))
        s_icpt_designate (ic, m, t);
    if (!ic->designated || m->designation_number != ic->designation_number)
        return; // nothing designated yet
    if (m->track_id != 0)
        ic->desig_track_id = m->track_id;
    ic->replans = m->replans;
    if (!ic->final) {
        ic->desig_state = m->state;
        ic->final = s_icpt_state_final (m->state);
        ic->final_s = ic->final ? t : NAN;
    }
    cgs_footprint_t fp;
    bool shown = s_icpt_footprint (m->footprint, &fp);
    if (!shown && m->footprint && m->footprint->n_corners >= 4)
        ic->malformed++; // a footprint with a non-finite corner: judges nothing
    cgs_score_footprint (&ic->score, t, shown ? &fp : NULL);
}

void ms_icpt_on_mti_truth (void *arg, const char *topic, const ProtobufCMessage *msg,
                           const Cgs__Header *hdr)
{
    (void)topic;
    ms_icpt_t *ic = arg;
    const Cgs__MtiTruth *m = (const Cgs__MtiTruth *)msg;
    ms_icpt_hits_t *h = s_icpt_radar (ic, m->uav_id, true);
    if (!h) {
        ic->radars_ignored++;
        return;
    }
    if (hdr->epoch != h->epoch) { // a restarted mtid numbers its hits from 1 again
        h->epoch = hdr->epoch;
        h->next = h->count = 0;
    }
    for (size_t i = 0; i < m->n_items; i++)
        if (m->items[i]->hit_id && m->items[i]->entity_id)
            s_hits_add (h, m->items[i]->hit_id, m->items[i]->entity_id);
}

void ms_icpt_on_track (void *arg, const char *topic, const ProtobufCMessage *msg,
                       const Cgs__Header *hdr)
{
    (void)topic;
    ms_icpt_t *ic = arg;
    const Cgs__TrackBatch *b = (const Cgs__TrackBatch *)msg;
    if (!ic->designated)
        return;
    for (size_t i = 0; i < b->n_tracks; i++) {
        const Cgs__Track *tr = b->tracks[i];
        if (tr->track_id != ic->desig_track_id)
            continue;
        // The designated target is the vehicle the designated track followed
        // first; a track that follows another vehicle since (the designated
        // one, which changed vehicle, or one that took over) is reported, and
        // the score stays with the designated one.
        uint32_t radar = tr->uav_id ? tr->uav_id : b->uav_id;
        uint32_t e = ms_icpt_track_entity (ic, radar, tr);
        if (e != 0 && ic->entity_id == 0) {
            ic->entity_id = e;
            ic->marking[0] = '\0';
        } else if (e != 0 && e == ic->entity_id) {
            s_other_clear (ic); // the track follows the designated vehicle (again)
        } else if (e != 0 && e != ic->other_entity_id) {
            s_other_begin (ic, s_icpt_radar (ic, radar, false), tr, e, hdr->sim_time_s);
        }
    }
}

void ms_icpt_on_entity (void *arg, const char *topic, const ProtobufCMessage *msg,
                        const Cgs__Header *hdr)
{
    (void)topic;
    ms_icpt_t *ic = arg;
    const Cgs__EntityBatch *b = (const Cgs__EntityBatch *)msg;
    if (!isfinite (hdr->sim_time_s)) {
        ic->malformed++;
        return;
    }
    ic->latest_s = fmax (ic->latest_s, hdr->sim_time_s);
    if (!ic->designated || ic->entity_id == 0)
        return;
    for (size_t i = 0; i < b->n_entities; i++) {
        const Cgs__Entity *en = b->entities[i];
        bool at = en->active && en->position && isfinite (en->position->east_m) &&
                  isfinite (en->position->north_m);
        if (ic->other_entity_id && en->entity_id == ic->other_entity_id)
            snprintf (ic->other_marking, sizeof ic->other_marking, "%s", en->marking);
        if (en->entity_id != ic->entity_id)
            continue;
        snprintf (ic->marking, sizeof ic->marking, "%s", en->marking);
        if (en->active && en->position && !at) {
            ic->malformed++;
        } else if (at) {
            cgs_score_target (&ic->score, hdr->sim_time_s,
                              (cgs_v2_t){en->position->east_m, en->position->north_m});
            size_t last = (ic->trail_next + MS_ICPT_TRAIL - 1) % MS_ICPT_TRAIL;
            if (ic->trail_count == 0 ||
                !(hdr->sim_time_s - ic->trail_t[last] < MS_ICPT_TRAIL_DT_S)) {
                ic->trail_t[ic->trail_next] = hdr->sim_time_s;
                ic->trail_e[ic->trail_next] = en->position->east_m;
                ic->trail_n[ic->trail_next] = en->position->north_m;
                ic->trail_next = (ic->trail_next + 1) % MS_ICPT_TRAIL;
                if (ic->trail_count < MS_ICPT_TRAIL)
                    ic->trail_count++;
            }
        }
    }
}

/* The intercept section of the summary, for a person. */
void ms_icpt_print (const ms_icpt_t *ic, FILE *f)
{
    const cgs_score_t *sc = &ic->score;
    fprintf (f, "Intercept\n");
    if (!ic->designated) {
        fprintf (f, "  no target was designated\n");
        return;
    }
    fprintf (f, "  designated        track %u at sim %.1f s (designation %llu)\n",
             ic->desig_track_id, sc->designation_s, (unsigned long long)ic->designation_number);
    if (ic->entity_id)
        fprintf (f, "  true target       entity %u \"%s\" (most of the track's MTI hits)\n",
                 ic->entity_id, ic->marking);
    else
        fprintf (f, "  true target       unknown (no MTI truth for the track's hits)\n");
    if (ic->other_entity_id)
        fprintf (f, "  %s track %u now follows entity %u \"%s\", not the designated target\n",
                 ic->desig_track_id != ic->first_track_id ? "hand-over        "
                                                          : "changed vehicle  ",
                 ic->desig_track_id, ic->other_entity_id, ic->other_marking);
    if (ic->other_entity_id && isfinite (ic->other_since_s)) {
        fprintf (f, "                    its hits of it since sim %.1f s", ic->other_since_s);
        if (isfinite (ic->other_unseen_s))
            fprintf (f, " (the first after %.0f s without a hit)", ic->other_unseen_s);
        if (isfinite (ic->other_gap_m))
            fprintf (f, ", the first %.0f m from the designated target", ic->other_gap_m);
        fprintf (f, "\n");
    }
    fprintf (f, "  state             %s", ms_icpt_state_name (ic->desig_state));
    if (ic->final)
        fprintf (f, " at sim %.1f s", ic->final_s);
    fprintf (f, ", %u replan%s\n", ic->replans, ic->replans == 1 ? "" : "s");
    if (sc->imaged)
        fprintf (f,
                 "  imaged            yes: %.1f s inside the footprint, first at sim %.1f s, "
                 "%.1f s after designation\n",
                 sc->inside_s, sc->first_inside_s, cgs_score_time_to_image (sc));
    else if (isfinite (sc->closest_edge_m))
        fprintf (f, "  imaged            no: %.1f m from the footprint at closest\n",
                 sc->closest_edge_m);
    else
        fprintf (f, "  imaged            no: no footprint was seen with the target\n");
    if (isfinite (sc->closest_m))
        fprintf (f, "  closest approach  %.1f m from the footprint centre at sim %.1f s\n",
                 sc->closest_m, sc->closest_s);
    fprintf (f, "  judged            %zu of %zu target positions against a footprint\n", sc->judged,
             sc->samples);
    if (ic->radars_ignored)
        fprintf (
            f, "  not read          MTI truth of %llu message%s from radars beyond the first %d\n",
            (unsigned long long)ic->radars_ignored, ic->radars_ignored == 1 ? "" : "s",
            MS_ICPT_RADARS_MAX);
    if (ic->malformed)
        fprintf (f,
                 "  ignored           %llu message%s with a non-finite time, position or corner\n",
                 (unsigned long long)ic->malformed, ic->malformed == 1 ? "" : "s");
}

/* A marking as a JSON string, its bytes read as Latin-1: DIS markings are
 * ASCII, and a byte beyond that from a faulty peer still makes valid UTF-8. */
static json_object *s_json_marking (const char *s)
{
    char u[2 * sizeof ((ms_icpt_t *)NULL)->marking];
    size_t n = 0;
    for (const unsigned char *c = (const unsigned char *)s; *c && n + 2 <= sizeof u; c++) {
        if (*c < 0x80) {
            u[n++] = (char)*c;
        } else {
            u[n++] = (char)(0xc0 | *c >> 6);
            u[n++] = (char)(0x80 | (*c & 0x3f));
        }
    }
    return json_object_new_string_len (u, (int)n);
}

/* A whole number, or null when not known. */
static json_object *s_json_id (bool known, uint32_t v)
{
    return known ? json_object_new_int64 (v) : NULL;
}

json_object *ms_icpt_json (const ms_icpt_t *ic)
{
    json_object *o = json_object_new_object ();
    if (!o)
        return NULL;
    const cgs_score_t *sc = &ic->score;
    bool d = ic->designated;
    bool target = d && ic->entity_id;
    cgs_json_add (o, "designated", json_object_new_boolean (d));
    cgs_json_add (o, "track_id", s_json_id (d, ic->desig_track_id));
    cgs_json_add (o, "target_entity_id", s_json_id (target, ic->entity_id));
    cgs_json_add (o, "target_marking", target ? s_json_marking (ic->marking) : NULL);
    bool other = d && ic->other_entity_id;
    cgs_json_add (o, "follows_entity_id", s_json_id (other, ic->other_entity_id));
    cgs_json_add (
        o, "handed_over_to_entity_id",
        s_json_id (other && ic->desig_track_id != ic->first_track_id, ic->other_entity_id));
    cgs_json_add (o, "follows_since_s", cgs_json_fixed (other ? ic->other_since_s : NAN, 3));
    cgs_json_add (o, "follows_after_unseen_s",
                  cgs_json_fixed (other ? ic->other_unseen_s : NAN, 3));
    cgs_json_add (o, "follows_gap_m", cgs_json_fixed (other ? ic->other_gap_m : NAN, 1));
    cgs_json_add (o, "designation_time_s", cgs_json_fixed (d ? sc->designation_s : NAN, 3));
    cgs_json_add (o, "final_state",
                  d ? json_object_new_string (ms_icpt_state_name (ic->desig_state)) : NULL);
    cgs_json_add (o, "replans", s_json_id (d, ic->replans));
    cgs_json_add (o, "imaged", json_object_new_boolean (d && sc->imaged));
    cgs_json_add (o, "time_in_footprint_s", cgs_json_fixed (d ? sc->inside_s : NAN, 3));
    cgs_json_add (o, "closest_approach_m", cgs_json_fixed (d ? sc->closest_m : NAN, 3));
    cgs_json_add (o, "closest_approach_time_s", cgs_json_fixed (d ? sc->closest_s : NAN, 3));
    cgs_json_add (o, "designation_to_overflight_s",
                  cgs_json_fixed (cgs_score_time_to_image (sc), 3));
    return o;
}
