/* test_geo — cgs_geo against GeographicLib's published examples (CartConvert and
 * GeoConvert manual pages, example-Geocentric.cpp), closed-form WGS84 values,
 * and hand-worked DIS Euler angles. */
#include "cgs_geo.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <string.h>
#include <cmocka.h>

#include "test_util.h"

#define WGS84_A_M 6378137.0
#define WGS84_B_M 6356752.314245179 // a (1 - f), f = 1/298.257223563
#define DEG       (M_PI / 180.0)

// A small seeded generator (splitmix64), so every run draws the same cases.
static double s_uniform (uint64_t *state, double lo, double hi)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return lo + (hi - lo) * ((double)(z >> 11) / 9007199254740992.0);
}

static double s_dist_m (cgs_ecef_t a, cgs_ecef_t b)
{
    return sqrt ((a.x_m - b.x_m) * (a.x_m - b.x_m) + (a.y_m - b.y_m) * (a.y_m - b.y_m) +
                 (a.z_m - b.z_m) * (a.z_m - b.z_m));
}

static double s_enu_dist_m (cgs_enu_t a, cgs_enu_t b)
{
    return sqrt ((a.e_m - b.e_m) * (a.e_m - b.e_m) + (a.n_m - b.n_m) * (a.n_m - b.n_m) +
                 (a.u_m - b.u_m) * (a.u_m - b.u_m));
}

/* ---- lifecycle ---- */

static void test_new_destroy (void **state)
{
    (void)state;
    cgs_geo_destroy (NULL);
    cgs_geo_t *geo = NULL;
    cgs_geo_destroy (&geo);
    assert_null (geo);

    assert_null (cgs_geo_new (95.0, 0.0, 0.0));
    assert_null (cgs_geo_new (-90.5, 0.0, 0.0));
    assert_null (cgs_geo_new (NAN, 0.0, 0.0));
    assert_null (cgs_geo_new (0.0, INFINITY, 0.0));
    assert_null (cgs_geo_new (0.0, 0.0, NAN));

    geo = cgs_geo_new (36.5, -116.9, 900.0);
    assert_non_null (geo);
    cgs_geodetic_t o = cgs_geo_origin (geo);
    assert_true (o.lat_deg == 36.5 && o.lon_deg == -116.9 && o.height_m == 900.0);
    cgs_geo_destroy (&geo);
    assert_null (geo);
    cgs_geo_destroy (&geo); // twice is harmless

    geo = cgs_geo_new (90.0, 0.0, 0.0); // the pole is a valid origin
    assert_non_null (geo);
    cgs_geo_destroy (&geo);
}

/* ---- geocentric ---- */

static void test_geocentric_published (void **state)
{
    (void)state;
    cgs_ecef_t x;

    // Closed form: the equator at the prime meridian is (a, 0, 0), the north
    // pole (0, 0, b), the south pole at height 1000 m (0, 0, -(b + 1000)).
    assert_int_equal (cgs_geo_geodetic_to_ecef ((cgs_geodetic_t){0, 0, 0}, &x), 0);
    assert_near (x.x_m, WGS84_A_M, 1e-6);
    assert_near (x.y_m, 0.0, 1e-6);
    assert_near (x.z_m, 0.0, 1e-6);
    assert_int_equal (cgs_geo_geodetic_to_ecef ((cgs_geodetic_t){90, 0, 0}, &x), 0);
    assert_near (x.x_m, 0.0, 1e-6);
    assert_near (x.y_m, 0.0, 1e-6);
    assert_near (x.z_m, WGS84_B_M, 1e-6);
    assert_int_equal (cgs_geo_geodetic_to_ecef ((cgs_geodetic_t){-90, 0, 1000}, &x), 0);
    assert_near (x.z_m, -(WGS84_B_M + 1000.0), 1e-6);
    assert_int_equal (cgs_geo_geodetic_to_ecef ((cgs_geodetic_t){0, 90, 0}, &x), 0);
    assert_near (x.x_m, 0.0, 1e-6);
    assert_near (x.y_m, WGS84_A_M, 1e-6);

    // GeographicLib CartConvert(1), EXAMPLES:
    //   echo 33.3 44.4 6000 | CartConvert => 3816209.60 3737108.55 3485109.57
    assert_int_equal (cgs_geo_geodetic_to_ecef ((cgs_geodetic_t){33.3, 44.4, 6000}, &x), 0);
    assert_near (x.x_m, 3816209.60, 0.005);
    assert_near (x.y_m, 3737108.55, 0.005);
    assert_near (x.z_m, 3485109.57, 0.005);

    // GeographicLib example-Geocentric.cpp: Mt Everest, 27.99 86.93 8820,
    // printed rounded to km as 302 5636 2980 (the values its reverse sample uses).
    assert_int_equal (cgs_geo_geodetic_to_ecef ((cgs_geodetic_t){27.99, 86.93, 8820}, &x), 0);
    assert_near (floor (x.x_m / 1000 + 0.5), 302, 0);
    assert_near (floor (x.y_m / 1000 + 0.5), 5636, 0);
    assert_near (floor (x.z_m / 1000 + 0.5), 2980, 0);

    // CartConvert(1): echo 30000 30000 0 | CartConvert -r => 6.483 45 -6335709.73
    cgs_geodetic_t g;
    assert_int_equal (cgs_geo_ecef_to_geodetic ((cgs_ecef_t){30000, 30000, 0}, &g), 0);
    assert_near (g.lat_deg, 6.483, 0.0005);
    assert_near (g.lon_deg, 45.0, 1e-9);
    assert_near (g.height_m, -6335709.73, 0.005);

    // And back from the published ECEF point.
    assert_int_equal (
        cgs_geo_ecef_to_geodetic ((cgs_ecef_t){3816209.60, 3737108.55, 3485109.57}, &g), 0);
    assert_near (g.lat_deg, 33.3, 1e-7);
    assert_near (g.lon_deg, 44.4, 1e-7);
    assert_near (g.height_m, 6000.0, 0.01);
}

