/* out_file.c — the output layer (contract in out_file.h). */
#include "kernel/out_file.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* A tool has at most a handful of outputs (rtsim: json, vcd, heatmap,
 * autosize; rttrace: six). */
#define OUT_MAX 16
#define OUT_PATH 4096 /* PATH_MAX on Linux */
/* The longest output name: PATH_MAX less room for the temporary names
 * derived from it (".tmp.PID" twice, 2 x 17, and an extension up to 21). */
#define OUT_NAME_MAX (OUT_PATH - 1 - 56)

enum { KIND_TEMP, KIND_IN_PLACE };

struct ks_out {
    char opt[40];
    char path[OUT_PATH];      /* as given */
    char target[OUT_PATH];    /* KIND_TEMP: the resolved file replaced on commit */
    char tmp[OUT_PATH + 64];  /* the temporary (or staged) name */
    char inner[OUT_PATH + 96];/* the name a writer of this repo derives from a staged name */
    int kind;
    int fd;                   /* reserved descriptor until begin (-1 after) */
    FILE *f;
    bool staged;
    bool chr;                 /* a character device: may be shared */
    bool has_id;
    dev_t dev;
    ino_t ino;
    volatile sig_atomic_t live;     /* planned, not yet committed or discarded */
    volatile sig_atomic_t tmp_live; /* tmp (and inner) may exist on disk */
};

static ks_out g_outs[OUT_MAX];
static int g_nouts;
static bool g_atexit;
static pid_t g_owner;     /* the process that planned the outputs (a forked worker is not it) */

/* dst = a followed by suffix. Both names live in one ks_out: copied by
 * length, as gcc -O1's -Wrestrict flags an snprintf between members of one
 * object (a false positive: the members do not overlap). */
static void join(char *dst, size_t cap, const char *a, const char *suffix)
{
    size_t n = strlen(a);
    if (n >= cap)
        n = cap - 1;
    memmove(dst, a, n);
    snprintf(dst + n, cap - n, "%s", suffix);
}

static int fail(char *err, size_t errlen, const ks_out *o, const char *fmt, const char *a, const char *b)
{
    int n = snprintf(err, errlen, "%s %s: ", o->opt, o->path);
    if (n >= 0 && (size_t)n < errlen)
        snprintf(err + n, errlen - (size_t)n, fmt, a, b);
    return -1;
}

/* The descriptor a path names directly ("-", /dev/stdout, /dev/fd/N...), or -1. */
static int alias_fd(const char *p)
{
    if (!strcmp(p, "-") || !strcmp(p, "/dev/stdout"))
        return 1;
    if (!strcmp(p, "/dev/stderr"))
        return 2;
    const char *num = NULL;
    if (!strncmp(p, "/dev/fd/", 8))
        num = p + 8;
    else if (!strncmp(p, "/proc/self/fd/", 14))
        num = p + 14;
    if (!num || *num < '0' || *num > '9')
        return -1;
    char *end;
    long v = strtol(num, &end, 10);
    return *end || v > INT_MAX ? -1 : (int)v;
}

static const char *extension(const char *path)
{
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    /* a long "extension" is part of a name, not a format */
    return dot && (!slash || dot > slash) && dot[1] && strlen(dot) <= 21 ? dot : "";
}

/* Another live plan naming the same file, or NULL. */
static const ks_out *same_file(const ks_out *o)
{
    for (int i = 0; i < g_nouts; i++) {
        const ks_out *p = &g_outs[i];
        if (p == o || !p->live)
            continue;
        if (o->kind == KIND_TEMP && p->kind == KIND_TEMP && !strcmp(o->target, p->target))
            return p;
        if (o->has_id && p->has_id && o->dev == p->dev && o->ino == p->ino && !(o->chr && p->chr))
            return p;
    }
    return NULL;
}

/* Only in the process that made the plans: a forked worker that calls
 * exit() (kernel/fork_pool.h) must not remove its parent's temporaries. */
static void out_atexit(void)
{
    if (getpid() == g_owner)
        ks_out_discard_all();
}

