#!/usr/bin/env bash
# Installs whatever taylorode needs and is missing, then makes sure the test-drive
# dev-dependency is usable. Idempotent: when nothing is missing it prints nothing
# and takes a fraction of a second. It prints one line per thing it installs or
# repairs; a failure stops it with a message starting "setup: ERROR".
#   gfortran, LAPACK, BLAS, git, pkg-config, gcc : Debian packages (apt-get, as root or sudo)
#   fpm 0.12.0                  : the one on PATH if it is 0.12.0, otherwise PyPI's,
#                                 installed into the project's virtual environment
#                                 .venv (the Makefile puts .venv/bin first on PATH)
#   with the argument mpi       : Open MPI (mpif90, mpirun) for the package in mpi/
#   with the argument petsc     : Open MPI and PETSc (petsc-dev) for the package in petsc/
#   test-drive v0.5.0           : fetched by fpm itself when its repository can be
#                                 reached; otherwise our stand-in (tools/testdrive-standin)
#                                 is seeded into build/dependencies/test-drive. A broken
#                                 or missing checkout (e.g. the empty .git an offline fpm
#                                 run leaves behind) is repaired.
set -euo pipefail

FPM_VERSION="0.12.0"

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="$root/.venv"
standin="$root/tools/testdrive-standin"
dep_rel="build/dependencies/test-drive"
dep="$root/$dep_rel"
cache="$root/build/cache.toml"

say() { echo "setup: $*"; }
die() { echo "setup: ERROR: $*" >&2; exit 1; }
# Runs a command with its output kept in a log that is shown only if it fails.
quietly() {
  local log status=0
  log="$(mktemp)"
  "$@" >"$log" 2>&1 || status=$?
  if [ "$status" -ne 0 ]; then
    echo "setup: ERROR: '$*' failed (exit status $status):" >&2
    tail -n 25 "$log" | sed 's/^/  | /' >&2
  fi
  rm -f "$log"
  return "$status"
}

# ---------------------------------------------------------------- Debian packages
apt_updated=0
apt_install() {
  command -v apt-get >/dev/null 2>&1 ||
    die "missing: $*; install them with your system's package manager (this script knows apt-get only)"
  local -a sudo=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null 2>&1 || die "missing: $*; run as root: apt-get install $*"
    sudo=(sudo)
  fi
  if [ "$apt_updated" -eq 0 ]; then
    quietly "${sudo[@]}" apt-get update -qq || die "apt-get update failed (offline?); needed to install: $*"
    apt_updated=1
  fi
  quietly "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" ||
    die "could not install $* with apt-get"
  say "installed $* (apt)"
}

have_lib() { compgen -G "/usr/lib/*/lib$1.so" >/dev/null || compgen -G "/usr/lib/lib$1.so" >/dev/null; }

packages=()
command -v gfortran >/dev/null 2>&1 || packages+=(gfortran)
have_lib lapack || packages+=(liblapack-dev)
have_lib blas || packages+=(libblas-dev)
command -v git >/dev/null 2>&1 || packages+=(git)
# the C, F77 and Python interface tests build against an installation through pkg-config
command -v pkg-config >/dev/null 2>&1 || packages+=(pkg-config)
command -v cc >/dev/null 2>&1 || packages+=(gcc)
# the packages in mpi/ and petsc/, when asked for (bash tools/setup.sh mpi petsc)
for extra in "$@"; do
  case "$extra" in
    mpi | petsc)
      command -v mpif90 >/dev/null 2>&1 && command -v mpirun >/dev/null 2>&1 ||
        packages+=(libopenmpi-dev openmpi-bin)
      if [ "$extra" = petsc ]; then pkg-config --exists PETSc 2>/dev/null || packages+=(petsc-dev); fi ;;
    *) die "unknown argument '$extra' (known: mpi, petsc)" ;;
  esac
done
if [ "${#packages[@]}" -gt 0 ]; then apt_install $(printf '%s\n' "${packages[@]}" | sort -u); fi

# ---------------------------------------------------------------- fpm
fpm_version() { "$1" --version 2>/dev/null | sed -n 's/.*Version: *\([0-9][0-9.]*\).*/\1/p' | sed -n 1p || true; }

