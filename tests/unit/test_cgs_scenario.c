/* Unit tests of uavsim_scenario: the shipped scenarios load; every value lands
 * in the struct (positions in every form against cgs_geo's conversions,
 * per-point speeds and halts, defaults, ids); malformed scenarios fail with
 * the file, the exact line and the reason. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "cgs_geo.h"
#include "cgs_scenario.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define S_LAT 35.9600 // the default exercise's origin, Fort Hunter Liggett
#define S_LON -121.2300

typedef struct {
    char dir[64];   // a fresh temporary folder
    char path[128]; // dir/s.ini
    char dem[128];  // dir/hills.asc, an empty stand-in for a DEM
    cgs_geo_t *frame;
} s_tmp_t;

static int s_setup (void **state)
{
    s_tmp_t *t = calloc (1, sizeof *t);
    if (!t)
        return -1;
    snprintf (t->dir, sizeof t->dir, "/tmp/test_uavsim_scenario.XXXXXX");
    if (!mkdtemp (t->dir)) {
        free (t);
        return -1;
    }
    snprintf (t->path, sizeof t->path, "%s/s.ini", t->dir);
    snprintf (t->dem, sizeof t->dem, "%s/hills.asc", t->dir);
    t->frame = cgs_geo_new (S_LAT, S_LON, 0);
    *state = t;
    return t->frame ? 0 : -1;
}

static int s_teardown (void **state)
{
    s_tmp_t *t = *state;
    unlink (t->path);
    unlink (t->dem);
    rmdir (t->dir);
    cgs_geo_destroy (&t->frame);
    free (t);
    return 0;
}

static void s_write (const char *path, const char *text)
{
    FILE *f = fopen (path, "w");
    assert_non_null (f);
    fputs (text, f);
    fclose (f);
}

// Write text to the scenario file and load it with exercise seed 7; fails the test unless it loads.
static cgs_scenario_t *s_load (s_tmp_t *t, const char *text)
{
    s_write (t->path, text);
    char err[512] = "";
    cgs_scenario_t *sc = NULL;
    int rc = cgs_scenario_load (t->path, t->frame, 7, &sc, err, sizeof err);
    if (rc != 0)
        fail_msg ("load failed: %s", err);
    assert_non_null (sc);
    return sc;
}

// Loading text fails with -EINVAL, leaves *ret alone, and says "<path>" followed by expected.
static void s_fails (s_tmp_t *t, const char *text, const char *expected)
{
    s_write (t->path, text);
    char err[512] = "", want[640];
    cgs_scenario_t *sc = (cgs_scenario_t *)0x1;
    assert_int_equal (cgs_scenario_load (t->path, t->frame, 7, &sc, err, sizeof err), -EINVAL);
    assert_ptr_equal (sc, (cgs_scenario_t *)0x1);
    snprintf (want, sizeof want, "%s%s", t->path, expected);
    assert_string_equal (err, want);
}

static void s_near (cgs_enu_t a, cgs_enu_t b, double tol_m)
{
    if (fabs (a.e_m - b.e_m) > tol_m || fabs (a.n_m - b.n_m) > tol_m)
        fail_msg ("(%.3f, %.3f) is not within %g m of (%.3f, %.3f)", a.e_m, a.n_m, tol_m, b.e_m,
                  b.n_m);
}

static cgs_scenario_t *s_load_shipped (const char *name, const cgs_geo_t *frame)
{
    const char *root = getenv ("CGS_ROOT");
    char path[1024], err[512] = "";
    snprintf (path, sizeof path, "%s/deploy/scenarios/%s", root ? root : ".", name);
    cgs_scenario_t *sc = NULL;
    int rc = cgs_scenario_load (path, frame, 1, &sc, err, sizeof err);
    if (rc != 0)
        fail_msg ("%s", err);
    return sc;
}

// Turn at point i of a route, degrees (0 = straight on).
static double s_turn_deg (const cgs_point_t *p, size_t i)
{
    double a = atan2 (p[i].position.e_m - p[i - 1].position.e_m,
                      p[i].position.n_m - p[i - 1].position.n_m);
    double b = atan2 (p[i + 1].position.e_m - p[i].position.e_m,
                      p[i + 1].position.n_m - p[i].position.n_m);
    double d = fabs (b - a) * 180 / M_PI;
    return d > 180 ? 360 - d : d;
}

static void test_default_scenario (void **state)
{
    (void)state;
    cgs_geo_t *frame = cgs_geo_new (S_LAT, S_LON, 0);
    cgs_scenario_t *sc = s_load_shipped ("default.ini", frame);
    assert_int_equal (sc->uav_count, 1);
    const cgs_scenario_uav_t *u = cgs_scenario_uav (sc, "uav1");
    assert_non_null (u);
    assert_int_equal (u->id, 1);
    assert_true (sc->vehicle_count >= 12);
    assert_int_equal (sc->terrain.source, CGS_TERRAIN_FBM);

    size_t friendly_bcis = 0, unknown = 0, sharp = 0, kinds[5] = {0};
    double standoff_m = INFINITY;
    for (size_t i = 0; i < sc->vehicle_count; i++) {
        const cgs_scenario_vehicle_t *v = &sc->vehicles[i];
        assert_int_equal (v->id, i + 2); // ids in file order after the UAV
        friendly_bcis += v->force == CGS_FORCE_FRIENDLY && v->bcis_transponder;
        unknown += v->force == CGS_FORCE_UNKNOWN && !v->bcis_transponder;
        kinds[v->kind]++;
        assert_true (v->speed_mps >= 5 && v->speed_mps <= 15);
        for (size_t j = 0; j < v->point_count; j++) {
            const cgs_point_t *p = &v->points[j];
            double d = hypot (p->position.e_m - u->loiter_center.e_m,
                              p->position.n_m - u->loiter_center.n_m) -
                       u->loiter_radius_m;
            standoff_m = fmin (standoff_m, d);
            if (j > 0 && j + 1 < v->point_count && s_turn_deg (v->points, j) > 90)
                sharp++;
        }
    }
    assert_true (friendly_bcis >= 3);
    assert_true (unknown >= 3);
    assert_true (kinds[CGS_KIND_TRACKED] > 0 && kinds[CGS_KIND_WHEELED] > 0);
    assert_true (sharp >= 2);
    assert_true (standoff_m >= 3000); // a stand-off orbit, a few km from every route point

    // Positions written as geo, hemisphere and MGRS forms.
    const cgs_scenario_vehicle_t *car = cgs_scenario_vehicle (sc, "n_car");
    assert_non_null (car);
    s_near (car->points[0].position, (cgs_enu_t){-3000, -1000, 0}, 1.0);
    s_near (car->points[1].position, (cgs_enu_t){0, -1500, 0}, 1.0);
    s_near (u->loiter_center, (cgs_enu_t){-6000, -7000, 0}, 30.0);

    assert_int_equal (sc->designation_count, 1);
    assert_int_equal (sc->designations[0].pick, CGS_PICK_UNKNOWN);
    assert_true (sc->designations[0].time_s == 120);
    cgs_scenario_destroy (&sc);
    assert_null (sc);
    cgs_geo_destroy (&frame);
}

static void test_bench_scenario (void **state)
{
    (void)state;
    cgs_scenario_t *sc = s_load_shipped ("bench-1000.ini", NULL); // local metres only
    assert_int_equal (sc->uav_count, 1);
    assert_int_equal (sc->vehicle_count, 1000);
    assert_int_equal (sc->vehicles[999].id, 1001);
    size_t forces[4] = {0};
    for (size_t i = 0; i < sc->vehicle_count; i++) {
        assert_true (sc->vehicles[i].point_count >= 2);
        forces[sc->vehicles[i].force]++;
    }
    for (int f = 0; f < 4; f++)
        assert_true (forces[f] > 0);
    cgs_scenario_destroy (&sc);
}

/* Distance from (e, n) to the route's polyline (with the closing leg of a loop). */
static double s_route_dist (const cgs_scenario_vehicle_t *v, double e, double n)
{
    double best = INFINITY;
    size_t legs = v->point_count - (v->end != CGS_END_LOOP);
    for (size_t i = 0; i < legs; i++) {
        const cgs_enu_t *a = &v->points[i].position,
                        *b = &v->points[(i + 1) % v->point_count].position;
        double de = b->e_m - a->e_m, dn = b->n_m - a->n_m;
        double u = ((e - a->e_m) * de + (n - a->n_m) * dn) / (de * de + dn * dn);
        u = u < 0 ? 0 : u > 1 ? 1 : u;
        best = fmin (best, hypot (e - (a->e_m + u * de), n - (a->n_m + u * dn)));
    }
    return best;
}

