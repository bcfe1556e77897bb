/* cgs_config — INI files read with inih into an ordered store that keeps each
 * key's line, with typed getters that mark what they read and errors that
 * name the file, the line, the key and what was expected.
 *
 * inih reads through our own line reader, which counts lines and feeds inih
 * one whole line at a time with its indentation removed. So indentation is
 * free and inih's multi-line continuation never applies (an indented line is
 * a line of its own); the reader also notes section headers itself, so empty
 * sections are kept and section names have no length limit, and it reports
 * syntax errors at once with the right line. A line longer than inih's buffer
 * is an error, except a comment, which is cut. Pure: no logging, no globals. */
#include "cgs_config.h"
#include "cgs_util.h"

#include <ini.h>

#include <assert.h>
#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

typedef struct {
    char *key;
    char *value;
    int line;  // line of the file it was read from, 1-based
    bool used; // a getter read it, or its section was marked
} s_entry_t;

typedef struct {
    char *name;     // e.g. "uav uav1"; "" for keys before any section
    int line;       // where it first starts (the first key's line for "")
    int again_line; // where its header is given a second time, 0 if never
    bool looked_at; // a getter asked about one of its keys
    s_entry_t *entries;
    size_t count;
    size_t alloc;
} s_section_t;

struct cgs_config {
    char *path; // as given
    char *dir;  // folder of path, "." when none
    s_section_t *sections;
    size_t count;
    size_t alloc;
    char **strings; // joined paths handed out by cgs_config_get_path
    size_t nstrings;
    size_t astrings;
};

#define S_SYNTAX "syntax error (expected `key = value` or `[section]`)"
#define S_FORMS                                                                                    \
    "`E N [U]` or `local E N [U]` in metres, `geo LAT LON [H]`, `LAT{N|S} LON{E|W} [H]` or "       \
    "`mgrs GRID`"
#define S_GEO_FORMS "`geo LAT LON [H]`, `LAT{N|S} LON{E|W} [H]` or `mgrs GRID`"

// --- storage ------------------------------------------------------------------

static s_section_t *s_section (const cgs_config_t *self, const char *name)
{
    for (size_t i = 0; i < self->count; i++)
        if (strcmp (self->sections[i].name, name) == 0)
            return &self->sections[i];
    return NULL;
}

// Index of the section of that name, added at line when new; -ENOMEM.
static int s_section_add (cgs_config_t *self, const char *name, int line, size_t *ret_index)
{
    for (size_t i = 0; i < self->count; i++)
        if (strcmp (self->sections[i].name, name) == 0) {
            *ret_index = i;
            return 0;
        }
    if (self->count == self->alloc) {
        size_t alloc = self->alloc ? 2 * self->alloc : 8;
        s_section_t *sections = realloc (self->sections, alloc * sizeof *sections);
        if (!sections)
            return -ENOMEM;
        self->sections = sections;
        self->alloc = alloc;
    }
    char *copy = strdup (name);
    if (!copy)
        return -ENOMEM;
    self->sections[self->count] = (s_section_t){.name = copy, .line = line};
    *ret_index = self->count++;
    return 0;
}

static int s_entry_add (s_section_t *section, const char *key, const char *value, int line)
{
    if (section->count == section->alloc) {
        size_t alloc = section->alloc ? 2 * section->alloc : 8;
        s_entry_t *entries = realloc (section->entries, alloc * sizeof *entries);
        if (!entries)
            return -ENOMEM;
        section->entries = entries;
        section->alloc = alloc;
    }
    char *k = strdup (key);
    char *v = strdup (value);
    if (!k || !v) {
        free (k);
        free (v);
        return -ENOMEM;
    }
    section->entries[section->count++] = (s_entry_t){.key = k, .value = v, .line = line};
    return 0;
}

// The idx-th occurrence of key in the section, or NULL.
static s_entry_t *s_entry (const cgs_config_t *self, const char *section, const char *key,
                           size_t idx)
{
    s_section_t *sec = s_section (self, section);
    if (!sec)
        return NULL;
    for (size_t i = 0; i < sec->count; i++)
        if (strcmp (sec->entries[i].key, key) == 0 && idx-- == 0)
            return &sec->entries[i];
    return NULL;
}

// Keep a string for the config's lifetime; returns it, or NULL (and frees it) on -ENOMEM.
static const char *s_keep (cgs_config_t *self, char *s)
{
    if (!s)
        return NULL;
    if (self->nstrings == self->astrings) {
        size_t alloc = self->astrings ? 2 * self->astrings : 8;
        char **strings = realloc (self->strings, alloc * sizeof *strings);
        if (!strings) {
            free (s);
            return NULL;
        }
        self->strings = strings;
        self->astrings = alloc;
    }
    self->strings[self->nstrings++] = s;
    return s;
}

