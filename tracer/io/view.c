/* view.c — see view.h. */
#include "tracer/io/view.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tracer/io/scene_error.h"
#include "tracer/io/scene_file.h"

#define VIEW_SYNTAX "view <name> eye <x> <y> <z> at <x> <y> <z> up <x> <y> <z> fov <degrees>"

bool rt_views_line_is_blank(const char *line)
{
    while (*line == ' ' || *line == '\t' || *line == '\r')
        line++;
    return *line == 0 || *line == '\n' || *line == '#';
}

/* Next whitespace-separated token of *p into tok (up to cap-1 chars). A
 * longer token ends in "..." so that it matches no keyword, name or number
 * (it used to be cut silently: "4.5000...0e1" read as 4.5) and messages
 * show it as cut. */
static bool next_token(const char **p, char *tok, size_t cap)
{
    const char *s = *p;
    while (*s == ' ' || *s == '\t' || *s == '\r')
        s++;
    if (*s == 0 || *s == '\n')
        return false;
    size_t n = 0, len = 0;
    while (*s && *s != ' ' && *s != '\t' && *s != '\r' && *s != '\n') {
        if (n + 1 < cap)
            tok[n++] = *s;
        s++;
        len++;
    }
    if (len > n && n >= 3)
        memcpy(tok + n - 3, "...", 3);
    tok[n] = 0;
    *p = s;
    return true;
}

static bool parse_num(const char *tok, float *out)
{
    char *end;
    double d = strtod(tok, &end);
    if (end == tok || *end != 0 || !isfinite(d) || fabs(d) > 3.0e38)
        return false;
    *out = (float)d;
    return true;
}

bool rt_view_parse_line(const char *line, const char *file, unsigned lineno,
                        rt_view *out, char *err, size_t errlen)
{
    static const char *const keys[] = {"eye", "at", "up"};
    char tok[128];
    const char *p = line;
    memset(out, 0, sizeof *out);
    if (!next_token(&p, tok, sizeof tok) || strcmp(tok, "view") != 0) {
        rt_scene_errorf(err, errlen, "%s:%u: expected a line '%s', found '%s'", file, lineno,
                        VIEW_SYNTAX, tok);
        return false;
    }
    if (!next_token(&p, tok, sizeof tok)) {
        rt_scene_errorf(err, errlen, "%s:%u: missing view name; expected '%s'", file, lineno,
                        VIEW_SYNTAX);
        return false;
    }
    size_t nlen = strlen(tok);
    bool name_ok = nlen > 0 && nlen < RT_VIEW_NAME_MAX;
    for (size_t i = 0; i < nlen && name_ok; i++)
        name_ok = isalnum((unsigned char)tok[i]) || tok[i] == '-' || tok[i] == '_';
    if (!name_ok) {
        rt_scene_errorf(err, errlen,
                        "%s:%u: bad view name '%.64s': allowed are 1..%d letters, digits, '-', '_'",
                        file, lineno, tok, RT_VIEW_NAME_MAX - 1);
        return false;
    }
    memcpy(out->name, tok, nlen + 1);
    rt_vec3 *vecs[3] = {&out->eye, &out->at, &out->up};
    for (int k = 0; k < 3; k++) {
        if (!next_token(&p, tok, sizeof tok) || strcmp(tok, keys[k]) != 0) {
            rt_scene_errorf(err, errlen, "%s:%u: expected '%s' after %s; line syntax: '%s'", file,
                            lineno, keys[k], k == 0 ? "the name" : keys[k - 1], VIEW_SYNTAX);
            return false;
        }
        float xyz[3];
        for (int c = 0; c < 3; c++) {
            if (!next_token(&p, tok, sizeof tok) || !parse_num(tok, &xyz[c])) {
                rt_scene_errorf(err, errlen,
                                "%s:%u: '%s' needs 3 finite decimal numbers; coordinate %d is '%s'",
                                file, lineno, keys[k], c + 1, tok);
                return false;
            }
            tok[0] = 0;
        }
        *vecs[k] = (rt_vec3){xyz[0], xyz[1], xyz[2]};
    }
    if (!next_token(&p, tok, sizeof tok) || strcmp(tok, "fov") != 0) {
        rt_scene_errorf(err, errlen, "%s:%u: expected 'fov' after up; line syntax: '%s'", file,
                        lineno, VIEW_SYNTAX);
        return false;
    }
    tok[0] = 0;
    if (!next_token(&p, tok, sizeof tok) || !parse_num(tok, &out->fov_deg)) {
        rt_scene_errorf(err, errlen, "%s:%u: 'fov' needs a decimal number of degrees, found '%s'",
                        file, lineno, tok);
        return false;
    }
    if (next_token(&p, tok, sizeof tok)) {
        rt_scene_errorf(err, errlen, "%s:%u: unexpected '%s' after fov; line syntax: '%s'", file,
                        lineno, tok, VIEW_SYNTAX);
        return false;
    }
    return rt_view_validate(out, file, lineno, err, errlen);
}

