/* test_gw_gmti — the radars' bus messages as STANAG 4607 packets, read back
 * by a reader written here from the standard's layout (not the encoder's):
 * the 32-byte packet header, then segments behind a type (E8) and size (I32)
 * header: Mission (44 bytes), Job Definition (73), Platform Location (28) and
 * Dwell with its existence mask (D2 at bit 63 .. D31 at bit 34, D32.1 at bit
 * 33 .. D32.18 at bit 16) and target reports. Checked against values worked
 * by hand: the first dwell of a radar carries the mission and the job, the
 * next one a dwell only; job id the UAV's entity id; exercise indicator 129;
 * revisit and dwell index the scan and dwell numbers; a hit at the exercise
 * origin has SA32 latitude round(35.96 * 2^31 / 90) = 858039022 and BA32
 * longitude round(238.77 * 2^32 / 360) = 2848637059 (every other hit the
 * same formulas over cgs_geo's geodetic position, as Wireshark reads SA32);
 * LOS velocity round(v * 100) cm/s; times in ms since midnight of the
 * reference date (clock UTC 2026-11-27T10:00:00Z at simulation 0: a dwell
 * centred at t is 36,000,000 + 1000 t ms). With truth tags, a dwell waits for
 * the truth of its own (uav, scan, dwell); the tags are entity_id_base +
 * the entity of the truth item whose hit it is, 0 for a false alarm; the
 * second gw_gmti_tick, the radar's next dwell or gw_gmti_flush sends it
 * without the truth tag fields, counted. Platform locations at
 * platform_rate_hz of simulation time once the job started, with the mission
 * and job again 60 s of simulation time after they last went out. A
 * dwell of 3000 hits fills a first packet (2591 reports after the mission and
 * job) and a second (409), each at most 65,000 bytes. A dwell without a
 * platform position or with non-finite times is refused, nothing sent. */
#include "cgs_geo.h"
#include "gw_gmti.h"
#include "gw_params.h"

#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_util.h"

#define S_EXERCISE  42
#define S_UAV_ID    7
#define S_CLOCK_UTC 1795773600.0 // 2026-11-27T10:00:00Z (20784 days and 10 h past 1970)
#define S_MIDNIGHT  36000000.0   // ms from that day's midnight to 10:00
#define S_PKT_MAX   65000        // one UDP datagram, as the header says
#define S_PACKETS   64
#define S_SEGMENTS  8
#define S_TWO_31    2147483648.0
#define S_TWO_32    4294967296.0
#define S_DEG       (M_PI / 180.0)
#define S_MASK_D(n) (UINT64_C (1) << (63 - ((n)-2))) // D2 .. D31
#define S_MASK_R(k) (UINT64_C (1) << (33 - ((k)-1))) // D32.1 .. D32.18

/* ---- what the translator sends ------------------------------------------------------------- */

typedef struct {
    uint8_t *b[S_PACKETS];
    size_t len[S_PACKETS];
    size_t n;
} s_sink_t;

static void s_emit (void *arg, const uint8_t *packet, size_t len)
{
    s_sink_t *s = arg;
    assert_true (s->n < S_PACKETS);
    assert_true (len <= S_PKT_MAX);
    s->b[s->n] = malloc (len);
    assert_non_null (s->b[s->n]);
    memcpy (s->b[s->n], packet, len);
    s->len[s->n++] = len;
}

static void s_sink_clear (s_sink_t *s)
{
    for (size_t i = 0; i < s->n; i++)
        free (s->b[i]);
    s->n = 0;
}

/* ---- a STANAG 4607 reader, big-endian, from the standard's tables ------------------------------
 */

typedef struct {
    const uint8_t *b;
    size_t len, at;
} s_rd_t;

/* n bytes big-endian, unsigned; fails the test past the end. */
static uint64_t s_u (s_rd_t *r, size_t n)
{
    if (r->at + n > r->len)
        fail_msg ("read of %zu bytes at %zu runs past %zu", n, r->at, r->len);
    uint64_t v = 0;
    for (size_t i = 0; i < n; i++)
        v = v << 8 | r->b[r->at++];
    return v;
}

/* n bytes of text, space padding removed. */
static void s_text (s_rd_t *r, size_t n, char *out)
{
    for (size_t i = 0; i < n; i++)
        out[i] = (char)s_u (r, 1);
    out[n] = '\0';
    while (n && out[n - 1] == ' ')
        out[--n] = '\0';
}

typedef struct {
    char version[3], nationality[3], class_system[3], platform_id[11];
    uint32_t size, mission_id, job_id;
    uint8_t classification, exercise;
    uint16_t class_code;
    size_t nseg;
    uint8_t type[S_SEGMENTS];
    size_t off[S_SEGMENTS]; // of the segment's header
    uint32_t size_of[S_SEGMENTS];
} s_packet_t;

/* The header (P1-P10), then the segments, which must tile the packet exactly. */
static void s_packet (const uint8_t *b, size_t len, s_packet_t *p)
{
    memset (p, 0, sizeof *p);
    s_rd_t r = {b, len, 0};
    s_text (&r, 2, p->version);
    p->size = (uint32_t)s_u (&r, 4);
    s_text (&r, 2, p->nationality);
    p->classification = (uint8_t)s_u (&r, 1);
    s_text (&r, 2, p->class_system);
    p->class_code = (uint16_t)s_u (&r, 2);
    p->exercise = (uint8_t)s_u (&r, 1);
    s_text (&r, 10, p->platform_id);
    p->mission_id = (uint32_t)s_u (&r, 4);
    p->job_id = (uint32_t)s_u (&r, 4);
    assert_int_equal (r.at, 32);
    assert_int_equal (p->size, len);
    while (r.at < len) {
        assert_true (p->nseg < S_SEGMENTS);
        p->off[p->nseg] = r.at;
        p->type[p->nseg] = (uint8_t)s_u (&r, 1);
        p->size_of[p->nseg] = (uint32_t)s_u (&r, 4);
        assert_true (p->size_of[p->nseg] >= 5);
        r.at = p->off[p->nseg] + p->size_of[p->nseg];
        p->nseg++;
    }
    assert_int_equal (r.at, len); // the last segment ends with the packet
}