/* The scenario families for Monte Carlo runs: each is a whole scene with the
 * default UAV and parameter files, friendly vehicles with BCIS and unknown
 * ones without, and a designation of an unknown track next to the route of
 * an unknown vehicle. */
static void test_families (void **state)
{
    (void)state;
    static const char *const names[] = {"convoy.ini",  "crossing.ini", "notch.ini",
                                        "stop-go.ini", "masked.ini",   "dense.ini"};
    cgs_geo_t *frame = cgs_geo_new (S_LAT, S_LON, 0);
    for (size_t f = 0; f < sizeof names / sizeof names[0]; f++) {
        cgs_scenario_t *sc = s_load_shipped (names[f], frame);
        assert_int_equal (sc->uav_count, 1);
        const cgs_scenario_uav_t *u = cgs_scenario_uav (sc, "uav1");
        assert_non_null (u);
        assert_non_null (strstr (u->radar_params, "/params/radar.ini"));
        assert_non_null (strstr (u->bcis_params, "/params/bcis.ini"));
        assert_true (u->sensor_depression_deg == 45 && u->sensor_hfov_deg == 10 &&
                     u->sensor_vfov_deg == 7.5);
        s_near (u->loiter_center, (cgs_enu_t){-6004, -6999, 0}, 1);
        size_t friendly_bcis = 0, unknown = 0, halts = 0;
        for (size_t i = 0; i < sc->vehicle_count; i++) {
            const cgs_scenario_vehicle_t *v = &sc->vehicles[i];
            friendly_bcis += v->force == CGS_FORCE_FRIENDLY && v->bcis_transponder;
            unknown += v->force == CGS_FORCE_UNKNOWN && !v->bcis_transponder;
            for (size_t j = 0; j < v->point_count; j++)
                if (v->points[j].halt_s > 0) {
                    halts++;
                    assert_true (v->points[j].halt_s >= 30 && v->points[j].halt_s <= 120);
                }
        }
        assert_true (friendly_bcis >= 1 && unknown >= 1);
        assert_int_equal (sc->designation_count, 1);
        const cgs_designation_t *d = &sc->designations[0];
        assert_int_equal (d->pick, CGS_PICK_UNKNOWN);
        double near = INFINITY;
        for (size_t i = 0; i < sc->vehicle_count; i++)
            if (sc->vehicles[i].force == CGS_FORCE_UNKNOWN)
                near = fmin (near, s_route_dist (&sc->vehicles[i], d->near.e_m, d->near.n_m));
        print_message ("%-12s %3zu vehicles (%zu friendly with BCIS, %zu unknown), %zu halts; "
                       "designation at %.0f s, %.1f m from an unknown's route\n",
                       names[f], sc->vehicle_count, friendly_bcis, unknown, halts, d->time_s, near);
        assert_true (near <= 10);
        if (strcmp (names[f], "stop-go.ini") == 0)
            assert_true (halts >= 5);
        if (strcmp (names[f], "dense.ini") == 0)
            assert_int_equal (sc->vehicle_count, 201);
        if (strcmp (names[f], "convoy.ini") == 0)
            assert_true (sc->vehicle_count >= 12);
        cgs_scenario_destroy (&sc);
    }
    cgs_geo_destroy (&frame);
}

