/* memsys_config.c — schemas of the memory side; see memsys_config.h.
 * Defaults: the paper's MBVH4 machine (sec. 3: 16 KB node L1 per TRV, 128 KB
 * node L2, 128 KB primitive cache of two 64 B-line banks, all 4-way, node-
 * sized lines). MSHR counts, hit latencies and port counts are not in the
 * paper; the values below are our choices (see the preset comments). */
#include "model/mem/memsys_config.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/dram/dram_timing.h"
#include "tracer/bvh/bvh_layout.h"

/* The keys every cache has (ADDRESSING: the node caches' extra key, or nothing). */
#define CACHE_PARAMS(size, line, banks, mshrs, merge, lat, ...)                                                        \
    {                                                                                                                  \
        {"size", RTCFG_INT, size, 64, 1073741824.0, RTCFG_POW2, NULL, "bytes", "capacity"},                           \
        {"line", RTCFG_INT, line, 16, 4096, RTCFG_POW2, NULL, "bytes", "line size (node caches: node size)"},          \
        {"ways", RTCFG_INT, "4", 1, 64, RTCFG_POW2, NULL, "ways", "associativity (true LRU)"},                        \
        {"banks", RTCFG_INT, banks, 1, 16, RTCFG_POW2, NULL, "banks", "banks interleaved by line"},                   \
        {"ports", RTCFG_INT, "1", 1, 16, 0, NULL, "accesses/cycle", "accesses accepted per cycle"},                   \
        {"mshrs", RTCFG_INT, mshrs, 1, 256, 0, NULL, "lines", "miss status holding registers (missing lines)"},       \
        {"mshr_merge", RTCFG_INT, merge, 1, 64, 0, NULL, "requests", "requests that may wait on one MSHR"},           \
        {"hit_latency", RTCFG_INT, lat, 1, 1000, 0, NULL, "cycles", "cycles from access to data"},                    \
        __VA_ARGS__                                                                                                    \
    }

/* Node caches only: paper sec. 3.1's two organisations for nodes that are
 * not a power of two bytes (MBVH3, 5, 6): byte addresses and power-of-two
 * lines (nodes may straddle lines), or "array indices rather than byte
 * addresses, and ... a node-sized data word" (a line is one node). Both node
 * caches must agree (check_caches). */
#define NODE_ADDRESSING                                                                                                \
    {"addressing", RTCFG_ENUM, "byte", 0, 0, 0, "byte|index", "",                                                    \
     "byte: lines of `line` B; index: one node per line (N x 32 B, `line` unused), tag/set from the node index"}

static const rtcfg_param node_l1_params[] = CACHE_PARAMS("16K", "128", "1", "8", "4", "1", NODE_ADDRESSING);
static const rtcfg_param node_l2_params[] = CACHE_PARAMS("128K", "128", "1", "32", "8", "4", NODE_ADDRESSING);
static const rtcfg_param prim_params[] = CACHE_PARAMS("128K", "64", "2", "32", "8", "2", );

static int check_caches(const rtcfg *cfg, char *err, size_t errlen);

const rtcfg_schema memsys_schema_node_l1 = {"node_l1", "per-TRV node L1 cache", node_l1_params, 9, check_caches};
const rtcfg_schema memsys_schema_node_l2 = {"node_l2", "node L2 cache shared by the TRVs", node_l2_params, 9, NULL};
const rtcfg_schema memsys_schema_prim = {"prim", "primitive (triangle) cache of the IST", prim_params, 8, NULL};

static const rtcfg_param memory_params[] = {
    {"model", RTCFG_ENUM, "lpddr3", 0, 0, 0, "fixed|lpddr3", "", "main memory: fixed latency+bandwidth or LPDDR3"},
    {"fixed_latency", RTCFG_INT, "50", 1, 100000, 0, NULL, "cycles", "fixed model: request to data, accel cycles"},
    {"fixed_bandwidth_gbs", RTCFG_REAL, "12.8", 0, 10000, 0, NULL, "GB/s", "fixed model: peak bandwidth (0 = unlimited)"},
    {"dram_config", RTCFG_STRING, "lpddr3_1600.ini", 0, 0, 0, NULL, "", "lpddr3: spec file (relative: in model/data)"},
    {"dram_power", RTCFG_STRING, "lpddr3_1600_idd.ini", 0, 0, 0, NULL, "", "lpddr3: currents for energy (empty: none)"},
    {"max_outstanding", RTCFG_INT, "256", 1, 65536, 0, NULL, "requests", "requests in flight at the memory"},
};
const rtcfg_schema memsys_schema_memory = {"memory", "main memory", memory_params, 6, NULL};