typedef struct {
    char mission_plan[13], flight_plan[13], config[11];
    uint8_t platform_type, month, day;
    uint16_t year;
} s_mission_t;

static void s_mission (const uint8_t *b, const s_packet_t *p, size_t i, s_mission_t *m)
{
    assert_int_equal (p->type[i], 1);
    assert_int_equal (p->size_of[i], 44);
    s_rd_t r = {b + p->off[i], p->size_of[i], 5};
    s_text (&r, 12, m->mission_plan);
    s_text (&r, 12, m->flight_plan);
    m->platform_type = (uint8_t)s_u (&r, 1);
    s_text (&r, 10, m->config);
    m->year = (uint16_t)s_u (&r, 2);
    m->month = (uint8_t)s_u (&r, 1);
    m->day = (uint8_t)s_u (&r, 1);
    assert_int_equal (r.at, 44);
}

typedef struct {
    uint32_t job_id;
    uint8_t sensor_type, priority, radar_mode, mdv;
    char model[7];
    int32_t lat[4];
    uint32_t lon[4];
    uint16_t revisit_ds;
} s_job_t;

static void s_job (const uint8_t *b, const s_packet_t *p, size_t i, s_job_t *j)
{
    assert_int_equal (p->type[i], 5);
    assert_int_equal (p->size_of[i], 73);
    s_rd_t r = {b + p->off[i], p->size_of[i], 5};
    j->job_id = (uint32_t)s_u (&r, 4);     // J1
    j->sensor_type = (uint8_t)s_u (&r, 1); // J2
    s_text (&r, 6, j->model);              // J3
    s_u (&r, 1);                           // J4 filter
    j->priority = (uint8_t)s_u (&r, 1);    // J5
    for (int k = 0; k < 4; k++) {          // J6-J13
        j->lat[k] = (int32_t)(uint32_t)s_u (&r, 4);
        j->lon[k] = (uint32_t)s_u (&r, 4);
    }
    j->radar_mode = (uint8_t)s_u (&r, 1);    // J14
    j->revisit_ds = (uint16_t)s_u (&r, 2);   // J15
    s_u (&r, 2 + 2 + 2 + 1 + 2 + 2 + 2 + 2); // J16-J23
    j->mdv = (uint8_t)s_u (&r, 1);           // J24
    s_u (&r, 1 + 1 + 1 + 1);                 // J25-J28
    assert_int_equal (r.at, 73);
}

typedef struct {
    uint32_t time_ms, speed_mmps;
    int32_t lat, alt_cm;
    uint32_t lon;
    uint16_t track;
    int8_t vv;
} s_platform_t;

static void s_platform (const uint8_t *b, const s_packet_t *p, size_t i, s_platform_t *pl)
{
    assert_int_equal (p->type[i], 13);
    assert_int_equal (p->size_of[i], 28);
    s_rd_t r = {b + p->off[i], p->size_of[i], 5};
    pl->time_ms = (uint32_t)s_u (&r, 4);
    pl->lat = (int32_t)(uint32_t)s_u (&r, 4);
    pl->lon = (uint32_t)s_u (&r, 4);
    pl->alt_cm = (int32_t)(uint32_t)s_u (&r, 4);
    pl->track = (uint16_t)s_u (&r, 2);
    pl->speed_mmps = (uint32_t)s_u (&r, 4);
    pl->vv = (int8_t)(uint8_t)s_u (&r, 1);
    assert_int_equal (r.at, 28);
}

/* Bytes of D2..D31 (by field number) and of D32.1..D32.18 (by sub-number), Edition 3. */
static const size_t s_dwell_bytes[32] = {
    [2] = 2,  [3] = 2,  [4] = 1,  [5] = 2,  [6] = 4,  [7] = 4,  [8] = 4,  [9] = 4,
    [10] = 4, [11] = 4, [12] = 4, [13] = 4, [14] = 2, [15] = 2, [16] = 4, [17] = 1,
    [18] = 1, [19] = 2, [20] = 2, [21] = 2, [22] = 2, [23] = 2, [24] = 4, [25] = 4,
    [26] = 2, [27] = 2, [28] = 2, [29] = 2, [30] = 2, [31] = 1,
};
static const size_t s_report_bytes[19] = {
    [1] = 2,  [2] = 4,  [3] = 4,  [4] = 2,  [5] = 2,  [6] = 2,  [7] = 2,  [8] = 2,  [9] = 1,
    [10] = 1, [11] = 1, [12] = 2, [13] = 2, [14] = 1, [15] = 2, [16] = 1, [17] = 4, [18] = 1,
};

typedef struct {
    uint64_t mask;
    uint64_t f[32];    // raw D2..D31 (0 when absent)
    size_t n;          // D5
    uint64_t (*r)[19]; // raw D32.k of each report
} s_dwell_t;

static void s_dwell (const uint8_t *b, const s_packet_t *p, size_t i, s_dwell_t *d)
{
    assert_int_equal (p->type[i], 2);
    memset (d, 0, sizeof *d);
    s_rd_t r = {b + p->off[i], p->size_of[i], 5};
    d->mask = s_u (&r, 8);
    for (int k = 2; k <= 31; k++)
        if (d->mask & S_MASK_D (k))
            d->f[k] = s_u (&r, s_dwell_bytes[k]);
    d->n = (size_t)d->f[5];
    d->r = calloc (d->n ? d->n : 1, sizeof *d->r);
    assert_non_null (d->r);
    for (size_t j = 0; j < d->n; j++)
        for (int k = 1; k <= 18; k++)
            if (d->mask & S_MASK_R (k))
                d->r[j][k] = s_u (&r, s_report_bytes[k]);
    assert_int_equal (r.at, p->size_of[i]); // the reports end the segment
}

