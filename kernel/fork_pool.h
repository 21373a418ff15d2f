/* fork_pool.h — independent pieces of work run in parallel, each in a worker
 * process forked from this one, each handing back a fixed-size result of
 * plain data through a pipe (docs/kernel.md "Worker processes").
 *
 * Contract:
 *  - ks_pool_run(n, jobs, size, fn, user, results, err, errlen) calls
 *    fn(user, i, results + i * size, err, errlen) for every piece i in 0..n-1
 *    and returns once all are done. fn returns 0 or a non-zero status with a
 *    message in err.
 *  - jobs <= 1 or n <= 1: in this process, in index order, stopping at the
 *    first failure. Otherwise every piece runs in its own child process
 *    (fork), at most `jobs` at once, started in index order; the child's
 *    result bytes are copied to results + i * size when it ends. So a piece
 *    sees memory as it was at the call, and its changes to memory other
 *    than its result are lost: the results are the same whatever `jobs`
 *    when fn depends only on its inputs. A result must be plain data;
 *    pointers in it may point only to what parent and child share (string
 *    literals, memory made before the call). A worker has one thread: a
 *    piece must not rely on a thread pool its library started before the
 *    fork (rtsim's pieces are single-threaded C: model, tracer traversal).
 *  - Returns 0; else the status of the lowest-indexed failed piece with its
 *    message (after a failure no further piece is started; those running
 *    finish); 1 when a worker died (a crash, killed) or its result was cut
 *    short; 128 + the signal when this process received SIGINT/SIGTERM
 *    (kernel/interrupt.h) while waiting: the workers are killed and reaped
 *    before the return, err says "interrupted by SIGINT".
 *  - Workers: stdio is flushed before each fork; a worker takes SIGINT and
 *    SIGTERM's default action (a Ctrl-C reaches the whole process group:
 *    the workers die, the parent stops the rest and reports), dies with its
 *    parent (Linux PR_SET_PDEATHSIG) and ends with _exit: no atexit
 *    handlers run, so the parent's output files (kernel/out_file.h) and
 *    stdio buffers are never touched by a worker; a piece that calls
 *    exit(status) ends its worker at once with _exit(status) (library exit
 *    handlers in a forked copy may wait for the parent's threads forever).
 *  - Every worker is reaped before ks_pool_run returns, so their CPU time is
 *    in getrusage(RUSAGE_CHILDREN): ks_pool_children_cpu_s().
 * Not thread-safe (one pool at a time per process). */
#ifndef KS_FORK_POOL_H
#define KS_FORK_POOL_H

#include <stddef.h>
#include <stdint.h>

typedef int (*ks_pool_fn)(void *user, int index, void *result, char *err, size_t errlen);

int ks_pool_run(int n, int jobs, size_t result_size, ks_pool_fn fn, void *user, void *results, char *err,
                size_t errlen);

/* Progress: after each piece ends (in this process or in a worker, seen
 * from this process), fn(user, pieces ended, pieces of the run) is called;
 * NULL removes it. One hook per process, as there is one pool at a time. */
typedef void (*ks_pool_progress_fn)(void *user, int done, int total);
void ks_pool_set_progress(ks_pool_progress_fn fn, void *user);

/* The CPUs this process may run on (sched_getaffinity: honours taskset and
 * cgroup cpusets), at least 1; the online CPUs when that fails. */
int ks_pool_cpus(void);
/* Worker processes forked by ks_pool_run since the start of the process. */
uint64_t ks_pool_workers_forked(void);
/* User + system CPU seconds of the reaped children of this process. */
double ks_pool_children_cpu_s(void);
/* CPU seconds of this process and of its reaped children: a run's whole
 * cost in CPU, workers included, however many cores ran it. */
double ks_pool_process_cpu_s(void);

#endif
