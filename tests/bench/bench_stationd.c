/* bench_stationd — how fast the tactical map follows a busy picture: 5,000
 * MTI hits and 1,000 tracks, pushed by stationd and applied by the page in
 * headless Chromium. Goal: updates at 5 Hz or more, each applied in under
 * 100 ms.
 *
 *   bench_stationd [options]     (--help lists them)
 *
 * The picture. One radar (UAV 1, loitering a 3 km circle at the origin) scans
 * every --scan-s seconds (default 2) in dwells of 0.1 s; 1,000 targets move
 * at 5 to 20 m/s in straight lines over a 40 km square, bouncing off its
 * edges. Each scan's hits fall on evenly spaced targets (25 m noise), so that
 * any 21 consecutive scans hold --hits hits (default 5,000: about 238 a
 * scan), which is what stationd keeps at its default parameters: 20 grey
 * complete scans, the newest complete scan, and the scan in progress. After
 * each scan every target's track is published (confirmed, a fifth of them
 * friendly, with its last five hits as history and a covariance, in batches
 * of 200 as trackerd sends them).
 *
 * 1. In process: that picture after 21 scans (exactly --hits hits, 1,000
 *    tracks) is built with stationd's own st_state, and st_state_json, the
 *    JSON every push carries, is timed (wall clock, nothing else running):
 *    the median of 40 calls per run, and the picture's size.
 * 2. End to end: a temporary folder holds an exercise file naming
 *    `uavsim`, `mtid.uav1` and `trackerd` (publish only) and `stationd`,
 *    with ipc:// endpoints in that folder. A forked feeder process publishes
 *    as the first three, with the project's publisher (cgs_pub): it waits
 *    until stationd has connected to all three (a socket monitor), sends the
 *    first 21 scans at once (simulation time 0 to 42 s, so the map is full at
 *    once), then goes on in real time: every 0.1 s a `clock`, a `uav` and one
 *    dwell's `mti`, and at each scan's end an `mti.scan` and the `track`
 *    batches. The real stationd (BUILD/bin/stationd: $CGS_BUILD/bin, else
 *    ../bin beside this program) runs with its default parameters (5 pushes a
 *    second), no scenario (so no relief), on a free port.
 * 3. Each run starts `node CGS_ROOT/tests/bench/bench_stationd.js` ($CGS_ROOT,
 *    else the tree three folders above this program's), which connects a
 *    WebSocket client of its own (the `ws` package), waits until stationd's
 *    pushes carry the whole picture, opens the page in a fresh headless
 *    Chromium (playwright-core, /usr/bin/chromium) with a 1920x1080 window
 *    (--viewport), waits until the page shows it, and for --seconds (default
 *    20) records every push the client receives and every update the page
 *    applies. It prints figures as `fig key=value` lines, read here; see the
 *    script's header for each one's definition. The first run then profiles
 *    the page for 6 s and prints where its time goes.
 *
 * Figures (each the median over the runs, with the runs' min and max):
 *   json_build_ms_median  st_state_json of the full picture, in process
 *   picture_bytes         its size (push_bytes: as stationd pushed it)
 *   push_hz_ws            pushes a second the WebSocket client received:
 *                         the median over the window's 1 s intervals
 *   push_hz_page          updates a second the page applied, the same way
 *   apply_ms_median/_p95/_max  the page's own measure of an update: from its
 *                         WebSocket message handler's start (JSON.parse) to
 *                         after map.renderSync(), window.cgs.stats.applyMs
 *   lag_ms_median/_p95    from the client's receipt of a push to the end of
 *                         the page's applying that same push (queueing in
 *                         the page included)
 *   parse_ms              JSON.parse of one push in the page, alone
 *   apply_ms_scan_end_median, apply_ms_between_median  see below
 *   cpu_*_pct             CPU over the window: the machine (% of all
 *                         cores), stationd and Chromium (% of one core)
 * Verdict: PASS when both push rates are at least 5 Hz and every update of
 * every run was applied in under 100 ms (the slowest, apply_ms_max, decides;
 * the updates over 100 ms are counted and printed, so a single garbage
 * collection pause that broke the goal is visible as such). Exit 0 whether or not the goal is met;
 * 1 when a measurement broke (stationd did not start or died, the feeder failed, no updates came,
 * node or Chromium failed), with verdict=FAIL and why.
 *
 * Everything shares the machine's cores: stationd, the feeder, node and
 * Chromium's processes (and whatever else runs), as on a small lab machine;
 * the script prints the machine's, stationd's and Chromium's CPU use over
 * each window, and the updates at a scan's end (every track moved and the
 * grey history changed in the same push) apart from the others
 * (apply_ms_scan_end_median, apply_ms_between_median): at one scan every
 * 2 s they are one update in ten, so they set the p95.
 *
 * Departures from the style guide: prints to stdout (its output is the
 * product); forks a feeder that never returns into main (_exit); spawns
 * stationd and node with posix_spawn and stops them itself (SIGTERM, then
 * SIGKILL after 5 s). No zmq context exists in this process at the fork. */
#include "bench_util.h"
#include "cgs_bus.h"
#include "cgs_msg.h"
#include "st_state.h"

#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <limits.h>
#include <math.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include <zmq.h>

extern char **environ;

#define S_PI            3.14159265358979323846
#define S_MAX_RUNS      20
#define S_GOAL_HZ       5.0
#define S_GOAL_APPLY_MS 100.0
#define S_UAV_ID        1
#define S_DWELL_S       0.1                   // one mti message per dwell, a tick of the feeder
#define S_HALF_M        20000.0               // the targets' square: +-20 km around the origin
#define S_HISTORY_SCANS 20                    // stationd's default history_scans
#define S_SCANS         (S_HISTORY_SCANS + 1) // complete scans on the map
#define S_TRACK_HISTORY 5                     // hits of history in each track
#define S_BATCH_TRACKS  200                   // tracks per `track` message, as trackerd
#define S_JSON_CALLS    40                    // st_state_json calls timed per run
#define S_PROFILE_S     6                     // seconds the first run profiles the page
#define S_EXERCISE_ID   1

typedef struct {
    int runs;
    long seconds; // measured window of each run
    double scan_s;
    long hits; // on the map: in any 21 consecutive scans
    long tracks;
    char viewport[32];
} s_opts_t;

/* ---- the figures ----------------------------------------------------------------- */

typedef struct {
    double v[S_MAX_RUNS];
    int n;
    double median, min, max;
} s_fig_t;

static void s_fig_add (s_fig_t *f, double v)
{
    if (f->n < S_MAX_RUNS && isfinite (v))
        f->v[f->n++] = v;
}

static void s_fig_done (s_fig_t *f)
{
    if (f->n == 0) {
        f->median = f->min = f->max = NAN;
        return;
    }
    double tmp[S_MAX_RUNS];
    memcpy (tmp, f->v, sizeof tmp);
    f->median = bench_median (tmp, f->n);
    f->min = tmp[0];
    f->max = tmp[f->n - 1];
}

/* ---- the simulated world ----------------------------------------------------------- */

typedef struct {
    double e0, n0, ve, vn; // start and velocity; bounces off the square's edges
} s_target_t;