static int32_t s_s32 (uint64_t raw)
{
    return (int32_t)(uint32_t)raw;
}

static int16_t s_s16 (uint64_t raw)
{
    return (int16_t)(uint16_t)raw;
}

/* The encodings worked from their definitions. */
static int64_t s_sa32 (double deg)
{
    return llround (deg * S_TWO_31 / 90.0);
}

static int64_t s_ba32 (double deg)
{
    double a = fmod (deg, 360.0);
    return llround ((a < 0 ? a + 360.0 : a) * S_TWO_32 / 360.0);
}

static int64_t s_ba16 (double deg)
{
    double a = fmod (deg, 360.0);
    return llround ((a < 0 ? a + 360.0 : a) * 65536.0 / 360.0);
}

static int64_t s_sa16 (double deg)
{
    return llround (deg * 32768.0 / 90.0);
}

/* ---- messages ------------------------------------------------------------------------------ */

typedef struct {
    Cgs__Uav u;
    Cgs__Enu p;
    Cgs__EnuVelocity v;
} s_uav_t;

static void s_uav (s_uav_t *m, uint32_t id, const char *name, cgs_enu_t p, cgs_enu_t v)
{
    cgs__uav__init (&m->u);
    cgs__enu__init (&m->p);
    cgs__enu_velocity__init (&m->v);
    m->p.east_m = p.e_m, m->p.north_m = p.n_m, m->p.up_m = p.u_m;
    m->v.east_mps = v.e_m, m->v.north_mps = v.n_m, m->v.up_mps = v.u_m;
    m->u.entity_id = id;
    m->u.name = (char *)name;
    m->u.position = &m->p;
    m->u.velocity = &m->v;
    m->u.heading_deg = 37;
    m->u.pitch_deg = 2;
    m->u.roll_deg = -5;
}

typedef struct {
    Cgs__Mti m;
    Cgs__Enu plat;
    Cgs__MtiHit *hit;
    Cgs__Enu *pos;
    Cgs__MtiHit **hp;
} s_mti_t;

/* A dwell of n hits (ids 101..), spread over the radar's range window. */
static void s_mti (s_mti_t *x, uint32_t scan, uint32_t dwell, size_t n)
{
    memset (x, 0, sizeof *x);
    cgs__mti__init (&x->m);
    cgs__enu__init (&x->plat);
    x->plat.east_m = 1000, x->plat.north_m = -2000, x->plat.up_m = 1500;
    x->hit = calloc (n ? n : 1, sizeof *x->hit);
    x->pos = calloc (n ? n : 1, sizeof *x->pos);
    x->hp = calloc (n ? n : 1, sizeof *x->hp);
    assert_true (x->hit && x->pos && x->hp);
    for (size_t i = 0; i < n; i++) {
        cgs__mti_hit__init (&x->hit[i]);
        cgs__enu__init (&x->pos[i]);
        x->pos[i].east_m = 2000.0 + 3.0 * (double)i;
        x->pos[i].north_m = 3000.0 - 2.0 * (double)i;
        x->pos[i].up_m = 20.0 + (double)(i % 7);
        x->hit[i].hit_id = 101 + (uint32_t)i;
        x->hit[i].position = &x->pos[i];
        x->hit[i].range_m = 10000;
        x->hit[i].azimuth_deg = 45;
        x->hit[i].radial_velocity_mps = -3.0 + 0.0137 * (double)i;
        x->hit[i].snr_db = 15.2;
        x->hit[i].range_sigma_m = 7.4;
        x->hit[i].azimuth_sigma_deg = 0.3;
        x->hp[i] = &x->hit[i];
    }
    x->m.uav_id = S_UAV_ID;
    x->m.scan_number = scan;
    x->m.dwell_number = dwell;
    x->m.beam_azimuth_deg = 45;
    x->m.platform_position = &x->plat;
    x->m.n_hits = n;
    x->m.hits = x->hp;
    x->m.dwell_start_s = 100.0;
    x->m.dwell_end_s = 100.05;
    x->m.wrap_velocity_mps = 30;
    x->m.min_range_m = 2000;
    x->m.max_range_m = 20000;
    x->m.azimuth_beamwidth_deg = 3;
    x->m.frequency_hz = 10e9;
    x->m.radial_velocity_sigma_mps = 0.4;
}

static void s_mti_free (s_mti_t *x)
{
    free (x->hit);
    free (x->pos);
    free (x->hp);
}

/* The three hits of the worked example: the exercise origin, and two more. */
static void s_three_hits (s_mti_t *x)
{
    const double p[3][3] = {{0, 0, 0}, {5000, 3000, 20}, {-4000, 6000, 35}};
    const double v[3] = {12.344, -7.891, 0.25};
    for (int i = 0; i < 3; i++) {
        x->pos[i].east_m = p[i][0], x->pos[i].north_m = p[i][1], x->pos[i].up_m = p[i][2];
        x->hit[i].radial_velocity_mps = v[i];
    }
}

typedef struct {
    cgs_geo_t *geo;
    gw_params_t p;
    s_sink_t sink;
} s_fix_t;

static int s_setup (void **state)
{
    s_fix_t *f = calloc (1, sizeof *f);
    if (!f || !(f->geo = cgs_geo_new (35.96, -121.23, 0)))
        return -1;
    gw_params_defaults (&f->p);
    *state = f;
    return 0;
}

static int s_teardown (void **state)
{
    s_fix_t *f = *state;
    s_sink_clear (&f->sink);
    cgs_geo_destroy (&f->geo);
    free (f);
    return 0;
}

static gw_gmti_t *s_new (s_fix_t *f)
{
    gw_gmti_t *g = gw_gmti_new (&f->p, f->geo, S_EXERCISE, s_emit, &f->sink);
    assert_non_null (g);
    return g;
}

