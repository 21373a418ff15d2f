/* tb_cache_core.c — the generic cache core (model/mem/cache_core.h): crafted hit, miss,
 * merge, eviction, MSHR exhaustion, port and bank sequences, and random
 * sequences against a simple reference model (an explicit MRU..LRU list per
 * set, a list of pending lines) that must agree on every result, every popped
 * miss, every line's presence and the statistics; the same for an
 * index-addressed cache of 96 B and 160 B node words (non-power-of-two sets);
 * the functional levels' access (cache_core_touch) against access-then-fill. */
#include "model/mem/cache_core.h"
#include "testbench/tb.h"

static cache_core *mk_addressed(uint32_t size, uint32_t line, uint32_t ways, uint32_t banks, uint32_t ports,
                          uint32_t mshrs, uint32_t merge, uint32_t index_addressed)
{
    cache_params p = {size, line, ways, banks, ports, mshrs, merge, 1, index_addressed};
    char err[256];
    cache_core *c = cache_core_create(&p, err, sizeof err);
    if (!c)
        printf("cache_core_create: %s\n", err);
    return c;
}

static cache_core *mk(uint32_t size, uint32_t line, uint32_t ways, uint32_t banks, uint32_t ports, uint32_t mshrs,
                 uint32_t merge)
{
    return mk_addressed(size, line, ways, banks, ports, mshrs, merge, 0);
}

/* Pops the oldest downstream request and answers it at once. */
static int serve_one(cache_core *c, int64_t now)
{
    mem_req r;
    if (!cache_core_pop_miss(c, &r))
        return -2;
    mem_resp resp = {r.addr, r.bytes, r.src, 0, r.tag};
    return cache_core_fill(c, &resp, now);
}

static void test_hit_miss_merge(void)
{
    tb_begin("hit_miss_merge_fill");
    cache_core *c = mk(1024, 64, 2, 1, 1, 4, 4);
    TB_EQ_INT(cache_core_access(c, 0x100, 64, 0), CACHE_MISS);
    TB_EQ_INT(cache_core_access(c, 0x120, 8, 1), CACHE_MISS); /* same line: merges */
    cache_stats s;
    cache_core_get_stats(c, &s);
    TB_EQ_INT(s.miss_lines, 1);
    TB_EQ_INT(s.merged, 1);
    TB_EQ_INT(s.misses, 2);
    TB_EQ_INT(cache_core_mshrs_busy(c), 1);
    TB_CHECK(cache_core_line_pending(c, 0x13f) && !cache_core_contains(c, 0x100), "pending, not present");
    mem_req r;
    TB_CHECK(cache_core_pop_miss(c, &r), "a miss is queued");
    TB_EQ_INT(r.addr, 0x100);
    TB_EQ_INT(r.bytes, 64);
    TB_CHECK(!cache_core_pop_miss(c, &r), "only one request for the merged line");
    TB_EQ_INT(cache_core_access(c, 0x100, 4, 2), CACHE_MISS); /* still pending before the fill */
    mem_resp bad = {0x140, 64, 0, 0, r.tag};
    TB_EQ_INT(cache_core_fill(c, &bad, 3), -1);             /* wrong line for that MSHR */
    mem_resp ok = {0x100, 64, 0, 0, r.tag};
    TB_EQ_INT(cache_core_fill(c, &ok, 3), 0);               /* probes leave no waiters */
    TB_EQ_INT(cache_core_access(c, 0x104, 16, 4), CACHE_HIT);
    TB_EQ_INT(cache_core_mshrs_busy(c), 0);
    cache_core_get_stats(c, &s);
    TB_EQ_INT(s.hits, 1);
    TB_EQ_INT(s.fills, 1);
    TB_EQ_INT(s.accesses, 4);
    cache_core_destroy(c);
    tb_end();
}

static void test_lru_eviction(void)
{
    tb_begin("lru_eviction_order");
    /* 4-way, 4 sets of 64 B: lines 0, 4, 8, 12, 16 (x64 B) map to set 0 */
    cache_core *c = mk(1024, 64, 4, 1, 1, 8, 1);
    int64_t t = 0;
    for (int i = 0; i < 4; i++) {
        TB_EQ_INT(cache_core_access(c, (uint64_t)i * 256, 64, t++), CACHE_MISS);
        TB_EQ_INT(serve_one(c, t), 0);
    }
    TB_EQ_INT(cache_core_access(c, 0, 64, t++), CACHE_HIT);     /* line 0 becomes MRU; line 4 is LRU */
    TB_EQ_INT(cache_core_access(c, 1024, 64, t++), CACHE_MISS); /* line 16 */
    TB_EQ_INT(serve_one(c, t), 0);
    TB_CHECK(cache_core_contains(c, 0), "MRU line kept");
    TB_CHECK(!cache_core_contains(c, 256), "LRU line evicted");
    TB_CHECK(cache_core_contains(c, 512) && cache_core_contains(c, 768) && cache_core_contains(c, 1024), "others kept");
    TB_CHECK(cache_core_contains(c, 0) && !cache_core_contains(c, 64), "other sets untouched");
    cache_stats s;
    cache_core_get_stats(c, &s);
    TB_EQ_INT(s.evictions, 1);
    TB_EQ_INT(s.fills, 5);
    cache_core_destroy(c);
    tb_end();
}

