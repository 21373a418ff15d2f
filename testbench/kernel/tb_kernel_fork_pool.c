/* tb_kernel_fork_pool — independent pieces in worker processes
 * (kernel/fork_pool.h): results in piece order and the same whatever the
 * number of workers; a worker's other memory writes are lost; the
 * lowest-indexed failure is reported with its message; a worker that dies
 * is reported, not waited for forever, and one that calls exit() leaves the
 * parent's planned output files alone; SIGINT to the parent while workers
 * run stops them and returns 130; workers' CPU is counted as children's. */
#include <signal.h>
#include <string.h>
#include <unistd.h>

#include "kernel/fork_pool.h"
#include "kernel/interrupt.h"
#include "kernel/out_file.h"
#include "testbench/tb.h"

typedef struct piece_res {
    uint64_t value;
    int index;
} piece_res;

static int g_touched;   /* written by pieces: lost when they run in workers */

/* A deterministic function of the index, with some work in it. */
typedef struct progress_seen {
    int calls, last_done, total;
    bool rising;
} progress_seen;

static void count_progress(void *user, int done, int total)
{
    progress_seen *p = user;
    p->rising = p->rising && done == p->last_done + 1;
    p->calls++, p->last_done = done, p->total = total;
}

static int work_piece(void *user, int index, void *result, char *err, size_t errlen)
{
    (void)err, (void)errlen;
    const int *fail = user;
    piece_res *r = result;
    uint64_t x = 0x9e3779b97f4a7c15ULL * (uint64_t)(index + 1);
    for (int i = 0; i < 200000; i++)
        x = x * 6364136223846793005ULL + 1442695040888963407ULL;
    r->value = x;
    r->index = index;
    g_touched = 1;
    if (fail && (index == fail[0] || index == fail[1])) {
        snprintf(err, errlen, "piece %d failed", index);
        return 2 + index;
    }
    return 0;
}

static int dying_piece(void *user, int index, void *result, char *err, size_t errlen)
{
    (void)user, (void)err, (void)errlen;
    memset(result, 0, sizeof(piece_res));
    if (index == 1)
        raise(SIGKILL);
    return 0;
}

/* A library's fatal error: exit() runs the atexit handlers in the worker. */
static int exiting_piece(void *user, int index, void *result, char *err, size_t errlen)
{
    (void)user, (void)err, (void)errlen;
    memset(result, 0, sizeof(piece_res));
    if (index == 0)
        exit(3);
    return 0;
}

/* Piece 0 sends SIGINT to the parent, then every piece waits (long enough
 * that only the parent's stopping ends it). */
static int interrupting_piece(void *user, int index, void *result, char *err, size_t errlen)
{
    (void)err, (void)errlen;
    memset(result, 0, sizeof(piece_res));
    if (index == 0)
        kill(*(pid_t *)user, SIGINT);
    sleep(20);
    return 0;
}