/* The world and the messages it fills (reused from one message to the next). */
typedef struct {
    const s_opts_t *o;
    long ntg;
    s_target_t *tg;
    int dwells; // per scan
    uint64_t rng;
    uint32_t hit_id;
    // one dwell's hits
    Cgs__MtiHit *hit;
    Cgs__Enu *hit_pos;
    Cgs__MtiHit **hit_ptr;
    long hit_cap;
    // one scan's tracks
    Cgs__Track *trk;
    Cgs__Enu *trk_pos;
    Cgs__EnuVelocity *trk_vel;
    Cgs__Track **trk_ptr;
    double *cov;
    Cgs__TrackHistoryPoint *hist;
    Cgs__Enu *hist_pos;
    Cgs__TrackHistoryPoint **hist_ptr;
} s_world_t;

static double s_uniform (s_world_t *w)
{
    w->rng = w->rng * 6364136223846793005ull + 1442695040888963407ull;
    return ((double)(w->rng >> 11) + 0.5) / 9007199254740992.0;
}

static double s_gauss (s_world_t *w)
{
    return sqrt (-2 * log (s_uniform (w))) * cos (2 * S_PI * s_uniform (w));
}

/* A coordinate moving at v from x0 for t seconds, bouncing between -half and
 * half; its velocity now in *ret_v. */
static double s_bounce (double x0, double v, double t, double half, double *ret_v)
{
    double span = 4 * half, u = fmod (x0 + v * t + half, span);
    if (u < 0)
        u += span;
    if (u > 2 * half) {
        *ret_v = -v;
        return 3 * half - u;
    }
    *ret_v = v;
    return u - half;
}

static void s_target_at (const s_world_t *w, long i, double t, double p[2], double v[2])
{
    const s_target_t *g = &w->tg[i];
    p[0] = s_bounce (g->e0, g->ve, t, S_HALF_M, &v[0]);
    p[1] = s_bounce (g->n0, g->vn, t, S_HALF_M, &v[1]);
}

static double s_heading (double ve, double vn)
{
    double h = atan2 (ve, vn) * 180 / S_PI;
    return h < 0 ? h + 360 : h;
}

static void s_world_free (s_world_t *w)
{
    free (w->tg);
    free (w->hit);
    free (w->hit_pos);
    free (w->hit_ptr);
    free (w->trk);
    free (w->trk_pos);
    free (w->trk_vel);
    free (w->trk_ptr);
    free (w->cov);
    free (w->hist);
    free (w->hist_pos);
    free (w->hist_ptr);
    memset (w, 0, sizeof *w);
}

static int s_world_new (s_world_t *w, const s_opts_t *o)
{
    memset (w, 0, sizeof *w);
    w->o = o;
    w->ntg = o->tracks;
    w->dwells = (int)lround (o->scan_s / S_DWELL_S);
    w->rng = 0x853c49e6748fea9bull;
    w->hit_cap = o->hits / S_SCANS / w->dwells + 2;
    long nh = w->ntg * S_TRACK_HISTORY;
    w->tg = calloc ((size_t)w->ntg, sizeof *w->tg);
    w->hit = calloc ((size_t)w->hit_cap, sizeof *w->hit);
    w->hit_pos = calloc ((size_t)w->hit_cap, sizeof *w->hit_pos);
    w->hit_ptr = calloc ((size_t)w->hit_cap, sizeof *w->hit_ptr);
    w->trk = calloc ((size_t)w->ntg, sizeof *w->trk);
    w->trk_pos = calloc ((size_t)w->ntg, sizeof *w->trk_pos);
    w->trk_vel = calloc ((size_t)w->ntg, sizeof *w->trk_vel);
    w->trk_ptr = calloc ((size_t)w->ntg, sizeof *w->trk_ptr);
    w->cov = calloc ((size_t)w->ntg * 16, sizeof *w->cov);
    w->hist = calloc ((size_t)nh, sizeof *w->hist);
    w->hist_pos = calloc ((size_t)nh, sizeof *w->hist_pos);
    w->hist_ptr = calloc ((size_t)nh, sizeof *w->hist_ptr);
    if (!w->tg || !w->hit || !w->hit_pos || !w->hit_ptr || !w->trk || !w->trk_pos || !w->trk_vel ||
        !w->trk_ptr || !w->cov || !w->hist || !w->hist_pos || !w->hist_ptr) {
        s_world_free (w);
        return -1;
    }
    for (long i = 0; i < w->ntg; i++) {
        double h = 2 * S_PI * s_uniform (w), s = 5 + 15 * s_uniform (w);
        w->tg[i] = (s_target_t){(2 * s_uniform (w) - 1) * S_HALF_M,
                                (2 * s_uniform (w) - 1) * S_HALF_M, s * sin (h), s * cos (h)};
    }
    return 0;
}

/* Hits of scan k (from 1): any S_SCANS consecutive scans hold o->hits. */
static long s_scan_hits (const s_world_t *w, long k)
{
    return w->o->hits * k / S_SCANS - w->o->hits * (k - 1) / S_SCANS;
}

/* Where a message goes: the feeder publishes it, the in-process figure takes
 * it into an st_state. 0, or -1 when it failed. */
typedef int (s_emit_fn) (void *arg, const char *topic, ProtobufCMessage *msg, double t_s);

/* The UAV loiters a 3 km circle round the origin at 40 m/s. */
static int s_emit_uav (s_world_t *w, s_emit_fn *emit, void *arg, uint64_t tick, double t)
{
    (void)w;
    double r = 3000, v = 40, a = v * t / r;
    Cgs__Enu pos = CGS__ENU__INIT, centre = CGS__ENU__INIT;
    Cgs__EnuVelocity vel = CGS__ENU_VELOCITY__INIT;
    Cgs__LoiterOrbit orbit = CGS__LOITER_ORBIT__INIT;
    Cgs__Uav u = CGS__UAV__INIT;
    Cgs__Clock c = CGS__CLOCK__INIT;
    pos.east_m = r * cos (a);
    pos.north_m = r * sin (a);
    pos.up_m = 3000;
    vel.east_mps = -v * sin (a);
    vel.north_mps = v * cos (a);
    orbit.center = &centre;
    orbit.radius_m = r;
    u.entity_id = S_UAV_ID;
    u.name = "uav1";
    u.position = &pos;
    u.velocity = &vel;
    u.heading_deg = s_heading (vel.east_mps, vel.north_mps);
    u.roll_deg = -20;
    u.airspeed_mps = v;
    u.ground_speed_mps = v;
    u.altitude_agl_m = 3000;
    u.commanded_altitude_agl_m = 3000;
    u.commanded_airspeed_mps = v;
    u.mode = CGS__UAV_MODE__UAV_MODE_LOITER;
    u.loiter = &orbit;
    c.sim_time_s = t;
    c.time_scale = 1;
    c.tick = tick;
    c.step_s = S_DWELL_S;
    if (emit (arg, "clock", &c.base, t) < 0)
        return -1;
    return emit (arg, "uav", &u.base, t);
}

