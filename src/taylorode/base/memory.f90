!> Allocation that reports instead of stopping. An `allocate` without `stat=` that
!> cannot get its memory stops the program ("Error allocating N bytes"); every array of
!> the library whose size grows with the problem is allocated with `stat=` instead, here
!> (`sized`) or beside a call of `out_of_memory`, and a failure is status_out_of_memory
!> with a message that names the array and the bytes it needed.
module taylorode_base_memory
   use taylorode_base_kinds, only: dp, i8
   use taylorode_base_status, only: status_type, set_status, status_ok, status_out_of_memory
   implicit none
   private

   public :: sized, out_of_memory, real_bytes, integer_bytes, complex_bytes

   !> Bytes of one real(dp), one default integer and one complex(dp)
   integer, parameter :: real_bytes = storage_size(1.0_dp)/8, integer_bytes = storage_size(1)/8, &
      complex_bytes = storage_size((1.0_dp, 1.0_dp))/8

   !> A work array allocated again only when its shape differs (vector or matrix), with
   !> a status: status_out_of_memory leaves it unallocated
   interface sized
      module procedure sized_vector, sized_matrix
   end interface sized

contains

   !> stat = status_out_of_memory: "out of memory: cannot allocate <what> (<extents>,
   !> <bytes> bytes)", the extents joined by " x " (several arrays of one size: their
   !> number first). Built in a fixed-length buffer (safe from any thread).
   pure subroutine out_of_memory(stat, what, extents, element_bytes)
      !> Status to set
      type(status_type), intent(inout) :: stat
      !> What could not be allocated ("a dense matrix", "the stepper's work arrays")
      character(len=*), intent(in) :: what
      !> Its shape
      integer, intent(in) :: extents(:)
      !> Bytes of one element (real_bytes, integer_bytes, complex_bytes)
      integer, intent(in) :: element_bytes
      character(len=120) :: shape
      character(len=40) :: amount
      character(len=400) :: text
      real(dp) :: bytes
      bytes = real(element_bytes, dp)*product(real(extents, dp))
      write (shape, '(*(i0, :, " x "))') extents
      if (bytes < real(huge(1_i8), dp)) then
         write (amount, '(i0)') int(bytes, i8)
      else
         write (amount, '(es10.3)') bytes
      end if
      write (text, '("out of memory: cannot allocate ", a, " (", a, ", ", a, " bytes)")') what, trim(shape), &
         trim(adjustl(amount))
      call set_status(stat, status_out_of_memory, trim(text))
   end subroutine out_of_memory

   !> A work array of n entries: allocated again only when its size differs; of no
   !> entries it is left unallocated (an array a given use does not need costs no
   !> allocation: a work array sized `merge(n, 0, needed)` is allocated exactly when
   !> needed). Nothing is done after an earlier failure (stat not ok), so that a sequence
   !> of calls stops at the first.
   pure subroutine sized_vector(work, n, what, stat)
      !> The work array
      real(dp), allocatable, intent(inout) :: work(:)
      !> Its size
      integer, intent(in) :: n
      !> What it is, for the message
      character(len=*), intent(in) :: what
      !> status_out_of_memory when it cannot be allocated (it is then unallocated)
      type(status_type), intent(inout) :: stat
      integer :: memory
      if (stat%code /= status_ok) return
      if (allocated(work)) then
         if (size(work) == n) return
         deallocate (work)
      end if
      if (n == 0) return
      allocate (work(n), stat=memory)
      if (memory /= 0) call out_of_memory(stat, what, [n], real_bytes)
   end subroutine sized_vector

   !> A work matrix of rows x columns: allocated again only when its shape differs, left
   !> unallocated without entries (see sized_vector).
   pure subroutine sized_matrix(work, rows, columns, what, stat)
      !> The work matrix
      real(dp), allocatable, intent(inout) :: work(:, :)
      !> Its shape
      integer, intent(in) :: rows, columns
      !> What it is, for the message
      character(len=*), intent(in) :: what
      !> status_out_of_memory when it cannot be allocated (it is then unallocated)
      type(status_type), intent(inout) :: stat
      integer :: memory
      if (stat%code /= status_ok) return
      if (allocated(work)) then
         if (size(work, 1) == rows .and. size(work, 2) == columns) return
         deallocate (work)
      end if
      if (rows == 0 .or. columns == 0) return
      allocate (work(rows, columns), stat=memory)
      if (memory /= 0) call out_of_memory(stat, what, [rows, columns], real_bytes)
   end subroutine sized_matrix

end module taylorode_base_memory