void cgs_config_destroy (cgs_config_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    cgs_config_t *self = *self_p;
    for (size_t i = 0; i < self->count; i++) {
        s_section_t *sec = &self->sections[i];
        for (size_t j = 0; j < sec->count; j++) {
            free (sec->entries[j].key);
            free (sec->entries[j].value);
        }
        free (sec->entries);
        free (sec->name);
    }
    free (self->sections);
    for (size_t i = 0; i < self->nstrings; i++)
        free (self->strings[i]);
    free (self->strings);
    free (self->path);
    free (self->dir);
    free (self);
    *self_p = NULL;
}

// A config named path (no sections yet), or NULL.
static cgs_config_t *s_new (const char *path)
{
    cgs_config_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->path = strdup (path);
    if (!self->path)
        goto fail;
    const char *slash = strrchr (path, '/');
    if (!slash)
        self->dir = strdup (".");
    else if (slash == path)
        self->dir = strdup ("/");
    else
        self->dir = strndup (path, (size_t)(slash - path));
    if (!self->dir)
        goto fail;
    return self;
fail:
    cgs_config_destroy (&self);
    return NULL;
}

// --- reading --------------------------------------------------------------------

typedef struct {
    cgs_config_t *cfg;
    FILE *file;       // read lines from this, or
    const char *text; // from this (what is left of it)
    char *raw;        // the current line, without its newline
    size_t rawsize;   // bytes allocated at raw
    int line;         // lines read so far
    size_t section;   // index of the current section; SIZE_MAX before the first
    int rc;           // the first error, negative errno; the message is in err
    char *err;
    size_t errlen;
} s_parser_t;

// Next line into p->raw without its newline; false at the end or on error.
static bool s_next_line (s_parser_t *p)
{
    size_t n;
    if (p->file) {
        ssize_t got = getline (&p->raw, &p->rawsize, p->file);
        if (got < 0) {
            if (ferror (p->file)) {
                int e = errno ? errno : EIO;
                p->rc = -e;
                cgs_errf (p->err, p->errlen, "%s: %s", p->cfg->path, strerror (e));
            }
            return false;
        }
        n = (size_t)got;
    } else {
        if (!*p->text)
            return false;
        const char *nl = strchr (p->text, '\n');
        n = nl ? (size_t)(nl - p->text) + 1 : strlen (p->text);
        if (n + 1 > p->rawsize) {
            char *raw = realloc (p->raw, n + 1);
            if (!raw) {
                p->rc = -ENOMEM;
                cgs_errf (p->err, p->errlen, "%s: out of memory", p->cfg->path);
                return false;
            }
            p->raw = raw;
            p->rawsize = n + 1;
        }
        memcpy (p->raw, p->text, n);
        p->raw[n] = '\0';
        p->text += n;
    }
    if (n > 0 && p->raw[n - 1] == '\n')
        p->raw[n - 1] = '\0';
    return true;
}

static void s_syntax_error (s_parser_t *p)
{
    p->rc = -EINVAL;
    cgs_errf (p->err, p->errlen, "%s:%d: " S_SYNTAX, p->cfg->path, p->line);
}

// inih's rule for where a name ends: at one of chars, or at a ';' comment after whitespace.
static const char *s_find_chars_or_comment (const char *s, const char *chars)
{
    bool was_space = false;
    while (*s && !strchr (chars, *s) && !(was_space && *s == ';')) {
        was_space = isspace ((unsigned char)*s);
        s++;
    }
    return s;
}

// A "[name]" line: makes that section current. Anything but a comment after ']' is an error.
static void s_section_line (s_parser_t *p, const char *s)
{
    const char *end = s_find_chars_or_comment (s + 1, "]");
    if (*end != ']') {
        s_syntax_error (p);
        return;
    }
    const char *rest = end + 1;
    while (isspace ((unsigned char)*rest))
        rest++;
    if (*rest && *rest != ';' && *rest != '#') {
        s_syntax_error (p);
        return;
    }
    // The name, trimmed, with runs of blanks made one space: "[uav   uav1]" is "uav uav1".
    char *name = malloc ((size_t)(end - s));
    if (!name) {
        p->rc = -ENOMEM;
        cgs_errf (p->err, p->errlen, "%s: out of memory", p->cfg->path);
        return;
    }
    size_t n = 0;
    for (const char *c = s + 1; c < end; c++) {
        if (isspace ((unsigned char)*c)) {
            if (n > 0 && name[n - 1] != ' ')
                name[n++] = ' ';
        } else
            name[n++] = *c;
    }
    if (n > 0 && name[n - 1] == ' ')
        n--;
    name[n] = '\0';
    if (n == 0) {
        p->rc = -EINVAL;
        cgs_errf (p->err, p->errlen, "%s:%d: empty section name", p->cfg->path, p->line);
    } else if (s_section_add (p->cfg, name, p->line, &p->section) < 0) {
        p->rc = -ENOMEM;
        cgs_errf (p->err, p->errlen, "%s: out of memory", p->cfg->path);
    } else {
        s_section_t *sec = &p->cfg->sections[p->section];
        if (sec->line != p->line && sec->again_line == 0)
            sec->again_line = p->line; // merged, but remembered
    }
    free (name);
}