ks_out *ks_out_plan(const char *opt, const char *path, char *err, size_t errlen)
{
    if (g_nouts == OUT_MAX) {
        /* reuse a finished slot */
        int i = 0;
        while (i < OUT_MAX && g_outs[i].live)
            i++;
        if (i == OUT_MAX) {
            snprintf(err, errlen, "%s: too many outputs (at most %d)", opt, OUT_MAX);
            return NULL;
        }
        g_outs[i] = g_outs[--g_nouts];
    }
    ks_out *o = &g_outs[g_nouts];
    memset(o, 0, sizeof *o);
    o->fd = -1;
    snprintf(o->opt, sizeof o->opt, "%s", opt ? opt : "output");
    if (!path || !*path) {
        snprintf(err, errlen, "%s: empty file name", o->opt);
        return NULL;
    }
    if (strlen(path) > OUT_NAME_MAX) {
        snprintf(err, errlen, "%s %.64s...: path longer than %d characters", o->opt, path, OUT_NAME_MAX);
        return NULL;
    }
    memcpy(o->path, path, strlen(path) + 1);
    struct stat st;
    int afd = alias_fd(path);
    if (afd >= 0) {
        if (fstat(afd, &st) != 0 || (fcntl(afd, F_GETFL) & O_ACCMODE) == O_RDONLY) {
            fail(err, errlen, o, "descriptor %s is not open for writing%s", afd == 1 ? "1 (stdout)" : "", "");
            return NULL;
        }
        o->kind = KIND_IN_PLACE;
        o->fd = dup(afd);
    } else if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
        if (S_ISDIR(st.st_mode)) {
            fail(err, errlen, o, "is a folder (give a file name)%s%s", "", "");
            return NULL;
        }
        /* a device, a named pipe or a socket: written where it is */
        o->kind = KIND_IN_PLACE;
        o->fd = open(path, O_WRONLY | O_NOCTTY | O_CLOEXEC);
        if (o->fd < 0) {
            fail(err, errlen, o, "cannot open for writing: %s%s", strerror(errno), "");
            return NULL;
        }
    } else {
        o->kind = KIND_TEMP;
        struct stat lst;
        if (lstat(path, &lst) == 0 && S_ISLNK(lst.st_mode) && stat(path, &st) != 0) {
            fail(err, errlen, o, "is a symbolic link to a missing file%s%s", "", "");
            return NULL;
        }
        bool exists = stat(path, &st) == 0;
        if (exists) {
            /* a regular file, or a symlink to one: replace the target, keep the link */
            if (!realpath(path, o->target)) {
                fail(err, errlen, o, "cannot resolve: %s%s", strerror(errno), "");
                return NULL;
            }
        } else {
            char dir[OUT_PATH], rdir[OUT_PATH];
            const char *slash = strrchr(path, '/');
            const char *base = slash ? slash + 1 : path;
            if (slash)
                snprintf(dir, sizeof dir, "%.*s", slash == path ? 1 : (int)(slash - path), path);
            else
                snprintf(dir, sizeof dir, ".");
            struct stat dst;
            if (!*base) {
                fail(err, errlen, o, "is a folder (give a file name)%s%s", "", "");
                return NULL;
            }
            if (stat(dir, &dst) != 0 || !S_ISDIR(dst.st_mode) || !realpath(dir, rdir)) {
                fail(err, errlen, o, "folder %s does not exist%s", dir, "");
                return NULL;
            }
            if (snprintf(o->target, sizeof o->target, "%s/%s", strcmp(rdir, "/") ? rdir : "", base) >=
                (int)sizeof o->target) {
                fail(err, errlen, o, "path too long once resolved%s%s", "", "");
                return NULL;
            }
        }
        if (strlen(o->target) > OUT_NAME_MAX) {
            snprintf(err, errlen, "%s %.64s...: path longer than %d characters (resolved: %zu)", o->opt, path,
                     OUT_NAME_MAX, strlen(o->target));
            return NULL;
        }
        char suffix[32];
        snprintf(suffix, sizeof suffix, ".tmp.%ld", (long)getpid());
        join(o->tmp, sizeof o->tmp, o->target, suffix);
        o->fd = open(o->tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
        if (o->fd < 0) {
            const char *why = errno == EACCES || errno == EROFS ? "folder is not writable" : strerror(errno);
            fail(err, errlen, o, "cannot create a file there (%s)%s", why, "");
            return NULL;
        }
        o->tmp_live = 1;
    }
    if (o->fd < 0) {
        fail(err, errlen, o, "cannot open: %s%s", strerror(errno), "");
        return NULL;
    }
    if (o->kind == KIND_IN_PLACE ? fstat(o->fd, &st) == 0 : stat(o->target, &st) == 0) {
        o->has_id = true;
        o->dev = st.st_dev;
        o->ino = st.st_ino;
        o->chr = S_ISCHR(st.st_mode);
    }
    const ks_out *dup_of = same_file(o);
    if (dup_of) {
        char other[sizeof dup_of->opt + OUT_PATH + 1];
        snprintf(other, sizeof other, "%s %s", dup_of->opt, dup_of->path);
        close(o->fd);
        if (o->tmp_live)
            unlink(o->tmp);
        fail(err, errlen, o, "names the same file as %s (each output needs its own file)%s", other, "");
        return NULL;
    }
    o->live = 1;
    g_nouts++;
    if (!g_atexit) {
        atexit(out_atexit);
        g_atexit = true;
        g_owner = getpid();
    }
    return o;
}

ks_out *ks_out_find(const char *path, const char *opt)
{
    for (int i = 0; path && opt && i < g_nouts; i++)
        if (g_outs[i].live && !g_outs[i].f && !g_outs[i].staged && !strcmp(g_outs[i].path, path) &&
            !strcmp(g_outs[i].opt, opt))
            return &g_outs[i];
    return NULL;
}

bool ks_out_in_place(const ks_out *o) { return o->kind == KIND_IN_PLACE; }

FILE *ks_out_begin(ks_out *o, char *err, size_t errlen)
{
    if (o->f)
        return o->f;
    o->f = o->fd >= 0 ? fdopen(o->fd, "wb") : NULL;
    if (!o->f) {
        fail(err, errlen, o, "cannot open: %s%s", strerror(errno), "");
        return NULL;
    }
    o->fd = -1;
    return o->f;
}

