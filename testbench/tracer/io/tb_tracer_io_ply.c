/* tb_tracer_io_ply.c — PLY reader: ASCII, binary little and big endian,
 * properties in any order with extras, list count/index types, other
 * elements skipped, polygons, gzip, and malformed files (message names the
 * file and line or byte offset and element). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "testbench/tb.h"
#include "tracer/io/ply_load.h"
#include "tracer/util/rng.h"

typedef struct buf {
    unsigned char d[8192];
    size_t n;
} buf;

enum fmt { ASCII, LE, BE };

static void put_text(buf *b, const char *s)
{
    size_t n = strlen(s);
    memcpy(b->d + b->n, s, n);
    b->n += n;
}

/* Appends value v as PLY type `type` in format f (ASCII adds a space). */
static void put(buf *b, enum fmt f, const char *type, double v)
{
    if (f == ASCII) {
        char s[64];
        snprintf(s, sizeof s, "%.17g ", v);
        put_text(b, s);
        return;
    }
    unsigned char raw[8];
    unsigned n;
    if (!strcmp(type, "float")) {
        float x = (float)v;
        memcpy(raw, &x, n = 4);
    } else if (!strcmp(type, "double")) {
        memcpy(raw, &v, n = 8);
    } else if (!strcmp(type, "uchar") || !strcmp(type, "uint8") || !strcmp(type, "char")) {
        raw[0] = (unsigned char)(int)v;
        n = 1;
    } else if (!strcmp(type, "ushort") || !strcmp(type, "short") || !strcmp(type, "uint16") ||
               !strcmp(type, "int16")) {
        uint16_t x = (uint16_t)(int)v;
        memcpy(raw, &x, n = 2);
    } else {
        uint32_t x = (uint32_t)(int64_t)v;
        memcpy(raw, &x, n = 4);
    }
    for (unsigned i = 0; i < n; i++)   /* test host is little-endian (x86-64, arm64) */
        b->d[b->n++] = f == BE ? raw[n - 1 - i] : raw[i];
}

static const char *fmt_name(enum fmt f)
{
    return f == ASCII ? "ascii" : f == LE ? "binary_little_endian" : "binary_big_endian";
}

/* 5 vertices; faces: triangle (0,1,2) and quad (1,2,3,4); an edge element
 * between vertex and face, a material element with a list after face. */
static void make_ply(buf *b, enum fmt f, const char *ctype, const char *itype)
{
    char h[1024];
    b->n = 0;
    snprintf(h, sizeof h,
             "ply\nformat %s 1.0\ncomment made by tb_tracer_io_ply\nobj_info test\n"
             "element vertex 5\nproperty float z\nproperty uchar red\nproperty double x\n"
             "property float nx\nproperty float y\n"
             "element edge 2\nproperty int vertex1\nproperty int vertex2\n"
             "element face 2\nproperty uchar flags\nproperty list %s %s vertex_indices\n"
             "property float quality\n"
             "element material 1\nproperty list uchar float coeffs\nend_header\n",
             fmt_name(f), ctype, itype);
    put_text(b, h);
    for (int i = 0; i < 5; i++) {
        put(b, f, "float", -i);
        put(b, f, "uchar", 200);
        put(b, f, "double", i * 1.5 - 1);
        put(b, f, "float", 0.5);
        put(b, f, "float", 0.25 * i);
        if (f == ASCII)
            put_text(b, "\n");
    }
    for (int i = 0; i < 2; i++) {
        put(b, f, "int", i);
        put(b, f, "int", i + 1);
        if (f == ASCII)
            put_text(b, "\n");
    }
    static const int faces[2][5] = {{3, 0, 1, 2}, {4, 1, 2, 3, 4}};
    for (int i = 0; i < 2; i++) {
        put(b, f, "uchar", 7);
        put(b, f, ctype, faces[i][0]);
        for (int k = 1; k <= faces[i][0]; k++)
            put(b, f, itype, faces[i][k]);
        put(b, f, "float", 0.75);
        if (f == ASCII)
            put_text(b, "\n");
    }
    put(b, f, "uchar", 3);
    for (int k = 0; k < 3; k++)
        put(b, f, "float", k);
    if (f == ASCII)
        put_text(b, "\n");
}