int main(void)
{
    enum { N = 7 };
    piece_res ref[N], got[N];

    tb_begin("pool_in_process_in_order");
    memset(ref, 0, sizeof ref);
    g_touched = 0;
    uint64_t forked0 = ks_pool_workers_forked();
    char err[TB_ERR_MAX] = "";
    TB_EQ_INT(ks_pool_run(N, 1, sizeof(piece_res), work_piece, NULL, ref, err, sizeof err), 0);
    for (int i = 0; i < N; i++)
        TB_EQ_INT(ref[i].index, i);
    TB_EQ_INT(g_touched, 1);
    TB_EQ_INT(ks_pool_workers_forked(), forked0);
    tb_end();

    for (int jobs = 2; jobs <= 8; jobs += 3) {
        char name[64];
        snprintf(name, sizeof name, "pool_%d_workers_same_results", jobs);
        tb_begin(name);
        memset(got, 0xab, sizeof got);
        g_touched = 0;
        forked0 = ks_pool_workers_forked();
        double cpu0 = ks_pool_children_cpu_s();
        TB_EQ_INT(ks_pool_run(N, jobs, sizeof(piece_res), work_piece, NULL, got, err, sizeof err), 0);
        TB_CHECK(!memcmp(got, ref, sizeof got), "results differ from the in-process run");
        TB_EQ_INT(g_touched, 0);   /* the workers' own writes stay in the workers */
        TB_EQ_INT(ks_pool_workers_forked() - forked0, N);
        TB_CHECK(ks_pool_children_cpu_s() >= cpu0, "children's CPU went down");
        tb_end();
    }

    /* the progress hook: called once per piece, the count rising to N, in
     * this process whether the pieces ran here or in workers */
    for (int jobs = 1; jobs <= 3; jobs += 2) {
        char name[64];
        snprintf(name, sizeof name, "pool_%d_progress_hook_per_piece", jobs);
        tb_begin(name);
        progress_seen ps = {0, 0, 0, true};
        ks_pool_set_progress(count_progress, &ps);
        TB_EQ_INT(ks_pool_run(N, jobs, sizeof(piece_res), work_piece, NULL, got, err, sizeof err), 0);
        ks_pool_set_progress(NULL, NULL);
        TB_EQ_INT(ps.calls, N);
        TB_EQ_INT(ps.last_done, N);
        TB_EQ_INT(ps.total, N);
        TB_CHECK(ps.rising, "the count of pieces ended did not rise by one per call");
        tb_end();
    }

    tb_begin("pool_lowest_failure_reported");
    for (int jobs = 1; jobs <= 4; jobs += 3) {
        int fail[2] = {5, 3};
        err[0] = 0;
        int rc = ks_pool_run(N, jobs, sizeof(piece_res), work_piece, fail, got, err, sizeof err);
        TB_EQ_INT(rc, 2 + 3);
        TB_CHECK(!strcmp(err, "piece 3 failed"), "jobs %d: message '%s'", jobs, err);
    }
    tb_end();

    tb_begin("pool_dead_worker_reported");
    err[0] = 0;
    TB_EQ_INT(ks_pool_run(3, 3, sizeof(piece_res), dying_piece, NULL, got, err, sizeof err), 1);
    TB_CHECK(strstr(err, "(piece 1) was killed by signal 9") != NULL, "message '%s'", err);
    tb_end();

    tb_begin("pool_worker_exit_keeps_parent_outputs");
    {
        char path[TB_PATH_MAX], tmp[TB_PATH_MAX + 16];
        const char *dir = getenv("RTSIM_TMP") ? getenv("RTSIM_TMP") : "/tmp";
        tb_pathf(path, sizeof path, "%s/tb_kernel_fork_pool.%d.json", dir, (int)getpid());
        tb_pathf(tmp, sizeof tmp, "%s.tmp.%d", path, (int)getpid());
        ks_out *o = ks_out_plan("--json", path, err, sizeof err);
        TB_CHECK(o != NULL, "plan: %s", err);
        err[0] = 0;
        TB_EQ_INT(ks_pool_run(2, 2, sizeof(piece_res), exiting_piece, NULL, got, err, sizeof err), 1);
        TB_CHECK(strstr(err, "(piece 0) exited with status 3") != NULL, "message '%s'", err);
        TB_CHECK(access(tmp, F_OK) == 0, "the worker's exit removed the parent's temporary %s", tmp);
        if (o)
            ks_out_discard(o);
        TB_CHECK(access(tmp, F_OK) != 0, "%s left after discard", tmp);
    }
    tb_end();

    tb_begin("pool_sigint_stops_workers");
    ks_interrupt_install("tb_kernel_fork_pool");
    pid_t self = getpid();
    err[0] = 0;
    int rc = ks_pool_run(3, 3, sizeof(piece_res), interrupting_piece, &self, got, err, sizeof err);
    TB_EQ_INT(rc, 130);
    TB_CHECK(strstr(err, "interrupted by SIGINT") != NULL, "message '%s'", err);
    TB_CHECK(!ks_interrupt_polling(false), "the polling phase was not left");
    ks__interrupt_signal = 0;
    signal(SIGINT, SIG_DFL);
    tb_end();

    tb_begin("pool_cpus_positive");
    TB_CHECK(ks_pool_cpus() >= 1, "%d CPUs", ks_pool_cpus());
    tb_end();
    return tb_finish();
}
