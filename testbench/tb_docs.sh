#!/usr/bin/env bash
# The documentation a reader navigates (README.md, docs/**/*.md; docs/README.md
# is the index, docs/design.md "Conventions for contributors" the rules):
# - docs_images_used: every file in docs/images is shown or linked by some page;
# - docs_links_resolve: every relative link and image in README.md and
#   docs/**/*.md names an existing file, and its #anchor, if any, a heading
#   of that page (GitHub's heading ids);
# - docs_no_tracker_or_phase: no tracker number ("issue 15") and no work
#   phase ("session") in docs/ or README.md: a reader cannot look them up;
# - docs_index_lists_every_page: docs/README.md links every page of docs/;
# - docs_checker_catches_faults: the same checks on a made-up tree with one
#   broken link, one bad anchor, one unused image and one tracker number
#   report each of them (a control: the checks can fail).
#   bash testbench/tb_docs.sh [ROOT]     (ROOT: the checkout, found by default)
root=${1:-}
if [ -z "$root" ]; then
  root=$(cd "$(dirname "$0")" && pwd)
  while [ "$root" != / ] && ! { [ -f "$root/README.md" ] && [ -d "$root/docs" ]; }; do root=$(dirname "$root"); done
fi
if ! [ -f "$root/README.md" ] || ! [ -d "$root/docs" ]; then
  echo "FAIL docs_checkout: no README.md and docs/ above $(dirname "$0")"; exit 0
fi

# check_docs ROOT PREFIX: prints one PASS/FAIL line per rule, names prefixed.
check_docs() {
  python3 - "$1" "$2" <<'PY'
import os, re, sys, unicodedata
root, prefix = sys.argv[1], sys.argv[2]
pages = [os.path.join(root, "README.md")]
for d, _, fs in os.walk(os.path.join(root, "docs")):
    pages += [os.path.join(d, f) for f in sorted(fs) if f.endswith(".md")]
pages.sort()
rel = lambda p: os.path.relpath(p, root)

def strip_code(text):
    """Text outside fenced code blocks and inline code spans (links there are examples)."""
    out, fence = [], None
    for line in text.split("\n"):
        m = re.match(r"\s*(```+|~~~+)", line)
        if m:
            if fence is None: fence = m.group(1)[:3]
            elif m.group(1).startswith(fence): fence = None
            out.append(""); continue
        if fence is not None or re.match(r"(    |\t)", line) and not re.match(r"\s*([-*+]|\d+\.|\|)", line):
            out.append(""); continue
        out.append(re.sub(r"(`+)(?:(?!\1).)+\1", "", line))
    return "\n".join(out)

def slug(h):
    """GitHub's heading id: lower case, punctuation dropped, spaces to hyphens."""
    h = re.sub(r"`|\*\*|__|<[^>]+>", "", h.strip()).lower()
    h = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", h)
    h = "".join(c for c in h if c in "-_ " or unicodedata.category(c)[0] in "LN")
    return h.replace(" ", "-")

anchors = {}
def anchors_of(path):
    if path not in anchors:
        ids, seen = set(), {}
        fence = None
        for line in open(path, encoding="utf-8").read().split("\n"):
            m = re.match(r"\s*(```+|~~~+)", line)
            if m:
                fence = None if fence else m.group(1)[:3]; continue
            m = None if fence else re.match(r"#{1,6}\s+(.*?)\s*#*\s*$", line)
            if m:
                s = slug(m.group(1)); n = seen.get(s, 0); seen[s] = n + 1
                ids.add(s if n == 0 else "%s-%d" % (s, n))
        anchors[path] = ids
    return anchors[path]

link_re = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
bad, used = [], set()
for p in pages:
    text = strip_code(open(p, encoding="utf-8").read())
    for m in link_re.finditer(text):
        target = m.group(1)
        if re.match(r"[a-z][a-z0-9+.-]*:", target, re.I):   # http:, mailto: ...
            continue
        path, _, anchor = target.partition("#")
        dest = p if path == "" else os.path.normpath(os.path.join(os.path.dirname(p), path))
        line = text.count("\n", 0, m.start()) + 1
        if not os.path.exists(dest):
            bad.append("%s:%d: %s (no such file)" % (rel(p), line, target)); continue
        used.add(os.path.realpath(dest))
        if anchor and dest.endswith(".md") and os.path.isfile(dest) and anchor not in anchors_of(dest):
            bad.append("%s:%d: %s (no heading with id '%s' in %s)" % (rel(p), line, target, anchor, rel(dest)))

def report(name, faults):
    if faults: print("FAIL %s%s: %d: %s" % (prefix, name, len(faults), "; ".join(faults[:4])))
    else: print("PASS %s%s" % (prefix, name))

img_dir = os.path.join(root, "docs", "images")
images = sorted(os.listdir(img_dir)) if os.path.isdir(img_dir) else []
report("docs_images_used", [i for i in images if os.path.realpath(os.path.join(img_dir, i)) not in used])
report("docs_links_resolve", bad)

phase = re.compile(r"\bissues? #?[0-9]|\(#[0-9]+\)|\bsessions?\b", re.I)
hits = []
for p in pages:
    for n, line in enumerate(open(p, encoding="utf-8"), 1):
        if phase.search(line): hits.append("%s:%d: %s" % (rel(p), n, line.strip()[:70]))
report("docs_no_tracker_or_phase", hits)

index = os.path.join(root, "docs", "README.md")
if os.path.isfile(index):
    listed = {os.path.normpath(os.path.join(os.path.dirname(index), m.group(1).partition("#")[0]))
              for m in link_re.finditer(strip_code(open(index, encoding="utf-8").read()))}
    report("docs_index_lists_every_page",
           [rel(p) for p in pages if p != index and rel(p) != "README.md" and os.path.normpath(p) not in listed])
else:
    report("docs_index_lists_every_page", ["docs/README.md missing"])
PY
}

check_docs "$root" ""

# Control: a made-up checkout with one fault of each kind.
tmp=$(mktemp -d "${RTSIM_TMP:-${TMPDIR:-/tmp}}/tb_docs.XXXXXX") || { echo "FAIL docs_checker_catches_faults: mktemp"; exit 0; }
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/docs/images" "$tmp/docs/validation"
printf 'x' >"$tmp/docs/images/used.png"; printf 'x' >"$tmp/docs/images/unused.png"
printf '# Top\n\nSee [a](docs/a.md), [gone](docs/gone.md), ![u](docs/images/used.png).\n' >"$tmp/README.md"
printf '# Index\n\n[a](a.md) [b](validation/b.md)\n' >"$tmp/docs/README.md"
printf '# A page\n\n## Real heading\n\n[ok](#real-heading) [bad](#no-such-heading) [up](../README.md#top)\nFixed in issue 12.\n' >"$tmp/docs/a.md"
printf '# B\n\n[code `x`](../a.md#a-page) `[not a link](nowhere.md)`\n' >"$tmp/docs/validation/b.md"
out=$(check_docs "$tmp" "control_")
want='FAIL control_docs_images_used: 1: unused.png
FAIL control_docs_links_resolve: 2: README.md:3: docs/gone.md (no such file); docs/a.md:5: #no-such-heading (no heading with id '"'no-such-heading'"' in docs/a.md)
FAIL control_docs_no_tracker_or_phase: 1: docs/a.md:6: Fixed in issue 12.
PASS control_docs_index_lists_every_page'
if [ "$out" = "$want" ]; then echo "PASS docs_checker_catches_faults"
else echo "FAIL docs_checker_catches_faults: got: $(echo "$out" | tr '\n' '|')"; fi
