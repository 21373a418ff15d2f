/* tb_tracer_io_obj.c — Wavefront OBJ reader: every face form, negative
 * indices, polygons, comments/CRLF/blank lines, number syntax, gzip, and
 * malformed files (message names file and line). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "testbench/tb.h"
#include "tracer/io/obj_load.h"
#include "tracer/util/rng.h"

static const char *tmpdir(void)
{
    const char *t = getenv("RTSIM_TMP");
    return t && *t ? t : "/tmp";
}

static bool parse(const char *text, rt_mesh *m, char *err, size_t n)
{
    return rt_obj_parse(text, strlen(text), "t.obj", m, err, n);
}

static bool tri_is(const rt_mesh *m, uint32_t i, uint32_t a, uint32_t b, uint32_t c)
{
    return i < m->ntris && m->tris[3 * i] == a && m->tris[3 * i + 1] == b && m->tris[3 * i + 2] == c;
}

static void test_face_forms(void)
{
    tb_begin("obj_face_forms_v_vt_vn");
    const char *text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n"
                       "f 1 2 3\nf 1/1 2/2 3/3\nf 1//1 2//1 3//1\nf 1/1/1 2/2/1 3/3/1\n";
    rt_mesh m;
    char err[TB_ERR_MAX] = "";
    bool ok = parse(text, &m, err, sizeof err);
    if (TB_CHECK(ok, "parse failed: %s", err)) {
        TB_EQ_INT(m.nverts, 3);
        TB_EQ_INT(m.ntris, 4);
        for (uint32_t i = 0; i < 4; i++)
            TB_CHECK(tri_is(&m, i, 0, 1, 2), "triangle %u is not (0,1,2)", i);
        TB_CHECK(m.verts[1].x == 1.0f && m.verts[2].y == 1.0f, "vertex values");
    }
    rt_mesh_free(&m);
    tb_end();
}

static void test_negative_and_polygons(void)
{
    tb_begin("obj_negative_indices_and_fan_triangulation");
    const char *text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                       "f -4 -3 -2\n"            /* (0,1,2) */
                       "f 1 2 3 4\n"             /* quad -> (0,1,2) (0,2,3) */
                       "v 0.5 2 0\n"
                       "f -5 -4 -3 -2 -1\n";     /* pentagon 0..4 -> 3 triangles */
    rt_mesh m;
    char err[TB_ERR_MAX] = "";
    bool ok = parse(text, &m, err, sizeof err);
    if (TB_CHECK(ok, "parse failed: %s", err)) {
        TB_EQ_INT(m.ntris, 6);
        TB_CHECK(tri_is(&m, 0, 0, 1, 2), "negative indices resolve against vertices so far");
        TB_CHECK(tri_is(&m, 1, 0, 1, 2) && tri_is(&m, 2, 0, 2, 3), "quad fan order");
        TB_CHECK(tri_is(&m, 3, 0, 1, 2) && tri_is(&m, 4, 0, 2, 3) && tri_is(&m, 5, 0, 3, 4),
                 "pentagon fan order");
    }
    rt_mesh_free(&m);
    tb_end();
}

static void test_forward_refs_and_bom(void)
{
    tb_begin("obj_forward_references_and_byte_order_mark");
    const char *text = "\xef\xbb\xbfv 0 0 0\nf 1 2 3\nf 1/2 3/1 4/2\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 1\n";
    rt_mesh m;
    char err[TB_ERR_MAX] = "";
    bool ok = parse(text, &m, err, sizeof err);
    if (TB_CHECK(ok, "parse failed: %s", err)) {
        TB_EQ_INT(m.nverts, 4);
        TB_CHECK(tri_is(&m, 0, 0, 1, 2) && tri_is(&m, 1, 0, 2, 3), "triangles");
        TB_CHECK(m.verts[0].x == 0 && m.verts[3].y == 1, "BOM skipped, first vertex read");
    }
    rt_mesh_free(&m);
    tb_end();
}