// inih's reader: one whole line per call, unindented, checked before inih sees it.
static char *s_reader (char *str, int num, void *stream)
{
    s_parser_t *p = stream;
    if (p->rc || num < 2 || !s_next_line (p))
        return NULL;
    p->line++;
    char *s = p->raw;
    if (p->line == 1 && strncmp (s, "\xEF\xBB\xBF", 3) == 0)
        s += 3; // UTF-8 byte order mark
    while (isspace ((unsigned char)*s))
        s++;
    size_t len = strlen (s);
    bool comment = *s == ';' || *s == '#';
    if (len > (size_t)num - 1) {
        if (!comment) {
            p->rc = -EINVAL;
            cgs_errf (p->err, p->errlen,
                      "%s:%d: line too long (at most %d characters, not counting indentation)",
                      p->cfg->path, p->line, num - 1);
            return NULL;
        }
        len = (size_t)num - 1;
    }
    if (*s == '[')
        s_section_line (p, s);
    else if (*s && !comment) {
        const char *sep = s_find_chars_or_comment (s, "=:");
        if (*sep != '=' && *sep != ':')
            s_syntax_error (p);
        else if (sep == s)
            s_syntax_error (p); // no key before '='
    }
    if (p->rc)
        return NULL;
    memcpy (str, s, len);
    str[len] = '\0';
    return str;
}

static int s_handler (void *user, const char *section, const char *name, const char *value)
{
    s_parser_t *p = user;
    (void)section; // inih's copy is cut at 50 characters: the reader keeps the real one
    if (p->rc)
        return 0;
    if (!*name) {
        s_syntax_error (p);
        return 0;
    }
    if (p->section == SIZE_MAX && s_section_add (p->cfg, "", p->line, &p->section) < 0)
        goto nomem;
    if (s_entry_add (&p->cfg->sections[p->section], name, value ? value : "", p->line) < 0)
        goto nomem;
    return 1;
nomem:
    p->rc = -ENOMEM;
    cgs_errf (p->err, p->errlen, "%s: out of memory", p->cfg->path);
    return 0;
}

// Parse from file or text into a config called name.
static int s_load (const char *name, FILE *file, const char *text, cgs_config_t **ret_cfg,
                   char *err, size_t errlen)
{
    s_parser_t p = {.file = file, .text = text, .section = SIZE_MAX, .err = err, .errlen = errlen};
    p.cfg = s_new (name);
    if (!p.cfg) {
        cgs_errf (err, errlen, "%s: out of memory", name);
        return -ENOMEM;
    }
    int rc = ini_parse_stream (s_reader, &p, s_handler, &p);
    free (p.raw);
    if (p.rc == 0 && rc > 0) {
        // The reader checks what inih would reject, so this is only a fallback.
        p.rc = -EINVAL;
        cgs_errf (err, errlen, "%s:%d: " S_SYNTAX, name, rc);
    } else if (p.rc == 0 && rc < 0) {
        p.rc = -ENOMEM;
        cgs_errf (err, errlen, "%s: out of memory", name);
    }
    if (p.rc) {
        cgs_config_destroy (&p.cfg);
        return p.rc;
    }
    *ret_cfg = p.cfg;
    return 0;
}

int cgs_config_load (const char *path, cgs_config_t **ret_cfg, char *err, size_t errlen)
{
    assert (path && ret_cfg);
    FILE *file = fopen (path, "r");
    if (!file) {
        int rc = -errno;
        cgs_errf (err, errlen, "%s: %s", path, strerror (errno));
        return rc;
    }
    int rc = s_load (path, file, NULL, ret_cfg, err, errlen);
    fclose (file);
    return rc;
}

int cgs_config_load_string (const char *name, const char *text, cgs_config_t **ret_cfg, char *err,
                            size_t errlen)
{
    assert (name && text && ret_cfg);
    return s_load (name, NULL, text, ret_cfg, err, errlen);
}

// --- plain accessors ------------------------------------------------------------

const char *cgs_config_path (const cgs_config_t *self)
{
    return self->path;
}

const char *cgs_config_dir (const cgs_config_t *self)
{
    return self->dir;
}

size_t cgs_config_section_count (const cgs_config_t *self)
{
    return self->count;
}

const char *cgs_config_section_name (const cgs_config_t *self, size_t i)
{
    return i < self->count ? self->sections[i].name : NULL;
}

int cgs_config_section_again (const cgs_config_t *self, size_t i)
{
    return i < self->count ? self->sections[i].again_line : 0;
}

int cgs_config_section_line (const cgs_config_t *self, size_t i)
{
    return i < self->count ? self->sections[i].line : 0;
}

bool cgs_config_has_section (const cgs_config_t *self, const char *section)
{
    return s_section (self, section) != NULL;
}

