/* cgs_config — ASCII `key = value` INI files, read with inih, with typed
 * getters. Every key read is marked; cgs_config_check_unused then reports
 * keys nobody asked for. Every error names the file, the line, the key and
 * what was expected: "scenario.ini:12: [uav uav1] speed_mps: expected a
 * number in [10, 100], got 'fast'". Pure: no logging. */
#ifndef CGS_CONFIG_H
#define CGS_CONFIG_H

#include "cgs_geo.h"
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct cgs_config cgs_config_t;

/* Parse a file; 0, or -ENOENT/-EINVAL/-ENOMEM with "file:line: reason" in err. */
int cgs_config_load (const char *path, cgs_config_t **ret_cfg, char *err, size_t errlen);
/* Parse text as if it were a file called name (for tests and inline config). */
int cgs_config_load_string (const char *name, const char *text, cgs_config_t **ret_cfg, char *err,
                            size_t errlen);
/* Free; accepts NULL; sets *self_p to NULL. */
void cgs_config_destroy (cgs_config_t **self_p);

/* The path the config was read from. */
const char *cgs_config_path (const cgs_config_t *self);
/* The folder of that path ("." when none): relative paths in a file are relative to it. */
const char *cgs_config_dir (const cgs_config_t *self);
/* Number of sections, in file order (a section named twice counts once). */
size_t cgs_config_section_count (const cgs_config_t *self);
/* Name of section i, e.g. "uav uav1". */
const char *cgs_config_section_name (const cgs_config_t *self, size_t i);
/* Line where section i (first) starts. */
int cgs_config_section_line (const cgs_config_t *self, size_t i);
/* Line where section i's header is given a second time (its keys are merged
 * into the first), 0 when it is given once. */
int cgs_config_section_again (const cgs_config_t *self, size_t i);
/* -EINVAL with "file:line: [section] given twice (first at line N)" for the
 * first section header given twice (its keys would be merged), else 0. */
int cgs_config_check_repeated (const cgs_config_t *self, char *err, size_t errlen);
/* True when the section exists. Marks nothing. */
bool cgs_config_has_section (const cgs_config_t *self, const char *section);
/* True when the key is present in the section. Marks nothing. */
bool cgs_config_has (const cgs_config_t *self, const char *section, const char *key);
/* How many times a key appears (for repeated keys such as `point =`). */
size_t cgs_config_count (const cgs_config_t *self, const char *section, const char *key);
/* Line of the idx-th occurrence of a key, 0 when absent. */
int cgs_config_line (const cgs_config_t *self, const char *section, const char *key, size_t idx);

/* Typed getters. When the key is absent, *ret gets the default and the call
 * returns 0. When it is present (once) and valid, *ret gets the value, the key
 * is marked used, 0. Otherwise -EINVAL with the reason in err and *ret is not
 * written. A key given twice is an error for these single-value getters. */
int cgs_config_get_string (cgs_config_t *self, const char *section, const char *key,
                           const char *def, const char **ret, char *err, size_t errlen);
int cgs_config_get_double (cgs_config_t *self, const char *section, const char *key, double def,
                           double min, double max, double *ret, char *err, size_t errlen);
int cgs_config_get_int (cgs_config_t *self, const char *section, const char *key, long def,
                        long min, long max, long *ret, char *err, size_t errlen);
int cgs_config_get_uint64 (cgs_config_t *self, const char *section, const char *key, uint64_t def,
                           uint64_t *ret, char *err, size_t errlen);
/* true/false, yes/no, on/off, 1/0. */
int cgs_config_get_bool (cgs_config_t *self, const char *section, const char *key, bool def,
                         bool *ret, char *err, size_t errlen);
/* One of names (NULL-terminated), case-insensitive; *ret is its index. */
int cgs_config_get_enum (cgs_config_t *self, const char *section, const char *key,
                         const char *const *names, int def, int *ret, char *err, size_t errlen);
/* A path; relative paths are taken from the config file's folder. *ret points
 * into storage owned by the config. */
int cgs_config_get_path (cgs_config_t *self, const char *section, const char *key, const char *def,
                         const char **ret, char *err, size_t errlen);
