/* options.c — the option parser of rtsim, rttrace and rtdram (cli/options.h). */
#include <errno.h>
#include <getopt.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "cli/options.h"
#include "cli/version.h"

/* ---- values ---- */

static void cli_range_text(const cli_opt *o, char *buf, size_t len)
{
    if (o->kind == CLI_UINT)
        snprintf(buf, len, "%llu..%llu", (unsigned long long)o->min, (unsigned long long)o->max);
    else if (o->kind == CLI_REAL && o->lo_open)
        snprintf(buf, len, "%g < %s <= %g", o->lo, o->arg ? o->arg : "value", o->hi);
    else if (o->kind == CLI_REAL)
        snprintf(buf, len, "%g..%g", o->lo, o->hi);
    else
        snprintf(buf, len, "%s", "");
}

/* The choices joined by sep ("a, b, c" or "a|b|c"). */
static void cli_choices_text(const cli_opt *o, const char *sep, char *buf, size_t len)
{
    size_t n = 0;
    buf[0] = 0;
    for (int i = 0; o->choices && o->choices[i] && n < len; i++)
        n += (size_t)snprintf(buf + n, len - n, "%s%s", i ? sep : "", o->choices[i]);
}

bool cli_parse_u64(const char *text, uint64_t min, uint64_t max, uint64_t *out)
{
    if (text[0] < '0' || text[0] > '9')
        return false;
    char *end;
    errno = 0;
    unsigned long long v = strtoull(text, &end, 10);
    if (errno || *end || v < min || v > max)
        return false;
    *out = v;
    return true;
}

/* Parses text for row o into its destination; false with err (possibly
 * empty: the row's `what` then says what is allowed). */
static bool cli_set_value(const cli_opt *o, const char *text, char *err, size_t errlen)
{
    err[0] = 0;
    switch (o->kind) {
    case CLI_UINT: return cli_parse_u64(text, o->min, o->max, o->to.u);
    case CLI_REAL: {
        char *end;
        errno = 0;
        double v = strtod(text, &end);
        if (errno || end == text || *end || !(o->lo_open ? v > o->lo : v >= o->lo) || !(v <= o->hi))
            return false;
        *o->to.real = v;
        return true;
    }
    case CLI_CHOICE:
        for (int i = 0; o->choices[i]; i++)
            if (!strcmp(text, o->choices[i])) {
                *o->to.choice = i;
                return true;
            }
        return false;
    case CLI_CUSTOM: return o->parse(text, o->to.custom, err, errlen);
    case CLI_STRING: *o->to.str = text; return true;
    default: return true;
    }
}

/* ---- --help ---- */

/* Writes a help text: "\n" continues at column `col`; {default} and {range}
 * are the row's. */
static void cli_put_help(const cli_opt *o, const char *s, int col, FILE *out)
{
    char range[96];
    cli_range_text(o, range, sizeof range);
    for (; *s; s++) {
        if (!strncmp(s, "{default}", 9)) {
            fputs(o->def ? o->def : "", out);
            s += 8;
        } else if (!strncmp(s, "{range}", 7)) {
            fputs(range, out);
            s += 6;
        } else {
            fputc(*s, out);
            if (*s == '\n' && s[1])
                fprintf(out, "%*s", col, "");
        }
    }
}

/* "--name ARG" as the option list or the synopsis shows it. */
static void cli_opt_text(const cli_opt *o, bool synopsis, char *buf, size_t len)
{
    char choices[256];
    cli_choices_text(o, "|", choices, sizeof choices);
    const char *arg = o->kind == CLI_CHOICE && (synopsis || !o->arg) ? choices : o->arg;
    if (o->kind == CLI_HELP && !synopsis)
        snprintf(buf, len, "--help, --version");
    else
        snprintf(buf, len, "--%s%s%s", o->name, arg ? " " : "", arg ? arg : "");
}

void cli_usage(const cli_tool *t, FILE *out)
{
    char text[320];
    if (t->synopsis) {
        /* continuation lines start under the tool's first argument */
        const int cont = (int)(strstr(t->synopsis, t->name) - t->synopsis + strlen(t->name));
        int at = (int)strlen(t->synopsis);
        fputs(t->synopsis, out);
        for (const cli_opt *o = t->opts; o->name; o++) {
            cli_opt_text(o, true, text, sizeof text);
            const char *more = o->kind == CLI_LIST ? "..." : "";
            int n = (int)(strlen(text) + strlen(more)) + 3;   /* " [" text "]" */
            if (at + n > t->width) {
                fprintf(out, "\n%*s", cont, "");
                at = cont;
            }
            fprintf(out, " [%s]%s", text, more);
            at += n;
        }
        fputs("\n", out);
    }
    fputs(t->about, out);
    for (const cli_opt *o = t->opts; o->name; o++) {
        if (!o->help)
            continue;
        cli_opt_text(o, false, text, sizeof text);
        int n = t->indent + (int)strlen(text);
        fprintf(out, "%*s%s", t->indent, "", text);
        if (!*o->help) {
            fputs("\n", out);
            continue;
        }
        if (n + 1 <= t->column)
            fprintf(out, "%*s", t->column - n, "");
        else
            fprintf(out, "\n%*s", t->column, "");
        cli_put_help(o, o->help, t->column, out);
        fputs("\n", out);
    }
    if (t->footer)
        fputs(t->footer, out);
}

