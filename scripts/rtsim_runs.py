"""rtsim_runs — the one runner of rtsim points for the experiment scripts
(scripts/paper-tables, sensitivity, branching, speed-accuracy, sweep), and
their one definition of the figures of merit and of a change in percent.

A point is one rtsim run: scene, ray type, machine, resolution, --set
overrides and further rtsim arguments. rtsim_argv() spells its command line
(the one place that does). The Python scripts run points with run_all(): one
JSON per point in a runs folder, reused when present (an interrupted script
resumes), points run in parallel, every failure reported with its command and
rtsim's message. scripts/sweep plans its grid and runs each point through
this module too (sweep_plan, sweep_point: `python3 scripts/rtsim_runs.py
sweep-plan ...` and `sweep-point DIR INDEX`), so that GNU parallel and a
Slurm array can run one point a process.

Standard library only."""
import argparse
import concurrent.futures as cf
import hashlib
import json
import os
import signal
import socket
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_BIN = os.path.join(ROOT, "build", "bin", "rtsim")

# The figures of merit of a run, in the order of the paper's Table 2, then
# area and power: (key, short name, JSON statistic, divisor, chart label).
FIGURES = [
    ("mrps", "MRPS", "mrps", 1, "MRPS (million rays per second)"),
    ("energy_mj", "mJ/frame", "energy_mj", 1, "energy per frame (mJ)"),
    ("mrps_per_mm2", "MRPS/mm2", "mrps_per_mm2", 1, "MRPS/mm²"),
    ("dram_mb", "DRAM MB", "dram_bytes", 1e6, "DRAM traffic (MB)"),
    ("area_mm2", "area mm2", "area_mm2", 1, "area (mm²)"),
    ("power_mw", "power mW", "power_mw", 1, "average power (mW)"),
]
# The four of the paper's Table 2 as (key, short name).
TABLE2_FIGURES = [(f[0], f[1]) for f in FIGURES[:4]]


def die(tool, msg):
    print("%s: %s" % (tool, msg), file=sys.stderr)
    sys.exit(2)


def figure(stats, key):
    """Figure of merit `key` (FIGURES) of a run's JSON, in its unit; None when
    the run does not report it (a cheaper fidelity level, an older build)."""
    f = next(f for f in FIGURES if f[0] == key)
    v = stats.get(f[2])
    return None if v is None else (v / f[3] if f[3] != 1 else v)


def fom(stats, area_mm2=None):
    """Every figure of merit a run reports, {key: value}. area_mm2: the
    machine's area, for a run of a cheaper fidelity level that reports no
    MRPS/mm2 (then MRPS / area)."""
    out = {}
    for f in FIGURES:
        v = figure(stats, f[0])
        if v is not None:
            out[f[0]] = v
    if "mrps_per_mm2" not in out and area_mm2:
        out["mrps_per_mm2"] = stats["mrps"] / area_mm2
    return out


def change_pct(new, old):
    """The change from old to new in percent; None when old is 0 (a change
    from nothing has no percentage: reported as undefined, not as 0)."""
    return 100.0 * (new - old) / old if old else None


def fmt_change(change, form, undefined="n/a"):
    """A change_pct() value in printf form, or `undefined` for None."""
    return undefined if change is None else form % change


def scene_key(scene):
    """Short name of a scene argument: a built-in name or a file's base name."""
    b = os.path.basename(scene)
    for ext in (".scene", ".gz", ".obj", ".ply"):
        if b.endswith(ext):
            b = b[: -len(ext)]
    return b


def point_name(scene, rays, machine, res, sets=(), extra=()):
    """File name of a point: readable, plus a hash of the overrides and of
    any further rtsim arguments."""
    name = "%s_%s_%s_%s" % (scene_key(scene), rays, machine, res)
    for args in (sets, extra):
        if args:
            name += "_" + hashlib.sha1("\n".join(args).encode()).hexdigest()[:12]
    return name + ".json"


def rtsim_argv(rtsim, scene, rays, machine, res, sets=(), extra=(), json_path=None, quiet=True):
    """rtsim's command line for a point: its definition (scene, rays, machine,
    resolution, overrides, further arguments), then how it reports."""
    argv = [rtsim, scene, "--rays", rays, "--machine", machine, "--res", res]
    for s in sets:
        argv += ["--set", s]
    argv += list(extra)
    if quiet:
        argv.append("--quiet")
    if json_path:
        argv += ["--json", json_path]
    return argv


class Refused(Exception):
    """rtsim refused the machine at start-up (exit 2): not a valid point."""


