!> Matrices of the Newton iterations: dense or banded storage behind one interface,
!> so that a scheme writes its formulas once, and the structure a problem declares
!> for its Jacobians.
!>
!> A banded matrix keeps LAPACK band storage with room for the LU fill-in. Sums
!> into a dense matrix accept any storage; sums into a banded matrix accept banded
!> operands whose bandwidths fit. Anything else is a storage mismatch, reported as
!> a status, never silently skipped.
module taylorode_linalg_matrix
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_status, status_ok, status_invalid_argument
   use taylorode_base_memory, only: out_of_memory, real_bytes
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   implicit none
   private

   public :: matrix_structure_type, dense_structure, band_structure, storage_dense, storage_band
   public :: matrix_type, dense_matrix_type, band_matrix_type, new_matrix, stacked_structure
   public :: stacked_row_scale

   !> Every entry stored (n x n)
   integer, parameter :: storage_dense = 1
   !> LAPACK band storage: only entries with i - j <= lower and j - i <= upper are kept
   integer, parameter :: storage_band = 2

   !> Where the nonzeros of a Jacobian (or a Newton matrix) can be
   type :: matrix_structure_type
      !> storage_dense or storage_band (room is left for a sparse storage)
      integer :: storage = storage_dense
      !> Lower and upper bandwidths (banded storage only): J(i, j) = 0 for
      !> i - j > lower or j - i > upper
      integer :: lower = 0, upper = 0
   end type matrix_structure_type

   !> Band products go diagonal by diagonal (long loops) while the band has at most
   !> this many entries (1 MiB, within a core's cache); column by column (one pass
   !> over the matrix) beyond
   integer, parameter :: cached_band_entries = 131072

   !> An n x n matrix with the operations the schemes need
   type, abstract :: matrix_type
      !> Order
      integer :: n = 0
   contains
      !> Storage and bandwidths
      procedure(structure_interface), deferred :: structure
      !> y = y + alpha A x
      procedure(multiply_add_interface), deferred :: multiply_add
      !> A = 0
      procedure(zero_interface), deferred :: set_zero
      !> A = A + alpha B
      procedure(scaled_interface), deferred :: add_scaled
      !> A = A + alpha I (alpha_even on the even rows when given: a stacked matrix's
      !> second block rows, as `stacked_row_scale` scales them)
      procedure(identity_interface), deferred :: add_identity
      !> Block (r, c) of A, of order 2 n_B, interleaved: A(2i - 2 + r, 2j - 2 + c) += alpha B(i, j)
      procedure(block_interface), deferred :: add_block
      !> A = alpha B (+ s I)
      procedure :: set_scaled
      !> Whether every entry of the matrix is finite (neither NaN nor Inf)
      procedure, non_overridable :: all_finite
      !> The largest magnitude of its entries
      procedure, non_overridable :: largest_magnitude
   end type matrix_type

   !> Dense storage
   type, extends(matrix_type) :: dense_matrix_type
      !> Entries
      real(dp), allocatable :: a(:, :)
   contains
      !> Storage and bandwidths
      procedure :: structure => dense_structure_of
      !> y = y + alpha A x
      procedure :: multiply_add => dense_multiply_add
      !> A = 0
      procedure :: set_zero => dense_set_zero
      !> A = A + alpha B
      procedure :: add_scaled => dense_add_scaled
      !> A = A + alpha I (alpha_even on the even rows when given)
      procedure :: add_identity => dense_add_identity
      !> Block (r, c) of A, interleaved: A(2i - 2 + r, 2j - 2 + c) += alpha B(i, j)
      procedure :: add_block => dense_add_block
   end type dense_matrix_type

   !> Band storage: A(i, j) in ab(diagonal + i - j, j) for max(1, j - ku) <= i <=
   !> min(n, j + kl). A matrix to be factored keeps LAPACK's layout, kl rows above the
   !> band for the LU fill-in (diagonal = kl + ku + 1); any other keeps the band alone
   !> (diagonal = ku + 1), a third less memory for equal bandwidths
   type, extends(matrix_type) :: band_matrix_type
      !> Lower and upper bandwidths
      integer :: kl = 0, ku = 0
      !> Rows above the band kept for the LU fill-in (kl or 0)
      integer :: fill = 0
      !> Row of ab that holds the diagonal: fill + ku + 1
      integer :: diagonal = 1
      !> Band storage, (fill + kl + ku + 1) x n
      real(dp), allocatable :: ab(:, :)
   contains
      !> Storage and bandwidths
      procedure :: structure => band_structure_of
      !> y = y + alpha A x
      procedure :: multiply_add => band_multiply_add
      !> A = 0
      procedure :: set_zero => band_set_zero
      !> A = A + alpha B
      procedure :: add_scaled => band_add_scaled
      !> A = A + alpha I (alpha_even on the even rows when given)
      procedure :: add_identity => band_add_identity
      !> Block (r, c) of A, interleaved: A(2i - 2 + r, 2j - 2 + c) += alpha B(i, j)
      procedure :: add_block => band_add_block
      !> A = alpha B, in one pass over the band when B is a band matrix within A's bands
      procedure :: set_scaled => band_set_scaled
   end type band_matrix_type

   abstract interface
      pure function structure_interface(self) result(structure)
         import :: matrix_type, matrix_structure_type
         class(matrix_type), intent(in) :: self
         type(matrix_structure_type) :: structure
      end function structure_interface
      subroutine multiply_add_interface(self, alpha, x, y)
         import :: matrix_type, dp
         class(matrix_type), intent(in) :: self
         real(dp), intent(in) :: alpha
         real(dp), intent(in) :: x(:)
         real(dp), intent(inout) :: y(:)
      end subroutine multiply_add_interface
      subroutine zero_interface(self)
         import :: matrix_type
         class(matrix_type), intent(inout) :: self
      end subroutine zero_interface
      subroutine scaled_interface(self, alpha, b, stat)
         import :: matrix_type, dp, status_type
         class(matrix_type), intent(inout) :: self
         real(dp), intent(in) :: alpha
         class(matrix_type), intent(in) :: b
         type(status_type), intent(inout) :: stat
      end subroutine scaled_interface
      subroutine identity_interface(self, alpha, alpha_even)
         import :: matrix_type, dp
         class(matrix_type), intent(inout) :: self
         real(dp), intent(in) :: alpha
         real(dp), intent(in), optional :: alpha_even
      end subroutine identity_interface
      subroutine block_interface(self, alpha, b, row_block, column_block, stat)
         import :: matrix_type, dp, status_type
         class(matrix_type), intent(inout) :: self
         real(dp), intent(in) :: alpha
         class(matrix_type), intent(in) :: b
         integer, intent(in) :: row_block, column_block
         type(status_type), intent(inout) :: stat
      end subroutine block_interface
   end interface