bool cgs_config_has (const cgs_config_t *self, const char *section, const char *key)
{
    return s_entry (self, section, key, 0) != NULL;
}

size_t cgs_config_count (const cgs_config_t *self, const char *section, const char *key)
{
    const s_section_t *sec = s_section (self, section);
    size_t n = 0;
    for (size_t i = 0; sec && i < sec->count; i++)
        n += strcmp (sec->entries[i].key, key) == 0;
    return n;
}

int cgs_config_line (const cgs_config_t *self, const char *section, const char *key, size_t idx)
{
    const s_entry_t *e = s_entry (self, section, key, idx);
    return e ? e->line : 0;
}

// --- errors ---------------------------------------------------------------------

static int s_verror (const cgs_config_t *self, const char *section, const char *key, size_t idx,
                     char *err, size_t errlen, const char *fmt, va_list ap)
{
    if (!err || errlen == 0)
        return -EINVAL;
    int line = 0;
    if (key)
        line = cgs_config_line (self, section, key, idx);
    else {
        const s_section_t *sec = s_section (self, section);
        line = sec ? sec->line : 0;
    }
    char where[32] = "";
    if (line > 0)
        snprintf (where, sizeof where, ":%d", line);
    int n;
    if (!*section)
        n = snprintf (err, errlen, "%s%s: %s%s", self->path, where, key ? key : "",
                      key ? ": " : "");
    else
        n = snprintf (err, errlen, "%s%s: [%s] %s%s", self->path, where, section, key ? key : "",
                      key ? ": " : "");
    if (n >= 0 && (size_t)n < errlen)
        vsnprintf (err + n, errlen - (size_t)n, fmt, ap);
    return -EINVAL;
}

// With key NULL the message is about the section, at its first line: "file:3: [sec] ...".
int cgs_config_error (const cgs_config_t *self, const char *section, const char *key, size_t idx,
                      char *err, size_t errlen, const char *fmt, ...)
{
    va_list ap;
    va_start (ap, fmt);
    int rc = s_verror (self, section, key, idx, err, errlen, fmt, ap);
    va_end (ap);
    return rc;
}

int cgs_config_value_error (const cgs_config_t *self, const char *section, const char *key,
                            const char *msg, char *err, size_t errlen)
{
    if (self && cgs_config_has (self, section, key))
        return cgs_config_error (self, section, key, 0, err, errlen, "%s", msg);
    if (self)
        cgs_errf (err, errlen, "%s: [%s] %s: %s", self->path, section, key, msg);
    else
        cgs_errf (err, errlen, "[%s] %s: %s", section, key, msg);
    return -EINVAL;
}

// --- typed getters --------------------------------------------------------------

/* The single occurrence of key, or NULL when absent; -EINVAL when it is given
 * twice. Notes that the section was looked at. */
static int s_lookup (cgs_config_t *self, const char *section, const char *key,
                     s_entry_t **ret_entry, char *err, size_t errlen)
{
    assert (self && section && key);
    s_section_t *sec = s_section (self, section);
    s_entry_t *first = NULL;
    if (sec) {
        sec->looked_at = true;
        for (size_t i = 0; i < sec->count; i++) {
            if (strcmp (sec->entries[i].key, key) != 0)
                continue;
            if (first)
                return cgs_config_error (self, section, key, 1, err, errlen,
                                         "given twice (first at line %d)", first->line);
            first = &sec->entries[i];
        }
    }
    *ret_entry = first;
    return 0;
}

int cgs_config_get_string (cgs_config_t *self, const char *section, const char *key,
                           const char *def, const char **ret, char *err, size_t errlen)
{
    s_entry_t *e;
    int rc = s_lookup (self, section, key, &e, err, errlen);
    if (rc < 0)
        return rc;
    if (!e) {
        *ret = def;
        return 0;
    }
    e->used = true;
    *ret = e->value;
    return 0;
}

// Whole of s as a finite number.
static bool s_parse_double (const char *s, double *ret)
{
    if (!*s || isspace ((unsigned char)*s))
        return false;
    char *end;
    double v = strtod (s, &end);
    if (end == s || *end || !isfinite (v))
        return false;
    *ret = v;
    return true;
}

int cgs_config_get_double (cgs_config_t *self, const char *section, const char *key, double def,
                           double min, double max, double *ret, char *err, size_t errlen)
{
    s_entry_t *e;
    int rc = s_lookup (self, section, key, &e, err, errlen);
    if (rc < 0)
        return rc;
    if (!e) {
        *ret = def;
        return 0;
    }
    double v;
    if (!s_parse_double (e->value, &v) || v < min || v > max) {
        bool lo = isfinite (min) && min > -DBL_MAX, hi = isfinite (max) && max < DBL_MAX;
        const char *sec = section, *k = key;
        if (lo && hi)
            return cgs_config_error (self, sec, k, 0, err, errlen,
                                     "expected a number in [%.15g, %.15g], got '%s'", min, max,
                                     e->value);
        if (lo)
            return cgs_config_error (self, sec, k, 0, err, errlen,
                                     "expected a number >= %.15g, got '%s'", min, e->value);
        if (hi)
            return cgs_config_error (self, sec, k, 0, err, errlen,
                                     "expected a number <= %.15g, got '%s'", max, e->value);
        return cgs_config_error (self, sec, k, 0, err, errlen, "expected a number, got '%s'",
                                 e->value);
    }
    e->used = true;
    *ret = v;
    return 0;
}