static cgs_geodetic_t s_geodetic (const s_fix_t *f, double e, double n, double u)
{
    cgs_geodetic_t g;
    assert_int_equal (cgs_geo_enu_to_geodetic (f->geo, (cgs_enu_t){e, n, u}, &g), 0);
    return g;
}

/* Packet i of the sink: its header checked (what every packet of radar 7 says). */
static void s_header (const s_fix_t *f, size_t i, s_packet_t *p)
{
    assert_true (i < f->sink.n);
    s_packet (f->sink.b[i], f->sink.len[i], p);
    assert_string_equal (p->version, "30");
    assert_string_equal (p->nationality, "XN");
    assert_int_equal (p->classification, 5);
    assert_string_equal (p->class_system, "XN");
    assert_int_equal (p->exercise, 129); // exercise, simulated data
    assert_string_equal (p->platform_id, "uav1");
    assert_int_equal (p->mission_id, S_EXERCISE);
    assert_int_equal (p->job_id, S_UAV_ID); // the job is the UAV's
}

/* ---- tests --------------------------------------------------------------------------------- */

/* The mask of a dwell of a heard UAV: D2-D9, the platform's track, speed
 * and vertical velocity (D15-17) and attitude (D21-23), the dwell area
 * D24-D27, the MDV D31; reports with index, hi-res location, height, LOS
 * and wrap velocity, SNR, class and the four uncertainties. */
static uint64_t s_expected_mask (bool tags)
{
    uint64_t m = 0;
    for (int k = 2; k <= 9; k++)
        m |= S_MASK_D (k);
    for (int k = 15; k <= 17; k++)
        m |= S_MASK_D (k);
    for (int k = 21; k <= 27; k++)
        m |= S_MASK_D (k);
    m |= S_MASK_D (31);
    const int r[] = {1, 2, 3, 6, 7, 8, 9, 10, 12, 13, 14, 15};
    for (size_t k = 0; k < sizeof r / sizeof r[0]; k++)
        m |= S_MASK_R (r[k]);
    if (tags)
        m |= S_MASK_R (16) | S_MASK_R (17);
    return m;
}

static void test_dwell (void **state)
{
    s_fix_t *f = *state;
    gw_gmti_t *g = s_new (f);
    gw_gmti_set_clock (g, S_CLOCK_UTC, 0);
    s_uav_t u;
    s_uav (&u, S_UAV_ID, "uav1", (cgs_enu_t){1000, -2000, 1500}, (cgs_enu_t){30, 40, 0});
    gw_gmti_on_uav (g, &u.u, 99.9);
    assert_int_equal (f->sink.n, 0); // no platform location before the job
    s_mti_t x;
    s_mti (&x, 12, 3, 3);
    s_three_hits (&x);
    assert_int_equal (gw_gmti_on_mti (g, &x.m), 0);
    assert_int_equal (f->sink.n, 1);

    s_packet_t p;
    s_header (f, 0, &p);
    assert_int_equal (p.nseg, 3);
    s_mission_t m;
    s_mission (f->sink.b[0], &p, 0, &m);
    assert_string_equal (m.mission_plan, "mscgs ex 42");
    assert_string_equal (m.flight_plan, "uav1");
    assert_int_equal (m.platform_type, 16); // UAV (Army)
    assert_int_equal (m.year, 2026);
    assert_int_equal (m.month, 11);
    assert_int_equal (m.day, 27);
    s_job_t j;
    s_job (f->sink.b[0], &p, 1, &j);
    assert_int_equal (j.job_id, S_UAV_ID);
    assert_int_equal (j.sensor_type, 1); // other
    assert_string_equal (j.model, "MSCGS");
    assert_int_equal (j.priority, 1);
    assert_int_equal (j.radar_mode, 1);
    // A revolution: 0.05 s a 3-degree beamwidth, 120 of them: 6 s, 60 ds.
    assert_int_equal (j.revisit_ds, 60);
    assert_int_equal (j.mdv, 6); // 0.58 m/s in dm/s
    // The bounding area's first corner: north-west of the UAV by the range, 20 km.
    cgs_geodetic_t nw = s_geodetic (f, 1000 - 20000, -2000 + 20000, 0);
    assert_int_equal (j.lat[0], s_sa32 (nw.lat_deg));
    assert_int_equal (j.lon[0], s_ba32 (nw.lon_deg));

    s_dwell_t d;
    s_dwell (f->sink.b[0], &p, 2, &d);
    assert_int_equal (d.mask, s_expected_mask (false));
    assert_int_equal (d.f[2], 12); // revisit index: the scan
    assert_int_equal (d.f[3], 3);  // dwell index: the dwell
    assert_int_equal (d.f[4], 0);  // not the scan's last
    assert_int_equal (d.n, 3);
    // The dwell's centre, 100.025 s after 10:00.
    assert_near ((double)d.f[6], S_MIDNIGHT + 100025.0, 1.0);
    cgs_geodetic_t pg = s_geodetic (f, 1000, -2000, 1500);
    assert_int_equal (s_s32 (d.f[7]), s_sa32 (pg.lat_deg));
    assert_int_equal (d.f[8], s_ba32 (pg.lon_deg));
    assert_int_equal (s_s32 (d.f[9]), llround (pg.height_m * 100));
    // Velocity (30, 40): track atan2(30, 40) = 36.87 degrees, 50 m/s.
    assert_int_equal (d.f[15], s_ba16 (atan2 (30, 40) / S_DEG));
    assert_int_equal (d.f[15], 6712);
    assert_int_equal (d.f[16], 50000);
    assert_int_equal (d.f[17], 0);
    assert_int_equal (d.f[21], s_ba16 (37));
    assert_int_equal (s_s16 (d.f[22]), s_sa16 (2));
    assert_int_equal (s_s16 (d.f[23]), s_sa16 (-5));
    // The dwell area: on the beam (45 degrees) at the middle of the ground
    // ranges of the slant window 2-20 km from 1500 m up.
    double gmin = sqrt (2000.0 * 2000 - 1500.0 * 1500),
           gmax = sqrt (20000.0 * 20000 - 1500.0 * 1500);
    double gc = (gmin + gmax) / 2;
    cgs_geodetic_t ag =
        s_geodetic (f, 1000 + gc * sin (45 * S_DEG), -2000 + gc * cos (45 * S_DEG), 0);
    assert_int_equal (s_s32 (d.f[24]), s_sa32 (ag.lat_deg));
    assert_int_equal (d.f[25], s_ba32 (ag.lon_deg));
    assert_int_equal (d.f[26], 1192); // (gmax - gmin) / 2 = 9.3104 km, B16: 1191.7 / 128
    assert_int_equal (d.f[27], 273);  // half the beamwidth, 1.5 degrees in BA16
    assert_int_equal (d.f[31], 6);

    // The reports. The first hit is the origin, worked by hand.
    assert_int_equal (s_s32 (d.r[0][2]), 858039022);
    assert_int_equal (d.r[0][3], 2848637059u);
    const double v[3] = {12.344, -7.891, 0.25};
    const int32_t vlos[3] = {1234, -789, 25};
    for (size_t i = 0; i < 3; i++) {
        cgs_geodetic_t hg = s_geodetic (f, x.pos[i].east_m, x.pos[i].north_m, x.pos[i].up_m);
        assert_int_equal (d.r[i][1], i); // report index
        assert_int_equal (s_s32 (d.r[i][2]), s_sa32 (hg.lat_deg));
        assert_int_equal (d.r[i][3], s_ba32 (hg.lon_deg));
        assert_int_equal (s_s16 (d.r[i][6]), llround (hg.height_m));
        assert_int_equal (s_s16 (d.r[i][7]), llround (v[i] * 100));
        assert_int_equal (s_s16 (d.r[i][7]), vlos[i]);
        assert_int_equal (d.r[i][8], 3000); // wrap velocity 30 m/s in cm/s
        assert_int_equal ((int8_t)d.r[i][9], 15);
        assert_int_equal (d.r[i][10], 128); // no information, simulated target
        assert_int_equal (d.r[i][12], 740); // slant range sigma, cm
        assert_int_equal (d.r[i][13], 524); // 10 km * 0.3 degrees = 52.36 m, dm
        assert_int_equal (d.r[i][14], 7);
        assert_int_equal (d.r[i][15], 40); // radial velocity sigma, cm/s
    }
    free (d.r);

    // The next dwell: a dwell segment alone.
    s_sink_clear (&f->sink);
    x.m.dwell_number = 4;
    x.m.last_of_scan = true;
    x.m.dwell_start_s = 100.05, x.m.dwell_end_s = 100.1;
    assert_int_equal (gw_gmti_on_mti (g, &x.m), 0);
    assert_int_equal (f->sink.n, 1);
    s_header (f, 0, &p);
    assert_int_equal (p.nseg, 1);
    s_dwell (f->sink.b[0], &p, 0, &d);
    assert_int_equal (d.f[2], 12);
    assert_int_equal (d.f[3], 4);
    assert_int_equal (d.f[4], 1); // the scan's last
    assert_int_equal (d.n, 3);
    assert_near ((double)d.f[6], S_MIDNIGHT + 100075.0, 1.0);
    free (d.r);
    const gw_gmti_stats_t *st = gw_gmti_stats (g);
    assert_int_equal (st->packets, 2);
    assert_int_equal (st->dwells, 2);
    assert_int_equal (st->reports, 6);
    assert_int_equal (st->missions, 1);
    assert_int_equal (st->no_uav, 0);
    s_mti_free (&x);
    gw_gmti_destroy (&g);
    assert_null (g);
    gw_gmti_destroy (&g); // again: a no-op
}

