/* Links with `pkg-config --cflags --libs ffrf` alone; prints the library's version. */
#include <stdio.h>

#include <ffrf.h>

int main(void)
{
    int major = -1, minor = -1, patch = -1;
    ffrf_version(&major, &minor, &patch);
    printf("%d.%d.%d\n", major, minor, patch);
    return 0;
}