static void test_mshr_exhaustion(void)
{
    tb_begin("mshr_exhaustion_blocks_then_recovers");
    cache_core *c = mk(1024, 64, 4, 1, 4, 2, 2);
    TB_EQ_INT(cache_core_access(c, 0x000, 4, 0), CACHE_MISS);
    TB_EQ_INT(cache_core_access(c, 0x040, 4, 0), CACHE_MISS);
    TB_EQ_INT(cache_core_access(c, 0x080, 4, 0), CACHE_BLOCKED);   /* no MSHR left */
    TB_EQ_INT(cache_core_access(c, 0x044, 4, 0), CACHE_MISS);      /* merging still works */
    TB_CHECK(!cache_core_line_pending(c, 0x080), "a blocked access changes nothing");
    /* an access needing two new MSHRs when one is free: blocked, nothing allocated */
    TB_EQ_INT(serve_one(c, 1), 0);
    TB_EQ_INT(cache_core_access(c, 0x0b0, 48, 2), CACHE_BLOCKED);  /* lines 0x80 and 0xc0 */
    TB_EQ_INT(cache_core_mshrs_busy(c), 1);
    TB_EQ_INT(cache_core_access(c, 0x080, 4, 2), CACHE_MISS);
    cache_stats s;
    cache_core_get_stats(c, &s);
    TB_EQ_INT(s.blocked_mshr, 2);
    TB_EQ_INT(s.miss_lines, 3);
    char d[200];
    cache_core_describe(c, 10, d, sizeof d);
    TB_CHECK(strstr(d, "mshrs 2/2 busy (2 unsent)") && strstr(d, "oldest miss 0x40 waiting 10 cycles"), "describe: %s", d);
    cache_core_destroy(c);
    tb_end();
}

/* One MSHR and a probe over two missing lines: all-or-nothing could never
 * accept it (the ray would loop forever, as the primitive cache did with
 * prim.mshrs=1), so it takes the free MSHR for its first line and the
 * second on a later try. */
static void test_partial_probe_one_mshr(void)
{
    tb_begin("one_mshr_two_line_probe_progresses_line_by_line");
    cache_core *c = mk(1024, 64, 4, 2, 1, 1, 4);
    TB_EQ_INT(cache_core_access(c, 0x030, 48, 0), CACHE_MISS); /* lines 0x00 and 0x40, two banks */
    TB_CHECK(cache_core_line_pending(c, 0x000) && !cache_core_line_pending(c, 0x040), "first line requested only");
    TB_EQ_INT(cache_core_access(c, 0x030, 48, 1), CACHE_BLOCKED); /* its one MSHR is busy */
    TB_EQ_INT(serve_one(c, 2), 0);
    TB_EQ_INT(cache_core_access(c, 0x030, 48, 3), CACHE_MISS);   /* now the second line */
    TB_CHECK(cache_core_contains(c, 0x000) && cache_core_line_pending(c, 0x040), "second line requested");
    TB_EQ_INT(serve_one(c, 4), 0);
    TB_EQ_INT(cache_core_access(c, 0x030, 48, 5), CACHE_HIT);
    /* requests (waiters need all their lines at once) stay all-or-nothing */
    mem_req q = {.addr = 0x130, .bytes = 48, .tag = 7};
    TB_EQ_INT(cache_core_request(c, &q, 6), CACHE_BLOCKED);
    TB_EQ_INT(cache_core_mshrs_busy(c), 0);
    cache_stats s;
    cache_core_get_stats(c, &s);
    TB_EQ_INT(s.miss_lines, 2);
    TB_EQ_INT(s.blocked_mshr, 2);
    cache_core_destroy(c);
    tb_end();
}

static void test_request_waiters(void)
{
    tb_begin("request_mode_waiters_and_merge_limit");
    cache_core *c = mk(4096, 128, 4, 1, 8, 4, 2);
    mem_req a = {0x200, 64, 3, 0, 0, 77}, b = {0x240, 64, 1, 0, 0, 78}, x = {0x200, 64, 2, 0, 0, 79};
    TB_EQ_INT(cache_core_request(c, &a, 0), CACHE_MISS);
    TB_EQ_INT(cache_core_request(c, &b, 0), CACHE_MISS);   /* same 128 B line */
    TB_EQ_INT(cache_core_request(c, &x, 0), CACHE_BLOCKED); /* mshr_merge = 2 */
    cache_stats s;
    cache_core_get_stats(c, &s);
    TB_EQ_INT(s.blocked_merge, 1);
    TB_EQ_INT(cache_core_ready_count(c), 0);
    TB_EQ_INT(serve_one(c, 5), 2);
    mem_req out;
    TB_CHECK(cache_core_pop_ready(c, &out) && out.tag == 77 && out.src == 3 && out.addr == 0x200, "first waiter back");
    TB_CHECK(cache_core_pop_ready(c, &out) && out.tag == 78 && out.src == 1, "second waiter back");
    TB_CHECK(!cache_core_pop_ready(c, &out), "no more");
    TB_EQ_INT(cache_core_request(c, &x, 6), CACHE_HIT);
    /* a request over two lines, one present: waits for the other only */
    mem_req y = {0x260, 64, 0, 0, 0, 90};             /* lines 0x200 (present) and 0x280 */
    TB_EQ_INT(cache_core_request(c, &y, 7), CACHE_MISS);
    TB_EQ_INT(serve_one(c, 8), 1);
    TB_CHECK(cache_core_pop_ready(c, &out) && out.tag == 90, "two-line waiter released");
    /* a waiter over two missing lines is released by the second fill only */
    mem_req z = {0x3c0, 128, 0, 0, 0, 91};
    TB_EQ_INT(cache_core_request(c, &z, 9), CACHE_MISS);
    TB_EQ_INT(cache_core_misses_queued(c), 2);
    TB_EQ_INT(serve_one(c, 10), 0);
    TB_EQ_INT(serve_one(c, 11), 1);
    TB_CHECK(cache_core_pop_ready(c, &out) && out.tag == 91, "released after both");
    cache_core_destroy(c);
    tb_end();
}

