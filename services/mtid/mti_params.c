/* mti_params — the MTI radar's parameter file, read through cgs_config over
 * the built-in defaults, every value range-checked and the whole set checked
 * for consistency.
 *
 * One table per value type says each key's section, field and range: loading
 * reads with cgs_config's typed getters from it, and mti_params_check checks
 * a struct built in code against the same table. The consistency checks name
 * the file's line of the first key they involve that the file gives (or the
 * section, or no line when the file gives none of them), so a file's error
 * reads "radar.ini:12: [processing] n: ..." and a struct's "[processing] n:
 * ...". Pure: no logging, no globals (the tables are constant). */
#include "mti_params.h"
#include "cgs_config.h"
#include "cgs_util.h"

#include <assert.h>
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#define S_C            299792458.0 // speed of light, m/s
#define S_RES_SLACK    1e-3        // range resolution may exceed c tau / 2 by this fraction
#define S_TARGET       "target"    // [target NAME]
#define S_DEFAULT_NAME "default"   // the class used for names the file does not give

// --- tables -------------------------------------------------------------------

enum {
    S_LO_OPEN = 1, // the minimum itself is out of range
    S_HI_OPEN = 2, // the maximum itself is out of range
};

// A real-valued key: the field at offset (in mti_params_t, or mti_class_t for classes).
typedef struct {
    const char *section;
    const char *key;
    size_t offset;
    double min, max;
    int open; // S_LO_OPEN | S_HI_OPEN
} s_real_t;

#define S_P(field) offsetof (mti_params_t, field)

static const s_real_t s_reals[] = {
    {"radar", "frequency_hz", S_P (frequency_hz), 1e8, 1e11, 0},
    {"radar", "prf_hz", S_P (prf_hz), 100, 1e6, 0},
    {"radar", "pulse_width_s", S_P (pulse_width_s), 1e-9, 1e-3, 0},
    {"radar", "range_resolution_m", S_P (range_resolution_m), 0.1, 10000, 0},
    {"radar", "azimuth_beamwidth_deg", S_P (azimuth_beamwidth_deg), 0.1, 90, 0},
    {"radar", "elevation_beamwidth_deg", S_P (elevation_beamwidth_deg), 0.1, 120, 0},
    {"radar", "beam_depression_deg", S_P (beam_depression_deg), -90, 90, 0},
    {"radar", "sweep_rate_dps", S_P (sweep_rate_dps), 0.1, 3600, 0},
    {"radar", "transmit_power_w", S_P (transmit_power_w), 0.001, 1e8, 0},
    {"radar", "antenna_gain_db", S_P (antenna_gain_db), 0, 60, 0},
    {"radar", "noise_figure_db", S_P (noise_figure_db), 0, 30, 0},
    {"radar", "losses_db", S_P (losses_db), 0, 40, 0},
    {"radar", "noise_temperature_k", S_P (noise_temperature_k), 1, 10000, 0},
    {"radar", "min_range_m", S_P (min_range_m), 0, 1e6, 0},
    {"radar", "max_range_m", S_P (max_range_m), 1, 1e6, 0},
    {"scan", "sector_center_deg", S_P (sector_center_deg), -360, 360, 0},
    {"scan", "sector_width_deg", S_P (sector_width_deg), 0.1, 360, 0},
    {"processing", "pfa", S_P (pfa), 0, 0.5, S_LO_OPEN | S_HI_OPEN},
    {"clutter", "gamma_db", S_P (clutter_gamma_db), -80, 10, 0},
    {"clutter", "internal_motion_mps", S_P (clutter_internal_mps), 0, 10, 0},
};

// The real-valued key of each [target NAME] section (its section is the class's).
static const s_real_t s_rcs = {S_TARGET, "rcs_m2", offsetof (mti_class_t, rcs_m2),
                               0,        1e6,      S_LO_OPEN};

enum {
    S_ANY = 0,  // any integer in range
    S_POW2 = 1, // a power of two
    S_EVEN = 2, // an even number
};

// An integer key: an int field of mti_params_t.
typedef struct {
    const char *section;
    const char *key;
    size_t offset;
    int min, max;
    int kind; // S_ANY, S_POW2, S_EVEN
} s_int_t;

