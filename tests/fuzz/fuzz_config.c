/* libFuzzer target: any text as a config file, read with every getter the
 * services use, and as a position. Must never crash, leak or hit undefined
 * behaviour; errors must be reported, not asserted. */
#include "cgs_config.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput (const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput (const uint8_t *data, size_t size)
{
    static cgs_geo_t *frame;
    if (!frame)
        frame = cgs_geo_new (35.96, -121.23, 0);
    char *text = malloc (size + 1);
    if (!text)
        return 0;
    memcpy (text, data, size);
    text[size] = '\0';
    char err[512];
    cgs_enu_t p;
    cgs_config_parse_position (text, frame, &p, err, sizeof err);
    cgs_config_t *cfg = NULL;
    if (cgs_config_load_string ("fuzz.ini", text, &cfg, err, sizeof err) == 0) {
        for (size_t i = 0; i < cgs_config_section_count (cfg); i++) {
            const char *sec = cgs_config_section_name (cfg, i);
            double d;
            long l;
            bool b;
            int e;
            uint64_t u;
            const char *s;
            static const char *const names[] = {"a", "b", NULL};
            cgs_config_get_double (cfg, sec, "x", 0, -1e9, 1e9, &d, err, sizeof err);
            cgs_config_get_int (cfg, sec, "n", 0, -100, 100, &l, err, sizeof err);
            cgs_config_get_uint64 (cfg, sec, "u", 0, &u, err, sizeof err);
            cgs_config_get_bool (cfg, sec, "b", false, &b, err, sizeof err);
            cgs_config_get_enum (cfg, sec, "e", names, 0, &e, err, sizeof err);
            cgs_config_get_string (cfg, sec, "s", "", &s, err, sizeof err);
            cgs_config_get_path (cfg, sec, "path", "", &s, err, sizeof err);
            cgs_config_get_position (cfg, sec, "p", frame, (cgs_enu_t){0}, &p, err, sizeof err);
            for (size_t k = 0; k < cgs_config_count (cfg, sec, "point"); k++)
                (void)cgs_config_get_nth (cfg, sec, "point", k);
        }
        cgs_config_check_unused (cfg, err, sizeof err);
        cgs_config_destroy (&cfg);
    }
    free (text);
    return 0;
}
