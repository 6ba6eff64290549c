#!/usr/bin/env bash
# The API documentation of the library modules (src/) with FORD, into build/docs:
#   bash tools/docs.sh          (make docs)
# FORD $FORD_VERSION is installed from PyPI into the project's virtual environment .venv
# (the one tools/setup.sh uses for fpm) when it is not there yet. Offline, without it,
# this stops with a message and builds nothing. The build fails when a public entity
# of the library has no `!>` comment (tools/doc_coverage.py lists them) or when FORD
# prints a warning.
set -euo pipefail

FORD_VERSION="7.0.13"

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="$root/.venv"
cd "$root"

die() { echo "docs: ERROR: $*" >&2; exit 1; }

# A Python 3 outside .venv that can create a virtual environment with pip
base_python() {
  local py
  for py in $(type -ap python3 2>/dev/null); do
    case "$py" in "$venv"/*) continue ;; esac
    if "$py" -c 'import venv, ensurepip' >/dev/null 2>&1; then echo "$py"; return 0; fi
  done
  return 1
}

ford_version() { "$venv/bin/ford" --version 2>/dev/null | sed -n 's/^ford version \([0-9.]*\).*/\1/p'; }

if [ "$(ford_version || true)" != "$FORD_VERSION" ]; then
  if ! "$venv/bin/python" -c 'import pip' >/dev/null 2>&1; then
    py="$(base_python)" || die "no Python 3 with the venv module on PATH (on Debian: apt-get install python3-venv)"
    rm -rf "$venv"
    "$py" -m venv "$venv" >/dev/null || die "could not create the virtual environment $venv with $py"
  fi
  log="$(mktemp)"
  if ! "$venv/bin/python" -m pip install --quiet --disable-pip-version-check --timeout 20 --retries 1 \
    "ford==$FORD_VERSION" >"$log" 2>&1; then
    tail -n 5 "$log" | sed 's/^/  | /' >&2
    rm -f "$log"
    die "FORD $FORD_VERSION is not in .venv and could not be installed from PyPI (offline?); nothing was built." \
      "Run make docs again when PyPI can be reached, or install it yourself: .venv/bin/python -m pip install ford==$FORD_VERSION"
  fi
  rm -f "$log"
  echo "docs: installed FORD $FORD_VERSION (PyPI) into .venv"
fi

# every public entity documented
"$venv/bin/python" tools/doc_coverage.py ford.md || die "document the entities above with !> comments"

# FORD itself, its warnings kept; the version is fpm.toml's
version="$(sed -n 's/^version = "\(.*\)"/\1/p' fpm.toml)"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
rm -rf build/docs
COLUMNS=200 "$venv/bin/ford" --revision "$version" ford.md >"$log" 2>&1 || { cat "$log" >&2; die "FORD failed"; }
if grep -qi 'warning' "$log"; then
  cat "$log" >&2
  die "FORD printed warnings (above)"
fi
echo "docs: API documentation in build/docs/index.html"
