/* trk_checkpoint — the tracker's checkpoint (see trk_checkpoint.h).
 *
 * A cgs_ckpt frame "TRKS", version 1. Payload: u32 next id, u32 count, then
 * per track: u32 id, u32 radar, u8 status, the estimate (4 + 16 + 1 f64),
 * f64 height, u32 hits, updates, misses, window, scans, f64 last hit time,
 * u32 last scan, u8 friendly, u32 responder, f64 its time, u8 have_uv,
 * 2 f64 velocity, u8 turning, 2 × (f64 unit velocity, f64 velocity) before
 * the turn, u32 turn scan, u32 history count and per point 4 f64 (e, n, u,
 * t) and u32 scan number, u32 hit id; per IMM model its estimate (4 + 16 +
 * 1 f64) and f64 probability; f64 existence, f64 detection probability, u8
 * reconfirm, u32 continued track, f64 its probability. Every f64 is finite. */
#include "trk_checkpoint.h"
#include "cgs_ckpt.h"
#include "cgs_util.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define S_MAGIC     "TRKS"
#define S_VERSION   1u
#define S_WHAT      "trackerd checkpoint"
#define S_TRACK_MIN 300 // bytes a track takes at least (without history)

static void s_put_estimate (cgs_ckpt_writer_t *w, const trk_estimate_t *e)
{
    for (int i = 0; i < 4; i++)
        cgs_ckpt_put_f64 (w, e->x[i]);
    for (int i = 0; i < 16; i++)
        cgs_ckpt_put_f64 (w, e->P[i]);
    cgs_ckpt_put_f64 (w, e->t_s);
}

static void s_put_track (cgs_ckpt_writer_t *w, const trk_track_t *t)
{
    cgs_ckpt_put_u32 (w, t->id);
    cgs_ckpt_put_u32 (w, t->uav_id);
    cgs_ckpt_put_u8 (w, (uint8_t)t->status);
    s_put_estimate (w, &t->est);
    cgs_ckpt_put_f64 (w, t->up_m);
    cgs_ckpt_put_u32 (w, t->hits);
    cgs_ckpt_put_u32 (w, t->updates);
    cgs_ckpt_put_u32 (w, t->misses);
    cgs_ckpt_put_u32 (w, t->window);
    cgs_ckpt_put_u32 (w, t->scans);
    cgs_ckpt_put_f64 (w, t->last_hit_s);
    cgs_ckpt_put_u32 (w, t->last_scan);
    cgs_ckpt_put_bool (w, t->friendly);
    cgs_ckpt_put_u32 (w, t->friendly_id);
    cgs_ckpt_put_f64 (w, t->friendly_s);
    cgs_ckpt_put_bool (w, t->have_uv);
    cgs_ckpt_put_f64 (w, t->v_last[0]);
    cgs_ckpt_put_f64 (w, t->v_last[1]);
    cgs_ckpt_put_bool (w, t->turning);
    for (int i = 0; i < 2; i++) {
        cgs_ckpt_put_f64 (w, t->uv_before[i]);
        cgs_ckpt_put_f64 (w, t->v_before[i]);
    }
    cgs_ckpt_put_u32 (w, t->turn_scan);
    cgs_ckpt_put_u32 (w, t->history_count);
    for (uint32_t k = 0; k < t->history_count; k++) {
        const trk_history_point_t *h = &t->history[k];
        cgs_ckpt_put_f64 (w, h->e_m);
        cgs_ckpt_put_f64 (w, h->n_m);
        cgs_ckpt_put_f64 (w, h->u_m);
        cgs_ckpt_put_f64 (w, h->t_s);
        cgs_ckpt_put_u32 (w, h->scan_number);
        cgs_ckpt_put_u32 (w, h->hit_id);
    }
    for (int j = 0; j < TRK_IMM_MODELS; j++) {
        s_put_estimate (w, &t->imm.m[j]);
        cgs_ckpt_put_f64 (w, t->imm.mu[j]);
    }
    cgs_ckpt_put_f64 (w, t->existence);
    cgs_ckpt_put_f64 (w, t->pd);
    cgs_ckpt_put_bool (w, t->reconfirm);
    cgs_ckpt_put_u32 (w, t->continues);
    cgs_ckpt_put_f64 (w, t->continues_p);
}