static void test_values (void **state)
{
    s_tmp_t *t = *state;
    // MGRS and geodetic spellings of known local points, through cgs_geo.
    cgs_geodetic_t g1, g2, g3;
    assert_int_equal (cgs_geo_enu_to_geodetic (t->frame, (cgs_enu_t){1500, -2500, 0}, &g1), 0);
    assert_int_equal (cgs_geo_enu_to_geodetic (t->frame, (cgs_enu_t){-4000, 3000, 0}, &g2), 0);
    assert_int_equal (cgs_geo_enu_to_geodetic (t->frame, (cgs_enu_t){2200, 700, 0}, &g3), 0);
    char mgrs[32];
    assert_int_equal (cgs_geo_to_mgrs (g3, 5, mgrs, sizeof mgrs), 0);
    cgs_geodetic_t g3m; // the MGRS square's centre
    assert_int_equal (cgs_geo_from_mgrs (mgrs, &g3m, NULL), 0);
    cgs_enu_t want3;
    assert_int_equal (cgs_geo_geodetic_to_enu (t->frame, g3m, &want3), 0);
    s_write (t->dem, "");

    char text[4096];
    snprintf (text, sizeof text,
              "; every key\n"
              "[terrain]\n"
              "dem = hills.asc\n"
              "resolution_m = 25\n"
              "half_extent_m = 6000\n"
              "\n"
              "[uav hawk]\n"
              "id = 40\n"
              "marking = HAWK-1\n"
              "dis_type = 1 2 225 50 3 1 0\n"
              "position = geo %.9f %.9f %.6f\n"
              "altitude_agl_m = 1500\n"
              "airspeed_mps = 36.5\n"
              "heading_deg = 270\n"
              "loiter_center = %.9f%c %.9f%c %.6f\n"
              "loiter_radius_m = 2000\n"
              "loiter_direction = anticlockwise\n"
              "bank_limit_deg = 25\n"
              "climb_rate_mps = 4\n"
              "airspeed_min_mps = 25\n"
              "airspeed_max_mps = 70\n"
              "sensor_depression_deg = 40\n"
              "sensor_hfov_deg = 12\n"
              "sensor_vfov_deg = 9\n"
              "radar_params = params/radar.ini\n"
              "bcis_params = /etc/mscgs/bcis.ini\n"
              "\n"
              "[vehicle alpha]\n"
              "marking = A 1\n"
              "force = hostile\n"
              "kind = wheeled\n"
              "dis_type = 1 1 222 7 2 0 0\n"
              "bcis_transponder = yes\n"
              "rcs_class = truck\n"
              "start_time_s = 30\n"
              "speed_mps = 9\n"
              "point = 100 200\n"
              "point = local 1100 200 5 @ 6.5\n"
              "point = mgrs %s\n"
              "point = -500 900@12\n"
              "end = loop\n"
              "deviation_m = 12\n"
              "deviation_seed = 99\n"
              "\n"
              "[vehicle bravo]\n"
              "force = friendly\n"
              "point = 0 0\n"
              "point = 0 1000\n"
              "end = reverse\n"
              "\n"
              "[operator]\n"
              "designate = any nearest 35.97N 121.22W at 75.5\n"
              "designate = friendly nearest mgrs %s at 200\n"
              "\n"
              "[uavsim]\n"
              "step_s = 0.02\n"
              "entity_rate_hz = 25\n"
              "uav_rate_hz = 5\n"
              "clock_rate_hz = 50\n"
              "checkpoint_interval_s = 2.5\n",
              g1.lat_deg, g1.lon_deg, g1.height_m, fabs (g2.lat_deg), g2.lat_deg < 0 ? 'S' : 'N',
              fabs (g2.lon_deg), g2.lon_deg < 0 ? 'W' : 'E', g2.height_m, mgrs, mgrs);
    cgs_scenario_t *sc = s_load (t, text);
    assert_string_equal (sc->path, t->path);

    char want[256];
    assert_int_equal (sc->terrain.source, CGS_TERRAIN_DEM);
    assert_string_equal (sc->terrain.dem_path, t->dem);
    assert_true (sc->terrain.resolution_m == 25 && sc->terrain.half_extent_m == 6000);

    assert_int_equal (sc->uav_count, 1);
    const cgs_scenario_uav_t *u = &sc->uavs[0];
    assert_string_equal (u->name, "hawk");
    assert_int_equal (u->line, 7);
    assert_int_equal (u->id, 40);
    assert_string_equal (u->marking, "HAWK-1");
    assert_int_equal (u->dis_type.kind, 1);
    assert_int_equal (u->dis_type.domain, 2);
    assert_int_equal (u->dis_type.country, 225);
    assert_int_equal (u->dis_type.category, 50);
    assert_int_equal (u->dis_type.subcategory, 3);
    assert_int_equal (u->dis_type.specific, 1);
    assert_int_equal (u->dis_type.extra, 0);
    s_near (u->position, (cgs_enu_t){1500, -2500, 0}, 1e-3);
    s_near (u->loiter_center, (cgs_enu_t){-4000, 3000, 0}, 1e-3);
    assert_true (u->altitude_agl_m == 1500 && u->airspeed_mps == 36.5 && u->heading_deg == 270);
    assert_true (u->loiter_radius_m == 2000 && !u->loiter_clockwise);
    assert_true (u->bank_limit_deg == 25 && u->climb_rate_mps == 4);
    assert_true (u->airspeed_min_mps == 25 && u->airspeed_max_mps == 70);
    assert_true (u->sensor_depression_deg == 40 && u->sensor_hfov_deg == 12 &&
                 u->sensor_vfov_deg == 9);
    snprintf (want, sizeof want, "%s/params/radar.ini", t->dir);
    assert_string_equal (u->radar_params, want);
    assert_string_equal (u->bcis_params, "/etc/mscgs/bcis.ini");

    assert_int_equal (sc->vehicle_count, 2);
    const cgs_scenario_vehicle_t *a = cgs_scenario_vehicle (sc, "alpha");
    assert_ptr_equal (a, &sc->vehicles[0]);
    assert_int_equal (a->id, 1); // auto ids skip none below 40
    assert_int_equal (a->line, 28);
    assert_string_equal (a->marking, "A 1");
    assert_int_equal (a->force, CGS_FORCE_HOSTILE);
    assert_int_equal (a->force, 2); // proto Force numbers
    assert_int_equal (a->kind, CGS_KIND_WHEELED);
    assert_int_equal (a->dis_type.country, 222);
    assert_int_equal (a->dis_type.category, 7);
    assert_true (a->bcis_transponder); // allowed on a hostile
    assert_string_equal (a->rcs_class, "truck");
    assert_true (a->start_time_s == 30 && a->speed_mps == 9);
    assert_int_equal (a->end, CGS_END_LOOP);
    assert_true (a->deviation_m == 12);
    assert_true (a->deviation_seed == 99);
    assert_int_equal (a->point_count, 4);
    s_near (a->points[0].position, (cgs_enu_t){100, 200, 0}, 0);
    s_near (a->points[1].position, (cgs_enu_t){1100, 200, 0}, 0);
    assert_true (a->points[1].position.u_m == 5);
    s_near (a->points[2].position, want3, 1e-6);
    s_near (a->points[3].position, (cgs_enu_t){-500, 900, 0}, 0); // no blank needed before '@'
    s_near (a->points[2].position, (cgs_enu_t){2200, 700, 0}, 1.0);
    // per-point speeds: the vehicle's unless '@' gives one; the last is the closing leg's
    assert_true (a->points[0].speed_mps == 9 && !a->points[0].speed_given);
    assert_true (a->points[1].speed_mps == 6.5 && a->points[1].speed_given);
    assert_true (a->points[2].speed_mps == 9 && !a->points[2].speed_given);
    assert_true (a->points[3].speed_mps == 12 && a->points[3].speed_given);
    assert_int_equal (a->points[0].line, 37);
    assert_int_equal (a->points[3].line, 40);

    const cgs_scenario_vehicle_t *b = cgs_scenario_vehicle (sc, "bravo");
    assert_int_equal (b->id, 2);
    assert_int_equal (b->end, CGS_END_REVERSE);
    assert_null (cgs_scenario_vehicle (sc, "charlie"));

    assert_int_equal (sc->designation_count, 2);
    cgs_geodetic_t gd = {35.97, -121.22, 0};
    cgs_enu_t d0;
    assert_int_equal (cgs_geo_geodetic_to_enu (t->frame, gd, &d0), 0);
    assert_int_equal (sc->designations[0].pick, CGS_PICK_ANY);
    s_near (sc->designations[0].near, d0, 1e-6);
    assert_true (sc->designations[0].time_s == 75.5);
    assert_int_equal (sc->designations[0].line, 52);
    assert_int_equal (sc->designations[1].pick, CGS_PICK_FRIENDLY);
    s_near (sc->designations[1].near, want3, 1e-6);
    assert_true (sc->designations[1].time_s == 200);

    assert_true (sc->settings.step_s == 0.02 && sc->settings.entity_rate_hz == 25);
    assert_true (sc->settings.uav_rate_hz == 5 && sc->settings.clock_rate_hz == 50);
    assert_true (sc->settings.checkpoint_interval_s == 2.5);
    cgs_scenario_destroy (&sc);
    cgs_scenario_destroy (&sc); // idempotent
}