static void test_ports(void)
{
    tb_begin("ports_and_banks_per_cycle");
    cache_core *c = mk(1024, 64, 4, 1, 1, 8, 8);
    TB_EQ_INT(cache_core_access(c, 0x000, 4, 0), CACHE_MISS);
    TB_EQ_INT(cache_core_access(c, 0x040, 4, 0), CACHE_BLOCKED);   /* one port */
    TB_EQ_INT(cache_core_access(c, 0x040, 4, 1), CACHE_MISS);
    cache_core_destroy(c);
    /* two ports, two banks: bank 0 takes two line reads per cycle */
    c = mk(1024, 64, 4, 2, 2, 8, 8);
    TB_EQ_INT(cache_core_access(c, 0x000, 160, 0), CACHE_MISS);    /* lines 0,1,2: bank 0 twice */
    TB_EQ_INT(cache_core_access(c, 0x100, 4, 0), CACHE_BLOCKED);   /* line 4: bank 0 full */
    TB_EQ_INT(cache_core_access(c, 0x0c0, 4, 0), CACHE_MISS);      /* line 3: bank 1 has a port left */
    TB_EQ_INT(cache_core_access(c, 0x100, 4, 1), CACHE_MISS);
    cache_stats s0;
    cache_core_get_stats(c, &s0);
    TB_EQ_INT(s0.blocked_bank, 1);
    cache_core_destroy(c);
    c = mk(1024, 64, 4, 2, 2, 8, 8);
    TB_EQ_INT(cache_core_access(c, 0x000, 4, 0), CACHE_MISS);
    TB_EQ_INT(cache_core_access(c, 0x040, 4, 0), CACHE_MISS);      /* other bank */
    TB_EQ_INT(cache_core_access(c, 0x080, 4, 0), CACHE_BLOCKED);   /* third access: 2 ports */
    TB_EQ_INT(cache_core_access(c, 0x080, 4, 1), CACHE_MISS);
    cache_stats s;
    cache_core_get_stats(c, &s);
    TB_EQ_INT(s.blocked_port, 1);
    TB_EQ_INT(s.blocked_bank, 0);
    cache_core_destroy(c);
    tb_end();
}

/* Triangles of 48 B back to back: the two-bank primitive cache serves one per
 * cycle even when a triangle straddles two 64 B lines; one bank cannot. */
static void test_banked_unaligned(void)
{
    tb_begin("two_bank_unaligned_48B_every_cycle");
    const int ntri = 64;
    cache_core *two = mk(131072, 64, 4, 2, 1, 32, 8), *one = mk(131072, 64, 4, 1, 1, 32, 8);
    cache_core *cs[2] = {two, one};
    for (int k = 0; k < 2; k++) { /* warm up: every line present */
        int64_t t = 0;
        for (int i = 0; i < ntri; i++) {
            while (cache_core_access(cs[k], 0x1000 + (uint64_t)i * 48, 48, t) == CACHE_BLOCKED)
                t++;
            t++;
            while (serve_one(cs[k], t) >= 0) {
            }
        }
    }
    int blocked2 = 0, spans = 0, blocked1 = 0;
    int64_t t = 1000;
    for (int i = 0; i < ntri; i++, t++) {
        uint64_t a = 0x1000 + (uint64_t)i * 48;
        spans += (a >> 6) != ((a + 47) >> 6);
        cache_result r = cache_core_access(two, a, 48, t);
        blocked2 += r == CACHE_BLOCKED;
        TB_CHECK(r == CACHE_HIT || r == CACHE_BLOCKED, "warm cache");
        TB_EQ_INT(cache_core_last_access_cycles(two), 1);
    }
    for (int i = 0; i < ntri;) {
        uint64_t a = 0x1000 + (uint64_t)i * 48;
        cache_result r = cache_core_access(one, a, 48, t++);
        if (r == CACHE_BLOCKED) {
            blocked1++;
            continue;
        }
        TB_EQ_INT(r, CACHE_HIT);
        TB_EQ_INT(cache_core_last_access_cycles(one), ((a >> 6) != ((a + 47) >> 6)) ? 2 : 1);
        i++;
    }
    TB_EQ_INT(blocked2, 0);
    TB_CHECK(spans == ntri / 2, "half the triangles straddle two lines (%d)", spans);
    TB_EQ_INT(blocked1, spans);   /* the one-bank cache loses a cycle per straddling read */
    cache_stats s;
    cache_core_get_stats(one, &s);
    TB_CHECK(s.bank_conflicts >= (uint64_t)spans, "bank conflicts counted");
    cache_core_get_stats(two, &s);
    TB_EQ_INT(s.blocked_bank, 0);
    cache_core_destroy(two);
    cache_core_destroy(one);
    tb_end();
}