/* Without a clock: the simulation time past 2000-01-01, whose midnight it
 * counts from; a dwell of a UAV not heard yet goes out, counted, without
 * the platform's motion and attitude. */
static void test_default_clock (void **state)
{
    s_fix_t *f = *state;
    gw_gmti_t *g = s_new (f);
    s_mti_t x;
    s_mti (&x, 1, 0, 2);
    assert_int_equal (gw_gmti_on_mti (g, &x.m), 0);
    assert_int_equal (f->sink.n, 1);
    s_packet_t p;
    s_packet (f->sink.b[0], f->sink.len[0], &p);
    assert_string_equal (p.platform_id, "uav7"); // no name heard
    assert_int_equal (p.nseg, 3);
    s_mission_t m;
    s_mission (f->sink.b[0], &p, 0, &m);
    assert_int_equal (m.year, 2000);
    assert_int_equal (m.month, 1);
    assert_int_equal (m.day, 1);
    s_dwell_t d;
    s_dwell (f->sink.b[0], &p, 2, &d);
    assert_near ((double)d.f[6], 100025.0, 1.0);
    assert_false (d.mask & S_MASK_D (15));
    assert_false (d.mask & S_MASK_D (21));
    assert_int_equal (d.n, 2);
    free (d.r);
    assert_int_equal (gw_gmti_stats (g)->no_uav, 1);
    s_mti_free (&x);
    gw_gmti_destroy (&g);
}

/* The truth entity (D32.17) of each report of packet i's dwell segment k. */
static void s_tags (const s_fix_t *f, size_t i, size_t k, const uint32_t *app, const uint32_t *ent,
                    size_t n)
{
    s_packet_t p;
    s_header (f, i, &p);
    s_dwell_t d;
    s_dwell (f->sink.b[i], &p, k, &d);
    assert_int_equal (d.mask, s_expected_mask (true));
    assert_int_equal (d.n, n);
    for (size_t j = 0; j < n; j++) {
        if (d.r[j][16] != app[j] || d.r[j][17] != ent[j])
            fail_msg ("report %zu: tag %u/%u, want %u/%u", j, (unsigned)d.r[j][16],
                      (unsigned)d.r[j][17], app[j], ent[j]);
    }
    free (d.r);
}

