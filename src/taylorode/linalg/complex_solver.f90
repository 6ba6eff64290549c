!> Complex shifted systems (s I - J) x = b with a real Jacobian J and a complex
!> shift s: the second Newton matrix of Radau IIA after the eigen-decomposition
!> of its coefficient matrix (Hairer & Wanner II, IV.8), where s = (alpha + i beta)/h.
!>
!> The solver assembles s I - J from a real dense or band `matrix_type`, factors
!> it with partial pivoting (zgetrf, or zgbtrf in band storage with room for the
!> fill-in; bands up to `narrow_band_max_width` wide by the written-out band LU, as
!> the real solver does) and solves with the factors as often as needed. (Radau IIA keeps the
!> factors of small dense systems itself: `small_lu_factor`, `small_lu_solve_pair`.) A J whose storage does not fit the
!> solver's (a dense J for a band solver, bandwidths wider than the solver's) is
!> reported as status_invalid_argument, never silently truncated.
module taylorode_linalg_complex_solver
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_status, status_ok, status_invalid_argument, &
      status_singular_matrix
   use taylorode_base_memory, only: out_of_memory, complex_bytes
   use taylorode_linalg_matrix, only: matrix_type, dense_matrix_type, band_matrix_type, &
      matrix_structure_type, storage_dense, storage_band
   use taylorode_linalg_lapack, only: complex_lu_factor, complex_lu_solve, complex_band_lu_factor, &
      complex_band_lu_solve, narrow_band_lu_factor, narrow_band_lu_solve, narrow_band_lu_solve_pair, &
      narrow_band_max_width
   use taylorode_linalg_solver, only: linear_solver_type
   implicit none
   private

   public :: complex_solver_type, new_complex_solver

   !> LU factorization of s I - J, J real, s complex
   type :: complex_solver_type
      !> Order
      integer :: n = 0
      !> storage_dense or storage_band
      integer :: storage = storage_dense
      !> Lower and upper bandwidths (band storage)
      integer :: kl = 0, ku = 0
      !> The matrix s I - J, then its LU factors: n x n, or (2 kl + ku + 1) x n in
      !> LAPACK band storage (A(i, j) in a(kl + ku + 1 + i - j, j))
      complex(dp), allocatable :: a(:, :)
      !> Row interchanges of the factorization
      integer, allocatable :: pivots(:)
      !> Superdiagonals of the band factor U that hold entries (written-out band LU, which
      !> keeps the reciprocals of the pivots on U's diagonal)
      integer :: upper_width = 0
      !> Right-hand side work space of `solve_parts` for LAPACK's solves (the written-out
      !> band solve takes the parts as they are)
      complex(dp), allocatable :: work(:)
      !> Whether `a` holds valid factors
      logical :: factored = .false.
   contains
      !> a = s I - J
      procedure :: assemble
      !> Factor the assembled matrix in place
      procedure :: factor
      !> (re + i im) = (s I - J)^(-1) (re + i im), real and imaginary parts apart
      procedure :: solve_parts
      !> x = (real solver)^(-1) x and (re + i im) = (s I - J)^(-1) (re + i im) together
      procedure :: solve_with_real
   end type complex_solver_type