static void test_geocentric_rejects (void **state)
{
    (void)state;
    cgs_ecef_t x = {1, 2, 3};
    assert_int_equal (cgs_geo_geodetic_to_ecef ((cgs_geodetic_t){90.001, 0, 0}, &x), -EINVAL);
    assert_int_equal (cgs_geo_geodetic_to_ecef ((cgs_geodetic_t){NAN, 0, 0}, &x), -EINVAL);
    assert_int_equal (cgs_geo_geodetic_to_ecef ((cgs_geodetic_t){0, 0, INFINITY}, &x), -EINVAL);
    assert_true (x.x_m == 1 && x.y_m == 2 && x.z_m == 3); // untouched on failure

    cgs_geodetic_t g = {1, 2, 3};
    assert_int_equal (cgs_geo_ecef_to_geodetic ((cgs_ecef_t){NAN, 0, 0}, &g), -EINVAL);
    assert_int_equal (cgs_geo_ecef_to_geodetic ((cgs_ecef_t){0, -INFINITY, 0}, &g), -EINVAL);
    assert_true (g.lat_deg == 1 && g.lon_deg == 2 && g.height_m == 3);
}

/* ---- local frame ---- */

static void test_local_published (void **state)
{
    (void)state;
    // CartConvert(1): echo 33.3 44.4 6000 | CartConvert -l 33 44 20
    //   => 37288.97 33374.29 5783.64
    cgs_geo_t *geo = cgs_geo_new (33, 44, 20);
    assert_non_null (geo);
    cgs_enu_t p;
    assert_int_equal (cgs_geo_geodetic_to_enu (geo, (cgs_geodetic_t){33.3, 44.4, 6000}, &p), 0);
    assert_near (p.e_m, 37288.97, 0.005);
    assert_near (p.n_m, 33374.29, 0.005);
    // The last published digit of u is truncated: evaluating the same point with
    // 40-digit arithmetic (mpmath, the closed-form WGS84 geocentric formulas and
    // the ENU rotation at the origin) gives 37288.9731966 33374.2949469 5783.6466155.
    assert_near (p.u_m, 5783.64, 0.01);
    assert_near (p.e_m, 37288.9731966, 1e-6);
    assert_near (p.n_m, 33374.2949469, 1e-6);
    assert_near (p.u_m, 5783.6466155, 1e-6);

    cgs_geodetic_t g;
    assert_int_equal (cgs_geo_enu_to_geodetic (geo, (cgs_enu_t){37288.97, 33374.29, 5783.64}, &g),
                      0);
    assert_near (g.lat_deg, 33.3, 1e-7);
    assert_near (g.lon_deg, 44.4, 1e-7);
    assert_near (g.height_m, 6000.0, 0.01);

    // The same point through ECEF agrees with the published geocentric values.
    cgs_ecef_t x;
    assert_int_equal (cgs_geo_enu_to_ecef (geo, p, &x), 0);
    assert_near (x.x_m, 3816209.60, 0.005);
    assert_near (x.y_m, 3737108.55, 0.005);
    assert_near (x.z_m, 3485109.57, 0.005);
    cgs_geo_destroy (&geo);
}