const char *ks_out_stage(ks_out *o, char *err, size_t errlen)
{
    if (o->staged)
        return o->tmp;
    if (o->kind == KIND_TEMP) {
        /* the reserved temporary becomes the staged name with the target's
         * extension, so a writer choosing its format by name still can */
        char old[sizeof o->tmp];
        memcpy(old, o->tmp, sizeof old);
        char ext[32];
        snprintf(ext, sizeof ext, "%s", extension(o->target));
        join(o->tmp, sizeof o->tmp, old, ext);
        close(o->fd);
        o->fd = -1;
        if (strcmp(old, o->tmp) && rename(old, o->tmp) != 0) {
            unlink(old);
            o->tmp_live = 0;
            fail(err, errlen, o, "cannot create a file there (%s)%s", strerror(errno), "");
            return NULL;
        }
    } else {
        const char *dir = getenv("TMPDIR");
        const char *base = strrchr(o->path, '/') ? strrchr(o->path, '/') + 1 : o->path;
        static unsigned seq;
        /* the base name is cut to 200 bytes on purpose: the staging file's own
         * name must stay within NAME_MAX (255); the output keeps its name */
        if (snprintf(o->tmp, sizeof o->tmp, "%s/rtsim-out.%ld.%u.%.200s", dir && *dir ? dir : "/tmp", (long)getpid(),
                     seq++, base) >= (int)sizeof o->tmp) {
            fail(err, errlen, o, "TMPDIR %s: path too long for the staging file%s", dir, "");
            return NULL;
        }
        int fd = open(o->tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
        if (fd < 0) {
            fail(err, errlen, o, "cannot create the staging file %s: %s", o->tmp, strerror(errno));
            return NULL;
        }
        close(fd);
        o->tmp_live = 1;
    }
    /* the trace-log writer (tracer/log/trace_log_write.c) writes "NAME.tmp.PID" itself */
    char suffix[32];
    snprintf(suffix, sizeof suffix, ".tmp.%ld", (long)getpid());
    join(o->inner, sizeof o->inner, o->tmp, suffix);
    o->staged = true;
    return o->tmp;
}

static int copy_into(int from, int to)
{
    char buf[1 << 16];
    for (;;) {
        ssize_t n = read(from, buf, sizeof buf);
        if (n == 0)
            return 0;
        if (n < 0) {
            if (errno == EINTR)
                continue;
            return -1;
        }
        for (ssize_t done = 0; done < n;) {
            ssize_t w = write(to, buf + done, (size_t)(n - done));
            if (w < 0) {
                if (errno == EINTR)
                    continue;
                return -1;
            }
            done += w;
        }
    }
}

int ks_out_commit(ks_out *o, char *err, size_t errlen)
{
    if (!o->live)
        return 0;
    int rc = 0;
    if (o->f) {
        bool bad = fflush(o->f) != 0 || ferror(o->f);
        bad |= fclose(o->f) != 0;
        o->f = NULL;
        if (bad)
            rc = fail(err, errlen, o, "write error: %s%s", strerror(errno), "");
    } else if (o->staged && o->kind == KIND_IN_PLACE) {
        int from = open(o->tmp, O_RDONLY | O_CLOEXEC);
        if (from < 0 || copy_into(from, o->fd) != 0)
            rc = fail(err, errlen, o, "write error: %s%s", strerror(errno), "");
        if (from >= 0)
            close(from);
    }
    if (o->fd >= 0) {
        close(o->fd);
        o->fd = -1;
    }
    if (rc == 0 && o->kind == KIND_TEMP && rename(o->tmp, o->target) != 0)
        rc = fail(err, errlen, o, "cannot move the finished file into place: %s%s", strerror(errno), "");
    else if (rc == 0 && o->kind == KIND_TEMP)
        o->tmp_live = 0;
    if (o->tmp_live) {
        unlink(o->tmp);
        if (o->staged)
            unlink(o->inner);
        o->tmp_live = 0;
    }
    o->live = 0;
    return rc;
}

void ks_out_discard(ks_out *o)
{
    if (!o || !o->live)
        return;
    if (o->f)
        fclose(o->f);
    else if (o->fd >= 0)
        close(o->fd);
    o->f = NULL;
    o->fd = -1;
    if (o->tmp_live) {
        unlink(o->tmp);
        if (o->staged)
            unlink(o->inner);
        o->tmp_live = 0;
    }
    o->live = 0;
}

void ks_out_discard_all(void)
{
    for (int i = 0; i < g_nouts; i++)
        ks_out_discard(&g_outs[i]);
}

void ks_out_remove_temps_signal_safe(void)
{
    if (getpid() != g_owner)   /* getpid is async-signal-safe */
        return;
    for (int i = 0; i < g_nouts; i++)
        if (g_outs[i].tmp_live) {
            unlink(g_outs[i].tmp);
            if (g_outs[i].staged)
                unlink(g_outs[i].inner);
        }
}