#define FIFO_PARAM(name, desc) {name, RTCFG_INT, "32", 1, 65536, 0, NULL, "entries", desc}
static const rtcfg_param fifo_params[] = {
    FIFO_PARAM("mem_l1_miss", "node L1 -> L2 arbiter (per TRV)"),
    FIFO_PARAM("mem_l1_fill", "L2 arbiter -> node L1 (per TRV)"),
    FIFO_PARAM("mem_l2_req", "L2 arbiter -> node L2"),
    FIFO_PARAM("mem_l2_resp", "node L2 -> L2 arbiter"),
    FIFO_PARAM("mem_l2_miss", "node L2 -> memory arbiter"),
    FIFO_PARAM("mem_l2_fill", "memory arbiter -> node L2"),
    FIFO_PARAM("mem_prim_miss", "primitive cache -> memory arbiter"),
    FIFO_PARAM("mem_prim_fill", "memory arbiter -> primitive cache"),
    FIFO_PARAM("mem_req", "memory arbiter -> memory"),
    FIFO_PARAM("mem_resp", "memory -> memory arbiter"),
    FIFO_PARAM("mem_dram_req", "lpddr3: DRAM front end -> LPDDR3 port"),
    FIFO_PARAM("mem_dram_resp", "lpddr3: LPDDR3 port -> DRAM front end"),
    {"mem_latency", RTCFG_INT, "1", 1, 1000, 0, NULL, "cycles", "latency of every memory-side FIFO"},
};
const rtcfg_schema memsys_schema_fifo = {"fifo", "memory-side FIFOs", fifo_params, 13, NULL};

/* ---- [dram]: the keys of the DRAM standard file, built when the file is known ---- */

/* One block per configuration (freed by rtcfg_destroy through rtcfg_own):
 * the schema, its parameter table and the texts the table points to. */
typedef struct dram_schema_block {
    rtcfg_schema schema;
    int n;
    rtcfg_param params[DRAM_MAX_ENTRIES];
    char name[DRAM_MAX_ENTRIES][DRAM_NAME_LEN + DRAM_KEY_LEN];
    char def[DRAM_MAX_ENTRIES][DRAM_VALUE_LEN];
    char desc[DRAM_MAX_ENTRIES][DRAM_KEY_LEN + 48];
    char range[DRAM_MAX_ENTRIES][96];
    char title[300];
} dram_schema_block;

static void add_dram_param(void *user, const char *section, const char *key, const char *value)
{
    dram_schema_block *b = user;
    if (b->n == DRAM_MAX_ENTRIES) /* cannot happen: the loader holds at most as many */
        return;
    int i = b->n++;
    dram_spec_describe_key(section, key, b->range[i], sizeof b->range[i]);
    snprintf(b->name[i], sizeof b->name[i], "%s.%s", section, key);
    snprintf(b->def[i], sizeof b->def[i], "%s", value);
    snprintf(b->desc[i], sizeof b->desc[i], "DRAM file [%s] %s", section, key);
    /* type string: values are integer expressions over [timing] names, checked by
     * dram_spec_load in check_dram(); the range text is shown as the allowed values */
    b->params[i] = (rtcfg_param){b->name[i], RTCFG_STRING, b->def[i], 0, 0, 0, b->range[i], "", b->desc[i]};
}

int memsys_dram_path(const rtcfg *cfg, char *buf, size_t len)
{
    const char *file = rtcfg_str(cfg, "memory.dram_config");
    bool rel = strchr(file, '/') == NULL;
    if (snprintf(buf, len, "%s%s%s", rel ? rtcfg_data_dir() : "", rel ? "/" : "", file) >= (int)len)
        return -1;
    return 0;
}

static int check_dram(const rtcfg *cfg, char *err, size_t errlen);