static void test_local_axes (void **state)
{
    (void)state;
    // At lat 0, lon 0: east = ECEF +Y, north = +Z, up = +X.
    cgs_geo_t *geo = cgs_geo_new (0, 0, 0);
    cgs_ecef_t v;
    cgs_geo_enu_vector_to_ecef (geo, (cgs_enu_t){1, 0, 0}, &v);
    assert_near (v.x_m, 0, 1e-15);
    assert_near (v.y_m, 1, 1e-15);
    assert_near (v.z_m, 0, 1e-15);
    cgs_geo_enu_vector_to_ecef (geo, (cgs_enu_t){0, 1, 0}, &v);
    assert_near (v.x_m, 0, 1e-15);
    assert_near (v.y_m, 0, 1e-15);
    assert_near (v.z_m, 1, 1e-15);
    cgs_geo_enu_vector_to_ecef (geo, (cgs_enu_t){0, 0, 1}, &v);
    assert_near (v.x_m, 1, 1e-15);
    assert_near (v.y_m, 0, 1e-15);
    assert_near (v.z_m, 0, 1e-15);
    cgs_enu_t e;
    cgs_geo_ecef_vector_to_enu (geo, (cgs_ecef_t){2, 3, 4}, &e);
    assert_near (e.e_m, 3, 1e-15);
    assert_near (e.n_m, 4, 1e-15);
    assert_near (e.u_m, 2, 1e-15);
    cgs_geo_destroy (&geo);

    // At lat 45, lon 90: east = -X, north = (0, -s, s), up = (0, s, s), s = 1/sqrt 2.
    geo = cgs_geo_new (45, 90, 100);
    double s = sqrt (0.5);
    cgs_geo_enu_vector_to_ecef (geo, (cgs_enu_t){1, 0, 0}, &v);
    assert_near (v.x_m, -1, 1e-15);
    assert_near (v.y_m, 0, 1e-15);
    assert_near (v.z_m, 0, 1e-15);
    cgs_geo_enu_vector_to_ecef (geo, (cgs_enu_t){0, 1, 0}, &v);
    assert_near (v.x_m, 0, 1e-15);
    assert_near (v.y_m, -s, 1e-15);
    assert_near (v.z_m, s, 1e-15);
    cgs_geo_enu_vector_to_ecef (geo, (cgs_enu_t){0, 0, 1}, &v);
    assert_near (v.x_m, 0, 1e-15);
    assert_near (v.y_m, s, 1e-15);
    assert_near (v.z_m, s, 1e-15);
    cgs_geo_ecef_vector_to_enu (geo, (cgs_ecef_t){0, s, s}, &e);
    assert_near (e.e_m, 0, 1e-15);
    assert_near (e.n_m, 0, 1e-15);
    assert_near (e.u_m, 1, 1e-15);
    cgs_geo_destroy (&geo);
}

static void test_local_round_trips (void **state)
{
    (void)state;
    const cgs_geodetic_t origins[] = {
        {36.5, -116.9, 900}, {-33.9, 18.4, 0}, {0, 0, 0}, {89.9, 30, 2000}, {12.0, 179.99, 50},
    };
    const cgs_enu_t points[] = {
        {0, 0, 0},           {1000, -2000, 150},    {50000, 0, 0},
        {0, -50000, 3000},   {35355, 35355, 10000}, {-50000, 50000, -200},
        {-12.3, 4.56, 7890},
    };
    for (size_t i = 0; i < sizeof origins / sizeof origins[0]; i++) {
        cgs_geodetic_t o = origins[i];
        cgs_geo_t *geo = cgs_geo_new (o.lat_deg, o.lon_deg, o.height_m);
        assert_non_null (geo);
        for (size_t j = 0; j < sizeof points / sizeof points[0]; j++) {
            cgs_enu_t p = points[j], q;
            cgs_geodetic_t g, g2;
            cgs_ecef_t x, x2;
            // ENU -> geodetic -> ENU
            assert_int_equal (cgs_geo_enu_to_geodetic (geo, p, &g), 0);
            assert_int_equal (cgs_geo_geodetic_to_enu (geo, g, &q), 0);
            assert_near (s_enu_dist_m (p, q), 0, 1e-3);
            // ENU -> ECEF -> ENU
            assert_int_equal (cgs_geo_enu_to_ecef (geo, p, &x), 0);
            assert_int_equal (cgs_geo_ecef_to_enu (geo, x, &q), 0);
            assert_near (s_enu_dist_m (p, q), 0, 1e-3);
            // ENU -> ECEF -> geodetic agrees with ENU -> geodetic
            assert_int_equal (cgs_geo_ecef_to_geodetic (x, &g2), 0);
            assert_int_equal (cgs_geo_geodetic_to_ecef (g, &x2), 0);
            assert_near (s_dist_m (x, x2), 0, 1e-3);
            assert_near (g2.height_m, g.height_m, 1e-3);
            assert_near (g2.lat_deg, g.lat_deg, 1e-8);
            assert_angle_deg (g2.lon_deg, g.lon_deg, 1e-8);
            // geodetic -> ECEF -> geodetic -> ENU
            assert_int_equal (cgs_geo_geodetic_to_enu (geo, g2, &q), 0);
            assert_near (s_enu_dist_m (p, q), 0, 1e-3);
        }
        // The origin maps to zero.
        cgs_enu_t z;
        assert_int_equal (cgs_geo_geodetic_to_enu (geo, o, &z), 0);
        assert_near (s_enu_dist_m (z, (cgs_enu_t){0, 0, 0}), 0, 1e-6);
        cgs_geo_destroy (&geo);
    }
}