bool rt_view_validate(const rt_view *v, const char *file, unsigned lineno, char *err,
                      size_t errlen)
{
    char where[320];
    if (lineno)
        snprintf(where, sizeof where, "%s:%u", file, lineno);
    else
        snprintf(where, sizeof where, "%s", file);
    if (!(v->fov_deg > 0.0f && v->fov_deg < 180.0f)) {
        rt_scene_errorf(err, errlen, "%s: view '%s': fov %g out of range; allowed 0 < fov < 180",
                        where, v->name, (double)v->fov_deg);
        return false;
    }
    double f[3] = {(double)v->at.x - v->eye.x, (double)v->at.y - v->eye.y,
                   (double)v->at.z - v->eye.z};
    double u[3] = {v->up.x, v->up.y, v->up.z};
    double fl = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    double ul = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    if (!(fl > 0)) {
        rt_scene_errorf(err, errlen, "%s: view '%s': eye and at are the same point", where, v->name);
        return false;
    }
    double c[3] = {f[1] * u[2] - f[2] * u[1], f[2] * u[0] - f[0] * u[2], f[0] * u[1] - f[1] * u[0]};
    double cl = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    /* sin(angle(up, forward)) below 1e-6 leaves the right vector undefined in float. */
    if (!(ul > 0) || !(cl > 1e-6 * fl * ul)) {
        rt_scene_errorf(err, errlen,
                        "%s: view '%s': up is zero or parallel to the view direction (at - eye)",
                        where, v->name);
        return false;
    }
    return true;
}

bool rt_views_add(rt_views *vs, const rt_view *v, char *err, size_t errlen)
{
    if (rt_views_find(vs, v->name)) {
        rt_scene_errorf(err, errlen, "duplicate view name '%s'", v->name);
        return false;
    }
    rt_view *nv = realloc(vs->v, (vs->n + 1) * sizeof *nv);
    if (!nv) {
        rt_scene_errorf(err, errlen, "out of memory");
        return false;
    }
    vs->v = nv;
    vs->v[vs->n++] = *v;
    return true;
}

const rt_view *rt_views_find(const rt_views *vs, const char *name)
{
    for (uint32_t i = 0; i < vs->n; i++)
        if (strcmp(vs->v[i].name, name) == 0)
            return &vs->v[i];
    return NULL;
}

void rt_views_free(rt_views *vs)
{
    free(vs->v);
    vs->v = NULL;
    vs->n = 0;
}

bool rt_views_parse_text(const char *text, const char *file, rt_views *out, char *err,
                         size_t errlen)
{
    out->v = NULL;
    out->n = 0;
    unsigned lineno = 0;
    const char *p = text;
    if ((unsigned char)p[0] == 0xef && (unsigned char)p[1] == 0xbb && (unsigned char)p[2] == 0xbf)
        p += 3;   /* UTF-8 byte order mark */
    while (*p) {
        lineno++;
        const char *eol = strchr(p, '\n');
        size_t n = eol ? (size_t)(eol - p) : strlen(p);
        char line[1024];
        if (n >= sizeof line) {
            rt_scene_errorf(err, errlen, "%s:%u: line longer than %zu characters", file, lineno,
                            sizeof line - 1);
            goto fail;
        }
        memcpy(line, p, n);
        line[n] = 0;
        p = eol ? eol + 1 : p + n;
        if (rt_views_line_is_blank(line))
            continue;
        rt_view v;
        if (!rt_view_parse_line(line, file, lineno, &v, err, errlen))
            goto fail;
        if (rt_views_find(out, v.name)) {
            rt_scene_errorf(err, errlen, "%s:%u: duplicate view name '%s'; names must be unique",
                            file, lineno, v.name);
            goto fail;
        }
        if (!rt_views_add(out, &v, err, errlen))
            goto fail;
    }
    if (out->n == 0) {
        rt_scene_errorf(err, errlen, "%s: no views; expected at least one line '%s'", file,
                        VIEW_SYNTAX);
        goto fail;
    }
    return true;
fail:
    rt_views_free(out);
    return false;
}

bool rt_views_load(const char *path, rt_views *out, char *err, size_t errlen)
{
    size_t len;
    out->v = NULL;
    out->n = 0;
    unsigned char *buf = rt_read_file_gz(path, "views file", RT_TEXT_MAX_BYTES, &len, err, errlen);
    if (!buf)
        return false;
    if (memchr(buf, 0, len)) {
        rt_scene_errorf(err, errlen, "%s: contains a NUL byte; a views file is text", path);
        free(buf);
        return false;
    }
    bool ok = rt_views_parse_text((const char *)buf, path, out, err, errlen);
    free(buf);
    return ok;
}
