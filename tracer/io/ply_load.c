/* ply_load.c — see ply_load.h. Format: Greg Turk, "The PLY Polygon File
 * Format" (1994), with the sized type names (int8 .. float64) that later
 * writers (rply, tinyply, Blender, MeshLab) also use. */
#include "tracer/io/ply_load.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "tracer/io/scene_error.h"
#include "tracer/io/scene_file.h"
#include "tracer/io/scene_number.h"

enum { PLY_MAX_ELEMENTS = 32, PLY_MAX_PROPS = 64, PLY_NAME_MAX = 64 };

typedef enum ptype { T_NONE, T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64 } ptype;
static const unsigned type_size[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
static const char *const type_names[][2] = {
    {"", ""},          {"char", "int8"},   {"uchar", "uint8"},  {"short", "int16"}, {"ushort", "uint16"},
    {"int", "int32"}, {"uint", "uint32"}, {"float", "float32"}, {"double", "float64"}};
#define PLY_TYPES_ALLOWED \
    "char uchar short ushort int uint float double (or int8 uint8 int16 uint16 int32 uint32 float32 float64)"

typedef struct prop {
    char name[PLY_NAME_MAX];
    ptype type;         /* scalar type, or the item type of a list */
    ptype count_type;   /* T_NONE for scalars */
} prop;

typedef struct element {
    char name[PLY_NAME_MAX];
    uint64_t count;
    prop props[PLY_MAX_PROPS];
    int nprops;
} element;

typedef enum fmt { F_ASCII, F_LE, F_BE } fmt;

typedef struct ply {
    const unsigned char *data;
    size_t len, pos;          /* body cursor (absolute byte offset) */
    const char *file;
    fmt format;
    unsigned long line;       /* ASCII body: current line */
    element el[PLY_MAX_ELEMENTS];
    int nel;
    char *err;
    size_t errlen;
    const char *cur_el;       /* for messages */
    uint64_t cur_index;
} ply;

static bool is_int_type(ptype t) { return t >= T_I8 && t <= T_U32; }

static ptype parse_type(const char *s)
{
    for (int t = T_I8; t <= T_F64; t++)
        if (strcmp(s, type_names[t][0]) == 0 || strcmp(s, type_names[t][1]) == 0)
            return (ptype)t;
    return T_NONE;
}

/* Where a body error is: "FILE:LINE" (ASCII) or "FILE: byte N" (binary). */
static void body_error(ply *p, const char *what)
{
    if (p->format == F_ASCII)
        rt_scene_errorf(p->err, p->errlen, "%s:%lu: element %s index %llu: %s", p->file, p->line,
                        p->cur_el, (unsigned long long)p->cur_index, what);
    else
        rt_scene_errorf(p->err, p->errlen, "%s: byte %zu (element %s index %llu): %s", p->file,
                        p->pos, p->cur_el, (unsigned long long)p->cur_index, what);
}

/* ---- reading one value ---------------------------------------------------- */

static inline uint64_t load_uint(const unsigned char *b, unsigned n, bool be)
{
    uint64_t v = 0;
    if (be)
        for (unsigned i = 0; i < n; i++)
            v = (v << 8) | b[i];
    else
        for (unsigned i = n; i-- > 0;)
            v = (v << 8) | b[i];
    return v;
}

/* Reads one binary value as double; false when the data ends. */
static inline bool bin_value(ply *p, ptype t, double *out)
{
    unsigned n = type_size[t];
    if (p->len - p->pos < n) {
        body_error(p, "unexpected end of data (file truncated?)");
        return false;
    }
    uint64_t u = load_uint(p->data + p->pos, n, p->format == F_BE);
    p->pos += n;
    switch (t) {
    case T_I8: *out = (int8_t)u; break;
    case T_U8: *out = (uint8_t)u; break;
    case T_I16: *out = (int16_t)u; break;
    case T_U16: *out = (uint16_t)u; break;
    case T_I32: *out = (int32_t)u; break;
    case T_U32: *out = (uint32_t)u; break;
    case T_F32: {
        uint32_t w = (uint32_t)u;
        float f;
        memcpy(&f, &w, 4);
        *out = f;
        break;
    }
    default: {
        double d;
        memcpy(&d, &u, 8);
        *out = d;
        break;
    }
    }
    return true;
}

/* Reads one ASCII token as a value of type t. */
static bool ascii_value(ply *p, ptype t, double *out)
{
    const char *s = (const char *)p->data, *end = s + p->len;
    size_t i = p->pos;
    while (i < p->len && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r' || s[i] == '\n')) {
        if (s[i] == '\n')
            p->line++;
        i++;
    }
    p->pos = i;
    if (i >= p->len) {
        body_error(p, "unexpected end of data (file truncated?)");
        return false;
    }
    const char *tok = s + i, *r;
    if (is_int_type(t)) {
        long long v;
        r = rt_parse_int(tok, end, &v);
        *out = (double)v;
    } else {
        float f;
        r = rt_parse_float(tok, end, &f);
        *out = f;
    }
    if (!r || (r < end && !(*r == ' ' || *r == '\t' || *r == '\r' || *r == '\n'))) {
        char msg[160];
        int n = 0;
        while (tok + n < end && n < 24 && !(tok[n] == ' ' || tok[n] == '\t' || tok[n] == '\r' || tok[n] == '\n'))
            n++;
        snprintf(msg, sizeof msg, "bad %s value '%.*s'", type_names[t][0], n, tok);
        body_error(p, msg);
        return false;
    }
    p->pos = (size_t)(r - s);
    return true;
}

static inline bool read_value(ply *p, ptype t, double *out)
{
    return p->format == F_ASCII ? ascii_value(p, t, out) : bin_value(p, t, out);
}

/* Reads a list count: an integer 0..2^31. */
static bool read_count(ply *p, ptype t, uint32_t *out)
{
    double c;
    if (!read_value(p, t, &c))
        return false;
    if (!(c >= 0 && c <= 2147483647.0)) {
        body_error(p, "negative or huge list count");
        return false;
    }
    *out = (uint32_t)c;
    return true;
}

/* ---- header ---------------------------------------------------------------- */

static bool parse_header(ply *p)
{
    const char *s = (const char *)p->data;
    size_t i = 0;
    unsigned long line = 0;
    bool have_format = false;
    element *cur = NULL;
    for (;;) {
        line++;
        const char *nl = memchr(s + i, '\n', p->len - i);
        if (!nl) {
            rt_scene_errorf(p->err, p->errlen, "%s:%lu: header ends without 'end_header'", p->file,
                            line);
            return false;
        }
        size_t n = (size_t)(nl - (s + i));
        char buf[512];
        if (n >= sizeof buf) {
            rt_scene_errorf(p->err, p->errlen, "%s:%lu: header line longer than %zu characters",
                            p->file, line, sizeof buf - 1);
            return false;
        }
        memcpy(buf, s + i, n);
        buf[n] = 0;
        if (n && buf[n - 1] == '\r')
            buf[--n] = 0;
        i = (size_t)(nl - s) + 1;
        char *words[8];
        int nw = 0;
        for (char *tok = strtok(buf, " \t"); tok && nw < 8; tok = strtok(NULL, " \t"))
            words[nw++] = tok;
        if (line == 1) {
            if (nw != 1 || strcmp(words[0], "ply") != 0) {
                rt_scene_errorf(p->err, p->errlen, "%s:1: not a PLY file (first line must be 'ply')",
                                p->file);
                return false;
            }
            continue;
        }
        if (nw == 0 || strcmp(words[0], "comment") == 0 || strcmp(words[0], "obj_info") == 0)
            continue;
        if (strcmp(words[0], "end_header") == 0) {
            if (!have_format) {
                rt_scene_errorf(p->err, p->errlen, "%s:%lu: header has no 'format' line", p->file,
                                line);
                return false;
            }
            p->pos = i;
            p->line = line + 1;
            return true;
        }
        if (strcmp(words[0], "format") == 0) {
            if (nw != 3 || strcmp(words[2], "1.0") != 0) {
                rt_scene_errorf(p->err, p->errlen,
                                "%s:%lu: bad format line; expected 'format ascii|binary_little_endian|"
                                "binary_big_endian 1.0'",
                                p->file, line);
                return false;
            }
            if (strcmp(words[1], "ascii") == 0)
                p->format = F_ASCII;
            else if (strcmp(words[1], "binary_little_endian") == 0)
                p->format = F_LE;
            else if (strcmp(words[1], "binary_big_endian") == 0)
                p->format = F_BE;
            else {
                rt_scene_errorf(p->err, p->errlen,
                                "%s:%lu: unknown format '%s'; allowed ascii, binary_little_endian, "
                                "binary_big_endian",
                                p->file, line, words[1]);
                return false;
            }
            have_format = true;
        } else if (strcmp(words[0], "element") == 0) {
            char *end = NULL;
            errno = 0;
            unsigned long long cnt = nw == 3 ? strtoull(words[2], &end, 10) : 0;
            /* strtoull gives ULLONG_MAX for a count that does not fit: say so
             * rather than report that largest number as the count */
            if (nw == 3 && end && !*end && words[2][0] != '-' && errno == ERANGE) {
                rt_scene_errorf(p->err, p->errlen,
                                "%s:%lu: element %s: count %.40s%s does not fit in 64 bits (at most %llu)", p->file,
                                line, words[1], words[2], strlen(words[2]) > 40 ? "..." : "", ULLONG_MAX);
                return false;
            }
            if (nw != 3 || !end || *end || words[2][0] == '-') {
                rt_scene_errorf(p->err, p->errlen,
                                "%s:%lu: bad element line; expected 'element <name> <count>'",
                                p->file, line);
                return false;
            }
            if (p->nel == PLY_MAX_ELEMENTS) {
                rt_scene_errorf(p->err, p->errlen, "%s:%lu: more than %d elements", p->file, line,
                                PLY_MAX_ELEMENTS);
                return false;
            }
            cur = &p->el[p->nel++];
            memset(cur, 0, sizeof *cur);
            snprintf(cur->name, sizeof cur->name, "%s", words[1]);
            cur->count = cnt;
        } else if (strcmp(words[0], "property") == 0) {
            if (!cur) {
                rt_scene_errorf(p->err, p->errlen, "%s:%lu: property before any element", p->file,
                                line);
                return false;
            }
            if (cur->nprops == PLY_MAX_PROPS) {
                rt_scene_errorf(p->err, p->errlen, "%s:%lu: element %s has more than %d properties",
                                p->file, line, cur->name, PLY_MAX_PROPS);
                return false;
            }
            prop *pr = &cur->props[cur->nprops];
            memset(pr, 0, sizeof *pr);
            if (nw == 5 && strcmp(words[1], "list") == 0) {
                pr->count_type = parse_type(words[2]);
                pr->type = parse_type(words[3]);
                snprintf(pr->name, sizeof pr->name, "%s", words[4]);
                if (pr->count_type == T_NONE || pr->type == T_NONE) {
                    rt_scene_errorf(p->err, p->errlen, "%s:%lu: unknown type in '%s %s'; allowed " PLY_TYPES_ALLOWED,
                                    p->file, line, words[2], words[3]);
                    return false;
                }
                if (!is_int_type(pr->count_type)) {
                    rt_scene_errorf(p->err, p->errlen,
                                    "%s:%lu: list count type '%s' must be an integer type", p->file,
                                    line, words[2]);
                    return false;
                }
            } else if (nw == 3) {
                pr->type = parse_type(words[1]);
                snprintf(pr->name, sizeof pr->name, "%s", words[2]);
                if (pr->type == T_NONE) {
                    rt_scene_errorf(p->err, p->errlen, "%s:%lu: unknown type '%s'; allowed " PLY_TYPES_ALLOWED,
                                    p->file, line, words[1]);
                    return false;
                }
            } else {
                rt_scene_errorf(p->err, p->errlen,
                                "%s:%lu: bad property line; expected 'property <type> <name>' or "
                                "'property list <count type> <item type> <name>'",
                                p->file, line);
                return false;
            }
            cur->nprops++;
        } else {
            rt_scene_errorf(p->err, p->errlen,
                            "%s:%lu: unknown header keyword '%s'; allowed format, element, property, "
                            "comment, obj_info, end_header",
                            p->file, line, words[0]);
            return false;
        }
    }
}

/* ---- body -------------------------------------------------------------------- */

/* Smallest number of body bytes one element can take (overflow-safe check
 * that `count` elements can fit in the rest of the data). */
static bool check_fits(ply *p, const element *e)
{
    uint64_t min = 0;
    for (int k = 0; k < e->nprops; k++) {
        const prop *pr = &e->props[k];
        if (p->format == F_ASCII)
            min += 2;   /* one digit + one separator */
        else
            min += type_size[pr->count_type ? pr->count_type : pr->type];
    }
    if (p->format == F_ASCII && min)
        min -= 1;       /* the last value of the file needs no separator */
    uint64_t rest = p->len - p->pos;
    if (min && e->count > rest / min) {
        rt_scene_errorf(p->err, p->errlen,
                        "%s: element %s declares %llu entries of at least %llu bytes each, but only "
                        "%llu bytes of data remain (file truncated or count wrong)",
                        p->file, e->name, (unsigned long long)e->count, (unsigned long long)min,
                        (unsigned long long)rest);
        return false;
    }
    return true;
}

static bool skip_element(ply *p, const element *e)
{
    if (e->nprops == 0)
        return true;   /* no data, whatever the count (would loop for nothing) */
    bool fixed = p->format != F_ASCII;
    uint64_t size = 0;
    for (int k = 0; k < e->nprops; k++) {
        if (e->props[k].count_type)
            fixed = false;
        size += type_size[e->props[k].type];
    }
    if (fixed) {
        /* check_fits proved count * size <= rest */
        p->pos += (size_t)(e->count * size);
        return true;
    }
    double v;
    for (uint64_t i = 0; i < e->count; i++) {
        p->cur_index = i;
        for (int k = 0; k < e->nprops; k++) {
            const prop *pr = &e->props[k];
            uint32_t n = 1;
            if (pr->count_type && !read_count(p, pr->count_type, &n))
                return false;
            for (uint32_t j = 0; j < n; j++)
                if (!read_value(p, pr->type, &v))
                    return false;
        }
    }
    return true;
}

static bool read_vertices(ply *p, const element *e, rt_mesh *m)
{
    int ix[3] = {-1, -1, -1};
    static const char *const axis[3] = {"x", "y", "z"};
    for (int k = 0; k < e->nprops; k++)
        for (int a = 0; a < 3; a++)
            if (strcmp(e->props[k].name, axis[a]) == 0 && !e->props[k].count_type)
                ix[a] = k;
    for (int a = 0; a < 3; a++)
        if (ix[a] < 0) {
            rt_scene_errorf(p->err, p->errlen,
                            "%s: element vertex has no scalar property '%s'; x, y and z are required",
                            p->file, axis[a]);
            return false;
        }
    if (e->count > UINT32_MAX - 1u) {
        rt_scene_errorf(p->err, p->errlen, "%s: %llu vertices; at most %u supported", p->file,
                        (unsigned long long)e->count, UINT32_MAX - 1u);
        return false;
    }
    m->nverts = (uint32_t)e->count;
    m->verts = malloc((e->count ? e->count : 1) * sizeof *m->verts);
    if (!m->verts) {
        rt_scene_errorf(p->err, p->errlen, "%s: out of memory for %llu vertices", p->file,
                        (unsigned long long)e->count);
        return false;
    }
    /* Fast path: binary with only scalar properties and float32 x, y, z. */
    bool fast = p->format != F_ASCII;
    size_t stride = 0, off[PLY_MAX_PROPS];
    for (int k = 0; k < e->nprops; k++) {
        off[k] = stride;
        stride += type_size[e->props[k].type];
        if (e->props[k].count_type)
            fast = false;
    }
    for (int a = 0; a < 3; a++)
        if (e->props[ix[a]].type != T_F32)
            fast = false;
    if (fast) {
        const unsigned char *b = p->data + p->pos;   /* check_fits: count*stride fits */
        bool be = p->format == F_BE;
        for (uint64_t i = 0; i < e->count; i++, b += stride) {
            float c[3];
            for (int a = 0; a < 3; a++) {
                uint32_t w = (uint32_t)load_uint(b + off[ix[a]], 4, be);
                memcpy(&c[a], &w, 4);
            }
            if (!isfinite(c[0]) || !isfinite(c[1]) || !isfinite(c[2])) {
                p->cur_index = i;
                p->pos = (size_t)(b - p->data);
                body_error(p, "vertex coordinate is not a finite number");
                return false;
            }
            m->verts[i] = (rt_vec3){c[0], c[1], c[2]};
        }
        p->pos += (size_t)(e->count * stride);
        return true;
    }
    for (uint64_t i = 0; i < e->count; i++) {
        p->cur_index = i;
        double c[3] = {0, 0, 0};
        for (int k = 0; k < e->nprops; k++) {
            const prop *pr = &e->props[k];
            uint32_t n = 1;
            if (pr->count_type && !read_count(p, pr->count_type, &n))
                return false;
            for (uint32_t j = 0; j < n; j++) {
                double v;
                if (!read_value(p, pr->type, &v))
                    return false;
                for (int a = 0; a < 3; a++)
                    if (k == ix[a])
                        c[a] = v;
            }
        }
        float f[3] = {(float)c[0], (float)c[1], (float)c[2]};
        if (!isfinite(f[0]) || !isfinite(f[1]) || !isfinite(f[2])) {
            body_error(p, "vertex coordinate is not a finite float");
            return false;
        }
        m->verts[i] = (rt_vec3){f[0], f[1], f[2]};
    }
    return true;
}

static bool push_tris(ply *p, rt_mesh *m, size_t *cap, const uint32_t *poly, uint32_t n)
{
    size_t need = (size_t)m->ntris + (n - 2);
    if (need > UINT32_MAX) {
        body_error(p, "more than 2^32-1 triangles");
        return false;
    }
    if (need > *cap) {
        size_t ncap = *cap ? *cap * 2 : 1024;
        while (ncap < need)
            ncap *= 2;
        uint32_t *nt = realloc(m->tris, ncap * 3 * sizeof *nt);
        if (!nt) {
            body_error(p, "out of memory");
            return false;
        }
        m->tris = nt;
        *cap = ncap;
    }
    for (uint32_t i = 1; i + 1 < n; i++) {
        uint32_t *t = m->tris + 3 * (size_t)m->ntris++;
        t[0] = poly[0], t[1] = poly[i], t[2] = poly[i + 1];
    }
    return true;
}

static bool read_faces(ply *p, const element *e, uint64_t nverts_declared, rt_mesh *m)
{
    int li = -1;
    for (int k = 0; k < e->nprops; k++)
        if (e->props[k].count_type && (strcmp(e->props[k].name, "vertex_indices") == 0 ||
                                       strcmp(e->props[k].name, "vertex_index") == 0))
            li = k;
    if (li < 0) {
        rt_scene_errorf(p->err, p->errlen,
                        "%s: element face has no list property 'vertex_indices' (or 'vertex_index')",
                        p->file);
        return false;
    }
    if (!is_int_type(e->props[li].type)) {
        rt_scene_errorf(p->err, p->errlen,
                        "%s: face property %s has item type '%s'; vertex indices must be integers",
                        p->file, e->props[li].name, type_names[e->props[li].type][0]);
        return false;
    }
    /* check_fits bounded count by the data size (>= 1 byte per face), so one
     * triangle per face is a safe first guess; polygons grow the array. */
    size_t cap = (size_t)e->count;
    if (cap < 16)
        cap = 16;
    m->tris = malloc(cap * 3 * sizeof *m->tris);
    if (!m->tris) {
        rt_scene_errorf(p->err, p->errlen, "%s: out of memory", p->file);
        return false;
    }
    uint32_t *poly = NULL;
    uint32_t poly_cap = 0;
    bool ok = false;
    /* Fast path: binary, the list is the only property, uchar count, 32-bit
     * indices, triangles (the layout of ../shared/scenes). Other faces drop
     * to the general code below, element by element. */
    bool fast = p->format != F_ASCII && e->nprops == 1 && e->props[0].count_type == T_U8 &&
                (e->props[0].type == T_U32 || e->props[0].type == T_I32);
    bool be = p->format == F_BE;
    for (uint64_t i = 0; i < e->count; i++) {
        p->cur_index = i;
        if (fast && p->len - p->pos >= 13 && p->data[p->pos] == 3) {
            const unsigned char *b = p->data + p->pos + 1;
            uint32_t v[3];
            for (int k = 0; k < 3; k++)
                v[k] = (uint32_t)load_uint(b + 4 * k, 4, be);
            if (v[0] < nverts_declared && v[1] < nverts_declared && v[2] < nverts_declared) {
                if (m->ntris == cap) {
                    if (!push_tris(p, m, &cap, v, 3))
                        goto done;
                } else {
                    uint32_t *t = m->tris + 3 * (size_t)m->ntris++;
                    t[0] = v[0], t[1] = v[1], t[2] = v[2];
                }
                p->pos += 13;
                continue;
            }
            /* out of range: the general path reports it */
        }
        for (int k = 0; k < e->nprops; k++) {
            const prop *pr = &e->props[k];
            uint32_t n = 1;
            if (pr->count_type && !read_count(p, pr->count_type, &n))
                goto done;
            if (k == li) {
                if (n < 3) {
                    char msg[96];
                    snprintf(msg, sizeof msg, "face has %u vertex index(es); a face needs at least 3", n);
                    body_error(p, msg);
                    goto done;
                }
                /* Each index takes >= 1 byte: refuse lists longer than the
                 * rest of the data before allocating for them. */
                uint64_t item = p->format == F_ASCII ? 1 : type_size[pr->type];
                if ((uint64_t)n * item > p->len - p->pos) {
                    char msg[128];
                    snprintf(msg, sizeof msg, "list of %u vertex indices runs past the end of the data (file truncated?)", n);
                    body_error(p, msg);
                    goto done;
                }
                if (n > poly_cap) {
                    uint32_t *np = realloc(poly, (size_t)n * sizeof *np);
                    if (!np) {
                        body_error(p, "out of memory");
                        goto done;
                    }
                    poly = np;
                    poly_cap = n;
                }
            }
            for (uint32_t j = 0; j < n; j++) {
                double v;
                if (!read_value(p, pr->type, &v))
                    goto done;
                if (k == li) {
                    if (!(v >= 0 && v < (double)nverts_declared)) {
                        char msg[160];
                        snprintf(msg, sizeof msg,
                                 "vertex index %.0f out of range; allowed 0..%llu (%llu vertices)", v,
                                 (unsigned long long)nverts_declared - (nverts_declared > 0),
                                 (unsigned long long)nverts_declared);
                        body_error(p, msg);
                        goto done;
                    }
                    poly[j] = (uint32_t)v;
                }
            }
            if (k == li && !push_tris(p, m, &cap, poly, n))
                goto done;
        }
    }
    ok = true;
done:
    free(poly);
    return ok;
}

bool rt_ply_parse(const unsigned char *data, size_t len, const char *file, rt_mesh *out,
                  char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    ply *p = calloc(1, sizeof *p);
    if (!p) {
        rt_scene_errorf(err, errlen, "%s: out of memory", file);
        return false;
    }
    p->data = data;
    p->len = len;
    p->file = file;
    p->err = err;
    p->errlen = errlen;
    bool ok = false;
    if (!parse_header(p))
        goto done;
    const element *ev = NULL, *ef = NULL;
    for (int i = 0; i < p->nel; i++) {
        if (strcmp(p->el[i].name, "vertex") == 0 && !ev)
            ev = &p->el[i];
        if (strcmp(p->el[i].name, "face") == 0 && !ef)
            ef = &p->el[i];
    }
    if (!ev || !ef) {
        rt_scene_errorf(err, errlen, "%s: header declares no '%s' element; a mesh needs 'vertex' and 'face'",
                        file, ev ? "face" : "vertex");
        goto done;
    }
    for (int i = 0; i < p->nel; i++) {
        const element *e = &p->el[i];
        p->cur_el = e->name;
        p->cur_index = 0;
        if (!check_fits(p, e))
            goto done;
        bool r = e == ev ? read_vertices(p, e, out)
               : e == ef ? read_faces(p, e, ev->count, out)
                         : skip_element(p, e);
        if (!r)
            goto done;
    }
    if (out->ntris == 0) {
        rt_scene_errorf(err, errlen, "%s: no faces; a scene needs at least one triangle", file);
        goto done;
    }
    ok = true;
done:
    if (!ok)
        rt_mesh_free(out);
    free(p);
    return ok;
}

bool rt_ply_load(const char *path, rt_mesh *out, char *err, size_t errlen)
{
    size_t len;
    memset(out, 0, sizeof *out);
    unsigned char *buf = rt_read_file_gz(path, "mesh file", RT_MESH_MAX_BYTES, &len, err, errlen);
    if (!buf)
        return false;
    bool ok = rt_ply_parse(buf, len, path, out, err, errlen);
    free(buf);
    return ok;
}
