/* tb_tracer_io_scene.c — views.txt parsing (valid and malformed, message
 * names file and line), scene description files (.scene), views.txt beside
 * a mesh, the automatic view, and SCENE argument dispatch. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "testbench/tb.h"
#include "tracer/io/builtin.h"
#include "tracer/trace/camera.h"
#include "tracer/io/scene.h"

static char tmp[TB_PATH_MAX];

static bool write_text(const char *rel, const char *text)
{
    char path[TB_PATH_MAX];
    tb_pathf(path, sizeof path, "%s/%s", tmp, rel);
    FILE *f = fopen(path, "w");
    if (!f)
        return false;
    fputs(text, f);
    return fclose(f) == 0;
}

static const char *at(const char *rel)
{
    static char path[4][TB_PATH_MAX];
    static int k;
    k = (k + 1) % 4;
    tb_pathf(path[k], sizeof path[k], "%s/%s", tmp, rel);
    return path[k];
}

static void test_views_valid(void)
{
    tb_begin("views_parse_valid_with_bom_comments_crlf");
    const char *text = "\xef\xbb\xbf# cameras\r\n\r\nview front eye -0.21 0.16 0.235 at -0.0168 0.104 -0.0015 up 0 1 0 fov 36\r\n"
                       "view side_2  eye 1e1 0 0 at 0 0 0 up 0 1 0 fov 179.5\n";
    rt_views vs;
    char err[TB_ERR_MAX] = "";
    bool ok = rt_views_parse_text(text, "v.txt", &vs, err, sizeof err);
    if (TB_CHECK(ok, "%s", err)) {
        TB_EQ_INT(vs.n, 2);
        TB_CHECK(!strcmp(vs.v[0].name, "front") && vs.v[0].eye.x == -0.21f && vs.v[0].at.z == -0.0015f &&
                     vs.v[0].fov_deg == 36,
                 "first view values");
        TB_CHECK(rt_views_find(&vs, "side_2") == &vs.v[1] && vs.v[1].eye.x == 10 && !rt_views_find(&vs, "x"),
                 "find");
        rt_views_free(&vs);
    }
    tb_end();
}

static void test_views_errors(void)
{
    static const char *ok_line = "view a eye 0 0 0 at 0 0 -1 up 0 1 0 fov 40\n";
    static const struct {
        const char *name, *text, *where, *what;
    } cases[] = {
        {"views_error_missing_fov", "view a eye 0 0 0 at 0 0 -1 up 0 1 0\n", "v.txt:1:", "expected 'fov'"},
        {"views_error_bad_keyword", "# x\nvew a eye 0 0 0 at 0 0 -1 up 0 1 0 fov 40\n", "v.txt:2:", "expected a line"},
        {"views_error_two_coordinates", "view a eye 0 0 at 0 0 -1 up 0 1 0 fov 40\n", "v.txt:1:",
         "'eye' needs 3 finite"},
        {"views_error_fov_zero", "view a eye 0 0 0 at 0 0 -1 up 0 1 0 fov 0\n", "v.txt:1:", "0 < fov < 180"},
        {"views_error_fov_180", "view a eye 0 0 0 at 0 0 -1 up 0 1 0 fov 180\n", "v.txt:1:", "0 < fov < 180"},
        {"views_error_fov_not_number", "view a eye 0 0 0 at 0 0 -1 up 0 1 0 fov wide\n", "v.txt:1:", "'fov' needs"},
        {"views_error_duplicate_name", "view a eye 0 0 0 at 0 0 -1 up 0 1 0 fov 40\nview a eye 1 0 0 at 0 0 -1 up 0 1 0 fov 40\n",
         "v.txt:2:", "duplicate view name 'a'"},
        {"views_error_up_parallel", "view a eye 0 0 0 at 0 5 0 up 0 1 0 fov 40\n", "v.txt:1:", "parallel"},
        {"views_error_eye_equals_at", "view a eye 1 1 1 at 1 1 1 up 0 1 0 fov 40\n", "v.txt:1:", "same point"},
        {"views_error_bad_name", "view a.b eye 0 0 0 at 0 0 -1 up 0 1 0 fov 40\n", "v.txt:1:", "bad view name"},
        {"views_error_trailing_token", "view a eye 0 0 0 at 0 0 -1 up 0 1 0 fov 40 extra\n", "v.txt:1:",
         "unexpected 'extra'"},
        {"views_error_nan", "view a eye nan 0 0 at 0 0 -1 up 0 1 0 fov 40\n", "v.txt:1:", "finite"},
        {"views_error_empty", "# only a comment\n\n", "v.txt:", "no views"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        tb_begin(cases[i].name);
        rt_views vs;
        char err[TB_ERR_MAX] = "";
        bool ok = rt_views_parse_text(cases[i].text, "v.txt", &vs, err, sizeof err);
        TB_CHECK(!ok, "accepted");
        TB_CHECK(!ok && !strncmp(err, cases[i].where, strlen(cases[i].where)), "'%s' does not start with '%s'",
                 err, cases[i].where);
        TB_CHECK(!ok && strstr(err, cases[i].what), "'%s' lacks '%s'", err, cases[i].what);
        TB_CHECK(ok || (vs.n == 0 && vs.v == NULL), "views not emptied");
        if (ok)
            rt_views_free(&vs);
        tb_end();
    }
    (void)ok_line;

    /* a token longer than the parser's buffer was cut silently: this fov read 4.5 */
    tb_begin("views_error_overlong_number_not_cut");
    {
        char text[512];
        int n = snprintf(text, sizeof text, "view a eye 0 0 0 at 0 0 -1 up 0 1 0 fov 4.5");
        memset(text + n, '0', 200);
        snprintf(text + n + 200, sizeof text - (size_t)n - 200, "e1\n");
        rt_views vs;
        char err[TB_ERR_MAX] = "";
        bool ok = rt_views_parse_text(text, "v.txt", &vs, err, sizeof err);
        TB_CHECK(!ok, "accepted (fov %g)", ok && vs.n ? (double)vs.v[0].fov_deg : 0.0);
        TB_CHECK(!ok && strstr(err, "v.txt:1:") && strstr(err, "'fov' needs") && strstr(err, "000..."), "got '%s'",
                 err);
        if (ok)
            rt_views_free(&vs);
    }
    tb_end();
}

