// tracer_loader.cpp — scene loading speed: our OBJ/PLY readers (tracer/io/scene.h)
// against Assimp (the reference) on the same uncompressed file.
//
//   tracer_loader FILE [RUNS]        prints "ours_median_s ref_median_s tris_ours tris_ref"
//   tracer_loader --to-obj IN OUT    writes IN (any scene we read) as a plain OBJ
//
// Single-threaded; each loader runs RUNS times (default 5) and the median wall
// time is reported. Assimp gets only aiProcess_Triangulate (we fan-triangulate
// too and do nothing else). Exit 2 on bad input.
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "tracer/io/scene.h"

static double now_s()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

static double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static int to_obj(const char *in, const char *out)
{
    rt_mesh m;
    char err[1024];
    if (!rt_mesh_load(in, &m, err, sizeof err)) {
        std::fprintf(stderr, "tracer_loader: %s\n", err);
        return 2;
    }
    std::string tmp = std::string(out) + ".tmp";
    FILE *f = std::fopen(tmp.c_str(), "w");
    if (!f) {
        std::fprintf(stderr, "tracer_loader: cannot write %s\n", tmp.c_str());
        rt_mesh_free(&m);
        return 2;
    }
    std::fprintf(f, "# converted by tracer_loader from %s\n", in);
    for (uint32_t i = 0; i < m.nverts; i++)
        std::fprintf(f, "v %.6g %.6g %.6g\n", double(m.verts[i].x), double(m.verts[i].y), double(m.verts[i].z));
    for (uint32_t i = 0; i < m.ntris; i++)
        std::fprintf(f, "f %u %u %u\n", m.tris[3 * i] + 1, m.tris[3 * i + 1] + 1, m.tris[3 * i + 2] + 1);
    bool ok = std::fclose(f) == 0 && std::rename(tmp.c_str(), out) == 0;
    rt_mesh_free(&m);
    return ok ? 0 : 2;
}

int main(int argc, char **argv)
{
    if (argc == 4 && !std::strcmp(argv[1], "--to-obj"))
        return to_obj(argv[2], argv[3]);
    if (argc < 2 || argc > 3) {
        std::fprintf(stderr, "usage: tracer_loader FILE [RUNS] | tracer_loader --to-obj IN OUT\n");
        return 2;
    }
    const char *file = argv[1];
    int runs = argc == 3 ? std::atoi(argv[2]) : 5;
    if (runs < 1 || runs > 1000) {
        std::fprintf(stderr, "tracer_loader: RUNS must be 1..1000\n");
        return 2;
    }
    std::vector<double> ours, ref;
    unsigned long long tris_ours = 0, tris_ref = 0;
    char err[1024];
    for (int r = 0; r < runs; r++) {
        double t0 = now_s();
        rt_mesh m;
        if (!rt_mesh_load(file, &m, err, sizeof err)) {
            std::fprintf(stderr, "tracer_loader: %s\n", err);
            return 2;
        }
        ours.push_back(now_s() - t0);
        tris_ours = m.ntris;
        rt_mesh_free(&m);

        t0 = now_s();
        {
            Assimp::Importer imp;
            const aiScene *s = imp.ReadFile(file, aiProcess_Triangulate);
            if (!s) {
                std::fprintf(stderr, "tracer_loader: Assimp: %s\n", imp.GetErrorString());
                return 2;
            }
            tris_ref = 0;
            for (unsigned i = 0; i < s->mNumMeshes; i++)
                tris_ref += s->mMeshes[i]->mNumFaces;
        }   // the importer frees the scene here: part of the cost, as ours
        ref.push_back(now_s() - t0);
    }
    std::printf("%.6f %.6f %llu %llu\n", median(ours), median(ref), tris_ours, tris_ref);
    return 0;
}