static const s_int_t s_ints[] = {
    {"processing", "fft_size", S_P (fft_size), 4, MTI_FFT_MAX, S_POW2},
    {"processing", "cfar_reference_cells", S_P (ref_cells), 2, MTI_REF_CELLS_MAX, S_EVEN},
    {"processing", "cfar_guard_cells", S_P (guard_cells), 0, 16, S_ANY},
    {"processing", "m", S_P (m), 1, 64, S_ANY},
    {"processing", "n", S_P (n), 1, MTI_N_MAX, S_ANY},
};

#define S_COUNT(a) (sizeof (a) / sizeof (a)[0])

// Names an enumerated key accepts (case-insensitive), and the value each stands for.
static const char *const s_scan_names[] = {"full", "sector", NULL};
static const int s_scan_values[] = {MTI_SCAN_FULL, MTI_SCAN_SECTOR};
static const char *const s_ref_names[] = {"north", "heading", NULL};
static const int s_ref_values[] = {MTI_SECTOR_NORTH, MTI_SECTOR_HEADING};
static const char *const s_window_names[] = {"rectangular", "hann", "hamming", "blackman", NULL};
static const int s_window_values[] = {MTI_WINDOW_RECT, MTI_WINDOW_HANN, MTI_WINDOW_HAMMING,
                                      MTI_WINDOW_BLACKMAN};
static const char *const s_canceller_names[] = {"none", "two-pulse", "three-pulse", NULL};
static const int s_canceller_values[] = {MTI_CANCELLER_NONE, MTI_CANCELLER_TWO,
                                         MTI_CANCELLER_THREE};
static const char *const s_azimuth_names[] = {"beam-split", "monopulse", NULL};
static const int s_azimuth_values[] = {MTI_AZIMUTH_BEAM_SPLIT, MTI_AZIMUTH_MONOPULSE};
static const char *const s_swerling_names[] = {"0", "1", "2", "constant", "2-pulse", NULL};
static const int s_swerling_values[] = {MTI_SWERLING_0, MTI_SWERLING_1, MTI_SWERLING_2,
                                        MTI_SWERLING_0, MTI_SWERLING_2_PULSE};

int mti_swerling_parse (const char *text, mti_swerling_t *ret)
{
    for (int i = 0; text && s_swerling_names[i]; i++)
        if (strcasecmp (text, s_swerling_names[i]) == 0) {
            *ret = (mti_swerling_t)s_swerling_values[i];
            return 0;
        }
    return -EINVAL;
}

const char *mti_swerling_name (mti_swerling_t model)
{
    for (int i = 0; s_swerling_names[i]; i++)
        if (s_swerling_values[i] == (int)model)
            return s_swerling_names[i]; // the first name of each: the number's
    return "?";
}

// --- errors -------------------------------------------------------------------

typedef struct {
    cgs_config_t *cfg; // the file being read; NULL when checking a struct
    char *err;
    size_t errlen;
} s_ctx_t;

// A key an error may be about; key NULL means the section itself.
typedef struct {
    const char *section;
    const char *key;
} s_key_t;

static bool s_given (const cgs_config_t *cfg, const s_key_t *k)
{
    return k->key ? cgs_config_has (cfg, k->section, k->key)
                  : cgs_config_has_section (cfg, k->section);
}

/* An error about the first of keys (ending with {NULL}) the file gives, else
 * about the first of them: "file:line: [section] key: reason" when read from
 * a file (at the section's header when only the section is there, with no
 * line when not even that), "[section] key: reason" when checking a struct. */
static int s_fail (const s_ctx_t *c, const s_key_t *keys, const char *fmt, ...)
    __attribute__ ((format (printf, 3, 4)));