/* Deferred (rtcfg_finish): memory.dram_config is final now. */
static int register_dram(rtcfg *cfg, void *user, char *err, size_t errlen)
{
    (void)user;
    char path[RTCFG_PATH_MAX], why[RTCFG_MSG_MAX];
    const char *file = rtcfg_str(cfg, "memory.dram_config");
    bool needed = rtcfg_enum(cfg, "memory.model") == MEMSYS_LPDDR3;
    if (memsys_dram_path(cfg, path, sizeof path)) {
        if (!needed)
            return 0;
        return rtcfg_errorf(err, errlen, "memory.dram_config = %s: path longer than %d characters", file,
                            RTCFG_PATH_MAX - 1);
    }
    dram_schema_block *b = calloc(1, sizeof *b);
    if (!b)
        return rtcfg_errorf(err, errlen, "out of memory");
    if (dram_spec_entries(path, NULL, 0, add_dram_param, b, why, sizeof why)) {
        free(b);
        /* the fixed model does not read the file: no error, and no [dram] keys */
        return needed ? rtcfg_errorf(err, errlen, "memory.dram_config = %s: %s", file, why) : 0;
    }
    snprintf(b->title, sizeof b->title, "DRAM standard %s (SECTION.KEY of the file; docs/dram.md)", file);
    b->schema = (rtcfg_schema){"dram", b->title, b->params, b->n, check_dram};
    rtcfg_own(cfg, b);
    return rtcfg_add_schema(cfg, &b->schema, err, errlen);
}

int memsys_dram_spec_load(const rtcfg *cfg, dram_spec *spec, char *err, size_t errlen)
{
    char path[RTCFG_PATH_MAX];
    const char *file = rtcfg_str(cfg, "memory.dram_config");
    if (memsys_dram_path(cfg, path, sizeof path))
        return rtcfg_errorf(err, errlen, "memory.dram_config = %s: path longer than %d characters", file,
                            RTCFG_PATH_MAX - 1);
    const rtcfg_schema *ds = NULL;
    for (int i = 0; i < rtcfg_schema_count(cfg); i++)
        if (strcmp(rtcfg_schema_at(cfg, i)->section, "dram") == 0)
            ds = rtcfg_schema_at(cfg, i);
    /* overrides: the keys whose value came from a machine file or --set */
    int n = 0;
    const char **sets = NULL, **origins = NULL;
    char (*text)[DRAM_NAME_LEN + DRAM_KEY_LEN + DRAM_VALUE_LEN + 2] = NULL;
    if (ds && ds->nparams) {
        sets = calloc((size_t)ds->nparams, sizeof *sets);
        origins = calloc((size_t)ds->nparams, sizeof *origins);
        text = calloc((size_t)ds->nparams, sizeof *text);
        if (!sets || !origins || !text) {
            free(sets), free(origins), free(text);
            return rtcfg_errorf(err, errlen, "out of memory");
        }
        for (int k = 0; k < ds->nparams; k++) {
            char key[200];
            snprintf(key, sizeof key, "dram.%s", ds->params[k].name);
            const char *src = rtcfg_source(cfg, key);
            if (strcmp(src, "default") == 0)
                continue;
            snprintf(text[n], sizeof text[n], "%s=%s", ds->params[k].name, rtcfg_str(cfg, key));
            sets[n] = text[n];
            origins[n] = src;
            n++;
        }
    }
    char why[RTCFG_MSG_MAX];
    int rc = dram_spec_load_from(spec, path, sets, origins, n, why, sizeof why);
    if (rc)
        rtcfg_errorf(err, errlen, "memory.dram_config = %s: %s", file, why);
    free(sets), free(origins), free(text);
    return rc;
}

/* The standard must load with the [dram] values (ranges and cross-checks of
 * dram_spec_load), at rtcfg_finish so a bad value fails before any work. */
static int check_dram(const rtcfg *cfg, char *err, size_t errlen)
{
    dram_spec *spec = malloc(sizeof *spec);
    if (!spec)
        return rtcfg_errorf(err, errlen, "out of memory");
    int rc = memsys_dram_spec_load(cfg, spec, err, errlen);
    free(spec);
    return rc;
}

