/* ms_opts — the options of mscgs's commands, each command's from one table
 * (ms_opts.h says what the parser takes and says). */
#include "ms_opts.h"

#include "cgs_util.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#define S_USAGE_COLUMNS 100 // the usage's lines wrap before this
#define S_LIST_COLUMNS  15  // an option list's help starts this far from the option

static bool s_is_help (const ms_opt_t *o)
{
    return strcmp (o->name, "help") == 0;
}

/* Store or read an option's value (NULL for an option without one). */
static int s_apply (const ms_cmd_t *cmd, const ms_opt_t *o, const char *value)
{
    if (s_is_help (o)) {
        ms_opts_usage (cmd, stdout);
        return -ECANCELED;
    }
    if (o->str)
        *o->str = value;
    else if (o->flag)
        *o->flag = true;
    else if (o->fn && o->fn (o, value) < 0)
        return -EINVAL;
    return 0;
}

/* Say what is wrong as getopt_long says it, after "PROG: ", then the usage. */
static int s_bad (const ms_cmd_t *cmd, const char *prog, const char *fmt, ...)
    __attribute__ ((format (printf, 3, 4)));

static int s_bad (const ms_cmd_t *cmd, const char *prog, const char *fmt, ...)
{
    va_list ap;
    va_start (ap, fmt);
    fprintf (stderr, "%s: ", prog);
    vfprintf (stderr, fmt, ap);
    va_end (ap);
    ms_opts_usage (cmd, stderr);
    return -EINVAL;
}

/* argv[*i], "--NAME", "--NAME=V" or a prefix of a name; *i moves past a
 * value taken from the next argument. */
static int s_long (const ms_cmd_t *cmd, int argc, char **argv, int *i)
{
    const char *text = argv[*i] + 2;
    const char *eq = strchr (text, '=');
    size_t len = eq ? (size_t)(eq - text) : strlen (text);
    const ms_opt_t *found = NULL;
    int matches = 0;
    for (const ms_opt_t *o = cmd->opts; o->name; o++) {
        if (strncmp (o->name, text, len) != 0)
            continue;
        if (strlen (o->name) == len) { // an exact match is never ambiguous
            found = o;
            matches = 1;
            break;
        }
        if (matches++ == 0)
            found = o;
    }
    if (matches == 0)
        return s_bad (cmd, argv[0], "unrecognized option '--%s'\n", text);
    if (matches > 1) {
        fprintf (stderr, "%s: option '--%s' is ambiguous; possibilities:", argv[0], text);
        for (const ms_opt_t *o = cmd->opts; o->name; o++)
            if (strncmp (o->name, text, len) == 0)
                fprintf (stderr, " '--%s'", o->name);
        fputc ('\n', stderr);
        ms_opts_usage (cmd, stderr);
        return -EINVAL;
    }
    const char *value = NULL;
    if (eq && !found->value)
        return s_bad (cmd, argv[0], "option '--%s' doesn't allow an argument\n", found->name);
    if (eq)
        value = eq + 1;
    else if (found->value && *i + 1 < argc)
        value = argv[++*i];
    else if (found->value)
        return s_bad (cmd, argv[0], "option '--%s' requires an argument\n", found->name);
    return s_apply (cmd, found, value);
}

/* argv[*i], one or more letters after "-" ("-jn5", "-jn 5"); *i moves
 * past a value taken from the next argument. */
static int s_short (const ms_cmd_t *cmd, int argc, char **argv, int *i)
{
    for (const char *p = argv[*i] + 1; *p; p++) {
        const ms_opt_t *o = cmd->opts;
        while (o->name && o->letter != *p)
            o++;
        if (!o->name)
            return s_bad (cmd, argv[0], "invalid option -- '%c'\n", *p);
        if (!o->value) {
            int rc = s_apply (cmd, o, NULL);
            if (rc < 0)
                return rc;
            continue;
        }
        if (p[1])
            return s_apply (cmd, o, p + 1);
        if (*i + 1 < argc)
            return s_apply (cmd, o, argv[++*i]);
        return s_bad (cmd, argv[0], "option requires an argument -- '%c'\n", *p);
    }
    return 0;
}