contains

   !> Dense structure.
   pure function dense_structure() result(structure)
      type(matrix_structure_type) :: structure
      structure%storage = storage_dense
   end function dense_structure

   !> Banded structure with lower and upper bandwidths (each >= 0).
   pure function band_structure(lower, upper) result(structure)
      !> Lower bandwidth: J(i, j) = 0 for i - j > lower
      integer, intent(in) :: lower
      !> Upper bandwidth: J(i, j) = 0 for j - i > upper
      integer, intent(in) :: upper
      type(matrix_structure_type) :: structure
      structure%storage = storage_band
      structure%lower = lower
      structure%upper = upper
   end function band_structure

   !> Structure of the stacked 2 x 2 block matrix [[A, B], [C, D]] of order 2n whose blocks
   !> have structure `block`, rows and columns interleaved (unknown i of the first
   !> block at 2i - 1, of the second at 2i): a band (l, u) becomes the band (2l + 1, 2u + 1).
   pure function stacked_structure(block) result(structure)
      !> Structure of the n x n blocks
      type(matrix_structure_type), intent(in) :: block
      type(matrix_structure_type) :: structure
      if (block%storage == storage_band) then
         structure = band_structure(2*block%lower + 1, 2*block%upper + 1)
      else
         structure = dense_structure()
      end if
   end function stacked_structure

   !> A zero n x n matrix with the given structure; bandwidths are clamped to n - 1,
   !> and a structure that is not valid for n (negative bandwidths, unknown storage)
   !> leaves `matrix` unallocated with status_invalid_argument. A band matrix keeps
   !> room for LU factors only when `factored` says it will be factored. A matrix that
   !> cannot be allocated is status_out_of_memory (`matrix` unallocated).
   subroutine new_matrix(matrix, n, structure, stat, factored)
      !> The new matrix
      class(matrix_type), allocatable, intent(out) :: matrix
      !> Order, >= 1
      integer, intent(in) :: n
      !> Storage and bandwidths
      type(matrix_structure_type), intent(in) :: structure
      !> status_invalid_argument for an impossible structure, status_out_of_memory
      type(status_type), intent(inout) :: stat
      !> Whether the matrix will be factored in place (band: LAPACK's layout with room
      !> for the fill-in; default: no)
      logical, intent(in), optional :: factored
      type(dense_matrix_type), allocatable :: dense
      type(band_matrix_type), allocatable :: band
      integer :: memory

      if (n < 1) then
         call set_status(stat, status_invalid_argument, "matrix: the order must be at least 1")
         return
      end if
      select case (structure%storage)
      case (storage_dense)
         allocate (dense)
         dense%n = n
         allocate (dense%a(n, n), source=0.0_dp, stat=memory)
         if (memory /= 0) then
            call out_of_memory(stat, "a dense matrix", [n, n], real_bytes)
            return
         end if
         call move_alloc(dense, matrix)
      case (storage_band)
         if (structure%lower < 0 .or. structure%upper < 0) then
            call set_status(stat, status_invalid_argument, "matrix: bandwidths must be >= 0")
            return
         end if
         allocate (band)
         band%n = n
         band%kl = min(structure%lower, n - 1)
         band%ku = min(structure%upper, n - 1)
         band%fill = 0
         if (present(factored)) then
            if (factored) band%fill = band%kl
         end if
         band%diagonal = band%fill + band%ku + 1
         allocate (band%ab(band%fill + band%kl + band%ku + 1, n), source=0.0_dp, stat=memory)
         if (memory /= 0) then
            call out_of_memory(stat, "a band matrix", [band%fill + band%kl + band%ku + 1, n], real_bytes)
            return
         end if
         call move_alloc(band, matrix)
      case default
         call set_status(stat, status_invalid_argument, "matrix: unknown storage")
      end select
   end subroutine new_matrix

   !> A = alpha B, or alpha B + s I with the shift s.
   subroutine set_scaled(self, alpha, b, stat, shift)
      !> The matrix A
      class(matrix_type), intent(inout) :: self
      !> Factor
      real(dp), intent(in) :: alpha
      !> The matrix B
      class(matrix_type), intent(in) :: b
      !> status_invalid_argument on a storage mismatch
      type(status_type), intent(inout) :: stat
      !> The shift s added to the diagonal (default none)
      real(dp), intent(in), optional :: shift
      call self%set_zero()
      call self%add_scaled(alpha, b, stat)
      if (present(shift)) call self%add_identity(shift)
   end subroutine set_scaled

   !> Whether every entry of the matrix is finite: in band storage the entries of the
   !> band only (the rows kept for the fill of a factorization are not the matrix's).
   !> ieee_is_finite raises no floating-point exception, so that a NaN is found even
   !> where comparisons with it would trap.
   logical function all_finite(self)
      !> The matrix
      class(matrix_type), intent(in) :: self
      integer :: j, first, last
      all_finite = .false.
      select type (self)
      type is (dense_matrix_type)
         all_finite = finite_values(size(self%a), self%a)
         return
      type is (band_matrix_type)
         ! column by column, the band's rows of each (contiguous in the storage)
         do j = 1, self%n
            first = self%diagonal + max(1, j - self%ku) - j
            last = self%diagonal + min(self%n, j + self%kl) - j
            if (.not. finite_values(last - first + 1, self%ab(first:last, j))) return
         end do
      end select
      all_finite = .true.
   end function all_finite

   !> The largest |A(i, j)| (of the band only, for band storage).
   real(dp) function largest_magnitude(self)
      !> The matrix
      class(matrix_type), intent(in) :: self
      integer :: j, first, last
      largest_magnitude = 0.0_dp
      select type (self)
      type is (dense_matrix_type)
         largest_magnitude = maxval(abs(self%a))
      type is (band_matrix_type)
         do j = 1, self%n
            first = self%diagonal + max(1, j - self%ku) - j
            last = self%diagonal + min(self%n, j + self%kl) - j
            largest_magnitude = max(largest_magnitude, maxval(abs(self%ab(first:last, j))))
         end do
      end select
   end function largest_magnitude

   !> The factor of the second block rows (C and I) of a stacked Newton matrix
   !> [[A, B], [C, I]] whose C is -h J: 1, or 2 once h max|J| passes 1/sqrt(epsilon).
   !> With A about -h J there, the rows of A and C tie for the pivot; A's row won, and
   !> the solve recovered x as (r - B y) / A, where B y cancels r but for a relative
   !> epsilon h |lambda| / 2 (all of it beyond h |lambda| = 2/epsilon: a correction of
   !> exactly 0). Doubled, C's rows are the pivots and x follows from C x + y = 0 without
   !> the cancellation. The right-hand side's second half is 0, so the scaling changes
   !> nothing else; below the threshold (at most half the digits at stake) the matrix is
   !> as before, to the bit.
   pure real(dp) function stacked_row_scale(step_jacobian) result(scale)
      !> h max|J| (over the blocks in C)
      real(dp), intent(in) :: step_jacobian
      scale = merge(2.0_dp, 1.0_dp, step_jacobian > 1.0_dp/sqrt(epsilon(1.0_dp)))
   end function stacked_row_scale

   !> No NaN or Inf among n values (a dense matrix's storage, in one loop: its columns are
   !> a few entries long for the small systems, where nested loops cost more to enter)
   pure logical function finite_values(n, values)
      integer, intent(in) :: n
      real(dp), intent(in) :: values(n)
      integer :: i
      finite_values = .false.
      !GCC$ unroll 1
      do i = 1, n
         if (.not. ieee_is_finite(values(i))) return
      end do
      finite_values = .true.
   end function finite_values

   subroutine mismatch(stat, operation)
      type(status_type), intent(inout) :: stat
      character(len=*), intent(in) :: operation
      if (stat%code == status_ok) call set_status(stat, status_invalid_argument, &
         "matrix: "//operation//" of matrices whose storages do not fit")
   end subroutine mismatch

   pure function dense_structure_of(self) result(structure)
      class(dense_matrix_type), intent(in) :: self
      type(matrix_structure_type) :: structure
      structure = dense_structure()
   end function dense_structure_of

   subroutine dense_multiply_add(self, alpha, x, y)
      class(dense_matrix_type), intent(in) :: self
      real(dp), intent(in) :: alpha
      real(dp), intent(in) :: x(:)
      real(dp), intent(inout) :: y(:)
      integer :: i, j
      real(dp) :: ax
      do j = 1, self%n
         ax = alpha*x(j)
         !GCC$ unroll 1
         do i = 1, self%n
            y(i) = y(i) + ax*self%a(i, j)
         end do
      end do
   end subroutine dense_multiply_add

   subroutine dense_set_zero(self)
      class(dense_matrix_type), intent(inout) :: self
      self%a = 0.0_dp
   end subroutine dense_set_zero

   subroutine dense_add_scaled(self, alpha, b, stat)
      class(dense_matrix_type), intent(inout) :: self
      real(dp), intent(in) :: alpha
      class(matrix_type), intent(in) :: b
      type(status_type), intent(inout) :: stat
      integer :: i, j
      if (b%n /= self%n) then
         call mismatch(stat, "a sum")
         return
      end if
      select type (b)
      type is (dense_matrix_type)
         do j = 1, self%n
            do i = 1, self%n
               self%a(i, j) = self%a(i, j) + alpha*b%a(i, j)
            end do
         end do
      type is (band_matrix_type)
         do j = 1, self%n
            do i = max(1, j - b%ku), min(self%n, j + b%kl)
               self%a(i, j) = self%a(i, j) + alpha*b%ab(b%diagonal + i - j, j)
            end do
         end do
      class default
         call mismatch(stat, "a sum")
      end select
   end subroutine dense_add_scaled

   subroutine dense_add_identity(self, alpha, alpha_even)
      class(dense_matrix_type), intent(inout) :: self
      real(dp), intent(in) :: alpha
      real(dp), intent(in), optional :: alpha_even
      integer :: i
      if (present(alpha_even)) then
         do i = 1, self%n
            self%a(i, i) = self%a(i, i) + merge(alpha_even, alpha, mod(i, 2) == 0)
         end do
         return
      end if
      do i = 1, self%n
         self%a(i, i) = self%a(i, i) + alpha
      end do
   end subroutine dense_add_identity

   !> A(2i - 2 + r, 2j - 2 + c) += alpha B(i, j), B of order n / 2, dense or banded.
   subroutine dense_add_block(self, alpha, b, row_block, column_block, stat)
      class(dense_matrix_type), intent(inout) :: self
      real(dp), intent(in) :: alpha
      class(matrix_type), intent(in) :: b
      integer, intent(in) :: row_block, column_block
      type(status_type), intent(inout) :: stat
      integer :: i, j, row, column
      if (2*b%n /= self%n .or. min(row_block, column_block) < 1 .or. max(row_block, column_block) > 2) then
         call mismatch(stat, "a block")
         return
      end if
      select type (b)
      type is (dense_matrix_type)
         do j = 1, b%n
            column = 2*j - 2 + column_block
            do i = 1, b%n
               row = 2*i - 2 + row_block
               self%a(row, column) = self%a(row, column) + alpha*b%a(i, j)
            end do
         end do
      type is (band_matrix_type)
         do j = 1, b%n
            column = 2*j - 2 + column_block
            do i = max(1, j - b%ku), min(b%n, j + b%kl)
               row = 2*i - 2 + row_block
               self%a(row, column) = self%a(row, column) + alpha*b%ab(b%diagonal + i - j, j)
            end do
         end do
      class default
         call mismatch(stat, "a block")
      end select
   end subroutine dense_add_block

   pure function band_structure_of(self) result(structure)
      class(band_matrix_type), intent(in) :: self
      type(matrix_structure_type) :: structure
      structure = band_structure(self%kl, self%ku)
   end function band_structure_of

   subroutine band_multiply_add(self, alpha, x, y)
      class(band_matrix_type), intent(in) :: self
      real(dp), intent(in) :: alpha
      real(dp), intent(in) :: x(:)
      real(dp), intent(inout) :: y(:)
      call band_product(self%n, self%kl, self%ku, size(self%ab, 1), self%diagonal, self%ab, alpha, x, y)
   end subroutine band_multiply_add

   !> y = y + alpha A x for A in band storage ab (bandwidths kl, ku, the diagonal in row
   !> `diagonal`), ab explicit-shape: through the matrix's component its descriptor was
   !> reloaded at every entry (1.6 times the instructions).
   pure subroutine band_product(n, kl, ku, lda, diagonal, ab, alpha, x, y)
      !> Order
      integer, intent(in) :: n
      !> Bandwidths, leading dimension of ab and row of the diagonal
      integer, intent(in) :: kl, ku, lda, diagonal
      !> Band storage of A
      real(dp), intent(in) :: ab(lda, n)
      !> The factor
      real(dp), intent(in) :: alpha
      !> The vector multiplied
      real(dp), intent(in) :: x(:)
      !> The vector added to
      real(dp), intent(inout) :: y(:)
      integer :: i, j, d, row
      real(dp) :: ax
      if (lda*n <= cached_band_entries) then
         ! diagonal by diagonal: long loops instead of columns of kl + ku + 1 entries,
         ! each y(i) still summed over j in increasing order
         do d = kl, -ku, -1
            row = diagonal + d
            do j = max(1, 1 - d), min(n, n - d)
               y(j + d) = y(j + d) + (alpha*x(j))*ab(row, j)
            end do
         end do
      else
         ! column by column: one pass over a matrix that no longer fits in the cache
         do j = 1, n
            ax = alpha*x(j)
            do i = max(1, j - ku), min(n, j + kl)
               y(i) = y(i) + ax*ab(diagonal + i - j, j)
            end do
         end do
      end if
   end subroutine band_product

   subroutine band_set_zero(self)
      class(band_matrix_type), intent(inout) :: self
      self%ab = 0.0_dp
   end subroutine band_set_zero

   subroutine band_add_scaled(self, alpha, b, stat)
      class(band_matrix_type), intent(inout) :: self
      real(dp), intent(in) :: alpha
      class(matrix_type), intent(in) :: b
      type(status_type), intent(inout) :: stat
      integer :: i, j, shift, shift_b
      if (b%n /= self%n) then
         call mismatch(stat, "a sum")
         return
      end if
      select type (b)
      type is (band_matrix_type)
         if (b%kl > self%kl .or. b%ku > self%ku) then
            call mismatch(stat, "a sum")
            return
         end if
         shift = self%diagonal
         shift_b = b%diagonal
         do j = 1, self%n
            do i = max(1, j - b%ku), min(self%n, j + b%kl)
               self%ab(shift + i - j, j) = self%ab(shift + i - j, j) + alpha*b%ab(shift_b + i - j, j)
            end do
         end do
      class default
         call mismatch(stat, "a sum")
      end select
   end subroutine band_add_scaled

   !> A = alpha B (+ s I) for a band B within A's bands in one pass over the band: column
   !> j's rows j - ku ... j + kl (at ab rows first ... last), alpha B inside B's bands,
   !> zero outside, the shift added to the diagonal while the column is at hand (one pass
   !> over a large matrix, not two); the rows kept for the LU fill-in are left alone (the
   !> factorizations set them). Any other B: set_zero, then add_scaled (and add_identity).
   subroutine band_set_scaled(self, alpha, b, stat, shift)
      class(band_matrix_type), intent(inout) :: self
      real(dp), intent(in) :: alpha
      class(matrix_type), intent(in) :: b
      type(status_type), intent(inout) :: stat
      real(dp), intent(in), optional :: shift
      select type (b)
      type is (band_matrix_type)
         if (b%n == self%n .and. b%kl <= self%kl .and. b%ku <= self%ku) then
            if (present(shift)) then
               call scaled_band_into_band(self%n, self%kl, self%ku, size(self%ab, 1), self%diagonal, self%ab, alpha, &
                  b%kl, b%ku, size(b%ab, 1), b%diagonal, b%ab, .true., shift)
            else
               call scaled_band_into_band(self%n, self%kl, self%ku, size(self%ab, 1), self%diagonal, self%ab, alpha, &
                  b%kl, b%ku, size(b%ab, 1), b%diagonal, b%ab, .false., 0.0_dp)
            end if
            return
         end if
      end select
      call set_scaled(self, alpha, b, stat, shift)
   end subroutine band_set_scaled

   !> a = alpha b over a's band (kl, ku; diagonal in row `diagonal` of a), b a band
   !> matrix within it (kl_b, ku_b; diagonal in row diagonal_b): zeros outside b's band,
   !> a's other rows (kept for the LU fill-in) left alone; with `shifted`, s added to the
   !> diagonal. Explicit-shape arrays: the few entries of a column cost as much as the
   !> loops' bounds otherwise.
   pure subroutine scaled_band_into_band(n, kl, ku, lda, diagonal, a, alpha, kl_b, ku_b, ldb, diagonal_b, b, &
      shifted, s)
      !> Order
      integer, intent(in) :: n
      !> a's bandwidths, leading dimension and row of the diagonal
      integer, intent(in) :: kl, ku, lda, diagonal
      !> a's band storage
      real(dp), intent(inout) :: a(lda, n)
      !> The factor
      real(dp), intent(in) :: alpha
      !> b's bandwidths (at most a's), leading dimension and row of the diagonal
      integer, intent(in) :: kl_b, ku_b, ldb, diagonal_b
      !> b's band storage
      real(dp), intent(in) :: b(ldb, n)
      !> Whether s is added to the diagonal
      logical, intent(in) :: shifted
      !> The shift
      real(dp), intent(in) :: s
      integer :: i, j, first, last, first_b, last_b, shift
      shift = diagonal_b - diagonal
      do j = 1, n
         first = diagonal - min(ku, j - 1)
         last = diagonal + min(kl, n - j)
         first_b = max(first, diagonal - ku_b)
         last_b = min(last, diagonal + kl_b)
         !GCC$ unroll 1
         !GCC$ novector
         do i = first, first_b - 1
            a(i, j) = 0.0_dp
         end do
         !GCC$ unroll 1
         !GCC$ novector
         do i = first_b, last_b
            a(i, j) = alpha*b(i + shift, j)
         end do
         !GCC$ unroll 1
         !GCC$ novector
         do i = last_b + 1, last
            a(i, j) = 0.0_dp
         end do
         if (shifted) a(diagonal, j) = a(diagonal, j) + s
      end do
   end subroutine scaled_band_into_band

   subroutine band_add_identity(self, alpha, alpha_even)
      class(band_matrix_type), intent(inout) :: self
      real(dp), intent(in) :: alpha
      real(dp), intent(in), optional :: alpha_even
      integer :: j
      if (present(alpha_even)) then
         do j = 1, self%n
            self%ab(self%diagonal, j) = self%ab(self%diagonal, j) + merge(alpha_even, alpha, mod(j, 2) == 0)
         end do
         return
      end if
      do j = 1, self%n
         self%ab(self%diagonal, j) = self%ab(self%diagonal, j) + alpha
      end do
   end subroutine band_add_identity

   !> A(2i - 2 + r, 2j - 2 + c) += alpha B(i, j), B banded of order n / 2 with bands
   !> that fit A's once interleaved (2 kl_B + r - c <= kl_A, 2 ku_B + c - r <= ku_A).
   subroutine band_add_block(self, alpha, b, row_block, column_block, stat)
      class(band_matrix_type), intent(inout) :: self
      real(dp), intent(in) :: alpha
      class(matrix_type), intent(in) :: b
      integer, intent(in) :: row_block, column_block
      type(status_type), intent(inout) :: stat
      if (2*b%n /= self%n .or. min(row_block, column_block) < 1 .or. max(row_block, column_block) > 2) then
         call mismatch(stat, "a block")
         return
      end if
      select type (b)
      type is (band_matrix_type)
         if (2*b%kl + row_block - column_block > self%kl .or. 2*b%ku + column_block - row_block > self%ku) then
            call mismatch(stat, "a block")
            return
         end if
         call add_band_block(b%n, b%kl, b%ku, size(b%ab, 1), b%diagonal, b%ab, alpha, row_block, column_block, &
            size(self%ab, 1), self%diagonal, self%ab)
      class default
         call mismatch(stat, "a block")
      end select
   end subroutine band_add_block

   !> band_add_block's sum over explicit-shape arrays (through the matrices' components
   !> their descriptors were reloaded at every entry): a(2i - 2 + r, 2j - 2 + c) +=
   !> alpha b(i, j) in band storage, b of order n_b.
   pure subroutine add_band_block(n_b, kl_b, ku_b, ldb, diagonal_b, b, alpha, row_block, column_block, lda, &
      diagonal, a)
      !> b's order, bandwidths, leading dimension and row of the diagonal
      integer, intent(in) :: n_b, kl_b, ku_b, ldb, diagonal_b
      !> b's band storage
      real(dp), intent(in) :: b(ldb, n_b)
      !> The factor
      real(dp), intent(in) :: alpha
      !> The block (r, c), 1 or 2 each
      integer, intent(in) :: row_block, column_block
      !> a's leading dimension and row of the diagonal
      integer, intent(in) :: lda, diagonal
      !> a's band storage (order 2 n_b)
      real(dp), intent(inout) :: a(lda, 2*n_b)
      integer :: i, j, row, column
      do j = 1, n_b
         column = 2*j - 2 + column_block
         do i = max(1, j - ku_b), min(n_b, j + kl_b)
            row = 2*i - 2 + row_block
            a(diagonal + row - column, column) = a(diagonal + row - column, column) + alpha*b(diagonal_b + i - j, j)
         end do
      end do
   end subroutine add_band_block

end module taylorode_linalg_matrix