/* Dwell d of scan k: its share of the scan's hits, on evenly spaced targets. */
static int s_emit_dwell (s_world_t *w, s_emit_fn *emit, void *arg, long k, int d)
{
    long n = s_scan_hits (w, k), lo = n * d / w->dwells, hi = n * (d + 1) / w->dwells;
    double t = ((double)(k - 1) * w->dwells + d + 0.5) * S_DWELL_S;
    double ua = 40 * t / 3000, ue = 3000 * cos (ua), un = 3000 * sin (ua);
    Cgs__Enu platform = CGS__ENU__INIT;
    platform.east_m = ue;
    platform.north_m = un;
    platform.up_m = 3000;
    long m = 0;
    for (long j = lo; j < hi && m < w->hit_cap; j++, m++) {
        long i = (long)(((int64_t)j * w->ntg / (n > 0 ? n : 1) + k * 7) % w->ntg);
        double p[2], v[2];
        s_target_at (w, i, t, p, v);
        Cgs__Enu *q = &w->hit_pos[m];
        Cgs__MtiHit *h = &w->hit[m];
        cgs__enu__init (q);
        cgs__mti_hit__init (h);
        q->east_m = p[0] + 25 * s_gauss (w);
        q->north_m = p[1] + 25 * s_gauss (w);
        double de = q->east_m - ue, dn = q->north_m - un, range = hypot (de, dn);
        h->hit_id = ++w->hit_id;
        h->position = q;
        h->range_m = hypot (range, 3000);
        h->azimuth_deg = s_heading (de, dn);
        h->radial_velocity_mps = range > 0 ? (de * v[0] + dn * v[1]) / range : 0;
        h->snr_db = 12 + 6 * s_uniform (w);
        h->range_sigma_m = 10;
        h->azimuth_sigma_deg = 0.2;
        h->sim_time_s = t;
        w->hit_ptr[m] = h;
    }
    Cgs__Mti msg = CGS__MTI__INIT;
    msg.uav_id = S_UAV_ID;
    msg.scan_number = (uint32_t)k;
    msg.dwell_number = (uint32_t)d;
    msg.beam_azimuth_deg = 360.0 * d / w->dwells;
    msg.platform_position = &platform;
    msg.n_hits = (size_t)m;
    msg.hits = w->hit_ptr;
    return emit (arg, "mti", &msg.base, t);
}

/* The end of scan k: mti.scan, then every track in batches. */
static int s_emit_scan_end (s_world_t *w, s_emit_fn *emit, void *arg, long k)
{
    double t = (double)k * w->dwells * S_DWELL_S, scan_s = w->dwells * S_DWELL_S;
    Cgs__MtiScan sc = CGS__MTI_SCAN__INIT;
    sc.uav_id = S_UAV_ID;
    sc.scan_number = (uint32_t)k;
    sc.scan_start_s = t - scan_s;
    sc.scan_end_s = t;
    sc.full_revolution = true;
    sc.sector_width_deg = 360;
    sc.hit_count = (uint32_t)s_scan_hits (w, k);
    if (emit (arg, "mti.scan", &sc.base, t) < 0)
        return -1;
    long hp = 0;
    for (long i = 0; i < w->ntg; i++) {
        double p[2], v[2];
        s_target_at (w, i, t, p, v);
        Cgs__Track *m = &w->trk[i];
        cgs__track__init (m);
        cgs__enu__init (&w->trk_pos[i]);
        cgs__enu_velocity__init (&w->trk_vel[i]);
        w->trk_pos[i].east_m = p[0] + 5 * s_gauss (w);
        w->trk_pos[i].north_m = p[1] + 5 * s_gauss (w);
        w->trk_vel[i].east_mps = v[0] + 0.3 * s_gauss (w);
        w->trk_vel[i].north_mps = v[1] + 0.3 * s_gauss (w);
        m->track_id = (uint32_t)(i + 1);
        m->uav_id = S_UAV_ID;
        m->status = CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED;
        bool friendly = i % 5 == 0;
        m->identity = friendly ? CGS__TRACK_IDENTITY__TRACK_IDENTITY_FRIENDLY
                               : CGS__TRACK_IDENTITY__TRACK_IDENTITY_UNKNOWN;
        m->friendly_id = friendly ? (uint32_t)(9000 + i) : 0;
        m->position = &w->trk_pos[i];
        m->velocity = &w->trk_vel[i];
        m->heading_deg = s_heading (w->trk_vel[i].east_mps, w->trk_vel[i].north_mps);
        m->speed_mps = hypot (w->trk_vel[i].east_mps, w->trk_vel[i].north_mps);
        m->hit_count = (uint32_t)k;
        m->last_hit_time_s = t - scan_s / 2;
        m->last_scan_number = (uint32_t)k;
        double *cov = &w->cov[i * 16];
        memset (cov, 0, 16 * sizeof *cov);
        cov[0] = cov[5] = 400;
        cov[10] = cov[15] = 4;
        m->n_covariance = 16;
        m->covariance = cov;
        long first = k - S_TRACK_HISTORY + 1 > 1 ? k - S_TRACK_HISTORY + 1 : 1;
        m->history = &w->hist_ptr[hp];
        for (long s = first; s <= k; s++, hp++) {
            double hpnt[2], hv[2], ht = (double)s * scan_s - scan_s / 2;
            s_target_at (w, i, ht, hpnt, hv);
            Cgs__TrackHistoryPoint *q = &w->hist[hp];
            cgs__track_history_point__init (q);
            cgs__enu__init (&w->hist_pos[hp]);
            w->hist_pos[hp].east_m = hpnt[0] + 25 * s_gauss (w);
            w->hist_pos[hp].north_m = hpnt[1] + 25 * s_gauss (w);
            q->position = &w->hist_pos[hp];
            q->sim_time_s = ht;
            q->scan_number = (uint32_t)s;
            q->hit_id = (uint32_t)(s * 100000 + i);
            w->hist_ptr[hp] = q;
            m->n_history++;
        }
        w->trk_ptr[i] = m;
    }
    long batches = (w->ntg + S_BATCH_TRACKS - 1) / S_BATCH_TRACKS;
    for (long b = 0; b < batches; b++) {
        Cgs__TrackBatch tb = CGS__TRACK_BATCH__INIT;
        long lo = b * S_BATCH_TRACKS;
        tb.uav_id = S_UAV_ID;
        tb.scan_number = (uint32_t)k;
        tb.batch_index = (uint32_t)b;
        tb.batch_count = (uint32_t)batches;
        tb.n_tracks = (size_t)(w->ntg - lo < S_BATCH_TRACKS ? w->ntg - lo : S_BATCH_TRACKS);
        tb.tracks = &w->trk_ptr[lo];
        if (emit (arg, "track", &tb.base, t) < 0)
            return -1;
    }
    return 0;
}

/* Dwell number g (from 0) of the whole run: clock and UAV, the dwell's hits,
 * and at a scan's last dwell the scan's end and the tracks. */
static int s_world_tick (s_world_t *w, s_emit_fn *emit, void *arg, uint64_t g)
{
    long k = (long)(g / (uint64_t)w->dwells) + 1;
    int d = (int)(g % (uint64_t)w->dwells);
    if (s_emit_uav (w, emit, arg, g + 1, (double)(g + 1) * S_DWELL_S) < 0 ||
        s_emit_dwell (w, emit, arg, k, d) < 0)
        return -1;
    return d == w->dwells - 1 ? s_emit_scan_end (w, emit, arg, k) : 0;
}

/* ---- 1. st_state_json in process ---------------------------------------------------- */

static int s_take (void *arg, const char *topic, ProtobufCMessage *msg, double t_s)
{
    st_state_t *st = arg;
    Cgs__Header h = CGS__HEADER__INIT;
    h.source = "bench";
    h.exercise_id = S_EXERCISE_ID;
    h.epoch = 1;
    h.sim_time_s = t_s;
    int rc = 0;
    if (!strcmp (topic, "clock"))
        st_state_set_time (st, ((Cgs__Clock *)msg)->sim_time_s);
    else if (!strcmp (topic, "uav"))
        rc = st_state_take_uav (st, (Cgs__Uav *)msg, &h);
    else if (!strcmp (topic, "mti"))
        rc = st_state_take_mti (st, (Cgs__Mti *)msg, &h);
    else if (!strcmp (topic, "mti.scan"))
        rc = st_state_take_mti_scan (st, (Cgs__MtiScan *)msg, &h);
    else if (!strcmp (topic, "track"))
        rc = st_state_take_tracks (st, (Cgs__TrackBatch *)msg, &h);
    return rc < 0 ? -1 : 0;
}