# A base Python 3 (not the project's own venv) that can create a virtual environment
# with pip; on Debian that takes the python3-venv package (PEP 668 forbids pip install
# into the system Python, so fpm always goes into the venv).
base_python() {
  local py
  for py in $(type -ap python3 2>/dev/null); do
    case "$py" in "$venv"/*) continue ;; esac
    if "$py" -c 'import venv, ensurepip' >/dev/null 2>&1; then echo "$py"; return 0; fi
  done
  return 1
}

install_fpm() {
  local py
  if ! "$venv/bin/python" -c 'import pip' >/dev/null 2>&1; then
    if ! py="$(base_python)"; then
      if command -v python3 >/dev/null 2>&1; then apt_install python3-venv; else apt_install python3 python3-venv; fi
      py="$(base_python)" || die "no Python 3 with the venv and ensurepip modules found on PATH"
    fi
    rm -rf "$venv"
    quietly "$py" -m venv "$venv" || die "could not create the virtual environment $venv with $py"
  fi
  quietly "$venv/bin/python" -m pip install --quiet --disable-pip-version-check "fpm==$FPM_VERSION" ||
    die "could not install fpm $FPM_VERSION from PyPI into $venv (offline, or PyPI unreachable?)"
  [ "$(fpm_version "$venv/bin/fpm")" = "$FPM_VERSION" ] ||
    die "$venv/bin/fpm does not report version $FPM_VERSION after installation"
  say "installed fpm $FPM_VERSION (PyPI) into .venv; make puts .venv/bin on PATH"
}

if [ "$(fpm_version fpm)" != "$FPM_VERSION" ] && [ "$(fpm_version "$venv/bin/fpm")" != "$FPM_VERSION" ]; then
  install_fpm
fi

# ---------------------------------------------------------------- test-drive
# Where fpm.toml says to fetch it from (the stand-in stands in for v0.5.0)
td_url="$(sed -n 's/^ *test-drive\.git *= *"\(.*\)".*/\1/p' "$root/fpm.toml" | sed -n 1p)"
td_tag="$(sed -n 's/^ *test-drive\.tag *= *"\(.*\)".*/\1/p' "$root/fpm.toml" | sed -n 1p)"
[ -n "$td_url" ] || td_url="https://github.com/fortran-lang/test-drive"
[ -n "$td_tag" ] || td_tag="v0.5.0"

dgit() { git --git-dir="$dep/.git" --work-tree="$dep" "$@"; }

# A checkout fpm can use: a commit checked out (fpm runs `git log -n 1` in it), its
# files as committed, and the manifest of a package named test-drive. fpm's own
# checkout of the real repository has no local tags (it fetches the tag into
# FETCH_HEAD only), so the tag is not required here.
usable() {
  [ -d "$dep/.git" ] && [ -f "$dep/fpm.toml" ] || return 1
  dgit rev-parse -q --verify 'HEAD^{commit}' >/dev/null 2>&1 || return 1
  dgit diff --quiet HEAD -- >/dev/null 2>&1 || return 1
  grep -Eq '^name *= *"test-drive"' "$dep/fpm.toml" || return 1
  grep -Eiqs '^ *module +testdrive *(!.*)?$' "$dep"/src/*.[fF]90
}
is_standin() { [ "$(dgit log -1 --format=%s 2>/dev/null || true)" = "test-drive API stand-in (taylorode)" ]; }
standin_current() { diff -rq --exclude=.git "$standin" "$dep" >/dev/null 2>&1; }
reachable() { GIT_TERMINAL_PROMPT=0 timeout 20 git ls-remote --tags "$td_url" "$td_tag" >/dev/null 2>&1; }

# fpm's record of the dependency (build/cache.toml), "key=value" per line
cached_entry() {
  [ -f "$cache" ] || return 0
  awk '/^\[/ { in_td = ($0 == "[test-drive]"); next }
       in_td && /=/ { k = $1; v = $0; sub(/^[^=]*= *"?/, "", v); sub(/"? *$/, "", v); print k "=" v }' "$cache"
}
# fpm re-fetches when its record names another repository or tag than fpm.toml, and
# fails outright when the record points at a checkout that is gone; dropping the
# record makes it take the checkout in build/dependencies as it is.
cache_agrees() {
  local entry
  entry="$(cached_entry)"
  [ -z "$entry" ] && return 0
  grep -qxF "git=$td_url" <<<"$entry" && grep -qxF "obj=$td_tag" <<<"$entry" &&
    grep -qxF "proj-dir=$dep_rel" <<<"$entry"
}
forget_cached_entry() { rm -f "$cache"; }

seed_standin() {
  local tmp
  mkdir -p "$(dirname "$dep")"
  tmp="$(mktemp -d "$dep.seed.XXXXXX")"
  cp -R "$standin/." "$tmp/"
  (
    cd "$tmp"
    export GIT_AUTHOR_NAME="taylorode setup" GIT_AUTHOR_EMAIL="setup@taylorode.invalid"
    export GIT_COMMITTER_NAME="$GIT_AUTHOR_NAME" GIT_COMMITTER_EMAIL="$GIT_AUTHOR_EMAIL"
    export GIT_AUTHOR_DATE="2000-01-01T00:00:00Z" GIT_COMMITTER_DATE="2000-01-01T00:00:00Z"
    git -c init.defaultBranch=main init -q
    git add -A
    git -c commit.gpgsign=false commit -q --no-verify -m "test-drive API stand-in (taylorode)"
    git -c tag.gpgsign=false tag "$td_tag"
  ) >/dev/null 2>&1 || { rm -rf "$tmp"; die "could not create the git repository of the test-drive stand-in"; }
  rm -rf "$dep"
  mv "$tmp" "$dep"
  forget_cached_entry
}

if usable; then
  if is_standin && ! standin_current; then
    seed_standin
    say "updated the test-drive stand-in in $dep_rel (tools/testdrive-standin changed)"
  elif ! cache_agrees; then
    if reachable; then
      :   # fpm fetches the tag fpm.toml asks for
    elif ! is_standin; then
      seed_standin
      say "fpm.toml asks for test-drive $td_tag, unreachable; seeded the stand-in into $dep_rel"
    else
      forget_cached_entry
      say "dropped fpm's stale record of test-drive (build/cache.toml); it re-reads $dep_rel"
    fi
  fi
else
  broken=0
  [ -e "$dep" ] && broken=1
  rm -rf "$dep"
  forget_cached_entry
  if reachable; then
    [ "$broken" -eq 0 ] || say "removed a broken $dep_rel; fpm fetches test-drive $td_tag itself"
  else
    seed_standin
    if [ "$broken" -eq 1 ]; then
      say "$dep_rel was broken and test-drive is unreachable: seeded the stand-in (tools/testdrive-standin)"
    else
      say "test-drive is unreachable: seeded the stand-in (tools/testdrive-standin) into $dep_rel"
    fi
  fi
fi