static void test_create_errors(void)
{
    tb_begin("create_rejects_impossible_parameters");
    char err[256];
    cache_params p = {16384, 128, 3, 1, 1, 8, 4, 1, 0};
    TB_CHECK(cache_core_create(&p, err, sizeof err) == NULL && strstr(err, "must be a whole power of two"), "3 ways: %s", err);
    p.ways = 0;
    TB_CHECK(cache_core_create(&p, err, sizeof err) == NULL && strstr(err, "ways"), "0 ways: %s", err);
    p.ways = 4;
    p.line_bytes = 96;
    TB_CHECK(cache_core_create(&p, err, sizeof err) == NULL && strstr(err, "powers of two"), "96 B line: %s", err);
    p.line_bytes = 128;
    p.size_bytes = 256;
    TB_CHECK(cache_core_create(&p, err, sizeof err) == NULL, "smaller than one set");
    tb_end();
}

/* Index-addressed, 96 B words (an MBVH3 node): 1024 B, 2-way, one bank hold
 * floor(1024 / (96 * 2)) = 5 sets, 960 B; node k (bytes 96k..96k+95) is
 * word k, in set k mod 5. */
static void test_index_addressed_96(void)
{
    tb_begin("index_addressed_96B_words_hits_misses_sets");
    cache_core *c = mk_addressed(1024, 96, 2, 1, 1, 4, 4, 1);
    TB_CHECK(c != NULL, "created");
    if (!c) {
        tb_end();
        return;
    }
    const cache_params *p = cache_core_get_params(c);
    TB_EQ_INT(cache_core_capacity_bytes(p), 960);
    int64_t t = 0;
    /* node 1 = bytes 96..191: one word, not two 64 B lines or a straddle */
    TB_EQ_INT(cache_core_access(c, 96, 96, t++), CACHE_MISS);
    mem_req r;
    TB_CHECK(cache_core_pop_miss(c, &r), "one request");
    TB_EQ_INT(r.addr, 96);
    TB_EQ_INT(r.bytes, 96);
    TB_CHECK(!cache_core_pop_miss(c, &r), "only one request for one node");
    TB_CHECK(cache_core_line_pending(c, 191) && !cache_core_line_pending(c, 192), "pending word is bytes 96..191");
    mem_resp f = {96, 96, 0, 0, 0};
    TB_EQ_INT(cache_core_fill(c, &f, t), 0);
    TB_CHECK(cache_core_contains(c, 96) && cache_core_contains(c, 191) && !cache_core_contains(c, 95) && !cache_core_contains(c, 192),
             "word 1 present exactly");
    TB_EQ_INT(cache_core_access(c, 96, 96, t++), CACHE_HIT);
    TB_EQ_INT(cache_core_last_access_cycles(c), 1);
    TB_EQ_INT(cache_core_access(c, 100, 8, t++), CACHE_HIT); /* any part of the node */
    /* words 0, 5, 10 share set 0 (2 ways): 0 and 5 fill it, 0 is touched,
     * 10 evicts 5 */
    TB_EQ_INT(cache_core_access(c, 0, 96, t++), CACHE_MISS);
    TB_EQ_INT(serve_one(c, t), 0);
    TB_EQ_INT(cache_core_access(c, 5 * 96, 96, t++), CACHE_MISS);
    TB_EQ_INT(serve_one(c, t), 0);
    TB_EQ_INT(cache_core_access(c, 0, 96, t++), CACHE_HIT);
    TB_EQ_INT(cache_core_access(c, 10 * 96, 96, t++), CACHE_MISS);
    TB_CHECK(cache_core_pop_miss(c, &r) && r.addr == 960 && r.bytes == 96, "word 10 requested at 960: 0x%llx+%u",
             (unsigned long long)r.addr, r.bytes);
    mem_resp f10 = {960, 96, 0, 0, r.tag};
    TB_EQ_INT(cache_core_fill(c, &f10, t), 0);
    TB_CHECK(cache_core_contains(c, 0) && !cache_core_contains(c, 480) && cache_core_contains(c, 960), "LRU word 5 evicted");
    TB_CHECK(cache_core_contains(c, 96), "word 1 (set 1) untouched");
    /* an access across two words (bytes 150..249: words 1 and 2) touches both */
    TB_EQ_INT(cache_core_access(c, 150, 100, t++), CACHE_MISS);
    TB_EQ_INT(cache_core_mshrs_busy(c), 1); /* word 2 only */
    cache_stats s;
    cache_core_get_stats(c, &s);
    TB_EQ_INT(s.accesses, 8);
    TB_EQ_INT(s.hits, 3);
    TB_EQ_INT(s.misses, 5);
    TB_EQ_INT(s.miss_lines, 5);
    TB_EQ_INT(s.fills, 4);
    TB_EQ_INT(s.evictions, 1);
    TB_EQ_INT(s.bytes_filled, 4 * 96);
    cache_core_destroy(c);
    tb_end();
}

