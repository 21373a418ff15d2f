#!/usr/bin/env bash
# tb_scripts_help — every executable in scripts/ answers --help (exit 0, on
# stdout, before doing anything else) with a summary that is a whole sentence
# and a description of each option: every option its usage or synopsis line
# names, and every option line of the help, has words after it (on the line
# or the next, deeper-indented one). A reader that stops early (`--help |
# head -1`) ends the script quietly, with no traceback: its help is written
# into a pipe already closed. Runs each script's --help only.
set -u
cd "$(dirname "$0")/../.."
tmp=${RTSIM_TMP:-/tmp}/tb_scripts_help
rm -rf "$tmp"; mkdir -p "$tmp"
python3 - "$tmp" <<'PY'
import os
import re
import subprocess
import sys

tmp = sys.argv[1]
OPT = re.compile(r"(?<![\w-])(--?[A-Za-z][\w-]*)")
OPT_LINE = re.compile(r"^(\s+)((?:-[A-Za-z], )?--?[A-Za-z][\w-]*)(.*)$")


def described(lines, i):
    """Whether option line i has words after its option and value names."""
    m = OPT_LINE.match(lines[i])
    rest = m.group(3)   # the value's name (if any), then two or more blanks and the words
    parts = re.split(r"\s{2,}", rest if re.match(r"\s{2,}\S", rest) else rest.strip())
    if len(parts) >= 2 and re.search(r"\w", parts[1]):
        return True
    nxt = lines[i + 1] if i + 1 < len(lines) else ""
    return (len(nxt) - len(nxt.lstrip()) > len(m.group(1)) and re.search(r"\w", nxt)
            and not OPT_LINE.match(nxt))


scripts = sorted(f for f in os.listdir("scripts")
                 if os.path.isfile(os.path.join("scripts", f)) and os.access(os.path.join("scripts", f), os.X_OK))
for name in scripts:
    path = os.path.abspath(os.path.join("scripts", name))
    try:
        p = subprocess.run([path, "--help"], cwd=tmp, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                           timeout=60, env=dict(os.environ, RTSIM="/nonexistent/rtsim"))
    except subprocess.TimeoutExpired:
        print("FAIL scripts_help_%s: --help did not return within 60 s" % name)
        continue
    lines = p.stdout.rstrip("\n").split("\n")
    if p.returncode != 0 or not p.stdout.strip():
        print("FAIL scripts_help_%s: --help exit %d, %d bytes on stdout: %s" % (
            name, p.returncode, len(p.stdout), (p.stderr.strip().splitlines() or [""])[0][:120]))
        continue
    # the usage block (argparse) or the synopsis lines (a header comment)
    synopsis, i = [], 0
    if lines[0].startswith("usage:"):
        while i < len(lines) and lines[i].strip():
            synopsis.append(lines[i])
            i += 1
    for j, l in enumerate(lines):
        s = l.strip()
        if s.startswith("scripts/%s" % name) or s.startswith("usage:") or s.startswith("Usage:"):
            synopsis.append(l)
            k = j + 1
            while k < len(lines) and lines[k].strip().startswith("["):
                synopsis.append(lines[k])
                k += 1
    # the summary: the first paragraph after the usage block
    while i < len(lines) and not lines[i].strip():
        i += 1
    para = []
    while i < len(lines) and lines[i].strip() and not lines[i][:1].isspace() and \
            not re.match(r"(Usage|Arguments|Options):", lines[i]):
        para.append(lines[i].strip())
        i += 1
    summary = " ".join(para)
    problems = []
    if not summary or summary[-1] not in ".:":
        problems.append("summary does not end a sentence: '...%s'" % summary[-50:])
    named = {t for l in synopsis for t in OPT.findall(l) if t not in ("-h",)}
    listed = {}
    for j, l in enumerate(lines):
        m = OPT_LINE.match(l)
        if m:
            for t in OPT.findall(m.group(2)):
                listed[t] = listed.get(t) or described(lines, j)
    for t in sorted(named):
        if t not in listed:
            problems.append("%s is in the usage but not described" % t)
    for t, ok in sorted(listed.items()):
        if not ok:
            problems.append("%s has no description" % t)
    if problems:
        print("FAIL scripts_help_%s: %s" % (name, "; ".join(problems)))
    else:
        print("PASS scripts_help_%s" % name)
    # a closed pipe: the reader is gone before the first byte
    r, w = os.pipe()
    os.close(r)
    try:
        # Python's default output buffering, as on a user's machine (unbuffered,
        # the closed pipe passed unnoticed here and failed on a fresh one)
        env = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}
        q = subprocess.run([path, "--help"], cwd=tmp, stdout=w, stderr=subprocess.PIPE, text=True, timeout=60,
                           env=dict(env, RTSIM="/nonexistent/rtsim"))
        err = q.stderr
    except subprocess.TimeoutExpired:
        err = "did not return within 60 s"
    os.close(w)
    if "Traceback" in err or "Error" in err or "did not return" in err:
        print("FAIL scripts_help_pipe_%s: --help into a closed pipe: %s" % (name, err.strip().splitlines()[-1][:120]))
    else:
        print("PASS scripts_help_pipe_%s" % name)
PY
