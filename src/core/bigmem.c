/* bigmem.c - large zeroed arrays in 2 MiB pages (bigmem.h). */
#define _GNU_SOURCE /* MADV_HUGEPAGE */
#include "core/bigmem.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

void *bigmem_calloc(size_t count, size_t size)
{
    if (size && count > SIZE_MAX / size)
        return NULL;
    size_t n = count * size;
#ifdef MADV_HUGEPAGE
    if (n >= BIGMEM_MIN && n <= SIZE_MAX - BIGMEM_PAGE) {
        size_t whole = (n + BIGMEM_PAGE - 1) / BIGMEM_PAGE * BIGMEM_PAGE; /* whole huge pages */
        void *p = NULL;
        if (posix_memalign(&p, BIGMEM_PAGE, whole) != 0)
            return NULL;
        (void)madvise(p, whole, MADV_HUGEPAGE); /* a hint: refused, the pages are 4 KiB ones */
        memset(p, 0, n); /* a fault per huge page, where calloc's memory faults per 4 KiB */
        return p;
    }
#endif
    return calloc(count, size);
}