static void test_local_curvature (void **state)
{
    (void)state;
    // On the equator the east-west radius of curvature is a. A point d = 1000 m
    // east along the equator at the origin's height lies d^2 / (2a) = 0.0784 m
    // below the tangent plane (the sagitta), and conversely the tangent-plane
    // point (1000, 0, 0) is that much above the ellipsoid.
    const double d = 1000.0, h0 = 250.0;
    cgs_geo_t *geo = cgs_geo_new (0, 10, h0);
    double r = WGS84_A_M + h0;
    double sag = d * d / (2.0 * r);
    assert_near (sag, 0.0784, 0.0001);
    cgs_enu_t p;
    cgs_geodetic_t g = {0, 10 + d / r / DEG, h0}; // arc length d along the parallel
    assert_int_equal (cgs_geo_geodetic_to_enu (geo, g, &p), 0);
    assert_near (p.u_m, -sag, 1e-4);
    assert_near (p.e_m, d, 1e-3); // r sin(d/r) = d - 1.6e-6 m
    assert_near (p.n_m, 0, 1e-9);
    assert_int_equal (cgs_geo_enu_to_geodetic (geo, (cgs_enu_t){d, 0, 0}, &g), 0);
    assert_near (g.height_m - h0, sag, 1e-4);
    cgs_geo_destroy (&geo);

    // At latitude 45 the east-west radius is the prime vertical N = a / sqrt(1 -
    // e^2 sin^2 45) = 6388838.29 m and the drop is d^2 / (2 N) = 0.07826 m.
    geo = cgs_geo_new (45, 0, 0);
    double e2 = 0.0066943799901413165; // f (2 - f)
    double n_m = WGS84_A_M / sqrt (1 - e2 * 0.5);
    double p_m = n_m * cos (45 * DEG); // radius of the parallel
    assert_int_equal (cgs_geo_geodetic_to_enu (geo, (cgs_geodetic_t){45, d / p_m / DEG, 0}, &p), 0);
    assert_near (p.u_m, -d * d / (2 * n_m), 1e-4);
    assert_near (p.u_m, -0.07826, 1e-5);
    cgs_geo_destroy (&geo);
}

static void test_local_rejects (void **state)
{
    (void)state;
    cgs_geo_t *geo = cgs_geo_new (10, 20, 30);
    cgs_enu_t p = {7, 8, 9};
    cgs_geodetic_t g = {1, 2, 3};
    cgs_ecef_t x = {4, 5, 6};
    assert_int_equal (cgs_geo_geodetic_to_enu (geo, (cgs_geodetic_t){91, 0, 0}, &p), -EINVAL);
    assert_int_equal (cgs_geo_geodetic_to_enu (geo, (cgs_geodetic_t){0, NAN, 0}, &p), -EINVAL);
    assert_int_equal (cgs_geo_enu_to_geodetic (geo, (cgs_enu_t){NAN, 0, 0}, &g), -EINVAL);
    assert_int_equal (cgs_geo_enu_to_ecef (geo, (cgs_enu_t){0, INFINITY, 0}, &x), -EINVAL);
    assert_int_equal (cgs_geo_ecef_to_enu (geo, (cgs_ecef_t){0, 0, NAN}, &p), -EINVAL);
    assert_true (p.e_m == 7 && p.n_m == 8 && p.u_m == 9);
    assert_true (g.lat_deg == 1 && g.lon_deg == 2 && g.height_m == 3);
    assert_true (x.x_m == 4 && x.y_m == 5 && x.z_m == 6);
    cgs_geo_destroy (&geo);
}

/* ---- MGRS ---- */

