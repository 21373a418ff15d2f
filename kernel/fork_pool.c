/* fork_pool.c — pieces of work in forked worker processes (fork_pool.h). */
#include "kernel/fork_pool.h"

#include <errno.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

#include "kernel/interrupt.h"

/* What a worker writes to its pipe: this header, then the result bytes. */
typedef struct pool_msg {
    int32_t rc;
    char err[1024];
} pool_msg;

/* A running worker. */
typedef struct pool_worker {
    pid_t pid;
    int fd;                       /* read end of its pipe; -1 once at EOF */
    int index;                    /* the piece it runs */
    unsigned char *buf;           /* pool_msg + result */
    size_t got;
} pool_worker;

static uint64_t g_forked;
static ks_pool_progress_fn g_progress;
static void *g_progress_user;

void ks_pool_set_progress(ks_pool_progress_fn fn, void *user) { g_progress = fn, g_progress_user = user; }

/* A piece ended (in this process or a worker): tell the progress hook. */
static void piece_done(int done, int n)
{
    if (g_progress)
        g_progress(g_progress_user, done, n);
}

uint64_t ks_pool_workers_forked(void) { return g_forked; }

double ks_pool_children_cpu_s(void)
{
    struct rusage ru;
    if (getrusage(RUSAGE_CHILDREN, &ru))
        return 0;
    return (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec + (double)ru.ru_stime.tv_sec +
           1e-6 * (double)ru.ru_stime.tv_usec;
}

double ks_pool_process_cpu_s(void)
{
    struct timespec t;
    double self = clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t) == 0 ? (double)t.tv_sec + 1e-9 * (double)t.tv_nsec : 0;
    return self + ks_pool_children_cpu_s();
}

int ks_pool_cpus(void)
{
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0)
        return CPU_COUNT(&set);
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}

static int run_in_process(int n, size_t size, ks_pool_fn fn, void *user, void *results, char *err, size_t errlen)
{
    for (int i = 0; i < n; i++) {
        int rc = fn(user, i, (unsigned char *)results + (size_t)i * size, err, errlen);
        if (rc)
            return rc;
        piece_done(i + 1, n);
    }
    return 0;
}

/* Writes all of buf (a pipe: short writes continue). */
static int write_all(int fd, const void *buf, size_t len)
{
    const unsigned char *p = buf;
    while (len) {
        ssize_t w = write(fd, p, len);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return -1;
        p += w, len -= (size_t)w;
    }
    return 0;
}

/* A piece that calls exit() (a library's fatal error) ends the worker here,
 * before any other exit handler: those of the parent's libraries may wait
 * for threads that a forked copy does not have (liblog4cplus, which
 * OpenImageIO pulls in, waits forever so under ASan), and the output layer's
 * belong to the parent. Handlers registered later run first (on_exit is
 * glibc's atexit with the status). */
static void worker_on_exit(int status, void *arg)
{
    (void)arg;
    _exit(status);
}

/* The child's side: runs piece i, writes the message and the result, exits
 * without running atexit handlers or flushing the parent's stdio. */
static void worker_main(int fd, int i, size_t size, ks_pool_fn fn, void *user, pid_t parent)
{
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    on_exit(worker_on_exit, NULL);
#ifdef __linux__
    prctl(PR_SET_PDEATHSIG, SIGKILL);
#endif
    if (getppid() != parent)   /* the parent died before prctl */
        _exit(1);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, NULL);
    pool_msg *m = calloc(1, sizeof *m);
    unsigned char *res = calloc(1, size ? size : 1);
    if (!m || !res)
        _exit(3);
    m->rc = fn(user, i, res, m->err, sizeof m->err);
    m->err[sizeof m->err - 1] = 0;
    int bad = write_all(fd, m, sizeof *m) || write_all(fd, res, size);
    _exit(bad ? 4 : 0);
}

/* Why worker w failed, from its wait status. */
static void describe_death(const pool_worker *w, int status, size_t want, char *err, size_t errlen)
{
    if (WIFSIGNALED(status))
        snprintf(err, errlen, "worker process %d (piece %d) was killed by signal %d", (int)w->pid, w->index,
                 WTERMSIG(status));
    else if (WIFEXITED(status) && WEXITSTATUS(status))
        snprintf(err, errlen, "worker process %d (piece %d) exited with status %d", (int)w->pid, w->index,
                 WEXITSTATUS(status));
    else
        snprintf(err, errlen, "worker process %d (piece %d) handed back %zu of %zu bytes", (int)w->pid, w->index,
                 w->got, want);
}

static void stop_all(pool_worker *w, int nw)
{
    for (int k = 0; k < nw; k++)
        if (w[k].pid > 0)
            kill(w[k].pid, SIGKILL);
    for (int k = 0; k < nw; k++)
        if (w[k].pid > 0) {
            while (waitpid(w[k].pid, NULL, 0) < 0 && errno == EINTR) {
            }
            w[k].pid = 0;
        }
}

