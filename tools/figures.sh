#!/usr/bin/env bash
# Regenerates every number and figure the README quotes from the current code, with a
# description of the machine they were measured on:
#   bash tools/figures.sh          (make figures; FULL=1 make figures adds the full runs)
# It writes
#   out/                the app's CSV files, printed tables and machine.txt (not committed)
#   docs/*.png          the figures (tools/plot.py; needs Python 3 with matplotlib)
#   README.md           every block between "<!-- figures:NAME -->" and "<!-- /figures:NAME -->"
# With FULL=1 it also runs `taylorode table --full` (a few minutes) for the block "full"
# (the rows that stop at the step budget otherwise); without it that block keeps its
# earlier numbers and their own date line. PEERS=<the peer harness's folder> runs the
# peer solvers (CVODE, ARKODE) in the same run and draws them beside taylorode;
# FLOOR=<hand-coded floor, C> times i-t-2 against it (tools/floor.sh).
#
# The comparison with the peers (PEERS=...) comes from interleaved rounds: taylorode's
# bench runs, then the peers' runs, then taylorode's again, ..., ROUNDS times, each run
# repeated until MIN_TIME CPU seconds have accumulated; tools/ratios.py forms the CPU
# ratios at equal error within each round and gives their median over the rounds and
# their range. Settings (environment):
#   ROUNDS=3            rounds (without PEERS one round: nothing to interleave)
#   ERRORS=1e-8:1e-4    the errors at which CPU times are compared; only runs that end
#                       with status ok and an error in this range are compared
#   MIN_TIME=0.2        CPU seconds accumulated per run (both drivers)
#   QUICK=1             a check of the performance tooling in a few minutes: four small
#                       problems and bs1000, three schemes, 2 rounds of 0.05 s runs; the
#                       other runs are skipped, README.md and docs/ are left alone (the
#                       blocks are in out/quick/blocks, the figures in out/quick/png)
# The tolerances are fixed below: tol = 1e-3 ... 1e-10 on the small problems (OREGO's
# absolute error reaches 1e-4 only near tol = 1e-9), 1e-3 ... 1e-8 with the paper's
# embedded estimate (whose errors are far below the tolerance; beyond 1e-8 its runs
# reach the step budget), 1e-3 ... 1e-6 on bs1000 and bs10000; ARKODE 1e-3 ... 1e-9;
# CVODE, the reference of the ratios, down to 1e-11 (small) and 1e-8 (large), so that
# the others' tightest runs lie between two of its runs. A peer solve stops after 3 CPU
# seconds (the harness's -B; after three such stops the tighter tolerances are
# skipped), twice the longest solves that complete (ARKODE on Van der Pol at 1e-9 and on
# E5 at 1e-8, 1.4 s; it stops ARKODE on E5 at 1e-9): with 60 s a few runs that go
# nowhere (ARKODE and CVODE on Robertson at tol 1e-3) took a minute each.
# With PEERS, FLOOR, ROUNDS=3 and MIN_TIME=0.2: about 18 minutes on a busy 2-core machine,
# 16 of them the rounds (the machine block of the README gives the last run's).
# CPU times depend on the machine and on whatever else runs: use a quiet machine.
set -euo pipefail
trap 'echo "figures: ERROR: line $LINENO failed (exit status $?): $BASH_COMMAND" >&2' ERR
# PEERS and FLOOR as absolute paths, before the cd below
absolute() { case "$1" in ''|/*) echo "$1" ;; *) echo "$PWD/$1" ;; esac; }
peers="$(absolute "${PEERS:-}")"
floor="$(absolute "${FLOOR:-}")"
cd "$(dirname "${BASH_SOURCE[0]}")/.."
started="$(date +%s)"
quick="${QUICK:-0}"
out="out"
png="docs"
[ "$quick" != 1 ] || { out="out/quick"; png="$out/png"; }
blocks="$out/blocks"
mkdir -p "$out" "$png" "$blocks"
note() { echo "figures: $*" >&2; }
die() { note "ERROR: $*"; exit 1; }

errors="${ERRORS:-1e-8:1e-4}"
if [ "$quick" = 1 ]; then rounds="${ROUNDS:-2}"; min_time="${MIN_TIME:-0.05}"; else rounds="${ROUNDS:-3}"; min_time="${MIN_TIME:-0.2}"; fi
case "$rounds" in ''|*[!0-9]*|0) die "ROUNDS=$rounds: a whole number of rounds, at least 1" ;; esac
[[ "$min_time" =~ ^[0-9]*\.?[0-9]+$ ]] || die "MIN_TIME=$min_time: CPU seconds, e.g. 0.2"
[[ "$errors" =~ ^[0-9.eE+-]+:[0-9.eE+-]+$ ]] || die "ERRORS=$errors: LOW:HIGH, e.g. 1e-8:1e-4"
[ -n "$peers" ] || rounds=1

# the problems, schemes and tolerances of the comparison
small="vdp1e3_wp,vdp1e3_up,rober40,rober1e11,hires,orego,e5,bruss32,bruss512"
large="bs1000,bs10000"
huge="bs100000"
schemes="si-t-2,i-t-2,imex-rk21,radau5"
if [ "$quick" = 1 ]; then
  small="vdp1e3_wp,rober1e11,orego,bruss32"
  large="bs1000"
  huge=""
  schemes="si-t-2,i-t-2,radau5"
fi
tols_small="1e-3:1e-10"
tols_embedded="1e-3:1e-8"
tols_large="1e-3:1e-6"
peer_tols_small="1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9"
cvode_tols_small="$peer_tols_small,1e-10,1e-11"
cvode_tols_large="1e-3,1e-4,1e-5,1e-6,1e-7,1e-8"
peer_budget=3

# every input asked for, before any run: fail now rather than leave an empty table
if [ -n "$peers" ]; then
  [ -d "$peers" ] || die "PEERS=$peers is not a folder (the peer harness's)"
  [ -x "$peers/sundials_bench" ] || die "PEERS=$peers has no built sundials_bench (make -C $peers)"
  [ -d "$peers/refs" ] || die "PEERS=$peers has no refs/ (the reference solutions)"
  [ -f "$peers/report.py" ] || die "PEERS=$peers has no report.py"
  for problem in ${small//,/ }; do
    [ -s "$peers/refs/$problem.csv" ] || die "PEERS=$peers has no reference refs/$problem.csv"
  done
fi
if [ -n "$floor" ] && [ ! -f "$floor" ]; then die "FLOOR=$floor: no such file (the floor's C source)"; fi

# a Python with matplotlib for the figures, found before any run: the project's .venv
# (which make puts first on PATH when it provides fpm) or any python3 further on PATH
python=""
for candidate in .venv/bin/python $(type -ap python3); do
  if "$candidate" -c 'import matplotlib' >/dev/null 2>&1; then python="$candidate"; break; fi
done
if [ -z "$python" ]; then
  note "ERROR: no Python with matplotlib for the figures (python3 -m pip install matplotlib)"
  exit 1
fi

fpm build --profile release >/dev/null
app="$(fpm run --profile release --runner echo 2>/dev/null | tail -n 1)"
[ -x "$app" ] || { note "ERROR: no release build of the app ($app)"; exit 1; }
run() { "$app" "$@"; }

# ---------------------------------------------------------------- the machine
commit="$(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
if ! git diff --quiet HEAD -- src app example fpm.toml 2>/dev/null; then commit="$commit with uncommitted changes"; fi
cpu="$(sed -n 's/^model name[[:space:]]*: *//p' /proc/cpuinfo 2>/dev/null | sed -n 1p)"
[ -n "$cpu" ] || cpu="$(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | sed -n 1p)"
cores="$(lscpu -p=core,socket 2>/dev/null | grep -v '^#' | sort -u | wc -l)"
cpus="$(nproc)"
compiler="$(gfortran --version | sed -n 1p)"
libraries="$(ldd "$app" 2>/dev/null | awk '/liblapack|libblas|libopenblas/ { print $1 " -> " $3 }' |
  while read -r name _ path; do echo "$name $(readlink -f "$path")"; done | paste -sd ',' - | sed 's/,/, /g')"