static void test_defaults (void **state)
{
    s_tmp_t *t = *state;
    cgs_scenario_t *sc = s_load (t, "[vehicle a_very_long_name]\n"
                                    "force = friendly\n"
                                    "point = 0 0\n"
                                    "point = 500 0\n"
                                    "[vehicle b]\n"
                                    "id = 1\n"
                                    "force = unknown\n"
                                    "kind = wheeled\n"
                                    "point = 0 0\n"
                                    "point = 500 0\n"
                                    "[vehicle c]\n"
                                    "force = neutral\n"
                                    "kind = person\n"
                                    "point = 0 0\n"
                                    "point = 50 0\n"
                                    "[uav u]\n"
                                    "position = 1000 2000\n");
    // fBm terrain with the documented defaults, seeded with the exercise seed
    assert_int_equal (sc->terrain.source, CGS_TERRAIN_FBM);
    assert_null (sc->terrain.dem_path);
    cgs_terrain_fbm_t f;
    cgs_terrain_fbm_defaults (&f);
    const cgs_terrain_fbm_t *got = &sc->terrain.fbm;
    assert_true (got->seed == 7 && got->size_m == f.size_m && got->resolution_m == f.resolution_m &&
                 got->relief_m == f.relief_m && got->base_height_m == f.base_height_m &&
                 got->feature_m == f.feature_m && got->octaves == f.octaves &&
                 got->persistence == f.persistence);

    const cgs_scenario_uav_t *u = &sc->uavs[0];
    assert_int_equal (u->id, 2); // UAVs first; 1 is taken by b
    assert_string_equal (u->marking, "u");
    cgs_dis_type_t uav_type = {1, 2, 225, 50, 0, 0, 0};
    assert_memory_equal (&u->dis_type, &uav_type, sizeof uav_type);
    s_near (u->loiter_center, u->position, 0);
    assert_true (u->altitude_agl_m == 1200 && u->airspeed_mps == 35 && u->heading_deg == 0);
    assert_true (u->loiter_radius_m == 1500 && u->loiter_clockwise);
    assert_true (u->bank_limit_deg == 30 && u->climb_rate_mps == 5);
    assert_true (u->airspeed_min_mps == 20 && u->airspeed_max_mps == 60);
    assert_true (u->sensor_depression_deg == 45 && u->sensor_hfov_deg == 10 &&
                 u->sensor_vfov_deg == 7.5);
    assert_string_equal (u->radar_params, "");
    assert_string_equal (u->bcis_params, "");

    const cgs_scenario_vehicle_t *a = &sc->vehicles[0], *b = &sc->vehicles[1],
                                 *c = &sc->vehicles[2];
    assert_int_equal (a->id, 3);
    assert_int_equal (b->id, 1);
    assert_int_equal (c->id, 4);
    assert_string_equal (a->marking, "a_very_long"); // the name, cut to 11
    assert_int_equal (a->kind, CGS_KIND_TRACKED);
    cgs_dis_type_t tracked_usa = {1, 1, 225, 2, 0, 0, 0}, wheeled_other = {1, 1, 0, 6, 0, 0, 0},
                   person_other = {3, 1, 0, 0, 0, 0, 0};
    assert_memory_equal (&a->dis_type, &tracked_usa, sizeof tracked_usa);
    assert_memory_equal (&b->dis_type, &wheeled_other, sizeof wheeled_other);
    assert_memory_equal (&c->dis_type, &person_other, sizeof person_other);
    assert_int_equal (c->kind, CGS_KIND_PERSON);
    assert_true (a->bcis_transponder);
    assert_false (b->bcis_transponder);
    assert_false (c->bcis_transponder);
    assert_string_equal (a->rcs_class, "vehicle");
    assert_true (a->start_time_s == 0 && a->speed_mps == 10 && c->speed_mps == 1.5);
    assert_true (a->points[1].speed_mps == 10 && !a->points[1].speed_given);
    assert_int_equal (a->end, CGS_END_STOP);
    assert_true (a->deviation_m == 0);
    assert_true (a->deviation_seed == cgs_scenario_vehicle_seed (7, 3));
    assert_true (b->deviation_seed == cgs_scenario_vehicle_seed (7, 1));
    assert_true (a->deviation_seed != b->deviation_seed);
    assert_true (cgs_scenario_vehicle_seed (8, 3) != a->deviation_seed);

    assert_int_equal (sc->designation_count, 0);
    assert_null (sc->designations);
    assert_true (sc->settings.step_s == 0.05 && sc->settings.entity_rate_hz == 10 &&
                 sc->settings.uav_rate_hz == 10 && sc->settings.clock_rate_hz == 10 &&
                 sc->settings.checkpoint_interval_s == 5);
    cgs_scenario_destroy (&sc);
}

#define S_UAV "[uav u]\nposition = 0 0\n"        // lines 1-2
#define S_CAR "[vehicle car]\nforce = unknown\n" // lines 3-4 after S_UAV

