// kernel_systemc — the kernel benchmark workloads on SystemC 2.3.4, the
// reference for bench/kernel.sh (twin of kernel_ours.c; docs/kernel.md).
//   kernel_systemc a|a_thread|b|c|d N [VCD_BASE]
// a: ping-pong of N tokens through sc_fifo<uint64_t>(2), SC_METHODs on
//    data_read/data_written events; a_thread: the same with SC_THREADs and
//    blocking read/write;
// b: ring of 8 SC_METHOD stages on the rising edge of a 500 MHz sc_clock,
//    each moving a 32-byte item between sc_fifo<item>(4) every cycle, N cycles;
// c: 1000 SC_METHODs re-triggering themselves with next_trigger after
//    pseudo-random delays of 1..1000 ns, N activations in all;
// d: b with sc_trace of every stage's item id and FIFO occupancy to a VCD.
// Prints "<seconds> <checksum>" (simulation wall time only).
#include <systemc.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>

static double now_s()
{
    timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

// ---- a ----
SC_MODULE(PingPong)
{
    sc_fifo<uint64_t> f;
    uint64_t n, sent = 0, received = 0, sum = 0;
    SC_HAS_PROCESS(PingPong);
    PingPong(sc_module_name nm, uint64_t n_, bool threads) : sc_module(nm), f("fifo", 2), n(n_)
    {
        if (threads) {
            SC_THREAD(producer_thread);
            SC_THREAD(consumer_thread);
        } else {
            SC_METHOD(producer);
            sensitive << f.data_read_event();
            SC_METHOD(consumer);
            sensitive << f.data_written_event();
        }
    }
    void producer()
    {
        while (sent < n && f.num_free() > 0)
            f.nb_write(sent++);
    }
    void consumer()
    {
        uint64_t v;
        while (f.nb_read(v)) {
            sum += v;
            received++;
        }
    }
    void producer_thread()
    {
        for (uint64_t i = 0; i < n; i++)
            f.write(i);
    }
    void consumer_thread()
    {
        for (;;) {
            sum += f.read();
            received++;
        }
    }
};

// ---- b/d ----
struct Item {
    uint32_t id = 0, hops = 0;
    uint64_t payload[3] = {0, 0, 0};
    bool operator==(const Item &o) const { return id == o.id && hops == o.hops; }
};
inline std::ostream &operator<<(std::ostream &os, const Item &it) { return os << it.id; }

SC_MODULE(Stage)
{
    sc_in<bool> clk;
    sc_fifo<Item> *in = nullptr, *out = nullptr;
    uint32_t last_id = 0, occupancy = 0;
    uint64_t moved = 0;
    int index = 0;
    bool primed = false;
    SC_HAS_PROCESS(Stage);
    Stage(sc_module_name nm) : sc_module(nm)
    {
        SC_METHOD(step);
        sensitive << clk.pos();
        dont_initialize();
    }
    void step()
    {
        if (!primed) { // two items per FIFO, as the C version preloads
            primed = true;
            for (int k = 0; k < 2; k++) {
                Item it;
                it.id = (uint32_t)(((index + 1) % 8) * 2 + k);
                out->nb_write(it);
            }
            return;
        }
        if (in->num_available() > 0 && out->num_free() > 0) {
            Item it;
            in->nb_read(it);
            it.hops++;
            it.payload[0] += it.hops;
            out->nb_write(it);
            last_id = it.id;
            moved++;
        }
        occupancy = (uint32_t)in->num_available();
    }
};

static uint64_t run_ring(uint64_t cycles, const char *vcd_base)
{
    const int S = 8;
    sc_clock clk("clk", 2, SC_NS);
    sc_fifo<Item> *f[S];
    Stage *st[S];
    char name[64];
    for (int i = 0; i < S; i++) {
        snprintf(name, sizeof name, "fifo%d", i);
        f[i] = new sc_fifo<Item>(name, 4);
    }
    for (int i = 0; i < S; i++) {
        snprintf(name, sizeof name, "stage%d", i);
        st[i] = new Stage(name);
        st[i]->clk(clk);
        st[i]->in = f[i];
        st[i]->out = f[(i + 1) % S];
        st[i]->index = i;
    }
    sc_trace_file *tf = nullptr;
    if (vcd_base) {
        tf = sc_create_vcd_trace_file(vcd_base);
        tf->set_time_unit(1, SC_PS);
        for (int i = 0; i < S; i++) {
            snprintf(name, sizeof name, "ring.stage%d.id", i);
            sc_trace(tf, st[i]->last_id, name);
            snprintf(name, sizeof name, "ring.stage%d.in.occupancy", i);
            sc_trace(tf, st[i]->occupancy, name);
        }
    }
    sc_start(sc_time(2.0 * (double)(cycles + 1) - 1, SC_NS));
    uint64_t sum = 0;
    for (int i = 0; i < S; i++)
        sum += st[i]->moved;
    if (tf)
        sc_close_vcd_trace_file(tf);
    return sum;
}

// ---- c ----
SC_MODULE(Timed)
{
    uint64_t rng = 0;
    uint64_t *count = nullptr, limit = 0;
    SC_HAS_PROCESS(Timed);
    Timed(sc_module_name nm) : sc_module(nm) { SC_METHOD(fire); }
    void fire()
    {
        if (++*count >= limit)
            return;
        rng = rng * 6364136223846793005ull + 1442695040888963407ull;
        next_trigger(sc_time((double)(1 + (rng >> 33) % 1000), SC_NS));
    }
};

static uint64_t run_c(uint64_t n)
{
    const int P = 1000;
    static uint64_t count = 0;
    char name[32];
    for (int i = 0; i < P; i++) {
        snprintf(name, sizeof name, "p%d", i);
        Timed *t = new Timed(name);
        t->rng = (uint64_t)i * 0x9E3779B97F4A7C15ull + 1;
        t->count = &count;
        t->limit = n;
    }
    sc_start();
    return count ^ (uint64_t)(sc_time_stamp().value());
}

int sc_main(int argc, char **argv)
{
    sc_report_handler::set_actions(SC_INFO, SC_DO_NOTHING);
    sc_report_handler::set_actions(SC_WARNING, SC_DO_NOTHING);
    if (argc < 3) {
        fprintf(stderr, "usage: kernel_systemc a|a_thread|b|c|d N [VCD_BASE]\n");
        return 2;
    }
    uint64_t n = strtoull(argv[2], nullptr, 10);
    std::string w = argv[1];
    double t0 = now_s();
    uint64_t check = 0;
    if (w == "a" || w == "a_thread") {
        PingPong pp("pp", n, w == "a_thread");
        sc_start();
        check = pp.sum;
    } else if (w == "b") {
        check = run_ring(n, nullptr);
    } else if (w == "c") {
        check = run_c(n);
    } else if (w == "d") {
        check = run_ring(n, argc > 3 ? argv[3] : "kernel_systemc_trace");
    } else {
        fprintf(stderr, "kernel_systemc: unknown workload %s\n", argv[1]);
        return 2;
    }
    printf("%.6f %llu\n", now_s() - t0, (unsigned long long)check);
    return 0;
}