/* Build the picture after S_SCANS scans; time st_state_json o->runs times
 * S_JSON_CALLS calls (median of each run into ms); its size into *ret_bytes. */
static int s_in_process (const s_opts_t *o, s_fig_t *ms, size_t *ret_bytes, size_t *ret_hits,
                         size_t *ret_tracks, char *err, size_t errlen)
{
    s_world_t w;
    if (s_world_new (&w, o) < 0) {
        snprintf (err, errlen, "out of memory");
        return -1;
    }
    st_state_params_t sp = {S_HISTORY_SCANS, 5, 60, 30};
    st_state_t *st = st_state_new (&sp);
    int rc = st ? 0 : -1;
    if (rc < 0)
        snprintf (err, errlen, "out of memory");
    for (uint64_t g = 0; rc == 0 && g < (uint64_t)S_SCANS * (uint64_t)w.dwells; g++)
        if (s_world_tick (&w, s_take, st, g) < 0) {
            snprintf (err, errlen, "st_state refused a message of the picture");
            rc = -1;
        }
    if (rc == 0) {
        st_state_prune (st);
        *ret_hits = st_state_hit_count (st);
        *ret_tracks = st_state_track_count (st);
        if (*ret_hits != (size_t)o->hits || *ret_tracks != (size_t)o->tracks) {
            snprintf (err, errlen, "st_state holds %zu hits and %zu tracks, not %ld and %ld",
                      *ret_hits, *ret_tracks, o->hits, o->tracks);
            rc = -1;
        }
    }
    uint64_t seq = 0;
    for (int i = 0; rc == 0 && i < 5; i++) { // warm-up: allocator and caches
        size_t len = 0;
        char *json = st_state_json (st, ++seq, &len);
        if (!json) {
            snprintf (err, errlen, "st_state_json failed");
            rc = -1;
        }
        *ret_bytes = len;
        free (json);
    }
    for (int r = 0; rc == 0 && r < o->runs; r++) {
        double t[S_JSON_CALLS];
        for (int i = 0; i < S_JSON_CALLS && rc == 0; i++) {
            size_t len = 0;
            double t0 = bench_wall_s ();
            char *json = st_state_json (st, ++seq, &len);
            t[i] = (bench_wall_s () - t0) * 1e3;
            if (!json) {
                snprintf (err, errlen, "st_state_json failed");
                rc = -1;
            }
            free (json);
        }
        if (rc == 0)
            s_fig_add (ms, bench_median (t, S_JSON_CALLS));
    }
    st_state_destroy (&st);
    s_world_free (&w);
    return rc;
}

/* ---- 2. the feeder ---------------------------------------------------------------- */

static volatile sig_atomic_t s_stop;

static void s_on_term (int sig)
{
    (void)sig;
    s_stop = 1;
}

typedef struct {
    cgs_pub_t *uavsim, *mtid, *trackerd;
    uint64_t errors;
} s_feed_t;

static int s_publish (void *arg, const char *topic, ProtobufCMessage *msg, double t_s)
{
    s_feed_t *f = arg;
    cgs_pub_t *p = !strcmp (topic, "track")     ? f->trackerd
                   : !strncmp (topic, "mti", 3) ? f->mtid
                                                : f->uavsim;
    if (cgs_pub_send (p, topic, msg, t_s) < 0)
        f->errors++;
    return 0;
}

/* Watch socket i's accepted connections on the PAIR socket *ret (before its
 * bind, so that none is missed); 0 or -1. */
static int s_monitor (void *ctx, cgs_pub_t *pub, int i, void **ret)
{
    char ep[64];
    snprintf (ep, sizeof ep, "inproc://bench-monitor-%d", i);
    if (zmq_socket_monitor (cgs_pub_socket (pub), ep, ZMQ_EVENT_ACCEPTED) < 0)
        return -1;
    *ret = zmq_socket (ctx, ZMQ_PAIR);
    return *ret && zmq_connect (*ret, ep) == 0 ? 0 : -1;
}

/* Wait until each of the n monitored sockets has accepted a connection, at
 * most timeout_s; true when all have. Closes the monitors. */
static bool s_wait_accepted (void **mon, cgs_pub_t **pubs, int n, double timeout_s)
{
    bool seen[4] = {false};
    double end = bench_wall_s () + timeout_s;
    int left = n;
    while (left > 0 && !s_stop && bench_wall_s () < end) {
        zmq_pollitem_t items[4];
        for (int i = 0; i < n; i++)
            items[i] = (zmq_pollitem_t){mon[i], 0, ZMQ_POLLIN, 0};
        if (zmq_poll (items, n, 100) <= 0)
            continue;
        for (int i = 0; i < n; i++) {
            if (!(items[i].revents & ZMQ_POLLIN))
                continue;
            zmq_msg_t m;
            zmq_msg_init (&m);
            int more = 1;
            while (more && zmq_msg_recv (&m, mon[i], 0) >= 0)
                more = zmq_msg_more (&m);
            zmq_msg_close (&m);
            if (!seen[i]) {
                seen[i] = true;
                left--;
            }
        }
    }
    for (int i = 0; i < n; i++) {
        zmq_socket_monitor (cgs_pub_socket (pubs[i]), NULL, 0);
        if (mon[i])
            zmq_close (mon[i]);
        mon[i] = NULL;
    }
    return left == 0;
}

/* The feeder process: publish the world until SIGTERM; 0, or 1 when a
 * publisher failed. Runs in the forked child. */
static int s_feeder (const s_opts_t *o, const char *dir)
{
    struct sigaction sa = {.sa_handler = s_on_term};
    sigaction (SIGTERM, &sa, NULL);
    sigaction (SIGINT, &sa, NULL);
    s_world_t w;
    if (s_world_new (&w, o) < 0) {
        fprintf (stderr, "bench_stationd feeder: out of memory\n");
        return 1;
    }
    void *ctx = zmq_ctx_new ();
    s_feed_t f = {0};
    const char *names[3] = {"uavsim", "mtid.uav1", "trackerd"};
    cgs_pub_t **slots[3] = {&f.uavsim, &f.mtid, &f.trackerd};
    void *mon[3] = {NULL, NULL, NULL};
    int rc = ctx ? 0 : 1;
    for (int i = 0; i < 3 && rc == 0; i++) {
        char ep[PATH_MAX];
        snprintf (ep, sizeof ep, "ipc://%s/%s.pub", dir, names[i]);
        *slots[i] = cgs_pub_new (ctx, names[i], S_EXERCISE_ID);
        if (!*slots[i] || s_monitor (ctx, *slots[i], i, &mon[i]) < 0 ||
            cgs_pub_bind (*slots[i], ep) < 0) {
            fprintf (stderr, "bench_stationd feeder: cannot publish on %s\n", ep);
            rc = 1;
        }
    }
    cgs_pub_t *pubs[3] = {f.uavsim, f.mtid, f.trackerd};
    if (rc == 0 && !s_wait_accepted (mon, pubs, 3, 30) && !s_stop) {
        fprintf (stderr, "bench_stationd feeder: stationd did not connect in 30 s\n");
        rc = 1;
    }
    // Its subscriptions follow the connection at once; leave them time to land.
    struct timespec settle = {0, 300 * 1000 * 1000};
    nanosleep (&settle, NULL);
    uint64_t g = 0, full = (uint64_t)S_SCANS * (uint64_t)w.dwells;
    for (; rc == 0 && !s_stop && g < full; g++) // the first 21 scans at once
        s_world_tick (&w, s_publish, &f, g);
    struct timespec next;
    clock_gettime (CLOCK_MONOTONIC, &next);
    while (rc == 0 && !s_stop) { // then in real time
        s_world_tick (&w, s_publish, &f, g++);
        next.tv_nsec += (long)(S_DWELL_S * 1e9);
        if (next.tv_nsec >= 1000000000) {
            next.tv_nsec -= 1000000000;
            next.tv_sec++;
        }
        while (!s_stop && clock_nanosleep (CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL) == EINTR) {
        }
    }
    uint64_t drops = 0;
    for (int i = 0; i < 3; i++) {
        drops += pubs[i] ? cgs_pub_drops (pubs[i]) : 0;
        if (mon[i]) { // closed already when the wait ran
            zmq_socket_monitor (cgs_pub_socket (pubs[i]), NULL, 0);
            zmq_close (mon[i]);
        }
    }
    if (rc == 0 && (f.errors || drops)) {
        fprintf (stderr, "bench_stationd feeder: %llu sends failed, %llu messages dropped\n",
                 (unsigned long long)f.errors, (unsigned long long)drops);
        rc = 1;
    }
    for (int i = 0; i < 3; i++)
        cgs_pub_destroy (slots[i]);
    if (ctx)
        zmq_ctx_term (ctx);
    s_world_free (&w);
    return rc;
}

