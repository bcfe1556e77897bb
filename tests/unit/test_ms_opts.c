/* test_ms_opts — mscgs's option parser against what GNU getopt_long did
 * for the same table: values by `--name V`, `--name=V`, an unambiguous
 * prefix and short letters (`-n5`, `-jn 5`), operands anywhere and after
 * `--`, values read left to right (the first bad one stops the parse),
 * getopt_long's messages word for word followed by the usage, --help on
 * stdout, checked against glibc's getopt_long itself; the usage and the
 * option list made from the table; the number readers. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "ms_opts.h"

#include <errno.h>
#include <getopt.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* What the demo command's options set. */
typedef struct {
    const char *exercise;
    bool json;
    double count, wait_s, radius_m;
    uint32_t uav;
    int calls; // s_counted's calls
} s_vals_t;

static s_vals_t s_v;

/* Counts its calls; refuses "bad". */
static int s_counted (const ms_opt_t *opt, const char *value)
{
    (void)opt;
    s_v.calls++;
    if (strcmp (value, "bad") == 0) {
        fprintf (stderr, "demo: --mark: bad\n");
        return -EINVAL;
    }
    return 0;
}

static const ms_opt_t s_opts[] = {
    {.name = "exercise", .value = "F", .help = "exercise file", .str = &s_v.exercise},
    {.name = "json", .letter = 'j', .help = "one JSON object a line", .flag = &s_v.json},
    {.name = "count",
     .letter = 'n',
     .value = "N",
     .help = "stop after N",
     .fn = ms_opts_read_positive,
     .arg = &s_v.count},
    {.name = "wait",
     .value = "S",
     .help = "wait S seconds",
     .fn = ms_opts_read_positive,
     .arg = &s_v.wait_s},
    {.name = "radius",
     .value = "M",
     .help = "radius",
     .fn = ms_opts_read_number,
     .arg = &s_v.radius_m},
    {.name = "radius-max",
     .value = "M",
     .help = "the largest\nradius",
     .fn = ms_opts_read_number,
     .arg = &s_v.radius_m},
    {.name = "uav",
     .value = "ID",
     .help = "the UAV",
     .fn = ms_opts_read_entity_id,
     .arg = &s_v.uav},
    {.name = "mark", .value = "X", .fn = s_counted},
    {.name = "help", .letter = 'h'},
    {NULL},
};

static const ms_cmd_t s_cmd = {
    .name = "demo",
    .operands = "TOPIC",
    .about = "What demo does.\n",
    .opts = s_opts,
};

#define S_USAGE                                                                                    \
    "usage: mscgs demo TOPIC [--exercise F] [--json] [--count N] [--wait S] [--radius M] "         \
    "[--radius-max M]\n" /* 100 columns: the most a line takes */                                  \
    "                  [--uav ID]\n"                                                               \
    "What demo does.\n"

/* One parse of the words of line (after argv[0] "demo"), with what it
 * printed on stdout and stderr. */
typedef struct {
    int rc;
    int nargs;
    char *argv[32];
    char words[512];
    char out[4096], err[4096];
} s_parse_t;

static void s_slurp (FILE *f, char *buf, size_t size)
{
    rewind (f);
    size_t n = fread (buf, 1, size - 1, f);
    buf[n] = '\0';
    fclose (f);
}

static void s_parse (s_parse_t *p, const ms_cmd_t *cmd, const char *line)
{
    memset (p, 0, sizeof *p);
    memset (&s_v, 0, sizeof s_v);
    snprintf (p->words, sizeof p->words, "%s", line);
    int argc = 0;
    p->argv[argc++] = "demo";
    for (char *w = strtok (p->words, " "); w; w = strtok (NULL, " "))
        p->argv[argc++] = w;
    FILE *out = tmpfile (), *err = tmpfile ();
    assert_non_null (out);
    assert_non_null (err);
    fflush (stdout);
    fflush (stderr);
    int saved_out = dup (STDOUT_FILENO), saved_err = dup (STDERR_FILENO);
    dup2 (fileno (out), STDOUT_FILENO);
    dup2 (fileno (err), STDERR_FILENO);
    int rc = ms_opts_parse (cmd, argc, p->argv);
    p->rc = rc < 0 ? rc : 0;
    p->nargs = rc < 0 ? -1 : rc;
    fflush (stdout);
    fflush (stderr);
    dup2 (saved_out, STDOUT_FILENO);
    dup2 (saved_err, STDERR_FILENO);
    close (saved_out);
    close (saved_err);
    s_slurp (out, p->out, sizeof p->out);
    s_slurp (err, p->err, sizeof p->err);
}