int memsys_add_schemas(rtcfg *cfg, char *err, size_t errlen)
{
    const rtcfg_schema *all[] = {&memsys_schema_node_l1, &memsys_schema_node_l2, &memsys_schema_prim,
                                 &memsys_schema_memory, &memsys_schema_fifo};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        if (rtcfg_add_schema(cfg, all[i], err, errlen))
            return -1;
    rtcfg_add_deferred(cfg, register_dram, NULL);
    return 0;
}

void memsys_cache_params(const rtcfg *cfg, const char *section, cache_params *out)
{
    char key[64];
#define GET(field, name) (snprintf(key, sizeof key, "%s.%s", section, name), out->field = (uint32_t)rtcfg_int(cfg, key))
    GET(size_bytes, "size");
    GET(line_bytes, "line");
    GET(ways, "ways");
    GET(banks, "banks");
    GET(ports, "ports");
    GET(mshrs, "mshrs");
    GET(mshr_merge, "mshr_merge");
    GET(hit_latency, "hit_latency");
#undef GET
    out->index_addressed = 0;
    snprintf(key, sizeof key, "%s.addressing", section);
    if (rtcfg_has(cfg, key) && rtcfg_enum(cfg, key) == MEMSYS_INDEX) {
        /* one node per line: the node size replaces `line` */
        out->index_addressed = 1;
        out->line_bytes = (uint32_t)memsys_node_bytes(cfg);
    }
}

int64_t memsys_node_bytes(const rtcfg *cfg) { return RT_SLOT_BYTES * rtcfg_int(cfg, "machine.branching"); }

int64_t memsys_line_bytes(const rtcfg *cfg, const char *section)
{
    cache_params p;
    memsys_cache_params(cfg, section, &p);
    return p.line_bytes;
}

/* The most lines an object of `bytes` bytes touches in a cache of `line`-byte
 * lines, given the memory image's layout (tracer/bvh/bvh_image.c): nodes of N x
 * 32 B back to back from address 0, triangles of 48 B back to back from a
 * 4 KB boundary. Object i starts at i * bytes, so its offset within a line
 * is a multiple of g = gcd(bytes, line), at worst line - g. */
int64_t memsys_lines_touched(int64_t bytes, int64_t line)
{
    int64_t a = bytes, b = line;
    while (b) {
        int64_t r = a % b;
        a = b, b = r;
    }
    return (line - a + bytes - 1) / line + 1;
}

