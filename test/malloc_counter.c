/* Counts heap allocations of the test program, so that a test can show that the
   integrator's step loop allocates nothing. glibc's allocator stays in charge: these
   definitions count and forward to it. Under AddressSanitizer the sanitizer owns
   malloc, so nothing is replaced and the count is -1 (the test is then skipped). */
#include <stddef.h>

#if defined(__SANITIZE_ADDRESS__)
long long taylorode_allocation_count(void) { return -1; }
#else
extern void *__libc_malloc(size_t size);
extern void *__libc_calloc(size_t count, size_t size);
extern void *__libc_realloc(void *pointer, size_t size);

static long long allocations = 0;

void *malloc(size_t size) { __atomic_add_fetch(&allocations, 1, __ATOMIC_RELAXED); return __libc_malloc(size); }
void *calloc(size_t count, size_t size) { __atomic_add_fetch(&allocations, 1, __ATOMIC_RELAXED); return __libc_calloc(count, size); }
void *realloc(void *pointer, size_t size) { __atomic_add_fetch(&allocations, 1, __ATOMIC_RELAXED); return __libc_realloc(pointer, size); }

long long taylorode_allocation_count(void) { return __atomic_load_n(&allocations, __ATOMIC_RELAXED); }
#endif