int cgs_config_get_int (cgs_config_t *self, const char *section, const char *key, long def,
                        long min, long max, long *ret, char *err, size_t errlen)
{
    s_entry_t *e;
    int rc = s_lookup (self, section, key, &e, err, errlen);
    if (rc < 0)
        return rc;
    if (!e) {
        *ret = def;
        return 0;
    }
    const char *s = e->value;
    char *end = NULL;
    errno = 0;
    long v = *s && !isspace ((unsigned char)*s) ? strtol (s, &end, 10) : 0;
    if (!end || end == s || *end || errno == ERANGE || v < min || v > max) {
        bool lo = min > LONG_MIN, hi = max < LONG_MAX;
        if (lo && hi)
            return cgs_config_error (self, section, key, 0, err, errlen,
                                     "expected an integer in [%ld, %ld], got '%s'", min, max, s);
        if (lo)
            return cgs_config_error (self, section, key, 0, err, errlen,
                                     "expected an integer >= %ld, got '%s'", min, s);
        if (hi)
            return cgs_config_error (self, section, key, 0, err, errlen,
                                     "expected an integer <= %ld, got '%s'", max, s);
        return cgs_config_error (self, section, key, 0, err, errlen,
                                 "expected an integer, got '%s'", s);
    }
    e->used = true;
    *ret = v;
    return 0;
}

int cgs_config_get_uint64 (cgs_config_t *self, const char *section, const char *key, uint64_t def,
                           uint64_t *ret, char *err, size_t errlen)
{
    s_entry_t *e;
    int rc = s_lookup (self, section, key, &e, err, errlen);
    if (rc < 0)
        return rc;
    if (!e) {
        *ret = def;
        return 0;
    }
    const char *s = e->value;
    char *end = NULL;
    errno = 0;
    // strtoull takes "-1" as the largest value: only digits (and a '+') may start it.
    unsigned long long v = isdigit ((unsigned char)*s) || *s == '+' ? strtoull (s, &end, 10) : 0;
    if (!end || end == s || *end || errno == ERANGE)
        return cgs_config_error (self, section, key, 0, err, errlen,
                                 "expected an integer in [0, %llu], got '%s'",
                                 (unsigned long long)UINT64_MAX, s);
    e->used = true;
    *ret = (uint64_t)v;
    return 0;
}

int cgs_config_get_bool (cgs_config_t *self, const char *section, const char *key, bool def,
                         bool *ret, char *err, size_t errlen)
{
    static const char *const yes[] = {"true", "yes", "on", "1"};
    static const char *const no[] = {"false", "no", "off", "0"};
    s_entry_t *e;
    int rc = s_lookup (self, section, key, &e, err, errlen);
    if (rc < 0)
        return rc;
    if (!e) {
        *ret = def;
        return 0;
    }
    for (size_t i = 0; i < sizeof yes / sizeof yes[0]; i++) {
        if (strcasecmp (e->value, yes[i]) == 0 || strcasecmp (e->value, no[i]) == 0) {
            e->used = true;
            *ret = strcasecmp (e->value, yes[i]) == 0;
            return 0;
        }
    }
    return cgs_config_error (self, section, key, 0, err, errlen,
                             "expected true/false, yes/no, on/off or 1/0, got '%s'", e->value);
}

int cgs_config_get_enum (cgs_config_t *self, const char *section, const char *key,
                         const char *const *names, int def, int *ret, char *err, size_t errlen)
{
    assert (names);
    s_entry_t *e;
    int rc = s_lookup (self, section, key, &e, err, errlen);
    if (rc < 0)
        return rc;
    if (!e) {
        *ret = def;
        return 0;
    }
    for (int i = 0; names[i]; i++) {
        if (strcasecmp (e->value, names[i]) == 0) {
            e->used = true;
            *ret = i;
            return 0;
        }
    }
    // "expected one of 'a', 'b', 'c', got 'x'"
    char list[512] = "";
    size_t n = 0;
    for (int i = 0; names[i] && n < sizeof list; i++)
        n += (size_t)snprintf (list + n, sizeof list - n, "%s'%s'", i ? ", " : "", names[i]);
    return cgs_config_error (self, section, key, 0, err, errlen, "expected one of %s, got '%s'",
                             list, e->value);
}

