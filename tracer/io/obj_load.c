/* obj_load.c — see obj_load.h. */
#include "tracer/io/obj_load.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "tracer/io/scene_error.h"
#include "tracer/io/scene_file.h"
#include "tracer/io/scene_number.h"

typedef struct growbuf {
    void *data;
    size_t n, cap, elem;
} growbuf;

/* Makes room for `more` elements; false on overflow/out of memory. */
static bool grow(growbuf *g, size_t more)
{
    if (g->n + more <= g->cap)
        return true;
    size_t ncap = g->cap ? g->cap : 4096;
    while (ncap < g->n + more) {
        if (ncap > SIZE_MAX / 2 / g->elem)
            return false;
        ncap *= 2;
    }
    void *nd = realloc(g->data, ncap * g->elem);
    if (!nd)
        return false;
    g->data = nd;
    g->cap = ncap;
    return true;
}

static inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

static const char *skip_space(const char *p, const char *end)
{
    while (p < end && is_space(*p))
        p++;
    return p;
}

/* Shows the offending token (up to 24 chars) in messages. */
static int token_len(const char *p, const char *end)
{
    int n = 0;
    while (p + n < end && !is_space(p[n]) && p[n] != '\n' && n < 24)
        n++;
    return n;
}

/* Resolves an OBJ index (1-based, or negative relative to `count` defined so
 * far) to 0-based; false when out of range. */
static bool resolve_index(long long idx, uint64_t count, uint32_t *out)
{
    if (idx > 0 && (uint64_t)idx <= count) {
        *out = (uint32_t)(idx - 1);
        return true;
    }
    if (idx < 0 && (uint64_t)(-idx) <= count) {
        *out = (uint32_t)(count - (uint64_t)(-idx));
        return true;
    }
    return false;
}

