!> The LAPACK layer, the only module that calls LAPACK.
!>
!> Explicit interfaces to dgetrf/dgetrs (dense) and dgbtrf/dgbtrs (band), their
!> complex counterparts zgetrf/zgetrs and zgbtrf/zgbtrs, and assumed-shape
!> wrappers, so that a matrix is factored once and solved with several times.
!> Every wrapper checks the arguments it passes (sizes, bandwidths, leading
!> dimensions) and returns info = -1 without calling LAPACK when one is wrong. The
!> library also supplies LAPACK's error handler `xerbla`, which LAPACK calls on an
!> illegal argument: it does nothing, so LAPACK returns its negative info instead
!> of printing a message and stopping the program.
!>
!> `narrow_band_lu_factor` and `narrow_band_lu_solve` are dgbtrf's unblocked path
!> (dgbtf2) and dgbtrs written out, operation for operation, for narrow bands
!> (optionally with the reciprocals of the pivots on U's diagonal, which the solve
!> multiplies by), and for complex matrices zgbtrf's and zgbtrs's (radau5's second
!> Newton matrix on banded problems, where zgbtrs's BLAS calls per column cost more
!> than their arithmetic; the solve takes the real and imaginary parts apart).
!>
!> Beside them, `small_lu_factor` and `small_lu_solve`: the same LU with partial
!> pivoting (LAPACK's pivot choice and factor layout) written out for the tiny
!> dense systems of stiff test problems (n of 2 to a few dozen), where the cost
!> of a LAPACK call exceeds the arithmetic (dgetrs takes ~36 ns at n = 2, the
!> elimination a few ns), and `small_lu_solve_pair`, which solves a real and a
!> complex system (Radau IIA's two) with such factors in one pass. Up to order 4
!> (the stacked Newton matrices of two unknowns, Radau IIA's on problems of two to four
!> unknowns) the factorizations and both solves are written out statement by statement,
!> the same operations in the same order: the loops' set-up cost more than their
!> arithmetic there.
!> For the same reason their loops are not unrolled (`!GCC$ unroll 1`, which
!> overrides fpm's -funroll-loops): an unrolled loop of trip count 2 runs through
!> a ladder of remainder tests.
module taylorode_linalg_lapack
   use, intrinsic :: iso_c_binding, only: c_char, c_int
   use taylorode_base_kinds, only: dp
   implicit none
   private

   public :: lu_factor, lu_solve, band_lu_factor, band_lu_solve, lapack_error_handler
   public :: complex_lu_factor, complex_lu_solve, complex_band_lu_factor, complex_band_lu_solve
   public :: small_lu_factor, small_lu_solve, small_lu_solve_reciprocal, small_lu_solve_pair, small_lu_max_order
   public :: narrow_band_lu_factor, narrow_band_lu_solve, narrow_band_lu_solve_pair, narrow_band_max_width

   !> Largest order for which the written-out LU is used instead of LAPACK. With
   !> the netlib LAPACK and BLAS it factors 4x (n = 2) to 2x (n = 24) faster and
   !> solves 6x to 1.5x faster; complex factorizations draw level near n = 30.
   integer, parameter :: small_lu_max_order = 24
   !> Largest lower bandwidth for which the written-out band LU (LAPACK's unblocked
   !> dgbtf2, as dgbtrf runs it for such bands) replaces the call: below it, calling
   !> BLAS once per column costs more than the column's arithmetic
   integer, parameter :: narrow_band_max_width = 32

   !> Band LU factorization with partial pivoting written out (real or complex)
   interface narrow_band_lu_factor
      module procedure narrow_band_lu_factor_real, narrow_band_lu_factor_complex
   end interface narrow_band_lu_factor

   !> Solve with the factors of `narrow_band_lu_factor` (real or complex)
   interface narrow_band_lu_solve
      module procedure narrow_band_lu_solve_real, narrow_band_lu_solve_complex
   end interface narrow_band_lu_solve

   !> LU factorization with partial pivoting written out (real or complex)
   interface small_lu_factor
      module procedure small_lu_factor_real, small_lu_factor_complex
   end interface small_lu_factor

   !> Solve with the factors of `small_lu_factor` (real; complex systems: `small_lu_solve_pair`)
   interface small_lu_solve
      module procedure small_lu_solve_real
   end interface small_lu_solve

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
      pure subroutine zgetrf(m, n, a, lda, ipiv, info)
         import :: dp
         integer, intent(in) :: m, n, lda
         complex(dp), intent(inout) :: a(lda, *)
         integer, intent(out) :: ipiv(*)
         integer, intent(out) :: info
      end subroutine zgetrf
      pure subroutine zgetrs(trans, n, nrhs, a, lda, ipiv, b, ldb, info)
         import :: dp
         character(len=1), intent(in) :: trans
         integer, intent(in) :: n, nrhs, lda, ldb
         complex(dp), intent(in) :: a(lda, *)
         integer, intent(in) :: ipiv(*)
         complex(dp), intent(inout) :: b(ldb, *)
         integer, intent(out) :: info
      end subroutine zgetrs
      pure subroutine zgbtrf(m, n, kl, ku, ab, ldab, ipiv, info)
         import :: dp
         integer, intent(in) :: m, n, kl, ku, ldab
         complex(dp), intent(inout) :: ab(ldab, *)
         integer, intent(out) :: ipiv(*)
         integer, intent(out) :: info
      end subroutine zgbtrf
      pure subroutine zgbtrs(trans, n, kl, ku, nrhs, ab, ldab, ipiv, b, ldb, info)
         import :: dp
         character(len=1), intent(in) :: trans
         integer, intent(in) :: n, kl, ku, nrhs, ldab, ldb
         complex(dp), intent(in) :: ab(ldab, *)
         integer, intent(in) :: ipiv(*)
         complex(dp), intent(inout) :: b(ldb, *)
         integer, intent(out) :: info
      end subroutine zgbtrs
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

   !> Band LU factorization with partial pivoting in place, written out: LAPACK's
   !> dgbtf2 (which dgbtrf runs for bands up to its block size) operation for
   !> operation, without a BLAS call per column. Storage as `band_lu_factor`; the
   !> caller checks the sizes. info = j > 0: U(j, j) is exactly zero.
   pure subroutine narrow_band_lu_factor_real(ab, kl, ku, ipiv, info, reciprocal_diagonal, upper_width)
      !> Band matrix on entry, its LU factors on exit
      real(dp), contiguous, intent(inout) :: ab(:, :)
      !> Lower and upper bandwidths
      integer, intent(in) :: kl, ku
      !> Pivot indices, size(ab, 2)
      integer, contiguous, intent(out) :: ipiv(:)
      !> 0 success, j > 0 singular (first zero pivot)
      integer, intent(out) :: info
      !> Whether U's diagonal is stored as 1/U(j, j) (0 for a zero pivot), for solves that
      !> multiply instead of dividing (the back substitution chains one division per row);
      !> default: U(j, j), LAPACK's layout
      logical, intent(in), optional :: reciprocal_diagonal
      !> Superdiagonals of U that hold entries: ku without row interchanges, at most
      !> kl + ku (solves skip the others, which stay zero)
      integer, intent(out), optional :: upper_width
      integer :: n, kv, i, j, jp, ju, km, c, width
      real(dp) :: largest, swap, reciprocal_pivot, factor
      logical :: reciprocal

      n = size(ab, 2)
      kv = ku + kl
      info = 0
      reciprocal = .false.
      if (present(reciprocal_diagonal)) reciprocal = reciprocal_diagonal
      ! the fill-in rows above the band start as zeros
      do j = ku + 2, min(kv, n)
         do i = kv - j + 2, kl
            ab(i, j) = 0.0_dp
         end do
      end do
      ju = 1
      width = min(ku, n - 1)
      do j = 1, n
         km = min(kl, n - j)
         ! the pivot: the first entry of largest magnitude in A(j:j+km, j); in the same
         ! loop the fill-in rows of column j + kv start as zeros (km = kl there; a loop of
         ! their own is a call of memset per column for a few entries)
         jp = 1
         largest = abs(ab(kv + 1, j))
         do i = 2, km + 1
            if (j + kv <= n) ab(i - 1, j + kv) = 0.0_dp
            if (abs(ab(kv + i, j)) > largest) then
               largest = abs(ab(kv + i, j))
               jp = i
            end if
         end do
         ipiv(j) = jp + j - 1
         if (ab(kv + jp, j) == 0.0_dp) then
            if (info == 0) info = j
            cycle
         end if
         ju = max(ju, min(j + ku + jp - 1, n))
         width = max(width, ju - j)
         ! rows j and j + jp - 1 exchanged in columns j to ju (A(r, c) is ab(kv + 1 + r - c, c))
         if (jp /= 1) then
            do c = j, ju
               swap = ab(kv + jp - (c - j), c)
               ab(kv + jp - (c - j), c) = ab(kv + 1 - (c - j), c)
               ab(kv + 1 - (c - j), c) = swap
            end do
         end if
         reciprocal_pivot = 1.0_dp/ab(kv + 1, j)
         if (reciprocal) ab(kv + 1, j) = reciprocal_pivot
         if (km > 0) then
            do i = 1, km
               ab(kv + 1 + i, j) = ab(kv + 1 + i, j)*reciprocal_pivot
            end do
            ! A(j+i, c) = A(j+i, c) + l_i (-A(j, c)), as dger computes it (skipping zeros)
            do c = j + 1, ju
               factor = -ab(kv + 1 - (c - j), c)
               if (factor == 0.0_dp) cycle
               !GCC$ novector
               do i = 1, km
                  ab(kv + 1 + i - (c - j), c) = ab(kv + 1 + i - (c - j), c) + ab(kv + 1 + i, j)*factor
               end do
            end do
         end if
      end do
      if (present(upper_width)) upper_width = width
   end subroutine narrow_band_lu_factor_real

   !> Solve A x = b with the factors of `narrow_band_lu_factor` (or `band_lu_factor`):
   !> the row interchanges and L forward as LAPACK's dgbtrs applies them, then U
   !> backward, row by row over the superdiagonals that hold entries (dgbtrs's dtbsv
   !> goes column by column: the sums agree to rounding); b is overwritten by x. Each
   !> row waits for the one before it (the solve is bound by that chain, not by the
   !> arithmetic), so the value just found stays in a register and, with the
   !> reciprocal pivots, enters its row last through one multiply and one subtraction
   !> (the Brusselators' runs of si-t-2, i-t-2 and radau5: 0.84 of their time, median).
   pure subroutine narrow_band_lu_solve_real(ab, kl, ku, ipiv, b, reciprocal_diagonal, upper_width)
      !> LU factors
      real(dp), contiguous, intent(in) :: ab(:, :)
      !> Lower and upper bandwidths
      integer, intent(in) :: kl, ku
      !> Pivot indices
      integer, contiguous, intent(in) :: ipiv(:)
      !> Right-hand side on entry, solution on exit
      real(dp), contiguous, intent(inout) :: b(:)
      !> Whether U's diagonal holds 1/U(j, j) (`narrow_band_lu_factor` with
      !> reciprocal_diagonal): multiplied instead of dividing by U(j, j); default .false.
      logical, intent(in), optional :: reciprocal_diagonal
      !> `upper_width` from `narrow_band_lu_factor` (default kl + ku)
      integer, intent(in), optional :: upper_width
      integer :: n, kd, j, i, l, lm, width
      real(dp) :: swap, factor, total, carry
      logical :: reciprocal

      n = size(ab, 2)
      kd = kl + ku + 1
      width = kl + ku
      if (present(upper_width)) width = min(upper_width, width)
      reciprocal = .false.
      if (present(reciprocal_diagonal)) reciprocal = reciprocal_diagonal
      if (kl > 0 .and. n > 1) then
         ! the value of b(j + 1) just updated stays in `carry` for the next row (unless
         ! a row interchange brings another): the rows chain through one multiply and
         ! one subtraction, not through a store and a load as well
         carry = b(1)
         do j = 1, n - 1
            lm = min(kl, n - j)
            l = ipiv(j)
            if (l /= j) then
               swap = b(l)
               b(l) = b(j)
               b(j) = swap
               carry = swap
            end if
            factor = carry
            carry = b(j + 1) - ab(kd + 1, j)*factor
            b(j + 1) = carry
            !GCC$ novector
            do i = 2, lm
               b(j + i) = b(j + i) - ab(kd + i, j)*factor
            end do
         end do
      end if
      ! U backward row by row: x(j) = (b(j) - sum_i U(j, j + i) x(j + i)) / U(j, j), one
      ! running sum per row (U(j, j + i) is ab(kd - i, j + i)), summed from the far end:
      ! x(j + 1), found just before, enters last, so that each row waits for the one
      ! before it only through that term (the solve is bound by this chain, not by
      ! the arithmetic)
      if (reciprocal .and. width > 0) then
         ! x(j) = (b(j) - sum_(i >= 2) U(j, j + i) x(j + i))/U(j, j) - (U(j, j + 1)/U(j, j)) x(j + 1),
         ! x(j + 1), found just before, kept in `carry`: the rows chain through one multiply
         ! and one subtraction (the other terms use values found two or more rows before)
         carry = b(n)*ab(kd, n)
         b(n) = carry
         do j = n - 1, 1, -1
            total = b(j)
            !GCC$ novector
            do i = min(width, n - j), 2, -1
               total = total - ab(kd - i, j + i)*b(j + i)
            end do
            carry = total*ab(kd, j) - (ab(kd - 1, j + 1)*ab(kd, j))*carry
            b(j) = carry
         end do
         return
      end if
      do j = n, 1, -1
         total = b(j)
         !GCC$ novector
         do i = min(width, n - j), 1, -1
            total = total - ab(kd - i, j + i)*b(j + i)
         end do
         if (reciprocal) then
            b(j) = total*ab(kd, j)
         else
            b(j) = total/ab(kd, j)
         end if
      end do
   end subroutine narrow_band_lu_solve_real

   !> Complex counterpart of `narrow_band_lu_factor_real`: LAPACK's zgbtf2 (which zgbtrf
   !> runs for such bands) written out, the pivot of largest |Re| + |Im| (izamax's
   !> measure), the multipliers scaled by the pivot's reciprocal (`reciprocal`).
   pure subroutine narrow_band_lu_factor_complex(ab, kl, ku, ipiv, info, reciprocal_diagonal, upper_width)
      !> Band matrix on entry, its LU factors on exit
      complex(dp), contiguous, intent(inout) :: ab(:, :)
      !> Lower and upper bandwidths
      integer, intent(in) :: kl, ku
      !> Pivot indices, size(ab, 2)
      integer, contiguous, intent(out) :: ipiv(:)
      !> 0 success, j > 0 singular (first zero pivot)
      integer, intent(out) :: info
      !> Whether U's diagonal is stored as 1/U(j, j) (see `narrow_band_lu_factor_real`)
      logical, intent(in), optional :: reciprocal_diagonal
      !> Superdiagonals of U that hold entries (see `narrow_band_lu_factor_real`)
      integer, intent(out), optional :: upper_width
      integer :: n, kv, i, j, jp, ju, km, c, width
      real(dp) :: largest
      complex(dp) :: swap, reciprocal_pivot, factor
      logical :: reciprocal_stored

      n = size(ab, 2)
      kv = ku + kl
      info = 0
      reciprocal_stored = .false.
      if (present(reciprocal_diagonal)) reciprocal_stored = reciprocal_diagonal
      do j = ku + 2, min(kv, n)
         do i = kv - j + 2, kl
            ab(i, j) = (0.0_dp, 0.0_dp)
         end do
      end do
      ju = 1
      width = min(ku, n - 1)
      do j = 1, n
         km = min(kl, n - j)
         jp = 1
         largest = abs(ab(kv + 1, j)%re) + abs(ab(kv + 1, j)%im)
         do i = 2, km + 1
            if (j + kv <= n) ab(i - 1, j + kv) = (0.0_dp, 0.0_dp)
            if (abs(ab(kv + i, j)%re) + abs(ab(kv + i, j)%im) > largest) then
               largest = abs(ab(kv + i, j)%re) + abs(ab(kv + i, j)%im)
               jp = i
            end if
         end do
         ipiv(j) = jp + j - 1
         if (largest == 0.0_dp) then
            if (info == 0) info = j
            cycle
         end if
         ju = max(ju, min(j + ku + jp - 1, n))
         width = max(width, ju - j)
         if (jp /= 1) then
            do c = j, ju
               swap = ab(kv + jp - (c - j), c)
               ab(kv + jp - (c - j), c) = ab(kv + 1 - (c - j), c)
               ab(kv + 1 - (c - j), c) = swap
            end do
         end if
         reciprocal_pivot = reciprocal(ab(kv + 1, j))
         if (reciprocal_stored) ab(kv + 1, j) = reciprocal_pivot
         if (km > 0) then
            call scale_complex(km, reciprocal_pivot%re, reciprocal_pivot%im, ab(kv + 2:kv + 1 + km, j))
            ! A(j+i, c) = A(j+i, c) - A(j, c) l_i (zaxpy's sum with -A(j, c): the same rounding)
            do c = j + 1, ju
               factor = ab(kv + 1 - (c - j), c)
               if (factor == (0.0_dp, 0.0_dp)) cycle
               call subtract_multiple(km, factor%re, factor%im, ab(kv + 2:kv + 1 + km, j), &
                  ab(kv + 2 - (c - j):kv + 1 + km - (c - j), c))
            end do
         end if
      end do
      if (present(upper_width)) upper_width = width
   end subroutine narrow_band_lu_factor_complex

   !> Complex counterpart of `narrow_band_lu_solve_real` (the same order of operations),
   !> with the factors of `narrow_band_lu_factor_complex`, on the real and imaginary parts
   !> apart (radau5's second stage pair: no complex copy of the right-hand side); re and
   !> im hold those of b on entry, of x on exit.
   pure subroutine narrow_band_lu_solve_complex(ab, kl, ku, ipiv, re, im, reciprocal_diagonal, upper_width)
      !> LU factors
      complex(dp), contiguous, intent(in) :: ab(:, :)
      !> Lower and upper bandwidths
      integer, intent(in) :: kl, ku
      !> Pivot indices
      integer, contiguous, intent(in) :: ipiv(:)
      !> Real part of the right-hand side on entry, of the solution on exit
      real(dp), contiguous, intent(inout) :: re(:)
      !> Imaginary part of the right-hand side on entry, of the solution on exit
      real(dp), contiguous, intent(inout) :: im(:)
      !> Whether U's diagonal holds 1/U(j, j) (multiplied instead of dividing); default .false.
      logical, intent(in), optional :: reciprocal_diagonal
      !> `upper_width` from `narrow_band_lu_factor_complex` (default kl + ku)
      integer, intent(in), optional :: upper_width
      integer :: n, kd, j, i, l, lm, width
      complex(dp) :: factor, total, carry, updated
      logical :: reciprocal_stored

      n = size(ab, 2)
      kd = kl + ku + 1
      width = kl + ku
      if (present(upper_width)) width = min(upper_width, width)
      reciprocal_stored = .false.
      if (present(reciprocal_diagonal)) reciprocal_stored = reciprocal_diagonal
      if (kl > 0 .and. n > 1) then
         ! the value of b(j + 1) just updated stays in `carry` for the next row (unless
         ! a row interchange brings another): the rows chain through one multiply and
         ! one subtraction, not through a store and a load as well
         carry = cmplx(re(1), im(1), dp)
         do j = 1, n - 1
            lm = min(kl, n - j)
            l = ipiv(j)
            if (l /= j) then
               call exchange(re(j), re(l))
               call exchange(im(j), im(l))
               carry = cmplx(re(j), im(j), dp)
            end if
            factor = carry
            carry = cmplx(re(j + 1), im(j + 1), dp) - ab(kd + 1, j)*factor
            re(j + 1) = carry%re
            im(j + 1) = carry%im
            !GCC$ novector
            do i = 2, lm
               updated = cmplx(re(j + i), im(j + i), dp) - ab(kd + i, j)*factor
               re(j + i) = updated%re
               im(j + i) = updated%im
            end do
         end do
      end if
      if (reciprocal_stored .and. width > 0) then
         ! x(j) = (b(j) - sum_(i >= 2) U(j, j + i) x(j + i))/U(j, j) - (U(j, j + 1)/U(j, j)) x(j + 1),
         ! x(j + 1), found just before, kept in `carry`: the rows chain through one multiply
         ! and one subtraction (the other terms use values found two or more rows before)
         carry = cmplx(re(n), im(n), dp)*ab(kd, n)
         re(n) = carry%re
         im(n) = carry%im
         do j = n - 1, 1, -1
            total = cmplx(re(j), im(j), dp)
            !GCC$ novector
            do i = min(width, n - j), 2, -1
               total = total - ab(kd - i, j + i)*cmplx(re(j + i), im(j + i), dp)
            end do
            carry = total*ab(kd, j) - (ab(kd - 1, j + 1)*ab(kd, j))*carry
            re(j) = carry%re
            im(j) = carry%im
         end do
         return
      end if
      do j = n, 1, -1
         total = cmplx(re(j), im(j), dp)
         !GCC$ novector
         do i = min(width, n - j), 1, -1
            total = total - ab(kd - i, j + i)*cmplx(re(j + i), im(j + i), dp)
         end do
         if (reciprocal_stored) then
            total = total*ab(kd, j)
         else
            total = total/ab(kd, j)
         end if
         re(j) = total%re
         im(j) = total%im
      end do
   end subroutine narrow_band_lu_solve_complex

   !> A real and a complex system solved at once with factors of `narrow_band_lu_factor`
   !> with the reciprocals of their pivots, of the same order and bands: b = A^(-1) b and
   !> (re + i im) = C^(-1) (re + i im). The row operations of `narrow_band_lu_solve_real` and
   !> `narrow_band_lu_solve_complex` (the same values), their two forward passes in one loop
   !> over the rows and their two backward passes in another: each solve's chain of rows
   !> runs while the other's waits on memory (radau5 on the Brusselator of 200,000 unknowns:
   !> 7 % less CPU time in all). Written out rather than shared with the single
   !> solves: passes that take either system or both (optional arguments) cost 40 % more
   !> instructions. Other bands or factors: the two solves one after the other.
   pure subroutine narrow_band_lu_solve_pair(ab, kl, ku, ipiv, upper_width, b, complex_factors, complex_kl, &
      complex_ku, complex_pivots, complex_upper_width, re, im)
      !> Real LU factors (`narrow_band_lu_factor` with reciprocal_diagonal)
      real(dp), contiguous, intent(in) :: ab(:, :)
      !> Their lower and upper bandwidths
      integer, intent(in) :: kl, ku
      !> Their pivot indices
      integer, contiguous, intent(in) :: ipiv(:)
      !> Their `upper_width` from `narrow_band_lu_factor`
      integer, intent(in) :: upper_width
      !> Real right-hand side on entry, solution on exit
      real(dp), contiguous, intent(inout) :: b(:)
      !> Complex LU factors (`narrow_band_lu_factor` with reciprocal_diagonal)
      complex(dp), contiguous, intent(in) :: complex_factors(:, :)
      !> Their lower and upper bandwidths
      integer, intent(in) :: complex_kl, complex_ku
      !> Their pivot indices
      integer, contiguous, intent(in) :: complex_pivots(:)
      !> Their `upper_width` from `narrow_band_lu_factor`
      integer, intent(in) :: complex_upper_width
      !> Real and imaginary part of the complex right-hand side on entry, of the solution on exit
      real(dp), contiguous, intent(inout) :: re(:), im(:)
      integer :: n, kd, j, i, l, width, complex_width
      real(dp) :: swap, factor, total, carry
      complex(dp) :: complex_factor, complex_total, complex_carry, updated

      n = size(ab, 2)
      kd = kl + ku + 1
      width = min(upper_width, kl + ku)
      complex_width = min(complex_upper_width, kl + ku)
      if (kl <= 0 .or. complex_kl /= kl .or. complex_ku /= ku .or. n <= 1 .or. width <= 0 .or. &
         complex_width <= 0) then
         call narrow_band_lu_solve_real(ab, kl, ku, ipiv, b, reciprocal_diagonal=.true., upper_width=upper_width)
         call narrow_band_lu_solve_complex(complex_factors, complex_kl, complex_ku, complex_pivots, re, im, &
            reciprocal_diagonal=.true., upper_width=complex_upper_width)
         return
      end if
      carry = b(1)
      complex_carry = cmplx(re(1), im(1), dp)
      do j = 1, n - 1
         l = ipiv(j)
         if (l /= j) then
            swap = b(l)
            b(l) = b(j)
            b(j) = swap
            carry = swap
         end if
         factor = carry
         carry = b(j + 1) - ab(kd + 1, j)*factor
         b(j + 1) = carry
         !GCC$ novector
         do i = 2, min(kl, n - j)
            b(j + i) = b(j + i) - ab(kd + i, j)*factor
         end do
         l = complex_pivots(j)
         if (l /= j) then
            call exchange(re(j), re(l))
            call exchange(im(j), im(l))
            complex_carry = cmplx(re(j), im(j), dp)
         end if
         complex_factor = complex_carry
         complex_carry = cmplx(re(j + 1), im(j + 1), dp) - complex_factors(kd + 1, j)*complex_factor
         re(j + 1) = complex_carry%re
         im(j + 1) = complex_carry%im
         !GCC$ novector
         do i = 2, min(kl, n - j)
            updated = cmplx(re(j + i), im(j + i), dp) - complex_factors(kd + i, j)*complex_factor
            re(j + i) = updated%re
            im(j + i) = updated%im
         end do
      end do
      carry = b(n)*ab(kd, n)
      b(n) = carry
      complex_carry = cmplx(re(n), im(n), dp)*complex_factors(kd, n)
      re(n) = complex_carry%re
      im(n) = complex_carry%im
      do j = n - 1, 1, -1
         total = b(j)
         !GCC$ novector
         do i = min(width, n - j), 2, -1
            total = total - ab(kd - i, j + i)*b(j + i)
         end do
         carry = total*ab(kd, j) - (ab(kd - 1, j + 1)*ab(kd, j))*carry
         b(j) = carry
         complex_total = cmplx(re(j), im(j), dp)
         !GCC$ novector
         do i = min(complex_width, n - j), 2, -1
            complex_total = complex_total - complex_factors(kd - i, j + i)*cmplx(re(j + i), im(j + i), dp)
         end do
         complex_carry = complex_total*complex_factors(kd, j) - &
            (complex_factors(kd - 1, j + 1)*complex_factors(kd, j))*complex_carry
         re(j) = complex_carry%re
         im(j) = complex_carry%im
      end do
   end subroutine narrow_band_lu_solve_pair

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

   !> Complex LU factorization with partial pivoting, in place (LAPACK zgetrf).
   pure subroutine complex_lu_factor(a, ipiv, info)
      !> Square matrix on entry, its LU factors on exit
      complex(dp), contiguous, intent(inout) :: a(:, :)
      !> Pivot indices, size(a, 1)
      integer, contiguous, intent(out) :: ipiv(:)
      !> LAPACK info: 0 success, > 0 singular, < 0 bad argument
      integer, intent(out) :: info
      info = -1
      if (size(a, 1) /= size(a, 2) .or. size(a, 1) < 1 .or. size(ipiv) < size(a, 1)) return
      call zgetrf(size(a, 1), size(a, 2), a, size(a, 1), ipiv, info)
   end subroutine complex_lu_factor

   !> Solve A x = b with the factors from `complex_lu_factor`; b is overwritten by x.
   pure subroutine complex_lu_solve(lu, ipiv, b, info)
      !> LU factors from `complex_lu_factor`
      complex(dp), contiguous, intent(in) :: lu(:, :)
      !> Pivot indices from `complex_lu_factor`
      integer, contiguous, intent(in) :: ipiv(:)
      !> Right-hand side on entry, solution on exit
      complex(dp), contiguous, intent(inout) :: b(:)
      !> LAPACK info
      integer, intent(out) :: info
      info = -1
      if (size(lu, 1) /= size(lu, 2) .or. size(lu, 1) < 1 .or. size(ipiv) < size(lu, 1) .or. &
         size(b) /= size(lu, 1)) return
      call zgetrs("N", size(lu, 1), 1, lu, size(lu, 1), ipiv, b, size(b), info)
   end subroutine complex_lu_solve

   !> Complex band LU factorization with partial pivoting, in place (LAPACK zgbtrf),
   !> in the storage of `band_lu_factor`.
   pure subroutine complex_band_lu_factor(ab, kl, ku, ipiv, info)
      !> Band matrix on entry, its LU factors on exit, (2 kl + ku + 1) x n
      complex(dp), contiguous, intent(inout) :: ab(:, :)
      !> Lower and upper bandwidths
      integer, intent(in) :: kl, ku
      !> Pivot indices, size(ab, 2)
      integer, contiguous, intent(out) :: ipiv(:)
      !> LAPACK info: 0 success, > 0 singular
      integer, intent(out) :: info
      info = -1
      if (kl < 0 .or. ku < 0 .or. size(ab, 1) /= 2*kl + ku + 1 .or. size(ipiv) < size(ab, 2)) return
      call zgbtrf(size(ab, 2), size(ab, 2), kl, ku, ab, size(ab, 1), ipiv, info)
   end subroutine complex_band_lu_factor

   !> Solve A x = b with the factors from `complex_band_lu_factor`; b is overwritten by x.
   pure subroutine complex_band_lu_solve(ab, kl, ku, ipiv, b, info)
      !> LU factors from `complex_band_lu_factor`
      complex(dp), contiguous, intent(in) :: ab(:, :)
      !> Lower and upper bandwidths
      integer, intent(in) :: kl, ku
      !> Pivot indices from `complex_band_lu_factor`
      integer, contiguous, intent(in) :: ipiv(:)
      !> Right-hand side on entry, solution on exit
      complex(dp), contiguous, intent(inout) :: b(:)
      !> LAPACK info
      integer, intent(out) :: info
      info = -1
      if (kl < 0 .or. ku < 0 .or. size(ab, 1) /= 2*kl + ku + 1 .or. size(ipiv) < size(ab, 2) .or. &
         size(b) /= size(ab, 2) .or. size(b) < 1) return
      call zgbtrs("N", size(ab, 2), kl, ku, 1, ab, size(ab, 1), ipiv, b, size(b), info)
   end subroutine complex_band_lu_solve

   !> LU factorization with partial pivoting of a small real matrix, written out:
   !> the pivot is the first entry of largest magnitude (LAPACK's choice), rows are
   !> swapped across the whole matrix and the factors are stored as dgetrf stores
   !> them, so `lu_solve` accepts them too. info = k > 0: U(k, k) is exactly zero.
   pure subroutine small_lu_factor_real(n, a, ipiv, info, inverse_diagonal)
      !> Order
      integer, intent(in) :: n
      !> Square matrix on entry, its LU factors on exit
      real(dp), intent(inout) :: a(n, n)
      !> Pivot indices
      integer, intent(out) :: ipiv(n)
      !> 0 success, k > 0 singular (first zero pivot)
      integer, intent(out) :: info
      !> 1/U(k, k), for solves that multiply instead of divide (a division takes
      !> three times as long, and back substitution chains them)
      real(dp), intent(out), optional :: inverse_diagonal(n)
      integer :: i, j, k, p
      real(dp) :: largest, pivot, swap, factor

      if (n <= 4) then
         call tiny_lu_factor_real(n, a, ipiv, info, inverse_diagonal)
         return
      end if
      info = 0
      !GCC$ unroll 1
      do k = 1, n
         p = k
         largest = abs(a(k, k))
         !GCC$ unroll 1
         do i = k + 1, n
            if (abs(a(i, k)) > largest) then
               largest = abs(a(i, k))
               p = i
            end if
         end do
         ipiv(k) = p
         if (a(p, k) == 0.0_dp) then
            if (info == 0) info = k
            cycle
         end if
         if (p /= k) then
            !GCC$ unroll 1
            do j = 1, n
               swap = a(k, j)
               a(k, j) = a(p, j)
               a(p, j) = swap
            end do
         end if
         pivot = 1.0_dp/a(k, k)
         if (present(inverse_diagonal)) inverse_diagonal(k) = pivot
         !GCC$ unroll 1
         do i = k + 1, n
            a(i, k) = a(i, k)*pivot
         end do
         ! (a zero row entry leaves its column as it is: skipped, as dger skips it; the
         ! Jacobians of chemical kinetics are mostly zeros)
         !GCC$ unroll 1
         do j = k + 1, n
            factor = a(k, j)
            if (factor == 0.0_dp) cycle
            !GCC$ unroll 1
            do i = k + 1, n
               a(i, j) = a(i, j) - factor*a(i, k)
            end do
         end do
      end do
   end subroutine small_lu_factor_real

   !> `small_lu_factor_real` for n <= 4, statement by statement (column k: the pivot,
   !> the row interchange, the multipliers, the update of the columns right of it): the
   !> same operations in the same order as its loops, so the same factors bit for bit.
   pure subroutine tiny_lu_factor_real(n, a, ipiv, info, inverse_diagonal)
      !> Order, at most 4
      integer, intent(in) :: n
      !> Square matrix on entry, its LU factors on exit
      real(dp), intent(inout) :: a(n, n)
      !> Pivot indices
      integer, intent(out) :: ipiv(n)
      !> 0 success, k > 0 singular (first zero pivot)
      integer, intent(out) :: info
      !> 1/U(k, k)
      real(dp), intent(out), optional :: inverse_diagonal(n)
      integer :: p
      real(dp) :: largest
      real(dp) :: pivot, factor
      real(dp) :: a11, a21, a12, a22
      info = 0
      select case (n)
      case (1)
         ipiv(1) = 1
         if (a(1, 1) == 0.0_dp) then
            if (info == 0) info = 1
         else
            pivot = 1.0_dp/a(1, 1)
            if (present(inverse_diagonal)) inverse_diagonal(1) = pivot
         end if
      case (2)
         largest = abs(a(1, 1))
         p = 1
         if (abs(a(2, 1)) > largest) p = 2
         ipiv(1) = p
         ! the rows interchanged as they are read (the pivot's row first): four loads the
         ! vectorizer cannot pair, where the interchange in place loaded each column as
         ! one vector, which waited for the caller's two stores of it to be done (no
         ! store forwarding into a load that spans both)
         a11 = a(p, 1)
         a21 = a(3 - p, 1)
         a12 = a(p, 2)
         a22 = a(3 - p, 2)
         if (a11 == 0.0_dp) then
            if (info == 0) info = 1
         else
            pivot = 1.0_dp/a11
            if (present(inverse_diagonal)) inverse_diagonal(1) = pivot
            a21 = a21*pivot
            factor = a12
            if (factor /= 0.0_dp) a22 = a22 - factor*a21
            a(1, 1) = a11
            a(2, 1) = a21
            a(1, 2) = a12
            a(2, 2) = a22
         end if
         ipiv(2) = 2
         if (a22 == 0.0_dp) then
            if (info == 0) info = 2
         else
            pivot = 1.0_dp/a22
            if (present(inverse_diagonal)) inverse_diagonal(2) = pivot
         end if
      case (3)
         largest = abs(a(1, 1))
         p = 1
         if (abs(a(2, 1)) > largest) then
            largest = abs(a(2, 1))
            p = 2
         end if
         if (abs(a(3, 1)) > largest) p = 3
         ipiv(1) = p
         if (a(p, 1) == 0.0_dp) then
            if (info == 0) info = 1
         else
            if (p /= 1) call interchange_rows(n, a, 1, p)
            pivot = 1.0_dp/a(1, 1)
            if (present(inverse_diagonal)) inverse_diagonal(1) = pivot
            a(2, 1) = a(2, 1)*pivot
            a(3, 1) = a(3, 1)*pivot
            factor = a(1, 2)
            if (factor /= 0.0_dp) then
               a(2, 2) = a(2, 2) - factor*a(2, 1)
               a(3, 2) = a(3, 2) - factor*a(3, 1)
            end if
            factor = a(1, 3)
            if (factor /= 0.0_dp) then
               a(2, 3) = a(2, 3) - factor*a(2, 1)
               a(3, 3) = a(3, 3) - factor*a(3, 1)
            end if
         end if
         largest = abs(a(2, 2))
         p = 2
         if (abs(a(3, 2)) > largest) p = 3
         ipiv(2) = p
         if (a(p, 2) == 0.0_dp) then
            if (info == 0) info = 2
         else
            if (p /= 2) call interchange_rows(n, a, 2, p)
            pivot = 1.0_dp/a(2, 2)
            if (present(inverse_diagonal)) inverse_diagonal(2) = pivot
            a(3, 2) = a(3, 2)*pivot
            factor = a(2, 3)
            if (factor /= 0.0_dp) a(3, 3) = a(3, 3) - factor*a(3, 2)
         end if
         ipiv(3) = 3
         if (a(3, 3) == 0.0_dp) then
            if (info == 0) info = 3
         else
            pivot = 1.0_dp/a(3, 3)
            if (present(inverse_diagonal)) inverse_diagonal(3) = pivot
         end if
      case (4)
         largest = abs(a(1, 1))
         p = 1
         if (abs(a(2, 1)) > largest) then
            largest = abs(a(2, 1))
            p = 2
         end if
         if (abs(a(3, 1)) > largest) then
            largest = abs(a(3, 1))
            p = 3
         end if
         if (abs(a(4, 1)) > largest) p = 4
         ipiv(1) = p
         if (a(p, 1) == 0.0_dp) then
            if (info == 0) info = 1
         else
            if (p /= 1) call interchange_rows(n, a, 1, p)
            pivot = 1.0_dp/a(1, 1)
            if (present(inverse_diagonal)) inverse_diagonal(1) = pivot
            a(2, 1) = a(2, 1)*pivot
            a(3, 1) = a(3, 1)*pivot
            a(4, 1) = a(4, 1)*pivot
            factor = a(1, 2)
            if (factor /= 0.0_dp) then
               a(2, 2) = a(2, 2) - factor*a(2, 1)
               a(3, 2) = a(3, 2) - factor*a(3, 1)
               a(4, 2) = a(4, 2) - factor*a(4, 1)
            end if
            factor = a(1, 3)
            if (factor /= 0.0_dp) then
               a(2, 3) = a(2, 3) - factor*a(2, 1)
               a(3, 3) = a(3, 3) - factor*a(3, 1)
               a(4, 3) = a(4, 3) - factor*a(4, 1)
            end if
            factor = a(1, 4)
            if (factor /= 0.0_dp) then
               a(2, 4) = a(2, 4) - factor*a(2, 1)
               a(3, 4) = a(3, 4) - factor*a(3, 1)
               a(4, 4) = a(4, 4) - factor*a(4, 1)
            end if
         end if
         largest = abs(a(2, 2))
         p = 2
         if (abs(a(3, 2)) > largest) then
            largest = abs(a(3, 2))
            p = 3
         end if
         if (abs(a(4, 2)) > largest) p = 4
         ipiv(2) = p
         if (a(p, 2) == 0.0_dp) then
            if (info == 0) info = 2
         else
            if (p /= 2) call interchange_rows(n, a, 2, p)
            pivot = 1.0_dp/a(2, 2)
            if (present(inverse_diagonal)) inverse_diagonal(2) = pivot
            a(3, 2) = a(3, 2)*pivot
            a(4, 2) = a(4, 2)*pivot
            factor = a(2, 3)
            if (factor /= 0.0_dp) then
               a(3, 3) = a(3, 3) - factor*a(3, 2)
               a(4, 3) = a(4, 3) - factor*a(4, 2)
            end if
            factor = a(2, 4)
            if (factor /= 0.0_dp) then
               a(3, 4) = a(3, 4) - factor*a(3, 2)
               a(4, 4) = a(4, 4) - factor*a(4, 2)
            end if
         end if
         largest = abs(a(3, 3))
         p = 3
         if (abs(a(4, 3)) > largest) p = 4
         ipiv(3) = p
         if (a(p, 3) == 0.0_dp) then
            if (info == 0) info = 3
         else
            if (p /= 3) call interchange_rows(n, a, 3, p)
            pivot = 1.0_dp/a(3, 3)
            if (present(inverse_diagonal)) inverse_diagonal(3) = pivot
            a(4, 3) = a(4, 3)*pivot
            factor = a(3, 4)
            if (factor /= 0.0_dp) a(4, 4) = a(4, 4) - factor*a(4, 3)
         end if
         ipiv(4) = 4
         if (a(4, 4) == 0.0_dp) then
            if (info == 0) info = 4
         else
            pivot = 1.0_dp/a(4, 4)
            if (present(inverse_diagonal)) inverse_diagonal(4) = pivot
         end if
      end select
   contains
      !> Rows k and p of a interchanged
      pure subroutine interchange_rows(n, a, k, p)
         integer, intent(in) :: n, k, p
         real(dp), intent(inout) :: a(n, n)
         real(dp) :: swap
         integer :: j
         !GCC$ unroll 1
         do j = 1, n
            swap = a(k, j)
            a(k, j) = a(p, j)
            a(p, j) = swap
         end do
      end subroutine interchange_rows
   end subroutine tiny_lu_factor_real

   !> Solve A x = b with the factors from `small_lu_factor` (or `lu_factor`).
   pure subroutine small_lu_solve_real(n, lu, ipiv, b, inverse_diagonal)
      !> Order
      integer, intent(in) :: n
      !> LU factors
      real(dp), intent(in) :: lu(n, n)
      !> Pivot indices
      integer, intent(in) :: ipiv(n)
      !> Right-hand side on entry, solution on exit
      real(dp), intent(inout) :: b(n)
      !> 1/U(k, k) from `small_lu_factor`: multiplied instead of dividing by U(k, k)
      real(dp), intent(in), optional :: inverse_diagonal(n)
      integer :: i, k
      real(dp) :: swap, bk

      if (present(inverse_diagonal) .and. n <= 4) then
         call small_lu_solve_reciprocal(n, lu, ipiv, b, inverse_diagonal)
         return
      end if
      !GCC$ unroll 1
      do k = 1, n
         if (ipiv(k) /= k) then
            swap = b(k)
            b(k) = b(ipiv(k))
            b(ipiv(k)) = swap
         end if
      end do
      !GCC$ unroll 1
      do k = 1, n - 1
         bk = b(k)
         !GCC$ unroll 1
         do i = k + 1, n
            b(i) = b(i) - bk*lu(i, k)
         end do
      end do
      if (present(inverse_diagonal)) then
         !GCC$ unroll 1
         do k = n, 1, -1
            bk = b(k)*inverse_diagonal(k)
            b(k) = bk
            !GCC$ unroll 1
            do i = 1, k - 1
               b(i) = b(i) - bk*lu(i, k)
            end do
         end do
      else
         !GCC$ unroll 1
         do k = n, 1, -1
            b(k) = b(k)/lu(k, k)
            bk = b(k)
            !GCC$ unroll 1
            do i = 1, k - 1
               b(i) = b(i) - bk*lu(i, k)
            end do
         end do
      end if
   end subroutine small_lu_solve_real

   !> Solve A x = b with the factors and the 1/U(k, k) from `small_lu_factor`: the
   !> solvers' entry. Up to order 4 the written-out `tiny_lu_solve`, which saves none of
   !> the registers the loops need (no optional argument to test either); beyond it
   !> `small_lu_solve_real`'s loops.
   pure subroutine small_lu_solve_reciprocal(n, lu, ipiv, b, inverse_diagonal)
      !> Order
      integer, intent(in) :: n
      !> LU factors
      real(dp), intent(in) :: lu(n, n)
      !> Pivot indices
      integer, intent(in) :: ipiv(n)
      !> Right-hand side on entry, solution on exit
      real(dp), intent(inout) :: b(n)
      !> 1/U(k, k) from `small_lu_factor`
      real(dp), intent(in) :: inverse_diagonal(n)
      if (n <= 4) then
         call tiny_lu_solve(n, lu, ipiv, b, inverse_diagonal)
      else
         call small_lu_solve_real(n, lu, ipiv, b, inverse_diagonal)
      end if
   end subroutine small_lu_solve_reciprocal

   !> Solve A x = b (real) and C (y + i z) = c + i d (complex, the right-hand side and
   !> the solution kept as real and imaginary parts) with the factors of
   !> `small_lu_factor` (and its reciprocal pivots) in one pass over the rows: the two
   !> Newton systems of Radau IIA on small dense problems, where the loops cost more
   !> than their arithmetic (and array descriptors more than the loops: the arguments
   !> are explicit-shape). Each value is computed as `small_lu_solve` computes it; up to
   !> order 4 the two solves are written out (`tiny_lu_solve`, `tiny_complex_solve`).
   pure subroutine small_lu_solve_pair(n, a, a_pivots, a_inverse_diagonal, c, c_pivots, c_inverse_diagonal, x, re, im)
      !> Order of the systems
      integer, intent(in) :: n
      !> LU factors of the real matrix
      real(dp), intent(in) :: a(n, n)
      !> Its pivot indices
      integer, intent(in) :: a_pivots(n)
      !> Its 1/U(k, k)
      real(dp), intent(in) :: a_inverse_diagonal(n)
      !> LU factors of the complex matrix
      complex(dp), intent(in) :: c(n, n)
      !> Its pivot indices
      integer, intent(in) :: c_pivots(n)
      !> Its 1/U(k, k)
      complex(dp), intent(in) :: c_inverse_diagonal(n)
      !> Real right-hand side on entry, solution on exit
      real(dp), intent(inout) :: x(n)
      !> Real and imaginary parts of the complex right-hand side on entry, of the solution on exit
      real(dp), intent(inout) :: re(n), im(n)
      integer :: i, k, p
      real(dp) :: swap, bk, br, bi, lr, li

      if (n <= 4) then
         ! (tiny_lu_solve through small_lu_solve_reciprocal: its one caller, into which it is inlined)
         call small_lu_solve_reciprocal(n, a, a_pivots, x, a_inverse_diagonal)
         call tiny_complex_solve(n, c, c_pivots, c_inverse_diagonal, re, im)
         return
      end if
      !GCC$ unroll 1
      do k = 1, n
         p = a_pivots(k)
         if (p /= k) then
            swap = x(k)
            x(k) = x(p)
            x(p) = swap
         end if
         p = c_pivots(k)
         if (p /= k) then
            call exchange(re(k), re(p))
            call exchange(im(k), im(p))
         end if
      end do
      !GCC$ unroll 1
      do k = 1, n - 1
         bk = x(k)
         br = re(k)
         bi = im(k)
         !GCC$ unroll 1
         do i = k + 1, n
            call eliminate(x(i), re(i), im(i), a(i, k), c(i, k))
         end do
      end do
      !GCC$ unroll 1
      do k = n, 1, -1
         bk = x(k)*a_inverse_diagonal(k)
         x(k) = bk
         lr = c_inverse_diagonal(k)%re
         li = c_inverse_diagonal(k)%im
         br = re(k)*lr - im(k)*li
         bi = re(k)*li + im(k)*lr
         re(k) = br
         im(k) = bi
         !GCC$ unroll 1
         do i = 1, k - 1
            call eliminate(x(i), re(i), im(i), a(i, k), c(i, k))
         end do
      end do
   contains
      !> One row's values less the factors' entries (a_ik, c_ik) times the known values
      !> bk and br + i bi
      pure subroutine eliminate(xi, rei, imi, a_ik, c_ik)
         real(dp), intent(inout) :: xi, rei, imi
         real(dp), intent(in) :: a_ik
         complex(dp), intent(in) :: c_ik
         real(dp) :: lr, li
         xi = xi - bk*a_ik
         lr = c_ik%re
         li = c_ik%im
         rei = rei - (br*lr - bi*li)
         imi = imi - (br*li + bi*lr)
      end subroutine eliminate
   end subroutine small_lu_solve_pair

   !> The complex half of `small_lu_solve_pair` for n <= 4, statement by statement as
   !> `tiny_lu_solve` is for the real one: the row interchanges, then the forward and
   !> back substitution on the real and imaginary parts, the same operations in the same
   !> order as the pair's loops, so the same numbers bit for bit.
   pure subroutine tiny_complex_solve(n, c, pivots, inverse_diagonal, re, im)
      !> Order, at most 4
      integer, intent(in) :: n
      !> LU factors
      complex(dp), intent(in) :: c(n, n)
      !> Pivot indices
      integer, intent(in) :: pivots(n)
      !> 1/U(k, k)
      complex(dp), intent(in) :: inverse_diagonal(n)
      !> Real and imaginary parts of the right-hand side on entry, of the solution on exit
      real(dp), intent(inout) :: re(n), im(n)
      real(dp) :: r1, r2, r3, r4, i1, i2, i3, i4
      integer :: k, p
      ! (the last row has no other row left to interchange with: pivots(n) = n)
      !GCC$ unroll 1
      do k = 1, n - 1
         p = pivots(k)
         if (p /= k) then
            call exchange(re(k), re(p))
            call exchange(im(k), im(p))
         end if
      end do
      select case (n)
      case (1)
         r1 = re(1)
         i1 = im(1)
         call divide(r1, i1, inverse_diagonal(1))
         re(1) = r1
         im(1) = i1
      case (2)
         r1 = re(1)
         i1 = im(1)
         r2 = re(2)
         i2 = im(2)
         call eliminate(r2, i2, r1, i1, c(2, 1))
         call divide(r2, i2, inverse_diagonal(2))
         call eliminate(r1, i1, r2, i2, c(1, 2))
         call divide(r1, i1, inverse_diagonal(1))
         re(1) = r1
         im(1) = i1
         re(2) = r2
         im(2) = i2
      case (3)
         r1 = re(1)
         i1 = im(1)
         r2 = re(2)
         i2 = im(2)
         r3 = re(3)
         i3 = im(3)
         call eliminate(r2, i2, r1, i1, c(2, 1))
         call eliminate(r3, i3, r1, i1, c(3, 1))
         call eliminate(r3, i3, r2, i2, c(3, 2))
         call divide(r3, i3, inverse_diagonal(3))
         call eliminate(r1, i1, r3, i3, c(1, 3))
         call eliminate(r2, i2, r3, i3, c(2, 3))
         call divide(r2, i2, inverse_diagonal(2))
         call eliminate(r1, i1, r2, i2, c(1, 2))
         call divide(r1, i1, inverse_diagonal(1))
         re(1) = r1
         im(1) = i1
         re(2) = r2
         im(2) = i2
         re(3) = r3
         im(3) = i3
      case (4)
         r1 = re(1)
         i1 = im(1)
         r2 = re(2)
         i2 = im(2)
         r3 = re(3)
         i3 = im(3)
         r4 = re(4)
         i4 = im(4)
         call eliminate(r2, i2, r1, i1, c(2, 1))
         call eliminate(r3, i3, r1, i1, c(3, 1))
         call eliminate(r4, i4, r1, i1, c(4, 1))
         call eliminate(r3, i3, r2, i2, c(3, 2))
         call eliminate(r4, i4, r2, i2, c(4, 2))
         call eliminate(r4, i4, r3, i3, c(4, 3))
         call divide(r4, i4, inverse_diagonal(4))
         call eliminate(r1, i1, r4, i4, c(1, 4))
         call eliminate(r2, i2, r4, i4, c(2, 4))
         call eliminate(r3, i3, r4, i4, c(3, 4))
         call divide(r3, i3, inverse_diagonal(3))
         call eliminate(r1, i1, r3, i3, c(1, 3))
         call eliminate(r2, i2, r3, i3, c(2, 3))
         call divide(r2, i2, inverse_diagonal(2))
         call eliminate(r1, i1, r2, i2, c(1, 2))
         call divide(r1, i1, inverse_diagonal(1))
         re(1) = r1
         im(1) = i1
         re(2) = r2
         im(2) = i2
         re(3) = r3
         im(3) = i3
         re(4) = r4
         im(4) = i4
      end select
   contains
      !> (rei, imi) less c_ik times (br, bi), as the pair's `eliminate`
      pure subroutine eliminate(rei, imi, br, bi, c_ik)
         real(dp), intent(inout) :: rei, imi
         real(dp), intent(in) :: br, bi
         complex(dp), intent(in) :: c_ik
         real(dp) :: lr, li
         lr = c_ik%re
         li = c_ik%im
         rei = rei - (br*lr - bi*li)
         imi = imi - (br*li + bi*lr)
      end subroutine eliminate
      !> (br, bi) times the reciprocal pivot (lr, li)
      pure subroutine divide(br, bi, inverse)
         real(dp), intent(inout) :: br, bi
         complex(dp), intent(in) :: inverse
         real(dp) :: lr, li, r
         lr = inverse%re
         li = inverse%im
         r = br*lr - bi*li
         bi = br*li + bi*lr
         br = r
      end subroutine divide
   end subroutine tiny_complex_solve

   !> `small_lu_solve_real` (with 1/U(k, k)) for n <= 4, statement by statement: the row
   !> interchanges, then the forward and back substitution; the same operations in the
   !> same order, so the same numbers bit for bit.
   pure subroutine tiny_lu_solve(n, lu, ipiv, b, inverse_diagonal)
      !> Order, at most 4
      integer, intent(in) :: n
      !> LU factors
      real(dp), intent(in) :: lu(n, n)
      !> Pivot indices
      integer, intent(in) :: ipiv(n)
      !> Right-hand side on entry, solution on exit
      real(dp), intent(inout) :: b(n)
      !> 1/U(k, k)
      real(dp), intent(in) :: inverse_diagonal(n)
      real(dp) :: b1, b2, b3, b4
      select case (n)
      case (3)
         call interchange(b, 1)
         call interchange(b, 2)
      case (4)
         call interchange(b, 1)
         call interchange(b, 2)
         call interchange(b, 3)
      end select
      ! (the last row has no other row left to interchange with: ipiv(n) = n)
      select case (n)
      case (1)
         b(1) = b(1)*inverse_diagonal(1)
      case (2)
         ! the interchange of the two rows as the loads' addresses: two loads the
         ! vectorizer cannot pair into one, which would wait for the caller's two stores
         ! of b to be done (no store forwarding into a load that spans both)
         b1 = b(ipiv(1))
         b2 = b(3 - ipiv(1))
         b2 = b2 - b1*lu(2, 1)
         b2 = b2*inverse_diagonal(2)
         b1 = b1 - b2*lu(1, 2)
         b(1) = b1*inverse_diagonal(1)
         b(2) = b2
      case (3)
         b1 = b(1)
         b2 = b(2) - b1*lu(2, 1)
         b3 = b(3) - b1*lu(3, 1)
         b3 = b3 - b2*lu(3, 2)
         b3 = b3*inverse_diagonal(3)
         b1 = b1 - b3*lu(1, 3)
         b2 = b2 - b3*lu(2, 3)
         b2 = b2*inverse_diagonal(2)
         b1 = b1 - b2*lu(1, 2)
         b(1) = b1*inverse_diagonal(1)
         b(2) = b2
         b(3) = b3
      case (4)
         b1 = b(1)
         b2 = b(2) - b1*lu(2, 1)
         b3 = b(3) - b1*lu(3, 1)
         b4 = b(4) - b1*lu(4, 1)
         b3 = b3 - b2*lu(3, 2)
         b4 = b4 - b2*lu(4, 2)
         b4 = b4 - b3*lu(4, 3)
         b4 = b4*inverse_diagonal(4)
         b1 = b1 - b4*lu(1, 4)
         b2 = b2 - b4*lu(2, 4)
         b3 = b3 - b4*lu(3, 4)
         b3 = b3*inverse_diagonal(3)
         b1 = b1 - b3*lu(1, 3)
         b2 = b2 - b3*lu(2, 3)
         b2 = b2*inverse_diagonal(2)
         b1 = b1 - b2*lu(1, 2)
         b(1) = b1*inverse_diagonal(1)
         b(2) = b2
         b(3) = b3
         b(4) = b4
      end select

   contains

      !> Rows k and ipiv(k) of b interchanged (when they differ: a store and a load
      !> fewer on the way of every solve, where no interchange is the rule)
      pure subroutine interchange(b, k)
         real(dp), intent(inout) :: b(*)
         integer, intent(in) :: k
         real(dp) :: swap
         if (ipiv(k) == k) return
         swap = b(k)
         b(k) = b(ipiv(k))
         b(ipiv(k)) = swap
      end subroutine interchange

   end subroutine tiny_lu_solve

   !> Complex counterpart of `small_lu_factor_real` (pivot magnitude |Re| + |Im|,
   !> as LAPACK's izamax); the factors are those zgetrf stores.
   pure subroutine small_lu_factor_complex(n, a, ipiv, info, inverse_diagonal)
      !> Order
      integer, intent(in) :: n
      !> Square matrix on entry, its LU factors on exit
      complex(dp), intent(inout) :: a(n, n)
      !> Pivot indices
      integer, intent(out) :: ipiv(n)
      !> 0 success, k > 0 singular (first zero pivot)
      integer, intent(out) :: info
      !> 1/U(k, k), for solves that multiply instead of divide
      complex(dp), intent(out), optional :: inverse_diagonal(n)
      integer :: i, j, k, p
      real(dp) :: largest
      complex(dp) :: pivot, swap, factor

      if (n <= 4) then
         call tiny_lu_factor_complex(n, a, ipiv, info, inverse_diagonal)
         return
      end if
      info = 0
      !GCC$ unroll 1
      do k = 1, n
         p = k
         largest = abs(a(k, k)%re) + abs(a(k, k)%im)
         !GCC$ unroll 1
         do i = k + 1, n
            if (abs(a(i, k)%re) + abs(a(i, k)%im) > largest) then
               largest = abs(a(i, k)%re) + abs(a(i, k)%im)
               p = i
            end if
         end do
         ipiv(k) = p
         if (largest == 0.0_dp) then
            if (info == 0) info = k
            cycle
         end if
         if (p /= k) then
            !GCC$ unroll 1
            do j = 1, n
               swap = a(k, j)
               a(k, j) = a(p, j)
               a(p, j) = swap
            end do
         end if
         pivot = reciprocal(a(k, k))
         if (present(inverse_diagonal)) inverse_diagonal(k) = pivot
         call scale_complex(n - k, pivot%re, pivot%im, a(k + 1:n, k))
         !GCC$ unroll 1
         do j = k + 1, n
            factor = a(k, j)
            if (factor == (0.0_dp, 0.0_dp)) cycle
            call subtract_multiple(n - k, factor%re, factor%im, a(k + 1:n, k), a(k + 1:n, j))
         end do
      end do
   end subroutine small_lu_factor_complex

   !> x = x (pr + i pi), the complex factorizations' multipliers: the complex product's
   !> arithmetic, (xr pr - xi pi, xr pi + xi pr), with xr pr - xi pi written xr pr + xi
   !> (-pi) (the same rounding), so that both parts are a sum of two products, which
   !> gfortran computes in one pass of packed operations (for x*p it formed a sum and a
   !> difference and merged them). Explicit-shape: a column's contiguous run.
   pure subroutine scale_complex(m, pr, pi, x)
      integer, intent(in) :: m
      real(dp), intent(in) :: pr, pi
      complex(dp), intent(inout) :: x(m)
      integer :: i
      real(dp) :: xr, xi, minus_pi
      minus_pi = -pi
      !GCC$ unroll 1
      do i = 1, m
         xr = x(i)%re
         xi = x(i)%im
         x(i)%re = xr*pr + xi*minus_pi
         x(i)%im = xi*pr + xr*pi
      end do
   end subroutine scale_complex

   !> y = y - (fr + i fi) x, the complex factorizations' update of a column: as in
   !> `scale_complex`, the product's parts (fr xr - fi xi, fr xi + fi xr) as sums of
   !> two products, fr xr + (-fi) xi the first (explicit-shape: contiguous runs).
   pure subroutine subtract_multiple(m, fr, fi, x, y)
      integer, intent(in) :: m
      real(dp), intent(in) :: fr, fi
      complex(dp), intent(in) :: x(m)
      complex(dp), intent(inout) :: y(m)
      integer :: i
      real(dp) :: xr, xi, minus_fi
      minus_fi = -fi
      !GCC$ unroll 1
      do i = 1, m
         xr = x(i)%re
         xi = x(i)%im
         y(i)%re = y(i)%re - (fr*xr + minus_fi*xi)
         y(i)%im = y(i)%im - (fr*xi + fi*xr)
      end do
   end subroutine subtract_multiple

   !> `small_lu_factor_complex` for n <= 4, statement by statement (column k: the pivot,
   !> the row interchange, the multipliers, the update of the columns right of it): the
   !> same operations in the same order as its loops, so the same factors bit for bit.
   pure subroutine tiny_lu_factor_complex(n, a, ipiv, info, inverse_diagonal)
      !> Order, at most 4
      integer, intent(in) :: n
      !> Square matrix on entry, its LU factors on exit
      complex(dp), intent(inout) :: a(n, n)
      !> Pivot indices
      integer, intent(out) :: ipiv(n)
      !> 0 success, k > 0 singular (first zero pivot)
      integer, intent(out) :: info
      !> 1/U(k, k)
      complex(dp), intent(out), optional :: inverse_diagonal(n)
      integer :: p
      real(dp) :: largest
      complex(dp) :: pivot, factor
      info = 0
      select case (n)
      case (1)
         largest = abs(a(1, 1)%re) + abs(a(1, 1)%im)
         ipiv(1) = 1
         if (largest == 0.0_dp) then
            if (info == 0) info = 1
         else
            pivot = reciprocal(a(1, 1))
            if (present(inverse_diagonal)) inverse_diagonal(1) = pivot
         end if
      case (2)
         largest = abs(a(1, 1)%re) + abs(a(1, 1)%im)
         p = 1
         if (abs(a(2, 1)%re) + abs(a(2, 1)%im) > largest) then
            largest = abs(a(2, 1)%re) + abs(a(2, 1)%im)
            p = 2
         end if
         ipiv(1) = p
         if (largest == 0.0_dp) then
            if (info == 0) info = 1
         else
            if (p /= 1) call interchange_rows(n, a, 1, p)
            pivot = reciprocal(a(1, 1))
            if (present(inverse_diagonal)) inverse_diagonal(1) = pivot
            a(2, 1) = a(2, 1)*pivot
            factor = a(1, 2)
            if (factor /= (0.0_dp, 0.0_dp)) a(2, 2) = a(2, 2) - factor*a(2, 1)
         end if
         largest = abs(a(2, 2)%re) + abs(a(2, 2)%im)
         ipiv(2) = 2
         if (largest == 0.0_dp) then
            if (info == 0) info = 2
         else
            pivot = reciprocal(a(2, 2))
            if (present(inverse_diagonal)) inverse_diagonal(2) = pivot
         end if
      case (3)
         largest = abs(a(1, 1)%re) + abs(a(1, 1)%im)
         p = 1
         if (abs(a(2, 1)%re) + abs(a(2, 1)%im) > largest) then
            largest = abs(a(2, 1)%re) + abs(a(2, 1)%im)
            p = 2
         end if
         if (abs(a(3, 1)%re) + abs(a(3, 1)%im) > largest) then
            largest = abs(a(3, 1)%re) + abs(a(3, 1)%im)
            p = 3
         end if
         ipiv(1) = p
         if (largest == 0.0_dp) then
            if (info == 0) info = 1
         else
            if (p /= 1) call interchange_rows(n, a, 1, p)
            pivot = reciprocal(a(1, 1))
            if (present(inverse_diagonal)) inverse_diagonal(1) = pivot
            a(2, 1) = a(2, 1)*pivot
            a(3, 1) = a(3, 1)*pivot
            factor = a(1, 2)
            if (factor /= (0.0_dp, 0.0_dp)) then
               a(2, 2) = a(2, 2) - factor*a(2, 1)
               a(3, 2) = a(3, 2) - factor*a(3, 1)
            end if
            factor = a(1, 3)
            if (factor /= (0.0_dp, 0.0_dp)) then
               a(2, 3) = a(2, 3) - factor*a(2, 1)
               a(3, 3) = a(3, 3) - factor*a(3, 1)
            end if
         end if
         largest = abs(a(2, 2)%re) + abs(a(2, 2)%im)
         p = 2
         if (abs(a(3, 2)%re) + abs(a(3, 2)%im) > largest) then
            largest = abs(a(3, 2)%re) + abs(a(3, 2)%im)
            p = 3
         end if
         ipiv(2) = p
         if (largest == 0.0_dp) then
            if (info == 0) info = 2
         else
            if (p /= 2) call interchange_rows(n, a, 2, p)
            pivot = reciprocal(a(2, 2))
            if (present(inverse_diagonal)) inverse_diagonal(2) = pivot
            a(3, 2) = a(3, 2)*pivot
            factor = a(2, 3)
            if (factor /= (0.0_dp, 0.0_dp)) a(3, 3) = a(3, 3) - factor*a(3, 2)
         end if
         largest = abs(a(3, 3)%re) + abs(a(3, 3)%im)
         ipiv(3) = 3
         if (largest == 0.0_dp) then
            if (info == 0) info = 3
         else
            pivot = reciprocal(a(3, 3))
            if (present(inverse_diagonal)) inverse_diagonal(3) = pivot
         end if
      case (4)
         largest = abs(a(1, 1)%re) + abs(a(1, 1)%im)
         p = 1
         if (abs(a(2, 1)%re) + abs(a(2, 1)%im) > largest) then
            largest = abs(a(2, 1)%re) + abs(a(2, 1)%im)
            p = 2
         end if
         if (abs(a(3, 1)%re) + abs(a(3, 1)%im) > largest) then
            largest = abs(a(3, 1)%re) + abs(a(3, 1)%im)
            p = 3
         end if
         if (abs(a(4, 1)%re) + abs(a(4, 1)%im) > largest) then
            largest = abs(a(4, 1)%re) + abs(a(4, 1)%im)
            p = 4
         end if
         ipiv(1) = p
         if (largest == 0.0_dp) then
            if (info == 0) info = 1
         else
            if (p /= 1) call interchange_rows(n, a, 1, p)
            pivot = reciprocal(a(1, 1))
            if (present(inverse_diagonal)) inverse_diagonal(1) = pivot
            a(2, 1) = a(2, 1)*pivot
            a(3, 1) = a(3, 1)*pivot
            a(4, 1) = a(4, 1)*pivot
            factor = a(1, 2)
            if (factor /= (0.0_dp, 0.0_dp)) then
               a(2, 2) = a(2, 2) - factor*a(2, 1)
               a(3, 2) = a(3, 2) - factor*a(3, 1)
               a(4, 2) = a(4, 2) - factor*a(4, 1)
            end if
            factor = a(1, 3)
            if (factor /= (0.0_dp, 0.0_dp)) then
               a(2, 3) = a(2, 3) - factor*a(2, 1)
               a(3, 3) = a(3, 3) - factor*a(3, 1)
               a(4, 3) = a(4, 3) - factor*a(4, 1)
            end if
            factor = a(1, 4)
            if (factor /= (0.0_dp, 0.0_dp)) then
               a(2, 4) = a(2, 4) - factor*a(2, 1)
               a(3, 4) = a(3, 4) - factor*a(3, 1)
               a(4, 4) = a(4, 4) - factor*a(4, 1)
            end if
         end if
         largest = abs(a(2, 2)%re) + abs(a(2, 2)%im)
         p = 2
         if (abs(a(3, 2)%re) + abs(a(3, 2)%im) > largest) then
            largest = abs(a(3, 2)%re) + abs(a(3, 2)%im)
            p = 3
         end if
         if (abs(a(4, 2)%re) + abs(a(4, 2)%im) > largest) then
            largest = abs(a(4, 2)%re) + abs(a(4, 2)%im)
            p = 4
         end if
         ipiv(2) = p
         if (largest == 0.0_dp) then
            if (info == 0) info = 2
         else
            if (p /= 2) call interchange_rows(n, a, 2, p)
            pivot = reciprocal(a(2, 2))
            if (present(inverse_diagonal)) inverse_diagonal(2) = pivot
            a(3, 2) = a(3, 2)*pivot
            a(4, 2) = a(4, 2)*pivot
            factor = a(2, 3)
            if (factor /= (0.0_dp, 0.0_dp)) then
               a(3, 3) = a(3, 3) - factor*a(3, 2)
               a(4, 3) = a(4, 3) - factor*a(4, 2)
            end if
            factor = a(2, 4)
            if (factor /= (0.0_dp, 0.0_dp)) then
               a(3, 4) = a(3, 4) - factor*a(3, 2)
               a(4, 4) = a(4, 4) - factor*a(4, 2)
            end if
         end if
         largest = abs(a(3, 3)%re) + abs(a(3, 3)%im)
         p = 3
         if (abs(a(4, 3)%re) + abs(a(4, 3)%im) > largest) then
            largest = abs(a(4, 3)%re) + abs(a(4, 3)%im)
            p = 4
         end if
         ipiv(3) = p
         if (largest == 0.0_dp) then
            if (info == 0) info = 3
         else
            if (p /= 3) call interchange_rows(n, a, 3, p)
            pivot = reciprocal(a(3, 3))
            if (present(inverse_diagonal)) inverse_diagonal(3) = pivot
            a(4, 3) = a(4, 3)*pivot
            factor = a(3, 4)
            if (factor /= (0.0_dp, 0.0_dp)) a(4, 4) = a(4, 4) - factor*a(4, 3)
         end if
         largest = abs(a(4, 4)%re) + abs(a(4, 4)%im)
         ipiv(4) = 4
         if (largest == 0.0_dp) then
            if (info == 0) info = 4
         else
            pivot = reciprocal(a(4, 4))
            if (present(inverse_diagonal)) inverse_diagonal(4) = pivot
         end if
      end select
   contains
      !> Rows k and p of a interchanged
      pure subroutine interchange_rows(n, a, k, p)
         integer, intent(in) :: n, k, p
         complex(dp), intent(inout) :: a(n, n)
         complex(dp) :: swap
         integer :: j
         !GCC$ unroll 1
         do j = 1, n
            swap = a(k, j)
            a(k, j) = a(p, j)
            a(p, j) = swap
         end do
      end subroutine interchange_rows
   end subroutine tiny_lu_factor_complex

   !> 1/z for a nonzero z, scaled by the larger part so that neither squaring
   !> overflows nor underflows (the compiler's complex division is a library call).
   elemental function reciprocal(z) result(r)
      !> A nonzero complex number
      complex(dp), intent(in) :: z
      complex(dp) :: r
      real(dp) :: ratio, denominator
      if (abs(z%re) >= abs(z%im)) then
         ratio = z%im/z%re
         denominator = z%re + z%im*ratio
         r = cmplx(1.0_dp/denominator, -ratio/denominator, dp)
      else
         ratio = z%re/z%im
         denominator = z%re*ratio + z%im
         r = cmplx(ratio/denominator, -1.0_dp/denominator, dp)
      end if
   end function reciprocal

   !> Exchange two values (a row interchange of a right-hand side held as real and
   !> imaginary parts: one call for each part).
   elemental subroutine exchange(a, b)
      !> The values exchanged
      real(dp), intent(inout) :: a, b
      real(dp) :: swap
      swap = a
      a = b
      b = swap
   end subroutine exchange

end module taylorode_linalg_lapack