/* Packet i's dwell segment k, of dwell `dwell`, sent untagged: without the
 * truth tag fields (a tag of 0 would say "a false alarm" of every report). */
static void s_untagged (const s_fix_t *f, size_t i, size_t k, uint32_t dwell)
{
    s_packet_t p;
    s_header (f, i, &p);
    s_dwell_t d;
    s_dwell (f->sink.b[i], &p, k, &d);
    assert_int_equal (d.f[3], dwell);
    assert_int_equal (d.mask, s_expected_mask (false));
    assert_int_equal (d.n, 3);
    free (d.r);
}

typedef struct {
    Cgs__MtiTruth t;
    Cgs__MtiTruthItem it[4];
    Cgs__MtiTruthItem *ip[4];
} s_truth_t;

/* The truth of (uav, scan, dwell): entity 21 made hit 103, 22 hit 101, 23
 * was missed (hit 0), 24 names a hit this dwell does not have. */
static void s_truth (s_truth_t *x, uint32_t uav, uint32_t scan, uint32_t dwell)
{
    cgs__mti_truth__init (&x->t);
    const uint32_t ent[4] = {21, 22, 23, 24}, hit[4] = {103, 101, 0, 999};
    for (int i = 0; i < 4; i++) {
        cgs__mti_truth_item__init (&x->it[i]);
        x->it[i].entity_id = ent[i];
        x->it[i].hit_id = hit[i];
        x->it[i].detected = hit[i] != 0;
        x->ip[i] = &x->it[i];
    }
    x->t.uav_id = uav;
    x->t.scan_number = scan;
    x->t.dwell_number = dwell;
    x->t.n_items = 4;
    x->t.items = x->ip;
}

static void test_truth_tags (void **state)
{
    s_fix_t *f = *state;
    f->p.s4607_truth_tag = true;
    f->p.application = 5;
    f->p.entity_id_base = 1000;
    gw_gmti_t *g = s_new (f);
    gw_gmti_set_clock (g, S_CLOCK_UTC, 0);
    s_uav_t u;
    s_uav (&u, S_UAV_ID, "uav1", (cgs_enu_t){1000, -2000, 1500}, (cgs_enu_t){30, 40, 0});
    gw_gmti_on_uav (g, &u.u, 99.9);
    s_mti_t x;
    s_mti (&x, 12, 3, 3);
    assert_int_equal (gw_gmti_on_mti (g, &x.m), 0);
    assert_int_equal (f->sink.n, 0); // waits for its truth
    s_truth_t t;
    s_truth (&t, S_UAV_ID, 12, 2); // another dwell of the scan
    gw_gmti_on_truth (g, &t.t);
    s_truth (&t, S_UAV_ID, 11, 3); // the same dwell of another scan
    gw_gmti_on_truth (g, &t.t);
    s_truth (&t, S_UAV_ID + 1, 12, 3); // another radar
    gw_gmti_on_truth (g, &t.t);
    assert_int_equal (f->sink.n, 0);
    gw_gmti_tick (g); // one tick: its truth still has time
    assert_int_equal (f->sink.n, 0);
    s_truth (&t, S_UAV_ID, 12, 3);
    gw_gmti_on_truth (g, &t.t);
    assert_int_equal (f->sink.n, 1);
    // Hits 101, 102, 103 in order: 101 is entity 22's, 102 a false alarm, 103 entity 21's.
    s_tags (f, 0, 2, (const uint32_t[]){5, 0, 5}, (const uint32_t[]){1022, 0, 1021}, 3);
    assert_int_equal (gw_gmti_stats (g)->tagged, 2);
    assert_int_equal (gw_gmti_stats (g)->untagged, 0);
    gw_gmti_on_truth (g, &t.t); // again: nothing pending
    gw_gmti_tick (g);
    gw_gmti_tick (g);
    assert_int_equal (f->sink.n, 1);

    // A dwell whose truth does not come: out at the second tick, untagged.
    s_sink_clear (&f->sink);
    x.m.dwell_number = 4;
    assert_int_equal (gw_gmti_on_mti (g, &x.m), 0);
    gw_gmti_tick (g);
    assert_int_equal (f->sink.n, 0);
    gw_gmti_tick (g);
    assert_int_equal (f->sink.n, 1);
    s_untagged (f, 0, 0, 4);
    assert_int_equal (gw_gmti_stats (g)->untagged, 1);
    s_truth (&t, S_UAV_ID, 12, 4); // late: nothing left to tag
    gw_gmti_on_truth (g, &t.t);
    assert_int_equal (f->sink.n, 1);

    // The radar's next dwell sends the one waiting, untagged.
    s_sink_clear (&f->sink);
    x.m.dwell_number = 5;
    assert_int_equal (gw_gmti_on_mti (g, &x.m), 0);
    assert_int_equal (f->sink.n, 0);
    x.m.dwell_number = 6;
    assert_int_equal (gw_gmti_on_mti (g, &x.m), 0);
    assert_int_equal (f->sink.n, 1);
    s_untagged (f, 0, 0, 5);
    assert_int_equal (gw_gmti_stats (g)->untagged, 2);
    // Dwell 6 is tagged by its own truth; then flush has nothing to send.
    s_truth (&t, S_UAV_ID, 12, 6);
    gw_gmti_on_truth (g, &t.t);
    assert_int_equal (f->sink.n, 2);
    s_tags (f, 1, 0, (const uint32_t[]){5, 0, 5}, (const uint32_t[]){1022, 0, 1021}, 3);
    gw_gmti_flush (g);
    assert_int_equal (f->sink.n, 2);
    assert_int_equal (gw_gmti_stats (g)->untagged, 2);
    // Flush sends what waits, untagged, counted.
    x.m.dwell_number = 7;
    assert_int_equal (gw_gmti_on_mti (g, &x.m), 0);
    assert_int_equal (f->sink.n, 2);
    gw_gmti_flush (g);
    assert_int_equal (f->sink.n, 3);
    s_untagged (f, 2, 0, 7);
    assert_int_equal (gw_gmti_stats (g)->untagged, 3);
    assert_int_equal (gw_gmti_stats (g)->tagged, 4);
    s_mti_free (&x);
    gw_gmti_destroy (&g);
}

