/* number.c - numbers read and printed the same in every locale (number.h). */
#include "core/number.h"

#include <pthread.h>
#include <stdlib.h>

static locale_t g_c;
static pthread_once_t g_once = PTHREAD_ONCE_INIT;

static void make_c(void) { g_c = newlocale(LC_ALL_MASK, "C", (locale_t)0); }

locale_t num_c_begin(void)
{
    pthread_once(&g_once, make_c);
    /* without a "C" locale object (out of memory at the first call), the thread's own */
    return g_c ? uselocale(g_c) : (locale_t)0;
}

void num_c_end(locale_t previous)
{
    if (previous)
        uselocale(previous);
}

double num_strtod(const char *s, char **end)
{
    locale_t old = num_c_begin();
    double v = strtod(s, end);
    num_c_end(old);
    return v;
}
