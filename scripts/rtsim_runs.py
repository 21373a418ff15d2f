"""rtsim_runs — running rtsim points for the experiment scripts
(scripts/paper-tables, scripts/sensitivity): one JSON per point in a runs
folder, reused when present (an interrupted script resumes), points run in
parallel, every failure reported with its command and rtsim's message.
Standard library only."""
import concurrent.futures as cf
import hashlib
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_BIN = os.path.join(ROOT, "build", "bin", "rtsim")


def die(tool, msg):
    print("%s: %s" % (tool, msg), file=sys.stderr)
    sys.exit(2)


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


class Refused(Exception):
    """rtsim refused the machine at start-up (exit 2): not a valid point."""


def run_point(rtsim, runs_dir, scene, rays, machine, res, sets=(), extra=()):
    """Statistics of one point, running rtsim unless its JSON exists (rtsim
    writes it under a temporary name and renames it when complete). extra:
    further rtsim arguments (e.g. --accuracy 2%). A machine rtsim refuses
    (exit 2) raises Refused with rtsim's message."""
    path = os.path.join(runs_dir, point_name(scene, rays, machine, res, sets, extra))
    if not os.path.exists(path):
        cmd = [rtsim, scene, "--res", res, "--rays", rays, "--machine", machine, "--quiet", "--json", path]
        for s in sets:
            cmd += ["--set", s]
        cmd += list(extra)
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if p.returncode == 2:
            # rtsim's message, without the "(see rtsim --help)" hint after it
            lines = [l for l in p.stderr.strip().splitlines() if l and not l.startswith("(see ")]
            raise Refused("; ".join(lines) if lines else "exit 2")
        if p.returncode != 0:
            raise RuntimeError("%s: exit %d: %s" % (" ".join(cmd), p.returncode, p.stderr.strip()[-400:]))
    with open(path) as f:
        return json.load(f)


def run_all(tool, rtsim, runs_dir, points, jobs, refused=None):
    """points: list of (scene, rays, machine, res, sets[, extra]); returns {point: stats}.
    With a dict `refused`, a point rtsim refuses goes there (point: message)
    instead of stopping the script."""
    os.makedirs(runs_dir, exist_ok=True)
    out = {}
    with cf.ThreadPoolExecutor(max_workers=jobs) as ex:
        fut = {ex.submit(run_point, rtsim, runs_dir, *p): p for p in points}
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


def write_atomic(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def gnuplot(tool, script, outputs):
    """Runs a gnuplot script that writes OUT.tmp for each OUT, then renames."""
    p = subprocess.run(["gnuplot"], input=script, text=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    if p.returncode != 0:
        die(tool, "gnuplot failed: %s" % p.stderr.strip())
    for o in outputs:
        os.replace(o + ".tmp", o)