static void test_mgrs_published (void **state)
{
    (void)state;
    char buf[32];
    cgs_geodetic_t g;
    double prec_m = 0;

    // GeoConvert(1), EXAMPLES:
    //   echo E44d24 N33d20 | GeoConvert -m -p -3 => 38SMB4488   (2 digits)
    //   echo 38SMB4488 | GeoConvert => 33.33424 44.40363       (square centre)
    // and MGRS: 38SMB4488 is a 1 km square centred on 38n 444500 3688500.
    assert_int_equal (
        cgs_geo_to_mgrs ((cgs_geodetic_t){33.0 + 20.0 / 60.0, 44.4, 0}, 2, buf, sizeof buf), 0);
    assert_string_equal (buf, "38SMB4488");
    assert_int_equal (cgs_geo_from_mgrs ("38SMB4488", &g, &prec_m), 0);
    assert_near (g.lat_deg, 33.33424, 0.000005);
    assert_near (g.lon_deg, 44.40363, 0.000005);
    assert_true (g.height_m == 0);
    assert_near (prec_m, 1000.0, 0);
    // Spaces and lower case are accepted; the precision pointer may be NULL.
    cgs_geodetic_t g2;
    assert_int_equal (cgs_geo_from_mgrs (" 38s mb 44 88 ", &g2, NULL), 0);
    assert_true (g2.lat_deg == g.lat_deg && g2.lon_deg == g.lon_deg);

    // GeoConvert(1) gives 33.3 44.4 as UTM 38n 444140.54 3684706.36; MGRS
    // truncates, so at 1 m it is 38SMB4414084706 and at 0.1 m (6 digits, which
    // from_mgrs accepts) 38SMB441405847063.
    assert_int_equal (cgs_geo_to_mgrs ((cgs_geodetic_t){33.3, 44.4, 123}, 5, buf, sizeof buf), 0);
    assert_string_equal (buf, "38SMB4414084706");
    assert_int_equal (cgs_geo_to_mgrs ((cgs_geodetic_t){33.3, 44.4, 0}, 0, buf, sizeof buf), 0);
    assert_string_equal (buf, "38SMB");
    assert_int_equal (cgs_geo_from_mgrs ("38SMB4414084706", &g, &prec_m), 0);
    assert_near (prec_m, 1.0, 0);
    assert_near (g.lat_deg, 33.3, 1e-5); // centre of a 1 m square: within 1 m
    assert_near (g.lon_deg, 44.4, 1e-5);
    assert_int_equal (cgs_geo_from_mgrs ("38SMB441405847063", &g, &prec_m), 0);
    assert_near (prec_m, 0.1, 1e-12);
    assert_near (g.lat_deg, 33.3, 1e-6);
    assert_near (g.lon_deg, 44.4, 1e-6);
    assert_int_equal (cgs_geo_from_mgrs ("38SMB", &g, &prec_m), 0);
    assert_near (prec_m, 100000.0, 0);

    // GeoConvert(1), ZONE: 79.9S 6.1E is 32CMS4324728161 in its standard zone.
    assert_int_equal (cgs_geo_to_mgrs ((cgs_geodetic_t){-79.9, 6.1, 0}, 5, buf, sizeof buf), 0);
    assert_string_equal (buf, "32CMS4324728161");
    assert_int_equal (cgs_geo_to_mgrs ((cgs_geodetic_t){-79.9, 6.1, 0}, 2, buf, sizeof buf), 0);
    assert_string_equal (buf, "32CMS4328"); // GeoConvert -p -3 -m => 32CMS4328
    assert_int_equal (cgs_geo_from_mgrs ("32cms 43247 28161", &g, &prec_m), 0);
    assert_near (g.lat_deg, -79.9, 1e-5);
    assert_near (g.lon_deg, 6.1, 1e-4); // 1 m is 5e-5 degrees of longitude here
    // The centre of a square converts back to the same square.
    assert_int_equal (cgs_geo_to_mgrs (g, 5, buf, sizeof buf), 0);
    assert_string_equal (buf, "32CMS4324728161");
}

static void test_mgrs_rejects (void **state)
{
    (void)state;
    const char *bad[] = {
        "",          "   ",        "38SMB448",        "38SMB44X8", "XYZ",     "61SMB4488",
        "38IMB4488", "38SMB4488Q", "38SMB4488 extra", "38S",       "INVALID", "38SMB44884488X",
        "38NMB4488", "-38SMB4488",
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        cgs_geodetic_t g = {1, 2, 3};
        double prec_m = -1;
        int rc = cgs_geo_from_mgrs (bad[i], &g, &prec_m);
        if (rc != -EINVAL)
            fail_msg ("cgs_geo_from_mgrs (\"%s\") = %d, want -EINVAL", bad[i], rc);
        assert_true (g.lat_deg == 1 && g.lon_deg == 2 && g.height_m == 3);
        assert_true (prec_m == -1);
    }
    cgs_geodetic_t g;
    assert_int_equal (cgs_geo_from_mgrs (NULL, &g, NULL), -EINVAL);

    char buf[16];
    memset (buf, 'x', sizeof buf);
    cgs_geodetic_t p = {33.3, 44.4, 0};
    assert_int_equal (cgs_geo_to_mgrs (p, 6, buf, sizeof buf), -EINVAL);
    assert_int_equal (cgs_geo_to_mgrs (p, -1, buf, sizeof buf), -EINVAL);
    assert_int_equal (cgs_geo_to_mgrs ((cgs_geodetic_t){91, 0, 0}, 5, buf, sizeof buf), -EINVAL);
    assert_int_equal (cgs_geo_to_mgrs ((cgs_geodetic_t){NAN, 0, 0}, 5, buf, sizeof buf), -EINVAL);
    assert_int_equal (cgs_geo_to_mgrs ((cgs_geodetic_t){0, INFINITY, 0}, 5, buf, sizeof buf),
                      -EINVAL);
    assert_int_equal (cgs_geo_to_mgrs (p, 5, NULL, 16), -EINVAL);
    // "38SMB4488" needs 10 bytes with its terminator.
    assert_int_equal (cgs_geo_to_mgrs ((cgs_geodetic_t){33.0 + 20.0 / 60.0, 44.4, 0}, 2, buf, 9),
                      -ENOBUFS);
    assert_int_equal (cgs_geo_to_mgrs (p, 5, buf, 0), -ENOBUFS);
    for (size_t i = 0; i < sizeof buf; i++)
        assert_int_equal (buf[i], 'x'); // untouched on failure
    assert_int_equal (cgs_geo_to_mgrs ((cgs_geodetic_t){33.0 + 20.0 / 60.0, 44.4, 0}, 2, buf, 10),
                      0);
    assert_string_equal (buf, "38SMB4488");
}