int trk_checkpoint_save (const trk_tracker_t *trk, uint8_t **ret_buf, size_t *ret_len)
{
    cgs_ckpt_writer_t w;
    cgs_ckpt_writer_init (&w, S_MAGIC, S_VERSION);
    size_t count = trk_tracker_count (trk);
    cgs_ckpt_put_u32 (&w, trk_tracker_next_id (trk));
    cgs_ckpt_put_u32 (&w, (uint32_t)count);
    for (size_t i = 0; i < count; i++)
        s_put_track (&w, trk_tracker_at (trk, i));
    return cgs_ckpt_writer_finish (&w, ret_buf, ret_len);
}

/* An estimate whose variances are not negative; false (and r failed) else. */
static bool s_get_estimate (cgs_ckpt_reader_t *r, trk_estimate_t *e)
{
    for (int i = 0; i < 4; i++)
        e->x[i] = cgs_ckpt_get_finite (r);
    for (int i = 0; i < 16; i++)
        e->P[i] = cgs_ckpt_get_finite (r);
    e->t_s = cgs_ckpt_get_finite (r);
    for (int i = 0; i < 4; i++)
        if (!(e->P[i * 5] >= 0))
            cgs_ckpt_fail (r);
    return cgs_ckpt_ok (r);
}

/* One track, its values in range; false when it is not. */
static bool s_get_track (cgs_ckpt_reader_t *r, trk_track_t *t)
{
    memset (t, 0, sizeof *t);
    t->id = cgs_ckpt_get_u32 (r);
    t->uav_id = cgs_ckpt_get_u32 (r);
    uint8_t status = cgs_ckpt_get_u8 (r);
    s_get_estimate (r, &t->est);
    t->up_m = cgs_ckpt_get_finite (r);
    t->hits = cgs_ckpt_get_u32 (r);
    t->updates = cgs_ckpt_get_u32 (r);
    t->misses = cgs_ckpt_get_u32 (r);
    t->window = cgs_ckpt_get_u32 (r);
    t->scans = cgs_ckpt_get_u32 (r);
    t->last_hit_s = cgs_ckpt_get_finite (r);
    t->last_scan = cgs_ckpt_get_u32 (r);
    t->friendly = cgs_ckpt_get_bool (r);
    t->friendly_id = cgs_ckpt_get_u32 (r);
    t->friendly_s = cgs_ckpt_get_finite (r);
    t->have_uv = cgs_ckpt_get_bool (r);
    t->v_last[0] = cgs_ckpt_get_finite (r);
    t->v_last[1] = cgs_ckpt_get_finite (r);
    t->turning = cgs_ckpt_get_bool (r);
    for (int i = 0; i < 2; i++) {
        t->uv_before[i] = cgs_ckpt_get_finite (r);
        t->v_before[i] = cgs_ckpt_get_finite (r);
    }
    t->turn_scan = cgs_ckpt_get_u32 (r);
    t->history_count = cgs_ckpt_get_u32 (r);
    if (!cgs_ckpt_ok (r) || status > TRK_COASTING || t->id == 0 || t->hits == 0 ||
        t->history_count > TRK_HISTORY_MAX)
        return false;
    t->status = (trk_status_t)status;
    for (uint32_t k = 0; k < t->history_count; k++) {
        trk_history_point_t *h = &t->history[k];
        h->e_m = cgs_ckpt_get_finite (r);
        h->n_m = cgs_ckpt_get_finite (r);
        h->u_m = cgs_ckpt_get_finite (r);
        h->t_s = cgs_ckpt_get_finite (r);
        h->scan_number = cgs_ckpt_get_u32 (r);
        h->hit_id = cgs_ckpt_get_u32 (r);
    }
    double mu_sum = 0;
    for (int j = 0; j < TRK_IMM_MODELS; j++) {
        s_get_estimate (r, &t->imm.m[j]);
        t->imm.mu[j] = cgs_ckpt_get_finite (r);
        if (!(t->imm.mu[j] >= 0 && t->imm.mu[j] <= 1))
            return false;
        mu_sum += t->imm.mu[j];
    }
    t->existence = cgs_ckpt_get_finite (r);
    t->pd = cgs_ckpt_get_finite (r);
    t->reconfirm = cgs_ckpt_get_bool (r);
    t->continues = cgs_ckpt_get_u32 (r);
    t->continues_p = cgs_ckpt_get_finite (r);
    return cgs_ckpt_ok (r) && t->existence >= 0 && t->existence <= 1 && t->pd >= 0 && t->pd <= 1 &&
           t->continues_p >= 0 && t->continues_p <= 1 &&
           (mu_sum == 0 || fabs (mu_sum - 1) <= 1e-6); // 0: no models (the paper's filter)
}

