/* options.h — the command-line option tables of rtsim, rttrace and rtdram and
 * the one parser they share (cli/lib/options.c, in libcli).
 *
 * A tool declares every option once, in a table of cli_opt rows: its name,
 * the kind of its value, the allowed range or choices, the default, where
 * the value goes and its --help text. cli_parse() sets every destination to
 * its default, then reads argv with getopt_long (long options only, unique
 * prefixes and "--name=value" accepted), checks each value against its row
 * and, on --help, prints the help from the table. A tool's cli_tool says how
 * its messages are worded (each tool keeps its own long-standing wording):
 *  - a bad value: tool->bad_value with the option, the value and what is
 *    allowed ("allowed range 0..64"), then the hint line; exit 2;
 *  - an unknown option or a missing value: tool->unknown (tool->missing),
 *    then the usage or the hint; exit 2;
 *  - --help: the usage on stdout, exit 0; --version: "TOOL VERSION (git
 *    COMMIT)", exit 0.
 * Values are checked strictly: an integer is decimal digits only (no sign,
 * no blank), a real is all of the text; ranges are inclusive unless
 * lo_open. A row's default is text in the form the user would type, parsed
 * by the same rules (so --help prints exactly the default that applies). */
#ifndef RTSIM_CLI_OPTIONS_H
#define RTSIM_CLI_OPTIONS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* A macro's value as a string literal, for defaults and help texts. */
#define CLI_STR_(x) #x
#define CLI_STR(x) CLI_STR_(x)

/* What cli_parse returns when the tool goes on (otherwise: an exit status). */
#define CLI_GO_ON (-1)

typedef enum cli_kind {
    CLI_FLAG,     /* no value; to.flag = true */
    CLI_STRING,   /* to.str = the text (a path, a name) */
    CLI_LIST,     /* repeatable; the texts in to.list, in order */
    CLI_UINT,     /* decimal integer in min..max; to.u */
    CLI_REAL,     /* number in lo..hi (lo excluded when lo_open); to.real */
    CLI_CHOICE,   /* one of choices; to.choice = its index */
    CLI_CUSTOM,   /* parse(text, to.custom) decides */
    CLI_HELP,     /* prints the usage, exit 0; listed as "--help, --version" */
    CLI_VERSION,  /* prints the version, exit 0 */
} cli_kind;

/* The values of a repeatable option (cli_parse allocates v; free(v) after). */
typedef struct cli_list {
    const char **v;
    int n;
} cli_list;

/* A CLI_CUSTOM parser: true with the value stored in `to`; false with a
 * message in err, or with err empty for the row's `what`. */
typedef bool (*cli_parse_fn)(const char *text, void *to, char *err, size_t errlen);

typedef struct cli_opt {
    const char *name;                /* long option without "--"; NULL ends the table */
    cli_kind kind;
    union {                          /* where the value goes (the member of the kind) */
        bool *flag;
        const char **str;
        cli_list *list;
        uint64_t *u;
        double *real;
        int *choice;
        void *custom;
    } to;
    const char *arg;                 /* the value's name in --help ("N", "FILE"); a
                                        CLI_CHOICE without one shows its choices a|b|c */
    uint64_t min, max;               /* CLI_UINT */
    double lo, hi;                   /* CLI_REAL */
    bool lo_open;                    /* CLI_REAL: lo itself is not allowed */
    const char *const *choices;      /* CLI_CHOICE: NULL-terminated */
    cli_parse_fn parse;              /* CLI_CUSTOM */
    const char *def;                 /* default as typed on the command line; NULL: none
                                        (false, NULL, 0, no items) */
    const char *what;                /* what is allowed, for a bad value, when the tool's
                                        phrase for the kind does not fit: a printf format,
                                        its one %s (if any) the range or the choices */
    bool *given;                     /* set to true when the option is on the command line */
    bool stops;                      /* an action of its own: parsing stops after it */
    const char *help;                /* --help text (NULL: listed in the synopsis only; ""
                                        listed without text); a "\n" continues at the help
                                        column; {default} and {range} are the row's */
} cli_opt;

/* How a tool words its usage and its messages. */
typedef struct cli_tool {
    const char *name;                /* "rtsim": the first word of every message */
    const cli_opt *opts;             /* the table */
    /* --help: synopsis (if any), about, the options with help text, footer */
    const char *synopsis;            /* "usage: rtsim [SCENE]": followed by every option as
                                        "[--name ARG]", wrapped at `width`; NULL: none */
    int width;
    const char *about;               /* text after the synopsis */
    int indent, column;              /* options at `indent`, their help at `column` */
    const char *footer;
    /* messages (printf formats of %s arguments) */
    const char *bad_value;           /* option, value, what is allowed */
    const char *uint_what;           /* %s = "min..max" */
    const char *real_what;           /* %s = "lo..hi" or "lo < ARG <= hi" */
    const char *choice_what;         /* %s = "a, b, c" */
    const char *unknown;             /* %s = the option; NULL: getopt's own message */
    const char *missing;             /* %s = the option; NULL: as unknown */
    const char *hint;                /* line after a bad-usage message; NULL: the usage */
    bool unknown_shows_usage;        /* an unknown option is followed by the usage */
} cli_tool;

/* Sets every destination to its default, then reads the options of argv.
 * Returns CLI_GO_ON with *args the index of the first argument that is not
 * an option (after a `stops` option: the next one), or the exit status
 * (0 after --help or --version, 2 after a message). The lists' arrays are
 * the caller's to free in any case. */
int cli_parse(const cli_tool *t, int argc, char **argv, int *args);

/* The usage (--help): synopsis, about, each option with its help, footer. */
void cli_usage(const cli_tool *t, FILE *out);

/* "TOOL: message", then the hint line (or the usage when the tool has no
 * hint), on stderr. Returns 2, the exit status of bad usage. */
int cli_usage_error(const cli_tool *t, const char *fmt, ...);

/* A decimal integer in min..max (digits only: no sign, no blank). */
bool cli_parse_u64(const char *text, uint64_t min, uint64_t max, uint64_t *out);

#endif
