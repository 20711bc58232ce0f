/* bigmem.h - large zeroed arrays (a render's film, an image's pixels) in 2 MiB pages where
 * the kernel gives them.
 *
 * The first touch of each 4 KiB page of fresh memory is a page fault. On the project's EPYC
 * VM a fault costs some 10 to 40 us (a first touch traps to the hypervisor, even of a page
 * that madvise(MADV_POPULATE_WRITE) populated: 13 MB touched page by page took 136-181 ms,
 * 70 ms populated, 10-14 ms in 2 MiB pages, at load 6-9; docs/blasi.md, "Times"), so a
 * 400 x 400 render's film and image (13 MB) cost tens of ms.
 * Arrays of BIGMEM_MIN bytes or more are therefore aligned to 2 MiB, rounded up to whole
 * huge pages and marked for Linux's transparent huge pages (MADV_HUGEPAGE: used when the
 * system's setting is `madvise` or `always`, ignored under `never` or elsewhere); smaller
 * ones are calloc's.
 *
 * Ownership: the caller frees the array with free(). Failure: NULL, nothing allocated. */
#ifndef BRUME_CORE_BIGMEM_H
#define BRUME_CORE_BIGMEM_H

#include <stddef.h>

#define BIGMEM_PAGE ((size_t)2 << 20) /* bytes: one huge page */
#define BIGMEM_MIN ((size_t)512 << 10) /* bytes: from a quarter of a huge page up (a 400 x 400 film's
                                        sample counts, 640 KB: one fault instead of 320); at most
                                        1.5 MiB of a huge page is left unused */

/* count x size zeroed bytes, as calloc; NULL on overflow or out of memory. */
void *bigmem_calloc(size_t count, size_t size);

#endif