contains

   !> A solver for n x n systems with the given structure (dense or banded;
   !> bandwidths are clamped to n - 1).
   subroutine new_complex_solver(solver, n, structure, stat)
      !> The new solver
      type(complex_solver_type), intent(out) :: solver
      !> Order, >= 1
      integer, intent(in) :: n
      !> Storage and bandwidths of the Jacobians it will be assembled from
      type(matrix_structure_type), intent(in) :: structure
      !> status_invalid_argument for an impossible structure, status_out_of_memory
      type(status_type), intent(inout) :: stat
      integer :: memory
      logical :: written_out
      if (n < 1) then
         call set_status(stat, status_invalid_argument, "complex solver: the order must be at least 1")
         return
      end if
      select case (structure%storage)
      case (storage_dense)
         allocate (solver%a(n, n), stat=memory)
         if (memory /= 0) then
            call out_of_memory(stat, "a complex dense matrix", [n, n], complex_bytes)
            return
         end if
      case (storage_band)
         if (structure%lower < 0 .or. structure%upper < 0) then
            call set_status(stat, status_invalid_argument, "complex solver: bandwidths must be >= 0")
            return
         end if
         solver%kl = min(structure%lower, n - 1)
         solver%ku = min(structure%upper, n - 1)
         allocate (solver%a(2*solver%kl + solver%ku + 1, n), stat=memory)
         if (memory /= 0) then
            call out_of_memory(stat, "a complex band matrix", [2*solver%kl + solver%ku + 1, n], complex_bytes)
            return
         end if
      case default
         call set_status(stat, status_invalid_argument, "complex solver: unknown storage")
         return
      end select
      solver%n = n
      solver%storage = structure%storage
      solver%a = (0.0_dp, 0.0_dp)
      ! the work space only for LAPACK's solves
      written_out = solver%storage == storage_band .and. solver%kl <= narrow_band_max_width
      allocate (solver%pivots(n), stat=memory)
      if (memory == 0 .and. .not. written_out) allocate (solver%work(n), stat=memory)
      if (memory /= 0) then
         deallocate (solver%a)
         call out_of_memory(stat, "the pivots and work space of a complex LU factorization", &
            [merge(1, 2, written_out), n], complex_bytes)
      end if
   end subroutine new_complex_solver

   !> a = s I - J, or s M - J with a mass matrix M. J (and M) must have the solver's
   !> order and fit its storage: any for a dense solver, band matrices no wider than
   !> the solver's bands for a band solver.
   subroutine assemble(self, shift, jac, stat, mass)
      !> The solver
      class(complex_solver_type), intent(inout) :: self
      !> The complex shift s
      complex(dp), intent(in) :: shift
      !> The real Jacobian J
      class(matrix_type), intent(in) :: jac
      !> status_invalid_argument on a storage mismatch
      type(status_type), intent(inout) :: stat
      !> The real mass matrix M (default: the identity)
      class(matrix_type), intent(in), optional :: mass
      integer :: j
      complex(dp) :: diagonal_shift

      self%factored = .false.
      ! with a mass matrix the shift comes with it, below
      diagonal_shift = (0.0_dp, 0.0_dp)
      if (.not. present(mass)) diagonal_shift = shift
      if (self%storage == storage_band) then
         select type (jac)
         type is (band_matrix_type)
            if (jac%n /= self%n .or. jac%kl > self%kl .or. jac%ku > self%ku) then
               call mismatch()
               return
            end if
            call shifted_negative_band(self%n, self%kl, self%ku, self%a, diagonal_shift, jac%kl, jac%ku, &
               size(jac%ab, 1), jac%diagonal, jac%ab)
         class default
            call mismatch()
            return
         end select
      else
         call add_real(jac, (-1.0_dp, 0.0_dp), .true.)
         if (stat%code /= status_ok) return
         if (.not. present(mass)) then
            do j = 1, self%n
               self%a(j, j) = self%a(j, j) + shift
            end do
         end if
      end if
      if (present(mass)) call add_real(mass, shift, .false.)
   contains
      !> a = a + factor B (a = factor B first when `first`; a band B only after the
      !> Jacobian's pass, shifted_negative_band)
      subroutine add_real(b, factor, first)
         class(matrix_type), intent(in) :: b
         complex(dp), intent(in) :: factor
         logical, intent(in) :: first
         integer :: i, j, diagonal, shift_b
         if (b%n /= self%n) then
            call mismatch()
            return
         end if
         select type (b)
         type is (dense_matrix_type)
            if (self%storage /= storage_dense) then
               call mismatch()
               return
            end if
            if (first) then
               do j = 1, self%n
                  do i = 1, self%n
                     self%a(i, j) = factor*b%a(i, j)
                  end do
               end do
            else
               do j = 1, self%n
                  do i = 1, self%n
                     self%a(i, j) = self%a(i, j) + factor*b%a(i, j)
                  end do
               end do
            end if
         type is (band_matrix_type)
            if (self%storage == storage_dense) then
               if (first) self%a = (0.0_dp, 0.0_dp)
               do j = 1, self%n
                  do i = max(1, j - b%ku), min(self%n, j + b%kl)
                     self%a(i, j) = self%a(i, j) + factor*b%ab(b%diagonal + i - j, j)
                  end do
               end do
            else
               if (b%kl > self%kl .or. b%ku > self%ku) then
                  call mismatch()
                  return
               end if
               diagonal = self%kl + self%ku + 1
               shift_b = b%diagonal
               do j = 1, self%n
                  do i = max(1, j - b%ku), min(self%n, j + b%kl)
                     self%a(diagonal + i - j, j) = self%a(diagonal + i - j, j) + factor*b%ab(shift_b + i - j, j)
                  end do
               end do
            end if
         class default
            call mismatch()
         end select
      end subroutine add_real

      subroutine mismatch()
         call set_status(stat, status_invalid_argument, &
            "complex solver: the Jacobian's order or storage does not fit the solver")
      end subroutine mismatch
   end subroutine assemble

   !> a = shift I - B over a's band (LAPACK band storage of order n, bandwidths kl, ku;
   !> the kl rows kept for the fill-in are left alone), B a real band matrix within it
   !> (kl_b, ku_b; its diagonal in row diagonal_b of b): zeros outside B's band, in one
   !> pass over explicit-shape arrays (the few entries of a column cost as much as the
   !> loops' bounds otherwise).
   pure subroutine shifted_negative_band(n, kl, ku, a, shift, kl_b, ku_b, ldb, diagonal_b, b)
      !> Order
      integer, intent(in) :: n
      !> a's bandwidths
      integer, intent(in) :: kl, ku
      !> a's band storage, (2 kl + ku + 1) x n
      complex(dp), intent(inout) :: a(2*kl + ku + 1, n)
      !> The shift s
      complex(dp), intent(in) :: shift
      !> B's bandwidths (at most a's), leading dimension and row of the diagonal
      integer, intent(in) :: kl_b, ku_b, ldb, diagonal_b
      !> B's band storage
      real(dp), intent(in) :: b(ldb, n)
      integer :: i, j, diagonal, first, last, first_b, last_b, row_shift
      diagonal = kl + ku + 1
      row_shift = diagonal_b - diagonal
      do j = 1, n
         first = diagonal - min(ku, j - 1)
         last = diagonal + min(kl, n - j)
         first_b = max(first, diagonal - ku_b)
         last_b = min(last, diagonal + kl_b)
         !GCC$ unroll 1
         !GCC$ novector
         do i = first, first_b - 1
            a(i, j) = (0.0_dp, 0.0_dp)
         end do
         !GCC$ unroll 1
         !GCC$ novector
         do i = first_b, last_b
            a(i, j) = cmplx(-b(i + row_shift, j), 0.0_dp, dp)
         end do
         !GCC$ unroll 1
         !GCC$ novector
         do i = last_b + 1, last
            a(i, j) = (0.0_dp, 0.0_dp)
         end do
         a(diagonal, j) = a(diagonal, j) + shift
      end do
   end subroutine shifted_negative_band

   !> Factor the assembled matrix in place.
   subroutine factor(self, stat)
      !> The solver
      class(complex_solver_type), intent(inout) :: self
      !> status_singular_matrix when a pivot is exactly zero (NaN or Inf from an overflow:
      !> radau5 tests the real matrix it builds from the same Jacobian)
      type(status_type), intent(inout) :: stat
      integer :: info
      if (self%storage == storage_band .and. self%kl <= narrow_band_max_width) then
         call narrow_band_lu_factor(self%a, self%kl, self%ku, self%pivots, info, reciprocal_diagonal=.true., &
            upper_width=self%upper_width)
      else if (self%storage == storage_band) then
         call complex_band_lu_factor(self%a, self%kl, self%ku, self%pivots, info)
      else
         call complex_lu_factor(self%a, self%pivots, info)
      end if
      self%factored = info == 0
      if (info > 0) then
         call set_status(stat, status_singular_matrix, "complex solver: the matrix is singular")
      else if (info < 0) then
         call set_status(stat, status_invalid_argument, "complex solver: LAPACK rejected the matrix")
      end if
   end subroutine factor

   !> Solve (s I - J)(x_re + i x_im) = b_re + i b_im with the factors; re and im
   !> hold the parts of b on entry and those of x on exit.
   subroutine solve_parts(self, re, im, stat)
      !> The solver, factored
      class(complex_solver_type), intent(inout) :: self
      !> Real part of the right-hand side on entry, of the solution on exit
      real(dp), contiguous, intent(inout) :: re(:)
      !> Imaginary part of the right-hand side on entry, of the solution on exit
      real(dp), contiguous, intent(inout) :: im(:)
      !> status_invalid_argument when there are no factors or the sizes are wrong
      type(status_type), intent(inout) :: stat
      integer :: i, info
      if (.not. self%factored .or. size(re) /= self%n .or. size(im) /= self%n) then
         call set_status(stat, status_invalid_argument, "complex solver: no factors for a system of this size")
         return
      end if
      if (self%storage == storage_band .and. self%kl <= narrow_band_max_width) then
         call narrow_band_lu_solve(self%a, self%kl, self%ku, self%pivots, re, im, reciprocal_diagonal=.true., &
            upper_width=self%upper_width)
         return
      end if
      do i = 1, self%n
         self%work(i) = cmplx(re(i), im(i), dp)
      end do
      if (self%storage == storage_band) then
         call complex_band_lu_solve(self%a, self%kl, self%ku, self%pivots, self%work, info)
      else
         call complex_lu_solve(self%a, self%pivots, self%work, info)
      end if
      do i = 1, self%n
         re(i) = self%work(i)%re
         im(i) = self%work(i)%im
      end do
      if (info /= 0) call set_status(stat, status_invalid_argument, "complex solver: LAPACK rejected the solve")
   end subroutine solve_parts

   !> x = A^(-1) x with a real solver's factors and (re + i im) = (s I - J)^(-1) (re + i im):
   !> for two narrow band factorizations in one pass over the rows each way
   !> (`narrow_band_lu_solve_pair`, the same values), else one solve after the other.
   subroutine solve_with_real(self, real_solver, x, re, im, stat)
      !> The solver, factored
      class(complex_solver_type), intent(inout) :: self
      !> The real system's solver, factored
      type(linear_solver_type), intent(in) :: real_solver
      !> The real right-hand side on entry, the solution on exit
      real(dp), contiguous, intent(inout) :: x(:)
      !> Real and imaginary part of the complex right-hand side on entry, of the solution on exit
      real(dp), contiguous, intent(inout) :: re(:), im(:)
      !> status_invalid_argument when there are no factors or a size is wrong
      type(status_type), intent(inout) :: stat
      if (self%factored .and. real_solver%factored .and. size(x) == self%n .and. size(re) == self%n .and. &
         size(im) == self%n .and. self%storage == storage_band .and. self%kl <= narrow_band_max_width) then
         select type (a => real_solver%matrix)
         type is (band_matrix_type)
            if (a%n == self%n .and. a%kl <= narrow_band_max_width) then
               call narrow_band_lu_solve_pair(a%ab, a%kl, a%ku, real_solver%pivots, real_solver%upper_width, x, &
                  self%a, self%kl, self%ku, self%pivots, self%upper_width, re, im)
               return
            end if
         end select
      end if
      call real_solver%solve(x, stat)
      if (stat%code == status_ok) call self%solve_parts(re, im, stat)
   end subroutine solve_with_real

end module taylorode_linalg_complex_solver