static const char *tetra_obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
static const char *two_views = "view one eye 3 3 3 at 0 0 0 up 0 1 0 fov 40\nview two eye -3 1 2 at 0 0 0 up 0 1 0 fov 30\n";

static void test_scene_files(void)
{
    char d[TB_PATH_MAX];
    tb_pathf(d, sizeof d, "%s/sub", tmp);
    mkdir(d, 0777);
    tb_pathf(d, sizeof d, "%s/other", tmp);
    mkdir(d, 0777);
    bool wrote = write_text("sub/m.obj", tetra_obj) && write_text("sub/views.txt", two_views) &&
                 write_text("other/m.obj", tetra_obj) &&
                 write_text("extra.txt", "view e1 eye 0 0 5 at 0 0 0 up 0 1 0 fov 50\n") &&
                 write_text("s1.scene", "# interior from the top\nmesh interior\n\n"
                                        "view top eye 0 30 0.5 at 0 0 0 up 0 0 -1 fov 50\r\n") &&
                 write_text("s2.scene", "\xef\xbb\xbfmesh sub/m.obj\n") &&
                 write_text("s3.scene", "mesh sub/m.obj\nviews extra.txt\nview e2 eye 0 0 -5 at 0 0 0 up 0 1 0 fov 50\n") &&
                 write_text("s4.scene", "mesh builtin:city\n");
    char err[TB_ERR_MAX] = "";
    rt_scene s;

    tb_begin("scene_file_builtin_with_own_view");
    if (TB_CHECK(wrote, "cannot write test files under %s", tmp)) {
        bool ok = rt_scene_load(at("s1.scene"), &s, err, sizeof err);
        if (TB_CHECK(ok, "%s", err)) {
            rt_mesh ref;
            rt_builtin_generate("interior", &ref, NULL, err, sizeof err);
            TB_CHECK(rt_mesh_hash(&s.mesh) == rt_mesh_hash(&ref), "mesh = built-in interior");
            TB_CHECK(s.views.n == 1 && !strcmp(s.views.v[0].name, "top"), "own views replace the built-in's");
            TB_CHECK(!strcmp(s.name, "s1.scene"), "name %s", s.name);
            rt_mesh_free(&ref);
            rt_scene_free(&s);
        }
        ok = rt_scene_load(at("s4.scene"), &s, err, sizeof err);
        TB_CHECK(ok && s.views.n == 2 && !strcmp(s.views.v[0].name, "overview"), "no view lines: built-in views; %s", err);
        if (ok)
            rt_scene_free(&s);
    }
    tb_end();

    tb_begin("scene_mesh_file_uses_views_txt_beside_it");
    if (wrote) {
        bool ok = rt_scene_load(at("s2.scene"), &s, err, sizeof err);
        TB_CHECK(ok && s.mesh.ntris == 4 && s.views.n == 2 && !strcmp(s.views.v[0].name, "one"), "via .scene: %s", err);
        if (ok)
            rt_scene_free(&s);
        ok = rt_scene_load(at("sub/m.obj"), &s, err, sizeof err);
        TB_CHECK(ok && s.views.n == 2 && !strcmp(s.name, "m.obj"), "direct: %s", err);
        if (ok) {
            const rt_view *v = rt_scene_view(&s, NULL, err, sizeof err);
            TB_CHECK(v == &s.views.v[0], "default = first view");
            TB_CHECK(rt_scene_view(&s, "two", err, sizeof err) == &s.views.v[1], "by name");
            TB_CHECK(!rt_scene_view(&s, "three", err, sizeof err) && strstr(err, "three") && strstr(err, "one, two"),
                     "unknown view lists the names: %s", err);
            TB_CHECK(rt_scene_set_views_file(&s, at("extra.txt"), err, sizeof err) && s.views.n == 1 &&
                         !strcmp(s.views.v[0].name, "e1"),
                     "--views replaces: %s", err);
            rt_scene_free(&s);
        }
        ok = rt_scene_load(at("s3.scene"), &s, err, sizeof err);
        TB_CHECK(ok && s.views.n == 2 && !strcmp(s.views.v[0].name, "e1") && !strcmp(s.views.v[1].name, "e2"),
                 "views + view lines in order: %s", err);
        if (ok)
            rt_scene_free(&s);
    }
    tb_end();

    tb_begin("scene_auto_view_frames_mesh_without_views");
    if (wrote) {
        bool ok = rt_scene_load(at("other/m.obj"), &s, err, sizeof err);
        if (TB_CHECK(ok && s.views.n == 1 && !strcmp(s.views.v[0].name, "auto"), "%s", err)) {
            rt_camera cam;
            TB_CHECK(rt_camera_init(&cam, &s.views.v[0], 33, 19, err, sizeof err), "%s", err);
            rt_ray r = rt_camera_primary_ray(&cam, 16, 9);
            /* centre ray passes within 1e-4 of the bounds centre (0.5, 0.5, 0.5) */
            double w[3] = {0.5 - r.org.x, 0.5 - r.org.y, 0.5 - r.org.z};
            double t = w[0] * r.dir.x + w[1] * r.dir.y + w[2] * r.dir.z;
            double e[3] = {w[0] - t * r.dir.x, w[1] - t * r.dir.y, w[2] - t * r.dir.z};
            TB_CHECK(t > 0 && e[0] * e[0] + e[1] * e[1] + e[2] * e[2] < 1e-8, "centre ray misses the centre");
            rt_scene_free(&s);
        }
    }
    tb_end();

    static const struct {
        const char *name, *file, *text, *where, *what;
    } bad[] = {
        {"scene_error_unknown_keyword", "e1.scene", "mesh interior\ncamera x\n", "e1.scene:2:", "unknown keyword 'camera'"},
        {"scene_error_no_mesh", "e2.scene", "# nothing\nview a eye 0 0 1 at 0 0 0 up 0 1 0 fov 40\n", "e2.scene:",
         "no 'mesh' line"},
        {"scene_error_two_meshes", "e3.scene", "mesh city\nmesh forest\n", "e3.scene:2:", "second 'mesh'"},
        {"scene_error_missing_mesh_file", "e4.scene", "mesh nosuch.obj\n", "e4.scene:1:", "cannot open"},
        {"scene_error_unsupported_mesh_type", "e5.scene", "mesh thing.stl\n", "e5.scene:1:", ".obj, .ply"},
        {"scene_error_bad_view_line", "e6.scene", "mesh city\nview a eye 0 0 at 0 0 0 up 0 1 0 fov 40\n", "e6.scene:2:",
         "'eye' needs 3"},
        {"scene_error_bad_mesh_inside", "e7.scene", "\nmesh bad.obj\n", "e7.scene:2:", "bad.obj:2:"},
        {"scene_error_bad_views_beside_mesh", "e8.scene", "mesh badv/m.obj\n", "e8.scene:1:", "views.txt:1:"},
    };
    char bd[TB_PATH_MAX];
    tb_pathf(bd, sizeof bd, "%s/badv", tmp);
    mkdir(bd, 0777);
    write_text("bad.obj", "v 0 0 0\nf 1 2 3\n");
    write_text("badv/m.obj", tetra_obj);
    write_text("badv/views.txt", "view broken\n");
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        tb_begin(bad[i].name);
        write_text(bad[i].file, bad[i].text);
        bool ok = rt_scene_load(at(bad[i].file), &s, err, sizeof err);
        const char *msg = strstr(err, bad[i].where);
        TB_CHECK(!ok, "accepted");
        TB_CHECK(!ok && msg, "'%s' lacks '%s'", err, bad[i].where);
        TB_CHECK(!ok && strstr(err, bad[i].what), "'%s' lacks '%s'", err, bad[i].what);
        TB_CHECK(ok || (s.mesh.verts == NULL && s.views.v == NULL), "scene not zeroed");
        if (ok)
            rt_scene_free(&s);
        tb_end();
    }

    /* lines and paths longer than the loader's buffers were cut silently:
     * the view line's tail went unchecked, the mesh path named another file */
    {
        static char text[8192];
        int n = snprintf(text, sizeof text, "mesh city\nview a eye 0 0 1 at 0 0 0 up 0 1 0 fov 40");
        memset(text + n, ' ', 1300);
        snprintf(text + n + 1300, sizeof text - (size_t)n - 1300, "extra\n");
        tb_begin("scene_error_overlong_view_line");
        write_text("e9.scene", text);
        bool ok = rt_scene_load(at("e9.scene"), &s, err, sizeof err);
        TB_CHECK(!ok && strstr(err, "e9.scene:2:") && strstr(err, "longer than"), "got '%s'", err);
        if (ok)
            rt_scene_free(&s);
        tb_end();
        n = snprintf(text, sizeof text, "mesh ");
        for (int i = 0; i < 2100; i++)
            n += snprintf(text + n, sizeof text - (size_t)n, "./");
        snprintf(text + n, sizeof text - (size_t)n, "m.obj\n");
        tb_begin("scene_error_overlong_mesh_path");
        write_text("e10.scene", text);
        ok = rt_scene_load(at("e10.scene"), &s, err, sizeof err);
        TB_CHECK(!ok && strstr(err, "e10.scene:1:") && strstr(err, "mesh path longer than"), "got '%s'", err);
        if (ok)
            rt_scene_free(&s);
        tb_end();
    }

    tb_begin("scene_argument_unknown_type_lists_allowed");
    bool ok = rt_scene_load("model.stl", &s, err, sizeof err);
    TB_CHECK(!ok && strstr(err, "model.stl") && strstr(err, "interior, hairball, city, forest") && strstr(err, ".scene"),
             "%s", err);
    ok = rt_scene_load(at("nosuch.ply.gz"), &s, err, sizeof err);
    TB_CHECK(!ok && strstr(err, "nosuch.ply.gz") && strstr(err, "cannot open"), "%s", err);
    tb_end();
}