static int s_fail (const s_ctx_t *c, const s_key_t *keys, const char *fmt, ...)
{
    char msg[512];
    va_list ap;
    va_start (ap, fmt);
    vsnprintf (msg, sizeof msg, fmt, ap);
    va_end (ap);
    const s_key_t *k = &keys[0];
    for (const s_key_t *i = keys; c->cfg && i->section; i++)
        if (s_given (c->cfg, i)) {
            k = i;
            break;
        }
    const char *key = k->key;
    if (!c->cfg)
        cgs_errf (c->err, c->errlen, "[%s] %s%s%s", k->section, key ? key : "", key ? ": " : "",
                  msg);
    else if (key && cgs_config_has (c->cfg, k->section, key))
        cgs_config_error (c->cfg, k->section, key, 0, c->err, c->errlen, "%s", msg);
    else if (key)
        cgs_config_error (c->cfg, k->section, NULL, 0, c->err, c->errlen, "%s: %s", key, msg);
    else
        cgs_config_error (c->cfg, k->section, NULL, 0, c->err, c->errlen, "%s", msg);
    return -EINVAL;
}

// "[min, max]" with a parenthesis at an open end.
static const char *s_interval (const s_real_t *r, char *buf, size_t len)
{
    snprintf (buf, len, "%c%.15g, %.15g%c", r->open & S_LO_OPEN ? '(' : '[', r->min, r->max,
              r->open & S_HI_OPEN ? ')' : ']');
    return buf;
}

static bool s_real_ok (const s_real_t *r, double v)
{
    return isfinite (v) && v >= r->min && v <= r->max && !(r->open & S_LO_OPEN && v == r->min) &&
           !(r->open & S_HI_OPEN && v == r->max);
}

static bool s_int_ok (const s_int_t *d, int v)
{
    if (v < d->min || v > d->max)
        return false;
    if (d->kind == S_POW2)
        return (v & (v - 1)) == 0;
    if (d->kind == S_EVEN)
        return v % 2 == 0;
    return true;
}

static const char *s_int_what (const s_int_t *d)
{
    return d->kind == S_POW2   ? "a power of two"
           : d->kind == S_EVEN ? "an even integer"
                               : "an integer";
}

// The name value stands for in names/values, else "?".
static const char *s_enum_name (const char *const *names, const int *values, int value)
{
    for (size_t i = 0; names[i]; i++)
        if (values[i] == value)
            return names[i];
    return "?";
}

// --- reading --------------------------------------------------------------------

// The real key r of section into the field at base + r->offset, which holds its default.
static int s_get_real (s_ctx_t *c, const char *section, const s_real_t *r, void *base)
{
    double *field = (double *)((char *)base + r->offset);
    double v;
    int rc = cgs_config_get_double (c->cfg, section, r->key, *field, r->min, r->max, &v, c->err,
                                    c->errlen);
    // An open end: cgs_config's closed range would name the wrong interval, so say it here.
    bool open_fail =
        r->open && cgs_config_count (c->cfg, section, r->key) == 1 && (rc < 0 || !s_real_ok (r, v));
    if (open_fail) {
        const char *raw = "";
        cgs_config_get_string (c->cfg, section, r->key, "", &raw, NULL, 0);
        char range[80];
        return cgs_config_error (c->cfg, section, r->key, 0, c->err, c->errlen,
                                 "expected a number in %s, got '%s'",
                                 s_interval (r, range, sizeof range), raw);
    }
    if (rc < 0)
        return rc;
    *field = v;
    return 0;
}

static int s_get_int (s_ctx_t *c, const s_int_t *d, mti_params_t *p)
{
    int *field = (int *)((char *)p + d->offset);
    long v;
    int rc = cgs_config_get_int (c->cfg, d->section, d->key, *field, d->min, d->max, &v, c->err,
                                 c->errlen);
    if (rc < 0)
        return rc;
    if (!s_int_ok (d, (int)v)) {
        const char *raw = "";
        cgs_config_get_string (c->cfg, d->section, d->key, "", &raw, NULL, 0);
        return cgs_config_error (c->cfg, d->section, d->key, 0, c->err, c->errlen,
                                 "expected %s in [%d, %d], got '%s'", s_int_what (d), d->min,
                                 d->max, raw);
    }
    *field = (int)v;
    return 0;
}