// value joined to the config's folder when relative, kept by the config; NULL on -ENOMEM.
static const char *s_join (cgs_config_t *self, const char *value)
{
    if (!*value || value[0] == '/' || strcmp (self->dir, ".") == 0)
        return value;
    char *joined;
    if (asprintf (&joined, "%s%s%s", self->dir, strcmp (self->dir, "/") == 0 ? "" : "/", value) < 0)
        return NULL;
    return s_keep (self, joined);
}

/* An empty value gives "" (no file). A relative default is taken from the
 * config file's folder too, as if it had been written in the file. */
int cgs_config_get_path (cgs_config_t *self, const char *section, const char *key, const char *def,
                         const char **ret, char *err, size_t errlen)
{
    s_entry_t *e;
    int rc = s_lookup (self, section, key, &e, err, errlen);
    if (rc < 0)
        return rc;
    const char *value = e ? e->value : def;
    if (!value) {
        *ret = NULL;
        return 0;
    }
    const char *joined = s_join (self, value);
    if (!joined) {
        cgs_errf (err, errlen, "%s: out of memory", self->path);
        return -ENOMEM;
    }
    if (e)
        e->used = true;
    *ret = joined;
    return 0;
}

int cgs_config_get_position (cgs_config_t *self, const char *section, const char *key,
                             const cgs_geo_t *frame, cgs_enu_t def, cgs_enu_t *ret, char *err,
                             size_t errlen)
{
    s_entry_t *e;
    int rc = s_lookup (self, section, key, &e, err, errlen);
    if (rc < 0)
        return rc;
    if (!e) {
        *ret = def;
        return 0;
    }
    char why[512];
    cgs_enu_t p;
    if (cgs_config_parse_position (e->value, frame, &p, why, sizeof why) < 0)
        return cgs_config_error (self, section, key, 0, err, errlen, "%s", why);
    e->used = true;
    *ret = p;
    return 0;
}

const char *cgs_config_get_nth (cgs_config_t *self, const char *section, const char *key,
                                size_t idx)
{
    s_section_t *sec = s_section (self, section);
    if (sec)
        sec->looked_at = true;
    s_entry_t *e = s_entry (self, section, key, idx);
    if (!e)
        return NULL;
    e->used = true;
    return e->value;
}

int cgs_config_require (const cgs_config_t *self, const char *section, const char *key,
                        const char *what, char *err, size_t errlen)
{
    if (cgs_config_has (self, section, key))
        return 0;
    if (*section)
        cgs_errf (err, errlen, "%s: [%s]: missing key '%s' (expected %s)", self->path, section, key,
                  what);
    else
        cgs_errf (err, errlen, "%s: missing key '%s' (expected %s)", self->path, key, what);
    return -ENOENT;
}

void cgs_config_mark_section (cgs_config_t *self, const char *section)
{
    s_section_t *sec = s_section (self, section);
    if (!sec)
        return;
    sec->looked_at = true;
    for (size_t i = 0; i < sec->count; i++)
        sec->entries[i].used = true;
}

int cgs_config_check_unused (const cgs_config_t *self, char *err, size_t errlen)
{
    // The first thing in file order nobody read: a whole section, or one key.
    const s_section_t *bad_sec = NULL;
    const s_entry_t *bad_key = NULL;
    int bad_line = INT_MAX;
    for (size_t i = 0; i < self->count; i++) {
        const s_section_t *sec = &self->sections[i];
        if (!sec->looked_at) {
            if (sec->line < bad_line) {
                bad_line = sec->line;
                bad_sec = sec;
                bad_key = sec->count ? &sec->entries[0] : NULL;
            }
            continue;
        }
        for (size_t j = 0; j < sec->count; j++) {
            if (!sec->entries[j].used && sec->entries[j].line < bad_line) {
                bad_line = sec->entries[j].line;
                bad_sec = sec;
                bad_key = &sec->entries[j];
            }
        }
    }
    if (!bad_sec)
        return 0;
    if (!*bad_sec->name)
        cgs_errf (err, errlen, "%s:%d: unknown key '%s' (before any section)", self->path, bad_line,
                  bad_key->key);
    else if (!bad_sec->looked_at)
        cgs_errf (err, errlen, "%s:%d: unknown section [%s]", self->path, bad_line, bad_sec->name);
    else
        cgs_errf (err, errlen, "%s:%d: [%s] unknown key '%s'", self->path, bad_line, bad_sec->name,
                  bad_key->key);
    return -EINVAL;
}

// --- positions ------------------------------------------------------------------

#define S_MAX_TOKENS 8

/* Whole of tok as a finite number, with an optional hemisphere letter: pos
 * (e.g. 'N') keeps the sign, neg (e.g. 'S') flips it; a letter needs an
 * unsigned number. *ret_letter says whether one was there. */
