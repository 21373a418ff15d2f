/* output_path.h — checks a tool's output path before any work is done, so a
 * long run never ends with "cannot create": the folder must exist and be
 * writable, and the path must not be a folder. Outputs are still written to
 * a temporary name and renamed when complete (each tool does that). */
#ifndef RTSIM_CLI_OUTPUT_PATH_H
#define RTSIM_CLI_OUTPUT_PATH_H

#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* True when path (given with option opt) can be written; else false with
 * "OPT PATH: why" in err. A NULL path (option not given) is fine. */
static inline bool cli_output_path_ok(const char *opt, const char *path, char *err, size_t errlen)
{
    if (!path)
        return true;
    if (!*path) {
        snprintf(err, errlen, "%s: empty file name", opt);
        return false;
    }
    char dir[4096];
    /* room for the temporary name "PATH.tmp.PID" within PATH_MAX (4096); a
     * longer path's folder was cut below, and checking the cut folder let
     * the path pass until the run ended with "cannot create" */
    const size_t max_len = sizeof dir - 17;
    if (strlen(path) > max_len) {
        snprintf(err, errlen, "%s %.64s...: path longer than %zu characters", opt, path, max_len);
        return false;
    }
    const char *slash = strrchr(path, '/');
    if (slash)
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - path) ? (int)(slash - path) : 1, path);
    else
        snprintf(dir, sizeof dir, ".");
    struct stat st;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
        snprintf(err, errlen, "%s %s: folder %s does not exist", opt, path, dir);
        return false;
    }
    if (access(dir, W_OK) != 0) {
        snprintf(err, errlen, "%s %s: folder %s is not writable", opt, path, dir);
        return false;
    }
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        snprintf(err, errlen, "%s %s: is a folder", opt, path);
        return false;
    }
    return true;
}

#endif