// An enumerated key: *ret holds the default on entry and the value on success.
static int s_get_enum (s_ctx_t *c, const char *section, const char *key, const char *const *names,
                       const int *values, int *ret)
{
    int def = 0, idx;
    for (int i = 0; names[i]; i++)
        if (values[i] == *ret) {
            def = i;
            break;
        }
    int rc = cgs_config_get_enum (c->cfg, section, key, names, def, &idx, c->err, c->errlen);
    if (rc < 0)
        return rc;
    *ret = values[idx];
    return 0;
}

static bool s_name_ok (const char *s)
{
    size_t n = strlen (s);
    if (n == 0 || n > MTI_CLASS_NAME_MAX)
        return false;
    for (size_t i = 0; i < n; i++)
        if (!isalnum ((unsigned char)s[i]) && !strchr ("_.-", s[i]))
            return false;
    return true;
}

// The NAME of a "target NAME" section ("" for "target"), NULL for other sections.
static const char *s_target_name (const char *section)
{
    size_t n = strlen (S_TARGET);
    if (strncmp (section, S_TARGET, n) != 0 || (section[n] != ' ' && section[n] != '\0'))
        return NULL;
    return section[n] ? section + n + 1 : section + n;
}

#define S_STR(x)    S_STR2 (x)
#define S_STR2(x)   #x
#define S_NAME_RULE "1 to " S_STR (MTI_CLASS_NAME_MAX) " letters, digits, '_', '.' or '-'"

/* A [target NAME] section: replaces the values it gives of the class of that
 * name, or adds the class (which then needs rcs_m2). */
static int s_target (s_ctx_t *c, const char *section, const char *name, mti_params_t *p)
{
    if (!s_name_ok (name))
        return cgs_config_error (c->cfg, section, NULL, 0, c->err, c->errlen,
                                 "expected [target NAME] with NAME " S_NAME_RULE ", got '%s'",
                                 name);
    mti_class_t cls = {.rcs_m2 = 0, .swerling = MTI_SWERLING_2};
    size_t i = 0;
    while (i < p->class_count && strcmp (p->classes[i].name, name) != 0)
        i++;
    if (i < p->class_count)
        cls = p->classes[i];
    else if (p->class_count == MTI_CLASS_MAX)
        return cgs_config_error (c->cfg, section, NULL, 0, c->err, c->errlen,
                                 "too many classes (at most %d, the built-in ones included)",
                                 MTI_CLASS_MAX);
    else if (!cgs_config_has (c->cfg, section, s_rcs.key))
        return cgs_config_error (c->cfg, section, NULL, 0, c->err, c->errlen,
                                 "missing key 'rcs_m2' (a new class needs its mean radar "
                                 "cross-section, m²)");
    snprintf (cls.name, sizeof cls.name, "%s", name);
    int swerling = cls.swerling;
    int rc;
    if ((rc = s_get_real (c, section, &s_rcs, &cls)) < 0 ||
        (rc = s_get_enum (c, section, "swerling", s_swerling_names, s_swerling_values, &swerling)) <
            0)
        return rc;
    cls.swerling = (mti_swerling_t)swerling;
    p->classes[i] = cls;
    if (i == p->class_count)
        p->class_count++;
    return 0;
}

static int s_check (const s_ctx_t *c, const mti_params_t *p);