static void test_index_create_errors(void)
{
    tb_begin("index_addressed_create_rejects_impossible_parameters");
    char err[256];
    cache_params p = {16384, 100, 4, 1, 1, 8, 4, 1, 1};
    TB_CHECK(cache_core_create(&p, err, sizeof err) == NULL && strstr(err, "multiple of 16"), "100 B word: %s", err);
    p.line_bytes = 96;
    p.size_bytes = 128; /* less than one set of 2 x 96 B */
    p.ways = 2;
    TB_CHECK(cache_core_create(&p, err, sizeof err) == NULL && strstr(err, ">= 1"), "smaller than a set: %s", err);
    p.size_bytes = 16384;
    p.ways = 4;
    cache_core *c = cache_core_create(&p, err, sizeof err);
    TB_CHECK(c != NULL, "16 KB of 96 B words: %s", c ? "" : err);
    TB_EQ_INT(cache_core_capacity_bytes(&p), 42 * 4 * 96); /* floor(16384 / 384) = 42 sets */
    cache_core_destroy(c);
    tb_end();
}

/* ------------------------------------------------------------ reference */

#define REF_MAX_SETS 64
#define REF_MAX_WAYS 8
#define REF_MAX_PEND 16
typedef struct ref {
    uint32_t line, ways, banks, ports, mshrs, sets;
    uint64_t set_lines[REF_MAX_SETS][REF_MAX_WAYS]; /* [0] = MRU */
    int set_n[REF_MAX_SETS];
    uint64_t pend[REF_MAX_PEND];                    /* pending lines, allocation order */
    int npend;
    uint64_t sent[REF_MAX_PEND];                    /* popped but not filled */
    int nsent;
    int64_t cycle;
    uint32_t used_ports;
    int64_t bank_busy[16];
    int64_t bank_cycle;
    int bank_used[16];
    int last_cycles;
    uint32_t merge;
    struct { uint64_t tag; uint64_t lines[8]; int n; } w[256];  /* request-mode waiters, arrival order */
    int nw;
    cache_stats st;
} ref;

static int ref_waiters_on(const ref *r, uint64_t line)
{
    int n = 0;
    for (int i = 0; i < r->nw; i++)
        for (int k = 0; k < r->w[i].n; k++)
            n += r->w[i].lines[k] == line;
    return n;
}

