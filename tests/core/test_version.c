/* cvk_version() is "MAJOR.MINOR.PATCH" of the header's CLOTHVK_VERSION_* macros. */
#include <stdio.h>
#include <string.h>

#include "clothvk.h"
#include "harness.h"

int main(void)
{
    char expected[64];
    snprintf(expected, sizeof expected, "%d.%d.%d", CLOTHVK_VERSION_MAJOR, CLOTHVK_VERSION_MINOR,
             CLOTHVK_VERSION_PATCH);
    const char* got = cvk_version();
    CHECK(got && strcmp(got, expected) == 0, "cvk_version() is \"%s\", the header's macros say \"%s\"",
          got ? got : "(null)", expected);
    return harness_finish(NULL);
}
