/* progress.c — the terminal progress bar (cli/progress.h). */
#include <time.h>

#include "cli/progress.h"
#include "cli/run_info.h"

static double now(void) { return cli_run_clock(CLOCK_MONOTONIC); }

void cli_progress_start(cli_progress *p, bool on)
{
    p->on = on;
    p->t0 = p->last = now();
}

bool cli_progress_due(cli_progress *p, double every)
{
    double t = now();
    if (t - p->last < every)
        return false;
    p->last = t;
    return true;
}

void cli_progress_bar(int filled, char bar[CLI_PROGRESS_CELLS + 1])
{
    for (int i = 0; i < CLI_PROGRESS_CELLS; i++)
        bar[i] = i < filled ? '#' : '.';
    bar[CLI_PROGRESS_CELLS] = 0;
}

double cli_progress_eta(const cli_progress *p, double fraction)
{
    return fraction > 0 ? (now() - p->t0) * (1.0 - fraction) / fraction : 0.0;
}

double cli_progress_elapsed(const cli_progress *p) { return now() - p->t0; }