static void test_mgrs_polar (void **state)
{
    (void)state;
    // Above 84N MGRS uses UPS: zone letters Y/Z, no zone number.
    char buf[32];
    cgs_geodetic_t g;
    assert_int_equal (cgs_geo_to_mgrs ((cgs_geodetic_t){89.5, 30, 0}, 5, buf, sizeof buf), 0);
    assert_true (buf[0] == 'Z');
    assert_int_equal (strlen (buf), 13);
    assert_int_equal (cgs_geo_from_mgrs (buf, &g, NULL), 0);
    assert_near (g.lat_deg, 89.5, 1e-5);
    assert_near (g.lon_deg, 30, 1e-3);
}

/* ---- DIS Euler angles ---- */

// Worked examples (psi, theta, phi are the rotations of IEEE 1278.1 from ECEF
// axes to body axes x forward, y right, z down; the rows of
// R = Rx(phi) Ry(theta) Rz(psi) are the body axes in ECEF, with first row
// x_b = (cos theta cos psi, cos theta sin psi, -sin theta), and
// phi = atan2(y_b.z, z_b.z)). The tangent frame at lat phi0, lon lam0 is
// north = (-sin phi0 cos lam0, -sin phi0 sin lam0, cos phi0),
// east = (-sin lam0, cos lam0, 0), down = -(cos phi0 cos lam0, cos phi0 sin lam0, sin phi0).
//
// 1. lat 0, lon 0: north = +Z, east = +Y, down = -X. Heading east, level:
//    x_b = east = (0, 1, 0) so psi = atan2(1, 0) = 90 deg, theta = 0;
//    y_b = south = (0, 0, -1), z_b = down = (-1, 0, 0): phi = atan2(-1, 0) = -90 deg.
// 2. lat 0, lon 90: north = +Z, east = -X, down = -Y. Heading east, level:
//    x_b = (-1, 0, 0) so psi = atan2(0, -1) = 180 deg, theta = 0;
//    y_b = south = (0, 0, -1), z_b = (0, -1, 0): phi = atan2(-1, 0) = -90 deg.
// 3. lat 0, lon 0, heading east, pitch 30 up: in NED x_b = (0, cos 30, -sin 30),
//    which in ECEF is cos30 (0,1,0) - sin30 (-1,0,0) = (0.5, 0.866, 0): psi = 60 deg,
//    theta = 0; y_b = south = (0, 0, -1) still, z_b = (-0.866, 0.5, 0), phi = -90 deg.
//    (Pitching up at the equator facing east turns the body about ECEF Z.)
// 4. North pole (lat 90, lon 0): north = (-1, 0, 0), east = (0, 1, 0), down =
//    (0, 0, -1). Heading north, level: x_b = (-1, 0, 0), psi = 180 deg, theta = 0;
//    y_b = (0, 1, 0), z_b = (0, 0, -1), phi = atan2(0, -1) = 180 deg.
// 5. lat 0, lon 0, heading north, level: x_b = north = +Z, so theta = -90 deg
//    (gimbal lock); the y axis is east = +Y, and with phi taken as 0, psi = 0.
static void test_dis_worked_examples (void **state)
{
    (void)state;
    const struct {
        cgs_geodetic_t at;
        double h_deg, p_deg, r_deg;
        double psi_deg, theta_deg, phi_deg;
    } cases[] = {
        {{0, 0, 0}, 90, 0, 0, 90, 0, -90},  {{0, 90, 0}, 90, 0, 0, 180, 0, -90},
        {{0, 0, 0}, 90, 30, 0, 60, 0, -90}, {{90, 0, 0}, 0, 0, 0, 180, 0, 180},
        {{0, 0, 1e4}, 0, 0, 0, 0, -90, 0},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        cgs_dis_euler_t e;
        assert_int_equal (cgs_geo_dis_euler_from_hpr (cases[i].at, cases[i].h_deg, cases[i].p_deg,
                                                      cases[i].r_deg, &e),
                          0);
        assert_angle_rad (e.psi_rad, cases[i].psi_deg * DEG, 1e-12);
        assert_near (e.theta_rad, cases[i].theta_deg * DEG, 1e-12);
        assert_angle_rad (e.phi_rad, cases[i].phi_deg * DEG, 1e-12);

        double h, p, r;
        cgs_dis_euler_t given = {cases[i].psi_deg * DEG, cases[i].theta_deg * DEG,
                                 cases[i].phi_deg * DEG};
        assert_int_equal (cgs_geo_hpr_from_dis_euler (cases[i].at, given, &h, &p, &r), 0);
        assert_true (h >= 0 && h < 360);
        assert_angle_deg (h, cases[i].h_deg, 1e-9);
        assert_near (p, cases[i].p_deg, 1e-9);
        assert_angle_deg (r, cases[i].r_deg, 1e-9);
    }

    // Heading is normalised into [0, 360): -90 comes back as 270.
    cgs_dis_euler_t e;
    double h, p, r;
    assert_int_equal (cgs_geo_dis_euler_from_hpr ((cgs_geodetic_t){0, 0, 0}, -90, 0, 0, &e), 0);
    assert_angle_rad (e.psi_rad, -90 * DEG, 1e-12);
    assert_angle_rad (e.phi_rad, 90 * DEG, 1e-12); // west: y_b = north = +Z
    assert_int_equal (cgs_geo_hpr_from_dis_euler ((cgs_geodetic_t){0, 0, 0}, e, &h, &p, &r), 0);
    assert_near (h, 270, 1e-9);
    assert_int_equal (cgs_geo_dis_euler_from_hpr ((cgs_geodetic_t){0, 0, 0}, 720, 0, 0, &e), 0);
    assert_int_equal (cgs_geo_hpr_from_dis_euler ((cgs_geodetic_t){0, 0, 0}, e, &h, &p, &r), 0);
    assert_true (h >= 0 && h < 360);
    assert_angle_deg (h, 0, 1e-9);
}