static bool same_view(const rt_view *a, const rt_view *b)
{
    return !strcmp(a->name, b->name) && !memcmp(&a->eye, &b->eye, sizeof a->eye) &&
           !memcmp(&a->at, &b->at, sizeof a->at) && !memcmp(&a->up, &b->up, sizeof a->up) && a->fov_deg == b->fov_deg;
}

/* scenes/<name>.scene (run from the repository root, as run.sh does) name the
 * built-in and repeat its default views first, so the two cannot drift. */
static void test_repo_scene_files(void)
{
    tb_begin("repo_scene_files_match_builtins");
    for (unsigned i = 0; i < rt_builtin_count(); i++) {
        const char *name = rt_builtin_name(i);
        char path[TB_PATH_MAX], err[TB_ERR_MAX] = "";
        snprintf(path, sizeof path, "scenes/%s.scene", name);
        rt_scene s;
        rt_mesh m;
        rt_views vs;
        bool ok = rt_scene_load(path, &s, err, sizeof err);
        if (!TB_CHECK(ok, "%s", err))
            continue;
        rt_builtin_generate(name, &m, &vs, err, sizeof err);
        TB_CHECK(rt_mesh_hash(&s.mesh) == rt_mesh_hash(&m), "%s: mesh differs from the built-in", path);
        TB_CHECK(s.views.n >= vs.n, "%s: %u views", path, s.views.n);
        for (uint32_t k = 0; k < vs.n && k < s.views.n; k++)
            TB_CHECK(same_view(&s.views.v[k], &vs.v[k]), "%s: view %u (%s) differs from the built-in's %s", path, k,
                     s.views.v[k].name, vs.v[k].name);
        rt_scene_free(&s);
        rt_mesh_free(&m);
        rt_views_free(&vs);
    }
    tb_end();
}

int main(void)
{
    test_repo_scene_files();
    const char *t = getenv("RTSIM_TMP");
    tb_pathf(tmp, sizeof tmp, "%s/tb_tracer_io_scene", t && *t ? t : "/tmp");
    mkdir(tmp, 0777);
    test_views_valid();
    test_views_errors();
    test_scene_files();
    return tb_finish();
}
