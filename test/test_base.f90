!> The base layers: number formatting for messages and reports, and the written-out
!> factorizations of the linear algebra layer against LAPACK.
module test_base
   use testdrive, only: new_unittest, unittest_type, error_type, check
   use taylorode, only: dp, i8
   use taylorode_base_strings, only: format_count, format_real, format_fixed, format_integer
   use taylorode_linalg_lapack, only: lu_factor, lu_solve, band_lu_factor, band_lu_solve, small_lu_factor, &
      small_lu_solve, small_lu_solve_pair, complex_lu_factor, complex_lu_solve, narrow_band_lu_factor, &
      narrow_band_lu_solve, narrow_band_lu_solve_pair, complex_band_lu_factor, complex_band_lu_solve
   use taylorode_base_status, only: status_type, status_ok, status_nonfinite, status_singular_matrix
   use taylorode_linalg_solver, only: linear_solver_type, new_linear_solver
   use taylorode_linalg_matrix, only: matrix_type, band_matrix_type, dense_matrix_type, matrix_structure_type, &
      new_matrix, storage_band, storage_dense
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf, ieee_quiet_nan
   implicit none
   private

   public :: collect_base

contains

   !> Collect all exported unit tests
   subroutine collect_base(testsuite)
      type(unittest_type), allocatable, intent(out) :: testsuite(:)
      testsuite = [ &
         new_unittest("number-formats", test_formats), &
         new_unittest("written-out-lu-equals-lapack", test_written_out_lu), &
         new_unittest("written-out-complex-band-lu-equals-lapack", test_written_out_complex_band_lu), &
         new_unittest("band-pair-solve-equals-the-two-solves", test_band_pair_solve), &
         new_unittest("band-set-scaled-sets-the-band", test_band_set_scaled), &
         new_unittest("band-product-both-orders", test_band_product), &
         new_unittest("pair-solve-equals-single-solves", test_pair_solve), &
         new_unittest("tiny-lu-equals-column-elimination", test_tiny_lu), &
         new_unittest("matrix-finiteness-every-entry", test_all_finite), &
         new_unittest("band-factor-failures-named", test_band_factor_failures) &
         ]
   end subroutine collect_base

   !> The written-out dense and band LU give LAPACK's pivots, factors and solutions
   !> bit for bit (with LAPACK's division in the solve; with the reciprocals of the
   !> pivots, to 1e-13 relative dense, 1e-12 band), on pseudo-random matrices that need row
   !> interchanges (dense ones of even order 70 % zeros off the diagonal, whose elimination
   !> skips columns), for every order up to 24 (dense) and bandwidths 0 to 5 with n from
   !> 1 to 40 (band; the fill-in rows hold leftovers on entry, as in a reused matrix),
   !> and report the same first zero pivot of a singular matrix. The
   !> solve written out statement by statement (orders up to 4, with the reciprocals)
   !> gives the numbers of the column-by-column substitution bit for bit (200 right-hand
   !> sides each).
   subroutine test_written_out_lu(error)
      type(error_type), allocatable, intent(out) :: error
      integer, parameter :: orders(4) = [1, 2, 7, 40]
      real(dp), allocatable :: a(:, :), lu(:, :), ab(:, :), band(:, :), original(:, :), b(:), x(:), y(:), &
         inverse(:)
      integer, allocatable :: pivots(:), band_pivots(:)
      integer :: n, kl, ku, i, j, info, info_lapack, k, width
      integer(i8) :: state
      character(len=:), allocatable :: label

      state = 20261123_i8
      do n = 1, 24
         label = "dense n = "//format_integer(n)
         allocate (a(n, n), lu(n, n), b(n), x(n), y(n), pivots(n), band_pivots(n), inverse(n))
         do j = 1, n
            do i = 1, n
               a(i, j) = next_value(state)
               ! even orders mostly zeros off the diagonal (a kinetics Jacobian's pattern:
               ! the elimination skips the columns whose multiplier is zero)
               if (mod(n, 2) == 0 .and. i /= j .and. next_value(state) > -0.4_dp) a(i, j) = 0.0_dp
            end do
            b(j) = next_value(state)
         end do
         lu = a
         call lu_factor(lu, pivots, info_lapack)
         call small_lu_factor(n, a, band_pivots, info, inverse)
         call check(error, info == info_lapack .and. all(pivots == band_pivots) .and. all(a == lu), &
            label//": factors differ from dgetrf")
         if (allocated(error)) return
         x = b
         call lu_solve(lu, pivots, x, info_lapack)
         y = b
         call small_lu_solve(n, a, band_pivots, y)
         call check(error, all(x == y), label//": solution differs from dgetrs")
         if (allocated(error)) return
         y = b
         call small_lu_solve(n, a, band_pivots, y, inverse)
         call check(error, maxval(abs(x - y)) <= 1.0e-13_dp*maxval(abs(x)), label//": reciprocal pivots")
         if (allocated(error)) return
         do k = 1, merge(200, 1, n <= 4)
            if (k > 1) b = [(next_value(state), i=1, n)]
            y = b
            call small_lu_solve(n, a, band_pivots, y, inverse)
            x = b
            call substitute_by_columns(a, band_pivots, inverse, x)
            call check(error, all(x == y), label//": reciprocal pivots differ from the column-by-column substitution")
            if (allocated(error)) return
         end do
         deallocate (a, lu, b, x, y, pivots, band_pivots, inverse)
      end do

      do k = 1, size(orders)
         n = orders(k)
         do kl = 0, 5
            do ku = 0, 5
               label = "band n = "//format_integer(n)//", kl = "//format_integer(kl)//", ku = "//format_integer(ku)
               allocate (ab(2*kl + ku + 1, n), band(2*kl + ku + 1, n), original(2*kl + ku + 1, n), b(n), x(n), &
                  y(n), pivots(n), band_pivots(n))
               ab = 0.0_dp
               do j = 1, n
                  ! the fill-in rows (within the matrix) hold what a factorization before
                  ! left there: both factorizations set them to zero before they use them
                  do i = max(1, kl + ku + 2 - j), kl
                     ab(i, j) = next_value(state)
                  end do
                  do i = max(1, j - ku), min(n, j + kl)
                     ab(kl + ku + 1 + i - j, j) = next_value(state)
                  end do
                  b(j) = next_value(state)
               end do
               ! a zero column makes the largest case singular at a known pivot
               if (n == 40 .and. kl == 5 .and. ku == 5) ab(:, 17) = 0.0_dp
               original = ab
               band = ab
               call band_lu_factor(band, kl, ku, pivots, info_lapack)
               call narrow_band_lu_factor(ab, kl, ku, band_pivots, info)
               call check(error, info == info_lapack .and. all(pivots == band_pivots) .and. all(ab == band), &
                  label//": factors differ from dgbtrf")
               if (allocated(error)) return
               if (info == 0) then
                  x = b
                  call band_lu_solve(band, kl, ku, pivots, x, info_lapack)
                  y = b
                  call narrow_band_lu_solve(ab, kl, ku, band_pivots, y)
                  call check(error, maxval(abs(x - y)) <= 1.0e-12_dp*maxval(abs(x)), &
                     label//": solution differs from dgbtrs")
                  if (allocated(error)) return
                  ! U holds entries on no more superdiagonals than it says
                  band = original
                  call narrow_band_lu_factor(band, kl, ku, band_pivots, info, upper_width=width)
                  call check(error, width >= min(ku, n - 1) .and. width <= min(kl + ku, n - 1) .and. &
                     all(band(1:kl + ku - width, :) == 0.0_dp), label//": upper width")
                  if (allocated(error)) return
                  y = b
                  call narrow_band_lu_solve(ab, kl, ku, band_pivots, y, upper_width=width)
                  call check(error, maxval(abs(x - y)) <= 1.0e-12_dp*maxval(abs(x)), &
                     label//": solution over the upper width")
                  if (allocated(error)) return
                  ! without row interchanges (a dominant diagonal) U keeps the upper bandwidth
                  band = original
                  band(kl + ku + 1, :) = band(kl + ku + 1, :) + real(2*(kl + ku + 1), dp)
                  call narrow_band_lu_factor(band, kl, ku, band_pivots, info, upper_width=width)
                  call check(error, width, min(ku, n - 1), label//": upper width without interchanges")
                  if (allocated(error)) return
                  ! the reciprocal pivots on U's diagonal: the same factors otherwise, and
                  ! 1/U(j, j) as the division computes it
                  band = original
                  call narrow_band_lu_factor(band, kl, ku, band_pivots, info, reciprocal_diagonal=.true.)
                  call check(error, all(band(:kl + ku, :) == ab(:kl + ku, :)) .and. &
                     all(band(kl + ku + 2:, :) == ab(kl + ku + 2:, :)) .and. &
                     all(band(kl + ku + 1, :) == 1.0_dp/ab(kl + ku + 1, :)), label//": reciprocal pivots on the diagonal")
                  if (allocated(error)) return
                  y = b
                  call narrow_band_lu_solve(band, kl, ku, band_pivots, y, reciprocal_diagonal=.true.)
                  call check(error, maxval(abs(x - y)) <= 1.0e-12_dp*maxval(abs(x)), label//": reciprocal pivots")
                  if (allocated(error)) return
               else
                  call check(error, info, 17, label//": the zero column is the first zero pivot")
                  if (allocated(error)) return
               end if
               deallocate (ab, band, original, b, x, y, pivots, band_pivots)
            end do
         end do
      end do
   end subroutine test_written_out_lu

   !> The written-out complex band LU (radau5's second Newton matrix on banded problems)
   !> chooses zgbtrf's pivots and gives its factors to 1e-13 relative (the multipliers
   !> are scaled by the pivot's reciprocal, computed apart), and zgbtrs's solutions to
   !> 1e-12 relative (the solve takes the real and imaginary parts apart), with LAPACK's
   !> division or the reciprocal pivots on U's diagonal (the same factors otherwise) and
   !> over the upper width it reports, for bandwidths 0 to 5 with n from 1 to 40, on
   !> pseudo-random matrices that need row interchanges; a zero column is the first
   !> zero pivot.
   subroutine test_written_out_complex_band_lu(error)
      type(error_type), allocatable, intent(out) :: error
      integer, parameter :: orders(4) = [1, 2, 7, 40]
      complex(dp), allocatable :: ab(:, :), band(:, :), original(:, :), b(:), x(:)
      real(dp), allocatable :: re(:), im(:)
      integer, allocatable :: pivots(:), band_pivots(:)
      integer :: n, i, j, k, kl, ku, info, info_lapack, width
      integer(i8) :: state
      character(len=:), allocatable :: label

      state = 20261126_i8
      do k = 1, size(orders)
         n = orders(k)
         do kl = 0, 5
            do ku = 0, 5
               label = "complex band n = "//format_integer(n)//", kl = "//format_integer(kl)//", ku = "// &
                  format_integer(ku)
               allocate (ab(2*kl + ku + 1, n), band(2*kl + ku + 1, n), original(2*kl + ku + 1, n), b(n), x(n), &
                  pivots(n), band_pivots(n))
               ab = (0.0_dp, 0.0_dp)
               do j = 1, n
                  do i = max(1, kl + ku + 2 - j), kl
                     ab(i, j) = cmplx(next_value(state), next_value(state), dp)
                  end do
                  do i = max(1, j - ku), min(n, j + kl)
                     ab(kl + ku + 1 + i - j, j) = cmplx(next_value(state), next_value(state), dp)
                  end do
                  b(j) = cmplx(next_value(state), next_value(state), dp)
               end do
               if (n == 40 .and. kl == 5 .and. ku == 5) ab(:, 17) = (0.0_dp, 0.0_dp)
               original = ab
               band = ab
               call complex_band_lu_factor(band, kl, ku, pivots, info_lapack)
               call narrow_band_lu_factor(ab, kl, ku, band_pivots, info, upper_width=width)
               call check(error, info == info_lapack .and. all(pivots == band_pivots), &
                  label//": pivots differ from zgbtrf")
               if (allocated(error)) return
               if (info /= 0) then
                  call check(error, info, 17, label//": the zero column is the first zero pivot")
                  if (allocated(error)) return
                  deallocate (ab, band, original, b, x, pivots, band_pivots)
                  cycle
               end if
               call check(error, maxval(abs(ab(kl + 1:, :) - band(kl + 1:, :))) <= &
                  1.0e-13_dp*maxval(abs(band(kl + 1:, :))), label//": factors differ from zgbtrf")
               if (allocated(error)) return
               call check(error, width >= min(ku, n - 1) .and. width <= min(kl + ku, n - 1) .and. &
                  all(ab(1:kl + ku - width, :) == (0.0_dp, 0.0_dp)), label//": upper width")
               if (allocated(error)) return
               x = b
               call complex_band_lu_solve(band, kl, ku, pivots, x, info_lapack)
               re = b%re
               im = b%im
               call narrow_band_lu_solve(ab, kl, ku, band_pivots, re, im)
               call check(error, maxval(abs(x - cmplx(re, im, dp))) <= 1.0e-12_dp*maxval(abs(x)), &
                  label//": solution differs from zgbtrs")
               if (allocated(error)) return
               band = original
               call narrow_band_lu_factor(band, kl, ku, band_pivots, info, reciprocal_diagonal=.true.)
               call check(error, all(band(:kl + ku, :) == ab(:kl + ku, :)) .and. &
                  all(band(kl + ku + 2:, :) == ab(kl + ku + 2:, :)) .and. &
                  maxval(abs(band(kl + ku + 1, :)*ab(kl + ku + 1, :) - 1.0_dp)) <= 4.0e-15_dp, &
                  label//": reciprocal pivots on the diagonal")
               if (allocated(error)) return
               re = b%re
               im = b%im
               call narrow_band_lu_solve(band, kl, ku, band_pivots, re, im, reciprocal_diagonal=.true., &
                  upper_width=width)
               call check(error, maxval(abs(x - cmplx(re, im, dp))) <= 1.0e-12_dp*maxval(abs(x)), &
                  label//": reciprocal pivots over the upper width")
               if (allocated(error)) return
               deallocate (ab, band, original, b, x, pivots, band_pivots)
            end do
         end do
      end do
   end subroutine test_written_out_complex_band_lu

   !> narrow_band_lu_solve_pair (a real and a complex band system in one pass over the
   !> rows each way, radau5's two on band problems) gives the solutions of the two
   !> single solves with the reciprocal pivots over their upper widths bit for bit, for
   !> bandwidths 0 to 5 with n from 1 to 40, on pseudo-random matrices that need row
   !> interchanges (the two factorizations' pivots and upper widths differ), and when
   !> the complex factors' bands are not the real ones' (the single solves then).
   subroutine test_band_pair_solve(error)
      type(error_type), allocatable, intent(out) :: error
      integer, parameter :: orders(4) = [1, 2, 7, 40]
      real(dp), allocatable :: a(:, :), b(:), x(:), re(:), im(:), pair_re(:), pair_im(:), y(:)
      complex(dp), allocatable :: c(:, :)
      integer, allocatable :: pivots(:), c_pivots(:)
      integer :: n, i, j, k, kl, ku, c_kl, c_ku, info, c_info, width, c_width
      integer(i8) :: state
      character(len=:), allocatable :: label

      state = 20261127_i8
      do k = 1, size(orders)
         n = orders(k)
         do kl = 0, 5
            do ku = 0, 5
               ! the complex factors' bands: the real ones', and one case apart
               c_kl = kl
               c_ku = ku
               if (kl == 2 .and. ku == 3) c_ku = 1
               label = "band pair n = "//format_integer(n)//", kl = "//format_integer(kl)//", ku = "// &
                  format_integer(ku)//", complex ku = "//format_integer(c_ku)
               allocate (a(2*kl + ku + 1, n), c(2*c_kl + c_ku + 1, n), b(n), x(n), y(n), re(n), im(n), &
                  pair_re(n), pair_im(n), pivots(n), c_pivots(n))
               a = 0.0_dp
               c = (0.0_dp, 0.0_dp)
               do j = 1, n
                  do i = max(1, j - ku), min(n, j + kl)
                     a(kl + ku + 1 + i - j, j) = next_value(state)
                  end do
                  do i = max(1, j - c_ku), min(n, j + c_kl)
                     c(c_kl + c_ku + 1 + i - j, j) = cmplx(next_value(state), next_value(state), dp)
                  end do
                  b(j) = next_value(state)
                  re(j) = next_value(state)
                  im(j) = next_value(state)
               end do
               call narrow_band_lu_factor(a, kl, ku, pivots, info, reciprocal_diagonal=.true., upper_width=width)
               call narrow_band_lu_factor(c, c_kl, c_ku, c_pivots, c_info, reciprocal_diagonal=.true., &
                  upper_width=c_width)
               call check(error, info == 0 .and. c_info == 0, label//": a factorization failed")
               if (allocated(error)) return
               y = b
               pair_re = re
               pair_im = im
               call narrow_band_lu_solve_pair(a, kl, ku, pivots, width, y, c, c_kl, c_ku, c_pivots, c_width, &
                  pair_re, pair_im)
               x = b
               call narrow_band_lu_solve(a, kl, ku, pivots, x, reciprocal_diagonal=.true., upper_width=width)
               call narrow_band_lu_solve(c, c_kl, c_ku, c_pivots, re, im, reciprocal_diagonal=.true., &
                  upper_width=c_width)
               call check(error, all(y == x), label//": the real solution differs from the single solve")
               if (allocated(error)) return
               call check(error, all(pair_re == re) .and. all(pair_im == im), &
                  label//": the complex solution differs from the single solve")
               if (allocated(error)) return
               deallocate (a, c, b, x, y, re, im, pair_re, pair_im, pivots, c_pivots)
            end do
         end do
      end do
   end subroutine test_band_pair_solve

   !> A = alpha B for band matrices sets every entry of A's band in the matrix: alpha B
   !> inside B's (narrower or equal) band, zero outside it, whatever A held before (7
   !> everywhere here); the rows kept for the fill-in are left to the factorization. Checked against set_zero and add_scaled entry by entry,
   !> and A = alpha B + s I in its one pass against add_identity after them, bit for bit.
   subroutine test_band_set_scaled(error)
      type(error_type), allocatable, intent(out) :: error
      class(matrix_type), allocatable :: a, b, expected
      type(status_type) :: stat
      integer :: n, i, j, kl_b, ku_b, with_shift
      integer(i8) :: state
      character(len=:), allocatable :: label

      state = 7_i8
      do with_shift = 0, 1
         do n = 1, 9, 4
            do kl_b = 0, 3
               do ku_b = 0, 2
                  label = "n = "//format_integer(n)//", B's bands "//format_integer(kl_b)//", "//format_integer(ku_b)// &
                     trim(merge(", shifted", "         ", with_shift == 1))
                  call new_matrix(a, n, matrix_structure_type(storage_band, 3, 2), stat, factored=.true.)
                  call new_matrix(expected, n, matrix_structure_type(storage_band, 3, 2), stat, factored=.true.)
                  call new_matrix(b, n, matrix_structure_type(storage_band, kl_b, ku_b), stat)
                  select type (a)
                  type is (band_matrix_type)
                     a%ab = 7.0_dp
                  end select
                  select type (b)
                  type is (band_matrix_type)
                     do j = 1, n
                        do i = max(1, j - ku_b), min(n, j + kl_b)
                           b%ab(b%diagonal + i - j, j) = next_value(state)
                        end do
                     end do
                  end select
                  call expected%set_zero()
                  call expected%add_scaled(-2.5_dp, b, stat)
                  if (with_shift == 1) then
                     call a%set_scaled(-2.5_dp, b, stat, shift=1.75_dp)
                     call expected%add_identity(1.75_dp)
                  else
                     call a%set_scaled(-2.5_dp, b, stat)
                  end if
                  call check(error, stat%code, status_ok, label//": status")
                  if (allocated(error)) return
                  select type (a)
                  type is (band_matrix_type)
                     select type (expected)
                     type is (band_matrix_type)
                        do j = 1, n
                           do i = max(1, j - a%ku), min(n, j + a%kl)
                              call check(error, a%ab(a%diagonal + i - j, j) == expected%ab(a%diagonal + i - j, j), &
                                 label//": entry ("//format_integer(i)//", "//format_integer(j)//")")
                              if (allocated(error)) return
                           end do
                        end do
                     end select
                  end select
               end do
            end do
         end do
      end do
   end subroutine test_band_set_scaled

   !> y + alpha B x for a band matrix (bands 3 and 2) against the sum written out here
   !> (each y_i summed over j in increasing order, alpha x_j times B(i, j)), to 1e-14:
   !> on 7 unknowns (the product diagonal by diagonal) and on 30,000, whose band no
   !> longer fits in the cache (column by column).
   subroutine test_band_product(error)
      type(error_type), allocatable, intent(out) :: error
      integer, parameter :: orders(2) = [7, 30000], kl = 3, ku = 2
      real(dp), parameter :: alpha = -1.25_dp
      class(matrix_type), allocatable :: b
      real(dp), allocatable :: x(:), y(:), expected(:)
      type(status_type) :: stat
      integer :: k, n, i, j
      integer(i8) :: state

      state = 11_i8
      do k = 1, size(orders)
         n = orders(k)
         call new_matrix(b, n, matrix_structure_type(storage_band, kl, ku), stat)
         x = [(next_value(state), i=1, n)]
         y = [(next_value(state), i=1, n)]
         expected = y
         select type (b)
         type is (band_matrix_type)
            do j = 1, n
               do i = max(1, j - ku), min(n, j + kl)
                  b%ab(b%diagonal + i - j, j) = next_value(state)
               end do
            end do
            do i = 1, n
               do j = max(1, i - kl), min(n, i + ku)
                  expected(i) = expected(i) + (alpha*x(j))*b%ab(b%diagonal + i - j, j)
               end do
            end do
         end select
         call b%multiply_add(alpha, x, y)
         ! (equal but for the rounding a compiler may change by contracting a * b + c)
         call check(error, maxval(abs(y - expected)) <= 1.0e-14_dp*maxval(abs(expected)), "n = "// &
            format_integer(n)//": largest difference "//format_real(maxval(abs(y - expected))))
         if (allocated(error)) return
      end do
   end subroutine test_band_product

   !> all_finite finds a NaN or an Inf at every entry of a dense matrix (3 x 3) and of a
   !> band (bands (2, 1) of 5, with the rows a factorization fills), and nothing in the
   !> fill rows, which are not the matrix's.
   subroutine test_all_finite(error)
      type(error_type), allocatable, intent(out) :: error
      class(matrix_type), allocatable :: a
      type(status_type) :: stat
      real(dp) :: bad(2)
      integer :: i, j, k
      bad = [ieee_value(1.0_dp, ieee_quiet_nan), ieee_value(1.0_dp, ieee_positive_inf)]
      call new_matrix(a, 3, matrix_structure_type(storage_dense, 3, 3), stat)
      call check(error, a%all_finite(), "a dense matrix of zeros")
      if (allocated(error)) return
      select type (a)
      type is (dense_matrix_type)
         do k = 1, size(bad)
            do j = 1, 3
               do i = 1, 3
                  a%a(i, j) = bad(k)
                  call check(error, .not. a%all_finite(), "dense: "//format_real(bad(k))//" at ("// &
                     format_integer(i)//", "//format_integer(j)//") not found")
                  if (allocated(error)) return
                  a%a(i, j) = 1.0_dp
               end do
            end do
         end do
      end select
      call new_matrix(a, 5, matrix_structure_type(storage_band, 2, 1), stat, factored=.true.)
      select type (a)
      type is (band_matrix_type)
         a%ab(1:a%fill, :) = bad(1)
         call check(error, a%all_finite(), "band: a NaN in the fill rows taken for the matrix's")
         if (allocated(error)) return
         do k = 1, size(bad)
            do j = 1, 5
               do i = max(1, j - 1), min(5, j + 2)
                  a%ab(a%diagonal + i - j, j) = bad(k)
                  call check(error, .not. a%all_finite(), "band: "//format_real(bad(k))//" at ("// &
                     format_integer(i)//", "//format_integer(j)//") not found")
                  if (allocated(error)) return
                  a%ab(a%diagonal + i - j, j) = 1.0_dp
               end do
            end do
         end do
      end select
   end subroutine test_all_finite

   !> The linear solver's band factorization (the written-out band LU, which keeps
   !> 1/U(j, j) on U's diagonal) names its failures: a pivot of -Inf (as an overflow in
   !> the elimination leaves it) is status_nonfinite (its reciprocal is 0), an exact zero pivot
   !> status_singular_matrix; a regular matrix of the same pattern factors and solves.
   subroutine test_band_factor_failures(error)
      type(error_type), allocatable, intent(out) :: error
      type(linear_solver_type) :: solver
      type(status_type) :: stat
      real(dp) :: x(2)
      ! (-Inf given, not reached by an overflow, which the checked build traps)
      call factor_band([1.0_dp, 0.5_dp, 1.0_dp, -ieee_value(1.0_dp, ieee_positive_inf)], status_nonfinite, &
         "a pivot of -Inf")
      if (allocated(error)) return
      call factor_band([1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], status_singular_matrix, "a zero pivot")
      if (allocated(error)) return
      call factor_band([2.0_dp, 1.0_dp, 1.0_dp, 3.0_dp], status_ok, "a regular matrix")
      if (allocated(error)) return
      ! [2 1; 1 3] x = [3; 4]: x = [1; 1]
      x = [3.0_dp, 4.0_dp]
      call solver%solve(x, stat)
      call check(error, stat%code == status_ok .and. maxval(abs(x - 1.0_dp)) <= 4.0_dp*epsilon(1.0_dp), &
         "the regular matrix's solution: "//format_real(x(1))//", "//format_real(x(2)))
   contains
      !> Factor the 2 x 2 band matrix [a11 a12; a21 a22] (entries in column order) and
      !> check the status.
      subroutine factor_band(entries, expected, what)
         real(dp), intent(in) :: entries(4)
         integer, intent(in) :: expected
         character(len=*), intent(in) :: what
         stat = status_type()
         call new_linear_solver(solver, 2, matrix_structure_type(storage_band, 1, 1), stat)
         select type (a => solver%matrix)
         type is (band_matrix_type)
            a%ab(a%diagonal, 1) = entries(1)
            a%ab(a%diagonal + 1, 1) = entries(2)
            a%ab(a%diagonal - 1, 2) = entries(3)
            a%ab(a%diagonal, 2) = entries(4)
         end select
         call solver%factor(stat)
         call check(error, stat%code, expected, what//": the factorization's status")
      end subroutine factor_band
   end subroutine test_band_factor_failures

   !> small_lu_solve_pair (a real and a complex system in one pass, Radau IIA's two)
   !> gives the real solution of small_lu_solve with the reciprocal pivots bit for bit,
   !> and the complex one of zgetrs on the same (zgetrf's) factors to 1e-13 relative,
   !> for every order up to 24, on pseudo-random matrices that need row interchanges
   !> (even orders 70 % zeros off the diagonal); its complex solution is that of the
   !> substitution column by column bit for bit (200 right-hand sides up to order 6: the
   !> orders up to 4 are written out statement by statement, the others loops).
   subroutine test_pair_solve(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp), allocatable :: a(:, :), inverse(:), b(:), x(:), rhs(:, :)
      complex(dp), allocatable :: c(:, :), lu(:, :), c_inverse(:), d(:), z(:)
      integer, allocatable :: pivots(:), c_pivots(:), lapack_pivots(:)
      integer :: n, i, j, k, info
      integer(i8) :: state
      character(len=:), allocatable :: label

      state = 20261125_i8
      do n = 1, 24
         label = "n = "//format_integer(n)
         allocate (a(n, n), inverse(n), b(n), x(n), rhs(n, 3), c(n, n), lu(n, n), c_inverse(n), d(n), z(n), &
            pivots(n), c_pivots(n), lapack_pivots(n))
         do j = 1, n
            do i = 1, n
               a(i, j) = next_value(state)
               c(i, j) = cmplx(next_value(state), next_value(state), dp)
               ! even orders mostly zeros off the diagonal (see test_written_out_lu)
               if (mod(n, 2) == 0 .and. i /= j .and. next_value(state) > -0.4_dp) then
                  a(i, j) = 0.0_dp
                  c(i, j) = (0.0_dp, 0.0_dp)
               end if
            end do
            b(j) = next_value(state)
            d(j) = cmplx(next_value(state), next_value(state), dp)
         end do
         lu = c
         call complex_lu_factor(lu, lapack_pivots, info)
         call small_lu_factor(n, c, c_pivots, info, c_inverse)
         call small_lu_factor(n, a, pivots, info, inverse)
         x = b
         call small_lu_solve(n, a, pivots, x, inverse)
         z = d
         call complex_lu_solve(lu, lapack_pivots, z, info)
         ! the right-hand sides of the pair solve: b, and d's real and imaginary parts
         rhs(:, 1) = b
         rhs(:, 2) = d%re
         rhs(:, 3) = d%im
         call small_lu_solve_pair(n, a, pivots, inverse, c, c_pivots, c_inverse, rhs(:, 1), rhs(:, 2), rhs(:, 3))
         call check(error, all(rhs(:, 1) == x), label//": the real solution differs from small_lu_solve")
         if (allocated(error)) return
         call check(error, maxval(abs(cmplx(rhs(:, 2), rhs(:, 3), dp) - z)) <= 1.0e-13_dp*maxval(abs(z)), &
            label//": the complex solution differs from zgetrs")
         if (allocated(error)) return
         do k = 1, merge(200, 0, n <= 6)
            rhs = reshape([(next_value(state), i=1, 3*n)], [n, 3])
            b = rhs(:, 2)
            x = rhs(:, 3)
            call complex_substitute_by_columns(c, c_pivots, c_inverse, b, x)
            call small_lu_solve_pair(n, a, pivots, inverse, c, c_pivots, c_inverse, rhs(:, 1), rhs(:, 2), rhs(:, 3))
            call check(error, all(rhs(:, 2) == b) .and. all(rhs(:, 3) == x), &
               label//": the complex solution differs from the column-by-column substitution")
            if (allocated(error)) return
         end do
         deallocate (a, inverse, b, x, rhs, c, lu, c_inverse, d, z, pivots, c_pivots, lapack_pivots)
      end do
   end subroutine test_pair_solve

   !> x = A^(-1) x from LU factors, row interchanges and 1/U(k, k): the interchanges, then
   !> the forward and back substitution column by column.
   pure subroutine substitute_by_columns(lu, pivots, inverse, x)
      real(dp), intent(in) :: lu(:, :), inverse(:)
      integer, intent(in) :: pivots(:)
      real(dp), intent(inout) :: x(:)
      integer :: i, k, n
      real(dp) :: swap
      n = size(x)
      do k = 1, n
         swap = x(k)
         x(k) = x(pivots(k))
         x(pivots(k)) = swap
      end do
      do k = 1, n - 1
         do i = k + 1, n
            x(i) = x(i) - x(k)*lu(i, k)
         end do
      end do
      do k = n, 1, -1
         x(k) = x(k)*inverse(k)
         do i = 1, k - 1
            x(i) = x(i) - x(k)*lu(i, k)
         end do
      end do
   end subroutine substitute_by_columns

   !> small_lu_factor, real and complex, written out statement by statement up to order 4,
   !> gives the pivots, factors, reciprocal pivots and first zero pivot of the elimination
   !> column by column (`eliminate_by_columns`) bit for bit, for orders 1 to 6 (5 and 6 the
   !> loops) on 300 pseudo-random matrices each: half of the entries off the diagonal zero
   !> (the update skips their columns), ties in magnitude (the first row of the largest
   !> magnitude is the pivot), and one matrix in ten singular (a zero column).
   subroutine test_tiny_lu(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp), allocatable :: a(:, :), a_expected(:, :), inverse(:), inverse_expected(:)
      complex(dp), allocatable :: c(:, :), c_expected(:, :), c_inverse(:), c_inverse_expected(:)
      integer, allocatable :: pivots(:), pivots_expected(:)
      integer :: n, trial, i, j, info, info_expected
      integer(i8) :: state
      character(len=:), allocatable :: label

      state = 20261126_i8
      do n = 1, 6
         allocate (a(n, n), a_expected(n, n), inverse(n), inverse_expected(n), c(n, n), c_expected(n, n), &
            c_inverse(n), c_inverse_expected(n), pivots(n), pivots_expected(n))
         do trial = 1, 300
            label = "n = "//format_integer(n)//", matrix "//format_integer(trial)
            do j = 1, n
               do i = 1, n
                  a(i, j) = next_value(state)
                  c(i, j) = cmplx(next_value(state), next_value(state), dp)
                  if (i /= j .and. next_value(state) > 0.0_dp) then
                     a(i, j) = 0.0_dp
                     c(i, j) = (0.0_dp, 0.0_dp)
                  end if
                  ! a tie: the same magnitude as the entry above it
                  if (i > 1 .and. next_value(state) > 0.8_dp) then
                     a(i, j) = -a(i - 1, j)
                     c(i, j) = cmplx(-c(i - 1, j)%re, c(i - 1, j)%im, dp)
                  end if
               end do
            end do
            if (mod(trial, 10) == 0) then
               j = 1 + mod(trial/10, n)
               a(:, j) = 0.0_dp
               c(:, j) = (0.0_dp, 0.0_dp)
            end if
            a_expected = a
            c_expected = c
            call eliminate_by_columns(a_expected, pivots_expected, info_expected, inverse_expected)
            call small_lu_factor(n, a, pivots, info, inverse)
            call check(error, info == info_expected .and. all(pivots == pivots_expected) .and. &
               all(a == a_expected) .and. all(inverse == inverse_expected .or. diagonal(a) == 0.0_dp), &
               label//": the real factors differ from the elimination column by column")
            if (allocated(error)) return
            call complex_eliminate_by_columns(c_expected, pivots_expected, info_expected, c_inverse_expected)
            call small_lu_factor(n, c, pivots, info, c_inverse)
            call check(error, info == info_expected .and. all(pivots == pivots_expected) .and. &
               all(c == c_expected) .and. all(c_inverse == c_inverse_expected .or. &
               [(c(j, j) == (0.0_dp, 0.0_dp), j=1, n)]), &
               label//": the complex factors differ from the elimination column by column")
            if (allocated(error)) return
         end do
         deallocate (a, a_expected, inverse, inverse_expected, c, c_expected, c_inverse, c_inverse_expected, &
            pivots, pivots_expected)
      end do
   contains
      pure function diagonal(a) result(d)
         real(dp), intent(in) :: a(:, :)
         real(dp) :: d(size(a, 1))
         integer :: k
         d = [(a(k, k), k=1, size(a, 1))]
      end function diagonal
   end subroutine test_tiny_lu

   !> LU with partial pivoting column by column (the first row of the largest magnitude
   !> is the pivot; a zero multiplier row entry skips its column; a zero pivot is
   !> reported and its column left), with the reciprocals of the pivots.
   pure subroutine eliminate_by_columns(a, pivots, info, inverse)
      real(dp), intent(inout) :: a(:, :)
      integer, intent(out) :: pivots(:), info
      real(dp), intent(out) :: inverse(:)
      integer :: i, j, k, p, n
      real(dp) :: row(size(a, 2))
      n = size(a, 1)
      info = 0
      do k = 1, n
         p = k
         do i = k + 1, n
            if (abs(a(i, k)) > abs(a(p, k))) p = i
         end do
         pivots(k) = p
         if (a(p, k) == 0.0_dp) then
            if (info == 0) info = k
            cycle
         end if
         row = a(k, :)
         a(k, :) = a(p, :)
         a(p, :) = row
         inverse(k) = 1.0_dp/a(k, k)
         a(k + 1:, k) = a(k + 1:, k)*inverse(k)
         do j = k + 1, n
            if (a(k, j) /= 0.0_dp) a(k + 1:, j) = a(k + 1:, j) - a(k, j)*a(k + 1:, k)
         end do
      end do
   end subroutine eliminate_by_columns

   !> eliminate_by_columns for a complex matrix: magnitudes |Re| + |Im| (LAPACK's), the
   !> reciprocal of a pivot scaled by its larger part.
   pure subroutine complex_eliminate_by_columns(a, pivots, info, inverse)
      complex(dp), intent(inout) :: a(:, :)
      integer, intent(out) :: pivots(:), info
      complex(dp), intent(out) :: inverse(:)
      integer :: i, j, k, p, n
      complex(dp) :: row(size(a, 2))
      real(dp) :: ratio, denominator
      n = size(a, 1)
      info = 0
      do k = 1, n
         p = k
         do i = k + 1, n
            if (abs(a(i, k)%re) + abs(a(i, k)%im) > abs(a(p, k)%re) + abs(a(p, k)%im)) p = i
         end do
         pivots(k) = p
         if (a(p, k) == (0.0_dp, 0.0_dp)) then
            if (info == 0) info = k
            cycle
         end if
         row = a(k, :)
         a(k, :) = a(p, :)
         a(p, :) = row
         if (abs(a(k, k)%re) >= abs(a(k, k)%im)) then
            ratio = a(k, k)%im/a(k, k)%re
            denominator = a(k, k)%re + a(k, k)%im*ratio
            inverse(k) = cmplx(1.0_dp/denominator, -ratio/denominator, dp)
         else
            ratio = a(k, k)%re/a(k, k)%im
            denominator = a(k, k)%re*ratio + a(k, k)%im
            inverse(k) = cmplx(ratio/denominator, -1.0_dp/denominator, dp)
         end if
         a(k + 1:, k) = a(k + 1:, k)*inverse(k)
         do j = k + 1, n
            if (a(k, j) /= (0.0_dp, 0.0_dp)) a(k + 1:, j) = a(k + 1:, j) - a(k, j)*a(k + 1:, k)
         end do
      end do
   end subroutine complex_eliminate_by_columns

   !> (re + i im) = C^(-1) (re + i im) from C's LU factors, row interchanges and 1/U(k, k),
   !> as substitute_by_columns on the real and imaginary parts: each complex product
   !> (a + i b)(c + i d) as (ac - bd) + i (ad + bc).
   pure subroutine complex_substitute_by_columns(lu, pivots, inverse, re, im)
      complex(dp), intent(in) :: lu(:, :), inverse(:)
      integer, intent(in) :: pivots(:)
      real(dp), intent(inout) :: re(:), im(:)
      integer :: i, k, n
      real(dp) :: swap, br, bi
      n = size(re)
      do k = 1, n
         swap = re(k)
         re(k) = re(pivots(k))
         re(pivots(k)) = swap
         swap = im(k)
         im(k) = im(pivots(k))
         im(pivots(k)) = swap
      end do
      do k = 1, n - 1
         do i = k + 1, n
            re(i) = re(i) - (re(k)*lu(i, k)%re - im(k)*lu(i, k)%im)
            im(i) = im(i) - (re(k)*lu(i, k)%im + im(k)*lu(i, k)%re)
         end do
      end do
      do k = n, 1, -1
         br = re(k)*inverse(k)%re - im(k)*inverse(k)%im
         bi = re(k)*inverse(k)%im + im(k)*inverse(k)%re
         re(k) = br
         im(k) = bi
         do i = 1, k - 1
            re(i) = re(i) - (br*lu(i, k)%re - bi*lu(i, k)%im)
            im(i) = im(i) - (br*lu(i, k)%im + bi*lu(i, k)%re)
         end do
      end do
   end subroutine complex_substitute_by_columns

   !> Pseudo-random numbers in (-1, 1) (the minimal standard generator of Park and
   !> Miller: the same sequence on every machine, no integer overflow).
   real(dp) function next_value(state)
      integer(i8), intent(inout) :: state
      state = modulo(48271_i8*state, 2147483647_i8)
      next_value = 2.0_dp*real(state, dp)/2147483647.0_dp - 1.0_dp
   end function next_value

   subroutine test_formats(error)
      type(error_type), allocatable, intent(out) :: error
      call check(error, format_count(125748_i8), "125,748")
      if (allocated(error)) return
      call check(error, format_count(999_i8), "999")
      if (allocated(error)) return
      call check(error, format_count(-2000000_i8), "-2,000,000")
      if (allocated(error)) return
      call check(error, format_real(5.2123e-5_dp, 3), "5.21E-05")
      if (allocated(error)) return
      call check(error, format_fixed(0.0881_dp, 3), "0.088")
      if (allocated(error)) return
      call check(error, format_real(1.0e4_dp, 1), "1E+04")
      if (allocated(error)) return
      call check(error, format_fixed(626.6_dp, 0), "627")
      if (allocated(error)) return
      ! exponents of three digits and non-finite numbers (no asterisks)
      call check(error, format_real(1.2345e-120_dp, 3), "1.23E-120")
      if (allocated(error)) return
      call check(error, format_real(tiny(1.0_dp), 2), "2.2E-308")
      if (allocated(error)) return
      call check(error, format_real(-huge(1.0_dp), 2), "-1.8E+308")
      if (allocated(error)) return
      call check(error, format_real(ieee_value(1.0_dp, ieee_positive_inf), 2), "inf")
   end subroutine test_formats

end module test_base