// Everything in the file over p (the defaults), then the checks.
static int s_read (s_ctx_t *c, mti_params_t *p)
{
    int rc = cgs_config_check_repeated (c->cfg, c->err, c->errlen);
    for (size_t i = 0; i < S_COUNT (s_reals) && rc == 0; i++)
        rc = s_get_real (c, s_reals[i].section, &s_reals[i], p);
    for (size_t i = 0; i < S_COUNT (s_ints) && rc == 0; i++)
        rc = s_get_int (c, &s_ints[i], p);
    int scan = p->scan_mode, ref = p->sector_ref, window = p->window, canceller = p->canceller,
        azimuth = p->azimuth;
    if (rc == 0)
        rc = s_get_enum (c, "scan", "mode", s_scan_names, s_scan_values, &scan);
    if (rc == 0)
        rc = s_get_enum (c, "scan", "sector_reference", s_ref_names, s_ref_values, &ref);
    if (rc == 0)
        rc = s_get_enum (c, "processing", "window", s_window_names, s_window_values, &window);
    if (rc == 0)
        rc = s_get_enum (c, "processing", "canceller", s_canceller_names, s_canceller_values,
                         &canceller);
    if (rc == 0)
        rc = s_get_enum (c, "processing", "azimuth", s_azimuth_names, s_azimuth_values, &azimuth);
    if (rc < 0)
        return rc;
    p->azimuth = (mti_azimuth_t)azimuth;
    p->scan_mode = (mti_scan_mode_t)scan;
    p->sector_ref = (mti_sector_ref_t)ref;
    p->window = (mti_window_t)window;
    p->canceller = (mti_canceller_t)canceller;
    for (size_t i = 0; i < cgs_config_section_count (c->cfg) && rc == 0; i++) {
        const char *section = cgs_config_section_name (c->cfg, i);
        const char *name = s_target_name (section);
        if (name)
            rc = s_target (c, section, name, p);
    }
    if (rc == 0)
        rc = cgs_config_check_unused (c->cfg, c->err, c->errlen);
    if (rc == 0)
        rc = s_check (c, p);
    return rc;
}

// --- checks ---------------------------------------------------------------------

static int s_check_classes (const s_ctx_t *c, const mti_params_t *p)
{
    if (p->class_count < 1 || p->class_count > MTI_CLASS_MAX)
        return s_fail (c, (const s_key_t[]){{"target NAME", NULL}, {NULL, NULL}},
                       "expected 1 to %d radar cross-section classes, got %zu", MTI_CLASS_MAX,
                       p->class_count);
    for (size_t i = 0; i < p->class_count; i++) {
        const mti_class_t *k = &p->classes[i];
        char section[sizeof S_TARGET + MTI_CLASS_NAME_MAX + 2];
        bool terminated = memchr (k->name, '\0', sizeof k->name) != NULL;
        snprintf (section, sizeof section, "%s %.*s", S_TARGET, MTI_CLASS_NAME_MAX, k->name);
        if (!terminated || !s_name_ok (k->name))
            return s_fail (c, (const s_key_t[]){{section, NULL}, {NULL, NULL}},
                           "expected a class name of " S_NAME_RULE);
        for (size_t j = 0; j < i; j++)
            if (strcmp (p->classes[j].name, k->name) == 0)
                return s_fail (c, (const s_key_t[]){{section, NULL}, {NULL, NULL}},
                               "class given twice (classes %zu and %zu)", j, i);
        char range[80];
        if (!s_real_ok (&s_rcs, k->rcs_m2))
            return s_fail (c, (const s_key_t[]){{section, s_rcs.key}, {NULL, NULL}},
                           "expected a number in %s, got %.15g",
                           s_interval (&s_rcs, range, sizeof range), k->rcs_m2);
        if (k->swerling < MTI_SWERLING_0 || k->swerling > MTI_SWERLING_2_PULSE)
            return s_fail (c, (const s_key_t[]){{section, "swerling"}, {NULL, NULL}},
                           "expected 0, 1, 2 or 2-pulse, got %d", (int)k->swerling);
    }
    return 0;
}

// Each value in its range, each enumeration one of its values.
static int s_check_values (const s_ctx_t *c, const mti_params_t *p)
{
    char range[80];
    for (size_t i = 0; i < S_COUNT (s_reals); i++) {
        const s_real_t *r = &s_reals[i];
        double v = *(const double *)((const char *)p + r->offset);
        if (!s_real_ok (r, v))
            return s_fail (c, (const s_key_t[]){{r->section, r->key}, {NULL, NULL}},
                           "expected a number in %s, got %.15g",
                           s_interval (r, range, sizeof range), v);
    }
    for (size_t i = 0; i < S_COUNT (s_ints); i++) {
        const s_int_t *d = &s_ints[i];
        int v = *(const int *)((const char *)p + d->offset);
        if (!s_int_ok (d, v))
            return s_fail (c, (const s_key_t[]){{d->section, d->key}, {NULL, NULL}},
                           "expected %s in [%d, %d], got %d", s_int_what (d), d->min, d->max, v);
    }
    struct {
        const char *section, *key;
        const char *const *names;
        const int *values;
        int value;
    } enums[] = {
        {"scan", "mode", s_scan_names, s_scan_values, (int)p->scan_mode},
        {"scan", "sector_reference", s_ref_names, s_ref_values, (int)p->sector_ref},
        {"processing", "window", s_window_names, s_window_values, (int)p->window},
        {"processing", "canceller", s_canceller_names, s_canceller_values, (int)p->canceller},
        {"processing", "azimuth", s_azimuth_names, s_azimuth_values, (int)p->azimuth},
    };
    for (size_t i = 0; i < S_COUNT (enums); i++)
        if (strcmp (s_enum_name (enums[i].names, enums[i].values, enums[i].value), "?") == 0)
            return s_fail (c, (const s_key_t[]){{enums[i].section, enums[i].key}, {NULL, NULL}},
                           "%d is not a value of this enumeration", enums[i].value);
    return s_check_classes (c, p);
}

