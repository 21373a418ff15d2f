/* out_file.h — the output layer of the tools (rtsim, rttrace, rtdram) and of
 * the VCD writer: every output file of a run goes through it, so no output
 * is destroyed, left half-written, or found unwritable only after the run.
 *
 * Contract:
 *  - ks_out_plan(opt, path) is called for every output before any work is
 *    done. It checks the path, classifies it and reserves it:
 *      "-", /dev/stdout, /dev/stderr, /dev/fd/N, /proc/self/fd/N: that open
 *        descriptor (duplicated, so the offset is shared), written in place;
 *      an existing device, named pipe or socket (also through a symlink):
 *        opened for writing now (a pipe waits for its reader), in place;
 *      a regular file or a new name (a symlink to a regular file: its
 *        target; the link is kept): the temporary file "TARGET.tmp.PID" is
 *        created now beside the target and renamed over it on commit.
 *    Refused, with "OPT PATH: why" in err: an empty name, a folder, a
 *    missing or unwritable folder, a dangling symlink, a name too long for
 *    its temporary, and a path naming the same file as an earlier plan
 *    (same device and inode, or the same resolved name; character devices
 *    such as /dev/null may be shared).
 *  - Stream writers: ks_out_begin() gives the FILE* to write; ks_out_commit()
 *    closes it and renames the temporary into place (in place: flushes).
 *  - Writers that open a file by name (images, trace logs): ks_out_stage()
 *    gives the name to write: the temporary, with the target's extension
 *    appended so the writer picks its format ("a.png.tmp.PID.png"); for an
 *    in-place target a file in $TMPDIR (default /tmp) that commit copies in.
 *  - ks_out_discard() closes and removes the temporary (an in-place output
 *    keeps what was written: it cannot be taken back).
 *  - ks_out_find(path, opt): the live plan of path made for option opt, so
 *    a library writer given only a path (the VCD writer: opt "--vcd") uses
 *    the tool's plan; NULL if none. Character devices may be planned twice
 *    (--json /dev/null --vcd /dev/null): the option tells the plans apart.
 *  - ks_out_remove_temps_signal_safe(): unlinks every temporary not yet
 *    committed using only async-signal-safe calls (the interrupt handler);
 *    ks_out_discard_all() does the same from normal code.
 *  - Only the process that made the plans removes their temporaries (at
 *    exit, on a signal): a forked worker (fork_pool.h) that calls exit()
 *    leaves its parent's outputs alone.
 * Plans live until the process ends (a tool makes a handful). Not
 * thread-safe. */
#ifndef KS_OUT_FILE_H
#define KS_OUT_FILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

typedef struct ks_out ks_out;

ks_out *ks_out_plan(const char *opt, const char *path, char *err, size_t errlen);
ks_out *ks_out_find(const char *path, const char *opt);
/* True when the output is written in place (stdout, a device, a pipe). */
bool ks_out_in_place(const ks_out *o);

FILE *ks_out_begin(ks_out *o, char *err, size_t errlen);
const char *ks_out_stage(ks_out *o, char *err, size_t errlen);
/* 0, or -1 with "OPT PATH: why" in err (the temporary is removed). */
int ks_out_commit(ks_out *o, char *err, size_t errlen);
void ks_out_discard(ks_out *o);
void ks_out_discard_all(void);
void ks_out_remove_temps_signal_safe(void);

#endif