static bool s_coord (const char *tok, char pos, char neg, double *ret, bool *ret_letter)
{
    size_t n = strlen (tok);
    char buf[64];
    if (n == 0 || n >= sizeof buf)
        return false;
    memcpy (buf, tok, n + 1);
    char last = (char)toupper ((unsigned char)buf[n - 1]);
    bool letter = last == pos || last == neg;
    if (letter) {
        buf[n - 1] = '\0';
        if (!isdigit ((unsigned char)buf[0]) && buf[0] != '.')
            return false;
    }
    double v;
    if (!s_parse_double (buf, &v))
        return false;
    *ret = letter && last == neg ? -v : v;
    *ret_letter = letter;
    return true;
}

// lat lon [h] tokens as geodetic, each coordinate optionally with its hemisphere letter.
static int s_geodetic_tokens (char **tok, size_t n, const char *text, cgs_geodetic_t *ret,
                              char *why, size_t whylen)
{
    cgs_geodetic_t g = {0.0, 0.0, 0.0};
    bool letter;
    if (n < 2 || n > 3 || !s_coord (tok[0], 'N', 'S', &g.lat_deg, &letter) ||
        !s_coord (tok[1], 'E', 'W', &g.lon_deg, &letter) ||
        (n == 3 && !s_parse_double (tok[2], &g.height_m))) {
        cgs_errf (why, whylen,
                  "expected latitude and longitude in degrees and an optional height in metres "
                  "(`geo LAT LON [H]` or `LAT{N|S} LON{E|W} [H]`), got '%s'",
                  text);
        return -EINVAL;
    }
    if (g.lat_deg < -90.0 || g.lat_deg > 90.0) {
        cgs_errf (why, whylen, "latitude %.15g is outside [-90, 90] in '%s'", g.lat_deg, text);
        return -EINVAL;
    }
    if (g.lon_deg < -180.0 || g.lon_deg > 180.0) {
        cgs_errf (why, whylen, "longitude %.15g is outside [-180, 180] in '%s'", g.lon_deg, text);
        return -EINVAL;
    }
    *ret = g;
    return 0;
}

static bool s_hemisphere_token (const char *tok, char pos, char neg)
{
    double v;
    bool letter;
    return s_coord (tok, pos, neg, &v, &letter) && letter;
}

/* Any of the position forms: local metres in *ret_local (*ret_is_local true),
 * or geodetic in *ret_geo. */
static int s_parse_any (const char *text, bool *ret_is_local, cgs_enu_t *ret_local,
                        cgs_geodetic_t *ret_geo, char *why, size_t whylen)
{
    char buf[256];
    size_t len = strlen (text);
    if (len >= sizeof buf) {
        cgs_errf (why, whylen, "position too long (%zu characters)", len);
        return -EINVAL;
    }
    memcpy (buf, text, len + 1);
    char *tok[S_MAX_TOKENS];
    size_t n = 0;
    for (char *save = NULL, *t = strtok_r (buf, " \t\r\n", &save); t;
         t = strtok_r (NULL, " \t\r\n", &save)) {
        if (n == S_MAX_TOKENS)
            goto bad;
        tok[n++] = t;
    }
    if (n == 0)
        goto bad;

    // Which form: a keyword, hemisphere letters, an MGRS zone, or else local metres.
    const char *grid = NULL; // MGRS reference, when that is the form
    size_t first = 0;        // first token of local metres
    if (strcasecmp (tok[0], "local") == 0)
        first = 1;
    else if (strcasecmp (tok[0], "geo") == 0) {
        *ret_is_local = false;
        return s_geodetic_tokens (tok + 1, n - 1, text, ret_geo, why, whylen);
    } else if (strcasecmp (tok[0], "mgrs") == 0) {
        grid = text + strspn (text, " \t\r\n") + strlen ("mgrs");
    } else if ((n == 2 || n == 3) && s_hemisphere_token (tok[0], 'N', 'S') &&
               s_hemisphere_token (tok[1], 'E', 'W')) {
        *ret_is_local = false;
        return s_geodetic_tokens (tok, n, text, ret_geo, why, whylen);
    } else if (isdigit ((unsigned char)tok[0][0]) &&
               (isalpha ((unsigned char)tok[0][1]) ||
                (isdigit ((unsigned char)tok[0][1]) && isalpha ((unsigned char)tok[0][2]))))
        grid = text; // "10SEG1234567890": a zone number, then its band letter

    if (grid) {
        cgs_geodetic_t g;
        if (cgs_geo_from_mgrs (grid, &g, NULL) < 0) {
            if (grid == text)
                goto bad; // it only looked like MGRS: list every form
            cgs_errf (why, whylen,
                      "'%s' is not an MGRS reference (expected e.g. `mgrs 10SEG 12345 67890`)",
                      text);
            return -EINVAL;
        }
        *ret_is_local = false;
        *ret_geo = g;
        return 0;
    }
    cgs_enu_t p = {0.0, 0.0, 0.0};
    n -= first;
    if ((n == 2 || n == 3) && s_parse_double (tok[first], &p.e_m) &&
        s_parse_double (tok[first + 1], &p.n_m) &&
        (n == 2 || s_parse_double (tok[first + 2], &p.u_m))) {
        *ret_is_local = true;
        *ret_local = p;
        return 0;
    }
bad:
    cgs_errf (why, whylen, "expected a position as " S_FORMS ", got '%s'", text);
    return -EINVAL;
}

