/* cgs_json — small helpers over json-c for the JSON the programs write:
 * numbers with a fixed number of decimals (json-c's own format keeps 17
 * significant digits), members added in order, an object printed to a
 * stream. A value json-c cannot allocate is written as null; a member it
 * cannot add is left out. */
#ifndef CGS_JSON_H
#define CGS_JSON_H

#include <json-c/json.h>
#include <stdio.h>

/* A number printed with decimals decimals; NULL (JSON null) when not finite. */
json_object *cgs_json_fixed (double v, int decimals);
/* Add member key (a string constant, not yet in o), taking v (NULL: null). */
void cgs_json_add (json_object *o, const char *key, json_object *v);
/* o as JSON text (json-c's flags; '/' is not escaped), then end, to f; 0,
 * -ENOMEM or -EIO. */
int cgs_json_print (FILE *f, json_object *o, int flags, const char *end);

#endif
