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
# CPU times depend on the machine and on whatever else runs: use a quiet machine.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
out="out"
png="docs"
blocks="$out/blocks"
mkdir -p "$out" "$png" "$blocks"
note() { echo "figures: $*" >&2; }

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
{
  echo "| | |"
  echo "|---|---|"
  sed 's/^\([^:]*\): \(.*\)$/| \1 | \2 |/' "$out/machine.txt"
} > "$blocks/machine.md"

# ---------------------------------------------------------------- runs
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
extreme_status=0
run extreme --out "$out" --force > "$out/extreme.txt" 2>/dev/null || extreme_status=$?
run accuracy --out "$out" --force > "$out/accuracy.txt"
fpm run --profile release --example convergence_study 2>/dev/null > "$out/convergence_study.txt"
if [ "${FULL:-0}" = 1 ]; then
  echo "figures: FULL=1: table --full (a few minutes)" >&2
  mkdir -p "$out/full"
  run table --full --out "$out/full" --force > "$out/full/table.txt"
fi

# ---------------------------------------------------------------- performance
# taylorode's bench on the peer harness's problems; with PEERS=<the peer harness's
# folder> (its sundials_bench built, its refs/) the peers run on the same problems in
# this same run, their references are used, tools/plot.py draws everyone's work-precision
# curves (the harness's report.py reads the same files into out/report) and
# tools/ratios.py the CPU ratios at equal error. FLOOR=<it2_vdp.c> adds
# the per-step comparison with the hand-coded floor.
peers="${PEERS:-}"
refs=()
if [ -n "$peers" ]; then
  [ -x "$peers/sundials_bench" ] || { note "ERROR: PEERS=$peers has no built sundials_bench"; exit 1; }
  refs=(--refs "$peers/refs")
  for n in 1000 10000 100000; do
    [ -s "$peers/refs/bs$n.csv" ] || "$peers/sundials_bench" ref cvode_bdf "bs$n" 1e-13 1e-15 > "$peers/refs/bs$n.csv"
  done
fi
echo "figures: bench (about ten minutes)" >&2
small="vdp1e3_wp,vdp1e3_up,rober40,rober1e11,hires,orego,e5,bruss32,bruss512"
large="bs1000,bs10000"
run bench --problems "vdp-paper,$small" --schemes si-t-2,i-t-2,imex-rk21,radau5 --tols 1e-3:1e-8 "${refs[@]}" \
  --csv "$out/bench_small.csv" --force > "$out/bench_small.txt"
run bench --problems "$small" --schemes si-t-2,i-t-2 --tols 1e-3:1e-8 --estimate embedded "${refs[@]}" \
  --csv "$out/bench_embedded.csv" --force > "$out/bench_embedded.txt"
# si-t-2 with step doubling, beside its default (the estimate of its own step's error)
run bench --problems "$small,$large" --schemes si-t-2 --tols 1e-3:1e-6 --estimate doubling "${refs[@]}" \
  --csv "$out/bench_doubling.csv" --force > "$out/bench_doubling.txt"
run bench --problems "$large" --schemes si-t-2,i-t-2,imex-rk21,radau5 --tols 1e-3:1e-6 "${refs[@]}" \
  --csv "$out/bench_large.csv" --force > "$out/bench_large.txt"
/usr/bin/env time -v "$app" bench --problems bs100000 --schemes si-t-2 --tols 1e-3:1e-5 --min-time 0.01 "${refs[@]}" \
  --csv "$out/bench_huge.csv" --force > "$out/bench_huge.txt" 2> "$out/bench_huge.time" ||
  run bench --problems bs100000 --schemes si-t-2 --tols 1e-3:1e-5 --min-time 0.01 "${refs[@]}" \
    --csv "$out/bench_huge.csv" --force > "$out/bench_huge.txt"
ours=("$out/bench_small.csv" "$out/bench_embedded.csv" "$out/bench_doubling.csv" "$out/bench_large.csv" \
  "$out/bench_huge.csv")
{
  echo "$stamp"
  echo
  echo '```'
  grep -vE '^(wrote|peak) ' "$out/bench_small.txt"
  grep -E '^(bs|problem)' "$out/bench_large.txt" | grep -v '^problem'
  grep -E '^bs' "$out/bench_huge.txt"
  echo '```'
  memory="$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$out/bench_huge.time" 2>/dev/null || true)"
  [ -z "$memory" ] || echo "Peak memory of the bs100000 run (si-t-2, 200,000 unknowns): $((memory / 1024)) MiB."
} > "$blocks/performance.md"
if [ -n "$peers" ]; then
  echo "figures: the peers on the same problems (about ten minutes)" >&2
  "$peers/sundials_bench" bench -p "$small" -s cvode_bdf,ark_imex3 -t 1e-3,1e-4,1e-5,1e-6,1e-7,1e-8 -m 0.2 -B 60 \
    -r "$peers/refs" > "$out/peers_small.csv"
  "$peers/sundials_bench" bench -p "$large,bs100000" -s cvode_bdf -t 1e-3,1e-4,1e-5,1e-6 -m 0.2 -B 60 \
    -r "$peers/refs" > "$out/peers_large.csv"
  /usr/bin/env time -v "$peers/sundials_bench" bench -p bs100000 -s cvode_bdf -t 1e-4 -m 0.01 -r "$peers/refs" \
    > /dev/null 2> "$out/peers_huge.time" || true
  # the harness's own report reads the same CSV files (out/report); the README's figures
  # beside the peers come from tools/plot.py below, which tells the peers from the schemes
  "$python" "$peers/report.py" -o "$out/report" "$out/peers_small.csv" "$out/peers_large.csv" "${ours[@]}" >/dev/null
  {
    echo "$stamp"
    echo
    echo "CPU time against CVODE (BDF, band solver on the Brusselator) at equal error, median over the runs"
    echo "with error >= 1e-4 (below 1: faster; in parentheses the number of runs compared):"
    echo
    python3 tools/ratios.py --min-error 1e-4 "$out/peers_small.csv" "$out/peers_large.csv" "${ours[@]}"
    memory="$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$out/peers_huge.time" 2>/dev/null || true)"
    [ -z "$memory" ] || { echo; echo "Peak memory of CVODE on bs100000: $((memory / 1024)) MiB."; }
  } > "$blocks/peers.md"
fi
if [ -n "${FLOOR:-}" ]; then
  { echo "$stamp"; echo; echo '```'; bash tools/floor.sh "$FLOOR" 5; echo '```'; } > "$blocks/floor.md"
fi

# ---------------------------------------------------------------- README blocks
# 1234567 -> 1,234,567
thousands='function th(n,  s) { s = sprintf("%d", n); while (s ~ /[0-9][0-9][0-9][0-9]/) sub(/[0-9][0-9][0-9]($|,)/, ",&", s); return s }'

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
"$python" tools/plot.py "$out" "$png"
echo "figures: README numbers, figures in $png/, tables and CSV files in $out/ (machine: $out/machine.txt)"
[ "$extreme_status" -eq 0 ] || note "taylorode extreme reported a failed case (see out/extreme.txt and the README)"
