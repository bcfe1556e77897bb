/* cgs_scenario — reads a scenario file (terrain, UAVs, ground vehicles,
 * operator script, service settings) through cgs_config into the plain
 * cgs_scenario_t the service reads. Each getter checks its value's range
 * and names file and line; what cgs_config cannot see (a section header given
 * twice, a name or id used twice, a route too short) is checked here with the
 * same message shape. Pure: no logging, no globals. */
#include "cgs_scenario.h"
#include "cgs_config.h"
#include "cgs_util.h"

#include <assert.h>
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#define S_MAX_FILE_BYTES (64u << 20) // a scenario larger than this is refused
#define S_MAX_RANGE_M    200000.0    // positions farther from the origin are refused
#define S_MAX_ID         65534       // DIS entity ids 1..65534 (0 and 65535 are reserved)
#define S_MAX_NODES      (1 << 26)   // cgs_terrain's grid limit
#define S_GRAVITY        9.80665
#define S_SPEED_MIN      0.5  // ground vehicle speeds, m/s
#define S_SPEED_MAX      40.0 // about 145 km/h
#define S_RCS_MAX        31   // characters in a radar cross-section class name
#define S_HALT_MAX_S     3600 // longest halt on a route point, seconds

// Everything the parser passes around.
typedef struct {
    cgs_config_t *cfg;
    const cgs_geo_t *frame;
    uint64_t seed; // the exercise seed
    cgs_scenario_t *sc;
    char *err;
    size_t errlen;
} s_ctx_t;

// --- small helpers ------------------------------------------------------------

static char *s_strdup (const char *s)
{
    return strdup (s ? s : "");
}

static int s_nomem (s_ctx_t *c)
{
    cgs_errf (c->err, c->errlen, "%s: out of memory", cgs_config_path (c->cfg));
    return -ENOMEM;
}

// An error about a key when the file has it, else about the section (at its header line).
static int s_key_error (s_ctx_t *c, const char *sec, const char *key, const char *fmt, ...)
    __attribute__ ((format (printf, 4, 5)));
static int s_key_error (s_ctx_t *c, const char *sec, const char *key, const char *fmt, ...)
{
    char msg[512];
    va_list ap;
    va_start (ap, fmt);
    vsnprintf (msg, sizeof msg, fmt, ap);
    va_end (ap);
    if (cgs_config_has (c->cfg, sec, key))
        return cgs_config_error (c->cfg, sec, key, 0, c->err, c->errlen, "%s", msg);
    return cgs_config_error (c->cfg, sec, NULL, 0, c->err, c->errlen, "%s: %s", key, msg);
}

// "file:line: [sec] missing key 'key' (expected what)", at the section's header.
static int s_missing (s_ctx_t *c, const char *sec, const char *key, const char *what)
{
    return cgs_config_error (c->cfg, sec, NULL, 0, c->err, c->errlen,
                             "missing key '%s' (expected %s)", key, what);
}

// Whole of s as a finite number.
static bool s_number (const char *s, double *ret)
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

// Whole of s as an unsigned integer <= max.
static bool s_unsigned (const char *s, unsigned long max, unsigned long *ret)
{
    if (!isdigit ((unsigned char)*s))
        return false;
    char *end;
    errno = 0;
    unsigned long v = strtoul (s, &end, 10);
    if (*end || errno == ERANGE || v > max)
        return false;
    *ret = v;
    return true;
}

// s with leading and trailing blanks removed, in place.
static char *s_trim (char *s)
{
    while (isspace ((unsigned char)*s))
        s++;
    size_t n = strlen (s);
    while (n > 0 && isspace ((unsigned char)s[n - 1]))
        s[--n] = '\0';
    return s;
}

static bool s_name_ok (const char *s, size_t max)
{
    size_t n = strlen (s);
    if (n == 0 || n > max)
        return false;
    for (size_t i = 0; i < n; i++)
        if (!isalnum ((unsigned char)s[i]) && !strchr ("_.-", s[i]))
            return false;
    return true;
}

