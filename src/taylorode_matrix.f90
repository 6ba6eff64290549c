!> Matrices of the Newton iterations: dense or banded, behind one interface, so
!> that a scheme writes its formulas once. A banded matrix keeps LAPACK band storage
!> with room for the LU fill-in; products of banded matrices are banded with the
!> summed bandwidths, so the Newton matrix of a second-order scheme is created
!> with twice the problem's bandwidths.
module taylorode_matrix
   use taylorode_kinds, only: dp
   use taylorode_linalg, only: lu_factor, lu_solve, band_lu_factor, band_lu_solve
   implicit none
   private

   public :: matrix_type, dense_matrix_type, band_matrix_type, new_matrix

   !> An n x n matrix with the operations the schemes need
   type, abstract :: matrix_type
      !> Order
      integer :: n = 0
   contains
      !> y = y + alpha A x
      procedure(multiply_add_interface), deferred :: multiply_add
      !> A = alpha B (B of the same kind, bandwidths within A's)
      procedure(scaled_interface), deferred :: set_scaled
      !> A = A + alpha B
      procedure(scaled_interface), deferred :: add_scaled
      !> A = A + alpha B C
      procedure(product_interface), deferred :: add_product
      !> A = A + alpha I
      procedure(identity_interface), deferred :: add_identity
      !> LU factorization in place; info > 0: singular
      procedure(factor_interface), deferred :: factor
      !> x = A^(-1) x with the factors
      procedure(solve_interface), deferred :: solve
   end type matrix_type

   !> Dense storage
   type, extends(matrix_type) :: dense_matrix_type
      !> Entries
      real(dp), allocatable :: a(:, :)
      !> LU pivots
      integer, allocatable :: pivots(:)
   contains
      procedure :: multiply_add => dense_multiply_add
      procedure :: set_scaled => dense_set_scaled
      procedure :: add_scaled => dense_add_scaled
      procedure :: add_product => dense_add_product
      procedure :: add_identity => dense_add_identity
      procedure :: factor => dense_factor
      procedure :: solve => dense_solve
   end type dense_matrix_type

   !> LAPACK band storage: A(i, j) in ab(kl + ku + 1 + i - j, j) for
   !> max(1, j - ku) <= i <= min(n, j + kl); the first kl rows hold the LU fill-in
   type, extends(matrix_type) :: band_matrix_type
      !> Lower and upper bandwidths
      integer :: kl = 0, ku = 0
      !> Band storage, (2 kl + ku + 1) x n
      real(dp), allocatable :: ab(:, :)
      !> LU pivots
      integer, allocatable :: pivots(:)
   contains
      procedure :: multiply_add => band_multiply_add
      procedure :: set_scaled => band_set_scaled
      procedure :: add_scaled => band_add_scaled
      procedure :: add_product => band_add_product
      procedure :: add_identity => band_add_identity
      procedure :: factor => band_factor
      procedure :: solve => band_solve
      !> Row of ab holding A(i, j)
      procedure :: row => band_row
   end type band_matrix_type

   abstract interface
      subroutine multiply_add_interface(self, alpha, x, y)
         import :: matrix_type, dp
         class(matrix_type), intent(in) :: self
         real(dp), intent(in) :: alpha
         real(dp), intent(in) :: x(:)
         real(dp), intent(inout) :: y(:)
      end subroutine multiply_add_interface
      subroutine scaled_interface(self, alpha, b)
         import :: matrix_type, dp
         class(matrix_type), intent(inout) :: self
         real(dp), intent(in) :: alpha
         class(matrix_type), intent(in) :: b
      end subroutine scaled_interface
      subroutine product_interface(self, alpha, b, c)
         import :: matrix_type, dp
         class(matrix_type), intent(inout) :: self
         real(dp), intent(in) :: alpha
         class(matrix_type), intent(in) :: b, c
      end subroutine product_interface
      subroutine identity_interface(self, alpha)
         import :: matrix_type, dp
         class(matrix_type), intent(inout) :: self
         real(dp), intent(in) :: alpha
      end subroutine identity_interface
      subroutine factor_interface(self, info)
         import :: matrix_type
         class(matrix_type), intent(inout) :: self
         integer, intent(out) :: info
      end subroutine factor_interface
      subroutine solve_interface(self, x, info)
         import :: matrix_type, dp
         class(matrix_type), intent(in) :: self
         real(dp), contiguous, intent(inout) :: x(:)
         integer, intent(out) :: info
      end subroutine solve_interface
   end interface

contains

   !> A zero n x n matrix: dense when kl < 0, else banded with bandwidths kl, ku.
   subroutine new_matrix(matrix, n, kl, ku)
      !> The new matrix
      class(matrix_type), allocatable, intent(out) :: matrix
      !> Order
      integer, intent(in) :: n
      !> Lower and upper bandwidths (kl < 0: dense)
      integer, intent(in) :: kl, ku
      type(dense_matrix_type) :: dense
      type(band_matrix_type) :: band
      if (kl < 0) then
         dense%n = n
         allocate (dense%a(n, n), dense%pivots(n))
         dense%a = 0.0_dp
         allocate (matrix, source=dense)
      else
         band%n = n
         band%kl = min(kl, n - 1)
         band%ku = min(ku, n - 1)
         allocate (band%ab(2*band%kl + band%ku + 1, n), band%pivots(n))
         band%ab = 0.0_dp
         allocate (matrix, source=band)
      end if
   end subroutine new_matrix

   subroutine dense_multiply_add(self, alpha, x, y)
      class(dense_matrix_type), intent(in) :: self
      real(dp), intent(in) :: alpha
      real(dp), intent(in) :: x(:)
      real(dp), intent(inout) :: y(:)
      integer :: j
      do j = 1, self%n
         y = y + (alpha*x(j))*self%a(:, j)
      end do
   end subroutine dense_multiply_add

   subroutine dense_set_scaled(self, alpha, b)
      class(dense_matrix_type), intent(inout) :: self
      real(dp), intent(in) :: alpha
      class(matrix_type), intent(in) :: b
      select type (b)
      type is (dense_matrix_type)
         self%a = alpha*b%a
      end select
   end subroutine dense_set_scaled

   subroutine dense_add_scaled(self, alpha, b)
      class(dense_matrix_type), intent(inout) :: self
      real(dp), intent(in) :: alpha
      class(matrix_type), intent(in) :: b
      select type (b)
      type is (dense_matrix_type)
         self%a = self%a + alpha*b%a
      end select
   end subroutine dense_add_scaled

   subroutine dense_add_product(self, alpha, b, c)
      class(dense_matrix_type), intent(inout) :: self
      real(dp), intent(in) :: alpha
      class(matrix_type), intent(in) :: b, c
      integer :: i, j
      select type (b)
      type is (dense_matrix_type)
         select type (c)
         type is (dense_matrix_type)
            do j = 1, self%n
               do i = 1, self%n
                  self%a(:, j) = self%a(:, j) + (alpha*c%a(i, j))*b%a(:, i)
               end do
            end do
         end select
      end select
   end subroutine dense_add_product

   subroutine dense_add_identity(self, alpha)
      class(dense_matrix_type), intent(inout) :: self
      real(dp), intent(in) :: alpha
      integer :: i
      do i = 1, self%n
         self%a(i, i) = self%a(i, i) + alpha
      end do
   end subroutine dense_add_identity

   subroutine dense_factor(self, info)
      class(dense_matrix_type), intent(inout) :: self
      integer, intent(out) :: info
      call lu_factor(self%a, self%pivots, info)
   end subroutine dense_factor

   subroutine dense_solve(self, x, info)
      class(dense_matrix_type), intent(in) :: self
      real(dp), contiguous, intent(inout) :: x(:)
      integer, intent(out) :: info
      call lu_solve(self%a, self%pivots, x, info)
   end subroutine dense_solve

   !> Row of ab that holds A(i, j).
   elemental integer function band_row(self, i, j)
      class(band_matrix_type), intent(in) :: self
      integer, intent(in) :: i, j
      band_row = self%kl + self%ku + 1 + i - j
   end function band_row

   subroutine band_multiply_add(self, alpha, x, y)
      class(band_matrix_type), intent(in) :: self
      real(dp), intent(in) :: alpha
      real(dp), intent(in) :: x(:)
      real(dp), intent(inout) :: y(:)
      integer :: i, j, shift
      real(dp) :: ax
      shift = self%kl + self%ku + 1
      do j = 1, self%n
         ax = alpha*x(j)
         do i = max(1, j - self%ku), min(self%n, j + self%kl)
            y(i) = y(i) + ax*self%ab(shift + i - j, j)
         end do
      end do
   end subroutine band_multiply_add

   subroutine band_set_scaled(self, alpha, b)
      class(band_matrix_type), intent(inout) :: self
      real(dp), intent(in) :: alpha
      class(matrix_type), intent(in) :: b
      self%ab = 0.0_dp
      call self%add_scaled(alpha, b)
   end subroutine band_set_scaled

   subroutine band_add_scaled(self, alpha, b)
      class(band_matrix_type), intent(inout) :: self
      real(dp), intent(in) :: alpha
      class(matrix_type), intent(in) :: b
      integer :: i, j, shift, shift_b
      select type (b)
      type is (band_matrix_type)
         shift = self%kl + self%ku + 1
         shift_b = b%kl + b%ku + 1
         do j = 1, self%n
            do i = max(1, j - b%ku), min(self%n, j + b%kl)
               self%ab(shift + i - j, j) = self%ab(shift + i - j, j) + alpha*b%ab(shift_b + i - j, j)
            end do
         end do
      end select
   end subroutine band_add_scaled

   !> A = A + alpha B C, column by column: (B C)(:, j) = sum_k B(:, k) C(k, j).
   subroutine band_add_product(self, alpha, b, c)
      class(band_matrix_type), intent(inout) :: self
      real(dp), intent(in) :: alpha
      class(matrix_type), intent(in) :: b, c
      integer :: i, j, k, shift, shift_b, shift_c
      real(dp) :: ckj
      select type (b)
      type is (band_matrix_type)
         select type (c)
         type is (band_matrix_type)
            shift = self%kl + self%ku + 1
            shift_b = b%kl + b%ku + 1
            shift_c = c%kl + c%ku + 1
            do j = 1, self%n
               do k = max(1, j - c%ku), min(self%n, j + c%kl)
                  ckj = alpha*c%ab(shift_c + k - j, j)
                  do i = max(1, k - b%ku), min(self%n, k + b%kl)
                     self%ab(shift + i - j, j) = self%ab(shift + i - j, j) + ckj*b%ab(shift_b + i - k, k)
                  end do
               end do
            end do
         end select
      end select
   end subroutine band_add_product

   subroutine band_add_identity(self, alpha)
      class(band_matrix_type), intent(inout) :: self
      real(dp), intent(in) :: alpha
      integer :: j
      do j = 1, self%n
         self%ab(self%kl + self%ku + 1, j) = self%ab(self%kl + self%ku + 1, j) + alpha
      end do
   end subroutine band_add_identity

   subroutine band_factor(self, info)
      class(band_matrix_type), intent(inout) :: self
      integer, intent(out) :: info
      call band_lu_factor(self%ab, self%kl, self%ku, self%pivots, info)
   end subroutine band_factor

   subroutine band_solve(self, x, info)
      class(band_matrix_type), intent(in) :: self
      real(dp), contiguous, intent(inout) :: x(:)
      integer, intent(out) :: info
      call band_lu_solve(self%ab, self%kl, self%ku, self%pivots, x, info)
   end subroutine band_solve

end module taylorode_matrix
