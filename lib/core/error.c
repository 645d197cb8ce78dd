#include "core/error.h"

#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

/* A message is one line: a control character that reached it from what it quotes (a file's
   text in a JSON error, a key or a path with a newline in it) is written as "\xNN", as far as
   the buffer holds; what no longer fits is cut at a whole escape. */
static void one_line(char* message, size_t size)
{
    size_t length = strlen(message), controls = 0;
    for (size_t i = 0; i < length; i++)
        controls += (unsigned char)message[i] < 0x20 || message[i] == 0x7f;
    if (controls == 0)
        return;
    char escaped[sizeof ((cvk_error*)0)->message];
    size_t out = 0;
    for (size_t i = 0; i < length; i++) {
        unsigned char c = (unsigned char)message[i];
        bool control = c < 0x20 || c == 0x7f;
        if (out + (control ? 4 : 1) >= sizeof escaped || out + (control ? 4 : 1) >= size)
            break;
        if (control)
            out += (size_t)snprintf(escaped + out, 5, "\\x%02x", c);
        else
            escaped[out++] = (char)c;
    }
    escaped[out] = '\0';
    memcpy(message, escaped, out + 1);
}

cvk_result cvk_fail(cvk_error* error, cvk_result result, const char* format, ...)
{
    if (error) {
        error->result = result;
        va_list args;
        va_start(args, format);
        vsnprintf(error->message, sizeof error->message, format, args);
        va_end(args);
        one_line(error->message, sizeof error->message);
    }
    return result;
}

cvk_result cvk_fail_vk(cvk_error* error, const char* call, VkResult vr)
{
    cvk_result result = CVK_ERROR_VULKAN;
    if (vr == VK_ERROR_OUT_OF_HOST_MEMORY || vr == VK_ERROR_OUT_OF_DEVICE_MEMORY)
        result = CVK_ERROR_OUT_OF_MEMORY;
    if (vr == VK_ERROR_DEVICE_LOST)
        result = CVK_ERROR_DEVICE_LOST;
    return cvk_fail(error, result, "%s failed: %s (%d)", call, cvk_vk_result_name(vr), (int)vr);
}

void cvk_error_prefix(cvk_error* error, const char* format, ...)
{
    if (!error)
        return;
    char prefix[256];
    va_list args;
    va_start(args, format);
    vsnprintf(prefix, sizeof prefix, format, args);
    va_end(args);
    char joined[sizeof error->message];
    /* Truncation is acceptable: the message stays a valid, shorter sentence. */
    if (snprintf(joined, sizeof joined, "%s: %s", prefix, error->message) < 0)
        return;
    memcpy(error->message, joined, sizeof joined);
    one_line(error->message, sizeof error->message);
}

const char* cvk_result_name(cvk_result result)
{
    switch (result) {
    case CVK_SUCCESS: return "CVK_SUCCESS";
    case CVK_ERROR_INVALID_ARGUMENT: return "CVK_ERROR_INVALID_ARGUMENT";
    case CVK_ERROR_IO: return "CVK_ERROR_IO";
    case CVK_ERROR_PARSE: return "CVK_ERROR_PARSE";
    case CVK_ERROR_UNSUPPORTED: return "CVK_ERROR_UNSUPPORTED";
    case CVK_ERROR_DEVICE_LIMIT: return "CVK_ERROR_DEVICE_LIMIT";
    case CVK_ERROR_OUT_OF_MEMORY: return "CVK_ERROR_OUT_OF_MEMORY";
    case CVK_ERROR_VULKAN: return "CVK_ERROR_VULKAN";
    case CVK_ERROR_DIVERGED: return "CVK_ERROR_DIVERGED";
    case CVK_ERROR_DEVICE_LOST: return "CVK_ERROR_DEVICE_LOST";
    }
    return "CVK_ERROR_UNKNOWN";
}

const char* cvk_vk_result_name(VkResult vr)
{
    switch (vr) {
#define CASE(x) case x: return #x;
    CASE(VK_SUCCESS)
    CASE(VK_NOT_READY)
    CASE(VK_TIMEOUT)
    CASE(VK_EVENT_SET)
    CASE(VK_EVENT_RESET)
    CASE(VK_INCOMPLETE)
    CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    CASE(VK_ERROR_INITIALIZATION_FAILED)
    CASE(VK_ERROR_DEVICE_LOST)
    CASE(VK_ERROR_MEMORY_MAP_FAILED)
    CASE(VK_ERROR_LAYER_NOT_PRESENT)
    CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    CASE(VK_ERROR_TOO_MANY_OBJECTS)
    CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    CASE(VK_ERROR_FRAGMENTED_POOL)
    CASE(VK_ERROR_UNKNOWN)
    CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
#undef CASE
    default: return "VkResult (unnamed)";
    }
}

cvk_result cvk_fail_vk_for(cvk_error* error, const char* call, VkResult vr, const char* format, ...)
{
    cvk_result r = cvk_fail_vk(error, call, vr);
    if (error) {
        char what[256];
        va_list args;
        va_start(args, format);
        vsnprintf(what, sizeof what, format, args);
        va_end(args);
        cvk_error_prefix(error, "%s", what);
    }
    return r;
}

cvk_result cvk_fail_errno(cvk_error* error, const char* path, const char* action, int code)
{
    char reason[128];
    if (strerror_r(code, reason, sizeof reason) != 0)
        snprintf(reason, sizeof reason, "error %d", code);
    return cvk_fail(error, CVK_ERROR_IO, "%s: %s: %s", path, action, reason);
}
