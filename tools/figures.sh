#!/usr/bin/env bash
# Produce the CSV files and the README's figures with the release build:
#   bash tools/figures.sh [CSV_DIR] [PNG_DIR]     (defaults: out, docs)
# Needs matplotlib for the pictures (python3 -m pip install matplotlib).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
csv_dir="${1:-out}"
png_dir="${2:-docs}"
mkdir -p "$csv_dir" "$png_dir"
fpm build --profile release
app="$(fpm run --profile release --runner echo | tail -n 1)"
run() { "$app" "$@"; }
for scheme in si-t-1 si-t-2 i-t-1 i-t-2 radau5; do
  run vdp --scheme "$scheme" --history "$csv_dir/vdp_$scheme.csv" --force > "$csv_dir/vdp_$scheme.txt"
done
run table --out "$csv_dir" --force > "$csv_dir/table.txt"
run sweep --tols 1e-3:1e-7 --out "$csv_dir" --force > "$csv_dir/sweep.txt"
run stability --out "$csv_dir" --force > "$csv_dir/stability.txt"
run extreme --out "$csv_dir" --force > "$csv_dir/extreme.txt"
python3 tools/plot.py "$csv_dir" "$png_dir"
echo "figures in $png_dir, tables and CSV files in $csv_dir"