static void test_comments_crlf(void)
{
    tb_begin("obj_comments_crlf_blank_lines_ignored_statements");
    const char *text = "# header comment\r\n\r\n   \r\nmtllib x.mtl\r\no thing\r\ng group1\r\n"
                       "v\t0 0 0\r\nv 1 0 0   \r\n  v 0 1 0 1.0\r\nv 0 0 1 0.5 0.5 0.5\r\n"
                       "usemtl red\r\ns off\r\nl 1 2\r\np 3\r\nvp 0.5\r\n"
                       "f 1 2 3 # trailing comment\r\n\tf 1 3 4\r\n#f 9 9 9\r\n"
                       "f 2 3 4";   /* no final newline */
    rt_mesh m;
    char err[TB_ERR_MAX] = "";
    bool ok = parse(text, &m, err, sizeof err);
    if (TB_CHECK(ok, "parse failed: %s", err)) {
        TB_EQ_INT(m.nverts, 4);
        TB_EQ_INT(m.ntris, 3);
        TB_CHECK(tri_is(&m, 0, 0, 1, 2) && tri_is(&m, 1, 0, 2, 3) && tri_is(&m, 2, 1, 2, 3),
                 "triangles");
        TB_CHECK(m.verts[3].z == 1.0f, "vertex with colour keeps xyz");
    }
    rt_mesh_free(&m);
    tb_end();
}

static void test_numbers(void)
{
    tb_begin("obj_number_syntax_matches_strtof");
    static const char *nums[] = {"1e2", "-.5", "+3.", "1.5E-3", "0.1234567890123", "-0.037830",
                                 "123456789", "1e-30", "3.4e38", "0.000001", "7", "-0",
                                 "0.30000000000000004", "16777217", "2.5e+10"};
    enum { N = sizeof nums / sizeof nums[0] };
    char text[2048];
    size_t n = 0;
    for (int i = 0; i < N; i++)
        n += (size_t)snprintf(text + n, sizeof text - n, "v %s 0 0\n", nums[i]);
    snprintf(text + n, sizeof text - n, "f 1 2 3\n");
    rt_mesh m;
    char err[TB_ERR_MAX] = "";
    bool ok = parse(text, &m, err, sizeof err);
    if (TB_CHECK(ok, "parse failed: %s", err))
        for (int i = 0; i < N; i++) {
            float want = strtof(nums[i], NULL);
            TB_CHECK(memcmp(&m.verts[i].x, &want, sizeof want) == 0, "'%s' -> %.9g, strtof %.9g",
                     nums[i], (double)m.verts[i].x, (double)want);
        }
    rt_mesh_free(&m);
    tb_end();
}

static bool write_file(const char *path, const char *data, size_t n, bool gz)
{
    if (gz) {
        gzFile f = gzopen(path, "wb");
        if (!f)
            return false;
        bool ok = gzwrite(f, data, (unsigned)n) == (int)n;
        return gzclose(f) == Z_OK && ok;
    }
    FILE *f = fopen(path, "wb");
    if (!f)
        return false;
    bool ok = fwrite(data, 1, n, f) == n;
    return fclose(f) == 0 && ok;
}