static int s_check (const s_ctx_t *c, const mti_params_t *p)
{
    int rc = s_check_values (c, p);
    if (rc < 0)
        return rc;
    if (p->min_range_m >= p->max_range_m)
        return s_fail (
            c, (const s_key_t[]){{"radar", "min_range_m"}, {"radar", "max_range_m"}, {NULL, NULL}},
            "min_range_m %.15g must be below max_range_m %.15g", p->min_range_m, p->max_range_m);
    double unambiguous_m = S_C / (2 * p->prf_hz);
    if (p->max_range_m > unambiguous_m)
        return s_fail (
            c, (const s_key_t[]){{"radar", "max_range_m"}, {"radar", "prf_hz"}, {NULL, NULL}},
            "max_range_m %.15g is beyond the unambiguous range c / (2 prf_hz) = %.0f m "
            "at prf_hz %.15g",
            p->max_range_m, unambiguous_m, p->prf_hz);
    double pulse_m = S_C * p->pulse_width_s / 2;
    if (p->range_resolution_m > pulse_m * (1 + S_RES_SLACK))
        return s_fail (c,
                       (const s_key_t[]){{"radar", "range_resolution_m"},
                                         {"radar", "pulse_width_s"},
                                         {NULL, NULL}},
                       "range_resolution_m %.15g is coarser than the pulse gives, c * "
                       "pulse_width_s / 2 = %.4g m with pulse_width_s %.15g (finer is allowed: "
                       "pulse compression)",
                       p->range_resolution_m, pulse_m, p->pulse_width_s);
    if (p->sector_width_deg < p->azimuth_beamwidth_deg)
        return s_fail (c,
                       (const s_key_t[]){{"scan", "sector_width_deg"},
                                         {"radar", "azimuth_beamwidth_deg"},
                                         {NULL, NULL}},
                       "sector_width_deg %.15g is narrower than one beam (azimuth_beamwidth_deg "
                       "%.15g)",
                       p->sector_width_deg, p->azimuth_beamwidth_deg);
    if (p->m > p->n)
        return s_fail (c, (const s_key_t[]){{"processing", "m"}, {"processing", "n"}, {NULL, NULL}},
                       "m %d is more than n %d (m crossings of n coherent intervals)", p->m, p->n);
    double dwell_s = mti_params_dwell_s (p);
    long have = (long)floor (p->prf_hz * dwell_s + 1e-9);
    int cpi = mti_params_cpi_pulses (p);
    long need = (long)p->n * cpi;
    if (need > have)
        return s_fail (c,
                       (const s_key_t[]){{"processing", "n"},
                                         {"processing", "fft_size"},
                                         {"processing", "canceller"},
                                         {"radar", "sweep_rate_dps"},
                                         {"radar", "azimuth_beamwidth_deg"},
                                         {"radar", "prf_hz"},
                                         {NULL, NULL}},
                       "n = %d coherent intervals of %d pulses (fft_size %d, canceller %s) need "
                       "%ld pulses, but a dwell has only %ld (azimuth_beamwidth_deg %.15g / "
                       "sweep_rate_dps %.15g = %.4g s at prf_hz %.15g)",
                       p->n, cpi, p->fft_size,
                       s_enum_name (s_canceller_names, s_canceller_values, (int)p->canceller), need,
                       have, p->azimuth_beamwidth_deg, p->sweep_rate_dps, dwell_s, p->prf_hz);
    return 0;
}