// The rows of R(psi, theta, phi) are the body axes in ECEF; check body x
// (the nose) against the ENU direction of heading/pitch rotated to ECEF.
static void test_dis_nose_direction (void **state)
{
    (void)state;
    uint64_t seed = 12345;
    for (int i = 0; i < 200; i++) {
        cgs_geodetic_t at = {s_uniform (&seed, -89, 89), s_uniform (&seed, -180, 180),
                             s_uniform (&seed, 0, 5000)};
        double hd = s_uniform (&seed, 0, 360), pd = s_uniform (&seed, -80, 80);
        double rd = s_uniform (&seed, -180, 180);
        cgs_dis_euler_t e;
        assert_int_equal (cgs_geo_dis_euler_from_hpr (at, hd, pd, rd, &e), 0);
        cgs_geo_t *geo = cgs_geo_new (at.lat_deg, at.lon_deg, at.height_m);
        cgs_ecef_t want;
        cgs_geo_enu_vector_to_ecef (geo,
                                    (cgs_enu_t){sin (hd * DEG) * cos (pd * DEG),
                                                cos (hd * DEG) * cos (pd * DEG), sin (pd * DEG)},
                                    &want);
        assert_near (cos (e.theta_rad) * cos (e.psi_rad), want.x_m, 1e-12);
        assert_near (cos (e.theta_rad) * sin (e.psi_rad), want.y_m, 1e-12);
        assert_near (-sin (e.theta_rad), want.z_m, 1e-12);
        cgs_geo_destroy (&geo);
    }
}

static void test_dis_round_trips (void **state)
{
    (void)state;
    uint64_t seed = 20240601;
    for (int i = 0; i < 2000; i++) {
        cgs_geodetic_t at = {s_uniform (&seed, -90, 90), s_uniform (&seed, -180, 180),
                             s_uniform (&seed, -100, 20000)};
        double hd = s_uniform (&seed, 0, 360), pd = s_uniform (&seed, -85, 85);
        double rd = s_uniform (&seed, -179, 179);
        cgs_dis_euler_t e;
        double h, p, r;
        assert_int_equal (cgs_geo_dis_euler_from_hpr (at, hd, pd, rd, &e), 0);
        assert_true (e.theta_rad >= -M_PI / 2 && e.theta_rad <= M_PI / 2);
        assert_true (fabs (e.psi_rad) <= M_PI && fabs (e.phi_rad) <= M_PI);
        assert_int_equal (cgs_geo_hpr_from_dis_euler (at, e, &h, &p, &r), 0);
        assert_true (h >= 0 && h < 360);
        assert_angle_deg (h, hd, 1e-7);
        assert_near (p, pd, 1e-7);
        assert_near (r, rd, 1e-7);

        // And the other way: Euler angles -> hpr -> Euler angles.
        cgs_dis_euler_t e0 = {s_uniform (&seed, -M_PI, M_PI), s_uniform (&seed, -1.5, 1.5),
                              s_uniform (&seed, -M_PI, M_PI)};
        assert_int_equal (cgs_geo_hpr_from_dis_euler (at, e0, &h, &p, &r), 0);
        if (fabs (p) > 89.9)
            continue; // near gimbal lock in the tangent frame
        assert_int_equal (cgs_geo_dis_euler_from_hpr (at, h, p, r, &e), 0);
        assert_angle_rad (e.psi_rad, e0.psi_rad, 1e-9);
        assert_near (e.theta_rad, e0.theta_rad, 1e-9);
        assert_angle_rad (e.phi_rad, e0.phi_rad, 1e-9);
    }
}