static int check_caches(const rtcfg *cfg, char *err, size_t errlen)
{
    static const char *const secs[] = {"node_l1", "node_l2", "prim"};
    for (int i = 0; i < 3; i++) {
        char key[32];
        snprintf(key, sizeof key, "%s.size", secs[i]);
        if (!rtcfg_has(cfg, key))
            continue;
        cache_params p;
        memsys_cache_params(cfg, secs[i], &p);
        if (cache_core_check_params(&p, secs[i], err, errlen))
            return -1;
    }
    /* A probe is all-or-nothing (cache.h): every line one access touches
     * must fit in the cache at once, or the requester loops for ever, and
     * the cache serves at most CACHE_MAX_LINES_PER_ACCESS lines per access.
     * Consecutive lines spread over the sets and banks, so the cache holds
     * them all when it has that many lines. */
    static const struct {
        const char *sec, *what;
    } fits[] = {{"node_l1", "one BVH node"}, {"prim", "one triangle"}};
    for (int i = 0; i < 2; i++) {
        char ks[32], kl[32];
        snprintf(ks, sizeof ks, "%s.size", fits[i].sec);
        snprintf(kl, sizeof kl, "%s.line", fits[i].sec);
        if (!rtcfg_has(cfg, ks))
            continue;
        int64_t bytes = i == 0 ? RT_SLOT_BYTES * rtcfg_int(cfg, "machine.branching") : RT_TRI_BYTES;
        int64_t size = rtcfg_int(cfg, ks), line = memsys_line_bytes(cfg, fits[i].sec);
        int64_t need = memsys_lines_touched(bytes, line);
        if (need > CACHE_MAX_LINES_PER_ACCESS) {
            int64_t min_line = line;
            while (memsys_lines_touched(bytes, min_line) > CACHE_MAX_LINES_PER_ACCESS)
                min_line *= 2;
            return rtcfg_errorf(err, errlen,
                                "%s = %lld: %s of %lld B touches up to %lld lines, more than the %d one access may "
                                "touch: %s must be >= %lld",
                                kl, (long long)line, fits[i].what, (long long)bytes, (long long)need,
                                CACHE_MAX_LINES_PER_ACCESS, kl, (long long)min_line);
        }
        /* node L1: the lines of one node must be requested together, so
         * they arrive together: with fewer MSHRs they come one round trip
         * after the other while the other rays of the TRV probe and fill
         * theirs, evicting the first ones (found by tb_accel_random_configs:
         * 1 MSHR, 7-line nodes, a direct-mapped L1, two rays per TRV looping
         * for ever). The primitive cache is exempt: one ray issues at a
         * time in the IST, so a one-MSHR primitive cache fetching a
         * triangle's two lines in turn completes (tb_cache_memsys,
         * tb_accel_system "one_mshr"). */
        char km[32];
        snprintf(km, sizeof km, "%s.mshrs", fits[i].sec);
        if (i == 0 && rtcfg_int(cfg, km) < need)
            return rtcfg_errorf(err, errlen,
                                "%s = %lld: %s of %lld B touches up to %lld lines of %s = %lld B, all requested at "
                                "once: %s must be >= %lld (or raise %s)",
                                km, (long long)rtcfg_int(cfg, km), fits[i].what, (long long)bytes, (long long)need, kl,
                                (long long)line, km, (long long)need, kl);
        /* direct-mapped and an access over several lines: two waiting
         * rays whose lines share a set evict each other's lines on every
         * fill, for ever (found by tb_accel_random_configs four times, in
         * both caches: 1 way, nodes of 3, 5 and 7 lines, triangles of 2) */
        char kw[32];
        snprintf(kw, sizeof kw, "%s.ways", fits[i].sec);
        if (need > 1 && rtcfg_int(cfg, kw) < 2)
            return rtcfg_errorf(err, errlen,
                                "%s = 1: %s of %lld B touches up to %lld lines of %s = %lld B; a direct-mapped cache "
                                "lets the rays waiting on it evict each other's lines for ever: %s must be >= 2 (or "
                                "raise %s to hold it in one line)",
                                kw, fits[i].what, (long long)bytes, (long long)need, kl, (long long)line, kw, kl);
        if (size / line < need)
            return rtcfg_errorf(err, errlen,
                                "%s = %lld holds %lld line(s) of %s = %lld B, but %s of %lld B touches up to %lld "
                                "lines, which must all be present at once: %s must be >= %lld",
                                ks, (long long)size, (long long)(size / line), kl, (long long)line, fits[i].what,
                                (long long)bytes, (long long)need, ks, (long long)(need * line));
    }
    if (!rtcfg_has(cfg, "node_l2.line"))
        return 0;
    /* paper sec. 3.1: "the node cache hierarchy" is addressed one way; a
     * mixed pair would make an L1 fill a part of an L2 line, or straddle
     * two L2 words */
    if (rtcfg_enum(cfg, "node_l1.addressing") != rtcfg_enum(cfg, "node_l2.addressing"))
        return rtcfg_errorf(err, errlen,
                            "node_l1.addressing = %s (%s) but node_l2.addressing = %s (%s): the node cache hierarchy "
                            "is addressed one way (byte|index, both keys the same; an L1 fill is one L2 line)",
                            rtcfg_str(cfg, "node_l1.addressing"), rtcfg_source(cfg, "node_l1.addressing"),
                            rtcfg_str(cfg, "node_l2.addressing"), rtcfg_source(cfg, "node_l2.addressing"));
    if (rtcfg_int(cfg, "node_l1.line") > rtcfg_int(cfg, "node_l2.line") && rtcfg_enum(cfg, "node_l1.addressing") == MEMSYS_BYTE)
        return rtcfg_errorf(err, errlen, "node_l1.line = %lld must be <= node_l2.line = %lld (an L1 fill is one L2 line)",
                            (long long)rtcfg_int(cfg, "node_l1.line"), (long long)rtcfg_int(cfg, "node_l2.line"));
    return 0;
}