static void test_gzip(void)
{
    tb_begin("obj_gzip_equals_plain");
    const char *text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    char plain[TB_PATH_MAX], gz[TB_PATH_MAX], err[TB_ERR_MAX] = "";
    tb_pathf(plain, sizeof plain, "%s/tb_obj_plain.obj", tmpdir());
    tb_pathf(gz, sizeof gz, "%s/tb_obj_gz.obj.gz", tmpdir());
    rt_mesh a, b;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    if (TB_CHECK(write_file(plain, text, strlen(text), false) &&
                     write_file(gz, text, strlen(text), true),
                 "cannot write test files in %s", tmpdir())) {
        bool ok = rt_obj_load(plain, &a, err, sizeof err);
        TB_CHECK(ok, "plain: %s", err);
        ok = ok && rt_obj_load(gz, &b, err, sizeof err);
        TB_CHECK(ok, "gz: %s", err);
        if (ok)
            TB_CHECK(rt_mesh_hash(&a) == rt_mesh_hash(&b) && a.ntris == 2, "gz mesh differs");
        /* A corrupt trailer (ISIZE claims ~4 GB) is reported, not trusted. */
        {
            FILE *g = fopen(gz, "r+b");
            bool patched = g && fseek(g, -4, SEEK_END) == 0 && fwrite("\xf0\xff\xff\xff", 1, 4, g) == 4;
            if (g)
                fclose(g);
            rt_mesh c;
            bool ok2 = patched && rt_obj_load(gz, &c, err, sizeof err);
            TB_CHECK(patched && !ok2 && strstr(err, gz) && strstr(err, "corrupt"), "bad ISIZE: %s",
                     ok2 ? "(loaded)" : err);
            if (ok2)
                rt_mesh_free(&c);
            write_file(gz, text, strlen(text), true);
        }
        /* A gzip file cut in half must be reported, not silently shortened. */
        FILE *f = fopen(gz, "rb");
        unsigned char buf[512];
        size_t n = f ? fread(buf, 1, sizeof buf, f) : 0;
        if (f)
            fclose(f);
        write_file(gz, (const char *)buf, n / 2, false);
        rt_mesh c;
        ok = rt_obj_load(gz, &c, err, sizeof err);
        TB_CHECK(!ok && strstr(err, gz) && strstr(err, "truncated"),
                 "truncated gzip not reported: %s", ok ? "(loaded)" : err);
        if (ok)
            rt_mesh_free(&c);
    }
    rt_mesh_free(&a);
    rt_mesh_free(&b);
    tb_end();
}

