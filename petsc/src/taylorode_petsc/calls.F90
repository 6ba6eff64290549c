#include <petsc/finclude/petscts.h>
#include <petsc/finclude/petscdmda.h>
!> Every call into PETSc of this package, and nothing else: the other modules see
!> Fortran arrays and the types below, never a PETSc object. Written for PETSc 3.18
!> (Debian 12); PETSc 3.23 rewrote its Fortran interface, and a newer PETSc means
!> rewriting this module alone.
!>
!> What it offers:
!> - `grid_type`: a 2D structured grid (a DMDA, one unknown per point, a five-point
!>   stencil) distributed over the ranks, with the exchange of ghost values, sums and
!>   maxima over the ranks, and the whole field gathered in natural order;
!> - `krylov_type`: GMRES on an operator applied through Fortran (matrix-free) with a
!>   preconditioner P = a I - c J assembled from a five-point stencil J, applied as one
!>   algebraic multigrid cycle (GAMG) per factor of P^k;
!> - `register_imex_tables` and `run_arkimex`: Butcher tables of this library
!>   registered with TSARKIMEXRegister, and PETSc's adaptive TS running them on a
!>   split problem (g in TSSetIFunction as U' - g, f in TSSetRHSFunction).
!>
!> PETSc calls Fortran back (shell matrix, shell preconditioner, TS functions) without
!> a way to carry a Fortran object; the object in use is recorded in this module for
!> the length of one solve (one solve at a time per process, as PETSc itself).
module taylorode_petsc_calls
   use petscts
   use petscdmda
   use, intrinsic :: iso_c_binding, only: c_int, c_double, c_char, c_null_char
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_status, status_ok, status_invalid_argument, &
      status_newton_not_converged
   implicit none
   private

   public :: petsc_start, petsc_stop, petsc_ranks
   public :: grid_type, new_grid, stencil_west, stencil_east, stencil_south, stencil_north, stencil_center
   public :: operator_type, krylov_type
   public :: split_system_type, arkimex_stats_type, register_imex_tables, run_arkimex
   public :: table_imex_rk21, table_si_t_1
   public :: grid_sum, grid_max

   !> Rows of a five-point stencil: the point itself and its four neighbours
   integer, parameter :: stencil_center = 1, stencil_west = 2, stencil_east = 3, stencil_south = 4, &
      stencil_north = 5
   !> `grid_reduce` operations
   integer, parameter :: grid_sum = 1, grid_max = 2
   !> Names of the ARKIMEX tables this module registers
   character(len=*), parameter :: table_imex_rk21 = "taylorode-imex-rk21", table_si_t_1 = "taylorode-si-t-1"

   !> A 2D grid of nx x ny interior points distributed over the ranks; this rank owns
   !> the points (i, j), i = xs .. xs + xm - 1, j = ys .. ys + ym - 1 (0-based, x
   !> fastest), and its ghosted rectangle starts at (gxs, gys) with gxm x gym points
   type :: grid_type
      !> Interior points in x and y
      integer :: nx = 0, ny = 0
      !> Owned rectangle: first point and extent
      integer :: xs = 0, ys = 0, xm = 0, ym = 0
      !> Owned rectangle with its ghost layer (clipped at the boundary)
      integer :: gxs = 0, gys = 0, gxm = 0, gym = 0
      !> Owned points (xm ym) and points over all ranks (nx ny)
      integer :: owned = 0, points = 0
      !> This rank and the number of ranks of the grid
      integer :: rank = 0, ranks = 1
      !> Whether the PETSc objects exist
      logical :: created = .false.
      DM, private :: da
      Vec, private :: global, local
      MPI_Comm, private :: comm
   contains
      !> Owned values to owned-plus-ghost values (neighbours' values from their ranks)
      procedure :: exchange
      !> The whole field in natural order (index i + nx j + 1) on every rank
      procedure :: gather
      !> Sum or maximum of values over the ranks of the grid
      procedure :: reduce_values
      !> Release the PETSc objects
      procedure :: destroy => destroy_grid
   end type grid_type

   !> A linear operator applied by Fortran code to this rank's part of a vector
   type, abstract :: operator_type
   contains
      !> y = A x
      procedure(apply_interface), deferred :: apply
   end type operator_type

   !> GMRES with a matrix-free operator and an assembled, multigrid-applied preconditioner
   type :: krylov_type
      !> Whether the PETSc objects exist
      logical :: created = .false.
      !> Factors of the preconditioner: P^cycles, each inverted by one GAMG cycle
      integer :: cycles = 1
      !> Krylov iterations of the last solve and of all solves
      integer :: iterations = 0
      integer :: total_iterations = 0
      Mat, private :: shell, preconditioner
      KSP, private :: ksp
      PC, private :: multigrid
      Vec, private :: x, b, between
      real(dp), allocatable, private :: x_work(:), y_work(:)
   contains
      !> Create the solver for the grid's layout
      procedure :: create => create_krylov
      !> Assemble P = diagonal I - scale J from J's stencil and set up its multigrid
      procedure :: set_preconditioner
      !> Solve A x = b (x holds the initial guess) to a relative residual rtol
      procedure :: solve => krylov_solve
      !> Release the PETSc objects
      procedure :: destroy => destroy_krylov
   end type krylov_type

   !> A split system for PETSc's TS: U' = f(t, U) + g(t, U), g with a five-point Jacobian
   type, abstract :: split_system_type
   contains
      !> f(t, u), the non-stiff part
      procedure(part_interface), deferred :: nonstiff
      !> g(t, u), the stiff part
      procedure(part_interface), deferred :: stiff
      !> The five-point stencil of dg/dU at (t, u) for every owned point
      procedure(stencil_interface), deferred :: stiff_stencil
   end type split_system_type

   !> What a TS run did
   type :: arkimex_stats_type
      !> Accepted steps and rejected ones
      integer :: steps = 0, rejected = 0
      !> Newton iterations (SNES) and Krylov iterations over the run
      integer :: nonlinear_iterations = 0, linear_iterations = 0
   end type arkimex_stats_type

   abstract interface
      !> y = A x on this rank's parts.
      subroutine apply_interface(self, x, y)
         import :: operator_type, dp
         class(operator_type), intent(inout) :: self
         real(dp), intent(in) :: x(:)
         real(dp), intent(out) :: y(:)
      end subroutine apply_interface

      !> One part of the right-hand side on this rank's points.
      subroutine part_interface(self, t, u, dudt)
         import :: split_system_type, dp
         class(split_system_type), intent(inout) :: self
         real(dp), intent(in) :: t, u(:)
         real(dp), intent(out) :: dudt(:)
      end subroutine part_interface

      !> stencil(:, p): the coefficients (stencil_center, _west, _east, _south, _north)
      !> of row p of the Jacobian at (t, u).
      subroutine stencil_interface(self, t, u, stencil)
         import :: split_system_type, dp
         class(split_system_type), intent(inout) :: self
         real(dp), intent(in) :: t, u(:)
         real(dp), intent(out) :: stencil(:, :)
      end subroutine stencil_interface
   end interface

   interface
      !> PETSc's TSARKIMEXRegister (C; PetscInt is a C int in this PETSc build)
      function arkimex_register(name, order, stages, at, bt, ct, a, b, c, bembedt, bembed, pinterp, binterpt, &
         binterp) result(error) bind(C, name="TSARKIMEXRegister")
         import :: c_int, c_double, c_char
         character(kind=c_char), intent(in) :: name(*)
         integer(c_int), value :: order, stages, pinterp
         real(c_double), intent(in) :: at(*), bt(*), ct(*), a(*), b(*), c(*), bembedt(*), bembed(*), binterpt(*), &
            binterp(*)
         integer(c_int) :: error
      end function arkimex_register
   end interface

   !> The operator and solver of the Krylov solve in progress (see the module's comment)
   class(operator_type), pointer :: active_operator => null()
   type(krylov_type), pointer :: active_krylov => null()
   !> The split system and grid of the TS run in progress
   class(split_system_type), pointer :: active_system => null()
   type(grid_type), pointer :: active_grid => null()
   !> Work arrays of the TS callbacks
   real(dp), allocatable :: ts_u(:), ts_f(:), ts_stencil(:, :)
   !> Whether this process registered the tables
   logical :: tables_registered = .false.

contains

   ! ---------------------------------------------------------------- start, stop

   !> PetscInitialize (MPI too, unless it is running already).
   subroutine petsc_start(stat)
      !> Outcome
      type(status_type), intent(out) :: stat
      PetscErrorCode :: ierr
      call PetscInitialize(PETSC_NULL_CHARACTER, ierr)
      if (ierr /= 0) call set_status(stat, status_invalid_argument, "petsc: PetscInitialize failed")
   end subroutine petsc_start

   !> PetscFinalize.
   subroutine petsc_stop()
      PetscErrorCode :: ierr
      call PetscFinalize(ierr)
   end subroutine petsc_stop

   !> The number of ranks of PETSC_COMM_WORLD.
   integer function petsc_ranks()
      PetscErrorCode :: ierr
      PetscMPIInt :: ranks
      call MPI_Comm_size(PETSC_COMM_WORLD, ranks, ierr)
      petsc_ranks = ranks
   end function petsc_ranks

   !> A failed PETSc call (ierr /= 0) into stat; true when it failed.
   logical function failed(ierr, what, stat)
      PetscErrorCode, intent(in) :: ierr
      character(len=*), intent(in) :: what
      type(status_type), intent(inout) :: stat
      failed = ierr /= 0
      if (failed) call set_status(stat, status_invalid_argument, "petsc: "//what//" failed")
   end function failed

   ! ---------------------------------------------------------------- grid

   !> A grid of nx x ny interior points over every rank (alone = .false.) or over this
   !> rank alone (alone = .true.: the whole grid in natural order, as one process has it).
   subroutine new_grid(grid, nx, ny, alone, stat)
      !> The grid
      type(grid_type), intent(inout) :: grid
      !> Interior points in x and y (>= 3)
      integer, intent(in) :: nx, ny
      !> This rank alone
      logical, intent(in) :: alone
      !> Outcome
      type(status_type), intent(out) :: stat
      PetscErrorCode :: ierr
      PetscInt :: xs, ys, zs, xm, ym, zm, points_x, points_y
      PetscMPIInt :: rank, ranks
      if (nx < 3 .or. ny < 3) then
         call set_status(stat, status_invalid_argument, "grid: at least 3 x 3 points")
         return
      end if
      call grid%destroy()
      grid%comm = PETSC_COMM_WORLD
      if (alone) grid%comm = PETSC_COMM_SELF
      points_x = nx
      points_y = ny
      call DMDACreate2d(grid%comm, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DMDA_STENCIL_STAR, points_x, points_y, &
         PETSC_DECIDE, PETSC_DECIDE, 1, 1, PETSC_NULL_INTEGER, PETSC_NULL_INTEGER, grid%da, ierr)
      if (failed(ierr, "DMDACreate2d", stat)) return
      call DMSetUp(grid%da, ierr)
      if (failed(ierr, "DMSetUp", stat)) return
      call DMCreateGlobalVector(grid%da, grid%global, ierr)
      if (failed(ierr, "DMCreateGlobalVector", stat)) return
      call DMCreateLocalVector(grid%da, grid%local, ierr)
      if (failed(ierr, "DMCreateLocalVector", stat)) return
      call DMDAGetCorners(grid%da, xs, ys, zs, xm, ym, zm, ierr)
      grid%xs = xs
      grid%ys = ys
      grid%xm = xm
      grid%ym = ym
      call DMDAGetGhostCorners(grid%da, xs, ys, zs, xm, ym, zm, ierr)
      grid%gxs = xs
      grid%gys = ys
      grid%gxm = xm
      grid%gym = ym
      call MPI_Comm_rank(grid%comm, rank, ierr)
      call MPI_Comm_size(grid%comm, ranks, ierr)
      grid%rank = rank
      grid%ranks = ranks
      grid%nx = nx
      grid%ny = ny
      grid%owned = grid%xm*grid%ym
      grid%points = nx*ny
      grid%created = .true.
   end subroutine new_grid

   !> ghosted(:) (gxm gym values) from owned(:) (xm ym values): this rank's values and
   !> its neighbours' next to its rectangle.
   subroutine exchange(self, owned, ghosted)
      !> The grid
      class(grid_type), intent(inout) :: self
      !> Values at the owned points
      real(dp), intent(in) :: owned(:)
      !> Values at the owned and ghost points
      real(dp), intent(out) :: ghosted(:)
      PetscErrorCode :: ierr
      PetscScalar, pointer :: values(:)
      call VecGetArrayF90(self%global, values, ierr)
      values = owned
      call VecRestoreArrayF90(self%global, values, ierr)
      call DMGlobalToLocalBegin(self%da, self%global, INSERT_VALUES, self%local, ierr)
      call DMGlobalToLocalEnd(self%da, self%global, INSERT_VALUES, self%local, ierr)
      call VecGetArrayReadF90(self%local, values, ierr)
      ghosted = values
      call VecRestoreArrayReadF90(self%local, values, ierr)
   end subroutine exchange

   !> The whole field on every rank, in natural order (point (i, j) at i + nx j + 1).
   subroutine gather(self, owned, whole)
      !> The grid
      class(grid_type), intent(inout) :: self
      !> Values at the owned points
      real(dp), intent(in) :: owned(:)
      !> Values at every point, size nx ny
      real(dp), intent(out) :: whole(:)
      integer :: i, j
      whole = 0.0_dp
      do j = 0, self%ym - 1
         do i = 0, self%xm - 1
            whole(self%xs + i + self%nx*(self%ys + j) + 1) = owned(i + self%xm*j + 1)
         end do
      end do
      call self%reduce_values(grid_sum, whole)
   end subroutine gather

   !> values combined over the ranks of the grid (grid_sum or grid_max), in place.
   subroutine reduce_values(self, operation, values)
      !> The grid
      class(grid_type), intent(in) :: self
      !> grid_sum or grid_max
      integer, intent(in) :: operation
      !> This rank's values on entry, the combined ones on exit
      real(dp), intent(inout) :: values(:)
      PetscErrorCode :: ierr
      integer :: count
      count = size(values)
      if (self%ranks == 1) return
      if (operation == grid_sum) then
         call MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE_PRECISION, MPI_SUM, self%comm, ierr)
      else
         call MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE_PRECISION, MPI_MAX, self%comm, ierr)
      end if
   end subroutine reduce_values

   !> Release the grid's PETSc objects.
   subroutine destroy_grid(self)
      !> The grid
      class(grid_type), intent(inout) :: self
      PetscErrorCode :: ierr
      if (.not. self%created) return
      call VecDestroy(self%global, ierr)
      call VecDestroy(self%local, ierr)
      call DMDestroy(self%da, ierr)
      self%created = .false.
   end subroutine destroy_grid

   !> Assemble matrix = diagonal I - scale J from J's stencil (stencil(:, p) for owned
   !> point p; neighbours outside the grid are left out).
   subroutine assemble_stencil(grid, matrix, diagonal, scale, stencil, stat)
      type(grid_type), intent(in) :: grid
      Mat, intent(inout) :: matrix
      real(dp), intent(in) :: diagonal, scale
      real(dp), intent(in) :: stencil(:, :)
      type(status_type), intent(inout) :: stat
      PetscErrorCode :: ierr
      MatStencil :: row(4), columns(4, 5)
      PetscScalar :: entries(5)
      PetscInt :: count
      integer :: i, j, p
      call MatZeroEntries(matrix, ierr)
      do j = grid%ys, grid%ys + grid%ym - 1
         do i = grid%xs, grid%xs + grid%xm - 1
            p = (i - grid%xs) + grid%xm*(j - grid%ys) + 1
            row = 0
            row(MatStencil_i) = i
            row(MatStencil_j) = j
            count = 1
            columns = 0
            columns(MatStencil_i, 1) = i
            columns(MatStencil_j, 1) = j
            entries(1) = diagonal - scale*stencil(stencil_center, p)
            call add_neighbour(i > 0, i - 1, j, stencil(stencil_west, p))
            call add_neighbour(i < grid%nx - 1, i + 1, j, stencil(stencil_east, p))
            call add_neighbour(j > 0, i, j - 1, stencil(stencil_south, p))
            call add_neighbour(j < grid%ny - 1, i, j + 1, stencil(stencil_north, p))
            call MatSetValuesStencil(matrix, 1, row, count, columns, entries, INSERT_VALUES, ierr)
            if (failed(ierr, "MatSetValuesStencil", stat)) return
         end do
      end do
      call MatAssemblyBegin(matrix, MAT_FINAL_ASSEMBLY, ierr)
      call MatAssemblyEnd(matrix, MAT_FINAL_ASSEMBLY, ierr)
      if (failed(ierr, "MatAssemblyEnd", stat)) return
   contains
      subroutine add_neighbour(inside, ni, nj, coefficient)
         logical, intent(in) :: inside
         integer, intent(in) :: ni, nj
         real(dp), intent(in) :: coefficient
         if (.not. inside) return
         count = count + 1
         columns(MatStencil_i, count) = ni
         columns(MatStencil_j, count) = nj
         entries(count) = -scale*coefficient
      end subroutine add_neighbour
   end subroutine assemble_stencil

   ! ---------------------------------------------------------------- Krylov solver

   !> GMRES for the grid's layout: a shell matrix that calls the operator of the solve,
   !> a preconditioner matrix with the grid's five-point pattern and its GAMG, which
   !> rebuilds its interpolation for every new matrix (kept across changing step sizes it
   !> makes the iteration diverge).
   subroutine create_krylov(self, grid, stat)
      !> The solver
      class(krylov_type), intent(inout) :: self
      !> The grid of the unknowns
      type(grid_type), intent(in) :: grid
      !> Outcome
      type(status_type), intent(out) :: stat
      PetscErrorCode :: ierr
      PetscInt :: owned, points
      PC :: outer
      integer :: no_context
      call self%destroy()
      owned = grid%owned
      points = grid%points
      no_context = 0
      call MatCreateShell(grid%comm, owned, owned, points, points, no_context, self%shell, ierr)
      if (failed(ierr, "MatCreateShell", stat)) return
      call MatShellSetOperation(self%shell, MATOP_MULT, shell_multiply, ierr)
      if (failed(ierr, "MatShellSetOperation", stat)) return
      call DMCreateMatrix(grid%da, self%preconditioner, ierr)
      if (failed(ierr, "DMCreateMatrix", stat)) return
      call DMCreateGlobalVector(grid%da, self%x, ierr)
      call DMCreateGlobalVector(grid%da, self%b, ierr)
      call DMCreateGlobalVector(grid%da, self%between, ierr)
      call KSPCreate(grid%comm, self%ksp, ierr)
      if (failed(ierr, "KSPCreate", stat)) return
      call KSPSetType(self%ksp, KSPGMRES, ierr)
      call KSPSetOperators(self%ksp, self%shell, self%preconditioner, ierr)
      call KSPSetInitialGuessNonzero(self%ksp, PETSC_TRUE, ierr)
      call KSPGetPC(self%ksp, outer, ierr)
      call PCSetType(outer, PCSHELL, ierr)
      call PCShellSetApply(outer, shell_precondition, ierr)
      if (failed(ierr, "PCShellSetApply", stat)) return
      call PCCreate(grid%comm, self%multigrid, ierr)
      call PCSetType(self%multigrid, PCGAMG, ierr)
      call PCGAMGSetReuseInterpolation(self%multigrid, PETSC_FALSE, ierr)
      if (failed(ierr, "PCGAMGSetReuseInterpolation", stat)) return
      call PCSetOperators(self%multigrid, self%preconditioner, self%preconditioner, ierr)
      call KSPSetFromOptions(self%ksp, ierr)
      if (failed(ierr, "KSPSetFromOptions", stat)) return
      allocate (self%x_work(grid%owned), self%y_work(grid%owned))
      self%created = .true.
   end subroutine create_krylov

   !> P = diagonal I - scale J, J from its stencil at every owned point; the
   !> preconditioner applies P^(-1) `cycles` times, each by one GAMG cycle (a
   !> preconditioner for the product of `cycles` equal factors).
   subroutine set_preconditioner(self, grid, diagonal, scale, stencil, cycles, stat)
      !> The solver
      class(krylov_type), intent(inout) :: self
      !> The grid
      type(grid_type), intent(in) :: grid
      !> Diagonal shift and the scale of J
      real(dp), intent(in) :: diagonal, scale
      !> J's five-point stencil at every owned point
      real(dp), intent(in) :: stencil(:, :)
      !> Factors of the preconditioner (1 or 2)
      integer, intent(in) :: cycles
      !> Outcome
      type(status_type), intent(inout) :: stat
      PetscErrorCode :: ierr
      call assemble_stencil(grid, self%preconditioner, diagonal, scale, stencil, stat)
      if (stat%code /= status_ok) return
      call PCSetUp(self%multigrid, ierr)
      if (failed(ierr, "PCSetUp (GAMG)", stat)) return
      self%cycles = cycles
   end subroutine set_preconditioner

   !> Solve A x = b with A applied by `operator`; x holds the initial guess on entry.
   !> status_newton_not_converged (code only) when GMRES does not reach rtol.
   subroutine krylov_solve(self, operator, b, x, rtol, stat)
      !> The solver (recorded for the callbacks during the solve)
      class(krylov_type), intent(inout), target :: self
      !> The operator (recorded for the callbacks during the solve)
      class(operator_type), intent(inout), target :: operator
      !> Right-hand side (this rank's part)
      real(dp), intent(in) :: b(:)
      !> Initial guess on entry, solution on exit
      real(dp), intent(inout) :: x(:)
      !> Relative residual reduction asked for
      real(dp), intent(in) :: rtol
      !> Outcome
      type(status_type), intent(inout) :: stat
      PetscErrorCode :: ierr
      PetscScalar, pointer :: values(:)
      PetscInt :: iterations
      KSPConvergedReason :: reason
      select type (self)
      type is (krylov_type)
         active_krylov => self
      end select
      active_operator => operator
      call VecGetArrayF90(self%b, values, ierr)
      values = b
      call VecRestoreArrayF90(self%b, values, ierr)
      call VecGetArrayF90(self%x, values, ierr)
      values = x
      call VecRestoreArrayF90(self%x, values, ierr)
      call KSPSetTolerances(self%ksp, rtol, 1.0e-300_dp, 1.0e10_dp, 500, ierr)
      call KSPSolve(self%ksp, self%b, self%x, ierr)
      nullify (active_operator, active_krylov)
      if (failed(ierr, "KSPSolve", stat)) return
      call KSPGetIterationNumber(self%ksp, iterations, ierr)
      call KSPGetConvergedReason(self%ksp, reason, ierr)
      self%iterations = iterations
      self%total_iterations = self%total_iterations + iterations
      call VecGetArrayReadF90(self%x, values, ierr)
      x = values
      call VecRestoreArrayReadF90(self%x, values, ierr)
      if (reason < 0) stat%code = status_newton_not_converged
   end subroutine krylov_solve

   !> Release the solver's PETSc objects.
   subroutine destroy_krylov(self)
      !> The solver
      class(krylov_type), intent(inout) :: self
      PetscErrorCode :: ierr
      if (.not. self%created) return
      call KSPDestroy(self%ksp, ierr)
      call PCDestroy(self%multigrid, ierr)
      call MatDestroy(self%shell, ierr)
      call MatDestroy(self%preconditioner, ierr)
      call VecDestroy(self%x, ierr)
      call VecDestroy(self%b, ierr)
      call VecDestroy(self%between, ierr)
      deallocate (self%x_work, self%y_work)
      self%created = .false.
   end subroutine destroy_krylov

   !> MATOP_MULT of the shell matrix: y = A x through the operator of the solve.
   subroutine shell_multiply(matrix, x, y, ierr)
      Mat :: matrix
      Vec :: x, y
      PetscErrorCode :: ierr
      PetscScalar, pointer :: values(:)
      call VecGetArrayReadF90(x, values, ierr)
      active_krylov%x_work = values
      call VecRestoreArrayReadF90(x, values, ierr)
      call active_operator%apply(active_krylov%x_work, active_krylov%y_work)
      call VecGetArrayF90(y, values, ierr)
      values = active_krylov%y_work
      call VecRestoreArrayF90(y, values, ierr)
   end subroutine shell_multiply

   !> The shell preconditioner: one GAMG cycle on P per factor of P^cycles.
   subroutine shell_precondition(outer, x, y, ierr)
      PC :: outer
      Vec :: x, y
      PetscErrorCode :: ierr
      if (active_krylov%cycles == 1) then
         call PCApply(active_krylov%multigrid, x, y, ierr)
      else
         call PCApply(active_krylov%multigrid, x, active_krylov%between, ierr)
         call PCApply(active_krylov%multigrid, active_krylov%between, y, ierr)
      end if
   end subroutine shell_precondition

   ! ---------------------------------------------------------------- ARKIMEX

   !> Register the library's IMEX tables with PETSc's ARKIMEX (once per process):
   !> table_imex_rk21, the paper's IMEX-RK(2,1) with its embedded first-order weights
   !> (0, 1), and table_si_t_1, SI-T-1 as IMEX Euler (Y1 = U0, U1 = Y2 = U0 + h f(Y1) +
   !> h g(Y2)), whose error estimate is the difference to explicit Euler, h (g(U1) -
   !> g(U0)). PETSc takes its step-size exponent from the order of a table (1/2 and 1).
   subroutine register_imex_tables(stat)
      !> Outcome
      type(status_type), intent(out) :: stat
      real(c_double), parameter :: gamma = 1.0_c_double - sqrt(2.0_c_double)/2.0_c_double
      real(c_double), parameter :: c = 1.0_c_double/(2.0_c_double*gamma)
      real(c_double) :: at(4), bt(2), ct(2), a(4), b(2), cc(2), bembedt(2), bembed(2)
      integer(c_int) :: error
      if (tables_registered) return
      ! IMEX-RK(2,1), row-major: implicit [[gamma, 0], [1 - gamma, gamma]], explicit [[0, 0], [c, 0]]
      at = [gamma, 0.0_c_double, 1.0_c_double - gamma, gamma]
      bt = [1.0_c_double - gamma, gamma]
      ct = [gamma, 1.0_c_double]
      a = [0.0_c_double, 0.0_c_double, c, 0.0_c_double]
      b = [1.0_c_double - gamma, gamma]
      cc = [0.0_c_double, c]
      bembedt = [0.0_c_double, 1.0_c_double]
      bembed = [0.0_c_double, 1.0_c_double]
      error = arkimex_register(table_imex_rk21//c_null_char, 2_c_int, 2_c_int, at, bt, ct, a, b, cc, bembedt, &
         bembed, 1_c_int, bt, b)
      if (error /= 0) then
         call set_status(stat, status_invalid_argument, "petsc: TSARKIMEXRegister ("//table_imex_rk21//") failed")
         return
      end if
      ! SI-T-1: implicit [[0, 0], [0, 1]], explicit [[0, 0], [1, 0]]; embedded: explicit Euler
      at = [0.0_c_double, 0.0_c_double, 0.0_c_double, 1.0_c_double]
      bt = [0.0_c_double, 1.0_c_double]
      ct = [0.0_c_double, 1.0_c_double]
      a = [0.0_c_double, 0.0_c_double, 1.0_c_double, 0.0_c_double]
      b = [1.0_c_double, 0.0_c_double]
      cc = [0.0_c_double, 1.0_c_double]
      bembedt = [1.0_c_double, 0.0_c_double]
      bembed = [1.0_c_double, 0.0_c_double]
      error = arkimex_register(table_si_t_1//c_null_char, 1_c_int, 2_c_int, at, bt, ct, a, b, cc, bembedt, &
         bembed, 1_c_int, bt, b)
      if (error /= 0) then
         call set_status(stat, status_invalid_argument, "petsc: TSARKIMEXRegister ("//table_si_t_1//") failed")
         return
      end if
      tables_registered = .true.
   end subroutine register_imex_tables

   !> Integrate the split system from t0 to t_end with PETSc's TSARKIMEX and one of the
   !> registered tables: adaptively (PETSc's basic controller with rtol and atol) or
   !> with fixed steps h0. u holds this rank's part of U(t0) on entry and of U(t_end)
   !> on exit. Stage equations are solved by SNES with the assembled Jacobian
   !> shift I - J_g, GMRES and GAMG, to a relative residual of snes_rtol.
   subroutine run_arkimex(system, grid, table, t0, t_end, h0, adaptive, rtol, atol, snes_rtol, u, stats, stat)
      !> The split system (recorded for the callbacks during the run)
      class(split_system_type), intent(inout), target :: system
      !> Its grid (recorded for the callbacks during the run)
      type(grid_type), intent(inout), target :: grid
      !> table_imex_rk21 or table_si_t_1
      character(len=*), intent(in) :: table
      !> Start, end and the first (or every) step size
      real(dp), intent(in) :: t0, t_end, h0
      !> Adaptive steps (else fixed steps h0)
      logical, intent(in) :: adaptive
      !> Tolerances of the adaptive controller and of the stage equations
      real(dp), intent(in) :: rtol, atol, snes_rtol
      !> This rank's part of the state
      real(dp), intent(inout) :: u(:)
      !> Steps, rejections and iterations
      type(arkimex_stats_type), intent(out) :: stats
      !> Outcome
      type(status_type), intent(out) :: stat
      PetscErrorCode :: ierr
      TS :: ts
      TSAdapt :: adapt
      SNES :: snes
      KSP :: ksp
      PC :: pc
      Mat :: jacobian
      Vec :: x
      PetscScalar, pointer :: values(:)
      PetscInt :: count
      TSConvergedReason :: reason
      integer :: no_context

      call register_imex_tables(stat)
      if (stat%code /= status_ok) return
      if (allocated(ts_u)) deallocate (ts_u, ts_f, ts_stencil)
      allocate (ts_u(grid%owned), ts_f(grid%owned), ts_stencil(5, grid%owned))
      active_system => system
      active_grid => grid
      no_context = 0
      call DMCreateMatrix(grid%da, jacobian, ierr)
      call DMCreateGlobalVector(grid%da, x, ierr)
      call VecGetArrayF90(x, values, ierr)
      values = u
      call VecRestoreArrayF90(x, values, ierr)
      call TSCreate(grid%comm, ts, ierr)
      if (failed(ierr, "TSCreate", stat)) return
      call TSSetProblemType(ts, TS_NONLINEAR, ierr)
      call TSSetType(ts, TSARKIMEX, ierr)
      call TSARKIMEXSetType(ts, table, ierr)
      if (failed(ierr, "TSARKIMEXSetType", stat)) return
      call TSSetIFunction(ts, PETSC_NULL_VEC, ts_ifunction, no_context, ierr)
      call TSSetIJacobian(ts, jacobian, jacobian, ts_ijacobian, no_context, ierr)
      call TSSetRHSFunction(ts, PETSC_NULL_VEC, ts_rhsfunction, no_context, ierr)
      call TSSetTime(ts, t0, ierr)
      call TSSetTimeStep(ts, h0, ierr)
      call TSSetMaxTime(ts, t_end, ierr)
      call TSSetMaxSteps(ts, 10000000, ierr)
      call TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP, ierr)
      call TSSetTolerances(ts, atol, PETSC_NULL_VEC, rtol, PETSC_NULL_VEC, ierr)
      call TSGetAdapt(ts, adapt, ierr)
      if (.not. adaptive) call TSAdaptSetType(adapt, TSADAPTNONE, ierr)
      call TSGetSNES(ts, snes, ierr)
      call SNESSetTolerances(snes, 1.0e-300_dp, snes_rtol, 0.0_dp, 50, 1000, ierr)
      call SNESGetKSP(snes, ksp, ierr)
      call KSPSetType(ksp, KSPGMRES, ierr)
      call KSPSetTolerances(ksp, 1.0e-2_dp*snes_rtol, 1.0e-300_dp, 1.0e10_dp, 1000, ierr)
      call KSPGetPC(ksp, pc, ierr)
      call PCSetType(pc, PCGAMG, ierr)
      call PCGAMGSetReuseInterpolation(pc, PETSC_FALSE, ierr)
      call TSSetFromOptions(ts, ierr)
      if (failed(ierr, "TSSetFromOptions", stat)) return
      call TSSolve(ts, x, ierr)
      if (.not. failed(ierr, "TSSolve", stat)) then
         call TSGetConvergedReason(ts, reason, ierr)
         if (reason < 0) call set_status(stat, status_newton_not_converged, "petsc: the TS run did not reach t_end")
         call VecGetArrayReadF90(x, values, ierr)
         u = values
         call VecRestoreArrayReadF90(x, values, ierr)
         call TSGetStepNumber(ts, count, ierr)
         stats%steps = count
         call TSGetStepRejections(ts, count, ierr)
         stats%rejected = count
         call TSGetSNESIterations(ts, count, ierr)
         stats%nonlinear_iterations = count
         call TSGetKSPIterations(ts, count, ierr)
         stats%linear_iterations = count
      end if
      call TSDestroy(ts, ierr)
      call MatDestroy(jacobian, ierr)
      call VecDestroy(x, ierr)
      nullify (active_system, active_grid)
   end subroutine run_arkimex

   !> TS's RHS function: f(t, X).
   subroutine ts_rhsfunction(ts, t, x, f, context, ierr)
      TS :: ts
      PetscReal :: t
      Vec :: x, f
      integer :: context
      PetscErrorCode :: ierr
      PetscScalar, pointer :: values(:)
      call VecGetArrayReadF90(x, values, ierr)
      ts_u = values
      call VecRestoreArrayReadF90(x, values, ierr)
      call active_system%nonstiff(t, ts_u, ts_f)
      call VecGetArrayF90(f, values, ierr)
      values = ts_f
      call VecRestoreArrayF90(f, values, ierr)
   end subroutine ts_rhsfunction

   !> TS's implicit function: X' - g(t, X).
   subroutine ts_ifunction(ts, t, x, xdot, f, context, ierr)
      TS :: ts
      PetscReal :: t
      Vec :: x, xdot, f
      integer :: context
      PetscErrorCode :: ierr
      PetscScalar, pointer :: values(:)
      call VecGetArrayReadF90(x, values, ierr)
      ts_u = values
      call VecRestoreArrayReadF90(x, values, ierr)
      call active_system%stiff(t, ts_u, ts_f)
      call VecGetArrayReadF90(xdot, values, ierr)
      ts_f = values - ts_f
      call VecRestoreArrayReadF90(xdot, values, ierr)
      call VecGetArrayF90(f, values, ierr)
      values = ts_f
      call VecRestoreArrayF90(f, values, ierr)
   end subroutine ts_ifunction

   !> TS's implicit Jacobian: shift I - J_g(t, X), assembled from g's stencil.
   subroutine ts_ijacobian(ts, t, x, xdot, shift, jacobian, preconditioner, context, ierr)
      TS :: ts
      PetscReal :: t, shift
      Vec :: x, xdot
      Mat :: jacobian, preconditioner
      integer :: context
      PetscErrorCode :: ierr
      PetscScalar, pointer :: values(:)
      type(status_type) :: stat
      call VecGetArrayReadF90(x, values, ierr)
      ts_u = values
      call VecRestoreArrayReadF90(x, values, ierr)
      call active_system%stiff_stencil(t, ts_u, ts_stencil)
      call assemble_stencil(active_grid, preconditioner, shift, 1.0_dp, ts_stencil, stat)
      if (stat%code /= status_ok) ierr = 1
   end subroutine ts_ijacobian

end module taylorode_petsc_calls