def run_point(rtsim, runs_dir, scene, rays, machine, res, sets=(), extra=(), name=None, summary=False):
    """Statistics of one point, running rtsim unless its JSON exists (rtsim
    writes it under a temporary name and renames it when complete). extra:
    further rtsim arguments (e.g. --accuracy 2%). name: the files' stem
    (default point_name's). summary: keep rtsim's printed summary too, in
    NAME.txt, and return (statistics, summary). A machine rtsim refuses
    (exit 2) raises Refused with rtsim's message."""
    stem = name or point_name(scene, rays, machine, res, sets, extra)[: -len(".json")]
    path = os.path.join(runs_dir, stem + ".json")
    txt = os.path.join(runs_dir, stem + ".txt")
    if not (os.path.exists(path) and (not summary or os.path.exists(txt))):
        cmd = rtsim_argv(rtsim, scene, rays, machine, res, sets, extra, path, quiet=not summary)
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if p.returncode == 2:
            # rtsim's message, without the "(see rtsim --help)" hint after it
            lines = [l for l in p.stderr.strip().splitlines() if l and not l.startswith("(see ")]
            raise Refused("; ".join(lines) if lines else "exit 2")
        if p.returncode != 0:
            raise RuntimeError("%s: exit %d: %s" % (" ".join(cmd), p.returncode, p.stderr.strip()[-400:]))
        if summary:
            write_atomic(txt, p.stdout)
    with open(path) as f:
        stats = json.load(f)
    if not summary:
        return stats
    with open(txt) as f:
        return stats, f.read()


def run_all(tool, rtsim, runs_dir, points, jobs, refused=None, summary=False):
    """points: tuples of run_point's arguments after runs_dir (scene, rays,
    machine, res[, sets[, extra[, name]]]); returns {point: run_point's
    result}. With a dict `refused`, a point rtsim refuses goes there (point:
    message) instead of stopping the script."""
    os.makedirs(runs_dir, exist_ok=True)
    out = {}
    with cf.ThreadPoolExecutor(max_workers=jobs) as ex:
        fut = {ex.submit(run_point, rtsim, runs_dir, *p, summary=summary): p for p in points}
        for f in cf.as_completed(fut):
            try:
                out[fut[f]] = f.result()
            except Refused as e:
                if refused is None:
                    die(tool, str(e))
                refused[fut[f]] = str(e)
            except Exception as e:
                die(tool, str(e))
    return out


def arg_parser(prog, doc):
    """The argument parser of a script whose docstring is its manual: --help
    shows the docstring's first paragraph (what the script does), the usage
    of every option from their help texts, then the paragraphs after the
    synopsis (which the usage line replaces)."""
    paras = doc.strip("\n").split("\n\n")
    rest = [p for p in paras[1:] if not p.lstrip().startswith("scripts/")]
    return argparse.ArgumentParser(prog=prog, description=paras[0], epilog="\n\n".join(rest) or None,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)


def write_atomic(path, text):
    """Writes text to path through a temporary name of this process, renamed
    when complete: a reader never sees half a file, two writers never share
    a temporary."""
    tmp = "%s.tmp.%d" % (path, os.getpid())
    with open(tmp, "w", newline="") as f:
        f.write(text)
    os.replace(tmp, path)


def write_jobs(dir, text):
    """DIR/jobs.tsv with text, rewritten only on a change (atomically), so a
    running Slurm array never sees its indices move."""
    jobs = os.path.join(dir, "jobs.tsv")
    try:
        with open(jobs) as f:
            if f.read() == text:
                return
    except OSError:
        pass
    write_atomic(jobs, text)


