/* brume.c - the brume command-line tool (placeholder until the render command lands). */
#include <stdio.h>

#include "brume.h"

int main(void)
{
    printf("brume %s\n", brume_version());
    return 0;
}