/* Values by every spelling, stored or read as they come. */
static void test_values (void **state)
{
    (void)state;
    s_parse_t p;
    s_parse (&p, &s_cmd, "--exercise x.ini --wait=2.5 --json -n 5 --radius -40 --uav=7");
    assert_int_equal (p.rc, 0);
    assert_int_equal (p.nargs, 0);
    assert_string_equal (s_v.exercise, "x.ini");
    assert_true (s_v.json);
    assert_true (s_v.count == 5);
    assert_true (s_v.wait_s == 2.5);
    assert_true (s_v.radius_m == -40); // the next argument is a value, '-' or not
    assert_int_equal (s_v.uav, 7);
    assert_string_equal (p.out, "");
    assert_string_equal (p.err, "");

    s_parse (&p, &s_cmd, "-jn5 --ex=y.ini --radius-m 3 --radius 4"); // exact beats prefix
    assert_int_equal (p.rc, 0);
    assert_true (s_v.json && s_v.count == 5 && s_v.radius_m == 4);
    assert_string_equal (s_v.exercise, "y.ini");

    s_parse (&p, &s_cmd, "-jn 6 --radius-m=9 --exercise=");
    assert_int_equal (p.rc, 0);
    assert_true (s_v.json && s_v.count == 6 && s_v.radius_m == 9);
    assert_string_equal (s_v.exercise, "");
}

/* Operands anywhere, in order, moved to argv[1..]; after `--` all are. */
static void test_operands (void **state)
{
    (void)state;
    s_parse_t p;
    s_parse (&p, &s_cmd, "a --json b - --wait 1 c -- --count -x d");
    assert_int_equal (p.rc, 0);
    assert_int_equal (p.nargs, 7);
    const char *want[] = {"a", "b", "-", "c", "--count", "-x", "d"};
    for (int i = 0; i < 7; i++)
        assert_string_equal (p.argv[1 + i], want[i]);
    assert_true (s_v.json && s_v.wait_s == 1 && s_v.count == 0);

    s_parse (&p, &s_cmd, "");
    assert_int_equal (p.rc, 0);
    assert_int_equal (p.nargs, 0);
}

/* getopt_long's messages, then the usage; the exit code 2. */
static void test_errors (void **state)
{
    (void)state;
    struct {
        const char *line, *said;
    } cases[] = {
        {"--bogus=3 a", "demo: unrecognized option '--bogus=3'\n"},
        {"--r=1", "demo: option '--r=1' is ambiguous; possibilities: '--radius' '--radius-max'\n"},
        {"--json=1", "demo: option '--json' doesn't allow an argument\n"},
        {"a --wai", "demo: option '--wait' requires an argument\n"},
        {"-q", "demo: invalid option -- 'q'\n"},
        {"-jx", "demo: invalid option -- 'x'\n"},
        {"-n", "demo: option requires an argument -- 'n'\n"},
        {"--json --bogus --wait", "demo: unrecognized option '--bogus'\n"}, // the first one
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        s_parse_t p;
        s_parse (&p, &s_cmd, cases[i].line);
        assert_int_equal (p.rc, -EINVAL);
        assert_int_equal (p.nargs, -1);
        assert_int_equal (ms_opts_exit_code (p.rc), 2);
        char want[4096];
        snprintf (want, sizeof want, "%s%s", cases[i].said, S_USAGE);
        assert_string_equal (p.err, want);
        assert_string_equal (p.out, "");
    }
}

/* A reader's refusal ends the parse with its own message, no usage; values
 * before it were read, options after it were not. */
static void test_readers_in_order (void **state)
{
    (void)state;
    s_parse_t p;
    s_parse (&p, &s_cmd, "--mark ok --mark bad --mark ok --bogus");
    assert_int_equal (p.rc, -EINVAL);
    assert_int_equal (s_v.calls, 2);
    assert_string_equal (p.err, "demo: --mark: bad\n");

    s_parse (&p, &s_cmd, "--wait x --help");
    assert_int_equal (p.rc, -EINVAL);
    assert_string_equal (p.err, "mscgs: --wait: expected a positive number, got 'x'\n");
    assert_string_equal (p.out, "");

    s_parse (&p, &s_cmd, "--count 0");
    assert_string_equal (p.err, "mscgs: --count: expected a positive number, got '0'\n");
    s_parse (&p, &s_cmd, "--radius 1e999");
    assert_string_equal (p.err, "mscgs: --radius: expected a number, got '1e999'\n");
    s_parse (&p, &s_cmd, "--uav -1");
    assert_string_equal (p.err, "mscgs: --uav: expected an entity id, got '-1'\n");
    s_parse (&p, &s_cmd, "--uav 4294967296");
    assert_int_equal (p.rc, -EINVAL);
    s_parse (&p, &s_cmd, "--uav 4294967295");
    assert_int_equal (p.rc, 0);
    assert_int_equal (s_v.uav, UINT32_MAX);
}