static bool check_mesh(const rt_mesh *m)
{
    bool ok = TB_EQ_INT(m->nverts, 5) && TB_EQ_INT(m->ntris, 3);
    for (uint32_t i = 0; ok && i < 5; i++)
        ok = TB_CHECK(m->verts[i].x == i * 1.5f - 1 && m->verts[i].y == 0.25f * i &&
                          m->verts[i].z == -(float)i,
                      "vertex %u = (%g %g %g)", i, (double)m->verts[i].x, (double)m->verts[i].y,
                      (double)m->verts[i].z);
    static const uint32_t want[9] = {0, 1, 2, 1, 2, 3, 1, 3, 4};
    if (ok)
        ok = TB_CHECK(memcmp(m->tris, want, sizeof want) == 0, "triangles differ");
    return ok;
}

static void test_formats(void)
{
    static const char *types[][2] = {{"uchar", "int"},   {"uchar", "uint"},  {"ushort", "uint"},
                                     {"int", "int"},     {"uint8", "uint16"}, {"char", "short"},
                                     {"uint8", "uint32"}};
    for (int f = ASCII; f <= BE; f++)
        for (size_t t = 0; t < sizeof types / sizeof types[0]; t++) {
            char name[128];
            snprintf(name, sizeof name, "ply_%s_list_%s_%s_extra_props_and_elements", fmt_name(f),
                     types[t][0], types[t][1]);
            tb_begin(name);
            static buf b;
            make_ply(&b, (enum fmt)f, types[t][0], types[t][1]);
            rt_mesh m;
            char err[TB_ERR_MAX] = "";
            bool ok = rt_ply_parse(b.d, b.n, "t.ply", &m, err, sizeof err);
            if (TB_CHECK(ok, "parse failed: %s", err))
                check_mesh(&m);
            rt_mesh_free(&m);
            tb_end();
        }
}

static void test_crlf_header_and_gzip(void)
{
    tb_begin("ply_gzip_and_crlf_header");
    const char *text = "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\n"
                       "property float y\r\nproperty float z\r\nelement face 1\r\n"
                       "property list uchar int vertex_index\r\nend_header\r\n"
                       "0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n";
    const char *tmp = getenv("RTSIM_TMP");
    char path[TB_PATH_MAX], err[TB_ERR_MAX] = "";
    tb_pathf(path, sizeof path, "%s/tb_ply.ply.gz", tmp && *tmp ? tmp : "/tmp");
    gzFile g = gzopen(path, "wb");
    bool wrote = g && gzwrite(g, text, (unsigned)strlen(text)) == (int)strlen(text);
    if (g)
        wrote = gzclose(g) == Z_OK && wrote;
    rt_mesh m;
    memset(&m, 0, sizeof m);
    if (TB_CHECK(wrote, "cannot write %s", path)) {
        bool ok = rt_ply_load(path, &m, err, sizeof err);
        if (TB_CHECK(ok, "load failed: %s", err))
            TB_CHECK(m.ntris == 1 && m.nverts == 3 && m.verts[1].x == 1.0f && m.tris[2] == 2,
                     "mesh content");
    }
    rt_mesh_free(&m);
    tb_end();
}