// --- public -----------------------------------------------------------------------

void mti_params_defaults (mti_params_t *p)
{
    assert (p);
    static const mti_class_t classes[] = {
        {"vehicle", 10, MTI_SWERLING_2}, {"tank", 20, MTI_SWERLING_2},
        {"truck", 15, MTI_SWERLING_2},   {"person", 1, MTI_SWERLING_2},
        {"car", 5, MTI_SWERLING_2},      {"reflector", 10, MTI_SWERLING_0},
    };
    *p = (mti_params_t){
        .frequency_hz = 16e9,
        .prf_hz = 5000,
        .pulse_width_s = 200e-9,
        .range_resolution_m = 30,
        .azimuth_beamwidth_deg = 3,
        .elevation_beamwidth_deg = 60,
        .beam_depression_deg = 30,
        .sweep_rate_dps = 36,
        .transmit_power_w = 20000,
        .antenna_gain_db = 24,
        .noise_figure_db = 4,
        .losses_db = 5,
        .noise_temperature_k = 290,
        .min_range_m = 500,
        .max_range_m = 20000,
        .scan_mode = MTI_SCAN_FULL,
        .sector_center_deg = 0,
        .sector_width_deg = 90,
        .sector_ref = MTI_SECTOR_NORTH,
        .fft_size = 64,
        .window = MTI_WINDOW_HAMMING,
        .canceller = MTI_CANCELLER_TWO,
        .ref_cells = 16,
        .guard_cells = 2,
        .pfa = 1e-4,
        .m = 2,
        .n = 4,
        .azimuth = MTI_AZIMUTH_MONOPULSE,
        .clutter_gamma_db = -15,
        .clutter_internal_mps = 0.1,
    };
    memcpy (p->classes, classes, sizeof classes);
    p->class_count = S_COUNT (classes);
}

// Read cfg over the defaults into *p (arg).
static int s_load (cgs_config_t *cfg, void *arg, char *err, size_t errlen)
{
    mti_params_t *p = arg, q;
    mti_params_defaults (&q);
    s_ctx_t c = {.cfg = cfg, .err = err, .errlen = errlen};
    int rc = s_read (&c, &q);
    if (rc == 0)
        *p = q;
    return rc;
}

int mti_params_load (const char *path, mti_params_t *p, char *err, size_t errlen)
{
    assert (path && p);
    return cgs_config_read (path, NULL, s_load, p, err, errlen);
}

int mti_params_load_string (const char *name, const char *text, mti_params_t *p, char *err,
                            size_t errlen)
{
    assert (name && text && p);
    return cgs_config_read (name, text, s_load, p, err, errlen);
}

int mti_params_check (const mti_params_t *p, char *err, size_t errlen)
{
    assert (p);
    s_ctx_t c = {.cfg = NULL, .err = err, .errlen = errlen};
    return s_check (&c, p);
}

double mti_params_wavelength_m (const mti_params_t *p)
{
    return S_C / p->frequency_hz;
}

int mti_params_cpi_pulses (const mti_params_t *p)
{
    return p->fft_size + (int)p->canceller - 1;
}

double mti_params_dwell_s (const mti_params_t *p)
{
    return p->azimuth_beamwidth_deg / p->sweep_rate_dps;
}

const mti_class_t *mti_params_class (const mti_params_t *p, const char *name, bool *ret_known)
{
    const mti_class_t *fallback = NULL;
    for (size_t i = 0; i < p->class_count; i++) {
        if (name && strcmp (p->classes[i].name, name) == 0) {
            if (ret_known)
                *ret_known = true;
            return &p->classes[i];
        }
        if (!fallback && strcmp (p->classes[i].name, S_DEFAULT_NAME) == 0)
            fallback = &p->classes[i];
    }
    if (ret_known)
        *ret_known = false;
    if (!fallback && p->class_count > 0)
        fallback = &p->classes[0];
    return fallback;
}
