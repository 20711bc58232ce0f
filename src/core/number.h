/* number.h - numbers read and printed the same in every locale.
 *
 * strtod, sscanf("%lf") and printf("%g") follow the calling thread's LC_NUMERIC: a program
 * that links libbrume and calls setlocale(LC_ALL, "") in a German locale would make them
 * read "0.5" as 0 and print 0,5. Files brume reads (.pbrt, phase tables, kernel tables, grid
 * sidecars) are written with a '.', so every number is read through num_strtod, and code
 * that must call a locale-dependent function runs it between num_c_begin and num_c_end. */
#ifndef BRUME_CORE_NUMBER_H
#define BRUME_CORE_NUMBER_H

#include <locale.h>

/* strtod in the "C" locale, whatever the thread's locale. */
double num_strtod(const char *s, char **end);

/* The "C" locale made current for this thread until num_c_end(returned value): for sscanf
 * and snprintf calls that read or print numbers. Nests. */
locale_t num_c_begin(void);
void num_c_end(locale_t previous);

#endif