int ks_pool_run(int n, int jobs, size_t result_size, ks_pool_fn fn, void *user, void *results, char *err,
                size_t errlen)
{
    if (jobs <= 1 || n <= 1)
        return run_in_process(n, result_size, fn, user, results, err, errlen);
    if (jobs > n)
        jobs = n;
    const size_t want = sizeof(pool_msg) + result_size;
    pool_worker *w = calloc((size_t)jobs, sizeof *w);
    struct pollfd *pfd = calloc((size_t)jobs, sizeof *pfd);
    int *slot_of = calloc((size_t)jobs, sizeof *slot_of);
    char *fail_msg = calloc(1, errlen ? errlen : 1);
    if (!w || !pfd || !slot_of || !fail_msg) {
        free(w), free(pfd), free(slot_of), free(fail_msg);
        snprintf(err, errlen, "out of memory");
        return 2;
    }
    for (int k = 0; k < jobs; k++)
        w[k].fd = -1;
    int fail_rc = 0, fail_index = n;   /* the lowest-indexed failure so far */
    int next = 0, running = 0, rc = 0, done = 0;
    bool was_polling = ks_interrupt_polling(true);   /* a signal is recorded: we stop the workers */
    const pid_t self = getpid();
    for (;;) {
        /* start pieces while there is room and nothing has failed */
        while (running < jobs && next < n && !fail_rc && !ks_interrupted()) {
            int k = 0;
            while (w[k].pid > 0)
                k++;
            int p[2];
            if (!(w[k].buf = malloc(want)) || pipe(p)) {
                free(w[k].buf), w[k].buf = NULL;
                snprintf(fail_msg, errlen, "cannot start a worker process: %s", strerror(errno ? errno : ENOMEM));
                fail_rc = 2, fail_index = next;
                break;
            }
            fflush(NULL);   /* nothing buffered is written twice */
            sigset_t block, old;
            sigemptyset(&block);
            sigaddset(&block, SIGINT);
            sigaddset(&block, SIGTERM);
            sigprocmask(SIG_BLOCK, &block, &old);   /* the child resets its handlers first */
            pid_t pid = fork();
            if (pid == 0) {
                close(p[0]);
                worker_main(p[1], next, result_size, fn, user, self);
            }
            int fork_errno = errno;
            sigprocmask(SIG_SETMASK, &old, NULL);
            close(p[1]);
            if (pid < 0) {
                close(p[0]);
                free(w[k].buf), w[k].buf = NULL;
                snprintf(fail_msg, errlen, "cannot start a worker process: %s", strerror(fork_errno));
                fail_rc = 2, fail_index = next;
                break;
            }
            g_forked++;
            w[k].pid = pid, w[k].fd = p[0], w[k].index = next++, w[k].got = 0;
            running++;
        }
        if (ks_interrupted()) {
            stop_all(w, jobs);
            snprintf(err, errlen, "interrupted by %s: worker processes stopped", ks_interrupt_name(ks_interrupted()));
            rc = ks_interrupt_exit_status();
            goto out;
        }
        if (!running)
            break;
        int np = 0;
        for (int k = 0; k < jobs; k++)
            if (w[k].pid > 0 && w[k].fd >= 0) {
                pfd[np].fd = w[k].fd, pfd[np].events = POLLIN, pfd[np].revents = 0;
                slot_of[np++] = k;
            }
        /* a bounded wait: the interrupt flag is checked at least every 0.1 s */
        int pr = poll(pfd, (nfds_t)np, 100);
        if (pr < 0 && errno != EINTR) {
            stop_all(w, jobs);
            snprintf(err, errlen, "waiting for worker processes: %s", strerror(errno));
            rc = 1;
            goto out;
        }
        for (int q = 0; pr > 0 && q < np; q++) {
            if (!pfd[q].revents)
                continue;
            pool_worker *x = &w[slot_of[q]];
            ssize_t r = read(x->fd, x->buf + x->got, want - x->got);
            if (r < 0 && errno == EINTR)
                continue;
            if (r > 0) {
                x->got += (size_t)r;
                if (x->got < want)
                    continue;
            }
            /* all bytes, EOF or a read error: the worker is finished */
            close(x->fd);
            x->fd = -1;
            int status = 0;
            while (waitpid(x->pid, &status, 0) < 0 && errno == EINTR) {
            }
            const pool_msg *m = (const pool_msg *)x->buf;
            int piece_rc;
            char msg[1100];
            if (x->got == want && WIFEXITED(status) && WEXITSTATUS(status) == 0) {
                piece_rc = m->rc;
                snprintf(msg, sizeof msg, "%s", m->err);
                if (!piece_rc)
                    memcpy((unsigned char *)results + (size_t)x->index * result_size, x->buf + sizeof(pool_msg),
                           result_size);
            } else {
                piece_rc = 1;
                describe_death(x, status, want, msg, sizeof msg);
            }
            if (piece_rc && x->index < fail_index) {
                fail_rc = piece_rc, fail_index = x->index;
                snprintf(fail_msg, errlen, "%s", msg);
            }
            free(x->buf);
            x->buf = NULL, x->pid = 0;
            running--;
            piece_done(++done, n);
        }
    }
    rc = fail_rc;
    if (rc)
        snprintf(err, errlen, "%s", fail_msg);
out:
    ks_interrupt_polling(was_polling);
    for (int k = 0; k < jobs; k++) {
        if (w[k].fd >= 0)
            close(w[k].fd);
        free(w[k].buf);
    }
    free(w), free(pfd), free(slot_of), free(fail_msg);
    return rc;
}