static int ref_set(const ref *r, uint64_t line)
{
    uint64_t bank = line % r->banks, per_bank = r->sets / r->banks;
    return (int)(bank * per_bank + (line / r->banks) % per_bank);
}
static int ref_find(const ref *r, uint64_t line)
{
    int s = ref_set(r, line);
    for (int i = 0; i < r->set_n[s]; i++)
        if (r->set_lines[s][i] == line)
            return i;
    return -1;
}
static bool ref_pending(const ref *r, uint64_t line)
{
    for (int i = 0; i < r->npend; i++)
        if (r->pend[i] == line)
            return true;
    for (int i = 0; i < r->nsent; i++)
        if (r->sent[i] == line)
            return true;
    return false;
}
static void ref_touch(ref *r, uint64_t line)
{
    int s = ref_set(r, line), i = ref_find(r, line);
    memmove(&r->set_lines[s][1], &r->set_lines[s][0], (size_t)i * sizeof(uint64_t));
    r->set_lines[s][0] = line;
}
static cache_result ref_access(ref *r, uint64_t addr, uint32_t bytes, int64_t now, const uint64_t *tag)
{
    if (now != r->cycle) {
        r->cycle = now;
        r->used_ports = 0;
    }
    if (r->used_ports == r->ports) {
        r->st.blocked_port++;
        return CACHE_BLOCKED;
    }
    uint64_t a = addr / r->line, b = (addr + bytes - 1) / r->line;
    int uses[16] = {0};
    for (uint64_t l = a; l <= b; l++)
        uses[l % r->banks]++;
    if (now != r->bank_cycle) {
        r->bank_cycle = now;
        memset(r->bank_used, 0, sizeof r->bank_used);
    }
    for (uint32_t k = 0; k < r->banks; k++) {
        if (!uses[k])
            continue;
        bool fits = r->bank_used[k] + uses[k] <= (int)r->ports || r->bank_used[k] == 0;
        if (r->bank_busy[k] >= now || !fits) {
            r->st.blocked_bank++;
            return CACHE_BLOCKED;
        }
    }
    int missing = 0, fresh = 0;
    for (uint64_t l = a; l <= b; l++)
        if (ref_find(r, l) < 0) {
            missing++;
            fresh += !ref_pending(r, l);
            if (tag && ref_pending(r, l) && ref_waiters_on(r, l) >= (int)r->merge) {
                r->st.blocked_merge++;
                return CACHE_BLOCKED;
            }
        }
    int free_mshrs = (int)r->mshrs - r->npend - r->nsent, alloc = fresh;
    if (fresh > free_mshrs) {
        /* a probe that needs more new lines than there are MSHRs at all
         * takes the free ones for its first lines (cache.h) */
        if (tag || fresh <= (int)r->mshrs || free_mshrs == 0) {
            r->st.blocked_mshr++;
            return CACHE_BLOCKED;
        }
        alloc = free_mshrs;
    }
    r->used_ports++;
    int maxcyc = 1;
    for (uint32_t k = 0; k < r->banks; k++)
        if (uses[k]) {
            int cyc = (uses[k] + (int)r->ports - 1) / (int)r->ports;
            r->bank_used[k] = cyc > 1 ? (int)r->ports : r->bank_used[k] + uses[k];
            if (cyc > 1)
                r->bank_busy[k] = now + cyc - 1;
            if (cyc > maxcyc)
                maxcyc = cyc;
        }
    r->st.bank_conflicts += maxcyc > 1;
    r->last_cycles = maxcyc;
    r->st.accesses++;
    for (uint64_t l = a; l <= b; l++)
        if (ref_find(r, l) >= 0)
            ref_touch(r, l);
    if (!missing) {
        r->st.hits++;
        return CACHE_HIT;
    }
    r->st.misses++;
    if (tag) {
        r->w[r->nw].tag = *tag;
        r->w[r->nw].n = 0;
        for (uint64_t l = a; l <= b; l++)
            if (ref_find(r, l) < 0)
                r->w[r->nw].lines[r->w[r->nw].n++] = l;
        r->nw++;
    }
    for (uint64_t l = a; l <= b; l++)
        if (ref_find(r, l) < 0) {
            if (ref_pending(r, l)) {
                r->st.merged++;
            } else if (alloc > 0) {
                alloc--;
                r->pend[r->npend++] = l;
                r->st.miss_lines++;
            }
        }
    return CACHE_MISS;
}
/* Installs line; appends the tags of released waiters to out. */
static void ref_fill(ref *r, uint64_t line, uint64_t *out, int *nout)
{
    for (int i = 0; i < r->nw; i++) {
        for (int k = 0; k < r->w[i].n; k++)
            if (r->w[i].lines[k] == line) {
                r->w[i].lines[k] = r->w[i].lines[--r->w[i].n];
                break;
            }
        if (r->w[i].n == 0) {
            out[(*nout)++] = r->w[i].tag;
            memmove(&r->w[i], &r->w[i + 1], (size_t)(r->nw - i - 1) * sizeof r->w[0]);
            r->nw--;
            i--;
        }
    }
    int s = ref_set(r, line);
    if (r->set_n[s] == (int)r->ways) {
        r->set_n[s]--; /* drop the LRU line */
        r->st.evictions++;
    }
    memmove(&r->set_lines[s][1], &r->set_lines[s][0], (size_t)r->set_n[s] * sizeof(uint64_t));
    r->set_lines[s][0] = line;
    r->set_n[s]++;
    r->st.fills++;
    for (int i = 0; i < r->nsent; i++)
        if (r->sent[i] == line) {
            r->sent[i] = r->sent[--r->nsent];
            break;
        }
}

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static uint32_t rnd(uint32_t n)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (uint32_t)(rng_state % n);
}

