/* test_st_params — stationd's parameter file: the shipped file equals the
 * defaults; every key is read; a server bound to anything but loopback
 * without an operators' token is refused (on the line of `listen`); a token
 * that could not sit in a URL's query, both token and token_file, a
 * missing token file, an address that is not one, and values out of range
 * each name the file, the line, the section and the key; a refused file
 * leaves the parameters alone. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "st_params.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void s_load (const char *text, st_params_t *p)
{
    char err[512] = "";
    if (st_params_load_string ("s.ini", text, p, err, sizeof err) != 0)
        fail_msg ("%s", err);
}

/* The text is refused with an error containing each of the parts. */
static void s_refused (const char *text, const char *part1, const char *part2)
{
    st_params_t p, before;
    st_params_defaults (&p);
    before = p;
    char err[512] = "";
    assert_int_equal (st_params_load_string ("s.ini", text, &p, err, sizeof err), -EINVAL);
    if (!strstr (err, part1) || (part2 && !strstr (err, part2)))
        fail_msg ("error '%s' lacks '%s' or '%s'", err, part1, part2 ? part2 : "");
    assert_memory_equal (&p, &before, sizeof p);
}

static void test_shipped_file_is_the_defaults (void **state)
{
    (void)state;
    st_params_t d, p;
    st_params_defaults (&d);
    st_params_defaults (&p);
    char path[4096], err[512] = "";
    const char *root = getenv ("CGS_ROOT");
    snprintf (path, sizeof path, "%s/deploy/params/station.ini", root ? root : ".");
    if (st_params_load (path, &p, err, sizeof err) != 0)
        fail_msg ("%s", err);
    assert_memory_equal (&p, &d, sizeof p);
    assert_string_equal (d.listen_address, "127.0.0.1");
    assert_int_equal (d.port, 8080);
    assert_true (d.push_hz == 5);
    assert_int_equal (d.history_scans, 20);
    assert_true (d.bcis_timeout_s == 5);
    assert_string_equal (d.token, "");
}

static void test_every_key (void **state)
{
    (void)state;
    st_params_t p;
    st_params_defaults (&p);
    s_load ("[http]\nlisten = 0.0.0.0\nport = 9000\ntoken = abcdefgh12\nweb_root = /srv/web\n"
            "threads = 8\nwrite_timeout_s = 2\n[display]\npush_hz = 10\nhistory_scans = 5\n"
            "bcis_timeout_s = 3\ntrack_stale_s = 20\ntruth_stale_s = 15\n[relief]\n"
            "sun_azimuth_deg = 90\nsun_elevation_deg = 30\nz_factor = 2\nmax_pixels = 1024\n"
            "[commands]\ntimeout_s = 0.5\nattempts = 2\n",
            &p);
    assert_string_equal (p.listen_address, "0.0.0.0");
    assert_int_equal (p.port, 9000);
    assert_string_equal (p.token, "abcdefgh12");
    assert_false (p.token_from_file);
    assert_string_equal (p.web_root, "/srv/web");
    assert_int_equal (p.threads, 8);
    assert_true (p.write_timeout_s == 2);
    assert_true (p.push_hz == 10);
    assert_int_equal (p.history_scans, 5);
    assert_true (p.bcis_timeout_s == 3);
    assert_true (p.track_stale_s == 20);
    assert_true (p.truth_stale_s == 15);
    assert_true (p.sun_azimuth_deg == 90);
    assert_true (p.sun_elevation_deg == 30);
    assert_true (p.z_factor == 2);
    assert_int_equal (p.max_pixels, 1024);
    assert_true (p.command_timeout_s == 0.5);
    assert_int_equal (p.command_attempts, 2);
    st_params_defaults (&p);
    s_load ("[http]\nlisten = ::1\n", &p); // IPv6 loopback needs no token
    assert_string_equal (p.listen_address, "::1");
}

static void test_token_file (void **state)
{
    (void)state;
    char dir[] = "/tmp/test_st_params.XXXXXX";
    assert_non_null (mkdtemp (dir));
    char path[256], text[512];
    snprintf (path, sizeof path, "%s/token", dir);
    FILE *f = fopen (path, "w");
    fputs ("s3cret-token-1\nignored second line\n", f);
    fclose (f);
    st_params_t p;
    st_params_defaults (&p);
    snprintf (text, sizeof text, "[http]\nlisten = 0.0.0.0\ntoken_file = %s\n", path);
    s_load (text, &p);
    assert_string_equal (p.token, "s3cret-token-1");
    assert_true (p.token_from_file);
    // A token file whose first line is not a usable token.
    f = fopen (path, "w");
    fputs ("short\n", f);
    fclose (f);
    s_refused (text, "s.ini:3: [http] token_file", "at least 8");
    // One longer than the token can be is refused, never cut.
    f = fopen (path, "w");
    for (int i = 0; i < ST_TOKEN_MAX + 10; i++)
        fputc ('x', f);
    fputc ('\n', f);
    fclose (f);
    s_refused (text, "s.ini:3: [http] token_file", "longer than");
    unlink (path);
    s_refused (text, "s.ini:3: [http] token_file", "cannot read");
    rmdir (dir);
}

static void test_errors (void **state)
{
    (void)state;
    s_refused ("[http]\nlisten = 0.0.0.0\n", "s.ini:2: [http] listen",
               "needs an operators' access token");
    s_refused ("; a comment\n[http]\nlisten = 10.1.2.3\nport = 80\n", "s.ini:3: [http] listen",
               "token");
    s_refused ("[http]\nlisten = localhost\n", "s.ini:2: [http] listen", "IPv4 or IPv6 address");
    s_refused ("[http]\ntoken = has space in\n", "s.ini:2: [http] token", "at least 8");
    s_refused ("[http]\ntoken = a&b=c#d%e\n", "s.ini:2: [http] token", NULL);
    s_refused ("[http]\ntoken = short\n", "s.ini:2: [http] token", NULL);
    s_refused ("[http]\ntoken = abcdefgh12\ntoken_file = /x\n", "[http] token_file", "not both");
    s_refused ("[http]\nport = 70000\n", "s.ini:2: [http] port", NULL);
    s_refused ("[display]\npush_hz = 0\n", "s.ini:2: [display] push_hz", NULL);
    s_refused ("[display]\nhistory_scans = -1\n", "s.ini:2: [display] history_scans", NULL);
    s_refused ("[relief]\nsun_elevation_deg = 0\n", "s.ini:2: [relief] sun_elevation_deg", NULL);
    s_refused ("[commands]\nattempts = 0\n", "s.ini:2: [commands] attempts", NULL);
    s_refused ("[display]\ncolour = red\n", "s.ini:2", "colour");
    s_refused ("[http]\nport = 1\nport = 2\n", "s.ini:3", "port");
}

static void test_loopback (void **state)
{
    (void)state;
    assert_true (st_params_is_loopback ("127.0.0.1"));
    assert_true (st_params_is_loopback ("127.1.2.3"));
    assert_true (st_params_is_loopback ("::1"));
    assert_false (st_params_is_loopback ("0.0.0.0"));
    assert_false (st_params_is_loopback ("::"));
    assert_false (st_params_is_loopback ("192.168.1.10"));
    assert_false (st_params_is_loopback ("128.0.0.1"));
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_shipped_file_is_the_defaults),
        cmocka_unit_test (test_every_key),
        cmocka_unit_test (test_token_file),
        cmocka_unit_test (test_errors),
        cmocka_unit_test (test_loopback),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