system="$( (. /etc/os-release 2>/dev/null && echo "$PRETTY_NAME") || uname -s), Linux $(uname -r)"
today="$(date -u +%Y-%m-%d)"
{
  echo "date: $today"
  echo "code: commit $commit, fpm release profile"
  echo "cpu: $cpu, $cpus logical CPUs available, $cores cores"
  echo "compiler: $compiler"
  echo "lapack/blas: $libraries"
  echo "system: $system"
} > "$out/machine.txt"
stamp="<sub>Measured $today with the code of commit $commit by \`make figures\` on $cpu ($cpus logical CPUs), $compiler.</sub>"

# ---------------------------------------------------------------- runs
extreme_status=0
if [ "$quick" != 1 ]; then
  echo "figures: running the app ($app); about three minutes" >&2
  for scheme in si-t-1 si-t-2 i-t-1 i-t-2 radau5; do
    run vdp --scheme "$scheme" --history "$out/vdp_$scheme.csv" --force > "$out/vdp_$scheme.txt"
  done
  for controller in i pi pid; do
    for ic in 1 2; do
      run vdp --scheme i-t-2 --controller "$controller" --ic "$ic" > "$out/controller_${controller}_ic$ic.txt"
    done
  done
  run table --out "$out" --force > "$out/table.txt"
  run sweep --tols 1e-3:1e-7 --out "$out" --force > "$out/sweep.txt"
  run stability --grid 401 --out "$out" --force > "$out/stability.txt"
  run extreme --out "$out" --force > "$out/extreme.txt" 2>/dev/null || extreme_status=$?
  run accuracy --out "$out" --force > "$out/accuracy.txt"
  fpm run --profile release --example convergence_study 2>/dev/null > "$out/convergence_study.txt"
  if [ "${FULL:-0}" = 1 ]; then
    echo "figures: FULL=1: table --full (a few minutes)" >&2
    mkdir -p "$out/full"
    run table --full --out "$out/full" --force > "$out/full/table.txt"
  fi
