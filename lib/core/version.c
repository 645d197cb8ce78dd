#include "clothvk.h"

/* meson.build's project version reaches this file as its three numbers (lib/meson.build);
   the header's macros must say the same, or a program built against the header would report
   one version and the library another. */
_Static_assert(CVK_PROJECT_VERSION_MAJOR == CLOTHVK_VERSION_MAJOR &&
                   CVK_PROJECT_VERSION_MINOR == CLOTHVK_VERSION_MINOR &&
                   CVK_PROJECT_VERSION_PATCH == CLOTHVK_VERSION_PATCH,
               "CLOTHVK_VERSION_* in clothvk.h differ from the version in meson.build");

#define CVK_STRING(x) #x
#define CVK_VERSION_TEXT(major, minor, patch) \
    CVK_STRING(major) "." CVK_STRING(minor) "." CVK_STRING(patch)

const char* cvk_version(void)
{
    return CVK_VERSION_TEXT(CLOTHVK_VERSION_MAJOR, CLOTHVK_VERSION_MINOR, CLOTHVK_VERSION_PATCH);
}
