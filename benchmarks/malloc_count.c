/* malloc-counting LD_PRELOAD shim (glibc). Interposes the allocation functions, forwards them to
 * glibc's __libc_* implementations and, between malloc_count_start() and malloc_count_stop(),
 * counts every call. Used by alloc_check.c (found there with dlsym, so the checker refuses to
 * report anything when the shim is not loaded):
 *
 *   cc -O2 -shared -fPIC benchmarks/malloc_count.c -o libmalloc_count.so
 *   LD_PRELOAD=./libmalloc_count.so ./alloc_check
 *
 * Counting is process-wide (all threads), so allocations by SUNDIALS/GSL/libc inside the timed
 * region are seen as well. */
#define _GNU_SOURCE
#include <errno.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdlib.h>

extern void *__libc_malloc(size_t size);
extern void *__libc_calloc(size_t n, size_t size);
extern void *__libc_realloc(void *p, size_t size);
extern void __libc_free(void *p);
extern void *__libc_memalign(size_t alignment, size_t size);

static atomic_int active;
static atomic_long n_alloc, n_free, n_bytes;

#define COUNT_ALLOC(sz)                                                                          \
    do {                                                                                         \
        if (atomic_load_explicit(&active, memory_order_relaxed)) {                               \
            atomic_fetch_add(&n_alloc, 1);                                                       \
            atomic_fetch_add(&n_bytes, (long)(sz));                                              \
        }                                                                                        \
    } while (0)

__attribute__((visibility("default"))) int malloc_count_loaded(void) { return 1; }

__attribute__((visibility("default"))) void malloc_count_start(void)
{
    atomic_store(&n_alloc, 0);
    atomic_store(&n_free, 0);
    atomic_store(&n_bytes, 0);
    atomic_store(&active, 1);
}

__attribute__((visibility("default"))) void malloc_count_stop(long *allocs, long *frees,
                                                              long *bytes)
{
    atomic_store(&active, 0);
    if (allocs) *allocs = atomic_load(&n_alloc);
    if (frees) *frees = atomic_load(&n_free);
    if (bytes) *bytes = atomic_load(&n_bytes);
}

void *malloc(size_t size)
{
    COUNT_ALLOC(size);
    return __libc_malloc(size);
}

void *calloc(size_t n, size_t size)
{
    COUNT_ALLOC(n * size);
    return __libc_calloc(n, size);
}

void *realloc(void *p, size_t size)
{
    COUNT_ALLOC(size);
    return __libc_realloc(p, size);
}

void free(void *p)
{
    if (p && atomic_load_explicit(&active, memory_order_relaxed)) atomic_fetch_add(&n_free, 1);
    __libc_free(p);
}

void *memalign(size_t alignment, size_t size)
{
    COUNT_ALLOC(size);
    return __libc_memalign(alignment, size);
}

void *aligned_alloc(size_t alignment, size_t size)
{
    COUNT_ALLOC(size);
    return __libc_memalign(alignment, size);
}

int posix_memalign(void **out, size_t alignment, size_t size)
{
    COUNT_ALLOC(size);
    void *p = __libc_memalign(alignment, size);
    if (!p) return ENOMEM;
    *out = p;
    return 0;
}

void *valloc(size_t size)
{
    COUNT_ALLOC(size);
    return __libc_memalign(4096, size);
}