/* A command that needs an operand says so when none came, after the
 * options were read. */
static void test_missing_operand (void **state)
{
    (void)state;
    ms_cmd_t cmd = s_cmd;
    cmd.missing = "which topic?";
    s_parse_t p;
    s_parse (&p, &cmd, "--json -- ");
    assert_int_equal (p.rc, -EINVAL);
    assert_true (s_v.json);
    assert_string_equal (p.err, "mscgs demo: which topic?\n");
    s_parse (&p, &cmd, "--json x");
    assert_int_equal (p.rc, 0);
    assert_int_equal (p.nargs, 1);
    s_parse (&p, &cmd, "--bogus");
    assert_string_equal (p.err, "demo: unrecognized option '--bogus'\n" S_USAGE);
    s_parse (&p, &cmd, "-h");
    assert_int_equal (p.rc, -ECANCELED);
}

/* --help and -h: the usage on stdout, exit code 0, wherever they stand. */
static void test_help (void **state)
{
    (void)state;
    const char *lines[] = {"--help", "-h", "--he", "a --help --wait x", "-jh"};
    for (size_t i = 0; i < sizeof lines / sizeof lines[0]; i++) {
        s_parse_t p;
        s_parse (&p, &s_cmd, lines[i]);
        assert_int_equal (p.rc, -ECANCELED);
        assert_int_equal (ms_opts_exit_code (p.rc), 0);
        assert_string_equal (p.out, S_USAGE);
        assert_string_equal (p.err, "");
    }
    // Without a help entry, --help is an unknown option.
    static const ms_opt_t bare[] = {{.name = "dir", .value = "DIR", .help = "where"}, {NULL}};
    static const ms_cmd_t cmd = {.name = "bare", .operands = "NAME", .opts = bare};
    s_parse_t p;
    s_parse (&p, &cmd, "--help");
    assert_int_equal (p.rc, -EINVAL);
    assert_string_equal (p.err, "demo: unrecognized option '--help'\n"
                                "usage: mscgs bare NAME [--dir DIR]\n");
}

/* A usage given as text replaces the table's; the option list. */
static void test_usage_and_list (void **state)
{
    (void)state;
    ms_cmd_t cmd = s_cmd;
    cmd.synopsis = "usage: mscgs demo A | B\n";
    cmd.about = NULL;
    char *text = NULL;
    size_t size = 0;
    FILE *f = open_memstream (&text, &size);
    assert_non_null (f);
    ms_opts_usage (&cmd, f);
    ms_opts_list (s_opts, 3, f);
    fclose (f);
    assert_string_equal (text, "usage: mscgs demo A | B\n"
                               "   --exercise F   exercise file\n"
                               "   --json         one JSON object a line\n"
                               "   --count N      stop after N\n"
                               "   --wait S       wait S seconds\n"
                               "   --radius M     radius\n"
                               "   --radius-max M  the largest\n"
                               "                  radius\n"
                               "   --uav ID       the UAV\n");
    free (text);
}

/* The readers of operands: ret untouched on refusal. */
static void test_number_readers (void **state)
{
    (void)state;
    double v = 7;
    const char *bad[] = {"", "x", "3x", "nan", "inf", "1e999", " "};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        fflush (stderr);
        int saved = dup (STDERR_FILENO);
        FILE *null = fopen ("/dev/null", "w");
        assert_non_null (null);
        dup2 (fileno (null), STDERR_FILENO);
        assert_int_equal (ms_opts_number ("altitude", bad[i], &v), -EINVAL);
        fflush (stderr);
        dup2 (saved, STDERR_FILENO);
        close (saved);
        fclose (null);
        assert_true (v == 7);
    }
    assert_int_equal (ms_opts_number ("altitude", "-2.5e2", &v), 0);
    assert_true (v == -250);
    uint32_t u = 9;
    assert_int_equal (ms_opts_u32 ("x", "an id", "0", &u), 0);
    assert_int_equal (u, 0);
    assert_int_equal (ms_opts_u32 ("x", "an id", "4294967295", &u), 0);
    assert_int_equal (u, UINT32_MAX);
}

/* What s_record saw, in order. */
static char s_seen[1024];