uint64_t cgs_scenario_vehicle_seed (uint64_t exercise_seed, uint32_t id)
{
    // Output number id of splitmix64 (Steele, Lea and Flood 2014) seeded with the exercise seed.
    uint64_t z = exercise_seed + 0x9E3779B97F4A7C15ull * (uint64_t)id;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

// --- typed values not in cgs_config ---------------------------------------------

#define S_DIS_FORMS                                                                                \
    "seven integers `kind domain country category subcategory specific extra` (country "           \
    "0..65535, the others 0..255)"

// A DIS entity type from its seven numbers; def when the key is absent.
static int s_get_dis_type (s_ctx_t *c, const char *sec, const char *key, cgs_dis_type_t def,
                           cgs_dis_type_t *ret)
{
    const char *value;
    int rc = cgs_config_get_string (c->cfg, sec, key, NULL, &value, c->err, c->errlen);
    if (rc < 0)
        return rc;
    if (!value) {
        *ret = def;
        return 0;
    }
    char buf[128];
    unsigned long v[7];
    size_t n = 0;
    bool ok = strlen (value) < sizeof buf;
    if (ok) {
        strcpy (buf, value);
        char *save = NULL;
        for (char *t = strtok_r (buf, " \t", &save); t && ok; t = strtok_r (NULL, " \t", &save)) {
            ok = n < 7 && s_unsigned (t, n == 2 ? 65535 : 255, &v[n]);
            n++;
        }
    }
    if (!ok || n != 7)
        return cgs_config_error (c->cfg, sec, key, 0, c->err, c->errlen,
                                 "expected " S_DIS_FORMS ", got '%s'", value);
    *ret = (cgs_dis_type_t){(uint8_t)v[0], (uint8_t)v[1], (uint16_t)v[2], (uint8_t)v[3],
                            (uint8_t)v[4], (uint8_t)v[5], (uint8_t)v[6]};
    return 0;
}

// A DIS marking: 1..11 printable ASCII characters; def when absent (cut to 11).
static int s_get_marking (s_ctx_t *c, const char *sec, const char *def, char *ret)
{
    const char *value;
    int rc = cgs_config_get_string (c->cfg, sec, "marking", NULL, &value, c->err, c->errlen);
    if (rc < 0)
        return rc;
    if (!value) {
        snprintf (ret, CGS_MARKING_MAX + 1, "%s", def);
        return 0;
    }
    size_t n = strlen (value);
    bool ok = n >= 1 && n <= CGS_MARKING_MAX;
    for (size_t i = 0; ok && i < n; i++)
        ok = value[i] >= 0x20 && value[i] <= 0x7E;
    if (!ok)
        return cgs_config_error (c->cfg, sec, "marking", 0, c->err, c->errlen,
                                 "expected 1 to %d printable ASCII characters, got '%s'",
                                 CGS_MARKING_MAX, value);
    memcpy (ret, value, n + 1);
    return 0;
}

// Position p (read from the idx-th `key`) must be within S_MAX_RANGE_M of the origin.
static int s_check_range (s_ctx_t *c, const char *sec, const char *key, size_t idx, cgs_enu_t p)
{
    double d = hypot (p.e_m, p.n_m);
    if (d <= S_MAX_RANGE_M)
        return 0;
    return cgs_config_error (c->cfg, sec, key, idx, c->err, c->errlen,
                             "position is %.0f km from the exercise origin (at most %.0f km)",
                             d / 1000.0, S_MAX_RANGE_M / 1000.0);
}

// A position, required or with a default, within range.
static int s_get_position (s_ctx_t *c, const char *sec, const char *key, const cgs_enu_t *def,
                           cgs_enu_t *ret)
{
    if (!def && !cgs_config_has (c->cfg, sec, key))
        return s_missing (c, sec, key, "a position");
    cgs_enu_t p;
    int rc = cgs_config_get_position (c->cfg, sec, key, c->frame, def ? *def : (cgs_enu_t){0}, &p,
                                      c->err, c->errlen);
    if (rc < 0)
        return rc;
    if (cgs_config_has (c->cfg, sec, key) && (rc = s_check_range (c, sec, key, 0, p)) < 0)
        return rc;
    *ret = p;
    return 0;
}

static int s_get_double (s_ctx_t *c, const char *sec, const char *key, double def, double min,
                         double max, double *ret)
{
    return cgs_config_get_double (c->cfg, sec, key, def, min, max, ret, c->err, c->errlen);
}

// --- sections -------------------------------------------------------------------

// The name after "uav " or "vehicle " in a section name, checked; NULL when not that type.
static const char *s_entity_name (const char *section, const char *type)
{
    size_t n = strlen (type);
    if (strncmp (section, type, n) != 0 || (section[n] != ' ' && section[n] != '\0'))
        return NULL;
    return section[n] ? section + n + 1 : section + n;
}

// --- terrain --------------------------------------------------------------------

/* [terrain]'s woods, procedural over either kind of terrain. */
static int s_vegetation (s_ctx_t *c)
{
    const char *sec = "terrain";
    cgs_vegetation_t *v = &c->sc->terrain.vegetation;
    cgs_vegetation_defaults (v);
    int rc;
    if ((rc = cgs_config_get_uint64 (c->cfg, sec, "vegetation_seed",
                                     cgs_scenario_vehicle_seed (c->seed, 0), &v->seed, c->err,
                                     c->errlen)) < 0 ||
        (rc = s_get_double (c, sec, "vegetation_cover", v->cover, 0, 1, &v->cover)) < 0 ||
        (rc = s_get_double (c, sec, "canopy_height_m", v->canopy_m, 0.5, 100, &v->canopy_m)) < 0 ||
        (rc = s_get_double (c, sec, "vegetation_feature_m", v->feature_m, 30, 1e5, &v->feature_m)) <
            0)
        return rc;
    return 0;
}

static int s_terrain (s_ctx_t *c)
{
    static const char *const fbm_keys[] = {"seed",      "size_m",  "relief_m",    "base_height_m",
                                           "feature_m", "octaves", "persistence", NULL};
    const char *sec = "terrain";
    cgs_terrain_spec_t *t = &c->sc->terrain;
    cgs_terrain_fbm_defaults (&t->fbm);
    t->fbm.seed = c->seed;
    int rc = s_vegetation (c);
    if (rc < 0)
        return rc;
    if (cgs_config_has (c->cfg, sec, "dem")) {
        const char *path;
        t->source = CGS_TERRAIN_DEM;
        if ((rc = cgs_config_get_path (c->cfg, sec, "dem", NULL, &path, c->err, c->errlen)) < 0)
            return rc;
        if (!*path)
            return cgs_config_error (c->cfg, sec, "dem", 0, c->err, c->errlen,
                                     "expected the path of a DEM file, got ''");
        if (access (path, R_OK) < 0)
            return cgs_config_error (c->cfg, sec, "dem", 0, c->err, c->errlen, "%s: %s", path,
                                     strerror (errno));
        if (!(t->dem_path = s_strdup (path)))
            return s_nomem (c);
        for (size_t i = 0; fbm_keys[i]; i++)
            if (cgs_config_has (c->cfg, sec, fbm_keys[i]))
                return cgs_config_error (c->cfg, sec, fbm_keys[i], 0, c->err, c->errlen,
                                         "applies to procedural terrain only, not with `dem =`");
        if ((rc = s_get_double (c, sec, "resolution_m", 0, 0, 10000, &t->resolution_m)) < 0 ||
            (rc = s_get_double (c, sec, "half_extent_m", 10000, 0, 1e6, &t->half_extent_m)) < 0)
            return rc;
        return 0;
    }
    if (cgs_config_has (c->cfg, sec, "half_extent_m"))
        return cgs_config_error (
            c->cfg, sec, "half_extent_m", 0, c->err, c->errlen,
            "applies to a DEM only (`dem =`); procedural terrain takes size_m");
    t->source = CGS_TERRAIN_FBM;
    cgs_terrain_fbm_t *f = &t->fbm;
    long octaves;
    if ((rc = cgs_config_get_uint64 (c->cfg, sec, "seed", c->seed, &f->seed, c->err, c->errlen)) <
            0 ||
        (rc = s_get_double (c, sec, "size_m", f->size_m, 200, 400000, &f->size_m)) < 0 ||
        (rc = s_get_double (c, sec, "resolution_m", f->resolution_m, 1, 1000, &f->resolution_m)) <
            0 ||
        (rc = s_get_double (c, sec, "relief_m", f->relief_m, 0, 5000, &f->relief_m)) < 0 ||
        (rc = s_get_double (c, sec, "base_height_m", f->base_height_m, -500, 9000,
                            &f->base_height_m)) < 0 ||
        (rc = s_get_double (c, sec, "feature_m", f->feature_m, 10, 1e6, &f->feature_m)) < 0 ||
        (rc = cgs_config_get_int (c->cfg, sec, "octaves", f->octaves, 1, 16, &octaves, c->err,
                                  c->errlen)) < 0 ||
        (rc = s_get_double (c, sec, "persistence", f->persistence, 0.01, 1, &f->persistence)) < 0)
        return rc;
    f->octaves = (int)octaves;
    double nodes = floor (f->size_m / f->resolution_m + 1e-9) + 1;
    if (nodes * nodes > (double)S_MAX_NODES)
        return s_key_error (
            c, sec, cgs_config_has (c->cfg, sec, "resolution_m") ? "resolution_m" : "size_m",
            "size_m %.15g / resolution_m %.15g gives %.0f x %.0f grid nodes, "
            "more than 2^26",
            f->size_m, f->resolution_m, nodes, nodes);
    return 0;
}

// With procedural terrain, route points must lie on it.
static int s_on_terrain (s_ctx_t *c, const char *sec, size_t idx, cgs_enu_t p)
{
    const cgs_terrain_spec_t *t = &c->sc->terrain;
    if (t->source != CGS_TERRAIN_FBM)
        return 0;
    double half = 0.5 * t->fbm.size_m;
    if (fabs (p.e_m) <= half && fabs (p.n_m) <= half)
        return 0;
    return cgs_config_error (c->cfg, sec, "point", idx, c->err, c->errlen,
                             "(%.0f, %.0f) is off the procedural terrain, a %.15g m square "
                             "about the origin",
                             p.e_m, p.n_m, t->fbm.size_m);
}

// --- entity ids -----------------------------------------------------------------

typedef struct {
    const char *section;
    uint32_t *id; // where the entity's id goes
} s_entity_t;

/* Ids: those given with `id =` first (each once), then 1, 2, ... in order
 * (UAVs, then vehicles, each in file order), skipping the ones given. */
static int s_assign_ids (s_ctx_t *c, s_entity_t *ents, size_t n)
{
    long *given = calloc (n ? n : 1, sizeof *given);
    if (!given)
        return s_nomem (c);
    int rc = 0;
    for (size_t i = 0; i < n && rc == 0; i++) {
        rc = cgs_config_get_int (c->cfg, ents[i].section, "id", 0, 1, S_MAX_ID, &given[i], c->err,
                                 c->errlen);
        for (size_t j = 0; j < i && rc == 0 && given[i]; j++)
            if (given[j] == given[i])
                rc = cgs_config_error (c->cfg, ents[i].section, "id", 0, c->err, c->errlen,
                                       "%ld is already the id of [%s] (line %d)", given[i],
                                       ents[j].section,
                                       cgs_config_line (c->cfg, ents[j].section, "id", 0));
    }
    long next = 1;
    for (size_t i = 0; i < n && rc == 0; i++) {
        if (given[i]) {
            *ents[i].id = (uint32_t)given[i];
            continue;
        }
        for (bool taken = true; taken; next++) {
            taken = false;
            for (size_t j = 0; j < n && !taken; j++)
                taken = given[j] == next;
            if (!taken)
                break;
        }
        if (next > S_MAX_ID) {
            rc = cgs_config_error (c->cfg, ents[i].section, NULL, 0, c->err, c->errlen,
                                   "no entity id left (at most %d entities)", S_MAX_ID);
            break;
        }
        *ents[i].id = (uint32_t)next++;
    }
    free (given);
    return rc;
}

// --- UAVs -----------------------------------------------------------------------

static int s_uav (s_ctx_t *c, const char *sec, cgs_scenario_uav_t *u)
{
    static const char *const directions[] = {"clockwise", "anticlockwise", "counterclockwise",
                                             NULL};
    static const char *const stares[] = {"off", "target", NULL};
    const cgs_dis_type_t uav_type = {1, 2, 225, 50, 0, 0, 0}; // platform, air, USA, unmanned
    int rc, dir, stare;
    const char *path;
    if ((rc = s_get_marking (c, sec, u->name, u->marking)) < 0 ||
        (rc = s_get_dis_type (c, sec, "dis_type", uav_type, &u->dis_type)) < 0 ||
        (rc = s_get_position (c, sec, "position", NULL, &u->position)) < 0 ||
        (rc = s_get_double (c, sec, "altitude_agl_m", 1200, 50, 10000, &u->altitude_agl_m)) < 0 ||
        (rc = s_get_double (c, sec, "airspeed_mps", 35, 10, 120, &u->airspeed_mps)) < 0 ||
        (rc = s_get_double (c, sec, "heading_deg", 0, 0, 360, &u->heading_deg)) < 0 ||
        (rc = s_get_position (c, sec, "loiter_center", &u->position, &u->loiter_center)) < 0 ||
        (rc = s_get_double (c, sec, "loiter_radius_m", 1500, 200, 20000, &u->loiter_radius_m)) <
            0 ||
        (rc = cgs_config_get_enum (c->cfg, sec, "loiter_direction", directions, 0, &dir, c->err,
                                   c->errlen)) < 0 ||
        (rc = s_get_double (c, sec, "standoff_m", 1000, 0, 1e5, &u->standoff_m)) < 0 ||
        (rc = s_get_double (c, sec, "bank_limit_deg", 30, 5, 60, &u->bank_limit_deg)) < 0 ||
        (rc = s_get_double (c, sec, "climb_rate_mps", 5, 0.5, 30, &u->climb_rate_mps)) < 0 ||
        (rc = s_get_double (c, sec, "airspeed_min_mps", fmin (20, u->airspeed_mps), 10, 120,
                            &u->airspeed_min_mps)) < 0 ||
        (rc = s_get_double (c, sec, "airspeed_max_mps", fmax (60, u->airspeed_mps), 10, 120,
                            &u->airspeed_max_mps)) < 0 ||
        (rc = s_get_double (c, sec, "sensor_depression_deg", 45, 0, 90,
                            &u->sensor_depression_deg)) < 0 ||
        (rc = s_get_double (c, sec, "sensor_hfov_deg", 10, 0.1, 120, &u->sensor_hfov_deg)) < 0 ||
        (rc = s_get_double (c, sec, "sensor_vfov_deg", 7.5, 0.1, 120, &u->sensor_vfov_deg)) < 0 ||
        (rc = cgs_config_get_bool (c->cfg, sec, "sensor_stabilized", false, &u->sensor_stabilized,
                                   c->err, c->errlen)) < 0 ||
        (rc = cgs_config_get_enum (c->cfg, sec, "sensor_stare", stares, 0, &stare, c->err,
                                   c->errlen)) < 0 ||
        (rc = s_get_double (c, sec, "sensor_depression_min_deg", fmin (5, u->sensor_depression_deg),
                            0, 90, &u->sensor_depression_min_deg)) < 0 ||
        (rc =
             s_get_double (c, sec, "sensor_depression_max_deg", fmax (89, u->sensor_depression_deg),
                           0, 90, &u->sensor_depression_max_deg)) < 0 ||
        (rc = s_get_double (c, sec, "sensor_hfov_min_deg", fmin (1, u->sensor_hfov_deg), 0.1, 120,
                            &u->sensor_hfov_min_deg)) < 0 ||
        (rc = s_get_double (c, sec, "sensor_hfov_max_deg", fmax (40, u->sensor_hfov_deg), 0.1, 120,
                            &u->sensor_hfov_max_deg)) < 0 ||
        (rc = s_get_double (c, sec, "gimbal_azimuth_limit_deg", 150, 1, 180,
                            &u->gimbal_azimuth_limit_deg)) < 0 ||
        (rc = s_get_double (c, sec, "gimbal_elevation_min_deg", -90, -90, 90,
                            &u->gimbal_elevation_min_deg)) < 0 ||
        (rc = s_get_double (c, sec, "gimbal_elevation_max_deg", 0, -90, 90,
                            &u->gimbal_elevation_max_deg)) < 0)
        return rc;
    u->sensor_stare_target = stare == 1;
    if (u->sensor_depression_deg < u->sensor_depression_min_deg ||
        u->sensor_depression_deg > u->sensor_depression_max_deg)
        return s_key_error (c, sec, "sensor_depression_deg",
                            "expected a depression between sensor_depression_min_deg and "
                            "sensor_depression_max_deg (%.15g..%.15g), got %.15g",
                            u->sensor_depression_min_deg, u->sensor_depression_max_deg,
                            u->sensor_depression_deg);
    if (u->sensor_hfov_deg < u->sensor_hfov_min_deg || u->sensor_hfov_deg > u->sensor_hfov_max_deg)
        return s_key_error (c, sec, "sensor_hfov_deg",
                            "expected a field of view between sensor_hfov_min_deg and "
                            "sensor_hfov_max_deg (%.15g..%.15g), got %.15g",
                            u->sensor_hfov_min_deg, u->sensor_hfov_max_deg, u->sensor_hfov_deg);
    if (u->gimbal_elevation_min_deg > u->gimbal_elevation_max_deg)
        return s_key_error (c, sec, "gimbal_elevation_max_deg",
                            "expected at least gimbal_elevation_min_deg (%.15g), got %.15g",
                            u->gimbal_elevation_min_deg, u->gimbal_elevation_max_deg);
    if (u->heading_deg == 360)
        u->heading_deg = 0;
    if (u->airspeed_mps < u->airspeed_min_mps || u->airspeed_mps > u->airspeed_max_mps)
        return s_key_error (c, sec, "airspeed_mps",
                            "expected a speed between airspeed_min_mps and airspeed_max_mps "
                            "(%.15g..%.15g), got %.15g",
                            u->airspeed_min_mps, u->airspeed_max_mps, u->airspeed_mps);
    if (u->climb_rate_mps >= u->airspeed_min_mps)
        return s_key_error (c, sec, "climb_rate_mps",
                            "expected less than airspeed_min_mps (%.15g), got %.15g",
                            u->airspeed_min_mps, u->climb_rate_mps);
    u->loiter_clockwise = dir == 0;
    // The orbit must be flyable: no tighter than the smallest turn, V^2 / (g tan(bank)).
    double r_min =
        u->airspeed_mps * u->airspeed_mps / (S_GRAVITY * tan (u->bank_limit_deg * M_PI / 180.0));
    if (u->loiter_radius_m < r_min)
        return s_key_error (c, sec, "loiter_radius_m",
                            "%.15g m is tighter than the UAV's smallest turn, %.0f m at "
                            "%.15g m/s and %.15g deg of bank",
                            u->loiter_radius_m, ceil (r_min), u->airspeed_mps, u->bank_limit_deg);
    // Parameter files are read by mtid and bcisd (maybe on other hosts): named, not opened.
    if ((rc = cgs_config_get_path (c->cfg, sec, "radar_params", "", &path, c->err, c->errlen)) < 0)
        return rc;
    if (!(u->radar_params = s_strdup (path)))
        return s_nomem (c);
    if ((rc = cgs_config_get_path (c->cfg, sec, "bcis_params", "", &path, c->err, c->errlen)) < 0)
        return rc;
    if (!(u->bcis_params = s_strdup (path)))
        return s_nomem (c);
    return 0;
}

// --- ground vehicles --------------------------------------------------------------

#define S_POINT_FORM      "`point = POSITION [@ SPEED_MPS]`"
#define S_POINT_HALT_FORM "`point = POSITION [@ SPEED_MPS] [halt SECONDS]`"

// Where the whole word (any case, between blanks or the ends of s) occurs in s:
// the last place, or NULL; *ret_count says how many times.
static char *s_word (char *s, const char *word, int *ret_count)
{
    size_t n = strlen (word);
    char *last = NULL;
    *ret_count = 0;
    for (char *p = s; (p = strcasestr (p, word)); p++)
        if ((p == s || isspace ((unsigned char)p[-1])) &&
            (!p[n] || isspace ((unsigned char)p[n]))) {
            last = p;
            ++*ret_count;
        }
    return last;
}

/* The idx-th `point =` of a vehicle: a position, then an optional '@' and leg
 * speed, then an optional word `halt` and its seconds. No position form has a
 * word "halt" or an '@', and a speed is a bare number, so the last such word
 * ends the position and speed, and the first '@' ends the position. */
static int s_point (s_ctx_t *c, const char *sec, size_t idx, double def_speed, cgs_point_t *ret)
{
    const char *value = cgs_config_get_nth (c->cfg, sec, "point", idx);
    char buf[512];
    if (strlen (value) >= sizeof buf)
        return cgs_config_error (c->cfg, sec, "point", idx, c->err, c->errlen,
                                 "too long (%zu characters)", strlen (value));
    strcpy (buf, value);
    int halts;
    char *halt = s_word (buf, "halt", &halts);
    double halt_s = 0;
    if (halts > 1)
        return cgs_config_error (c->cfg, sec, "point", idx, c->err, c->errlen,
                                 "expected " S_POINT_HALT_FORM " with one 'halt' at most, got '%s'",
                                 value);
    if (halt) {
        *halt = '\0';
        const char *secs = s_trim (halt + 4);
        if (strchr (secs, '@'))
            return cgs_config_error (
                c->cfg, sec, "point", idx, c->err, c->errlen,
                "expected " S_POINT_HALT_FORM " (the speed before the halt), got '%s'", value);
        if (!s_number (secs, &halt_s) || halt_s <= 0 || halt_s > S_HALT_MAX_S)
            return cgs_config_error (c->cfg, sec, "point", idx, c->err, c->errlen,
                                     "expected a halt after 'halt' in (0, %d] s, got '%s'",
                                     S_HALT_MAX_S, secs);
    }
    char *at = strchr (buf, '@');
    if (at && strchr (at + 1, '@'))
        return cgs_config_error (c->cfg, sec, "point", idx, c->err, c->errlen,
                                 "expected " S_POINT_FORM " with one '@' at most, got '%s'", value);
    cgs_point_t p = {.speed_mps = def_speed,
                     .halt_s = halt_s,
                     .line = cgs_config_line (c->cfg, sec, "point", idx)};
    if (at) {
        *at = '\0';
        const char *speed = s_trim (at + 1);
        double v;
        if (!s_number (speed, &v) || v < S_SPEED_MIN || v > S_SPEED_MAX)
            return cgs_config_error (c->cfg, sec, "point", idx, c->err, c->errlen,
                                     "expected a speed after '@' in [%.15g, %.15g] m/s, got '%s'",
                                     S_SPEED_MIN, S_SPEED_MAX, speed);
        p.speed_mps = v;
        p.speed_given = true;
    }
    char why[512];
    if (cgs_config_parse_position (s_trim (buf), c->frame, &p.position, why, sizeof why) < 0)
        return cgs_config_error (c->cfg, sec, "point", idx, c->err, c->errlen, "%s", why);
    int rc;
    if ((rc = s_check_range (c, sec, "point", idx, p.position)) < 0 ||
        (rc = s_on_terrain (c, sec, idx, p.position)) < 0)
        return rc;
    *ret = p;
    return 0;
}

static int s_route (s_ctx_t *c, const char *sec, cgs_scenario_vehicle_t *v)
{
    size_t n = cgs_config_count (c->cfg, sec, "point");
    if (n == 0)
        return s_missing (c, sec, "point", "a route of at least 2 " S_POINT_FORM " lines");
    if (n == 1)
        return cgs_config_error (c->cfg, sec, "point", 0, c->err, c->errlen,
                                 "a route needs at least 2 points, this is its only one");
    if (!(v->points = calloc (n, sizeof *v->points)))
        return s_nomem (c);
    v->point_count = n;
    int rc;
    for (size_t i = 0; i < n; i++) {
        if ((rc = s_point (c, sec, i, v->speed_mps, &v->points[i])) < 0)
            return rc;
        const cgs_point_t *a = &v->points[i - (i > 0)], *b = &v->points[i];
        if (i > 0 &&
            hypot (b->position.e_m - a->position.e_m, b->position.n_m - a->position.n_m) < 1.0)
            return cgs_config_error (c->cfg, sec, "point", i, c->err, c->errlen,
                                     "within 1 m of the previous point (line %d): a leg needs a "
                                     "length",
                                     a->line);
    }
    const cgs_point_t *first = &v->points[0], *last = &v->points[n - 1];
    if (v->end == CGS_END_LOOP && hypot (last->position.e_m - first->position.e_m,
                                         last->position.n_m - first->position.n_m) < 1.0)
        return cgs_config_error (c->cfg, sec, "point", n - 1, c->err, c->errlen,
                                 "repeats the first point: with end = loop the route closes by "
                                 "itself, so leave this point out");
    if (v->end != CGS_END_LOOP && last->speed_given)
        return cgs_config_error (c->cfg, sec, "point", n - 1, c->err, c->errlen,
                                 "no leg starts at the last point, so it takes no speed (only "
                                 "with end = loop, for the leg back to the first point)");
    if (v->end == CGS_END_STOP && first->halt_s > 0)
        return cgs_config_error (c->cfg, sec, "point", 0, c->err, c->errlen,
                                 "with end = stop the vehicle never comes back to its first "
                                 "point, so it cannot halt there (start_time_s delays its start)");
    if (v->end == CGS_END_STOP && last->halt_s > 0)
        return cgs_config_error (c->cfg, sec, "point", n - 1, c->err, c->errlen,
                                 "with end = stop the vehicle stops for good on its last point, "
                                 "so a halt there means nothing (use end = loop or reverse to "
                                 "drive on)");
    return 0;
}

static int s_vehicle (s_ctx_t *c, const char *sec, cgs_scenario_vehicle_t *v)
{
    static const char *const forces[] = {"unknown", "friendly", "hostile", "neutral", NULL};
    static const char *const kinds[] = {"tracked", "wheeled", "person", NULL};
    static const cgs_kind_t kind_of[] = {CGS_KIND_TRACKED, CGS_KIND_WHEELED, CGS_KIND_PERSON};
    static const char *const ends[] = {"stop", "loop", "reverse", NULL};
    int rc, force, kind, end;
    if ((rc = s_get_marking (c, sec, v->name, v->marking)) < 0)
        return rc;
    if (!cgs_config_has (c->cfg, sec, "force"))
        return s_missing (c, sec, "force", "friendly, hostile, neutral or unknown");
    if ((rc = cgs_config_get_enum (c->cfg, sec, "force", forces, 0, &force, c->err, c->errlen)) <
            0 ||
        (rc = cgs_config_get_enum (c->cfg, sec, "kind", kinds, 0, &kind, c->err, c->errlen)) < 0)
        return rc;
    v->force = (cgs_force_t)force; // the names are in the proto's order
    v->kind = kind_of[kind];
    // Default types (SISO-REF-010): platform/land armoured fighting vehicle (category 2) or
    // small wheeled utility vehicle (6), or life form/land; USA (225) when friendly, else other
    // (0).
    uint16_t country = v->force == CGS_FORCE_FRIENDLY ? 225 : 0;
    cgs_dis_type_t def = {1, 1, country, 2, 0, 0, 0};
    if (v->kind == CGS_KIND_WHEELED)
        def.category = 6;
    else if (v->kind == CGS_KIND_PERSON)
        def = (cgs_dis_type_t){3, 1, country, 0, 0, 0, 0};
    const char *rcs;
    if ((rc = s_get_dis_type (c, sec, "dis_type", def, &v->dis_type)) < 0 ||
        (rc = cgs_config_get_bool (c->cfg, sec, "bcis_transponder", v->force == CGS_FORCE_FRIENDLY,
                                   &v->bcis_transponder, c->err, c->errlen)) < 0 ||
        (rc = cgs_config_get_string (c->cfg, sec, "rcs_class", "vehicle", &rcs, c->err,
                                     c->errlen)) < 0)
        return rc;
    if (!s_name_ok (rcs, S_RCS_MAX))
        return cgs_config_error (c->cfg, sec, "rcs_class", 0, c->err, c->errlen,
                                 "expected a class name of 1 to %d letters, digits, '_', '.' or "
                                 "'-', got '%s'",
                                 S_RCS_MAX, rcs);
    if (!(v->rcs_class = s_strdup (rcs)))
        return s_nomem (c);
    double def_speed = v->kind == CGS_KIND_PERSON ? 1.5 : 10;
    if ((rc = s_get_double (c, sec, "start_time_s", 0, 0, 7 * 86400, &v->start_time_s)) < 0 ||
        (rc = s_get_double (c, sec, "speed_mps", def_speed, S_SPEED_MIN, S_SPEED_MAX,
                            &v->speed_mps)) < 0 ||
        (rc = cgs_config_get_enum (c->cfg, sec, "end", ends, 0, &end, c->err, c->errlen)) < 0 ||
        (rc = s_get_double (c, sec, "deviation_m", 0, 0, 200, &v->deviation_m)) < 0 ||
        (rc = cgs_config_get_uint64 (c->cfg, sec, "deviation_seed",
                                     cgs_scenario_vehicle_seed (c->seed, v->id), &v->deviation_seed,
                                     c->err, c->errlen)) < 0)
        return rc;
    v->end = (cgs_end_t)end;
    return s_route (c, sec, v);
}

// --- operator and settings --------------------------------------------------------

#define S_DESIGNATE_FORM "`designate = {unknown|friendly|any} nearest POSITION at TIME_S`"

static int s_designation (s_ctx_t *c, size_t idx, cgs_designation_t *ret)
{
    static const char *const picks[] = {"unknown", "friendly", "any"};
    const char *sec = "operator";
    const char *value = cgs_config_get_nth (c->cfg, sec, "designate", idx);
    char buf[512];
    cgs_designation_t d = {.line = cgs_config_line (c->cfg, sec, "designate", idx)};
    bool ok = strlen (value) < sizeof buf;
    char *pos = NULL, *time = NULL;
    char *rest = NULL;
    if (ok) {
        strcpy (buf, value);
        // FILTER, then "nearest", each a whole word.
        char *pick = buf + strspn (buf, " \t");
        char *p = pick + strcspn (pick, " \t");
        char *nearest = p + strspn (p, " \t");
        *p = '\0';
        p = nearest + strcspn (nearest, " \t");
        rest = p + strspn (p, " \t");
        *p = '\0';
        ok = strcasecmp (nearest, "nearest") == 0;
        for (int i = 0; ok && i < 3; i++) {
            if (strcasecmp (pick, picks[i]) == 0) {
                d.pick = (cgs_pick_t)i;
                break;
            }
            ok = i < 2;
        }
        // The position runs to the last whole word "at"; the time follows it.
        for (char *s = rest; ok && *s; s++)
            if ((s[0] == 'a' || s[0] == 'A') && (s[1] == 't' || s[1] == 'T') && s > rest &&
                isspace ((unsigned char)s[-1]) && isspace ((unsigned char)s[2]))
                time = s;
        if (time) {
            time[0] = '\0';
            pos = s_trim (rest);
            time = s_trim (time + 2);
        }
        ok = ok && time && *pos;
    }
    if (!ok)
        return cgs_config_error (c->cfg, sec, "designate", idx, c->err, c->errlen,
                                 "expected " S_DESIGNATE_FORM ", got '%s'", value);
    char why[512];
    if (cgs_config_parse_position (pos, c->frame, &d.near, why, sizeof why) < 0)
        return cgs_config_error (c->cfg, sec, "designate", idx, c->err, c->errlen, "%s", why);
    int rc = s_check_range (c, sec, "designate", idx, d.near);
    if (rc < 0)
        return rc;
    if (!s_number (time, &d.time_s) || d.time_s < 0 || d.time_s > 7 * 86400)
        return cgs_config_error (c->cfg, sec, "designate", idx, c->err, c->errlen,
                                 "expected a time after 'at' in [0, %d] s, got '%s'", 7 * 86400,
                                 time);
    *ret = d;
    return 0;
}

static int s_operator (s_ctx_t *c)
{
    size_t n = cgs_config_count (c->cfg, "operator", "designate");
    // Marks the section looked at even without designations, so its other keys are reported.
    (void)cgs_config_get_nth (c->cfg, "operator", "designate", 0);
    if (n == 0)
        return 0;
    if (!(c->sc->designations = calloc (n, sizeof *c->sc->designations)))
        return s_nomem (c);
    c->sc->designation_count = n;
    for (size_t i = 0; i < n; i++) {
        int rc = s_designation (c, i, &c->sc->designations[i]);
        if (rc < 0)
            return rc;
    }
    return 0;
}

static int s_settings (s_ctx_t *c)
{
    const char *sec = "uavsim";
    cgs_uavsim_settings_t *s = &c->sc->settings;
    int rc;
    if ((rc = s_get_double (c, sec, "step_s", 0.05, 0.001, 1, &s->step_s)) < 0 ||
        (rc = s_get_double (c, sec, "entity_rate_hz", 10, 0.01, 1000, &s->entity_rate_hz)) < 0 ||
        (rc = s_get_double (c, sec, "uav_rate_hz", 10, 0.01, 1000, &s->uav_rate_hz)) < 0 ||
        (rc = s_get_double (c, sec, "clock_rate_hz", 10, 0.01, 1000, &s->clock_rate_hz)) < 0 ||
        (rc = s_get_double (c, sec, "checkpoint_interval_s", 5, 0.1, 3600,
                            &s->checkpoint_interval_s)) < 0)
        return rc;
    // The service publishes at most once per step.
    const char *keys[] = {"entity_rate_hz", "uav_rate_hz", "clock_rate_hz"};
    const double rates[] = {s->entity_rate_hz, s->uav_rate_hz, s->clock_rate_hz};
    for (int i = 0; i < 3; i++)
        if (rates[i] * s->step_s > 1 + 1e-9)
            return s_key_error (c, sec, keys[i],
                                "%.15g Hz is more than one publication per step (step_s %.15g "
                                "allows at most %.15g Hz)",
                                rates[i], s->step_s, 1 / s->step_s);
    return 0;
}

// --- stand-off ---------------------------------------------------------------------

/* The least distance between the circle (centre o, radius r) and the segment
 * a-b: |p − o| along the segment is convex, from its least value (the point
 * nearest o) to its largest (an end); the circle's radius inside that range
 * means the segment crosses it. */
static double s_circle_segment (cgs_enu_t o, double r, cgs_enu_t a, cgs_enu_t b)
{
    double ax = a.e_m - o.e_m, ay = a.n_m - o.n_m, dx = b.e_m - a.e_m, dy = b.n_m - a.n_m;
    double len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? fmin (1, fmax (0, -(ax * dx + ay * dy) / len2)) : 0;
    double near = hypot (ax + t * dx, ay + t * dy);
    double far = fmax (hypot (ax, ay), hypot (ax + dx, ay + dy));
    if (r >= near && r <= far)
        return 0;
    return r < near ? near - r : r - far;
}

size_t cgs_scenario_standoff (const cgs_scenario_t *self, cgs_standoff_t *ret, size_t max)
{
    size_t n = 0;
    for (size_t i = 0; self && i < self->uav_count; i++) {
        const cgs_scenario_uav_t *u = &self->uavs[i];
        if (!(u->standoff_m > 0))
            continue;
        for (size_t j = 0; j < self->vehicle_count; j++) {
            const cgs_scenario_vehicle_t *v = &self->vehicles[j];
            cgs_standoff_t best = {i, j, 0, INFINITY};
            for (size_t k = 0; k + 1 < v->point_count; k++) {
                double d = s_circle_segment (u->loiter_center, u->loiter_radius_m,
                                             v->points[k].position, v->points[k + 1].position);
                if (d < best.distance_m) {
                    best.leg = k;
                    best.distance_m = d;
                }
            }
            if (best.distance_m < u->standoff_m) {
                if (n < max && ret)
                    ret[n] = best;
                n++;
            }
        }
    }
    return n;
}

void cgs_scenario_standoff_text (const cgs_scenario_t *self, const cgs_standoff_t *s, char *buf,
                                 size_t len)
{
    const cgs_scenario_uav_t *u = &self->uavs[s->uav];
    const cgs_scenario_vehicle_t *v = &self->vehicles[s->vehicle];
    snprintf (buf, len,
              "%s:%d: [uav %s] loiter orbit comes within %.0f m of vehicle %s's route (leg from "
              "line %d to line %d); stand-off is %.0f m",
              self->path ? self->path : "scenario", u->line, u->name, s->distance_m, v->name,
              v->points[s->leg].line, v->points[s->leg + 1].line, u->standoff_m);
}

// --- load -------------------------------------------------------------------------

void cgs_scenario_destroy (cgs_scenario_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    cgs_scenario_t *self = *self_p;
    free (self->path);
    free (self->terrain.dem_path);
    for (size_t i = 0; self->uavs && i < self->uav_count; i++) {
        free (self->uavs[i].radar_params);
        free (self->uavs[i].bcis_params);
    }
    free (self->uavs);
    for (size_t i = 0; self->vehicles && i < self->vehicle_count; i++) {
        free (self->vehicles[i].rcs_class);
        free (self->vehicles[i].points);
    }
    free (self->vehicles);
    free (self->designations);
    free (self);
    *self_p = NULL;
}

// Everything after the config is read: sections, then each part, then unknown keys.
static int s_parse (s_ctx_t *c)
{
    cgs_config_t *cfg = c->cfg;
    cgs_scenario_t *sc = c->sc;
    size_t nsec = cgs_config_section_count (cfg);
    // Count and name the entities; a UAV and a vehicle may not share a name.
    for (size_t i = 0; i < nsec; i++) {
        const char *sec = cgs_config_section_name (cfg, i);
        const char *name = s_entity_name (sec, "uav");
        bool uav = name != NULL;
        if (!name)
            name = s_entity_name (sec, "vehicle");
        if (!name)
            continue;
        if (!s_name_ok (name, CGS_SCENARIO_NAME_MAX))
            return cgs_config_error (cfg, sec, NULL, 0, c->err, c->errlen,
                                     "expected `[%s NAME]` with a NAME of 1 to %d letters, "
                                     "digits, '_', '.' or '-', got '%s'",
                                     uav ? "uav" : "vehicle", CGS_SCENARIO_NAME_MAX, name);
        for (size_t j = 0; j < i; j++) {
            const char *other = cgs_config_section_name (cfg, j);
            const char *oname = s_entity_name (other, "uav");
            if (!oname)
                oname = s_entity_name (other, "vehicle");
            if (oname && strcmp (oname, name) == 0)
                return cgs_config_error (cfg, sec, NULL, 0, c->err, c->errlen,
                                         "name '%s' is already used by [%s] (line %d)", name, other,
                                         cgs_config_section_line (cfg, j));
        }
        if (uav)
            sc->uav_count++;
        else
            sc->vehicle_count++;
    }
    if (sc->uav_count == 0) {
        cgs_errf (c->err, c->errlen, "%s: no [uav NAME] section (a scenario needs a UAV)",
                  cgs_config_path (cfg));
        return -EINVAL;
    }
    sc->uavs = calloc (sc->uav_count, sizeof *sc->uavs);
    sc->vehicles = calloc (sc->vehicle_count ? sc->vehicle_count : 1, sizeof *sc->vehicles);
    s_entity_t *ents = calloc (sc->uav_count + sc->vehicle_count, sizeof *ents);
    if (!sc->uavs || !sc->vehicles || !ents) {
        free (ents);
        return s_nomem (c);
    }
    size_t nu = 0, nv = 0;
    for (size_t i = 0; i < nsec; i++) {
        const char *sec = cgs_config_section_name (cfg, i);
        const char *name;
        if ((name = s_entity_name (sec, "uav"))) {
            snprintf (sc->uavs[nu].name, sizeof sc->uavs[nu].name, "%s", name);
            sc->uavs[nu].line = cgs_config_section_line (cfg, i);
            ents[nu] = (s_entity_t){sec, &sc->uavs[nu].id};
            nu++;
        }
    }
    for (size_t i = 0; i < nsec; i++) {
        const char *sec = cgs_config_section_name (cfg, i);
        const char *name;
        if ((name = s_entity_name (sec, "vehicle"))) {
            snprintf (sc->vehicles[nv].name, sizeof sc->vehicles[nv].name, "%s", name);
            sc->vehicles[nv].line = cgs_config_section_line (cfg, i);
            ents[nu + nv] = (s_entity_t){sec, &sc->vehicles[nv].id};
            nv++;
        }
    }
    int rc = s_assign_ids (c, ents, nu + nv);
    if (rc == 0)
        rc = s_terrain (c); // before the vehicles, whose points must lie on it
    for (size_t i = 0; i < nu && rc == 0; i++)
        rc = s_uav (c, ents[i].section, &sc->uavs[i]);
    for (size_t i = 0; i < nv && rc == 0; i++)
        rc = s_vehicle (c, ents[nu + i].section, &sc->vehicles[i]);
    free (ents);
    if (rc == 0)
        rc = s_operator (c);
    if (rc == 0)
        rc = s_settings (c);
    if (rc == 0)
        rc = cgs_config_check_unused (cfg, c->err, c->errlen);
    return rc;
}

int cgs_scenario_load_string (const char *name, const char *text, const cgs_geo_t *frame,
                              uint64_t default_seed, cgs_scenario_t **ret, char *err, size_t errlen)
{
    assert (name && text && ret);
    s_ctx_t c = {.frame = frame, .seed = default_seed, .err = err, .errlen = errlen};
    int rc = cgs_config_load_string (name, text, &c.cfg, err, errlen);
    if (rc < 0)
        return rc;
    if ((rc = cgs_config_check_repeated (c.cfg, err, errlen)) < 0)
        goto done;
    c.sc = calloc (1, sizeof *c.sc);
    if (!c.sc || !(c.sc->path = s_strdup (name))) {
        rc = s_nomem (&c);
        goto done;
    }
    rc = s_parse (&c);
done:
    if (rc == 0)
        *ret = c.sc;
    else
        cgs_scenario_destroy (&c.sc);
    cgs_config_destroy (&c.cfg);
    return rc;
}

int cgs_scenario_load (const char *path, const cgs_geo_t *frame, uint64_t default_seed,
                       cgs_scenario_t **ret, char *err, size_t errlen)
{
    assert (path && ret);
    FILE *f = fopen (path, "rb");
    if (!f) {
        int e = errno;
        cgs_errf (err, errlen, "%s: %s", path, strerror (e));
        return -e;
    }
    char *text = NULL;
    size_t len = 0, alloc = 0;
    int rc = 0;
    for (;;) {
        if (len + 4096 + 1 > alloc) {
            size_t a = alloc ? 2 * alloc : 65536;
            char *more = a <= S_MAX_FILE_BYTES + 1 ? realloc (text, a) : NULL;
            if (!more) {
                rc = a <= S_MAX_FILE_BYTES + 1 ? -ENOMEM : -EFBIG;
                break;
            }
            text = more;
            alloc = a;
        }
        size_t got = fread (text + len, 1, alloc - len - 1, f);
        len += got;
        if (got == 0) {
            if (ferror (f))
                rc = -EIO;
            break;
        }
    }
    fclose (f);
    if (rc == 0 && memchr (text, '\0', len))
        rc = -EBADMSG;
    if (rc < 0) {
        if (rc == -EFBIG)
            cgs_errf (err, errlen, "%s: larger than %u MiB, not a scenario", path,
                      S_MAX_FILE_BYTES >> 20);
        else if (rc == -EBADMSG)
            cgs_errf (err, errlen, "%s: contains a NUL byte, not a text file", path);
        else
            cgs_errf (err, errlen, "%s: %s", path, strerror (-rc));
        free (text);
        return rc == -EFBIG || rc == -EBADMSG ? -EINVAL : rc;
    }
    text[len] = '\0';
    rc = cgs_scenario_load_string (path, text, frame, default_seed, ret, err, errlen);
    free (text);
    return rc;
}

const cgs_scenario_vehicle_t *cgs_scenario_vehicle (const cgs_scenario_t *self, const char *name)
{
    for (size_t i = 0; i < self->vehicle_count; i++)
        if (strcmp (self->vehicles[i].name, name) == 0)
            return &self->vehicles[i];
    return NULL;
}

const cgs_scenario_uav_t *cgs_scenario_uav (const cgs_scenario_t *self, const char *name)
{
    for (size_t i = 0; i < self->uav_count; i++)
        if (strcmp (self->uavs[i].name, name) == 0)
            return &self->uavs[i];
    return NULL;
}

int cgs_scenario_terrain (const cgs_scenario_t *self, const cgs_geo_t *frame, cgs_terrain_t **ret_t,
                          char *err, size_t errlen)
{
    const cgs_terrain_spec_t *t = &self->terrain;
    cgs_terrain_t *terrain = NULL;
    if (t->source == CGS_TERRAIN_DEM) {
        if (!frame) {
            cgs_errf (err, errlen, "%s: a DEM needs the exercise origin", self->path);
            return -EINVAL;
        }
        int rc = cgs_terrain_load (t->dem_path, frame, t->resolution_m, t->half_extent_m, &terrain,
                                   err, errlen);
        if (rc < 0)
            return rc;
    } else {
        terrain = cgs_terrain_new_fbm (&t->fbm);
        if (!terrain) {
            cgs_errf (err, errlen, "%s: [terrain]: cannot generate the procedural terrain",
                      self->path);
            return -EINVAL;
        }
    }
    if (t->vegetation.cover > 0) {
        int rc = cgs_terrain_grow_vegetation (terrain, &t->vegetation);
        if (rc < 0) {
            cgs_errf (err, errlen, "%s: [terrain]: cannot grow the vegetation: %s", self->path,
                      strerror (-rc));
            cgs_terrain_destroy (&terrain);
            return rc;
        }
    }
    *ret_t = terrain;
    return 0;
}