/* A hit without a position is left out: the reports that remain are
 * numbered on, and each keeps its own hit's tag. */
static void test_hit_left_out (void **state)
{
    s_fix_t *f = *state;
    f->p.s4607_truth_tag = true;
    f->p.application = 5;
    f->p.entity_id_base = 1000;
    gw_gmti_t *g = s_new (f);
    s_mti_t x;
    s_mti (&x, 12, 3, 4); // hits 101..104
    x.hit[1].position = NULL;
    assert_int_equal (gw_gmti_on_mti (g, &x.m), 0);
    s_truth_t t;
    s_truth (&t, S_UAV_ID, 12, 3);
    t.it[3].hit_id = 104; // entity 24 made hit 104
    gw_gmti_on_truth (g, &t.t);
    assert_int_equal (f->sink.n, 1);
    s_packet_t p;
    s_packet (f->sink.b[0], f->sink.len[0], &p);
    s_dwell_t d;
    s_dwell (f->sink.b[0], &p, 2, &d);
    assert_int_equal (d.n, 3);
    assert_int_equal (gw_gmti_stats (g)->unplaceable, 1); // the hit left out is counted
    const uint32_t ent[3] = {1022, 1021, 1024}; // hits 101, 103, 104
    const size_t hit[3] = {0, 2, 3};
    for (size_t j = 0; j < 3; j++) {
        assert_int_equal (d.r[j][1], j);
        assert_int_equal (d.r[j][17], ent[j]);
        cgs_geodetic_t hg =
            s_geodetic (f, x.pos[hit[j]].east_m, x.pos[hit[j]].north_m, x.pos[hit[j]].up_m);
        assert_int_equal (s_s32 (d.r[j][2]), s_sa32 (hg.lat_deg));
    }
    free (d.r);
    s_mti_free (&x);
    gw_gmti_destroy (&g);
}

/* Platform locations at platform_rate_hz (2 Hz here) of simulation time,
 * from the job's start; the mission and job segments again every 60 s of
 * simulation time, in a platform location's packet. */
static void test_platform (void **state)
{
    s_fix_t *f = *state;
    f->p.s4607_platform_rate_hz = 2;
    gw_gmti_t *g = s_new (f);
    gw_gmti_set_clock (g, S_CLOCK_UTC + 100, 100); // the same clock, anchored later
    s_uav_t u;
    s_uav (&u, S_UAV_ID, "uav1", (cgs_enu_t){1000, -2000, 1500}, (cgs_enu_t){-30, 40, 2.5});
    gw_gmti_on_uav (g, &u.u, 10.0);
    assert_int_equal (f->sink.n, 0); // the job has not started
    s_mti_t x;
    s_mti (&x, 1, 0, 1);
    x.m.dwell_start_s = 10.0, x.m.dwell_end_s = 10.1;
    assert_int_equal (gw_gmti_on_mti (g, &x.m), 0);
    assert_int_equal (f->sink.n, 1);
    s_packet_t p;
    s_header (f, 0, &p);
    s_dwell_t d;
    s_dwell (f->sink.b[0], &p, 2, &d);
    assert_near ((double)d.f[6], S_MIDNIGHT + 10050.0, 1.0);
    free (d.r);
    // UAV states at 10.2 (sent), 10.5 (0.3 s later: not), 10.7 (0.5 s: sent),
    // 11.0 (not), 11.2 (sent), ...; the mission and job again in the first
    // platform packet 60 s or more after the dwell's centre (10.05): at
    // 70.5, and 60 s after that, at 130.9.
    const double t[11] = {10.2, 10.5, 10.7, 11.0, 11.2, 69.9, 70.1, 70.5, 71.0, 130.4, 130.9};
    const int sent[11] = {1, 0, 1, 0, 1, 1, 0, 3, 1, 1, 3}; // segments, 0: no packet
    size_t n = 1;
    for (int k = 0; k < 11; k++) {
        u.p.east_m = 1000 - 30 * (t[k] - 10), u.p.north_m = -2000 + 40 * (t[k] - 10);
        gw_gmti_on_uav (g, &u.u, t[k]);
        if (!sent[k]) {
            assert_int_equal (f->sink.n, n);
            continue;
        }
        assert_int_equal (f->sink.n, ++n);
        s_header (f, n - 1, &p);
        assert_int_equal (p.nseg, sent[k]);
        if (sent[k] == 3) {
            s_mission_t m;
            s_mission (f->sink.b[n - 1], &p, 0, &m);
            assert_int_equal (m.year * 10000 + m.month * 100 + m.day, 20261127);
            s_job_t j;
            s_job (f->sink.b[n - 1], &p, 1, &j);
            assert_int_equal (j.job_id, S_UAV_ID);
        }
        s_platform_t pl;
        s_platform (f->sink.b[n - 1], &p, p.nseg - 1, &pl);
        assert_near ((double)pl.time_ms, S_MIDNIGHT + t[k] * 1000, 1.0);
        cgs_geodetic_t ug = s_geodetic (f, u.p.east_m, u.p.north_m, 1500);
        assert_int_equal (pl.lat, s_sa32 (ug.lat_deg));
        assert_int_equal (pl.lon, s_ba32 (ug.lon_deg));
        assert_int_equal (pl.alt_cm, llround (ug.height_m * 100));
        assert_int_equal (pl.track, s_ba16 (atan2 (-30, 40) / S_DEG)); // 323.13 degrees
        assert_int_equal (pl.speed_mmps, 50000);
        assert_int_equal (pl.vv, 25); // 2.5 m/s in dm/s
    }
    assert_int_equal (gw_gmti_stats (g)->missions, 3);
    assert_int_equal (gw_gmti_stats (g)->platforms, 8);
    s_mti_free (&x);
    gw_gmti_destroy (&g);
}

