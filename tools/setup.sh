#!/usr/bin/env bash
# Installs the taylorode toolchain on a fresh Debian machine and makes the
# test-drive dev-dependency resolvable, online or offline.
#   gfortran, LAPACK, BLAS : Debian packages
#   fpm                    : PyPI, pinned
#   test-drive             : fetched by fpm when its repository is reachable;
#                            otherwise our API-compatible stand-in is seeded
#                            into build/dependencies/test-drive.
set -euo pipefail

FPM_VERSION="0.12.0"
TESTDRIVE_URL="https://github.com/fortran-lang/test-drive"
TESTDRIVE_TAG="v0.5.0"

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

have_lib() { compgen -G "/usr/lib/*/lib$1.so" >/dev/null || compgen -G "/usr/lib/lib$1.so" >/dev/null; }
if ! command -v gfortran >/dev/null 2>&1 || ! have_lib lapack || ! have_lib blas; then
  as_root apt-get update -qq
  DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -qq gfortran liblapack-dev libblas-dev >/dev/null
fi

installed_fpm="$(fpm --version 2>/dev/null | sed -n 's/.*Version: *\([0-9.]*\).*/\1/p' | sed -n 1p || true)"
if [ "$installed_fpm" != "$FPM_VERSION" ]; then
  python3 -m pip install --quiet --disable-pip-version-check "fpm==${FPM_VERSION}"
  if command -v pyenv >/dev/null 2>&1; then pyenv rehash; fi
fi
if ! command -v fpm >/dev/null 2>&1; then
  echo "setup: fpm was installed but is not on PATH; add $(python3 -m site --user-base)/bin to PATH" >&2
  exit 1
fi

# test-drive: the real one when its repository answers, our stand-in otherwise.
dep="$root/build/dependencies/test-drive"
if [ -d "$dep/.git" ]; then
  echo "setup: test-drive already present in build/dependencies"
elif timeout 20 git ls-remote --tags "$TESTDRIVE_URL" "$TESTDRIVE_TAG" >/dev/null 2>&1; then
  echo "setup: test-drive repository reachable; fpm fetches ${TESTDRIVE_TAG} itself"
else
  echo "setup: test-drive repository unreachable; seeding the stand-in from tools/testdrive-standin"
  rm -rf "$dep"
  mkdir -p "$dep"
  cp -R "$root/tools/testdrive-standin/." "$dep/"
  (
    cd "$dep"
    git init -q
    git config user.email "setup@taylorode.invalid"
    git config user.name "taylorode setup"
    git add -A
    git commit -q -m "test-drive API stand-in (taylorode)"
    git tag "$TESTDRIVE_TAG"
    git remote add origin "$TESTDRIVE_URL"
  )
fi

gfortran --version | sed -n 1p
fpm --version | sed -n 1p
