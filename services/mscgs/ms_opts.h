/* ms_opts — the options of mscgs's commands, each command's from one table.
 *
 * The parser takes what GNU getopt_long took for these commands, and says
 * what it said: `--name V` and `--name=V`, an unambiguous prefix of a name
 * (`--exer F`), short letters (`-h`, `-n5`, `-jn 5`), operands before,
 * between and after the options, `--` ending the options (an argument that
 * starts with `-` is an option before it). The first unknown, ambiguous or
 * incomplete option ends the parse with getopt_long's message and the
 * command's usage on stderr; `--help` prints the usage on stdout; a command
 * that needs an operand says so when none came. The usage is the table's:
 * `usage: mscgs NAME OPERANDS [--name V] ...`, wrapped at 100 columns, then
 * the command's text.
 */
#ifndef MS_OPTS_H
#define MS_OPTS_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

typedef struct ms_opt_s ms_opt_t;

/* Reads an option's value: 0, or -EINVAL after saying why on stderr. */
typedef int (ms_opt_fn_t) (const ms_opt_t *opt, const char *value);

/* One option. Exactly one of str, flag and fn says where its value goes;
 * an entry named "help" has none: it prints the usage. */
struct ms_opt_s {
    const char *name;  // the long name without "--"; NULL ends a table
    char letter;       // the short name (-h); 0: none
    const char *value; // the value's name in the usage ("S"); NULL: takes no value
    const char *help;  // its line in an option list ('\n' between lines); NULL: not in the usage
    const char **str;  // set to the value (it points into argv)
    bool *flag;        // set to true (an option without a value)
    ms_opt_fn_t *fn;   // called with the value (NULL for an option without one)
    void *arg;         // for fn
};

/* The --help entry (also -h) and a table's end. */
// clang-format off
#define MS_OPTS_HELP {.name = "help", .letter = 'h'}
#define MS_OPTS_END  {.name = NULL}
// clang-format on

/* A command: its name, usage and options. */
typedef struct {
    const char *name;     // "status": the usage's `mscgs status`
    const char *operands; // after the name in the usage ("TOPIC"); NULL: none
    const char *synopsis; // the usage's first lines, when not the table's; NULL: the table's
    const char *about;    // the usage's text after them; NULL: none
    const char *missing;  // said ("mscgs NAME: MISSING") when no operand came; NULL: none needed
    const ms_opt_t *opts; // ends with an entry whose name is NULL
} ms_cmd_t;

/* Parse argv[1] .. argv[argc - 1] (argv[0] names the command in messages).
 * Each option's value is stored or read as it comes, left to right.
 * Returns how many operands there are, moved in order to argv[1] ..
 * argv[n]; or -ECANCELED after --help printed the usage; or -EINVAL after
 * a bad option or value, or no operand where the command needs one (said on
 * stderr). argv's order changes in any case. */
int ms_opts_parse (const ms_cmd_t *cmd, int argc, char **argv);

/* The exit code of a command whose parse returned rc < 0: 0 after --help, 2. */
int ms_opts_exit_code (int rc);

/* Print the command's usage. */
void ms_opts_usage (const ms_cmd_t *cmd, FILE *f);

/* Print an option list: per option with a help line, indent spaces, the
 * option and its value in 13 columns, two spaces, the help (its next lines
 * under its first). */
void ms_opts_list (const ms_opt_t *opts, int indent, FILE *f);

/* Read text as a finite number into *ret: 0, or -EINVAL after saying
 * "mscgs: WHAT: expected a number, got 'TEXT'". */
int ms_opts_number (const char *what, const char *text, double *ret);

/* Read text as a positive finite number into *ret: 0, or -EINVAL after
 * saying "mscgs: WHAT: expected a positive number, got 'TEXT'". */
int ms_opts_positive (const char *what, const char *text, double *ret);

/* Read text as a whole number in 0 .. UINT32_MAX (an entity or track id):
 * 0, or -EINVAL after saying "mscgs: WHAT: expected EXPECTED, got 'TEXT'". */
int ms_opts_u32 (const char *what, const char *expected, const char *text, uint32_t *ret);

/* Option readers for fn, writing to arg: a finite number (double *), a
 * positive finite number (double *), an entity id (uint32_t *). Their
 * messages name the option ("mscgs: --radius: expected a number, got 'x'"). */
int ms_opts_read_number (const ms_opt_t *opt, const char *value);
int ms_opts_read_positive (const ms_opt_t *opt, const char *value);
int ms_opts_read_entity_id (const ms_opt_t *opt, const char *value);

#endif