static void run_random_addressed(uint32_t size, uint32_t line, uint32_t ways, uint32_t banks, uint32_t ports,
                                 uint32_t mshrs, uint32_t merge, bool requests, int ops, uint32_t index_addressed)
{
    char name[160];
    snprintf(name, sizeof name, "random_vs_reference_%s%s_%uB_%uB_%uway_%ubank_%uport_%umshr_%umerge",
             index_addressed ? "index_" : "", requests ? "requests" : "probes", size, line, ways, banks, ports, mshrs,
             merge);
    tb_begin(name);
    cache_core *c = mk_addressed(size, line, ways, banks, ports, mshrs, merge, index_addressed);
    static ref r;
    memset(&r, 0, sizeof r);
    r.merge = merge;
    uint64_t next_tag = 1;
    r.line = line, r.ways = ways, r.banks = banks, r.ports = ports, r.mshrs = mshrs;
    r.sets = size / (line * ways); /* index-addressed: floor, any whole number (the reference divides) */
    r.cycle = INT64_MIN;
    r.bank_cycle = INT64_MIN;
    for (int k = 0; k < 16; k++)
        r.bank_busy[k] = -1;
    /* the address pool covers 3x the capacity so that sets overflow */
    uint32_t pool_lines = 3 * size / line;
    mem_req sent[REF_MAX_PEND];
    int nsent = 0;
    int64_t now = 0;
    for (int op = 0; op < ops && !tb_case_failed; op++) {
        now += rnd(3) == 0;
        uint32_t kind = rnd(10);
        if (kind < 6) {
            uint64_t addr = (uint64_t)rnd(pool_lines) * line + rnd(line);
            uint32_t bytes = 1 + rnd(line + line / 2);
            cache_result got, want;
            if (requests) {
                mem_req q = {addr, bytes, (uint16_t)(next_tag & 7), 0, 0, next_tag};
                got = cache_core_request(c, &q, now);
                want = ref_access(&r, addr, bytes, now, &next_tag);
                next_tag++;
            } else {
                got = cache_core_access(c, addr, bytes, now);
                want = ref_access(&r, addr, bytes, now, NULL);
            }
            TB_CHECK(got == want, "op %d access 0x%llx+%u at %lld: %d vs reference %d", op, (unsigned long long)addr,
                     bytes, (long long)now, got, want);
            if (got == CACHE_HIT || got == CACHE_MISS)
                TB_EQ_INT(cache_core_last_access_cycles(c), r.last_cycles);
        } else if (kind < 8) {
            mem_req q;
            bool have = cache_core_pop_miss(c, &q);
            TB_CHECK(have == (r.npend > 0), "op %d pop_miss %d vs %d pending", op, have, r.npend);
            if (have && r.npend) {
                TB_CHECK(q.addr == r.pend[0] * line && q.bytes == line, "op %d miss order: 0x%llx vs 0x%llx", op,
                         (unsigned long long)q.addr, (unsigned long long)(r.pend[0] * line));
                r.sent[r.nsent++] = r.pend[0];
                memmove(&r.pend[0], &r.pend[1], (size_t)--r.npend * sizeof r.pend[0]);
                sent[nsent++] = q;
            }
        } else if (nsent) {
            int k = (int)rnd((uint32_t)nsent); /* memory answers out of order */
            mem_resp resp = {sent[k].addr, sent[k].bytes, 0, 0, sent[k].tag};
            uint64_t rel[256];
            int nrel = 0;
            ref_fill(&r, sent[k].addr / line, rel, &nrel);
            TB_EQ_INT(cache_core_fill(c, &resp, now), nrel);
            mem_req q;
            for (int i = 0; i < nrel && cache_core_pop_ready(c, &q); i++)
                TB_CHECK(q.tag == rel[i] && q.src == (rel[i] & 7), "op %d released tag %llu, reference %llu", op,
                         (unsigned long long)q.tag, (unsigned long long)rel[i]);
            TB_CHECK(!cache_core_pop_ready(c, &q), "op %d: extra ready request", op);
            sent[k] = sent[--nsent];
        }
        if (op % 64 == 0)
            for (uint32_t l = 0; l < pool_lines; l++)
                if (cache_core_contains(c, (uint64_t)l * line) != (ref_find(&r, l) >= 0)) {
                    TB_CHECK(false, "op %d: line %u presence differs", op, l);
                    break;
                }
    }
    cache_stats s;
    cache_core_get_stats(c, &s);
    TB_EQ_INT(s.accesses, r.st.accesses);
    TB_EQ_INT(s.hits, r.st.hits);
    TB_EQ_INT(s.misses, r.st.misses);
    TB_EQ_INT(s.miss_lines, r.st.miss_lines);
    TB_EQ_INT(s.merged, r.st.merged);
    TB_EQ_INT(s.blocked_mshr, r.st.blocked_mshr);
    TB_EQ_INT(s.blocked_merge, r.st.blocked_merge);
    TB_CHECK(!requests || s.blocked_merge > 0, "merge limit exercised");
    TB_EQ_INT(s.blocked_port, r.st.blocked_port);
    TB_EQ_INT(s.blocked_bank, r.st.blocked_bank);
    TB_EQ_INT(s.bank_conflicts, r.st.bank_conflicts);
    TB_EQ_INT(s.fills, r.st.fills);
    TB_EQ_INT(s.evictions, r.st.evictions);
    TB_CHECK(s.hits > 0 && s.evictions > 0 && (s.merged > 0 || merge == 1) && s.blocked_mshr + s.blocked_bank > 0,
             "sequence exercised hits %llu evictions %llu merges %llu blocks %llu", (unsigned long long)s.hits,
             (unsigned long long)s.evictions, (unsigned long long)s.merged,
             (unsigned long long)(s.blocked_mshr + s.blocked_bank));
    cache_core_destroy(c);
    tb_end();
}

static void run_random(uint32_t size, uint32_t line, uint32_t ways, uint32_t banks, uint32_t ports, uint32_t mshrs,
                       uint32_t merge, bool requests, int ops)
{
    run_random_addressed(size, line, ways, banks, ports, mshrs, merge, requests, ops, 0);
}

/* cache_core_touch (the functional levels' access) against what it stands
 * for: cache_core_access, retried a cycle later while BLOCKED, then every
 * queued miss popped and filled at once. On random accesses of one to three
 * lines both cores must give the same missed lines in the same order, the
 * same counts and, line by line, the same contents (so the same LRU order
 * behind them). */