static void test_errors (void **state)
{
    s_tmp_t *t = *state;
    // a bad position
    s_fails (t, S_UAV S_CAR "point = 0 0\npoint = 100 north\n",
             ":6: [vehicle car] point: expected a position as `E N [U]` or `local E N [U]` in "
             "metres, `geo LAT LON [H]`, `LAT{N|S} LON{E|W} [H]` or `mgrs GRID`, got '100 north'");
    s_fails (t, S_UAV S_CAR "point = 0 0\npoint = geo 95 10\n",
             ":6: [vehicle car] point: latitude 95 is outside [-90, 90] in 'geo 95 10'");
    s_fails (t, "[uav u]\nposition = mgrs 99ZZZ\n",
             ":2: [uav u] position: 'mgrs 99ZZZ' is not an MGRS reference (expected e.g. `mgrs "
             "10SEG 12345 67890`)");
    s_fails (t, S_UAV S_CAR "point = 0 0\npoint = geo 40 -121.23\n",
             ":6: [vehicle car] point: position is 448 km from the exercise origin (at most 200 "
             "km)");
    s_fails (t, S_UAV S_CAR "point = 0 0\npoint = 10500 0\n",
             ":6: [vehicle car] point: (10500, 0) is off the procedural terrain, a 20000 m square "
             "about the origin");
    // a route with one point, or none
    s_fails (t, S_UAV S_CAR "speed_mps = 8\npoint = 0 0\nend = loop\n",
             ":6: [vehicle car] point: a route needs at least 2 points, this is its only one");
    s_fails (t, S_UAV S_CAR,
             ":3: [vehicle car] missing key 'point' (expected a route of at least 2 `point = "
             "POSITION [@ SPEED_MPS]` lines)");
    s_fails (t, S_UAV S_CAR "point = 0 0\npoint = 0.5 0\n",
             ":6: [vehicle car] point: within 1 m of the previous point (line 5): a leg needs a "
             "length");
    s_fails (t, S_UAV S_CAR "end = loop\npoint = 0 0\npoint = 0 100\npoint = 0 0\n",
             ":8: [vehicle car] point: repeats the first point: with end = loop the route closes "
             "by itself, so leave this point out");
    s_fails (t, S_UAV S_CAR "point = 0 0\npoint = 0 100 @ 5\n",
             ":6: [vehicle car] point: no leg starts at the last point, so it takes no speed "
             "(only with end = loop, for the leg back to the first point)");
    // an unknown force, a missing one
    s_fails (t, S_UAV "[vehicle car]\nforce = enemy\npoint = 0 0\npoint = 0 100\n",
             ":4: [vehicle car] force: expected one of 'unknown', 'friendly', 'hostile', "
             "'neutral', got 'enemy'");
    s_fails (t, S_UAV "[vehicle car]\n\npoint = 0 0\npoint = 0 100\n",
             ":3: [vehicle car] missing key 'force' (expected friendly, hostile, neutral or "
             "unknown)");
    // an unknown key, section, operator key
    s_fails (t, S_UAV S_CAR "point = 0 0\npoint = 0 100\nspeed = 8\n",
             ":7: [vehicle car] unknown key 'speed'");
    s_fails (t, S_UAV "[vehicles car]\nforce = unknown\n", ":3: unknown section [vehicles car]");
    s_fails (t, S_UAV "[operator]\ndesignate = unknown nearest 0 0 at 10\ncancel = at 20\n",
             ":5: [operator] unknown key 'cancel'");
    // a duplicate vehicle name, a name shared by a UAV and a vehicle, a duplicate id
    s_fails (t,
             S_UAV S_CAR "point = 0 0\npoint = 0 100\n\n[vehicle car]\nforce = hostile\n"
                         "point = 0 0\npoint = 0 100\n",
             ":8: [vehicle car] given twice (first at line 3)");
    s_fails (t, S_UAV "[vehicle u]\nforce = hostile\npoint = 0 0\npoint = 0 100\n",
             ":3: [vehicle u] name 'u' is already used by [uav u] (line 1)");
    s_fails (t,
             S_UAV S_CAR "id = 5\npoint = 0 0\npoint = 0 100\n"
                         "[vehicle two]\nforce = hostile\nid = 5\npoint = 0 0\npoint = 0 100\n",
             ":10: [vehicle two] id: 5 is already the id of [vehicle car] (line 5)");
    s_fails (t, S_UAV "[vehicle bad name!]\nforce = hostile\n",
             ":3: [vehicle bad name!] expected `[vehicle NAME]` with a NAME of 1 to 63 letters, "
             "digits, '_', '.' or '-', got 'bad name!'");
    // a bad entity type, a bad marking
    s_fails (t, S_UAV S_CAR "dis_type = 1 1 225 2 0 0\npoint = 0 0\npoint = 0 100\n",
             ":5: [vehicle car] dis_type: expected seven integers `kind domain country category "
             "subcategory specific extra` (country 0..65535, the others 0..255), got '1 1 225 2 "
             "0 0'");
    s_fails (t, "[uav u]\nposition = 0 0\ndis_type = 1 2 225 256 0 0 0\n",
             ":3: [uav u] dis_type: expected seven integers `kind domain country category "
             "subcategory specific extra` (country 0..65535, the others 0..255), got '1 2 225 "
             "256 0 0 0'");
    s_fails (t, "[uav u]\nposition = 0 0\nmarking = TWELVE CHARS\n",
             ":3: [uav u] marking: expected 1 to 11 printable ASCII characters, got 'TWELVE "
             "CHARS'");
    // a speed out of range, on the vehicle and on a point
    s_fails (t, S_UAV S_CAR "speed_mps = 90\npoint = 0 0\npoint = 0 100\n",
             ":5: [vehicle car] speed_mps: expected a number in [0.5, 40], got '90'");
    s_fails (t, S_UAV S_CAR "point = 0 0 @ 0\npoint = 0 100\n",
             ":5: [vehicle car] point: expected a speed after '@' in [0.5, 40] m/s, got '0'");
    s_fails (t, S_UAV S_CAR "point = 0 0 @ fast\npoint = 0 100\n",
             ":5: [vehicle car] point: expected a speed after '@' in [0.5, 40] m/s, got 'fast'");
    s_fails (t, S_UAV S_CAR "point = 0 0 @ 5 @ 6\npoint = 0 100\n",
             ":5: [vehicle car] point: expected `point = POSITION [@ SPEED_MPS]` with one '@' at "
             "most, got '0 0 @ 5 @ 6'");
    s_fails (t, "[uav u]\nposition = 0 0\nairspeed_mps = 40\nairspeed_max_mps = 30\n",
             ":3: [uav u] airspeed_mps: expected a speed between airspeed_min_mps and "
             "airspeed_max_mps (20..30), got 40");
    s_fails (t, "[uav u]\nposition = 0 0\nairspeed_min_mps = 12\nclimb_rate_mps = 12\n",
             ":4: [uav u] climb_rate_mps: expected less than airspeed_min_mps (12), got 12");
    s_fails (t, "[uav u]\nposition = 0 0\nairspeed_mps = 5\n",
             ":3: [uav u] airspeed_mps: expected a number in [10, 120], got '5'");
    // UAV-specific checks
    s_fails (t, "[vehicle car]\nforce = unknown\npoint = 0 0\npoint = 0 100\n",
             ": no [uav NAME] section (a scenario needs a UAV)");
    s_fails (t, "[uav u]\nposition = 0 0\nairspeed_mps = 60\nloiter_radius_m = 300\n",
             ":4: [uav u] loiter_radius_m: 300 m is tighter than the UAV's smallest turn, 636 m "
             "at 60 m/s and 30 deg of bank");
    s_fails (t, "[uav u]\nairspeed_mps = 35\n",
             ":1: [uav u] missing key 'position' (expected a position)");
    s_fails (t, "[uav u]\nposition = 0 0\nloiter_direction = widdershins\n",
             ":3: [uav u] loiter_direction: expected one of 'clockwise', 'anticlockwise', "
             "'counterclockwise', got 'widdershins'");
    // operator, terrain, settings
    s_fails (t, S_UAV "[operator]\ndesignate = hostile nearest 0 0 at 10\n",
             ":4: [operator] designate: expected `designate = {unknown|friendly|any} nearest "
             "POSITION at TIME_S`, got 'hostile nearest 0 0 at 10'");
    s_fails (t, S_UAV "[operator]\ndesignate = unknown nearest 0 0 at -3\n",
             ":4: [operator] designate: expected a time after 'at' in [0, 604800] s, got '-3'");
    s_fails (t, S_UAV "[terrain]\nsize_m = 100000\nresolution_m = 5\n",
             ":5: [terrain] resolution_m: size_m 100000 / resolution_m 5 gives 20001 x 20001 "
             "grid nodes, more than 2^26");
    s_fails (t, S_UAV "[uavsim]\nstep_s = 0.1\nentity_rate_hz = 20\n",
             ":5: [uavsim] entity_rate_hz: 20 Hz is more than one publication per step (step_s "
             "0.1 allows at most 10 Hz)");
    s_fails (t, S_UAV "[uav u]\naltitude_agl_m = 100\n",
             ":3: [uav u] given twice (first at line 1)");
    s_fails (t, S_UAV "nonsense\n", ":3: syntax error (expected `key = value` or `[section]`)");
}