static void test_errors(void)
{
    static const struct {
        const char *name, *text, *where, *what;
    } cases[] = {
        {"obj_error_too_few_coordinates", "v 1 2\nf 1 1 1\n", "t.obj:1:", "coordinate"},
        {"obj_error_bad_number", "v 0 0 0\nv 1 2 x\n", "t.obj:2:", "bad number 'x'"},
        {"obj_error_number_garbage_suffix", "v 1 2 3abc\n", "t.obj:1:", "bad number"},
        {"obj_error_nan", "v 1 nan 3\n", "t.obj:1:", "bad number"},
        {"obj_error_index_out_of_range", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n", "t.obj:5:",
         "vertex index 4 out of range"},
        {"obj_error_index_zero", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "t.obj:4:", "index 0 is invalid"},
        {"obj_error_negative_out_of_range", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", "t.obj:4:",
         "out of range"},
        {"obj_error_texcoord_out_of_range", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n",
         "t.obj:5:", "texture coordinate index 2"},
        {"obj_error_normal_out_of_range", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n", "t.obj:4:",
         "normal index 1"},
        {"obj_error_two_vertex_face", "v 0 0 0\nv 1 0 0\nf 1 2\n", "t.obj:3:", "at least 3"},
        {"obj_error_bad_face_token", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 two 3\n", "t.obj:4:",
         "bad face vertex 'two'"},
        {"obj_error_forward_reference_beyond_file", "f 1 2 3\nf 2 9 1\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", "t.obj:2:",
         "vertex index 9 out of range; the file defines 3"},
        {"obj_error_negative_before_any_vertex", "f -1 -2 -3\nv 0 0 0\n", "t.obj:1:", "0 defined so far"},
        {"obj_error_lone_v", "v 0 0 0\nv\n", "t.obj:2:", "0 coordinate"},
        {"obj_error_lone_f", "v 0 0 0\nf\r\n", "t.obj:2:", "face has 0"},
        {"obj_error_no_faces", "v 0 0 0\n", "t.obj", "no faces"},
        {"obj_error_empty", "", "t.obj", "no faces"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        tb_begin(cases[i].name);
        rt_mesh m;
        char err[TB_ERR_MAX] = "";
        bool ok = parse(cases[i].text, &m, err, sizeof err);
        TB_CHECK(!ok, "malformed input accepted");
        TB_CHECK(!ok && strncmp(err, cases[i].where, strlen(cases[i].where)) == 0,
                 "message '%s' does not start with '%s'", err, cases[i].where);
        TB_CHECK(!ok && strstr(err, cases[i].what), "message '%s' lacks '%s'", err, cases[i].what);
        TB_CHECK(ok || (m.verts == NULL && m.tris == NULL && m.ntris == 0), "mesh not zeroed on error");
        if (ok)
            rt_mesh_free(&m);
        tb_end();
    }
    tb_begin("obj_error_directory_instead_of_file");
    {
        rt_mesh d;
        char e2[TB_ERR_MAX] = "";
        const char *t = getenv("RTSIM_TMP");
        bool ok = rt_obj_load(t && *t ? t : "/tmp", &d, e2, sizeof e2);
        TB_CHECK(!ok && strstr(e2, t && *t ? t : "/tmp") && strstr(e2, "is a folder, not a mesh file"),
                 "message: %s", e2);
        if (ok)
            rt_mesh_free(&d);
    }
    tb_end();
    tb_begin("obj_error_missing_file");
    rt_mesh m;
    char err[TB_ERR_MAX] = "";
    bool ok = rt_obj_load("/nonexistent/dir/x.obj", &m, err, sizeof err);
    TB_CHECK(!ok && strstr(err, "/nonexistent/dir/x.obj") && strstr(err, "cannot open"),
             "message: %s", err);
    tb_end();
}

/* Seeded random mutations of a valid file: success with indices in range,
 * or a message naming the file; never a crash or overread (ASan build). */
static void test_fuzz(void)
{
    tb_begin("obj_fuzz_mutations");
    static const char good[] = "# fuzz\nv 0 0 0\nv 1.5 0 -2e-3\nvt 0 1\nvn 0 0 1\nv 1 1 0\nv 0 1 0\n"
                               "g a\nf 1/1/1 2/1/1 3/1/1\nf -4 -2 -1\nf 1 2 3 4\r\nf 1//1 3//1 4//1\n";
    const char alphabet[] = " \t\r\n/-+.eE0123456789vtnf#x";
    rt_rng rng;
    rt_rng_seed(&rng, 77, 1);
    unsigned silent = 0;
    int runs = tb_is_sanitized() ? 3000 : 10000;
    for (int i = 0; i < runs; i++) {
        char b[sizeof good];
        size_t n = sizeof good - 1;
        memcpy(b, good, n);
        int edits = 1 + (int)rt_rng_below(&rng, 4);
        for (int e = 0; e < edits; e++) {
            size_t at = rt_rng_below(&rng, (uint32_t)n);
            if (rt_rng_below(&rng, 4) == 0)
                n = at + 1;
            else
                b[at] = alphabet[rt_rng_below(&rng, sizeof alphabet - 1)];
        }
        char *copy = malloc(n);   /* exact size, no NUL: ASan sees overreads */
        memcpy(copy, b, n);
        rt_mesh m;
        char err[TB_ERR_MAX] = "";
        bool ok = rt_obj_parse(copy, n, "t.obj", &m, err, sizeof err);
        free(copy);
        if (ok) {
            for (uint64_t k = 0; k < 3ull * m.ntris; k++)
                silent += m.tris[k] >= m.nverts;
            rt_mesh_free(&m);
        } else {
            silent += strncmp(err, "t.obj", 5) != 0;
        }
    }
    TB_EQ_INT(silent, 0);
    tb_end();
}

int main(void)
{
    test_fuzz();
    test_face_forms();
    test_negative_and_polygons();
    test_forward_refs_and_bom();
    test_comments_crlf();
    test_numbers();
    test_gzip();
    test_errors();
    return tb_finish();
}