/* ---- messages ---- */

int cli_usage_error(const cli_tool *t, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "%s: ", t->name);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputs("\n", stderr);
    if (t->hint)
        fprintf(stderr, "%s\n", t->hint);
    else
        cli_usage(t, stderr);
    return 2;
}

static int cli_bad_value(const cli_tool *t, const cli_opt *o, const char *text, const char *err)
{
    char opt[64], what[400], allowed[320];
    snprintf(opt, sizeof opt, "--%s", o->name);
    if (*err)
        return cli_usage_error(t, "%s: %s", opt, err);
    const char *phrase = o->what ? o->what
                         : o->kind == CLI_UINT ? t->uint_what
                         : o->kind == CLI_REAL ? t->real_what
                                               : t->choice_what;
    if (o->kind == CLI_CHOICE)
        cli_choices_text(o, ", ", allowed, sizeof allowed);
    else
        cli_range_text(o, allowed, sizeof allowed);
    snprintf(what, sizeof what, phrase ? phrase : "%s", allowed);
    return cli_usage_error(t, t->bad_value, opt, text, what);
}

/* ---- the parser ---- */

#define CLI_MAX_OPTS 64

int cli_parse(const cli_tool *t, int argc, char **argv, int *args)
{
    struct option longopts[CLI_MAX_OPTS + 1];
    *args = 0;
    char err[4096 + 512];   /* a message with a whole option value (a path) in it */
    int n = 0;
    for (const cli_opt *o = t->opts; o->name; o++, n++) {
        if (n == CLI_MAX_OPTS) {
            fprintf(stderr, "%s: option table: more than %d options\n", t->name, CLI_MAX_OPTS);
            abort();
        }
        bool has_arg = o->kind != CLI_FLAG && o->kind != CLI_HELP && o->kind != CLI_VERSION;
        longopts[n] = (struct option){o->name, has_arg ? required_argument : no_argument, NULL, 256 + n};
        if (o->given)
            *o->given = false;
        switch (o->kind) {
        case CLI_FLAG: *o->to.flag = false; break;
        case CLI_STRING: *o->to.str = o->def; break;
        case CLI_LIST:
            o->to.list->n = 0;
            o->to.list->v = calloc((size_t)argc + 1, sizeof *o->to.list->v);
            if (!o->to.list->v) {
                fprintf(stderr, "%s: out of memory\n", t->name);
                return 1;
            }
            break;
        case CLI_UINT: *o->to.u = 0; break;
        case CLI_REAL: *o->to.real = 0; break;
        case CLI_CHOICE: *o->to.choice = 0; break;
        default: break;
        }
        if (o->def && o->kind != CLI_STRING && !cli_set_value(o, o->def, err, sizeof err)) {
            fprintf(stderr, "%s: option table: --%s: bad default '%s' %s\n", t->name, o->name, o->def, err);
            abort();
        }
    }
    longopts[n] = (struct option){0, 0, 0, 0};
    opterr = !t->unknown;   /* without a message of its own, getopt's */
    int c;
    while ((c = getopt_long(argc, argv, t->unknown ? ":" : "", longopts, NULL)) != -1) {
        if (c == '?' || c == ':') {
            if (!t->unknown) {   /* getopt has said what is wrong */
                cli_usage(t, stderr);
                return 2;
            }
            char shortopt[3] = {'-', (char)optopt, 0};   /* optopt: a short option, or 0 */
            const char *opt = optopt > 0 && optopt < 256 ? shortopt : argv[optind - 1];
            const char *fmt = c == ':' && t->missing ? t->missing : t->unknown;
            fprintf(stderr, "%s: ", t->name);
            fprintf(stderr, fmt, opt);
            fputs("\n", stderr);
            if (t->hint && !t->unknown_shows_usage)
                fprintf(stderr, "%s\n", t->hint);
            else
                cli_usage(t, stderr);
            return 2;
        }
        const cli_opt *o = &t->opts[c - 256];
        if (o->given)
            *o->given = true;
        switch (o->kind) {
        case CLI_HELP: cli_usage(t, stdout); return 0;
        case CLI_VERSION: printf("%s %s (git %s)\n", t->name, RTSIM_VERSION, RTSIM_GIT); return 0;
        case CLI_FLAG: *o->to.flag = true; break;
        case CLI_LIST: o->to.list->v[o->to.list->n++] = optarg; break;
        default:
            if (!cli_set_value(o, optarg, err, sizeof err))
                return cli_bad_value(t, o, optarg, err);
        }
        if (o->stops)
            break;
    }
    *args = optind;
    return CLI_GO_ON;
}