int cgs_config_parse_position (const char *text, const cgs_geo_t *frame, cgs_enu_t *ret, char *why,
                               size_t whylen)
{
    assert (text && ret);
    bool is_local;
    cgs_enu_t local;
    cgs_geodetic_t g;
    int rc = s_parse_any (text, &is_local, &local, &g, why, whylen);
    if (rc < 0)
        return rc;
    if (is_local) {
        *ret = local;
        return 0;
    }
    if (!frame) {
        cgs_errf (why, whylen, "'%s' is geodetic, but there is no exercise origin to place it",
                  text);
        return -EINVAL;
    }
    if (cgs_geo_geodetic_to_enu (frame, g, &local) < 0) {
        cgs_errf (why, whylen, "cannot convert '%s' to local coordinates", text);
        return -EINVAL;
    }
    *ret = local;
    return 0;
}

int cgs_config_parse_geodetic (const char *text, cgs_geodetic_t *ret, char *why, size_t whylen)
{
    assert (text && ret);
    bool is_local;
    cgs_enu_t local;
    cgs_geodetic_t g;
    int rc = s_parse_any (text, &is_local, &local, &g, why, whylen);
    if (rc < 0)
        return rc;
    if (is_local) {
        cgs_errf (why, whylen,
                  "expected a geodetic position as " S_GEO_FORMS
                  " (local metres have no meaning here), got '%s'",
                  text);
        return -EINVAL;
    }
    *ret = g;
    return 0;
}

int cgs_config_check_repeated (const cgs_config_t *self, char *err, size_t errlen)
{
    for (size_t i = 0; i < cgs_config_section_count (self); i++) {
        int again = cgs_config_section_again (self, i);
        if (again > 0) {
            cgs_errf (err, errlen, "%s:%d: [%s] given twice (first at line %d)",
                      cgs_config_path (self), again, cgs_config_section_name (self, i),
                      cgs_config_section_line (self, i));
            return -EINVAL;
        }
    }
    return 0;
}

// --- parameter tables --------------------------------------------------------------

int cgs_config_get_table (cgs_config_t *self, const cgs_config_real_t *reals, size_t nreals,
                          const cgs_config_int_t *ints, size_t nints, void *base, char *err,
                          size_t errlen)
{
    int rc = 0;
    for (size_t i = 0; i < nreals && rc == 0; i++) {
        double *field = (double *)((char *)base + reals[i].offset);
        rc = cgs_config_get_double (self, reals[i].section, reals[i].key, *field, reals[i].min,
                                    reals[i].max, field, err, errlen);
    }
    for (size_t i = 0; i < nints && rc == 0; i++) {
        int *field = (int *)((char *)base + ints[i].offset);
        long v;
        rc = cgs_config_get_int (self, ints[i].section, ints[i].key, *field, ints[i].min,
                                 ints[i].max, &v, err, errlen);
        if (rc == 0)
            *field = (int)v;
    }
    return rc;
}

bool cgs_config_table_out_of_range (const cgs_config_real_t *reals, size_t nreals,
                                    const cgs_config_int_t *ints, size_t nints, const void *base,
                                    const char **ret_section, const char **ret_key, char *msg,
                                    size_t msglen)
{
    for (size_t i = 0; i < nreals; i++) {
        double v = *(const double *)((const char *)base + reals[i].offset);
        if (!(v >= reals[i].min && v <= reals[i].max)) {
            *ret_section = reals[i].section;
            *ret_key = reals[i].key;
            snprintf (msg, msglen, "expected a number in [%g, %g], got %g", reals[i].min,
                      reals[i].max, v);
            return true;
        }
    }
    for (size_t i = 0; i < nints; i++) {
        int v = *(const int *)((const char *)base + ints[i].offset);
        if (v < ints[i].min || v > ints[i].max) {
            *ret_section = ints[i].section;
            *ret_key = ints[i].key;
            snprintf (msg, msglen, "expected an integer in [%ld, %ld], got %d", ints[i].min,
                      ints[i].max, v);
            return true;
        }
    }
    return false;
}

int cgs_config_read (const char *path, const char *text, cgs_config_read_fn *fn, void *arg,
                     char *err, size_t errlen)
{
    cgs_config_t *cfg;
    int rc = text ? cgs_config_load_string (path, text, &cfg, err, errlen)
                  : cgs_config_load (path, &cfg, err, errlen);
    if (rc < 0)
        return rc;
    rc = fn (cfg, arg, err, errlen);
    cgs_config_destroy (&cfg);
    return rc;
}
