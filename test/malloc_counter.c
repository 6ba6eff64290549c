/* Counts heap allocations of the test program, so that a test can show that the
   integrator's step loop allocates nothing. glibc's allocator stays in charge: these
   definitions count and forward to it. */
#include <stddef.h>

extern void *__libc_malloc(size_t size);
extern void *__libc_calloc(size_t count, size_t size);
extern void *__libc_realloc(void *pointer, size_t size);

static long long allocations = 0;

void *malloc(size_t size) { allocations++; return __libc_malloc(size); }
void *calloc(size_t count, size_t size) { allocations++; return __libc_calloc(count, size); }
void *realloc(void *pointer, size_t size) { allocations++; return __libc_realloc(pointer, size); }

long long taylorode_allocation_count(void) { return allocations; }
