/* Counts heap allocations of the test program, so that a test can show that the
   integrator's step loop allocates nothing, and makes large ones fail on request, so
   that a test can show that every allocation of an integration that cannot get its
   memory ends in a status. glibc's allocator stays in charge: these definitions count
   and forward to it. Under AddressSanitizer the sanitizer owns malloc, so nothing is
   replaced, the count is -1 and no allocation fails (those tests are then skipped). */
#include <errno.h>
#include <stddef.h>

#if defined(__SANITIZE_ADDRESS__)
long long taylorode_allocation_count(void) { return -1; }
void taylorode_fail_allocations(long long min_size, long long allowed) { (void)min_size; (void)allowed; }
long long taylorode_large_allocations(void) { return -1; }
#else
extern void *__libc_malloc(size_t size);
extern void *__libc_calloc(size_t count, size_t size);
extern void *__libc_realloc(void *pointer, size_t size);

static long long allocations = 0;
/* Requests of at least fail_min_size bytes (none while it is < 0) fail once
   fail_allowed of them have been granted, as when memory runs out; large_requests
   counts them */
static long long fail_min_size = -1, fail_allowed = 0, large_requests = 0;

static int refused(size_t size) {
  if (__atomic_load_n(&fail_min_size, __ATOMIC_RELAXED) < 0 ||
      size < (size_t)__atomic_load_n(&fail_min_size, __ATOMIC_RELAXED))
    return 0;
  if (__atomic_add_fetch(&large_requests, 1, __ATOMIC_RELAXED) <= __atomic_load_n(&fail_allowed, __ATOMIC_RELAXED))
    return 0;
  errno = ENOMEM;
  return 1;
}

void *malloc(size_t size) {
  __atomic_add_fetch(&allocations, 1, __ATOMIC_RELAXED);
  return refused(size) ? NULL : __libc_malloc(size);
}
void *calloc(size_t count, size_t size) {
  __atomic_add_fetch(&allocations, 1, __ATOMIC_RELAXED);
  return refused(count * size) ? NULL : __libc_calloc(count, size);
}
void *realloc(void *pointer, size_t size) {
  __atomic_add_fetch(&allocations, 1, __ATOMIC_RELAXED);
  return refused(size) ? NULL : __libc_realloc(pointer, size);
}

long long taylorode_allocation_count(void) { return __atomic_load_n(&allocations, __ATOMIC_RELAXED); }

/* From now on, requests of at least min_size bytes fail after `allowed` of them were
   granted; min_size < 0 ends that */
void taylorode_fail_allocations(long long min_size, long long allowed) {
  __atomic_store_n(&large_requests, 0, __ATOMIC_RELAXED);
  __atomic_store_n(&fail_allowed, allowed, __ATOMIC_RELAXED);
  __atomic_store_n(&fail_min_size, min_size, __ATOMIC_RELAXED);
}

/* Requests of at least the size given to taylorode_fail_allocations since that call */
long long taylorode_large_allocations(void) { return __atomic_load_n(&large_requests, __ATOMIC_RELAXED); }
#endif