def gnuplot(tool, script, outputs):
    """Runs a gnuplot script that writes OUT.tmp for each OUT, then renames."""
    p = subprocess.run(["gnuplot"], input=script, text=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    if p.returncode != 0:
        die(tool, "gnuplot failed: %s" % p.stderr.strip())
    for o in outputs:
        os.replace(o + ".tmp", o)


# ---------------------------------------------------------------- sweep
# scripts/sweep's points (docs/sweep.md): DIR/jobs.tsv holds a header (name
# scene rays machine res set KEY... args), then one point a line; job i is
# line i + 1. DIR/sweep.conf names the rtsim binary, the folder the sweep was
# started in, the --stat keys and the paired changes' --baseline.


def _basename(path):
    """basename(1): the last component, trailing slashes ignored."""
    stripped = path.rstrip("/")
    return os.path.basename(stripped) if stripped else ("/" if path else "")


def sweep_point_name(scene, rays, machine, res, extra, sets):
    """A point's name: scene-rays-machine-HASH, HASH the first 12 hex digits
    of the SHA-1 of everything that defines the point (the overrides in byte
    order), so the same point always maps to the same result file, whatever
    the order of the options. Bytes outside [A-Za-z0-9._-] become '_'."""
    canon = "\n".join([scene, rays, machine, res, extra] + sorted(sets, key=lambda s: s.encode()))
    digest = hashlib.sha1(canon.encode()).hexdigest()[:12]
    m = machine[: -len(".ini")] if machine.endswith(".ini") else machine
    readable = "%s-%s-%s" % (_basename(scene).split(".", 1)[0], rays, _basename(m))
    keep = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789._-"
    safe = bytes(c if c in keep else ord("_") for c in readable.encode()).decode()
    return "%s-%s" % (safe, digest)


def sweep_plan(dir, rtsim, cwd, scenes, rays, machines, res, grid, fixed_sets, rtsim_args, stats, baseline=""):
    """Writes DIR/jobs.tsv (rewritten only on a change, so a running Slurm
    array never sees its indices move) and DIR/sweep.conf. Points in a fixed
    order: scenes, rays, machines, then the grid keys, the last one varying
    fastest; a point given twice is planned once. grid: [(key, [values])]."""
    fixed = ";".join(fixed_sets) if fixed_sets else "-"
    extra = " ".join(rtsim_args) if rtsim_args else "-"
    combos = [[]]
    for _, values in grid:
        combos = [c + [v] for c in combos for v in values]
    lines = ["\t".join(["name", "scene", "rays", "machine", "res", "set"] + [k for k, _ in grid] + ["args"])]
    seen = set()
    for s in scenes:
        for r in rays:
            for m in machines:
                for vals in combos:
                    sets = ["%s=%s" % (k, v) for (k, _), v in zip(grid, vals)] + list(fixed_sets)
                    name = sweep_point_name(s, r, m, res, extra, sets)
                    if name not in seen:
                        seen.add(name)
                        lines.append("\t".join([name, s, r, m, res, fixed] + vals + [extra]))
    write_jobs(dir, "\n".join(lines) + "\n")
    write_atomic(os.path.join(dir, "sweep.conf"),
                 "rtsim %s\ncwd %s\n" % (rtsim, cwd) + "".join("stat %s\n" % st for st in stats) +
                 ("baseline %s\n" % baseline if baseline else ""))


def _sweep_die(msg):
    print("sweep: " + msg, file=sys.stderr)
    sys.exit(2)


def sweep_conf(dir, key):
    """The rest of the first line of DIR/sweep.conf that starts with KEY ("" if none)."""
    try:
        with open(os.path.join(dir, "sweep.conf")) as f:
            for line in f:
                line = line.rstrip("\n")
                if line.split(" ", 1)[0] == key:
                    return line[len(key) + 1:]
    except OSError:
        pass
    return ""


def sweep_point(dir, index):
    """Runs point INDEX (1-based) of DIR/jobs.tsv: rtsim writes its JSON to a
    temporary name in DIR/results/, renamed to the point's file only when
    rtsim succeeded, so a result file is always complete and its existence
    means "done" (a resumed sweep skips it). Returns the exit status: 0 done
    (or done already), 1 rtsim failed, 2 bad input (DIR/bad-input then stops
    the remaining points)."""
    if not (index[:1] in "123456789" and index.isdigit() and index.isascii() and index):
        _sweep_die("run-point: INDEX must be a positive integer, not '%s'" % index)
    jobs = os.path.join(dir, "jobs.tsv")
    if not os.path.isfile(jobs):
        _sweep_die("run-point: %s not found" % jobs)
    dir = os.path.abspath(dir)   # absolute: the job changes folder below
    with open(jobs) as f:
        table = f.read().split("\n")
    line = table[int(index)] if int(index) < len(table) else ""
    if not line:
        _sweep_die("run-point: %s/jobs.tsv has no point %s" % (dir, index))
    rtsim = sweep_conf(dir, "rtsim")
    if not (os.path.isfile(rtsim) and os.access(rtsim, os.X_OK)):
        _sweep_die("run-point: rtsim binary '%s' (from %s/sweep.conf) is not executable" % (rtsim, dir))
    # Relative scene, machine and argument paths are relative to where the
    # sweep was started, wherever this job runs.
    cwd = sweep_conf(dir, "cwd")
    if cwd:
        try:
            os.chdir(cwd)
        except OSError:
            _sweep_die("run-point: cannot enter %s (from %s/sweep.conf)" % (cwd, dir))
    hdr = [x for x in table[0].split("\t") if x]
    f = [x for x in line.split("\t") if x]
    name, scene, rays, machine, res = f[:5]
    n = len(hdr)
    sets = [] if f[5] == "-" else [kv for kv in f[5].split(";") if kv]
    sets += ["%s=%s" % (hdr[i], f[i]) for i in range(6, n - 1)]
    extra = [] if f[n - 1] == "-" else f[n - 1].split()
    point = (scene, rays, machine, res, sets, extra)

    result = os.path.join(dir, "results", name + ".json")
    log = os.path.join(dir, "logs", name + ".log")
    if os.path.exists(result):
        print("sweep: %s: done already" % name)
        return 0
    if os.path.exists(os.path.join(dir, "bad-input")):
        print("sweep: %s: not run, an earlier point had bad input (%s/bad-input)" % (name, dir), file=sys.stderr)
        return 2
    os.makedirs(os.path.join(dir, "results"), exist_ok=True)
    os.makedirs(os.path.join(dir, "logs"), exist_ok=True)
    tmp = os.path.join(dir, "results", ".%s.json.tmp.%s.%d" % (name, socket.gethostname().split(".")[0],
                                                                os.getpid()))
    child = []

    def interrupted(signum, frame):
        # a run-point stopped by a signal leaves no temporary
        for p in child:
            p.send_signal(signum)
            p.wait()
        if os.path.exists(tmp):
            os.remove(tmp)
        sys.exit(130)

    signal.signal(signal.SIGINT, interrupted)
    signal.signal(signal.SIGTERM, interrupted)
    t0 = time.time()
    with open(log, "w") as out:
        p = subprocess.Popen(rtsim_argv(rtsim, *point, json_path=tmp), stdout=out, stderr=subprocess.STDOUT)
        child.append(p)
        rc = p.wait()
    t1 = time.time()
    # rtsim exits 1 on a deadlock or livelock and still writes a JSON marked
    # run_failed: that is a result of the point (the same every time), kept.
    failed_run = False
    if rc == 1 and os.path.exists(tmp):
        with open(tmp, errors="replace") as fh:
            failed_run = '"run_failed": 1' in fh.read()
    if rc == 0 or failed_run:
        os.replace(tmp, result)
        print("sweep: %s: done in %.1f s%s" % (name, t1 - t0,
                                                " (run failed: deadlock or livelock, see its log)" if rc == 1 else ""))
        return 0
    if os.path.exists(tmp):
        os.remove(tmp)
    with open(log, errors="replace") as fh:
        log_text = fh.read()
    if rc == 2:
        # Bad input (an unknown key, a value out of range, a missing scene):
        # every other point most likely shares it, so the remaining ones stop early.
        marker = os.path.join(dir, ".bad-input.%d" % os.getpid())
        with open(marker, "w") as fh:
            fh.write("point %s: rtsim %s\n%s" % (name, " ".join(rtsim_argv(rtsim, *point, quiet=False)[1:]), log_text))
        os.replace(marker, os.path.join(dir, "bad-input"))
        last = log_text.rstrip("\n").split("\n")[-1] if log_text else ""
        print("sweep: %s: bad input: %s" % (name, last), file=sys.stderr)
        return 2
    print("sweep: %s: rtsim exited with status %d (log: %s)" % (name, rc, log), file=sys.stderr)
    return 1


def _sweep_plan_main(argv):
    ap = argparse.ArgumentParser(prog="rtsim_runs.py sweep-plan",
                                 description="Plans a sweep's DIR/jobs.tsv and DIR/sweep.conf (scripts/sweep runs it).")
    ap.add_argument("--dir", required=True, help="the sweep's output folder (absolute)")
    ap.add_argument("--rtsim", required=True, help="the rtsim binary (absolute)")
    ap.add_argument("--cwd", required=True, help="the folder the sweep was started in")
    ap.add_argument("--res", required=True, help="resolution of every point, WxH")
    ap.add_argument("--scene", action="append", required=True, help="a scene (repeatable, in order)")
    ap.add_argument("--rays", action="append", required=True, help="a ray type (repeatable, in order)")
    ap.add_argument("--machine", action="append", required=True, help="a machine (repeatable, in order)")
    ap.add_argument("--grid", action="append", default=[], help="KEY=V1,V2,...: a swept key (repeatable)")
    ap.add_argument("--set", action="append", default=[], help="KEY=VALUE: a fixed override (repeatable)")
    ap.add_argument("--stat", action="append", default=[], help="one more JSON statistic for the CSV (repeatable)")
    ap.add_argument("--baseline", default="", help="KEY=V[,KEY=V]: the paired changes' baseline (scripts/paired.py)")
    ap.add_argument("rtsim_args", nargs="*", help="fixed rtsim arguments for every point (after --)")
    a = ap.parse_args(argv)
    grid = [(g.split("=", 1)[0], g.split("=", 1)[1].split(",")) for g in a.grid]
    sweep_plan(a.dir, a.rtsim, a.cwd, a.scene, a.rays, a.machine, a.res, grid, a.set, a.rtsim_args, a.stat,
               a.baseline)


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "sweep-point":
        sys.exit(sweep_point(sys.argv[2], sys.argv[3]))
    if len(sys.argv) >= 2 and sys.argv[1] == "sweep-plan":
        _sweep_plan_main(sys.argv[2:])
        sys.exit(0)
    print("usage: python3 scripts/rtsim_runs.py sweep-plan OPTIONS | sweep-point DIR INDEX\n"
          "(scripts/sweep runs these; the experiment scripts import this module)", file=sys.stderr)
    sys.exit(2)
