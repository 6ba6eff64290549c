#!/usr/bin/env bash
# The per-step cost of i-t-2 on the paper's Van der Pol run against a hand-coded floor
# (the same algorithm written out in C, e.g. the peer harness's floor/it2_vdp.c):
#   bash tools/floor.sh [FLOOR.c] [ROUNDS]          (make floor FLOOR=path/to/it2_vdp.c)
# Builds the floor with gcc -O2 and the app in the release profile, then runs them in
# turn ROUNDS times (default 5; floor, taylorode, floor, ...) and prints each round's
# nanoseconds per accepted step and the median ratio taylorode / floor with its range. The floor
# program must print "ns/step(min)=<number>" (it takes a repeat count argument).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
floor_source="${1:-${FLOOR:-../shared/peers/floor/it2_vdp.c}}"
rounds="${2:-5}"
[ -f "$floor_source" ] || { echo "floor: no floor program at $floor_source (give its path)" >&2; exit 2; }
case "$rounds" in ''|*[!0-9]*) echo "floor: ROUNDS must be a whole number" >&2; exit 2 ;; esac

mkdir -p build/floor
gcc -O2 -o build/floor/floor "$floor_source" -lm
fpm build --profile release >/dev/null 2>&1
app="$(fpm run --profile release --runner echo 2>/dev/null | tail -n 1)"

ratios=()
for round in $(seq 1 "$rounds"); do
  floor_ns="$(build/floor/floor 5 | sed -n 's/.*ns\/step(min)=\([0-9.]*\).*/\1/p')"
  ours_us="$("$app" bench --problems vdp-paper --schemes i-t-2 --min-time 0.5 2>/dev/null | \
    awk '$1 == "vdp-paper" { print $(NF - 2) }')"
  ratio="$(awk -v a="$ours_us" -v b="$floor_ns" 'BEGIN { printf "%.2f", 1000 * a / b }')"
  echo "round $round: floor $floor_ns ns/step, taylorode $(awk -v a="$ours_us" 'BEGIN { printf "%.0f", 1000 * a }') ns/step, ratio $ratio"
  ratios+=("$ratio")
done
summary="$(printf '%s\n' "${ratios[@]}" | sort -n | awk '{ v[NR] = $1 }
  END { printf "%.2f (%.2f-%.2f)", (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2, v[1], v[NR] }')"
echo "i-t-2 on the paper's Van der Pol run: median $summary x the floor's time per step ($rounds rounds; their range in parentheses)"