int ms_opts_parse (const ms_cmd_t *cmd, int argc, char **argv)
{
    int nargs = 0;
    bool options = true;
    for (int i = 1; i < argc; i++) {
        char *a = argv[i];
        if (!options || a[0] != '-' || a[1] == '\0') {
            argv[1 + nargs++] = a; // never past i: the operands move towards the front
            continue;
        }
        if (strcmp (a, "--") == 0) {
            options = false;
            continue;
        }
        int rc = a[1] == '-' ? s_long (cmd, argc, argv, &i) : s_short (cmd, argc, argv, &i);
        if (rc < 0)
            return rc;
    }
    if (cmd->missing && nargs == 0) {
        fprintf (stderr, "mscgs %s: %s\n", cmd->name, cmd->missing);
        return -EINVAL;
    }
    return nargs;
}

int ms_opts_exit_code (int rc)
{
    return rc == -ECANCELED ? 0 : 2;
}

void ms_opts_usage (const ms_cmd_t *cmd, FILE *f)
{
    if (cmd->synopsis) {
        fputs (cmd->synopsis, f);
    } else {
        int col = fprintf (f, "usage: mscgs %s", cmd->name);
        int indent = col + 1;
        if (cmd->operands)
            col += fprintf (f, " %s", cmd->operands);
        for (const ms_opt_t *o = cmd->opts; o->name; o++) {
            if (!o->help)
                continue;
            char piece[128];
            int n = snprintf (piece, sizeof piece, "[--%s%s%s]", o->name, o->value ? " " : "",
                              o->value ? o->value : "");
            if (col + 1 + n > S_USAGE_COLUMNS) {
                fprintf (f, "\n%*s%s", indent, "", piece);
                col = indent + n;
            } else {
                fprintf (f, " %s", piece);
                col += 1 + n;
            }
        }
        fputc ('\n', f);
    }
    if (cmd->about)
        fputs (cmd->about, f);
}

void ms_opts_list (const ms_opt_t *opts, int indent, FILE *f)
{
    for (const ms_opt_t *o = opts; o->name; o++) {
        if (!o->help)
            continue;
        char spec[128];
        snprintf (spec, sizeof spec, "--%s%s%s", o->name, o->value ? " " : "",
                  o->value ? o->value : "");
        fprintf (f, "%*s%-*s  ", indent, "", S_LIST_COLUMNS - 2, spec);
        for (const char *h = o->help; *h; h++)
            if (*h == '\n')
                fprintf (f, "\n%*s", indent + S_LIST_COLUMNS, "");
            else
                fputc (*h, f);
        fputc ('\n', f);
    }
}

/* Read text as a finite number, positive if asked: 0, or -EINVAL after
 * saying why. */
static int s_double (const char *what, const char *text, bool positive, double *ret)
{
    char *end = NULL;
    double v = strtod (text, &end);
    if (!end || end == text || *end || !isfinite (v) || (positive && !(v > 0))) {
        fprintf (stderr, "mscgs: %s: expected a %snumber, got '%s'\n", what,
                 positive ? "positive " : "", text);
        return -EINVAL;
    }
    *ret = v;
    return 0;
}

int ms_opts_number (const char *what, const char *text, double *ret)
{
    return s_double (what, text, false, ret);
}

int ms_opts_positive (const char *what, const char *text, double *ret)
{
    return s_double (what, text, true, ret);
}

int ms_opts_u32 (const char *what, const char *expected, const char *text, uint32_t *ret)
{
    uint64_t v = 0;
    if (cgs_parse_u64 (text, UINT32_MAX, &v) < 0) {
        fprintf (stderr, "mscgs: %s: expected %s, got '%s'\n", what, expected, text);
        return -EINVAL;
    }
    *ret = (uint32_t)v;
    return 0;
}

int ms_opts_read_number (const ms_opt_t *opt, const char *value)
{
    char what[128];
    snprintf (what, sizeof what, "--%s", opt->name);
    return ms_opts_number (what, value, opt->arg);
}

int ms_opts_read_positive (const ms_opt_t *opt, const char *value)
{
    char what[128];
    snprintf (what, sizeof what, "--%s", opt->name);
    return ms_opts_positive (what, value, opt->arg);
}

int ms_opts_read_entity_id (const ms_opt_t *opt, const char *value)
{
    char what[128];
    snprintf (what, sizeof what, "--%s", opt->name);
    return ms_opts_u32 (what, "an entity id", value, opt->arg);
}