// A DEM given with procedural keys is refused, and a DEM that is not there names its line.
static void test_dem_errors (void **state)
{
    s_tmp_t *t = *state;
    char want[256];
    snprintf (want, sizeof want, ":4: [terrain] dem: %s/nosuch.tif: No such file or directory",
              t->dir);
    s_fails (t, S_UAV "[terrain]\ndem = nosuch.tif\n", want);
    s_write (t->dem, "");
    s_fails (t, S_UAV "[terrain]\ndem = hills.asc\nrelief_m = 100\n",
             ":5: [terrain] relief_m: applies to procedural terrain only, not with `dem =`");
    s_fails (t, S_UAV "[terrain]\nhalf_extent_m = 100\n",
             ":4: [terrain] half_extent_m: applies to a DEM only (`dem =`); procedural terrain "
             "takes size_m");

    char err[512] = "";
    cgs_scenario_t *sc = (cgs_scenario_t *)0x1;
    snprintf (want, sizeof want, "%s/none.ini", t->dir);
    assert_int_equal (cgs_scenario_load (want, t->frame, 1, &sc, err, sizeof err), -ENOENT);
    assert_ptr_equal (sc, (cgs_scenario_t *)0x1);
    strcat (want, ": No such file or directory");
    assert_string_equal (err, want);
}

// A geodetic position needs a frame; without one the file is refused at that line.
static void test_no_frame (void **state)
{
    (void)state;
    char err[512] = "";
    cgs_scenario_t *sc = NULL;
    assert_int_equal (cgs_scenario_load_string ("x.ini", "[uav u]\nposition = geo 36 -121\n", NULL,
                                                1, &sc, err, sizeof err),
                      -EINVAL);
    assert_null (sc);
    assert_string_equal (err, "x.ini:2: [uav u] position: 'geo 36 -121' is geodetic, but there "
                              "is no exercise origin to place it");
    assert_int_equal (cgs_scenario_load_string ("x.ini", "[uav u]\nposition = 5 6\n", NULL, 1, &sc,
                                                err, sizeof err),
                      0);
    assert_int_equal (sc->vehicle_count, 0);
    cgs_scenario_destroy (&sc);
}

/* The stand-off check, worked by hand: the orbit about (0, 0), radius 1500,
 * stand-off 1000 (the default). Vehicle a: a leg along n = 3000 from
 * (−5000, 3000) to (5000, 3000): nearest the centre at (0, 3000), 3000 m,
 * so 1500 m from the orbit: no warning. Vehicle b: along n = 2000: 500 m
 * from the orbit: warned, leg 0. Vehicle c: its second leg runs from
 * (4000, 0) to (0, 0), through the centre: |p| goes from 0 to 4000 and
 * crosses 1500: distance 0, leg 1. Vehicle d: a leg wholly inside the
 * orbit, from (−300, 400) to (300, 400): |p| from 400 to 500, 1000 m
 * inside the orbit: 1000 is not below 1000: no warning. With standoff_m =
 * 0 nothing is checked. */
