/* cgs_json — small helpers over json-c (see cgs_json.h). */
#include "cgs_json.h"

#include <errno.h>
#include <math.h>

json_object *cgs_json_fixed (double v, int decimals)
{
    if (!isfinite (v))
        return NULL;
    char buf[48];
    snprintf (buf, sizeof buf, "%.*f", decimals, v);
    return json_object_new_double_s (v, buf);
}

void cgs_json_add (json_object *o, const char *key, json_object *v)
{
    if (json_object_object_add_ex (
            o, key, v, JSON_C_OBJECT_ADD_KEY_IS_NEW | JSON_C_OBJECT_KEY_IS_CONSTANT) < 0)
        json_object_put (v);
}

int cgs_json_print (FILE *f, json_object *o, int flags, const char *end)
{
    const char *text = json_object_to_json_string_ext (o, flags | JSON_C_TO_STRING_NOSLASHESCAPE);
    if (!text)
        return -ENOMEM;
    if (fputs (text, f) == EOF || fputs (end, f) == EOF)
        return -EIO;
    return 0;
}