/* 3000 hits: packets of at most 65,000 bytes. A report here is 25 bytes
 * (2 + 4 + 4 + 2 + 2 + 2 + 1 + 1 + 2 + 2 + 1 + 2), the dwell's fixed part
 * 62 (5 + 8 + 23 + 7 + 6 + 12 + 1); the first packet has 65,000 - 32 - 44
 * - 73 = 64,851 bytes for the dwell: 2591 reports; the second the 409 left. */
static void s_split (void **state, bool last_of_scan)
{
    s_fix_t *f = *state;
    gw_gmti_t *g = s_new (f);
    s_uav_t u;
    s_uav (&u, S_UAV_ID, "uav1", (cgs_enu_t){1000, -2000, 1500}, (cgs_enu_t){30, 40, 0});
    gw_gmti_on_uav (g, &u.u, 99.9);
    s_mti_t x;
    s_mti (&x, 9, 17, 3000);
    x.m.last_of_scan = last_of_scan;
    assert_int_equal (gw_gmti_on_mti (g, &x.m), 0);
    assert_int_equal (f->sink.n, 2);
    const size_t want[2] = {2591, 409};
    size_t total = 0;
    for (size_t i = 0; i < f->sink.n; i++) {
        assert_true (f->sink.len[i] <= 65000);
        s_packet_t p;
        s_header (f, i, &p);
        assert_int_equal (p.nseg, i == 0 ? 3 : 1);
        s_dwell_t d;
        s_dwell (f->sink.b[i], &p, p.nseg - 1, &d);
        assert_int_equal (d.f[2], 9);
        assert_int_equal (d.f[3], 17);
        assert_int_equal (d.n, want[i]);
        assert_int_equal (d.f[4], last_of_scan && i == f->sink.n - 1 ? 1 : 0);
        for (size_t j = 0; j < d.n; j++) // the reports follow on: the hits in order
            if (d.r[j][1] != total + j)
                fail_msg ("packet %zu report %zu has index %u", i, j, (unsigned)d.r[j][1]);
        cgs_geodetic_t hg =
            s_geodetic (f, x.pos[total].east_m, x.pos[total].north_m, x.pos[total].up_m);
        assert_int_equal (s_s32 (d.r[0][2]), s_sa32 (hg.lat_deg));
        total += d.n;
        free (d.r);
    }
    assert_int_equal (f->sink.len[0], 32 + 44 + 73 + 62 + 2591 * 25);
    assert_int_equal (total, 3000);
    assert_int_equal (gw_gmti_stats (g)->reports, 3000);
    assert_int_equal (gw_gmti_stats (g)->dwells, 2);
    s_mti_free (&x);
    gw_gmti_destroy (&g);
}

static void test_split_last (void **state)
{
    s_split (state, true);
}

static void test_split_not_last (void **state)
{
    s_split (state, false);
}

/* A dwell without hits is a dwell segment without reports. */
static void test_no_hits (void **state)
{
    s_fix_t *f = *state;
    gw_gmti_t *g = s_new (f);
    s_mti_t x;
    s_mti (&x, 2, 5, 0);
    x.m.last_of_scan = true;
    assert_int_equal (gw_gmti_on_mti (g, &x.m), 0);
    assert_int_equal (f->sink.n, 1);
    s_packet_t p;
    s_packet (f->sink.b[0], f->sink.len[0], &p);
    assert_int_equal (p.nseg, 3);
    s_dwell_t d;
    s_dwell (f->sink.b[0], &p, 2, &d);
    assert_int_equal (d.n, 0);
    assert_int_equal (d.f[3], 5);
    assert_int_equal (d.f[4], 1);
    free (d.r);
    s_mti_free (&x);
    gw_gmti_destroy (&g);
}

/* What a dwell segment must say and the message lacks: refused, nothing sent. */
static void test_invalid (void **state)
{
    s_fix_t *f = *state;
    gw_gmti_t *g = s_new (f);
    s_mti_t x;
    s_mti (&x, 1, 1, 3);
    x.m.platform_position = NULL;
    assert_int_equal (gw_gmti_on_mti (g, &x.m), -EINVAL);
    x.m.platform_position = &x.plat;
    x.m.dwell_start_s = NAN;
    assert_int_equal (gw_gmti_on_mti (g, &x.m), -EINVAL);
    x.m.dwell_start_s = 100;
    x.m.dwell_end_s = INFINITY;
    assert_int_equal (gw_gmti_on_mti (g, &x.m), -EINVAL);
    x.m.dwell_end_s = 99; // ends before it starts
    assert_int_equal (gw_gmti_on_mti (g, &x.m), -EINVAL);
    assert_int_equal (f->sink.n, 0);
    assert_int_equal (gw_gmti_stats (g)->packets, 0);
    // With truth tags, a refused dwell leaves the one waiting where it is.
    gw_gmti_destroy (&g);
    f->p.s4607_truth_tag = true;
    g = s_new (f);
    x.m.dwell_end_s = 100.05;
    assert_int_equal (gw_gmti_on_mti (g, &x.m), 0);
    x.m.dwell_number = 2;
    x.m.platform_position = NULL;
    assert_int_equal (gw_gmti_on_mti (g, &x.m), -EINVAL);
    assert_int_equal (f->sink.n, 0);
    gw_gmti_flush (g);
    assert_int_equal (f->sink.n, 1);
    s_mti_free (&x);
    gw_gmti_destroy (&g);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown (test_dwell, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_default_clock, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_truth_tags, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_hit_left_out, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_platform, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_split_last, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_split_not_last, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_no_hits, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_invalid, s_setup, s_teardown),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