bool rt_obj_parse(const char *text, size_t len, const char *file, rt_mesh *out, char *err,
                  size_t errlen)
{
    memset(out, 0, sizeof *out);
    growbuf verts = {NULL, 0, 0, sizeof(rt_vec3)};
    growbuf tris = {NULL, 0, 0, 3 * sizeof(uint32_t)};
    growbuf poly = {NULL, 0, 0, sizeof(uint32_t)};   /* vertex indices of the current face */
    uint64_t nvt = 0, nvn = 0;
    uint64_t fwd_max[3] = {0, 0, 0};        /* largest forward (positive) index per kind */
    unsigned long fwd_line[3] = {0, 0, 0};  /* and the line it is on */
    const char *p = text, *end = text + len;
    if (len >= 3 && (unsigned char)p[0] == 0xef && (unsigned char)p[1] == 0xbb && (unsigned char)p[2] == 0xbf)
        p += 3;   /* UTF-8 byte order mark */
    unsigned long line = 0;
    while (p < end) {
        line++;
        const char *eol = memchr(p, '\n', (size_t)(end - p));
        if (!eol)
            eol = end;
        const char *s = skip_space(p, eol);
        const char *next = eol < end ? eol + 1 : end;
        if (s == eol || *s == '#') {
            p = next;
            continue;
        }
        if (s[0] == 'v' && (s + 1 == eol || is_space(s[1]))) {
            /* v x y z [w | r g b]: three coordinates required, rest ignored. */
            float c[3];
            const char *q = s + 1;
            for (int k = 0; k < 3; k++) {
                q = skip_space(q, eol);
                const char *r = rt_parse_float(q, eol, &c[k]);
                if (!r || (r < eol && !is_space(*r))) {
                    if (q == eol)
                        rt_scene_errorf(err, errlen,
                                        "%s:%lu: vertex has %d coordinate(s); 'v' needs x y z",
                                        file, line, k);
                    else
                        rt_scene_errorf(err, errlen,
                                        "%s:%lu: bad number '%.*s' in vertex coordinate %d; "
                                        "expected a finite decimal number",
                                        file, line, token_len(q, eol), q, k + 1);
                    goto fail;
                }
                q = r;
            }
            if (verts.n >= UINT32_MAX) {
                rt_scene_errorf(err, errlen, "%s:%lu: more than %u vertices", file, line,
                                UINT32_MAX - 1u);
                goto fail;
            }
            if (!grow(&verts, 1))
                goto oom;
            ((rt_vec3 *)verts.data)[verts.n++] = (rt_vec3){c[0], c[1], c[2]};
        } else if (s[0] == 'v' && s + 2 <= eol && (s[1] == 't' || s[1] == 'n') &&
                   (s + 2 == eol || is_space(s[2]))) {
            if (s[1] == 't')
                nvt++;
            else
                nvn++;
        } else if (s[0] == 'f' && (s + 1 == eol || is_space(s[1]))) {
            poly.n = 0;
            const char *q = skip_space(s + 1, eol);
            while (q < eol && *q != '#') {
                long long idx[3];
                int have[3] = {1, 0, 0};
                const char *tok = q;
                const char *r = rt_parse_int(q, eol, &idx[0]);
                if (r && r < eol && *r == '/') {
                    r++;
                    if (r < eol && *r != '/') {
                        r = rt_parse_int(r, eol, &idx[1]);
                        have[1] = 1;
                    }
                    if (r && r < eol && *r == '/') {
                        r = rt_parse_int(r + 1, eol, &idx[2]);
                        have[2] = 1;
                    }
                }
                if (!r || (r < eol && !is_space(*r))) {
                    rt_scene_errorf(err, errlen,
                                    "%s:%lu: bad face vertex '%.*s'; allowed forms v, v/vt, v//vn, "
                                    "v/vt/vn with nonzero integer indices",
                                    file, line, token_len(tok, eol), tok);
                    goto fail;
                }
                static const char *const what[3] = {"vertex", "texture coordinate", "normal"};
                const uint64_t count[3] = {verts.n, nvt, nvn};
                uint32_t v0 = 0;
                for (int k = 0; k < 3; k++) {
                    uint32_t ix = 0;
                    if (!have[k])
                        continue;
                    if (idx[k] > 0 && (uint64_t)idx[k] > count[k] && idx[k] <= UINT32_MAX) {
                        /* A forward reference: checked against the final
                         * count at the end of the file. */
                        ix = (uint32_t)(idx[k] - 1);
                        if ((uint64_t)idx[k] > fwd_max[k])
                            fwd_max[k] = (uint64_t)idx[k], fwd_line[k] = line;
                    } else if (!resolve_index(idx[k], count[k], &ix)) {
                        if (idx[k] == 0)
                            rt_scene_errorf(err, errlen,
                                            "%s:%lu: %s index 0 is invalid; OBJ indices start at 1 "
                                            "(negative ones count back from the last defined)",
                                            file, line, what[k]);
                        else
                            rt_scene_errorf(err, errlen,
                                            "%s:%lu: %s index %lld out of range; %llu defined so far "
                                            "(negative indices allowed -1..-%llu)",
                                            file, line, what[k], idx[k], (unsigned long long)count[k],
                                            (unsigned long long)count[k]);
                        goto fail;
                    }
                    if (k == 0)
                        v0 = ix;
                }
                if (!grow(&poly, 1))
                    goto oom;
                ((uint32_t *)poly.data)[poly.n++] = v0;
                q = skip_space(r, eol);
            }
            if (poly.n < 3) {
                rt_scene_errorf(err, errlen,
                                "%s:%lu: face has %zu vertex(es); a face needs at least 3", file,
                                line, poly.n);
                goto fail;
            }
            if (!grow(&tris, poly.n - 2))
                goto oom;
            if (tris.n + (poly.n - 2) > UINT32_MAX) {
                rt_scene_errorf(err, errlen, "%s:%lu: more than %u triangles", file, line,
                                UINT32_MAX);
                goto fail;
            }
            const uint32_t *pv = poly.data;
            for (size_t i = 1; i + 1 < poly.n; i++) {
                uint32_t *t = (uint32_t *)tris.data + 3 * tris.n++;
                t[0] = pv[0], t[1] = pv[i], t[2] = pv[i + 1];
            }
        }
        /* Anything else (o, g, s, usemtl, mtllib, l, p, vp, ...) does not
         * contribute triangles and is ignored. */
        p = next;
    }
    free(poly.data);
    poly.data = NULL;
    {
        static const char *const what[3] = {"vertex", "texture coordinate", "normal"};
        const uint64_t final_count[3] = {verts.n, nvt, nvn};
        for (int k = 0; k < 3; k++)
            if (fwd_max[k] > final_count[k]) {
                rt_scene_errorf(err, errlen, "%s:%lu: %s index %llu out of range; the file defines %llu",
                                file, fwd_line[k], what[k], (unsigned long long)fwd_max[k],
                                (unsigned long long)final_count[k]);
                goto fail;
            }
    }
    if (tris.n == 0) {
        rt_scene_errorf(err, errlen, "%s: no faces ('f' lines); a scene needs at least one triangle",
                        file);
        free(verts.data);
        free(tris.data);
        return false;
    }
    out->verts = verts.data;
    out->tris = tris.data;
    out->nverts = (uint32_t)verts.n;
    out->ntris = (uint32_t)tris.n;
    /* Shrink to fit; keep the larger block if realloc declines. */
    rt_vec3 *sv = realloc(out->verts, verts.n * sizeof(rt_vec3));
    if (sv)
        out->verts = sv;
    uint32_t *st = realloc(out->tris, tris.n * 3 * sizeof(uint32_t));
    if (st)
        out->tris = st;
    return true;
oom:
    rt_scene_errorf(err, errlen, "%s:%lu: out of memory", file, line);
fail:
    free(verts.data);
    free(tris.data);
    free(poly.data);
    return false;
}

bool rt_obj_load(const char *path, rt_mesh *out, char *err, size_t errlen)
{
    size_t len;
    memset(out, 0, sizeof *out);
    unsigned char *buf = rt_read_file_gz(path, "mesh file", RT_MESH_MAX_BYTES, &len, err, errlen);
    if (!buf)
        return false;
    bool ok = rt_obj_parse((const char *)buf, len, path, out, err, errlen);
    free(buf);
    return ok;
}
