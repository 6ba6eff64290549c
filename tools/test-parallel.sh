#!/usr/bin/env bash
# Builds one of the packages beside the library and runs its tests on 1 and 2 MPI ranks:
#   bash tools/test-parallel.sh mpi     (mpi/: ensembles over ranks, distributed problems)
#   bash tools/test-parallel.sh petsc   (petsc/: one system over ranks through PETSc)
# Needs what `bash tools/setup.sh mpi` (or `petsc`) installs; `make test-mpi` and
# `make test-petsc` run both. Prints one PASS or FAIL line per test and rank count, and
# "N passed, N failed" last; the exit status is non-zero when a test failed.
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

package="${1:-}"
case "$package" in
  mpi | petsc) ;;
  *) echo "usage: bash tools/test-parallel.sh mpi|petsc" >&2; exit 2 ;;
esac

passed=0
failed=0
pass() { echo "PASS $*"; passed=$((passed + 1)); }
fail() { echo "FAIL $*"; failed=$((failed + 1)); }
finish() {
  echo "$passed passed, $failed failed"
  [ "$failed" -eq 0 ]
  exit $?
}

# Open MPI refuses to start as root unless told; more ranks than cores is allowed; a
# run that hangs (ranks that stopped agreeing) is ended after 10 minutes
if [ "$(id -u)" -eq 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
ranks() { local np="$1"; shift; timeout 600 mpirun --oversubscribe -np "$np" "$@"; }

flags=()
if [ "$package" = petsc ]; then
  # PETSc's Fortran modules and headers, and its library (added to the debug profile's
  # flags; fpm puts link flags before the objects, so the library must not be dropped)
  flags=(--profile debug --flag "$(pkg-config --cflags PETSc) -ffree-line-length-none"
    --link-flag "-Wl,--no-as-needed $(pkg-config --libs PETSc)")
fi
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
if ! (cd "$package" && fpm build --compiler mpif90 --tests "${flags[@]}") > "$log" 2>&1; then
  tail -n 30 "$log"
  fail "$package: build"
  finish
fi
find_program() { find "$package/build" -path "*/$1/$2" -type f -perm -u+x | head -n 1; }

# The test program reports its own PASS and FAIL lines and counts
for np in 1 2; do
  program="$(find_program test "taylorode-$package-test")"
  if [ -z "$program" ]; then fail "$package: test program not built"; finish; fi
  if ! ranks "$np" "$program" > "$log" 2>&1; then :; fi
  while IFS= read -r line; do
    case "$line" in
      "PASS "*) pass "np=$np ${line#PASS }" ;;
      "FAIL "*) fail "np=$np ${line#FAIL }" ;;
    esac
  done < "$log"
  if ! grep -qE '^[0-9]+ passed, [0-9]+ failed$' "$log"; then
    tail -n 20 "$log"
    fail "np=$np: the test program stopped before its summary"
  fi
done

if [ "$package" = mpi ]; then
  # the Van der Pol sweep: the same bytes on 1 and 2 ranks, dynamic and cyclic
  sweep="$(find_program app taylorode-mpi-sweep)"
  out="$(mktemp -d)"
  ranks 1 "$sweep" --members 12 --tend 20 > "$out/1" 2> "$out/err" &&
    ranks 2 "$sweep" --members 12 --tend 20 > "$out/2" 2>> "$out/err" &&
    ranks 2 "$sweep" --members 12 --tend 20 --schedule cyclic > "$out/2c" 2>> "$out/err"
  if [ -s "$out/1" ] && cmp -s "$out/1" "$out/2" && cmp -s "$out/1" "$out/2c" && [ "$(wc -l < "$out/1")" -eq 15 ]; then
    pass "sweep: the same bytes on 1 and 2 ranks, dynamic and cyclic"
  else
    cat "$out/err"
    fail "sweep: the output differs between 1 and 2 ranks (or is missing)"
  fi
  rm -rf "$out"
fi
finish