fi

# ---------------------------------------------------------------- performance
# taylorode's bench on the peer harness's problems; with PEERS=<the peer harness's
# folder> (its sundials_bench built, its refs/) the peers run on the same problems in
# the same rounds, their references are used, tools/ratios.py gives the CPU ratios at
# equal error over the rounds and writes the CSV files with each run's median CPU time
# over the rounds into out/, from which tools/plot.py draws everyone's work-precision
# curves (the harness's report.py reads the same files into out/report). FLOOR=<it2_vdp.c>
# adds the per-step comparison with the hand-coded floor.
refs=()
if [ -n "$peers" ]; then
  # the harness's references, and those of the scaling problems computed once into
  # out/refs (the harness's folder may be read-only)
  mkdir -p "$out/refs"
  for file in "$peers"/refs/*.csv; do ln -sf "$(readlink -f "$file")" "$out/refs/"; done
  for problem in ${large//,/ } $huge; do
    if [ ! -s "$out/refs/$problem.csv" ]; then
      note "the reference of $problem (CVODE at rtol 1e-13, atol 1e-15; bs100000 about 15 s)"
      "$peers/sundials_bench" ref cvode_bdf "$problem" 1e-13 1e-15 > "$out/refs/$problem.csv.new" 2>/dev/null
      mv "$out/refs/$problem.csv.new" "$out/refs/$problem.csv"
    fi
  done
  refs=(--refs "$out/refs")
fi

# runs a command with its standard error (the progress lines) in the file $1, whose end
# is shown if the command fails
logged() {
  local log="$1" status=0
  shift
  "$@" 2> "$log" || status=$?
  if [ "$status" -ne 0 ]; then
    note "ERROR: $* failed (exit status $status); the end of $log:"
    tail -n 5 "$log" | sed 's/^/  | /' >&2
  fi
  return "$status"
}

# one round of taylorode's runs into the folder $1; the peak memory of the bs100000
# run in $1/bench_huge.time
bench_round() {
  local dir="$1"
  logged "$dir/bench_small.log" run bench --problems "vdp-paper,$small" --schemes "$schemes" --tols "$tols_small" \
    --min-time "$min_time" "${refs[@]}" --csv "$dir/bench_small.csv" --force > "$dir/bench_small.txt"
  logged "$dir/bench_embedded.log" run bench --problems "$small" --schemes si-t-2,i-t-2 --tols "$tols_embedded" \
    --estimate embedded --min-time "$min_time" "${refs[@]}" --csv "$dir/bench_embedded.csv" --force \
    > "$dir/bench_embedded.txt"
  # si-t-2 with step doubling, beside its default (the estimate of its own step's error)
  logged "$dir/bench_doubling.log" run bench --problems "$small" --schemes si-t-2 --tols "$tols_small" \
    --estimate doubling --min-time "$min_time" "${refs[@]}" --csv "$dir/bench_doubling.csv" --force \
    > "$dir/bench_doubling.txt"
  logged "$dir/bench_doubling_large.log" run bench --problems "$large" --schemes si-t-2 --tols "$tols_large" \
    --estimate doubling --min-time "$min_time" "${refs[@]}" --csv "$dir/bench_doubling_large.csv" --force \
    > "$dir/bench_doubling_large.txt"
  logged "$dir/bench_large.log" run bench --problems "$large" --schemes "$schemes" --tols "$tols_large" \
    --min-time "$min_time" "${refs[@]}" --csv "$dir/bench_large.csv" --force > "$dir/bench_large.txt"
  if [ -n "$huge" ]; then
    # one run of each at 200,000 unknowns (min-time 0.01), with its peak memory
    if env time -v true >/dev/null 2>&1; then
      logged "$dir/bench_huge.time" /usr/bin/env time -v "$app" bench --problems "$huge" --schemes si-t-2 \
        --tols 1e-3:1e-5 --min-time 0.01 "${refs[@]}" --csv "$dir/bench_huge.csv" --force > "$dir/bench_huge.txt"
    else
      logged "$dir/bench_huge.log" run bench --problems "$huge" --schemes si-t-2 --tols 1e-3:1e-5 --min-time 0.01 \
        "${refs[@]}" --csv "$dir/bench_huge.csv" --force > "$dir/bench_huge.txt"
    fi
  fi
}

# one round of the peers' runs into the folder $1
peers_round() {
  local dir="$1" bench="$peers/sundials_bench"
  logged "$dir/peers_cvode.log" "$bench" bench -p "$small" -s cvode_bdf -t "$cvode_tols_small" -m "$min_time" \
    -B "$peer_budget" -r "$out/refs" > "$dir/peers_small.csv"
  logged "$dir/peers_ark.log" "$bench" bench -p "$small" -s ark_imex3 -t "$peer_tols_small" -m "$min_time" \
    -B "$peer_budget" -r "$out/refs" -H >> "$dir/peers_small.csv"
  logged "$dir/peers_large.log" "$bench" bench -p "$large" -s cvode_bdf -t "$cvode_tols_large" -m "$min_time" \
    -B "$peer_budget" -r "$out/refs" > "$dir/peers_large.csv"
  if [ -n "$huge" ]; then
    logged "$dir/peers_huge.log" "$bench" bench -p "$huge" -s cvode_bdf -t 1e-3,1e-4,1e-5,1e-6 -m 0.01 -B 60 \
      -r "$out/refs" -H >> "$dir/peers_large.csv"
  fi
}

rm -rf "$out/rounds"
for round in $(seq 1 "$rounds"); do
  dir="$out/rounds/$round"
  mkdir -p "$dir"
  mark="$(date +%s)"
  note "round $round of $rounds: taylorode's bench"
  bench_round "$dir"
  note "round $round of $rounds: taylorode's bench took $(($(date +%s) - mark)) s"
  if [ -n "$peers" ]; then
    mark="$(date +%s)"
    peers_round "$dir"
    note "round $round of $rounds: the peers took $(($(date +%s) - mark)) s"
  fi
done
first="$out/rounds/1"
for file in "$first"/bench_*.txt "$first"/bench_huge.time; do [ ! -f "$file" ] || cp "$file" "$out/"; done
ours=()
for file in "$first"/bench_*.csv; do ours+=("$out/$(basename "$file")"); done
{
  echo "$stamp"
  echo
  if [ "$rounds" -gt 1 ]; then
    echo "The bench's report of round 1 of $rounds (its CPU times are one round's; the spread over the rounds is"
    echo "given under the ratios above):"
    echo
  fi
  echo '```'
  grep -vE '^(wrote|peak) ' "$first/bench_small.txt"
  grep -E '^(bs|problem)' "$first/bench_large.txt" | grep -v '^problem'
  [ -z "$huge" ] || grep -E '^bs' "$first/bench_huge.txt"
  echo '```'
  memory="$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$first/bench_huge.time" 2>/dev/null || true)"
  [ -z "$memory" ] || echo "Peak memory of the bs100000 run (si-t-2, 200,000 unknowns): $((memory / 1024)) MiB."
} > "$blocks/performance.md"
if [ -n "$peers" ]; then
  if [ -n "$huge" ]; then
    /usr/bin/env time -v "$peers/sundials_bench" bench -p "$huge" -s cvode_bdf -t 1e-4 -m 0.01 -r "$out/refs" \
      > /dev/null 2> "$out/peers_huge.time" || true
  fi
  "$python" tools/ratios.py --errors "$errors" --summary "$out/peers_summary.md" --median-csv "$out" \
    "$out"/rounds/* > "$out/ratios.md"
  # the harness's own report reads the same CSV files (out/report); the README's figures
  # beside the peers come from tools/plot.py below, which tells the peers from the schemes
  "$python" "$peers/report.py" -o "$out/report" "$out/peers_small.csv" "$out/peers_large.csv" "${ours[@]}" >/dev/null
  range="$(echo "$errors" | awk -F: '{ if ($1 + 0 <= $2 + 0) print $1 " to " $2; else print $2 " to " $1 }')"
  plural="s"
  [ "$rounds" -gt 1 ] || plural=""
  {
    echo "$stamp"
    echo
    echo "CPU time against CVODE (BDF, band solver on the Brusselator) at equal error, for errors from $range"
    echo "(the harness's measure), from $rounds interleaved round$plural (taylorode's runs, then the peers', $rounds"
    echo "time$plural; each run repeated until $min_time s of CPU have accumulated): per cell the median over the rounds"
    echo "of the round's median ratio over the runs compared, their range over the rounds in parentheses, the"
    echo "number of runs compared per round in brackets; below 1: faster than CVODE. Only correct runs are"
    echo "compared, status ok and an error in the range; CVODE's time at the same error is interpolated between"
    echo "the two of its correct runs around it (\`tools/ratios.py\`)."
    echo
    cat "$out/ratios.md"
    memory="$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$out/peers_huge.time" 2>/dev/null || true)"
    ours_memory="$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$first/bench_huge.time" 2>/dev/null || true)"
    if [ -n "$memory" ] && [ -n "$ours_memory" ]; then
      echo
      echo "Peak memory on bs100000 (200,000 unknowns): CVODE $((memory / 1024)) MiB, taylorode's si-t-2 run" \
        "$((ours_memory / 1024)) MiB ($(awk -v a="$ours_memory" -v b="$memory" 'BEGIN { printf "%.2f", a / b }') x)."
    elif [ -n "$memory" ]; then
      echo
      echo "Peak memory of CVODE on bs100000: $((memory / 1024)) MiB."
    fi
  } > "$blocks/peers.md"
  {
    echo "$stamp"
    echo
    echo "Generated from the table above: per solver, the median and the range over the problems of the"
    echo "problems' ratios to CVODE's CPU time (errors $range; $rounds round$plural), and where it has none."
    echo
    cat "$out/peers_summary.md"
  } > "$blocks/peers-summary.md"
else
  for file in "${ours[@]}"; do cp "$first/$(basename "$file")" "$file"; done
fi
if [ -n "$floor" ]; then
  floor_rounds=5
  [ "$quick" != 1 ] || floor_rounds="$rounds"
  { echo "$stamp"; echo; echo '```'; bash tools/floor.sh "$floor" "$floor_rounds"; echo '```'; } > "$blocks/floor.md"
fi

# ---------------------------------------------------------------- README blocks
# 1234567 -> 1,234,567
thousands='function th(n,  s) { s = sprintf("%d", n); while (s ~ /[0-9][0-9][0-9][0-9]/) sub(/[0-9][0-9][0-9]($|,)/, ",&", s); return s }'

if [ "$quick" != 1 ]; then
  # Table 1 as markdown from table1.csv (ic,scheme,splitting,accepted,rejected,cpu_seconds,
  # runs,status,t_reached,error_t3000,max_error_grid301,paper_steps,paper_cpu_seconds)
  table1_md() {
    awk -F, "$thousands"'
      NR == 1 { print "| IC | scheme | split | accepted | rejected | CPU s | err t=3000 | max err grid | paper steps | paper CPU s |"
                print "|---|---|---|---|---|---|---|---|---|---|"; next }
      { acc = th($4)
        if ($8 != "ok") acc = "> " acc " (" $8 " at t = " sprintf("%.1f", $9) ")"
        printf "| %s | %s | %s | %s | %s | %.3f | %s | %s | %s | %s |\n", $1, $2, $3, acc, th($5), $6,
               ($8 == "ok" ? $10 : "–"), ($8 == "ok" ? $11 : "–"), ($12 == "" ? "" : th($12)), $13 }' "$1"
  }
  { echo "$stamp"; echo; table1_md "$out/table1.csv"; } > "$blocks/table1.md"
  # the full runs of the rows that stopped at the step budget above
  if [ -f "$out/full/table1.csv" ]; then
    awk -F, 'NR == FNR { if (FNR > 1 && $8 != "ok") capped[$1 FS $2 FS $3] = 1; next }
             FNR == 1 || ($1 FS $2 FS $3) in capped' "$out/table1.csv" "$out/full/table1.csv" > "$out/full/capped.csv"
    { echo "$stamp"; echo; table1_md "$out/full/capped.csv"; } > "$blocks/full.md"
  fi

  # i-t-2 under the three controllers
  {
    echo "$stamp"
    echo
    echo "| i-t-2, controller | IC1 accepted | IC1 rejected | IC2 accepted | IC2 rejected |"
    echo "|---|---|---|---|---|"
    for controller in i pi pid; do
      row="| $controller |"
      for ic in 1 2; do
        counts="$(sed -n 's/^accepted steps \([0-9,]*\), rejected \([0-9,]*\).*/\1 | \2/p' "$out/controller_${controller}_ic$ic.txt")"
        row="$row $counts |"
      done
      echo "$row"
    done
  } > "$blocks/controllers.md"

  # observed orders of the convergence study: "scheme  steps...  e1 e2 e3 e4  o1 o2 o3"
  {
    echo "$stamp"
    echo
    echo "| scheme | steps N | error at t = 1 for each N | observed orders |"
    echo "|---|---|---|---|"
    awk 'NR > 1 && NF >= 9 {
           n = NF; steps = ""; for (k = 2; k <= n - 7; k++) steps = steps (k > 2 ? " " : "") $k
           printf "| %s | %s | %s, %s, %s, %s | %s, %s, %s |\n", $1, steps, $(n-6), $(n-5), $(n-4), $(n-3), $(n-2), $(n-1), $n }' \
      "$out/convergence_study.txt"
  } > "$blocks/orders.md"

  # the stability and extreme reports as printed
  { echo "$stamp"; echo; echo '```'; grep -v '^wrote ' "$out/stability.txt"; echo '```'; } > "$blocks/stability.md"
  {
    echo "$stamp"
    echo
    echo '```'
    grep -E '^(ok|FAIL) ' "$out/extreme.txt" || true
    tail -n 1 "$out/extreme.txt" | grep -vE '^(ok|FAIL|wrote) ' || true
    echo '```'
    [ "$extreme_status" -eq 0 ] || echo "\`taylorode extreme\` exits with status $extreme_status: a case above failed."
  } > "$blocks/extreme.md"

  # the accuracy report: the summary over the problems, then every problem's table
  {
    echo "$stamp"
    echo
    echo '```'
    sed -n '/^worst over the problems/,/^wrote /p' "$out/accuracy.txt" | grep -v '^wrote '
    echo '```'
    echo
    echo '<details><summary>Every problem</summary>'
    echo
    echo '```'
    sed -n '1,/^worst over the problems/p' "$out/accuracy.txt" | grep -v '^worst over the problems'
    echo '```'
    echo
    echo '</details>'
  } > "$blocks/accuracy.md"