/* A position (see cgs_config_parse_position) in the frame; def when absent. */
int cgs_config_get_position (cgs_config_t *self, const char *section, const char *key,
                             const cgs_geo_t *frame, cgs_enu_t def, cgs_enu_t *ret, char *err,
                             size_t errlen);
/* The idx-th value of a repeated key, raw; marks it used; NULL when absent. */
const char *cgs_config_get_nth (cgs_config_t *self, const char *section, const char *key,
                                size_t idx);
/* -ENOENT with "file: [section]: missing key 'key' (expected what)" unless the key is present. */
int cgs_config_require (const cgs_config_t *self, const char *section, const char *key,
                        const char *what, char *err, size_t errlen);
/* Mark every key of a section used (for sections handled elsewhere). */
void cgs_config_mark_section (cgs_config_t *self, const char *section);
/* -EINVAL naming the first key or section nobody read ("unknown key"), else 0. */
int cgs_config_check_unused (const cgs_config_t *self, char *err, size_t errlen);
/* Format an error about a key: "file:line: [section] key: " then the message. Returns -EINVAL. */
int cgs_config_error (const cgs_config_t *self, const char *section, const char *key, size_t idx,
                      char *err, size_t errlen, const char *fmt, ...)
    __attribute__ ((format (printf, 7, 8)));

/* Reads a loaded config into the caller's struct (arg). */
typedef int cgs_config_read_fn (cgs_config_t *cfg, void *arg, char *err, size_t errlen);
/* Load the file at path (or, when text is not NULL, text under the name
 * path), read it with fn, free it: 0, or the first negative errno with err
 * filled. */
int cgs_config_read (const char *path, const char *text, cgs_config_read_fn *fn, void *arg,
                     char *err, size_t errlen);

/* Tables of numeric parameters kept in a struct: each entry names its
 * section and key, its field's offset, and its closed range. */
typedef struct {
    const char *section, *key;
    size_t offset; // of a double field
    double min, max;
} cgs_config_real_t;
typedef struct {
    const char *section, *key;
    size_t offset; // of an int field
    long min, max;
} cgs_config_int_t;

/* Read every key of the tables into the fields at base (each field's present
 * value is its default). 0, or -EINVAL at the first bad key (fields read
 * before it are written). */
int cgs_config_get_table (cgs_config_t *self, const cgs_config_real_t *reals, size_t nreals,
                          const cgs_config_int_t *ints, size_t nints, void *base, char *err,
                          size_t errlen);
/* The first field at base outside its range: true with its section and key
 * and "expected ..., got ..." in msg; false when every field is in range. */
bool cgs_config_table_out_of_range (const cgs_config_real_t *reals, size_t nreals,
                                    const cgs_config_int_t *ints, size_t nints, const void *base,
                                    const char **ret_section, const char **ret_key, char *msg,
                                    size_t msglen);
/* An error about a parameter's value found after reading: on the key's line
 * when self has it, else "file: [section] key: msg" (or "[section] key: msg"
 * when self is NULL). Returns -EINVAL. */
int cgs_config_value_error (const cgs_config_t *self, const char *section, const char *key,
                            const char *msg, char *err, size_t errlen);

/* Parse a position written in any of these forms (case-insensitive keywords):
 *   "1200 -350" or "1200 -350 20"      local metres east, north (, up)
 *   "local 1200 -350"                  the same, explicit
 *   "36.6 -121.9" is local metres too: geodetic positions need a keyword
 *   "geo 36.595 -121.874 [height_m]"   latitude, longitude in degrees
 *   "36.595N 121.874W [height_m]"      latitude, longitude with hemispheres
 *   "mgrs 10SEG 12345 67890" or "10SEG1234567890"   MGRS, height 0
 * Geodetic and MGRS positions become local ENU in frame (up is the frame's up
 * at that point). 0, or -EINVAL with the reason in why. */
int cgs_config_parse_position (const char *text, const cgs_geo_t *frame, cgs_enu_t *ret, char *why,
                               size_t whylen);
/* Parse a geodetic position (the geo, hemisphere or MGRS forms above; local
 * metres are rejected), e.g. an exercise origin. 0, or -EINVAL with the reason in why. */
int cgs_config_parse_geodetic (const char *text, cgs_geodetic_t *ret, char *why, size_t whylen);

#endif