static void test_standoff (void **state)
{
    (void)state;
    const char *text = "[uav u]\nposition = 0 0\nloiter_radius_m = 1500\n%s"
                       "[vehicle a]\nforce = hostile\npoint = -5000 3000\npoint = 5000 3000\n"
                       "[vehicle b]\nforce = hostile\npoint = -5000 2000\npoint = 5000 2000\n"
                       "[vehicle c]\nforce = hostile\npoint = 4000 9000\npoint = 4000 0\n"
                       "point = 0 0\n"
                       "[vehicle d]\nforce = hostile\npoint = -300 400\npoint = 300 400\n";
    char buf[1024], err[512] = "";
    snprintf (buf, sizeof buf, text, "");
    cgs_scenario_t *sc = NULL;
    assert_int_equal (cgs_scenario_load_string ("s.ini", buf, NULL, 1, &sc, err, sizeof err), 0);
    assert_true (sc->uavs[0].standoff_m == 1000);
    cgs_standoff_t near[4];
    assert_int_equal (cgs_scenario_standoff (sc, near, 4), 2);
    assert_int_equal (near[0].vehicle, 1);
    assert_int_equal (near[0].leg, 0);
    assert_true (fabs (near[0].distance_m - 500) < 1e-9);
    assert_int_equal (near[1].vehicle, 2);
    assert_int_equal (near[1].leg, 1);
    assert_true (near[1].distance_m == 0);
    char w[512];
    cgs_scenario_standoff_text (sc, &near[0], w, sizeof w);
    assert_string_equal (w, "s.ini:1: [uav u] loiter orbit comes within 500 m of vehicle b's "
                            "route (leg from line 10 to line 11); stand-off is 1000 m");
    assert_int_equal (cgs_scenario_standoff (sc, near, 1), 2); // counts all, writes one
    cgs_scenario_destroy (&sc);
    // A larger stand-off takes in a (1500 m) and d (1000 m) too.
    snprintf (buf, sizeof buf, text, "standoff_m = 1600\n");
    assert_int_equal (cgs_scenario_load_string ("s.ini", buf, NULL, 1, &sc, err, sizeof err), 0);
    assert_int_equal (cgs_scenario_standoff (sc, near, 4), 4);
    assert_true (fabs (near[0].distance_m - 1500) < 1e-9);
    assert_true (fabs (near[3].distance_m - 1000) < 1e-9);
    cgs_scenario_destroy (&sc);
    snprintf (buf, sizeof buf, text, "standoff_m = 0\n");
    assert_int_equal (cgs_scenario_load_string ("s.ini", buf, NULL, 1, &sc, err, sizeof err), 0);
    assert_int_equal (cgs_scenario_standoff (sc, near, 4), 0);
    cgs_scenario_destroy (&sc);
    snprintf (buf, sizeof buf, text, "standoff_m = -1\n");
    assert_int_equal (cgs_scenario_load_string ("s.ini", buf, NULL, 1, &sc, err, sizeof err),
                      -EINVAL);
    assert_non_null (strstr (err, "s.ini:4: [uav u] standoff_m"));
}

/* Woods in [terrain]: read, grown over the terrain at the cover asked;
 * bad values refused with file and line. */
static void test_vegetation (void **state)
{
    s_tmp_t *t = *state;
    cgs_scenario_t *sc = s_load (t, "[terrain]\nsize_m = 3000\nresolution_m = 30\n"
                                    "vegetation_cover = 0.25\ncanopy_height_m = 18\n"
                                    "vegetation_feature_m = 400\n" S_UAV);
    assert_true (sc->terrain.vegetation.cover == 0.25);
    assert_true (sc->terrain.vegetation.canopy_m == 18);
    assert_true (sc->terrain.vegetation.seed == cgs_scenario_vehicle_seed (7, 0));
    cgs_terrain_t *terrain = NULL;
    char err[256];
    assert_int_equal (cgs_scenario_terrain (sc, t->frame, &terrain, err, sizeof err), 0);
    assert_true (fabs (cgs_terrain_vegetated_fraction (terrain) - 0.25) < 1e-4);
    cgs_terrain_destroy (&terrain);
    cgs_scenario_destroy (&sc);
    // None unless asked.
    sc = s_load (t, S_UAV);
    assert_int_equal (cgs_scenario_terrain (sc, t->frame, &terrain, err, sizeof err), 0);
    assert_true (cgs_terrain_vegetated_fraction (terrain) == 0);
    cgs_terrain_destroy (&terrain);
    cgs_scenario_destroy (&sc);
    s_fails (t, "[terrain]\nvegetation_cover = 2\n" S_UAV,
             ":2: [terrain] vegetation_cover: expected a number in [0, 1], got '2'");
    s_fails (t, "[terrain]\ncanopy_height_m = tall\n" S_UAV,
             ":2: [terrain] canopy_height_m: expected a number in [0.5, 100], got 'tall'");
}

/* Halts: `point = POSITION [@ SPEED] [halt S]` with every position form, with
 * and without the speed and the halt, read into the struct. */
