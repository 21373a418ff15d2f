# common.bash — set-up shared by the rtsim benchmark suites (bench/*.sh;
# sourced, not a suite itself: make bench runs bench/*.sh only).
#   bench_setup SUITE DEFAULT_RUNS [BUILD_DIR]
# sets build, runs (RUNS overrides), bin (build/bin/rtsim, built if missing),
# out (BUILD_DIR/bench), tmp (removed at exit) and csv (OUT/SUITE.csv.tmp with
# the header benchmark,ours_median_s,reference_median_s,ratio; the suite
# renames it when complete), and defines median (stdin numbers -> median)
# and host_cpu (an rtsim summary on stdin -> its host CPU seconds).
bench_setup() {
  local suite=$1
  build=${3:-build}
  runs=${RUNS:-$2}
  bin=$build/bin/rtsim
  [ -x "$bin" ] || make -s BUILD="$build" "$bin" >&2
  out=$build/bench
  mkdir -p "$out"
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  csv=$out/$suite.csv.tmp
  echo "benchmark,ours_median_s,reference_median_s,ratio" >"$csv"
}

# the summary's CPU line "host  12.345 s CPU (...)", not --accuracy's steps line
host_cpu() { awk '/^host +[0-9]/ { print $2 }'; }
median() { sort -g | awk '{ v[NR] = $1 } END { if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
