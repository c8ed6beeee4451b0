/* A program that includes only the umbrella header, as an embedding application does, sees the
 * version macros (<fputlab.h> includes <fputlab/version.h>) and they match the library. */
#include <stdio.h>
#include <string.h>
#include <fputlab.h>

#if !defined(FPL_VERSION_MAJOR) || !defined(FPL_VERSION_MINOR) || !defined(FPL_VERSION_PATCH)
#error "<fputlab.h> must declare FPL_VERSION_MAJOR/MINOR/PATCH"
#endif

int main(void)
{
    char expected[64];
    snprintf(expected, sizeof expected, "%d.%d.%d", FPL_VERSION_MAJOR, FPL_VERSION_MINOR,
             FPL_VERSION_PATCH);
    if (strcmp(expected, fpl_version()) != 0 || strcmp(FPL_VERSION_STRING, fpl_version()) != 0) {
        fprintf(stderr, "FPL_VERSION_* %s vs fpl_version() %s\n", expected, fpl_version());
        return 1;
    }
    if (FPL_VERSION_NUMBER != FPL_VERSION_ENCODE(FPL_VERSION_MAJOR, FPL_VERSION_MINOR,
                                                 FPL_VERSION_PATCH)) {
        fprintf(stderr, "FPL_VERSION_NUMBER %d\n", FPL_VERSION_NUMBER);
        return 1;
    }
    printf("fputlab %s: the umbrella header declares the version\n", fpl_version());
    return 0;
}
