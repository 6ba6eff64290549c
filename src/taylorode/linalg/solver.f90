!> Linear solvers of the Newton iterations: a solver owns the matrix the caller
!> assembles, factors it in place and solves with the factors as often as needed.
!> The storage (dense or banded) comes from the structure the problem declares;
!> `new_linear_solver` picks the matching LAPACK path. Dense matrices of up to
!> `small_lu_max_order` rows are factored by the written-out LU instead (LAPACK's
!> pivots and factors; the solves multiply by the reciprocals of the pivots instead
!> of dividing), without the cost of a LAPACK call, which exceeds the arithmetic at
!> these sizes. Band matrices with narrow bands likewise go through the written-out
!> band LU (LAPACK's own operations, without a BLAS call per column; U's diagonal
!> holds the reciprocals of the pivots, which the solves multiply by).
module taylorode_linalg_solver
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_code, status_ok, status_invalid_argument, &
      status_singular_matrix, status_nonfinite
   use taylorode_base_memory, only: out_of_memory, real_bytes, integer_bytes
   use taylorode_linalg_matrix, only: matrix_type, dense_matrix_type, band_matrix_type, &
      matrix_structure_type, storage_dense, new_matrix
   use taylorode_linalg_lapack, only: lu_factor, lu_solve, band_lu_factor, band_lu_solve, &
      small_lu_factor, small_lu_solve_reciprocal, small_lu_max_order, narrow_band_lu_factor, narrow_band_lu_solve, &
      narrow_band_max_width
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   implicit none
   private

   public :: linear_solver_type, new_linear_solver, finite_diagonal

   !> LU factorization with partial pivoting of a matrix assembled in place
   type :: linear_solver_type
      !> The matrix: assembled by the caller, overwritten by its LU factors by `factor`
      class(matrix_type), allocatable :: matrix
      !> Row interchanges of the factorization
      integer, allocatable :: pivots(:)
      !> Reciprocals of the pivots (small dense matrices, factored by the written-out LU;
      !> the written-out band LU keeps them on U's diagonal)
      real(dp), allocatable :: inverse_diagonal(:)
      !> Superdiagonals of the band factor U that hold entries (written-out band LU)
      integer :: upper_width = 0
      !> Whether `matrix` holds valid factors
      logical :: factored = .false.
   contains
      !> Factor the assembled matrix in place
      procedure :: factor
      !> x = A^(-1) x with the factors
      procedure :: solve
      !> x = the first half of A^(-1) [x; 0], A a stacked matrix
      procedure :: solve_stacked
   end type linear_solver_type

contains

   !> A solver for n x n matrices with the given structure (dense or banded).
   subroutine new_linear_solver(solver, n, structure, stat)
      !> The new solver; its matrix is zero
      type(linear_solver_type), intent(out) :: solver
      !> Order
      integer, intent(in) :: n
      !> Storage and bandwidths of the matrices to factor
      type(matrix_structure_type), intent(in) :: structure
      !> status_invalid_argument for an impossible structure, status_out_of_memory (the
      !> solver is then without a matrix)
      type(status_type), intent(inout) :: stat
      integer :: memory
      call new_matrix(solver%matrix, n, structure, stat, factored=.true.)
      if (stat%code /= status_ok) return
      allocate (solver%pivots(n), stat=memory)
      if (memory == 0 .and. structure%storage == storage_dense .and. n <= small_lu_max_order) &
         allocate (solver%inverse_diagonal(n), stat=memory)
      if (memory /= 0) then
         deallocate (solver%matrix)
         call out_of_memory(stat, "the pivots of an LU factorization", [2, n], max(real_bytes, integer_bytes))
      end if
   end subroutine new_linear_solver

   !> Factor the assembled matrix in place (dgetrf or dgbtrf). Failures carry their
   !> code only (no message is built): status_nonfinite for NaN or Inf on U's diagonal
   !> (where a Jacobian that is NaN or Inf leaves it: n tests, not a pass over the
   !> matrix), else status_singular_matrix for a zero pivot.
   subroutine factor(self, stat)
      !> The solver
      class(linear_solver_type), intent(inout) :: self
      !> status_nonfinite or status_singular_matrix
      type(status_type), intent(inout) :: stat
      integer :: info
      select type (a => self%matrix)
      type is (dense_matrix_type)
         if (a%n <= small_lu_max_order) then
            call small_lu_factor(a%n, a%a, self%pivots, info, self%inverse_diagonal)
         else
            call lu_factor(a%a, self%pivots, info)
         end if
      type is (band_matrix_type)
         if (a%fill /= a%kl) then
            ! no room for the fill-in (a matrix not made to be factored)
            info = -1
         else if (a%kl <= narrow_band_max_width) then
            call narrow_band_lu_factor(a%ab, a%kl, a%ku, self%pivots, info, reciprocal_diagonal=.true., &
               upper_width=self%upper_width)
         else
            call band_lu_factor(a%ab, a%kl, a%ku, self%pivots, info)
         end if
      class default
         info = -1
      end select
      self%factored = info == 0
      if (info >= 0 .and. .not. finite_pivots(self, info == 0)) then
         self%factored = .false.
         call set_code(stat, status_nonfinite)
      else if (info > 0) then
         call set_code(stat, status_singular_matrix)
      else if (info < 0) then
         call set_code(stat, status_invalid_argument)
      end if
   end subroutine factor

   !> Whether the diagonal of the factor U is finite: the Jacobians are checked when
   !> they are evaluated, so that NaN or Inf there comes from an overflow in the
   !> elimination (a pivot of -Inf would make every increment 0). The written-out band
   !> LU holds 1/U(j, j) there: 0 is an infinite pivot when no pivot was zero.
   logical function finite_pivots(self, nonsingular)
      class(linear_solver_type), intent(in) :: self
      !> Whether the factorization found no zero pivot
      logical, intent(in) :: nonsingular
      integer :: k
      logical :: infinite_as_zero
      finite_pivots = .false.
      select type (a => self%matrix)
      type is (dense_matrix_type)
         finite_pivots = finite_diagonal(a%n, a%a)
         return
      type is (band_matrix_type)
         infinite_as_zero = a%kl <= narrow_band_max_width .and. nonsingular
         do k = 1, a%n
            if (.not. ieee_is_finite(a%ab(a%diagonal, k))) return
            if (infinite_as_zero .and. a%ab(a%diagonal, k) == 0.0_dp) return
         end do
      end select
      finite_pivots = .true.
   end function finite_pivots

   !> Whether the diagonal of a square matrix is finite: of LU factors, whether their
   !> pivots are (see `factor`). Explicit-shape: on a few unknowns the descriptor cost
   !> more than the loop.
   pure logical function finite_diagonal(n, a)
      !> Order
      integer, intent(in) :: n
      !> The matrix
      real(dp), intent(in) :: a(n, n)
      integer :: k
      finite_diagonal = .false.
      !GCC$ unroll 1
      do k = 1, n
         if (.not. ieee_is_finite(a(k, k))) return
      end do
      finite_diagonal = .true.
   end function finite_diagonal

   !> Solve A x = b with the factors; x holds b on entry.
   subroutine solve(self, x, stat)
      !> The solver, factored
      class(linear_solver_type), intent(in) :: self
      !> Right-hand side on entry, solution on exit
      real(dp), contiguous, intent(inout) :: x(:)
      !> status_invalid_argument (code only) when there are no factors or x has the wrong size
      type(status_type), intent(inout) :: stat
      integer :: info
      info = -1
      if (self%factored .and. size(x) == self%matrix%n) then
         select type (a => self%matrix)
         type is (dense_matrix_type)
            if (a%n <= small_lu_max_order) then
               call small_lu_solve_reciprocal(a%n, a%a, self%pivots, x, self%inverse_diagonal)
               info = 0
            else
               call lu_solve(a%a, self%pivots, x, info)
            end if
         type is (band_matrix_type)
            if (a%kl <= narrow_band_max_width) then
               call narrow_band_lu_solve(a%ab, a%kl, a%ku, self%pivots, x, reciprocal_diagonal=.true., &
                  upper_width=self%upper_width)
               info = 0
            else
               call band_lu_solve(a%ab, a%kl, a%ku, self%pivots, x, info)
            end if
         end select
      end if
      if (info /= 0) call set_code(stat, status_invalid_argument)
   end subroutine solve

   !> x = the first half of A^(-1) [x; 0] for a stacked matrix A of order 2m, its rows
   !> interleaved as `stacked_structure` orders them (x_i at row 2i - 1, 0 at row 2i).
   !> Dense stacked matrices of up to `small_lu_max_order` rows take [x; 0] in a local
   !> array and go straight to the written-out solve; the others go through `work`.
   !> (x is explicit-shape: on a few unknowns its descriptor cost more than the loops.)
   subroutine solve_stacked(self, m, x, work, stat)
      !> The solver, factored
      class(linear_solver_type), intent(in) :: self
      !> Unknowns (half the order of the stacked matrix)
      integer, intent(in) :: m
      !> The first half of the right-hand side on entry (the second is zero), of the
      !> solution on exit
      real(dp), intent(inout) :: x(m)
      !> Room for the whole right-hand side and solution (2m entries)
      real(dp), contiguous, intent(inout) :: work(:)
      !> status_invalid_argument (code only) when there are no factors or a size is wrong
      type(status_type), intent(inout) :: stat
      real(dp) :: b(small_lu_max_order)
      integer :: i
      if (2*m <= small_lu_max_order .and. self%factored .and. self%matrix%n == 2*m) then
         select type (a => self%matrix)
         type is (dense_matrix_type)
            ! scalar loops: a vector load of x (or of b) would wait for the two stores
            ! of it just done (by the caller, by the solve) to be complete, as no store
            ! forwards into a load that spans two
            !GCC$ unroll 1
            !GCC$ novector
            do i = 1, m
               b(2*i - 1) = x(i)
               b(2*i) = 0.0_dp
            end do
            call small_lu_solve_reciprocal(2*m, a%a, self%pivots, b, self%inverse_diagonal)
            !GCC$ unroll 1
            !GCC$ novector
            do i = 1, m
               x(i) = b(2*i - 1)
            end do
            return
         end select
      end if
      if (size(work) /= 2*m) then
         call set_code(stat, status_invalid_argument)
         return
      end if
      do i = 1, m
         work(2*i - 1) = x(i)
         work(2*i) = 0.0_dp
      end do
      call self%solve(work, stat)
      do i = 1, m
         x(i) = work(2*i - 1)
      end do
   end subroutine solve_stacked

end module taylorode_linalg_solver
