/* Unit tests of cgs_config: parsing, typed getters, error messages with file
 * and line, unused-key detection, paths and positions. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "cgs_config.h"
#include "cgs_geo.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

// Loads text as "test.ini" and fails the test unless that works.
static cgs_config_t *s_load (const char *text)
{
    char err[512] = "";
    cgs_config_t *cfg = NULL;
    int rc = cgs_config_load_string ("test.ini", text, &cfg, err, sizeof err);
    if (rc != 0)
        fail_msg ("load failed: %s", err);
    assert_non_null (cfg);
    return cfg;
}

// Loading text as "test.ini" fails with -EINVAL and exactly the message expected.
static void s_load_fails (const char *text, const char *expected)
{
    char err[512] = "";
    cgs_config_t *cfg = (cgs_config_t *)0x1; // must not be written
    assert_int_equal (cgs_config_load_string ("test.ini", text, &cfg, err, sizeof err), -EINVAL);
    assert_ptr_equal (cfg, (cgs_config_t *)0x1);
    assert_string_equal (err, expected);
}

static void test_getters_defaults_and_values (void **state)
{
    (void)state;
    cgs_config_t *cfg = s_load ("[uav uav1]\n"
                                "name = Predator one\n"
                                "speed_mps = 42.5\n"
                                "count = -7\n"
                                "seed = 18446744073709551615\n"
                                "loiter = yes\n");
    char err[256] = "";
    const char *s = NULL;
    assert_int_equal (cgs_config_get_string (cfg, "uav uav1", "name", "x", &s, err, sizeof err), 0);
    assert_string_equal (s, "Predator one");
    assert_int_equal (cgs_config_get_string (cfg, "uav uav1", "nick", "dflt", &s, err, sizeof err),
                      0);
    assert_string_equal (s, "dflt");
    assert_int_equal (cgs_config_get_string (cfg, "nosuch", "nick", NULL, &s, err, sizeof err), 0);
    assert_null (s);

    double d = 0;
    assert_int_equal (
        cgs_config_get_double (cfg, "uav uav1", "speed_mps", 1, 10, 100, &d, err, sizeof err), 0);
    assert_true (d == 42.5);
    assert_int_equal (
        cgs_config_get_double (cfg, "uav uav1", "alt_m", 1500, 0, 1e4, &d, err, sizeof err), 0);
    assert_true (d == 1500);

    long l = 0;
    assert_int_equal (
        cgs_config_get_int (cfg, "uav uav1", "count", 3, -10, 10, &l, err, sizeof err), 0);
    assert_int_equal (l, -7);
    assert_int_equal (
        cgs_config_get_int (cfg, "uav uav1", "other", 3, -10, 10, &l, err, sizeof err), 0);
    assert_int_equal (l, 3);

    uint64_t u = 0;
    assert_int_equal (cgs_config_get_uint64 (cfg, "uav uav1", "seed", 5, &u, err, sizeof err), 0);
    assert_true (u == UINT64_MAX);
    assert_int_equal (cgs_config_get_uint64 (cfg, "uav uav1", "seed2", 5, &u, err, sizeof err), 0);
    assert_true (u == 5);

    bool b = false;
    assert_int_equal (cgs_config_get_bool (cfg, "uav uav1", "loiter", false, &b, err, sizeof err),
                      0);
    assert_true (b);
    assert_int_equal (cgs_config_get_bool (cfg, "uav uav1", "other", true, &b, err, sizeof err), 0);
    assert_true (b);

    assert_int_equal (cgs_config_check_unused (cfg, err, sizeof err), 0);
    cgs_config_destroy (&cfg);
    assert_null (cfg);
}

static void test_number_errors (void **state)
{
    (void)state;
    cgs_config_t *cfg = s_load ("; a scenario\n"
                                "\n"
                                "[uav uav1]\n"
                                "speed_mps = fast\n"
                                "too_fast = 150\n"
                                "nan = nan\n"
                                "inf = inf\n"
                                "huge = 1e999\n"
                                "tail = 12abc\n"
                                "empty =\n"
                                "half = 12.5\n"
                                "hex = 0x10\n"
                                "big = 99999999999999999999\n"
                                "neg = -1\n"
                                "over = 18446744073709551616\n");
    cgs_config_t *named = NULL;
    char err[256] = "";
    double d = -1;
    // the message of the brief, with the file name the config was given
    assert_int_equal (cgs_config_load_string ("scenario.ini",
                                              "; a scenario\n\n\n\n\n\n\n\n\n\n\n"
                                              "[uav uav1]\nspeed_mps = fast\n",
                                              &named, err, sizeof err),
                      0);
    assert_int_equal (
        cgs_config_get_double (named, "uav uav1", "speed_mps", 50, 10, 100, &d, err, sizeof err),
        -EINVAL);
    assert_string_equal (err,
                         "scenario.ini:13: [uav uav1] speed_mps: expected a number in [10, 100], "
                         "got 'fast'");
    cgs_config_destroy (&named);

    assert_int_equal (
        cgs_config_get_double (cfg, "uav uav1", "speed_mps", 50, 10, 100, &d, err, sizeof err),
        -EINVAL);
    assert_string_equal (
        err, "test.ini:4: [uav uav1] speed_mps: expected a number in [10, 100], got 'fast'");
    assert_true (d == -1); // not written on failure
    assert_int_equal (
        cgs_config_get_double (cfg, "uav uav1", "too_fast", 50, 10, 100, &d, err, sizeof err),
        -EINVAL);
    assert_string_equal (
        err, "test.ini:5: [uav uav1] too_fast: expected a number in [10, 100], got '150'");
    const char *bad[] = {"nan", "inf", "huge", "tail", "empty"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        assert_int_equal (cgs_config_get_double (cfg, "uav uav1", bad[i], 0, -INFINITY, INFINITY,
                                                 &d, err, sizeof err),
                          -EINVAL);
    assert_string_equal (err, "test.ini:10: [uav uav1] empty: expected a number, got ''");
    assert_int_equal (
        cgs_config_get_double (cfg, "uav uav1", "tail", 0, 0, INFINITY, &d, err, sizeof err),
        -EINVAL);
    assert_string_equal (err, "test.ini:9: [uav uav1] tail: expected a number >= 0, got '12abc'");
    assert_true (d == -1);

    long l = 99;
    assert_int_equal (cgs_config_get_int (cfg, "uav uav1", "half", 0, 0, 100, &l, err, sizeof err),
                      -EINVAL);
    assert_string_equal (err, "test.ini:11: [uav uav1] half: expected an integer in [0, 100], got "
                              "'12.5'");
    assert_int_equal (
        cgs_config_get_int (cfg, "uav uav1", "hex", 0, LONG_MIN, LONG_MAX, &l, err, sizeof err),
        -EINVAL);
    assert_string_equal (err, "test.ini:12: [uav uav1] hex: expected an integer, got '0x10'");
    assert_int_equal (
        cgs_config_get_int (cfg, "uav uav1", "big", 0, LONG_MIN, LONG_MAX, &l, err, sizeof err),
        -EINVAL);
    assert_int_equal (cgs_config_get_int (cfg, "uav uav1", "neg", 0, 0, 10, &l, err, sizeof err),
                      -EINVAL);
    assert_string_equal (err, "test.ini:14: [uav uav1] neg: expected an integer in [0, 10], got "
                              "'-1'");
    assert_int_equal (l, 99);

    uint64_t u = 7;
    assert_int_equal (cgs_config_get_uint64 (cfg, "uav uav1", "neg", 0, &u, err, sizeof err),
                      -EINVAL);
    assert_string_equal (err, "test.ini:14: [uav uav1] neg: expected an integer in [0, "
                              "18446744073709551615], got '-1'");
    assert_int_equal (cgs_config_get_uint64 (cfg, "uav uav1", "over", 0, &u, err, sizeof err),
                      -EINVAL);
    assert_int_equal (cgs_config_get_uint64 (cfg, "uav uav1", "half", 0, &u, err, sizeof err),
                      -EINVAL);
    assert_true (u == 7);

    // nothing was read successfully, so the first key is the first unused one
    assert_int_equal (cgs_config_check_unused (cfg, err, sizeof err), -EINVAL);
    assert_string_equal (err, "test.ini:4: [uav uav1] unknown key 'speed_mps'");
    cgs_config_destroy (&cfg);
}

static void test_bool_forms (void **state)
{
    (void)state;
    cgs_config_t *cfg = s_load ("[b]\n"
                                "a = true\nb = FALSE\nc = Yes\nd = no\ne = on\nf = Off\n"
                                "g = 1\nh = 0\ni = maybe\nj = 2\n");
    const char *keys = "abcdefgh";
    char err[256] = "";
    for (int i = 0; keys[i]; i++) {
        char key[2] = {keys[i], '\0'};
        bool b = i % 2; // the opposite of what the file says
        assert_int_equal (cgs_config_get_bool (cfg, "b", key, b, &b, err, sizeof err), 0);
        assert_true (b == (i % 2 == 0));
    }
    bool b = true;
    assert_int_equal (cgs_config_get_bool (cfg, "b", "i", false, &b, err, sizeof err), -EINVAL);
    assert_string_equal (err, "test.ini:10: [b] i: expected true/false, yes/no, on/off or 1/0, got "
                              "'maybe'");
    assert_int_equal (cgs_config_get_bool (cfg, "b", "j", false, &b, err, sizeof err), -EINVAL);
    assert_true (b);
    cgs_config_destroy (&cfg);
}

static void test_enum (void **state)
{
    (void)state;
    static const char *const sensors[] = {"mti", "bcis", "image", NULL};
    cgs_config_t *cfg = s_load ("[uav uav1]\nsensor = BCIS\nother = radar\n");
    char err[256] = "";
    int v = -1;
    assert_int_equal (
        cgs_config_get_enum (cfg, "uav uav1", "sensor", sensors, 0, &v, err, sizeof err), 0);
    assert_int_equal (v, 1);
    assert_int_equal (
        cgs_config_get_enum (cfg, "uav uav1", "absent", sensors, 2, &v, err, sizeof err), 0);
    assert_int_equal (v, 2);
    assert_int_equal (
        cgs_config_get_enum (cfg, "uav uav1", "other", sensors, 0, &v, err, sizeof err), -EINVAL);
    assert_string_equal (err, "test.ini:3: [uav uav1] other: expected one of 'mti', 'bcis', "
                              "'image', got 'radar'");
    assert_int_equal (v, 2);
    cgs_config_destroy (&cfg);
}

static void test_duplicate_key (void **state)
{
    (void)state;
    cgs_config_t *cfg = s_load ("[uav uav1]\n"
                                "speed_mps = 40\n"
                                "; again\n"
                                "speed_mps = 50\n"
                                "[uav uav1]\n"
                                "name = a\n"
                                "[x]\n"
                                "[uav uav1]\n"
                                "name = b\n");
    char err[256] = "";
    double d = 0;
    assert_int_equal (
        cgs_config_get_double (cfg, "uav uav1", "speed_mps", 1, 0, 100, &d, err, sizeof err),
        -EINVAL);
    assert_string_equal (err, "test.ini:4: [uav uav1] speed_mps: given twice (first at line 2)");
    // a section named again merges: the key is still given twice
    const char *s = NULL;
    assert_int_equal (cgs_config_get_string (cfg, "uav uav1", "name", "", &s, err, sizeof err),
                      -EINVAL);
    assert_string_equal (err, "test.ini:9: [uav uav1] name: given twice (first at line 6)");
    assert_null (s);
    assert_int_equal (cgs_config_count (cfg, "uav uav1", "speed_mps"), 2);
    cgs_config_destroy (&cfg);
}

static void test_repeated_points (void **state)
{
    (void)state;
    cgs_config_t *cfg = s_load ("[route r1]\n"
                                "point = 0 0\n"
                                "point = 100 0\n"
                                "\n"
                                "point = 100 200   ; the turn\n"
                                "speed_mps = 10\n");
    assert_int_equal (cgs_config_count (cfg, "route r1", "point"), 3);
    assert_int_equal (cgs_config_count (cfg, "route r1", "nope"), 0);
    assert_int_equal (cgs_config_count (cfg, "nope", "point"), 0);
    assert_int_equal (cgs_config_line (cfg, "route r1", "point", 0), 2);
    assert_int_equal (cgs_config_line (cfg, "route r1", "point", 1), 3);
    assert_int_equal (cgs_config_line (cfg, "route r1", "point", 2), 5);
    assert_int_equal (cgs_config_line (cfg, "route r1", "point", 3), 0);
    assert_string_equal (cgs_config_get_nth (cfg, "route r1", "point", 0), "0 0");
    assert_string_equal (cgs_config_get_nth (cfg, "route r1", "point", 1), "100 0");
    char err[256] = "";
    // only two of three read: the third is still unknown
    assert_int_equal (cgs_config_check_unused (cfg, err, sizeof err), -EINVAL);
    assert_string_equal (err, "test.ini:5: [route r1] unknown key 'point'");
    assert_string_equal (cgs_config_get_nth (cfg, "route r1", "point", 2), "100 200");
    assert_null (cgs_config_get_nth (cfg, "route r1", "point", 3));
    assert_int_equal (cgs_config_check_unused (cfg, err, sizeof err), -EINVAL);
    assert_string_equal (err, "test.ini:6: [route r1] unknown key 'speed_mps'");
    // a single-value getter refuses a repeated key
    const char *s;
    assert_int_equal (cgs_config_get_string (cfg, "route r1", "point", NULL, &s, err, sizeof err),
                      -EINVAL);
    assert_string_equal (err, "test.ini:3: [route r1] point: given twice (first at line 2)");
    cgs_config_destroy (&cfg);
}

static void test_unknown_keys_and_sections (void **state)
{
    (void)state;
    const char *text = "[exercise]\n"
                       "id = 1\n"
                       "\n"
                       "colour = red\n"
                       "[foo]\n"
                       "bar = 1\n"
                       "[curve]\n"
                       "anything = 1\n"
                       "[empty]\n";
    char err[256] = "";
    long l;
    cgs_config_t *cfg = s_load (text);
    assert_int_equal (cgs_config_get_int (cfg, "exercise", "id", 0, 0, 9, &l, err, sizeof err), 0);
    assert_int_equal (cgs_config_check_unused (cfg, err, sizeof err), -EINVAL);
    assert_string_equal (err, "test.ini:4: [exercise] unknown key 'colour'");
    assert_int_equal (cgs_config_get_string (cfg, "exercise", "colour", NULL, &(const char *){0},
                                             err, sizeof err),
                      0);
    assert_int_equal (cgs_config_check_unused (cfg, err, sizeof err), -EINVAL);
    assert_string_equal (err, "test.ini:5: unknown section [foo]");
    // asking about a section, even for an absent key, makes its keys "unknown keys"
    assert_int_equal (cgs_config_get_int (cfg, "foo", "baz", 0, 0, 9, &l, err, sizeof err), 0);
    assert_int_equal (cgs_config_check_unused (cfg, err, sizeof err), -EINVAL);
    assert_string_equal (err, "test.ini:6: [foo] unknown key 'bar'");
    cgs_config_mark_section (cfg, "foo");
    cgs_config_mark_section (cfg, "curve");
    cgs_config_mark_section (cfg, "no such section");
    assert_int_equal (cgs_config_check_unused (cfg, err, sizeof err), -EINVAL);
    assert_string_equal (err, "test.ini:9: unknown section [empty]");
    cgs_config_mark_section (cfg, "empty");
    assert_int_equal (cgs_config_check_unused (cfg, err, sizeof err), 0);
    cgs_config_destroy (&cfg);

    // keys before any section
    cfg = s_load ("; top\nstray = 1\n[a]\n");
    cgs_config_mark_section (cfg, "a");
    assert_int_equal (cgs_config_check_unused (cfg, err, sizeof err), -EINVAL);
    assert_string_equal (err, "test.ini:2: unknown key 'stray' (before any section)");
    assert_string_equal (cgs_config_get_nth (cfg, "", "stray", 0), "1");
    assert_int_equal (cgs_config_check_unused (cfg, err, sizeof err), 0);
    cgs_config_destroy (&cfg);
}

static void test_sections (void **state)
{
    (void)state;
    cgs_config_t *cfg = s_load ("top = 1\n"
                                "[ uav   uav1 ]   ; the first UAV\n"
                                "a = 1\n"
                                "[vehicle v1]\n"
                                "[uav uav1]\n"
                                "b = 2\n"
                                "[a-very-long-section-name-longer-than-inih-keeps-for-itself x]\n"
                                "c = 3\n");
    assert_int_equal (cgs_config_section_count (cfg), 4);
    assert_string_equal (cgs_config_section_name (cfg, 0), "");
    assert_int_equal (cgs_config_section_line (cfg, 0), 1);
    assert_string_equal (cgs_config_section_name (cfg, 1), "uav uav1");
    assert_int_equal (cgs_config_section_line (cfg, 1), 2);
    assert_string_equal (cgs_config_section_name (cfg, 2), "vehicle v1");
    assert_int_equal (cgs_config_section_line (cfg, 2), 4);
    assert_string_equal (cgs_config_section_name (cfg, 3),
                         "a-very-long-section-name-longer-than-inih-keeps-for-itself x");
    assert_null (cgs_config_section_name (cfg, 4));
    // [uav uav1] is given again at line 5 (merged); the others once.
    assert_int_equal (cgs_config_section_again (cfg, 1), 5);
    assert_int_equal (cgs_config_section_again (cfg, 0), 0);
    assert_int_equal (cgs_config_section_again (cfg, 2), 0);
    assert_int_equal (cgs_config_section_again (cfg, 3), 0);
    assert_int_equal (cgs_config_section_again (cfg, 9), 0);
    assert_true (cgs_config_has_section (cfg, "vehicle v1"));
    assert_false (cgs_config_has_section (cfg, "vehicle v2"));
    assert_true (cgs_config_has (cfg, "uav uav1", "a"));
    assert_true (cgs_config_has (cfg, "uav uav1", "b"));
    assert_false (cgs_config_has (cfg, "uav uav1", "c"));
    assert_true (
        cgs_config_has (cfg, "a-very-long-section-name-longer-than-inih-keeps-for-itself x", "c"));
    assert_int_equal (cgs_config_line (cfg, "uav uav1", "b", 0), 6);
    assert_string_equal (cgs_config_path (cfg), "test.ini");
    assert_string_equal (cgs_config_dir (cfg), ".");
    // has and has_section mark nothing
    char err[256] = "";
    assert_int_equal (cgs_config_check_unused (cfg, err, sizeof err), -EINVAL);
    assert_string_equal (err, "test.ini:1: unknown key 'top' (before any section)");
    cgs_config_destroy (&cfg);
}

static void test_syntax_errors (void **state)
{
    (void)state;
    const char *expect = "test.ini:3: syntax error (expected `key = value` or `[section]`)";
    s_load_fails ("[a]\nx = 1\njust words\ny = 2\n", expect);
    s_load_fails ("[a]\nx = 1\n[unclosed\n", expect);
    s_load_fails ("[a]\nx = 1\n= 2\n", expect);
    s_load_fails ("[a]\nx = 1\n[b] y = 2\n", expect);
    s_load_fails ("[a]\nx = 1\n[b ; comment]\n", expect);
    s_load_fails ("[a]\n\n[  ]\n", "test.ini:3: empty section name");
    // the first error wins, even with more after it
    s_load_fails ("[a]\n\nbad\nbad again\n", expect);
}

static void test_comments_and_indentation (void **state)
{
    (void)state;
    cgs_config_t *cfg = s_load ("\xEF\xBB\xBF"
                                "# hash comment\r\n"
                                "[a]\r\n"
                                "   x = 1 ; inline comment\r\n"
                                "   y = tcp://host:5555;not a comment\r\n"
                                "\tz: 3\r\n"
                                "    ; indented comment\r\n"
                                "w = last");
    char err[256] = "";
    const char *s;
    assert_int_equal (cgs_config_get_string (cfg, "a", "x", NULL, &s, err, sizeof err), 0);
    assert_string_equal (s, "1");
    assert_int_equal (cgs_config_line (cfg, "a", "x", 0), 3);
    // an indented line is a key of its own, not a continuation of the one above
    assert_int_equal (cgs_config_get_string (cfg, "a", "y", NULL, &s, err, sizeof err), 0);
    assert_string_equal (s, "tcp://host:5555;not a comment");
    assert_int_equal (cgs_config_get_string (cfg, "a", "z", NULL, &s, err, sizeof err), 0);
    assert_string_equal (s, "3");
    assert_int_equal (cgs_config_get_string (cfg, "a", "w", NULL, &s, err, sizeof err), 0);
    assert_string_equal (s, "last");
    assert_int_equal (cgs_config_line (cfg, "a", "w", 0), 7);
    assert_int_equal (cgs_config_check_unused (cfg, err, sizeof err), 0);
    cgs_config_destroy (&cfg);
}

static void test_long_lines (void **state)
{
    (void)state;
    char text[1024];
    char filler[400];
    memset (filler, 'x', sizeof filler - 1);
    filler[sizeof filler - 1] = '\0';
    // a long comment is fine
    snprintf (text, sizeof text, "[a]\n; %s\nk = v\n", filler);
    cgs_config_t *cfg = s_load (text);
    assert_string_equal (cgs_config_get_nth (cfg, "a", "k", 0), "v");
    assert_int_equal (cgs_config_line (cfg, "a", "k", 0), 3);
    cgs_config_destroy (&cfg);
    // a long value is not cut silently
    snprintf (text, sizeof text, "[a]\nk = v\nlong = %s\n", filler);
    char err[256] = "";
    assert_int_equal (cgs_config_load_string ("test.ini", text, &cfg, err, sizeof err), -EINVAL);
    assert_null (cfg);
    assert_string_equal (err, "test.ini:3: line too long (at most 199 characters, not counting "
                              "indentation)");
}

static void test_load_file_and_paths (void **state)
{
    (void)state;
    char dir[] = "/tmp/test_config.XXXXXX";
    assert_non_null (mkdtemp (dir));
    char sub[300], path[400], want[600];
    snprintf (sub, sizeof sub, "%s/sub", dir);
    assert_int_equal (mkdir (sub, 0700), 0);
    snprintf (path, sizeof path, "%s/scenario.ini", sub);
    FILE *f = fopen (path, "w");
    assert_non_null (f);
    fputs ("[terrain]\n"
           "file = dem/a.tif\n"
           "abs = /data/b.tif\n"
           "none =\n"
           "dup = a\n"
           "dup = b\n",
           f);
    fclose (f);

    char err[512] = "";
    cgs_config_t *cfg = NULL;
    assert_int_equal (cgs_config_load (path, &cfg, err, sizeof err), 0);
    assert_string_equal (cgs_config_path (cfg), path);
    assert_string_equal (cgs_config_dir (cfg), sub);
    const char *p = NULL;
    assert_int_equal (cgs_config_get_path (cfg, "terrain", "file", NULL, &p, err, sizeof err), 0);
    snprintf (want, sizeof want, "%s/dem/a.tif", sub);
    assert_string_equal (p, want);
    assert_int_equal (cgs_config_get_path (cfg, "terrain", "abs", NULL, &p, err, sizeof err), 0);
    assert_string_equal (p, "/data/b.tif");
    assert_int_equal (cgs_config_get_path (cfg, "terrain", "none", "x", &p, err, sizeof err), 0);
    assert_string_equal (p, "");
    assert_int_equal (cgs_config_get_path (cfg, "terrain", "absent", NULL, &p, err, sizeof err), 0);
    assert_null (p);
    assert_int_equal (
        cgs_config_get_path (cfg, "terrain", "absent", "default.tif", &p, err, sizeof err), 0);
    snprintf (want, sizeof want, "%s/default.tif", sub);
    assert_string_equal (p, want);
    assert_int_equal (cgs_config_get_path (cfg, "terrain", "dup", NULL, &p, err, sizeof err),
                      -EINVAL);
    snprintf (want, sizeof want, "%s:6: [terrain] dup: given twice (first at line 5)", path);
    assert_string_equal (err, want);
    cgs_config_destroy (&cfg);

    // a file that is not there
    snprintf (path, sizeof path, "%s/nope.ini", dir);
    cfg = (cgs_config_t *)0x1;
    assert_int_equal (cgs_config_load (path, &cfg, err, sizeof err), -ENOENT);
    assert_ptr_equal (cfg, (cgs_config_t *)0x1);
    snprintf (want, sizeof want, "%s: No such file or directory", path);
    assert_string_equal (err, want);

    // a folder is not a file
    assert_int_equal (cgs_config_load (dir, &cfg, err, sizeof err), -EISDIR);
    snprintf (want, sizeof want, "%s: Is a directory", dir);
    assert_string_equal (err, want);

    snprintf (path, sizeof path, "%s/scenario.ini", sub);
    assert_int_equal (unlink (path), 0);
    assert_int_equal (rmdir (sub), 0);
    assert_int_equal (rmdir (dir), 0);

    // the folder of a name given to load_string
    const char *names[][2] = {{"a/b.ini", "a"}, {"b.ini", "."}, {"/b.ini", "/"}};
    for (size_t i = 0; i < 3; i++) {
        cfg = NULL;
        assert_int_equal (
            cgs_config_load_string (names[i][0], "[t]\nf = x.tif\n", &cfg, err, sizeof err), 0);
        assert_string_equal (cgs_config_dir (cfg), names[i][1]);
        assert_int_equal (cgs_config_get_path (cfg, "t", "f", NULL, &p, err, sizeof err), 0);
        const char *expect[] = {"a/x.tif", "x.tif", "/x.tif"};
        assert_string_equal (p, expect[i]);
        cgs_config_destroy (&cfg);
    }
}

static void s_assert_enu (cgs_enu_t a, cgs_enu_t b, double tol)
{
    if (fabs (a.e_m - b.e_m) > tol || fabs (a.n_m - b.n_m) > tol || fabs (a.u_m - b.u_m) > tol)
        fail_msg ("(%.6f, %.6f, %.6f) != (%.6f, %.6f, %.6f)", a.e_m, a.n_m, a.u_m, b.e_m, b.n_m,
                  b.u_m);
}

static void test_positions (void **state)
{
    (void)state;
    cgs_geo_t *frame = cgs_geo_new (35.96, -121.23, 0);
    assert_non_null (frame);
    char why[512] = "";
    cgs_enu_t p;

    // local metres, with and without the keyword; numbers alone are always local
    assert_int_equal (cgs_config_parse_position ("1200 -350", frame, &p, why, sizeof why), 0);
    s_assert_enu (p, (cgs_enu_t){1200, -350, 0}, 0);
    assert_int_equal (cgs_config_parse_position ("1200 -350 20", NULL, &p, why, sizeof why), 0);
    s_assert_enu (p, (cgs_enu_t){1200, -350, 20}, 0);
    assert_int_equal (cgs_config_parse_position ("LOCAL  1.5e3\t-2", NULL, &p, why, sizeof why), 0);
    s_assert_enu (p, (cgs_enu_t){1500, -2, 0}, 0);
    assert_int_equal (cgs_config_parse_position ("36.6 -121.9", frame, &p, why, sizeof why), 0);
    s_assert_enu (p, (cgs_enu_t){36.6, -121.9, 0}, 0);

    // geodetic, checked against cgs_geo
    cgs_enu_t want;
    assert_int_equal (cgs_geo_geodetic_to_enu (frame, (cgs_geodetic_t){36.0, -121.2, 100}, &want),
                      0);
    assert_true (want.n_m > 4000 && want.n_m < 5000); // 0.04 degrees north, about 4.4 km
    assert_int_equal (cgs_config_parse_position ("geo 36.0 -121.2 100", frame, &p, why, sizeof why),
                      0);
    s_assert_enu (p, want, 1e-6);
    assert_int_equal (cgs_config_parse_position ("36.0N 121.2W 100", frame, &p, why, sizeof why),
                      0);
    s_assert_enu (p, want, 1e-6);
    assert_int_equal (cgs_config_parse_position ("36n 121.2w 100", frame, &p, why, sizeof why), 0);
    s_assert_enu (p, want, 1e-6);
    assert_int_equal (cgs_config_parse_position ("Geo 36N 121.2W 100", frame, &p, why, sizeof why),
                      0);
    s_assert_enu (p, want, 1e-6);
    assert_int_equal (cgs_geo_geodetic_to_enu (frame, (cgs_geodetic_t){-33.5, 151.25, 0}, &want),
                      0);
    assert_int_equal (cgs_config_parse_position ("33.5S 151.25E", frame, &p, why, sizeof why), 0);
    s_assert_enu (p, want, 1e-6);

    // MGRS, both spellings, against cgs_geo_from_mgrs + cgs_geo_geodetic_to_enu
    char grid[32];
    assert_int_equal (cgs_geo_to_mgrs ((cgs_geodetic_t){35.97, -121.22, 0}, 5, grid, sizeof grid),
                      0);
    assert_int_equal (strlen (grid), 15); // e.g. 10SFF...: zone, band, square, 2 x 5 digits
    cgs_geodetic_t g;
    assert_int_equal (cgs_geo_from_mgrs (grid, &g, NULL), 0);
    assert_int_equal (cgs_geo_geodetic_to_enu (frame, g, &want), 0);
    assert_true (fabs (want.e_m - 900) < 100 && fabs (want.n_m - 1110) < 100);
    assert_int_equal (cgs_config_parse_position (grid, frame, &p, why, sizeof why), 0);
    s_assert_enu (p, want, 1e-6);
    char spaced[64];
    snprintf (spaced, sizeof spaced, "mgrs %.5s %.5s %.5s", grid, grid + 5, grid + 10);
    assert_int_equal (cgs_config_parse_position (spaced, frame, &p, why, sizeof why), 0);
    s_assert_enu (p, want, 1e-6);
    for (char *c = spaced; *c; c++)
        *c = (char)tolower ((unsigned char)*c);
    assert_int_equal (cgs_config_parse_position (spaced, frame, &p, why, sizeof why), 0);
    s_assert_enu (p, want, 1e-6);

    cgs_geo_destroy (&frame);
    assert_null (frame);
}

static void test_position_errors (void **state)
{
    (void)state;
    cgs_geo_t *frame = cgs_geo_new (35.96, -121.23, 0);
    assert_non_null (frame);
    char why[512] = "";
    cgs_enu_t p = {7, 7, 7};
    const char *bad[] = {"",
                         "1200",
                         "1 2 3 4",
                         "far away",
                         "1200 abc",
                         "geo 36",
                         "geo 95 10",
                         "geo 36 200",
                         "36N 121X",
                         "-36N 121W",
                         "mgrs 10SXX99999",
                         "99ZZZ1234512345",
                         "local",
                         "geo 36 -121 up",
                         "nan 1"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        if (cgs_config_parse_position (bad[i], frame, &p, why, sizeof why) != -EINVAL)
            fail_msg ("'%s' accepted", bad[i]);
        s_assert_enu (p, (cgs_enu_t){7, 7, 7}, 0);
    }
    assert_int_equal (cgs_config_parse_position ("far away", frame, &p, why, sizeof why), -EINVAL);
    assert_string_equal (why, "expected a position as `E N [U]` or `local E N [U]` in metres, "
                              "`geo LAT LON [H]`, `LAT{N|S} LON{E|W} [H]` or `mgrs GRID`, got "
                              "'far away'");
    assert_int_equal (cgs_config_parse_position ("geo 95 10", frame, &p, why, sizeof why), -EINVAL);
    assert_string_equal (why, "latitude 95 is outside [-90, 90] in 'geo 95 10'");
    assert_int_equal (cgs_config_parse_position ("mgrs 10SXX99999", frame, &p, why, sizeof why),
                      -EINVAL);
    assert_string_equal (why, "'mgrs 10SXX99999' is not an MGRS reference (expected e.g. `mgrs "
                              "10SEG 12345 67890`)");
    // what only looks like MGRS gets the list of every form
    assert_int_equal (cgs_config_parse_position ("36N 121X", frame, &p, why, sizeof why), -EINVAL);
    assert_string_equal (why, "expected a position as `E N [U]` or `local E N [U]` in metres, "
                              "`geo LAT LON [H]`, `LAT{N|S} LON{E|W} [H]` or `mgrs GRID`, got "
                              "'36N 121X'");
    // geodetic positions need a frame
    assert_int_equal (cgs_config_parse_position ("geo 36 -121", NULL, &p, why, sizeof why),
                      -EINVAL);
    assert_string_equal (why, "'geo 36 -121' is geodetic, but there is no exercise origin to place "
                              "it");

    // in a config: the error names file, line and key
    cgs_config_t *cfg = s_load ("[vehicle v1]\nstart = 1 2\nend = geo 36 -121.2\nbad = 1,2\n");
    char err[600] = "";
    assert_int_equal (cgs_config_get_position (cfg, "vehicle v1", "start", frame,
                                               (cgs_enu_t){0, 0, 0}, &p, err, sizeof err),
                      0);
    s_assert_enu (p, (cgs_enu_t){1, 2, 0}, 0);
    assert_int_equal (cgs_config_get_position (cfg, "vehicle v1", "end", frame,
                                               (cgs_enu_t){0, 0, 0}, &p, err, sizeof err),
                      0);
    assert_true (p.n_m > 4000);
    assert_int_equal (cgs_config_get_position (cfg, "vehicle v1", "none", frame,
                                               (cgs_enu_t){5, 6, 7}, &p, err, sizeof err),
                      0);
    s_assert_enu (p, (cgs_enu_t){5, 6, 7}, 0);
    assert_int_equal (cgs_config_get_position (cfg, "vehicle v1", "bad", frame,
                                               (cgs_enu_t){0, 0, 0}, &p, err, sizeof err),
                      -EINVAL);
    assert_string_equal (err, "test.ini:4: [vehicle v1] bad: expected a position as `E N [U]` or "
                              "`local E N [U]` in metres, `geo LAT LON [H]`, `LAT{N|S} LON{E|W} "
                              "[H]` or `mgrs GRID`, got '1,2'");
    s_assert_enu (p, (cgs_enu_t){5, 6, 7}, 0);
    cgs_config_destroy (&cfg);
    cgs_geo_destroy (&frame);
}

static void test_parse_geodetic (void **state)
{
    (void)state;
    char why[512] = "";
    cgs_geodetic_t g = {1, 2, 3};
    assert_int_equal (cgs_config_parse_geodetic ("geo 35.96 -121.23 12.5", &g, why, sizeof why), 0);
    assert_true (g.lat_deg == 35.96 && g.lon_deg == -121.23 && g.height_m == 12.5);
    assert_int_equal (cgs_config_parse_geodetic ("35.96N 121.23W", &g, why, sizeof why), 0);
    assert_true (g.lat_deg == 35.96 && g.lon_deg == -121.23 && g.height_m == 0);
    assert_int_equal (cgs_config_parse_geodetic ("1200 -350", &g, why, sizeof why), -EINVAL);
    assert_string_equal (why, "expected a geodetic position as `geo LAT LON [H]`, `LAT{N|S} "
                              "LON{E|W} [H]` or `mgrs GRID` (local metres have no meaning here), "
                              "got '1200 -350'");
    assert_true (g.lat_deg == 35.96 && g.lon_deg == -121.23 && g.height_m == 0);
}

static void test_require_and_error (void **state)
{
    (void)state;
    cgs_config_t *cfg = s_load ("top = 1\n[uav uav1]\nspeed_mps = 40\n");
    char err[256] = "";
    assert_int_equal (cgs_config_require (cfg, "uav uav1", "speed_mps", "a speed", err, sizeof err),
                      0);
    assert_int_equal (
        cgs_config_require (cfg, "uav uav1", "altitude_m", "a height in metres", err, sizeof err),
        -ENOENT);
    assert_string_equal (err,
                         "test.ini: [uav uav1]: missing key 'altitude_m' (expected a height in "
                         "metres)");
    assert_int_equal (cgs_config_require (cfg, "", "origin", "a position", err, sizeof err),
                      -ENOENT);
    assert_string_equal (err, "test.ini: missing key 'origin' (expected a position)");

    assert_int_equal (cgs_config_error (cfg, "uav uav1", "speed_mps", 0, err, sizeof err,
                                        "too slow for a %s", "Predator"),
                      -EINVAL);
    assert_string_equal (err, "test.ini:3: [uav uav1] speed_mps: too slow for a Predator");
    cgs_config_error (cfg, "uav uav1", "absent", 0, err, sizeof err, "needed");
    assert_string_equal (err, "test.ini: [uav uav1] absent: needed");
    cgs_config_error (cfg, "", "top", 0, err, sizeof err, "odd");
    assert_string_equal (err, "test.ini:1: top: odd");
    cgs_config_error (cfg, "uav uav1", NULL, 0, err, sizeof err, "no UAV of that name");
    assert_string_equal (err, "test.ini:2: [uav uav1] no UAV of that name");
    // a short buffer is cut, not overrun
    char small[8];
    cgs_config_error (cfg, "uav uav1", "speed_mps", 0, small, sizeof small, "x");
    assert_string_equal (small, "test.in");
    cgs_config_destroy (&cfg);
    cgs_config_destroy (&cfg); // idempotent
    cgs_config_destroy (NULL);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_getters_defaults_and_values),
        cmocka_unit_test (test_number_errors),
        cmocka_unit_test (test_bool_forms),
        cmocka_unit_test (test_enum),
        cmocka_unit_test (test_duplicate_key),
        cmocka_unit_test (test_repeated_points),
        cmocka_unit_test (test_unknown_keys_and_sections),
        cmocka_unit_test (test_sections),
        cmocka_unit_test (test_syntax_errors),
        cmocka_unit_test (test_comments_and_indentation),
        cmocka_unit_test (test_long_lines),
        cmocka_unit_test (test_load_file_and_paths),
        cmocka_unit_test (test_positions),
        cmocka_unit_test (test_position_errors),
        cmocka_unit_test (test_parse_geodetic),
        cmocka_unit_test (test_require_and_error),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
