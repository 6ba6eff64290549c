#!/usr/bin/env bash
# Checks the layering that ARCHITECTURE.md draws, from the sources themselves:
#   1. every library module lives in src/taylorode/<area>/<topic>.f90 and is named
#      taylorode_<area>_<topic> (facades: src/taylorode.f90, src/taylorode/<area>.f90);
#   2. no module uses a module of an area it may not use (no upward arrow);
#   3. a dependent fpm project that integrates a problem of its own through the
#      facade `taylorode` compiles no test-set, analysis or app module;
#   4. app/main.f90 holds the program and every other file app/<name>.f90 one module
#      app_<name> (never taylorode_*: make install removes the app's modules, and an
#      installation holds the library's modules only);
#   5. the legacy external procedures (src/taylorode/interfaces/legacy_entry.f90) use no
#      module that reaches an IEEE intrinsic module through USE (gfortran would save and
#      restore the floating-point environment around every call of them);
#   6. the installed library (build/install, when there) keeps no local variable in static
#      memory, which calls on separate objects from several threads would share (gfortran
#      12 keeps the length of a deferred-length character function result there, at each
#      call of such a function: the library returns such text through arguments).
# Prints one line per violation and "architecture: ok" when there is none.
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
# the fpm tools/setup.sh installs into .venv when none is on PATH (as make uses it)
if ! command -v fpm >/dev/null 2>&1 && [ -x .venv/bin/fpm ]; then export PATH="$PWD/.venv/bin:$PATH"; fi

# area -> areas it may use (its own area is always allowed)
declare -A may_use=(
  [base]=""
  [linalg]="base"
  [problem]="base linalg"
  [newton]="base linalg problem"
  [schemes]="base linalg problem newton"
  [integrate]="base linalg problem newton schemes"
  [testset]="base linalg problem"
  [analysis]="base linalg problem newton schemes integrate testset"
  [interfaces]="base linalg problem newton schemes integrate"
  [facade]="base linalg problem schemes integrate"
  [facade_testset]="testset"
  [facade_analysis]="analysis"
)
violations=0
complain() { echo "architecture: $*"; violations=$((violations + 1)); }

area_of_module() {  # taylorode_<area>_... -> area; taylorode, taylorode_testset, taylorode_analysis -> facade*
  case "$1" in
    taylorode) echo facade ;;
    taylorode_testset) echo facade_testset ;;
    taylorode_analysis) echo facade_analysis ;;
    taylorode_*) echo "$1" | cut -d_ -f2 ;;
    *) echo external ;;
  esac
}

