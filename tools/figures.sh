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
# earlier numbers and their own date line.
# CPU times depend on the machine and on whatever else runs: use a quiet machine.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
out="out"
png="docs"
blocks="$out/blocks"
mkdir -p "$out" "$png" "$blocks"
note() { echo "figures: $*" >&2; }

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
echo "figures: running the app ($app); about two minutes" >&2
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
fpm run --profile release --example convergence_study 2>/dev/null > "$out/convergence_study.txt"
if [ "${FULL:-0}" = 1 ]; then
  echo "figures: FULL=1: table --full (a few minutes)" >&2
  mkdir -p "$out/full"
  run table --full --out "$out/full" --force > "$out/full/table.txt"
fi

# Hook for the performance numbers: the `bench` command is being rewritten; once it
# has --csv its output fills the README's block "performance".
if run bench --help 2>/dev/null | grep -q -- '--csv'; then
  run bench --csv "$out/bench.csv" > "$out/bench.txt"
  { echo "$stamp"; echo; echo '```'; cat "$out/bench.txt"; echo '```'; } > "$blocks/performance.md"
else
  note "this taylorode has no 'bench --csv': the README's performance block is left as it is"
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
python=""
for candidate in .venv/bin/python python3; do
  if "$candidate" -c 'import matplotlib' >/dev/null 2>&1; then python="$candidate"; break; fi
done
if [ -z "$python" ]; then
  note "no Python with matplotlib: numbers regenerated, figures not (python3 -m pip install matplotlib)"
  exit 1
fi
"$python" tools/plot.py "$out" "$png"
echo "figures: README numbers, figures in $png/, tables and CSV files in $out/ (machine: $out/machine.txt)"
[ "$extreme_status" -eq 0 ] || note "taylorode extreme reported a failed case (see out/extreme.txt and the README)"