static void run_touch_vs_access(uint32_t size, uint32_t line, uint32_t ways, uint32_t banks, uint32_t ports,
                                uint32_t mshrs, int ops, uint32_t index_addressed)
{
    char name[160];
    snprintf(name, sizeof name, "touch_as_access_then_fill_%s%uB_%uB_%uway_%ubank_%umshr", index_addressed ? "index_" : "",
             size, line, ways, banks, mshrs);
    tb_begin(name);
    cache_core *a = mk_addressed(size, line, ways, banks, ports, mshrs, 4, index_addressed);
    cache_core *b = mk_addressed(size, line, ways, banks, ports, mshrs, 4, index_addressed);
    const uint32_t pool = 3 * size / line;
    int64_t now = 0;
    for (int op = 0; op < ops && !tb_case_failed; op++) {
        uint64_t addr = (uint64_t)rnd(pool) * line + rnd(line);
        uint32_t bytes = 1 + rnd(2 * line);
        cache_result r;
        while ((r = cache_core_access(a, addr, bytes, now)) == CACHE_BLOCKED)
            now++;
        now++;
        uint64_t want[CACHE_MAX_LINES_PER_ACCESS], got[CACHE_MAX_LINES_PER_ACCESS];
        int nwant = 0;
        mem_req q;
        while (cache_core_pop_miss(a, &q)) {
            want[nwant++] = q.addr;
            mem_resp resp = {q.addr, q.bytes, q.src, 0, q.tag};
            cache_core_fill(a, &resp, now);
        }
        const int ngot = cache_core_touch(b, addr, bytes, got);
        TB_CHECK(ngot == nwant && (r == CACHE_HIT) == (ngot == 0), "op %d (0x%llx, %u B): %d lines missed, want %d",
                 op, (unsigned long long)addr, bytes, ngot, nwant);
        for (int i = 0; i < ngot && i < nwant; i++)
            TB_CHECK(got[i] == want[i], "op %d: missed line %d at 0x%llx, want 0x%llx", op, i,
                     (unsigned long long)got[i], (unsigned long long)want[i]);
    }
    cache_stats sa, sb;
    cache_core_get_stats(a, &sa);
    cache_core_get_stats(b, &sb);
    TB_CHECK(sa.accesses == sb.accesses && sa.hits == sb.hits && sa.misses == sb.misses &&
                 sa.miss_lines == sb.miss_lines && sa.fills == sb.fills && sa.evictions == sb.evictions &&
                 sa.bytes_filled == sb.bytes_filled,
             "counts differ: accesses %llu/%llu hits %llu/%llu miss lines %llu/%llu evictions %llu/%llu",
             (unsigned long long)sa.accesses, (unsigned long long)sb.accesses, (unsigned long long)sa.hits,
             (unsigned long long)sb.hits, (unsigned long long)sa.miss_lines, (unsigned long long)sb.miss_lines,
             (unsigned long long)sa.evictions, (unsigned long long)sb.evictions);
    TB_CHECK(sb.misses > 0 && sb.evictions > 0 && sb.hits > 0, "the sequence exercised hits, misses and evictions");
    for (uint32_t l = 0; l < pool; l++)
        TB_CHECK(cache_core_contains(a, (uint64_t)l * line) == cache_core_contains(b, (uint64_t)l * line),
                 "line %u present in one core only", l);
    cache_core_destroy(a);
    cache_core_destroy(b);
    tb_end();
}

/* cache_core_bytes: what a copy of a core costs (the windowed level's
 * snapshots are refused beyond a budget): at least a tag and a stamp per
 * way, growing with the ways and the MSHRs as their arrays do. */
static void test_bytes(void)
{
    tb_begin("cache_core_bytes");
    cache_params small = {32768, 64, 4, 1, 1, 8, 4, 1, 0}, big = small, more = small;
    big.size_bytes = 65536;
    more.mshrs = 16;
    size_t bs = cache_core_bytes(&small), bb = cache_core_bytes(&big), bm = cache_core_bytes(&more);
    TB_CHECK(bs >= 512 * 16, "%zu bytes for 512 ways", bs);
    TB_CHECK(bb - bs >= 512 * 16 && bb - bs <= 512 * 16 + 256 * sizeof(int) * 2, "%zu more for 512 more ways", bb - bs);
    TB_CHECK(bm > bs && bm - bs < 8 * 256, "%zu more for 8 more MSHRs", bm - bs);
    tb_end();
}

int main(void)
{
    test_bytes();
    test_hit_miss_merge();
    test_lru_eviction();
    test_mshr_exhaustion();
    test_partial_probe_one_mshr();
    test_request_waiters();
    test_ports();
    test_banked_unaligned();
    test_create_errors();
    test_index_addressed_96();
    test_index_create_errors();
    int ops = tb_is_sanitized() ? 20000 : 100000;
    run_random(1024, 64, 4, 1, 1, 4, 64, false, ops);
    run_random(2048, 64, 4, 2, 1, 8, 64, false, ops);
    run_random(1024, 32, 1, 1, 2, 2, 64, false, ops);
    run_random(1024, 32, 2, 1, 2, 1, 64, false, ops); /* one MSHR: partial probes */
    run_random(2048, 128, 2, 2, 2, 3, 64, false, ops);
    run_random(4096, 64, 8, 4, 3, 16, 64, false, ops);
    run_random(1024, 64, 4, 1, 1, 4, 2, true, ops);
    run_random(2048, 64, 4, 2, 2, 8, 3, true, ops);
    run_random(4096, 128, 4, 2, 1, 16, 1, true, ops);
    /* index-addressed node words: 5, 2 per bank and 6 sets */
    run_random_addressed(1024, 96, 2, 1, 1, 4, 64, false, ops, 1);
    run_random_addressed(2048, 96, 2, 2, 2, 8, 3, true, ops, 1);
    run_random_addressed(4096, 160, 4, 1, 1, 16, 2, true, ops, 1);
    run_touch_vs_access(1024, 64, 4, 2, 1, 8, ops, 0);
    run_touch_vs_access(2048, 32, 2, 1, 2, 1, ops, 0); /* one MSHR: only a two-line access's first line */
    run_touch_vs_access(4096, 128, 8, 4, 1, 16, ops, 0);
    run_touch_vs_access(2048, 96, 2, 2, 1, 8, ops, 1);
    return tb_finish();
}