static void test_errors(void)
{
    static buf good;
    make_ply(&good, LE, "uchar", "uint");
    size_t body = (size_t)(strstr((char *)good.d, "end_header\n") - (char *)good.d) + 11;
    /* byte offsets in the LE body: vertices 5*21, edges 2*8, face 0 = 1+1+12+4 */
    size_t face0 = body + 5 * 21 + 2 * 8, face1 = face0 + 18;

    tb_begin("ply_error_truncated_binary_names_byte_and_element");
    {
        rt_mesh m;
        char err[TB_ERR_MAX] = "";
        bool ok = rt_ply_parse(good.d, face1 + 8, "t.ply", &m, err, sizeof err);
        TB_CHECK(!ok && strstr(err, "t.ply: byte") && strstr(err, "element face index 1") &&
                     strstr(err, "truncated"),
                 "message: %s", ok ? "(accepted)" : err);
        if (ok)
            rt_mesh_free(&m);
    }
    tb_end();

    tb_begin("ply_error_index_out_of_range_binary");
    {
        static buf b;
        b = good;
        uint32_t bad = 7;
        memcpy(b.d + face1 + 2 + 4, &bad, 4);   /* second index of face 1 */
        rt_mesh m;
        char err[TB_ERR_MAX] = "";
        bool ok = rt_ply_parse(b.d, b.n, "t.ply", &m, err, sizeof err);
        TB_CHECK(!ok && strstr(err, "element face index 1") && strstr(err, "vertex index 7 out of range") &&
                     strstr(err, "0..4"),
                 "message: %s", ok ? "(accepted)" : err);
        if (ok)
            rt_mesh_free(&m);
    }
    tb_end();

    tb_begin("ply_error_huge_list_count_refused_before_allocating");
    {
        static buf b;
        b = good;
        b.n = face1 + 2;   /* keep face 1's flags and count byte */
        b.d[face1 + 1] = 255;
        rt_mesh m;
        char err[TB_ERR_MAX] = "";
        bool ok = rt_ply_parse(b.d, b.n, "t.ply", &m, err, sizeof err);
        TB_CHECK(!ok && strstr(err, "element face index 1") && strstr(err, "runs past the end"), "message: %s",
                 ok ? "(accepted)" : err);
        if (ok)
            rt_mesh_free(&m);
    }
    tb_end();

    tb_begin("ply_error_count_bigger_than_data");
    {
        static buf b;
        b = good;
        char *p = strstr((char *)b.d, "element face 2");
        p[13] = '9';   /* "element face 9" */
        rt_mesh m;
        char err[TB_ERR_MAX] = "";
        bool ok = rt_ply_parse(b.d, b.n, "t.ply", &m, err, sizeof err);
        TB_CHECK(!ok && strstr(err, "t.ply") && strstr(err, "face"), "message: %s",
                 ok ? "(accepted)" : err);
        if (ok)
            rt_mesh_free(&m);
    }
    tb_end();

    static const struct {
        const char *name, *text, *want1, *want2;
    } cases[] = {
        {"ply_error_not_ply", "plx\nformat ascii 1.0\nend_header\n", "t.ply:1:", "not a PLY"},
        {"ply_error_missing_end_header", "ply\nformat ascii 1.0\nelement vertex 0\n", "t.ply:4:",
         "end_header"},
        {"ply_error_unknown_format", "ply\nformat binary_middle_endian 1.0\nend_header\n", "t.ply:2:",
         "binary_little_endian"},
        {"ply_error_missing_format", "ply\nelement vertex 0\nend_header\n", "t.ply:3:", "format"},
        {"ply_error_bad_type", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float33 x\nend_header\n",
         "t.ply:4:", "unknown type 'float33'"},
        {"ply_error_bad_element_line", "ply\nformat ascii 1.0\nelement vertex -3\nend_header\n",
         "t.ply:3:", "element <name> <count>"},
        {"ply_error_unknown_keyword", "ply\nformat ascii 1.0\nelemnt vertex 3\nend_header\n", "t.ply:3:",
         "unknown header keyword 'elemnt'"},
        {"ply_error_missing_z", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
         "property float y\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n0 0\n",
         "t.ply", "'z'"},
        {"ply_error_no_face_element", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
         "property float y\nproperty float z\nend_header\n0 0 0\n", "t.ply", "'face'"},
        {"ply_error_float_indices", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
         "property float y\nproperty float z\nelement face 1\nproperty list uchar float vertex_indices\n"
         "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "t.ply", "integers"},
        {"ply_error_ascii_bad_token_names_line", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
         "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
         "end_header\n0 0 0\n1 0 0\n0 1x 0\n3 0 1 2\n", "t.ply:12:", "bad float value '1x'"},
        {"ply_error_ascii_truncated", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
         "property float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\n"
         "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1", "t.ply", "truncated"},
        {"ply_error_ascii_index_out_of_range", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
         "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
         "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "t.ply:13:", "vertex index 3 out of range"},
        {"ply_error_ascii_negative_index", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
         "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
         "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", "t.ply:13:", "out of range"},
        {"ply_error_two_vertex_face", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
         "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
         "end_header\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "t.ply:13:", "at least 3"},
        {"ply_error_propertyless_element_huge_count_no_hang", "ply\nformat ascii 1.0\nelement junk 18000000000000000000\n"
         "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n"
         "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n", "t.ply:14:", "out of range"},
        {"ply_error_no_triangles", "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
         "property float y\nproperty float z\nelement face 0\nproperty list uchar int vertex_indices\n"
         "end_header\n", "t.ply", "no faces"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        tb_begin(cases[i].name);
        rt_mesh m;
        char err[TB_ERR_MAX] = "";
        bool ok = rt_ply_parse((const unsigned char *)cases[i].text, strlen(cases[i].text), "t.ply", &m,
                               err, sizeof err);
        TB_CHECK(!ok, "malformed input accepted");
        TB_CHECK(!ok && strncmp(err, cases[i].want1, strlen(cases[i].want1)) == 0,
                 "message '%s' does not start with '%s'", err, cases[i].want1);
        TB_CHECK(!ok && strstr(err, cases[i].want2), "message '%s' lacks '%s'", err, cases[i].want2);
        TB_CHECK(ok || (m.verts == NULL && m.tris == NULL), "mesh not zeroed on error");
        if (ok)
            rt_mesh_free(&m);
        tb_end();
    }
}

/* Every prefix of valid files and thousands of seeded random mutations:
 * the reader must either succeed or fail with a message naming the file,
 * never crash, hang or read out of bounds (the ASan build checks that). */
static void test_fuzz(void)
{
    for (int f = ASCII; f <= BE; f++) {
        char name[96];
        snprintf(name, sizeof name, "ply_fuzz_%s_prefixes_and_mutations", fmt_name(f));
        tb_begin(name);
        static buf good, b;
        make_ply(&good, (enum fmt)f, "uchar", "int");
        unsigned accepted_prefixes = 0, silent = 0;
        for (size_t n = 0; n < good.n; n++) {
            rt_mesh m;
            char err[TB_ERR_MAX] = "";
            unsigned char *copy = malloc(n ? n : 1);   /* exact size: ASan sees overreads */
            memcpy(copy, good.d, n);
            bool ok = rt_ply_parse(copy, n, "t.ply", &m, err, sizeof err);
            free(copy);
            if (ok) {
                accepted_prefixes++;
                rt_mesh_free(&m);
            } else if (strncmp(err, "t.ply", 5) != 0) {
                silent++;
            }
        }
        /* Only prefixes that end inside the unused material element's last
         * value or after the faces' trailing bytes can still be complete. */
        TB_CHECK(accepted_prefixes <= 16, "%u truncated prefixes accepted", accepted_prefixes);
        rt_rng rng;
        rt_rng_seed(&rng, 2024, (uint64_t)f);
        int runs = tb_is_sanitized() ? 1500 : 4000;
        for (int i = 0; i < runs; i++) {
            b = good;
            int edits = 1 + (int)rt_rng_below(&rng, 4);
            for (int e = 0; e < edits; e++) {
                size_t at = rt_rng_below(&rng, (uint32_t)b.n);
                switch (rt_rng_below(&rng, 3)) {
                case 0: b.d[at] = (unsigned char)rt_rng_u32(&rng); break;
                case 1: b.d[at] ^= (unsigned char)(1u << rt_rng_below(&rng, 8)); break;
                default: b.n = at + 1; break;   /* truncate */
                }
            }
            unsigned char *copy = malloc(b.n);
            memcpy(copy, b.d, b.n);
            rt_mesh m;
            char err[TB_ERR_MAX] = "";
            bool ok = rt_ply_parse(copy, b.n, "t.ply", &m, err, sizeof err);
            free(copy);
            if (ok) {
                for (uint64_t k = 0; k < 3ull * m.ntris; k++)
                    if (m.tris[k] >= m.nverts)
                        silent++;
                rt_mesh_free(&m);
            } else if (strncmp(err, "t.ply", 5) != 0) {
                silent++;
            }
        }
        TB_EQ_INT(silent, 0);
        tb_end();
    }
}

int main(void)
{
    test_fuzz();
    test_formats();
    test_crlf_header_and_gzip();
    test_errors();
    return tb_finish();
}