static void test_halts (void **state)
{
    s_tmp_t *t = *state;
    enum { FORMS = 6, SUFFIXES = 4 };
    static const char *const suffix_fmt[SUFFIXES] = {"", " @ %g", " halt %g", " @ %g halt %g"};
    char text[8192];
    size_t len = (size_t)snprintf (text, sizeof text,
                                   S_UAV "[vehicle h]\nforce = unknown\n"
                                         "speed_mps = 9\nend = loop\n");
    cgs_enu_t want[FORMS * SUFFIXES];
    double want_speed[FORMS * SUFFIXES], want_halt[FORMS * SUFFIXES];
    for (int f = 0; f < FORMS; f++)
        for (int x = 0; x < SUFFIXES; x++) {
            int i = f * SUFFIXES + x;
            // Points around a ring, well apart.
            cgs_enu_t p = {3000 * sin (i * 0.26), 3000 * cos (i * 0.26), 0};
            cgs_geodetic_t g;
            assert_int_equal (cgs_geo_enu_to_geodetic (t->frame, p, &g), 0);
            char pos[128], mgrs[32];
            if (f == 0)
                snprintf (pos, sizeof pos, "%.3f %.3f", p.e_m, p.n_m);
            else if (f == 1)
                snprintf (pos, sizeof pos, "local %.3f %.3f 12", p.e_m, p.n_m);
            else if (f == 2)
                snprintf (pos, sizeof pos, "geo %.9f %.9f", g.lat_deg, g.lon_deg);
            else if (f == 3) { // a height moves the point in the local frame a little
                snprintf (pos, sizeof pos, "%.9fN %.9fW 400", g.lat_deg, -g.lon_deg);
                g.height_m = 400;
                assert_int_equal (cgs_geo_geodetic_to_enu (t->frame, g, &p), 0);
            } else {
                assert_int_equal (cgs_geo_to_mgrs (g, 5, mgrs, sizeof mgrs), 0);
                cgs_geodetic_t gm; // the square's centre
                assert_int_equal (cgs_geo_from_mgrs (mgrs, &gm, NULL), 0);
                assert_int_equal (cgs_geo_geodetic_to_enu (t->frame, gm, &p), 0);
                if (f == 4) // "mgrs 10SFE 12345 67890"
                    snprintf (pos, sizeof pos, "mgrs %.5s %.5s %.5s", mgrs, mgrs + 5, mgrs + 10);
                else // "10SFE1234567890"
                    snprintf (pos, sizeof pos, "%s", mgrs);
            }
            want[i] = p;
            want_speed[i] = x == 1 || x == 3 ? 5 + 0.5 * i : 9;
            want_halt[i] = x >= 2 ? 1 + 10.25 * i : 0;
            char suffix[64];
            if (x == 2)
                snprintf (suffix, sizeof suffix, suffix_fmt[x], want_halt[i]);
            else
                snprintf (suffix, sizeof suffix, suffix_fmt[x], want_speed[i], want_halt[i]);
            len += (size_t)snprintf (text + len, sizeof text - len, "point = %s%s\n", pos, suffix);
            assert_true (len < sizeof text);
        }
    cgs_scenario_t *sc = s_load (t, text);
    const cgs_scenario_vehicle_t *v = &sc->vehicles[0];
    assert_int_equal (v->point_count, FORMS * SUFFIXES);
    for (size_t i = 0; i < v->point_count; i++) {
        const cgs_point_t *p = &v->points[i];
        s_near (p->position, want[i], 1e-3);
        assert_true (p->speed_mps == want_speed[i]);
        assert_true (p->speed_given == (i % SUFFIXES == 1 || i % SUFFIXES == 3));
        assert_true (p->halt_s == want_halt[i]);
        assert_int_equal (p->line, 7 + (int)i);
    }
    cgs_scenario_destroy (&sc);

    // Spellings: any case, any blanks, no blank needed before '@'; halts on
    // the first and last points of loop and reverse routes.
    sc = s_load (t, S_UAV "[vehicle a]\nforce = unknown\nend = reverse\n"
                          "point = 0 0@7 HALT 30\n"
                          "point = 0 500 \t Halt\t2.5\n"
                          "point = 500 500 halt 3600\n"
                          "[vehicle b]\nforce = friendly\nend = loop\n"
                          "point = 0 0 halt 0.5\n"
                          "point = 0 500\n"
                          "point = 500 500 @ 4 halt 60\n"
                          "[vehicle c]\nforce = friendly\n"
                          "point = 0 0 @ 6\npoint = 0 500 halt 45\npoint = 500 500\n");
    const cgs_scenario_vehicle_t *a = &sc->vehicles[0], *b = &sc->vehicles[1],
                                 *c = &sc->vehicles[2];
    assert_true (a->points[0].halt_s == 30 && a->points[0].speed_mps == 7);
    assert_true (a->points[1].halt_s == 2.5 && a->points[1].speed_mps == 10);
    assert_true (a->points[2].halt_s == 3600);
    s_near (a->points[1].position, (cgs_enu_t){0, 500, 0}, 0);
    assert_true (b->points[0].halt_s == 0.5 && b->points[1].halt_s == 0);
    assert_true (b->points[2].halt_s == 60 && b->points[2].speed_mps == 4);
    assert_true (c->points[0].halt_s == 0 && c->points[1].halt_s == 45 && c->points[2].halt_s == 0);
    cgs_scenario_destroy (&sc);
}

static void test_halt_errors (void **state)
{
    s_tmp_t *t = *state;
    const char *range = ":6: [vehicle car] point: expected a halt after 'halt' in (0, 3600] s, got";
    char want[256];
    const char *bad[] = {"0", "-5", "3600.5", "soon", "", "30s", "nan", "inf"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char text[256];
        snprintf (text, sizeof text,
                  S_UAV S_CAR "point = 0 0\npoint = 0 100 @ 5 halt %s\n"
                              "point = 0 200\n",
                  bad[i]);
        snprintf (want, sizeof want, "%s '%s'", range, bad[i]);
        s_fails (t, text, want);
    }
    s_fails (t, S_UAV S_CAR "point = 0 0\npoint = 0 100 halt 5 halt 6\npoint = 0 200\n",
             ":6: [vehicle car] point: expected `point = POSITION [@ SPEED_MPS] [halt SECONDS]` "
             "with one 'halt' at most, got '0 100 halt 5 halt 6'");
    s_fails (t, S_UAV S_CAR "point = 0 0\npoint = 0 100 halt 5 @ 8\npoint = 0 200\n",
             ":6: [vehicle car] point: expected `point = POSITION [@ SPEED_MPS] [halt SECONDS]` "
             "(the speed before the halt), got '0 100 halt 5 @ 8'");
    // Not a whole word: part of the position or the speed, which then fail.
    s_fails (t, S_UAV S_CAR "point = 0 0\npoint = 0 100 halt30\npoint = 0 200\n",
             ":6: [vehicle car] point: expected a position as `E N [U]` or `local E N [U]` in "
             "metres, `geo LAT LON [H]`, `LAT{N|S} LON{E|W} [H]` or `mgrs GRID`, got '0 100 "
             "halt30'");
    s_fails (t, S_UAV S_CAR "point = 0 0\npoint = 0 100 @ 8halt 30\npoint = 0 200\n",
             ":6: [vehicle car] point: expected a speed after '@' in [0.5, 40] m/s, got '8halt "
             "30'");
    s_fails (t, S_UAV S_CAR "point = 0 0\npoint = halt 30\npoint = 0 200\n",
             ":6: [vehicle car] point: expected a position as `E N [U]` or `local E N [U]` in "
             "metres, `geo LAT LON [H]`, `LAT{N|S} LON{E|W} [H]` or `mgrs GRID`, got ''");
    // Where a stop route never arrives, or arrives for good.
    s_fails (t, S_UAV S_CAR "point = 0 0 @ 5 halt 30\npoint = 0 100\n",
             ":5: [vehicle car] point: with end = stop the vehicle never comes back to its first "
             "point, so it cannot halt there (start_time_s delays its start)");
    s_fails (t, S_UAV S_CAR "point = 0 0\npoint = 0 100\npoint = 0 200 halt 30\n",
             ":7: [vehicle car] point: with end = stop the vehicle stops for good on its last "
             "point, so a halt there means nothing (use end = loop or reverse to drive on)");
    // A halt of a point the route refuses for another reason still names that reason.
    s_fails (t, S_UAV S_CAR "point = 0 0\npoint = 0 0.5 halt 30\npoint = 0 200\n",
             ":6: [vehicle car] point: within 1 m of the previous point (line 5): a leg needs a "
             "length");
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_default_scenario),
        cmocka_unit_test (test_bench_scenario),
        cmocka_unit_test (test_families),
        cmocka_unit_test_setup_teardown (test_values, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_defaults, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_errors, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_dem_errors, s_setup, s_teardown),
        cmocka_unit_test (test_no_frame),
        cmocka_unit_test (test_standoff),
        cmocka_unit_test_setup_teardown (test_vegetation, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_halts, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_halt_errors, s_setup, s_teardown),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