/* ---- processes ------------------------------------------------------------------- */

/* Stop a child: SIGTERM, then SIGKILL after grace_s; its wait status, or -1. */
static int s_stop_child (pid_t pid, double grace_s)
{
    if (pid <= 0)
        return -1;
    kill (pid, SIGTERM);
    double end = bench_wall_s () + grace_s;
    int status = 0;
    for (;;) {
        pid_t r = waitpid (pid, &status, WNOHANG);
        if (r == pid)
            return status;
        if (r < 0 && errno != EINTR)
            return -1;
        if (bench_wall_s () > end) {
            kill (pid, SIGKILL);
            while (waitpid (pid, &status, 0) < 0 && errno == EINTR) {
            }
            return -1;
        }
        struct timespec ts = {0, 20 * 1000 * 1000};
        nanosleep (&ts, NULL);
    }
}

/* True while the child runs (reaps it, into *status, when it has ended). */
static bool s_alive (pid_t pid, int *status)
{
    return waitpid (pid, status, WNOHANG) == 0;
}

static const char *s_status_text (int status, char *buf, size_t size)
{
    if (WIFEXITED (status))
        snprintf (buf, size, "exited with %d", WEXITSTATUS (status));
    else if (WIFSIGNALED (status))
        snprintf (buf, size, "killed by signal %d", WTERMSIG (status));
    else
        snprintf (buf, size, "ended (status %d)", status);
    return buf;
}

/* A TCP port on 127.0.0.1 free now (the kernel's pick), or -1. */
static int s_free_port (void)
{
    int fd = socket (AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_addr.s_addr = htonl (INADDR_LOOPBACK)};
    socklen_t len = sizeof a;
    int port = -1;
    if (fd >= 0 && bind (fd, (struct sockaddr *)&a, sizeof a) == 0 &&
        getsockname (fd, (struct sockaddr *)&a, &len) == 0)
        port = ntohs (a.sin_port);
    if (fd >= 0)
        close (fd);
    return port;
}