static int s_record (const ms_opt_t *opt, const char *value)
{
    size_t n = strlen (s_seen);
    snprintf (s_seen + n, sizeof s_seen - n, "--%s%s%s ", opt->name, value ? "=" : "",
              value ? value : "");
    return 0;
}

/* The same table twice: for ms_opts (every option recorded, an empty
 * usage) and for getopt_long (optstring "jn:"). */
static const ms_opt_t s_rec_opts[] = {
    {.name = "exercise", .value = "F", .help = "-", .fn = s_record},
    {.name = "json", .letter = 'j', .help = "-", .fn = s_record},
    {.name = "count", .letter = 'n', .value = "N", .help = "-", .fn = s_record},
    {.name = "radius", .value = "M", .help = "-", .fn = s_record},
    {.name = "radius-max", .value = "M", .help = "-", .fn = s_record},
    {NULL},
};
static const struct option s_rec_long[] = {
    {"exercise", required_argument, NULL, 1},   {"json", no_argument, NULL, 'j'},
    {"count", required_argument, NULL, 'n'},    {"radius", required_argument, NULL, 2},
    {"radius-max", required_argument, NULL, 3}, {NULL, 0, NULL, 0},
};

/* getopt_long over the words of line: what it returned, recorded as
 * s_record records, its operands, its message. */
static void s_getopt (s_parse_t *p, const char *line)
{
    memset (p, 0, sizeof *p);
    s_seen[0] = '\0';
    snprintf (p->words, sizeof p->words, "%s", line);
    int argc = 0;
    p->argv[argc++] = "demo";
    for (char *w = strtok (p->words, " "); w; w = strtok (NULL, " "))
        p->argv[argc++] = w;
    FILE *err = tmpfile ();
    assert_non_null (err);
    fflush (stderr);
    int saved = dup (STDERR_FILENO);
    dup2 (fileno (err), STDERR_FILENO);
    optind = 0; // glibc: start afresh
    int c, index = -1;
    while ((c = getopt_long (argc, p->argv, "jn:", s_rec_long, &index)) != -1) {
        if (c == '?' || c == ':') {
            p->rc = -EINVAL;
            break;
        }
        const ms_opt_t *o = s_rec_opts;
        if (c == 'j' || c == 'n')
            while (o->letter != c)
                o++;
        else
            o = &s_rec_opts[index];
        s_record (o, optarg);
        index = -1;
    }
    fflush (stderr);
    dup2 (saved, STDERR_FILENO);
    close (saved);
    s_slurp (err, p->err, sizeof p->err);
    if (p->rc == 0) {
        p->nargs = argc - optind;
        memmove (&p->argv[1], &p->argv[optind], (size_t)p->nargs * sizeof p->argv[0]);
    }
}

/* ms_opts takes, refuses and says what getopt_long does. */
static void test_same_as_getopt_long (void **state)
{
    (void)state;
    static const ms_cmd_t cmd = {.name = "demo", .synopsis = "", .opts = s_rec_opts};
    const char *lines[] = {"a --json b -- --count -x d",
                           "--ex=1 --radius-m 2 --radius 3 z",
                           "-jn5 q",
                           "-jn 5 -j",
                           "x --count=",
                           "--r=1",
                           "--rad 1",
                           "--bogus=2",
                           "--json=1",
                           "--count",
                           "-n",
                           "-q",
                           "-jq",
                           "--=x",
                           "- -- -",
                           "--exercise --json",
                           "a b c",
                           "",
                           "--",
                           "-- --"};
    for (size_t i = 0; i < sizeof lines / sizeof lines[0]; i++) {
        s_parse_t want, got;
        s_getopt (&want, lines[i]);
        char seen[sizeof s_seen];
        snprintf (seen, sizeof seen, "%s", s_seen);
        s_seen[0] = '\0';
        s_parse (&got, &cmd, lines[i]);
        assert_string_equal (s_seen, seen);
        assert_int_equal (got.rc, want.rc);
        assert_string_equal (got.err, want.err);
        if (want.rc == 0) {
            assert_int_equal (got.nargs, want.nargs);
            for (int k = 1; k <= want.nargs; k++)
                assert_string_equal (got.argv[k], want.argv[k]);
        }
    }
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_values),
        cmocka_unit_test (test_operands),
        cmocka_unit_test (test_errors),
        cmocka_unit_test (test_readers_in_order),
        cmocka_unit_test (test_missing_operand),
        cmocka_unit_test (test_help),
        cmocka_unit_test (test_usage_and_list),
        cmocka_unit_test (test_number_readers),
        cmocka_unit_test (test_same_as_getopt_long),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
