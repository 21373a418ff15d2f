/* ini_file.h — the one INI file reader of rtsim, on Debian's inih: machine
 * files (config.c), the DRAM standard and its currents (model/dram), the
 * energy tables (model/energy) and the run-time estimate all read through it,
 * so they open files, count lines and word their errors the same way.
 *
 * Contract:
 *  - ini_file_read() opens PATH and calls the handler for every key = value in
 *    file order, with the section and, through ini_file_line(), the line.
 *  - It refuses, with one line "PATH:LINE: message" in err (the error of the
 *    lowest line wins): a syntax error, a line longer than inih's buffer
 *    (198 characters; inih would split it), a key outside a [section], a key given
 *    twice in a section ("section.key given twice (first at line N)", also
 *    across repeated headings), a section other than opts->section when that
 *    is set, and whatever the handler reports with ini_file_error().
 *  - Without a line: "PATH: cannot open: REASON", "PATH: is a folder, not
 *    WHAT (.ini) file", "PATH: more than 4 MiB, the most an INI file may
 *    hold" (read from a stream, it stops there: /dev/zero, a FIFO fed
 *    forever, /dev/urandom end in a refusal, never in a hang).
 *  - The handler returns 0 to go on, or -1 after ini_file_error(); it is not
 *    called again after an error.
 *  - Returns 0, or -1 with the message in err. Deterministic. */
#ifndef RTSIM_CONFIG_INI_FILE_H
#define RTSIM_CONFIG_INI_FILE_H

/* The most ini_file_read() reads of one file; every INI file of the project
 * (machines, DRAM standards and currents, energy tables) is a few KiB. */
#define INI_FILE_MAX_BYTES (4 << 20)

#include <stddef.h>

typedef struct ini_file ini_file;

typedef struct ini_file_opts {
    const char *what;     /* with its article: "a machine configuration" names the file in
                             "is a folder, not a machine configuration (.ini) file" */
    const char *section;  /* the only section the file may have, or NULL: any */
    const char *example;  /* a section to suggest for a key outside one (NULL: `section`) */
} ini_file_opts;

typedef int (*ini_file_fn)(ini_file *f, void *user, const char *section, const char *key, const char *value);

int ini_file_read(const char *path, const ini_file_opts *opts, ini_file_fn fn, void *user, char *err, size_t errlen);

const char *ini_file_path(const ini_file *f);
/* The line of the key being handled. */
int ini_file_line(const ini_file *f);
/* Reports "PATH:LINE: message" (the first report of a file stands); returns -1. */
int ini_file_error(ini_file *f, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* The index of key in keys[0..n-1], else reports "unknown key 'KEY' in
 * [SECTION] (allowed k0, k1, ...)" and returns -1. */
int ini_file_key_index(ini_file *f, const char *section, const char *key, const char *const *keys, int n);
/* Reads a whole value as a finite decimal number: 0, or -1 (not a number,
 * trailing text, out of double's range, NaN or infinity). */
int ini_file_number(const char *value, double *out);

#endif