while IFS= read -r file; do
  rel="${file#src/}"
  case "$rel" in
    taylorode.f90) expected=taylorode ;;
    taylorode/*/*.f90) expected="$(echo "${rel%.f90}" | tr '/' '_')" ;;
    taylorode/*.f90) expected="$(echo "${rel%.f90}" | tr '/' '_')" ;;
    *) complain "$file: not in an area folder"; continue ;;
  esac
  modules="$(grep -ioE '^\s*module\s+[a-z0-9_]+\s*$' "$file" | awk '{print tolower($2)}')"
  if [ "$modules" != "$expected" ]; then
    complain "$file: defines \"$modules\", expected exactly \"$expected\""
  fi
  area="$(area_of_module "$expected")"
  [ -n "${may_use[$area]+set}" ] || { complain "$file: unknown area $area"; continue; }
  for used in $(grep -ioE '^\s*use\s+taylorode[a-z0-9_]*' "$file" | awk '{print tolower($2)}' | sort -u); do
    used_area="$(area_of_module "$used")"
    [ "$used_area" = "$area" ] && continue
    case " ${may_use[$area]} " in
      *" $used_area "*) ;;
      *) complain "$file ($area) uses $used ($used_area)" ;;
    esac
  done
done < <(find src -name '*.f90' | sort)

# The app: one program, and one module per file named after it
while IFS= read -r file; do
  base="$(basename "$file" .f90)"
  modules="$(grep -ioE '^\s*module\s+[a-z0-9_]+\s*$' "$file" | awk '{print tolower($2)}')"
  if [ "$base" = main ]; then
    [ -z "$modules" ] || complain "$file: the program's file defines modules: $(echo $modules)"
    grep -qiE '^\s*program\s+' "$file" || complain "$file: holds no program"
  elif [ "$modules" != "app_$base" ]; then
    complain "$file: defines \"$(echo $modules)\", expected exactly \"app_$base\""
  fi
done < <(find app -name '*.f90' | sort)

# The legacy externals: no module they use reaches an IEEE module (transitively)
reached=() pending=(src/taylorode/interfaces/legacy_entry.f90)
while [ "${#pending[@]}" -gt 0 ]; do
  file="${pending[0]}"; pending=("${pending[@]:1}")
  case " ${reached[*]} " in *" $file "*) continue ;; esac
  reached+=("$file")
  if grep -qiE '^\s*use\s*(,\s*intrinsic\s*::)?\s*ieee_' "$file"; then
    complain "$file uses an IEEE module, and the legacy externals reach it (legacy_entry.f90)"
  fi
  for used in $(grep -ioE '^\s*use\s+taylorode[a-z0-9_]*' "$file" | awk '{print tolower($2)}' | sort -u); do
    rel="$(echo "$used" | sed -E 's/^taylorode_([a-z0-9]+)_/taylorode\/\1\//')"
    [ -f "src/$rel.f90" ] && pending+=("src/$rel.f90")
  done
done

# A dependent project: only what its `use` statements reach is compiled (fpm prunes).
dependent="build/check-architecture/dependent"
rm -rf "$dependent" && mkdir -p "$dependent/app"
cat > "$dependent/fpm.toml" <<TOML
name = "dependent"
[build]
link = ["lapack", "blas"]
[dependencies]
taylorode.path = "../../.."
TOML
mkdir -p "$dependent/src"
cat > "$dependent/src/decay.f90" <<'F90'
module decay
   use taylorode, only: dp, ode_problem_fd
   implicit none
   private
   public :: decay_type
   type, extends(ode_problem_fd) :: decay_type
   contains
      procedure :: f => decay_f
      procedure :: g => decay_g
   end type decay_type
contains
   subroutine decay_f(self, t, u, dudt)
      class(decay_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = -u
   end subroutine decay_f
   subroutine decay_g(self, t, u, dudt)
      class(decay_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = -100.0_dp*u
   end subroutine decay_g
end module decay
F90
cat > "$dependent/app/main.f90" <<'F90'
program dependent
   use taylorode, only: dp, scheme_type, new_scheme, integrate, integrator_options_type, &
      integration_stats_type, status_type
   use decay, only: decay_type
   implicit none
   type(decay_type) :: problem
   class(scheme_type), allocatable :: scheme
   type(integrator_options_type) :: options
   type(integration_stats_type) :: stats
   type(status_type) :: stat
   real(dp) :: u(1)
   u = 1.0_dp
   call new_scheme("i-t-2", scheme, stat)
   call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat)
   if (.not. stat%ok()) error stop 1
   if (abs(u(1) - exp(-101.0_dp)) > 1.0e-6_dp) error stop 2
end program dependent
F90
if ! (cd "$dependent" && fpm build > build.log 2>&1 && fpm run > run.log 2>&1); then
  complain "the dependent project does not build or run (see $dependent/build.log, run.log)"
else
  compiled="$(find "$dependent/build" -path '*taylorode*' -name '*.o' | sed 's#.*/##' | sort)"
  unwanted="$(echo "$compiled" | grep -E 'testset|analysis|app_' || true)"
  if [ -n "$unwanted" ]; then
    complain "the dependent project compiled modules it does not use: $(echo $unwanted)"
  fi
  [ -n "$compiled" ] || complain "the dependent project compiled no taylorode object (cannot check)"
fi

# an installation holds the library's modules only (none of the examples' or the app's)
if [ -d build/install/include ]; then
  foreign="$(find build/install/include -name '*.mod' ! -name 'taylorode*.mod' -printf '%f ')"
  [ -z "$foreign" ] || complain "make install ships modules that are not the library's: $foreign"
fi

# no local static variables in the library (jump tables are read only)
if [ -f build/install/lib/libtaylorode.a ]; then
  shared="$(nm -A build/install/lib/libtaylorode.a 2>/dev/null | \
    awk '$(NF-1) ~ /^[bd]$/ && $NF !~ /^jumptable\./ && $1 ~ /:src_taylorode/ {sub(/:[0-9a-f]+$/, "", $1); print $1 ":" $NF}')"
  [ -z "$shared" ] || complain "static variables in the library, shared between threads: $(echo $shared)"
fi

if [ "$violations" -eq 0 ]; then
  echo "architecture: ok"
else
  echo "architecture: $violations violation(s)"
  exit 1
fi
