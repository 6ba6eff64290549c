!> LAPACK: the only module that calls it.
!>
!> Explicit interfaces to dgetrf/dgetrs (dense) and dgbtrf/dgbtrs (band) and
!> assumed-shape wrappers, so that a matrix is factored once and solved with
!> several times. Every wrapper checks the arguments it passes (sizes, bandwidths,
!> leading dimensions) and returns info = -1 without calling LAPACK when one is
!> wrong. The library also supplies LAPACK's error handler `xerbla`, which LAPACK
!> calls on an illegal argument: it does nothing, so LAPACK returns its negative
!> info instead of printing a message and stopping the program.
module taylorode_linalg_lapack
   use, intrinsic :: iso_c_binding, only: c_char, c_int
   use taylorode_base_kinds, only: dp
   implicit none
   private

   public :: lu_factor, lu_solve, band_lu_factor, band_lu_solve, lapack_error_handler

   interface
      pure subroutine dgetrf(m, n, a, lda, ipiv, info)
         import :: dp
         integer, intent(in) :: m, n, lda
         real(dp), intent(inout) :: a(lda, *)
         integer, intent(out) :: ipiv(*)
         integer, intent(out) :: info
      end subroutine dgetrf
      pure subroutine dgetrs(trans, n, nrhs, a, lda, ipiv, b, ldb, info)
         import :: dp
         character(len=1), intent(in) :: trans
         integer, intent(in) :: n, nrhs, lda, ldb
         real(dp), intent(in) :: a(lda, *)
         integer, intent(in) :: ipiv(*)
         real(dp), intent(inout) :: b(ldb, *)
         integer, intent(out) :: info
      end subroutine dgetrs
      pure subroutine dgbtrf(m, n, kl, ku, ab, ldab, ipiv, info)
         import :: dp
         integer, intent(in) :: m, n, kl, ku, ldab
         real(dp), intent(inout) :: ab(ldab, *)
         integer, intent(out) :: ipiv(*)
         integer, intent(out) :: info
      end subroutine dgbtrf
      pure subroutine dgbtrs(trans, n, kl, ku, nrhs, ab, ldab, ipiv, b, ldb, info)
         import :: dp
         character(len=1), intent(in) :: trans
         integer, intent(in) :: n, kl, ku, nrhs, ldab, ldb
         real(dp), intent(in) :: ab(ldab, *)
         integer, intent(in) :: ipiv(*)
         real(dp), intent(inout) :: b(ldb, *)
         integer, intent(out) :: info
      end subroutine dgbtrs
   end interface

contains

   !> Band LU factorization with partial pivoting, in place (LAPACK dgbtrf). The
   !> matrix is in LAPACK band storage with room for the fill-in: size(ab, 1) =
   !> 2 kl + ku + 1 and A(i, j) in ab(kl + ku + 1 + i - j, j).
   pure subroutine band_lu_factor(ab, kl, ku, ipiv, info)
      !> Band matrix on entry, its LU factors on exit
      real(dp), contiguous, intent(inout) :: ab(:, :)
      !> Lower and upper bandwidths
      integer, intent(in) :: kl, ku
      !> Pivot indices, size(ab, 2)
      integer, contiguous, intent(out) :: ipiv(:)
      !> LAPACK info: 0 success, > 0 singular
      integer, intent(out) :: info
      info = -1
      if (kl < 0 .or. ku < 0 .or. size(ab, 1) /= 2*kl + ku + 1 .or. size(ipiv) < size(ab, 2)) return
      call dgbtrf(size(ab, 2), size(ab, 2), kl, ku, ab, size(ab, 1), ipiv, info)
   end subroutine band_lu_factor

   !> Solve A x = b with the factors from `band_lu_factor`; b is overwritten by x.
   pure subroutine band_lu_solve(ab, kl, ku, ipiv, b, info)
      !> LU factors from `band_lu_factor`
      real(dp), contiguous, intent(in) :: ab(:, :)
      !> Lower and upper bandwidths
      integer, intent(in) :: kl, ku
      !> Pivot indices from `band_lu_factor`
      integer, contiguous, intent(in) :: ipiv(:)
      !> Right-hand side on entry, solution on exit
      real(dp), contiguous, intent(inout) :: b(:)
      !> LAPACK info
      integer, intent(out) :: info
      info = -1
      if (kl < 0 .or. ku < 0 .or. size(ab, 1) /= 2*kl + ku + 1 .or. size(ipiv) < size(ab, 2) .or. &
         size(b) /= size(ab, 2) .or. size(b) < 1) return
      call dgbtrs("N", size(ab, 2), kl, ku, 1, ab, size(ab, 1), ipiv, b, size(b), info)
   end subroutine band_lu_solve

   !> LU factorization with partial pivoting, in place (LAPACK dgetrf).
   !> `info > 0` means the matrix is exactly singular.
   pure subroutine lu_factor(a, ipiv, info)
      !> Square matrix on entry, its LU factors on exit
      real(dp), contiguous, intent(inout) :: a(:, :)
      !> Pivot indices, size(a, 1)
      integer, contiguous, intent(out) :: ipiv(:)
      !> LAPACK info: 0 success, > 0 singular, < 0 bad argument
      integer, intent(out) :: info
      info = -1
      if (size(a, 1) /= size(a, 2) .or. size(a, 1) < 1 .or. size(ipiv) < size(a, 1)) return
      call dgetrf(size(a, 1), size(a, 2), a, size(a, 1), ipiv, info)
   end subroutine lu_factor

   !> Solve A x = b with the factors from `lu_factor`; b is overwritten by x.
   pure subroutine lu_solve(lu, ipiv, b, info)
      !> LU factors from `lu_factor`
      real(dp), contiguous, intent(in) :: lu(:, :)
      !> Pivot indices from `lu_factor`
      integer, contiguous, intent(in) :: ipiv(:)
      !> Right-hand side on entry, solution on exit
      real(dp), contiguous, intent(inout) :: b(:)
      !> LAPACK info
      integer, intent(out) :: info
      info = -1
      if (size(lu, 1) /= size(lu, 2) .or. size(lu, 1) < 1 .or. size(ipiv) < size(lu, 1) .or. &
         size(b) /= size(lu, 1)) return
      call dgetrs("N", size(lu, 1), 1, lu, size(lu, 1), ipiv, b, size(b), info)
   end subroutine lu_solve

   !> LAPACK's error handler, called by every LAPACK routine that is given an illegal
   !> argument. The reference one prints the argument's position and stops the
   !> program; this one does nothing, and the routine returns info = -(position), which
   !> the wrappers above report as a status. (The wrappers check their arguments first,
   !> so it is a second line of defence, also for LAPACK calls a program makes itself.)
   subroutine lapack_error_handler(routine, position) bind(c, name="xerbla_")
      !> Name of the routine (Fortran character, not NUL-terminated)
      character(kind=c_char), intent(in) :: routine(*)
      !> Position of the illegal argument
      integer(c_int), intent(in) :: position
   end subroutine lapack_error_handler

end module taylorode_linalg_lapack