static bool s_port_open (int port)
{
    int fd = socket (AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    struct sockaddr_in a = {.sin_family = AF_INET,
                            .sin_port = htons ((uint16_t)port),
                            .sin_addr.s_addr = htonl (INADDR_LOOPBACK)};
    bool ok = fd >= 0 && connect (fd, (struct sockaddr *)&a, sizeof a) == 0;
    if (fd >= 0)
        close (fd);
    return ok;
}

static int s_rm (const char *path, const struct stat *st, int flag, struct FTW *ftw)
{
    (void)st, (void)flag, (void)ftw;
    remove (path);
    return 0;
}

/* The last lines of a file to stdout, indented (stationd's log on failure). */
static void s_tail (const char *path, int lines)
{
    FILE *f = fopen (path, "r");
    if (!f)
        return;
    char buf[64][512];
    int n = 0;
    while (fgets (buf[n % 64], sizeof buf[0], f))
        n++;
    fclose (f);
    int first = n > lines ? n - lines : 0;
    for (int i = first; i < n; i++)
        printf ("    | %s", buf[i % 64]);
}

/* The folder this program is in. */
static void s_exe_dir (char *buf, size_t size)
{
    ssize_t n = readlink ("/proc/self/exe", buf, size - 1);
    buf[n > 0 ? n : 0] = '\0';
    char *slash = strrchr (buf, '/');
    if (slash)
        *slash = '\0';
}

/* ---- 3. one run of the page, through node -------------------------------------------- */

typedef struct {
    double push_hz_ws, push_hz_page, apply_median, apply_p95, apply_max, lag_median, lag_p95;
    double parse_ms, push_bytes, hits_min, hits_max, tracks, over_goal, updates, missed;
    double cpu_machine, cpu_stationd, cpu_chromium, scan_end, between, hz_ws_mean;
} s_run_t;

static void s_run_set (s_run_t *r, const char *key, double v)
{
    static const struct {
        const char *key;
        size_t off;
    } keys[] = {
        {"push_hz_ws", offsetof (s_run_t, push_hz_ws)},
        {"push_hz_page", offsetof (s_run_t, push_hz_page)},
        {"apply_ms_median", offsetof (s_run_t, apply_median)},
        {"apply_ms_p95", offsetof (s_run_t, apply_p95)},
        {"apply_ms_max", offsetof (s_run_t, apply_max)},
        {"lag_ms_median", offsetof (s_run_t, lag_median)},
        {"lag_ms_p95", offsetof (s_run_t, lag_p95)},
        {"parse_ms", offsetof (s_run_t, parse_ms)},
        {"push_bytes", offsetof (s_run_t, push_bytes)},
        {"hits_min", offsetof (s_run_t, hits_min)},
        {"hits_max", offsetof (s_run_t, hits_max)},
        {"tracks", offsetof (s_run_t, tracks)},
        {"apply_over_goal", offsetof (s_run_t, over_goal)},
        {"page_updates", offsetof (s_run_t, updates)},
        {"page_missed", offsetof (s_run_t, missed)},
        {"cpu_machine_pct", offsetof (s_run_t, cpu_machine)},
        {"cpu_stationd_pct", offsetof (s_run_t, cpu_stationd)},
        {"cpu_chromium_pct", offsetof (s_run_t, cpu_chromium)},
        {"apply_ms_scan_end_median", offsetof (s_run_t, scan_end)},
        {"apply_ms_between_median", offsetof (s_run_t, between)},
        {"push_hz_ws_mean", offsetof (s_run_t, hz_ws_mean)},
    };
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        if (!strcmp (key, keys[i].key))
            *(double *)((char *)r + keys[i].off) = v;
}

/* Run the script once; its figures into *r. 0, or -1 with why in err. */
static int s_page_run (const char *root, int port, pid_t stationd, const s_opts_t *o, bool profile,
                       s_run_t *r, char *err, size_t errlen)
{
    char script[PATH_MAX], url[64], seconds[32], hits[32], tracks[32], pid[32], prof[16];
    snprintf (script, sizeof script, "%s/tests/bench/bench_stationd.js", root);
    snprintf (url, sizeof url, "http://127.0.0.1:%d/", port);
    snprintf (seconds, sizeof seconds, "%ld", o->seconds);
    snprintf (hits, sizeof hits, "%ld", o->hits);
    snprintf (tracks, sizeof tracks, "%ld", o->tracks);
    snprintf (pid, sizeof pid, "%d", (int)stationd);
    snprintf (prof, sizeof prof, "%d", profile ? S_PROFILE_S : 0);
    char *argv[] = {
        "node",           script, "--url",     url,    "--seconds",  seconds,
        "--hits",         hits,   "--tracks",  tracks, "--viewport", (char *)o->viewport,
        "--stationd-pid", pid,    "--profile", prof,   NULL};
    int fds[2];
    if (pipe2 (fds, O_CLOEXEC) < 0) {
        snprintf (err, errlen, "pipe: %s", strerror (errno));
        return -1;
    }
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init (&fa);
    posix_spawn_file_actions_adddup2 (&fa, fds[1], 1);
    posix_spawn_file_actions_addopen (&fa, 0, "/dev/null", O_RDONLY, 0);
    pid_t node;
    fflush (NULL);
    int rc = posix_spawnp (&node, "node", &fa, NULL, argv, environ);
    posix_spawn_file_actions_destroy (&fa);
    close (fds[1]);
    if (rc != 0) {
        close (fds[0]);
        snprintf (err, errlen, "cannot run node: %s", strerror (rc));
        return -1;
    }
    *r = (s_run_t){.push_hz_ws = NAN,
                   .push_hz_page = NAN,
                   .apply_median = NAN,
                   .scan_end = NAN,
                   .between = NAN,
                   .hz_ws_mean = NAN,
                   .lag_median = NAN,
                   .lag_p95 = NAN,
                   .parse_ms = NAN};
    // Its lines as they come: figures kept, the rest echoed indented.
    char buf[65536], last_error[512] = "";
    size_t have = 0;
    double deadline = bench_wall_s () + (double)o->seconds + S_PROFILE_S + 180;
    bool timed_out = false;
    for (;;) {
        struct pollfd p = {fds[0], POLLIN, 0};
        int left_ms = (int)((deadline - bench_wall_s ()) * 1000);
        int pr = left_ms > 0 ? poll (&p, 1, left_ms) : 0;
        if (pr < 0 && errno == EINTR)
            continue;
        if (pr <= 0) {
            timed_out = pr == 0;
            break;
        }
        ssize_t n = read (fds[0], buf + have, sizeof buf - 1 - have);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            break;
        have += (size_t)n;
        buf[have] = '\0';
        char *line = buf, *nl;
        while ((nl = strchr (line, '\n')) || (line == buf && have == sizeof buf - 1)) {
            if (nl)
                *nl = '\0'; // else a line longer than the buffer: taken as it is
            char key[64];
            double v;
            if (sscanf (line, "fig %63[^=]=%lf", key, &v) == 2)
                s_run_set (r, key, v);
            else
                printf ("    %s\n", line);
            if (!strncmp (line, "error ", 6))
                snprintf (last_error, sizeof last_error, "%s", line + 6);
            line = nl ? nl + 1 : buf + have;
        }
        have -= (size_t)(line - buf);
        memmove (buf, line, have);
        fflush (stdout);
    }
    if (timed_out)
        kill (node, SIGKILL);
    close (fds[0]);
    int status = 0;
    while (waitpid (node, &status, 0) < 0 && errno == EINTR) {
    }
    if (timed_out) {
        snprintf (err, errlen, "the page script took too long; killed");
        return -1;
    }
    if (!WIFEXITED (status) || WEXITSTATUS (status) != 0) {
        char st[64];
        snprintf (err, errlen, "the page script %s%s%s", s_status_text (status, st, sizeof st),
                  *last_error ? ": " : "", last_error);
        return -1;
    }
    if (!isfinite (r->push_hz_ws) || !isfinite (r->push_hz_page) || !isfinite (r->apply_median)) {
        snprintf (err, errlen, "the page script gave no push rate or apply time");
        return -1;
    }
    if (r->push_hz_ws <= 0 || r->updates <= 0) {
        snprintf (err, errlen, "no updates in the measured window");
        return -1;
    }
    return 0;
}

/* ---- main ---------------------------------------------------------------------------- */

static void s_usage (FILE *f)
{
    fprintf (
        f,
        "usage: bench_stationd [options]\n"
        "  --runs R         page runs (and in-process timings); medians, min and max (default 3)\n"
        "  --seconds S      measured window of each page run (default 20)\n"
        "  --scan-s S       radar scan period, simulation seconds, a multiple of 0.1 (default 2)\n"
        "  --hits N         hits on the map: in 21 consecutive scans (default 5000)\n"
        "  --tracks N       confirmed tracks (default 1000)\n"
        "  --viewport WxH   the browser's window (default 1920x1080)\n"
        "Environment: CGS_ROOT (source tree: the page script), CGS_BUILD (build folder:\n"
        "bin/stationd; default the folder above this program's).\n"
        "Other options that take a value (meant for other benchmarks) are ignored.\n");
}

static void s_keys (const char *key, const s_fig_t *f, int decimals)
{
    printf ("%s=%.*f\n%s_min=%.*f\n%s_max=%.*f\n", key, decimals, f->median, key, decimals, f->min,
            key, decimals, f->max);
}

int main (int argc, char **argv)
{
    s_opts_t o = {.runs = 3, .seconds = 20, .scan_s = 2, .hits = 5000, .tracks = 1000};
    snprintf (o.viewport, sizeof o.viewport, "1920x1080");
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp (a, "--help") || !strcmp (a, "-h")) {
            s_usage (stdout);
            return 0;
        }
        long n = 0;
        bool ok = true;
        if (!strcmp (a, "--runs") && (ok = bench_parse_long (v, 1, S_MAX_RUNS, &n)))
            o.runs = (int)n;
        else if (!strcmp (a, "--seconds"))
            ok = bench_parse_long (v, 2, 3600, &o.seconds);
        else if (!strcmp (a, "--scan-s")) {
            char *end = NULL;
            double s = v ? strtod (v, &end) : 0;
            double d = s / S_DWELL_S;
            ok = v && end != v && !*end && s >= S_DWELL_S && s <= 60 && fabs (d - round (d)) < 1e-6;
            if (ok)
                o.scan_s = s;
        } else if (!strcmp (a, "--hits"))
            ok = bench_parse_long (v, S_SCANS, 1000000, &o.hits);
        else if (!strcmp (a, "--tracks"))
            ok = bench_parse_long (v, 1, 100000, &o.tracks);
        else if (!strcmp (a, "--viewport")) {
            int w = 0, h = 0;
            char extra;
            ok = v && sscanf (v, "%dx%d%c", &w, &h, &extra) == 2 && w >= 320 && h >= 240 &&
                 w <= 7680 && h <= 4320;
            if (ok)
                snprintf (o.viewport, sizeof o.viewport, "%dx%d", w, h);
        } else if (strncmp (a, "--", 2) != 0 || !v)
            ok = false; // not an option, or one without its value
        if (!ok) {
            fprintf (stderr, "bench_stationd: bad option or value: %s %s\n", a, v ? v : "");
            s_usage (stderr);
            return 2;
        }
        i++; // every option takes a value
    }
    signal (SIGPIPE, SIG_IGN);
    long cores = sysconf (_SC_NPROCESSORS_ONLN);
    char err[1024] = "";
    bool broke = false;

    // Where things are: the build (stationd, the page) and the source tree (the script).
    char exe_dir[PATH_MAX], build[PATH_MAX], root[PATH_MAX], stationd_bin[PATH_MAX + 16];
    s_exe_dir (exe_dir, sizeof exe_dir);
    const char *env_build = getenv ("CGS_BUILD");
    if (env_build && *env_build)
        snprintf (build, sizeof build, "%s", env_build);
    else
        snprintf (build, sizeof build, "%s/..", exe_dir);
    snprintf (stationd_bin, sizeof stationd_bin, "%s/bin/stationd", build);
    const char *env_root = getenv ("CGS_ROOT");
    if (env_root && *env_root)
        snprintf (root, sizeof root, "%s", env_root);
    else {
        char guess[PATH_MAX + 8];
        snprintf (guess, sizeof guess, "%s/../../..", exe_dir);
        if (!realpath (guess, root))
            snprintf (root, sizeof root, "%s", guess);
        setenv ("CGS_ROOT", root, 1); // the script finds its packages through it
    }

    printf ("bench_stationd: %ld cores; %d runs of %ld s; %ld hits on the map (21 scans of about "
            "%ld, one radar, a scan every %.1f s) and %ld confirmed tracks; page %s\n",
            cores, o.runs, o.seconds, o.hits, o.hits / S_SCANS, o.scan_s, o.tracks, o.viewport);
    fflush (stdout);

    // 1. The picture's JSON, in process, before anything else runs.
    s_fig_t json_ms = {0};
    size_t picture_bytes = 0, st_hits = 0, st_tracks = 0;
    if (s_in_process (&o, &json_ms, &picture_bytes, &st_hits, &st_tracks, err, sizeof err) < 0)
        broke = true;
    s_fig_done (&json_ms);
    if (!broke)
        printf ("  picture build, in process (st_state_json of %zu hits and %zu tracks): median "
                "%.2f ms (runs %.2f..%.2f), %zu bytes\n",
                st_hits, st_tracks, json_ms.median, json_ms.min, json_ms.max, picture_bytes);
    fflush (stdout);

    // 2. stationd and its feed.
    char dir[PATH_MAX] = "", ex[PATH_MAX + 32] = "", logf[PATH_MAX + 32] = "";
    pid_t feeder = -1, stationd = -1;
    int port = -1;
    struct stat sb;
    char script[PATH_MAX + 32];
    snprintf (script, sizeof script, "%s/tests/bench/bench_stationd.js", root);
    if (!broke && stat (script, &sb) != 0) {
        snprintf (err, sizeof err, "no page script at %s (set CGS_ROOT to the source tree)",
                  script);
        broke = true;
    }
    if (!broke && (stat (stationd_bin, &sb) != 0 || !(sb.st_mode & S_IXUSR))) {
        snprintf (err, sizeof err, "no stationd at %s (build it: make O=... all)", stationd_bin);
        broke = true;
    }
    if (!broke) {
        const char *tmp = getenv ("TMPDIR") && *getenv ("TMPDIR") ? getenv ("TMPDIR") : "/tmp";
        snprintf (dir, sizeof dir, "%s/cgs-bench-stationd-XXXXXX", tmp);
        if (strlen (dir) > 70 || !mkdtemp (dir)) {
            snprintf (err, sizeof err,
                      "cannot make a temporary folder (for ipc:// paths of at "
                      "most 108 bytes) under %s",
                      tmp);
            dir[0] = '\0';
            broke = true;
        }
    }
    if (!broke) {
        snprintf (ex, sizeof ex, "%s/exercise.ini", dir);
        snprintf (logf, sizeof logf, "%s/stationd.log", dir);
        FILE *f = fopen (ex, "w");
        if (f) {
            fprintf (f,
                     "; bench_stationd: stationd and the three publishers the benchmark plays\n"
                     "[exercise]\nid = %d\nname = bench-stationd\norigin = geo 35.9600 "
                     "-121.2300 0\ntime_scale = 1\nseed = 1\nstate_dir = %s/state\n\n"
                     "[service uavsim]\npublish = ipc://%s/uavsim.pub\n\n"
                     "[service mtid.uav1]\npublish = ipc://%s/mtid.uav1.pub\nuav = uav1\n\n"
                     "[service trackerd]\npublish = ipc://%s/trackerd.pub\n\n"
                     "[service stationd]\npublish = ipc://%s/stationd.pub\n",
                     S_EXERCISE_ID, dir, dir, dir, dir, dir);
            if (fclose (f) != 0)
                f = NULL;
        }
        if (!f) {
            snprintf (err, sizeof err, "cannot write %s", ex);
            broke = true;
        }
    }
    if (!broke && (port = s_free_port ()) < 0) {
        snprintf (err, sizeof err, "no free TCP port");
        broke = true;
    }
    if (!broke) {
        fflush (NULL);
        feeder = fork ();
        if (feeder == 0)
            _exit (s_feeder (&o, dir));
        if (feeder < 0) {
            snprintf (err, sizeof err, "fork: %s", strerror (errno));
            broke = true;
        }
    }
    if (!broke) {
        char portarg[16];
        snprintf (portarg, sizeof portarg, "%d", port);
        char *sargv[] = {stationd_bin, "--exercise", ex,      "--instance",
                         "stationd",   "--port",     portarg, NULL};
        posix_spawn_file_actions_t fa;
        posix_spawn_file_actions_init (&fa);
        posix_spawn_file_actions_addopen (&fa, 0, "/dev/null", O_RDONLY, 0);
        posix_spawn_file_actions_addopen (&fa, 1, logf, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        posix_spawn_file_actions_adddup2 (&fa, 1, 2);
        int rc = posix_spawn (&stationd, stationd_bin, &fa, NULL, sargv, environ);
        posix_spawn_file_actions_destroy (&fa);
        if (rc != 0) {
            stationd = -1;
            snprintf (err, sizeof err, "cannot start %s: %s", stationd_bin, strerror (rc));
            broke = true;
        }
    }
    if (!broke) { // its web server up within 30 s
        double end = bench_wall_s () + 30;
        int status = 0;
        while (!s_port_open (port)) {
            if (!s_alive (stationd, &status)) {
                char st[64];
                snprintf (err, sizeof err, "stationd %s at start (its log above)",
                          s_status_text (status, st, sizeof st));
                stationd = -1;
                s_tail (logf, 20);
                broke = true;
                break;
            }
            if (bench_wall_s () > end) {
                snprintf (err, sizeof err, "stationd did not listen on port %d in 30 s", port);
                s_tail (logf, 20);
                broke = true;
                break;
            }
            struct timespec ts = {0, 50 * 1000 * 1000};
            nanosleep (&ts, NULL);
        }
    }
    if (!broke)
        printf ("  stationd (pid %d) at http://127.0.0.1:%d/, fed by pid %d; folder %s\n",
                (int)stationd, port, (int)feeder, dir);
    fflush (stdout);

    // 3. The runs.
    s_fig_t hz_ws = {0}, hz_page = {0}, ap_med = {0}, ap_p95 = {0}, ap_max = {0}, lag_med = {0},
            lag_p95 = {0}, parse = {0}, bytes = {0}, cpu_m = {0}, cpu_s = {0}, cpu_c = {0},
            ap_scan = {0}, ap_between = {0}, hz_mean = {0};
    double hits_min = INFINITY, hits_max = 0, over = 0, updates = 0, missed = 0, tracks_seen = 0;
    for (int r = 0; r < o.runs && !broke; r++) {
        printf ("  run %d:\n", r + 1);
        fflush (stdout);
        s_run_t run;
        if (s_page_run (root, port, stationd, &o, r == 0, &run, err, sizeof err) < 0) {
            broke = true;
            break;
        }
        int status = 0;
        if (!s_alive (stationd, &status)) {
            char st[64];
            snprintf (err, sizeof err, "stationd %s during run %d (its log above)",
                      s_status_text (status, st, sizeof st), r + 1);
            stationd = -1;
            s_tail (logf, 20);
            broke = true;
            break;
        }
        if (!s_alive (feeder, &status)) {
            snprintf (err, sizeof err, "the feeder stopped during run %d", r + 1);
            feeder = -1;
            broke = true;
            break;
        }
        s_fig_add (&hz_ws, run.push_hz_ws);
        s_fig_add (&hz_page, run.push_hz_page);
        s_fig_add (&ap_med, run.apply_median);
        s_fig_add (&ap_p95, run.apply_p95);
        s_fig_add (&ap_max, run.apply_max);
        s_fig_add (&lag_med, run.lag_median);
        s_fig_add (&lag_p95, run.lag_p95);
        s_fig_add (&parse, run.parse_ms);
        s_fig_add (&bytes, run.push_bytes);
        s_fig_add (&cpu_m, run.cpu_machine);
        s_fig_add (&cpu_s, run.cpu_stationd);
        s_fig_add (&cpu_c, run.cpu_chromium);
        s_fig_add (&ap_scan, run.scan_end);
        s_fig_add (&ap_between, run.between);
        s_fig_add (&hz_mean, run.hz_ws_mean);
        hits_min = fmin (hits_min, run.hits_min);
        hits_max = fmax (hits_max, run.hits_max);
        tracks_seen = run.tracks;
        over += run.over_goal;
        updates += run.updates;
        missed += run.missed;
    }

    // Stop stationd and the feeder; the feeder's status says whether it lost anything.
    if (stationd > 0) {
        int status = s_stop_child (stationd, 5);
        if (!broke && (status < 0 || !WIFEXITED (status) || WEXITSTATUS (status) != 0)) {
            char st[64];
            snprintf (err, sizeof err, "stationd did not stop cleanly (%s)",
                      status < 0 ? "killed after 5 s" : s_status_text (status, st, sizeof st));
            s_tail (logf, 20);
            broke = true;
        }
    }
    if (feeder > 0) {
        int status = s_stop_child (feeder, 5);
        if (!broke && (status < 0 || !WIFEXITED (status) || WEXITSTATUS (status) != 0)) {
            snprintf (err, sizeof err, "the feeder failed (see its message above)");
            broke = true;
        }
    }
    if (*dir)
        nftw (dir, s_rm, 16, FTW_DEPTH | FTW_PHYS);

    if (broke) {
        printf ("\n--- figures ---\nverdict=FAIL (%s)\n", err);
        return 1;
    }
    s_fig_t *all[] = {&hz_ws, &hz_page, &ap_med, &ap_p95, &ap_max,  &lag_med,    &lag_p95, &parse,
                      &bytes, &cpu_m,   &cpu_s,  &cpu_c,  &ap_scan, &ap_between, &hz_mean};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        s_fig_done (all[i]);
    bool hz_ok = hz_ws.median >= S_GOAL_HZ && hz_page.median >= S_GOAL_HZ;
    bool ap_ok = ap_max.max < S_GOAL_APPLY_MS; // each update, over every run

    printf ("\n");
    printf ("  pushes received by a WebSocket client  median %5.1f Hz (runs %.1f..%.1f): goal %.0f "
            "Hz %s\n",
            hz_ws.median, hz_ws.min, hz_ws.max, S_GOAL_HZ,
            hz_ws.median >= S_GOAL_HZ ? "met" : "NOT met");
    printf ("  updates applied by the page            median %5.1f Hz (runs %.1f..%.1f): goal %.0f "
            "Hz %s\n",
            hz_page.median, hz_page.min, hz_page.max, S_GOAL_HZ,
            hz_page.median >= S_GOAL_HZ ? "met" : "NOT met");
    printf ("  apply time of an update (page)         median %5.1f ms, p95 %.1f ms (runs "
            "%.1f..%.1f), max %.1f ms: goal under %.0f ms %s\n",
            ap_med.median, ap_p95.median, ap_p95.min, ap_p95.max, ap_max.max, S_GOAL_APPLY_MS,
            ap_ok ? "met" : "NOT met");
    char split[128] = "";
    if (isfinite (ap_scan.median))
        snprintf (split, sizeof split,
                  "updates at a scan's end: median %.1f ms, the others %.1f ms; ", ap_scan.median,
                  ap_between.median);
    printf ("    (%.0f of %.0f updates took %.0f ms or more; %sJSON.parse alone %.1f ms; push to "
            "applied: median %.1f ms, p95 %.1f ms; %.0f pushes the page missed)\n",
            over, updates, S_GOAL_APPLY_MS, split, parse.median, lag_med.median, lag_p95.median,
            missed);
    printf ("    (picture %.0f bytes pushed; st_state_json %.2f ms of the %.0f ms between pushes; "
            "CPU over the window: machine %.0f%% of %ld cores, stationd %.0f%%, Chromium %.0f%% "
            "of one core)\n",
            bytes.median, json_ms.median, 1000 / S_GOAL_HZ, cpu_m.median, cores, cpu_s.median,
            cpu_c.median);

    printf ("\n--- figures ---\n");
    printf ("cores=%ld\nruns=%d\nseconds_per_run=%ld\nscan_s=%.1f\nviewport=%s\n", cores, o.runs,
            o.seconds, o.scan_s, o.viewport);
    printf (
        "hits=%zu\ntracks=%zu\nhits_on_page_min=%.0f\nhits_on_page_max=%.0f\ntracks_on_page=%.0f\n",
        st_hits, st_tracks, hits_min, hits_max, tracks_seen);
    s_keys ("json_build_ms_median", &json_ms, 3);
    printf ("picture_bytes=%zu\n", picture_bytes);
    s_keys ("push_bytes", &bytes, 0);
    s_keys ("push_hz_ws", &hz_ws, 2);
    s_keys ("push_hz_ws_mean", &hz_mean, 2);
    s_keys ("push_hz_page", &hz_page, 2);
    s_keys ("apply_ms_median", &ap_med, 1);
    s_keys ("apply_ms_p95", &ap_p95, 1);
    s_keys ("apply_ms_max", &ap_max, 1);
    s_keys ("apply_ms_scan_end_median", &ap_scan, 1);
    s_keys ("apply_ms_between_median", &ap_between, 1);
    printf ("apply_over_goal=%.0f\npage_updates=%.0f\npage_missed=%.0f\n", over, updates, missed);
    s_keys ("parse_ms", &parse, 1);
    s_keys ("lag_ms_median", &lag_med, 1);
    s_keys ("lag_ms_p95", &lag_p95, 1);
    s_keys ("cpu_machine_pct", &cpu_m, 0);
    s_keys ("cpu_stationd_pct", &cpu_s, 0);
    s_keys ("cpu_chromium_pct", &cpu_c, 0);
    printf ("goal_push_hz=%.0f\ngoal_apply_ms=%.0f\n", S_GOAL_HZ, S_GOAL_APPLY_MS);
    printf ("verdict=%s\n", hz_ok && ap_ok ? "PASS" : "BELOW-GOAL");
    printf ("  (push rate goal %s, apply time goal %s)\n", hz_ok ? "met" : "NOT met",
            ap_ok ? "met" : "NOT met");
    return 0;
}