fi

# the machine, and how long this run took
elapsed=$(( ($(date +%s) - started + 30) / 60 ))
settings="PEERS $([ -n "$peers" ] && echo "set, $rounds rounds, MIN_TIME $min_time, errors $errors" || echo unset)"
settings="$settings, FLOOR $([ -n "$floor" ] && echo set || echo unset)"
[ "${FULL:-0}" != 1 ] || settings="$settings, FULL=1"
echo "duration: $elapsed min ($settings)" >> "$out/machine.txt"
{
  echo "| | |"
  echo "|---|---|"
  sed 's/^\([^:]*\): \(.*\)$/| \1 | \2 |/' "$out/machine.txt"
} > "$blocks/machine.md"

plot_errors=()
[ -z "$peers" ] || plot_errors=(--errors "$errors")
if [ "$quick" = 1 ]; then
  "$python" tools/plot.py "${plot_errors[@]}" "$out" "$png"
  note "QUICK=1: README.md and docs/ left alone; the blocks are in $blocks/, the figures in $png/ ($elapsed min)"
  exit 0
fi

# Replace each block of README.md with its new text (blocks not regenerated stay)
for file in "$blocks"/*.md; do
  name="$(basename "$file" .md)"
  if ! grep -qxF "<!-- figures:$name -->" README.md; then
    note "README.md has no block $name (<!-- figures:$name -->); its text is in $file"
    continue
  fi
  awk -v begin="<!-- figures:$name -->" -v end="<!-- /figures:$name -->" -v file="$file" '
    $0 == begin { print; while ((getline line < file) > 0) print line; skip = 1; next }
    $0 == end { skip = 0 }
    !skip { print }' README.md > README.md.new
  mv README.md.new README.md
done

# ---------------------------------------------------------------- figures
"$python" tools/plot.py "${plot_errors[@]}" "$out" "$png"
echo "figures: README numbers, figures in $png/, tables and CSV files in $out/ (machine: $out/machine.txt; $elapsed min)"
[ "$extreme_status" -eq 0 ] || note "taylorode extreme reported a failed case (see out/extreme.txt and the README)"
# the hand-written paragraphs that quote the blocks: to be re-read
prose="$(grep -nxF '<!-- prose: re-read after make figures -->' README.md | cut -d: -f1 | paste -sd, - || true)"
[ -z "$prose" ] || note "re-read by hand the paragraphs of README.md marked 'prose: re-read after make figures' (line $prose): they quote the blocks"