static void test_dis_rejects (void **state)
{
    (void)state;
    cgs_dis_euler_t e = {1, 2, 3};
    assert_int_equal (cgs_geo_dis_euler_from_hpr ((cgs_geodetic_t){91, 0, 0}, 0, 0, 0, &e),
                      -EINVAL);
    assert_int_equal (cgs_geo_dis_euler_from_hpr ((cgs_geodetic_t){0, 0, 0}, NAN, 0, 0, &e),
                      -EINVAL);
    assert_int_equal (cgs_geo_dis_euler_from_hpr ((cgs_geodetic_t){0, 0, 0}, 0, 0, INFINITY, &e),
                      -EINVAL);
    assert_true (e.psi_rad == 1 && e.theta_rad == 2 && e.phi_rad == 3);
    double h = 7, p = 8, r = 9;
    assert_int_equal (cgs_geo_hpr_from_dis_euler ((cgs_geodetic_t){0, NAN, 0}, e, &h, &p, &r),
                      -EINVAL);
    assert_int_equal (cgs_geo_hpr_from_dis_euler ((cgs_geodetic_t){0, 0, 0},
                                                  (cgs_dis_euler_t){0, NAN, 0}, &h, &p, &r),
                      -EINVAL);
    assert_true (h == 7 && p == 8 && r == 9);
}

static void test_dis_local_frame (void **state)
{
    (void)state;
    // At the origin the local frame is the tangent plane: both variants agree.
    uint64_t seed = 777;
    for (int i = 0; i < 200; i++) {
        cgs_geodetic_t o = {s_uniform (&seed, -89, 89), s_uniform (&seed, -180, 180),
                            s_uniform (&seed, 0, 3000)};
        cgs_geo_t *geo = cgs_geo_new (o.lat_deg, o.lon_deg, o.height_m);
        double hd = s_uniform (&seed, 0, 360), pd = s_uniform (&seed, -85, 85);
        double rd = s_uniform (&seed, -179, 179);
        cgs_dis_euler_t el, et;
        cgs_geo_dis_euler_from_local (geo, hd, pd, rd, &el);
        assert_int_equal (cgs_geo_dis_euler_from_hpr (o, hd, pd, rd, &et), 0);
        assert_angle_rad (el.psi_rad, et.psi_rad, 1e-12);
        assert_near (el.theta_rad, et.theta_rad, 1e-12);
        assert_angle_rad (el.phi_rad, et.phi_rad, 1e-12);
        double h, p, r;
        cgs_geo_local_from_dis_euler (geo, el, &h, &p, &r);
        assert_true (h >= 0 && h < 360);
        assert_angle_deg (h, hd, 1e-7);
        assert_near (p, pd, 1e-7);
        assert_near (r, rd, 1e-7);
        cgs_geo_destroy (&geo);
    }

    // Worked example 1 through the local frame at (0, 0).
    cgs_geo_t *geo = cgs_geo_new (0, 0, 0);
    cgs_dis_euler_t e;
    cgs_geo_dis_euler_from_local (geo, 90, 0, 0, &e);
    assert_angle_rad (e.psi_rad, 90 * DEG, 1e-12);
    assert_near (e.theta_rad, 0, 1e-12);
    assert_angle_rad (e.phi_rad, -90 * DEG, 1e-12);
    cgs_geo_destroy (&geo);

    // Away from the origin the frame's north differs from true north by the
    // meridian convergence. With the origin at lat phi0 = 45 and a point at
    // longitude offset dl to the east, the frame's north n0 = (-s, 0, c) (s = c
    // = sin 45) seen in the tangent frame there has east component n0.e1 =
    // sin phi0 sin dl and north component n0.n1 = sin^2 phi0 cos dl + cos^2 phi0,
    // so true heading = atan2(sin phi0 sin dl, sin^2 phi0 cos dl + cos^2 phi0),
    // about dl sin phi0 = 0.448 deg for 50 km (dl = 0.634 deg).
    geo = cgs_geo_new (45, 0, 0);
    cgs_geodetic_t at;
    assert_int_equal (cgs_geo_enu_to_geodetic (geo, (cgs_enu_t){50000, 0, 0}, &at), 0);
    double dl = at.lon_deg * DEG, s0 = sin (45 * DEG), c0 = cos (45 * DEG);
    double want_deg = atan2 (s0 * sin (dl), s0 * s0 * cos (dl) + c0 * c0) / DEG;
    assert_near (want_deg, 0.448, 0.001);
    cgs_geo_dis_euler_from_local (geo, 0, 0, 0, &e);
    double h, p, r;
    assert_int_equal (cgs_geo_hpr_from_dis_euler (at, e, &h, &p, &r), 0);
    assert_near (h, want_deg, 1e-4); // at.lat differs from 45 by 0.002 deg
    cgs_geo_destroy (&geo);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_new_destroy),        cmocka_unit_test (test_geocentric_published),
        cmocka_unit_test (test_geocentric_rejects), cmocka_unit_test (test_local_published),
        cmocka_unit_test (test_local_axes),         cmocka_unit_test (test_local_round_trips),
        cmocka_unit_test (test_local_curvature),    cmocka_unit_test (test_local_rejects),
        cmocka_unit_test (test_mgrs_published),     cmocka_unit_test (test_mgrs_rejects),
        cmocka_unit_test (test_mgrs_polar),         cmocka_unit_test (test_dis_worked_examples),
        cmocka_unit_test (test_dis_nose_direction), cmocka_unit_test (test_dis_round_trips),
        cmocka_unit_test (test_dis_rejects),        cmocka_unit_test (test_dis_local_frame),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