static int s_cmp_u32 (const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

/* Every id once, each below next_id (not 0); 0 or -EINVAL with the reason. */
static int s_check_ids (const trk_track_t *tracks, uint32_t count, uint32_t next_id, char *err,
                        size_t errlen)
{
    if (next_id == 0) {
        cgs_errf (err, errlen, "the checkpoint's next track id is 0");
        return -EINVAL;
    }
    if (count == 0)
        return 0;
    uint32_t *ids = malloc (count * sizeof *ids);
    if (!ids) {
        cgs_errf (err, errlen, "out of memory for %u tracks", count);
        return -ENOMEM;
    }
    for (uint32_t i = 0; i < count; i++)
        ids[i] = tracks[i].id;
    qsort (ids, count, sizeof *ids, s_cmp_u32);
    int rc = 0;
    for (uint32_t i = 0; i < count && rc == 0; i++)
        if ((i > 0 && ids[i] == ids[i - 1]) || ids[i] >= next_id) {
            cgs_errf (err, errlen,
                      "the checkpoint's track ids are inconsistent (id %u, next id %u)", ids[i],
                      next_id);
            rc = -EINVAL;
        }
    free (ids);
    return rc;
}

int trk_checkpoint_restore (trk_tracker_t *trk, const uint8_t *buf, size_t len, char *err,
                            size_t errlen)
{
    cgs_ckpt_reader_t r;
    int rc = cgs_ckpt_open (&r, buf, len, S_MAGIC, S_VERSION, S_WHAT, err, errlen);
    if (rc < 0)
        return rc;
    uint32_t next_id = cgs_ckpt_get_u32 (&r), count = cgs_ckpt_get_u32 (&r);
    // A count the payload cannot hold is damage, refused before allocating for it.
    if (!cgs_ckpt_ok (&r) || count > cgs_ckpt_left (&r) / S_TRACK_MIN) {
        cgs_errf (err, errlen, "the checkpoint claims %u tracks in %zu bytes", count, len);
        return -EINVAL;
    }
    trk_track_t *tracks = count ? malloc (count * sizeof *tracks) : NULL;
    if (count && !tracks) {
        cgs_errf (err, errlen, "out of memory for %u tracks", count);
        return -ENOMEM;
    }
    for (uint32_t i = 0; i < count && rc == 0; i++)
        if (!s_get_track (&r, &tracks[i])) {
            cgs_errf (err, errlen, "track %u of %u in the checkpoint is damaged", i + 1, count);
            rc = -EINVAL;
        }
    if (rc == 0)
        rc = cgs_ckpt_end (&r, S_WHAT, err, errlen);
    if (rc == 0)
        rc = s_check_ids (tracks, count, next_id, err, errlen);
    if (rc == 0 && (rc = trk_tracker_replace (trk, tracks, count, next_id)) < 0)
        cgs_errf (err, errlen, "out of memory for %u tracks", count);
    free (tracks);
    return rc;
}

int trk_checkpoint_next_id (const uint8_t *buf, size_t len, uint32_t *ret_id)
{
    cgs_ckpt_reader_t r;
    int rc = cgs_ckpt_open_unchecked (&r, buf, len, S_MAGIC, S_VERSION);
    if (rc < 0)
        return rc;
    uint32_t next_id = cgs_ckpt_get_u32 (&r);
    if (!cgs_ckpt_ok (&r) || next_id == 0)
        return -EINVAL;
    *ret_id = next_id;
    return 0;
}
