/* progress.h — the progress bar rtsim and rttrace draw on stderr when it is
 * a terminal: CLI_PROGRESS_CELLS cells, '#' for the part done and '.' for
 * the rest, redrawn in place at most every so often.
 *
 * Contract: cli_progress_start() records the start (host wall clock) and
 * whether to draw at all; cli_progress_due() says whether `every` seconds
 * have passed since the last drawing (and counts this one as drawn);
 * cli_progress_bar() fills the cells; cli_progress_eta() extrapolates the
 * time left from the fraction done (0 when nothing is done yet). */
#ifndef RTSIM_CLI_PROGRESS_H
#define RTSIM_CLI_PROGRESS_H

#include <stdbool.h>

#define CLI_PROGRESS_CELLS 30

typedef struct cli_progress {
    bool on;           /* draw (stderr is a terminal, the tool is not quiet) */
    double t0, last;   /* start and last drawing, host wall seconds */
} cli_progress;

void cli_progress_start(cli_progress *p, bool on);
bool cli_progress_due(cli_progress *p, double every);
/* The first `filled` cells '#' (clamped to 0..CLI_PROGRESS_CELLS), the rest '.'. */
void cli_progress_bar(int filled, char bar[CLI_PROGRESS_CELLS + 1]);
double cli_progress_eta(const cli_progress *p, double fraction);
/* Seconds since cli_progress_start. */
double cli_progress_elapsed(const cli_progress *p);

#endif
