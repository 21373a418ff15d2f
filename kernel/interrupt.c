/* interrupt.c — SIGINT/SIGTERM handling (contract in interrupt.h). */
#include "kernel/interrupt.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "kernel/out_file.h"

volatile sig_atomic_t ks__interrupt_signal;
static volatile sig_atomic_t g_polling;
static char g_msg_int[160], g_msg_term[160];

const char *ks_interrupt_name(int sig)
{
    return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "signal";
}

int ks_interrupt_exit_status(void) { return 128 + ks__interrupt_signal; }

static void on_signal(int sig)
{
    if (g_polling && !ks__interrupt_signal) {
        ks__interrupt_signal = sig;
        return;
    }
    /* nothing to finish (or asked twice): only async-signal-safe calls */
    ks_out_remove_temps_signal_safe();
    const char *m = sig == SIGINT ? g_msg_int : g_msg_term;
    ssize_t w = write(2, m, strlen(m));
    (void)w;
    _exit(128 + sig);
}

void ks_interrupt_install(const char *tool)
{
    snprintf(g_msg_int, sizeof g_msg_int, "\n%.60s: interrupted by SIGINT; temporary files removed\n", tool);
    snprintf(g_msg_term, sizeof g_msg_term, "\n%.60s: interrupted by SIGTERM; temporary files removed\n", tool);
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}

bool ks_interrupt_polling(bool on)
{
    bool was = g_polling != 0;
    g_polling = on;
    return was;
}
