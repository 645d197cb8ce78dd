/* Filling cvk_error: every failure path ends in one of these. */
#ifndef CVK_ERROR_H
#define CVK_ERROR_H

#include "clothvk.h"

/* Writes result and the formatted sentence into `error` (when not NULL); returns result. */
cvk_result cvk_fail(cvk_error* error, cvk_result result, const char* format, ...)
    __attribute__((format(printf, 3, 4)));

/* "vkCreateDevice failed: VK_ERROR_OUT_OF_HOST_MEMORY"; maps memory errors to
   CVK_ERROR_OUT_OF_MEMORY and the rest to CVK_ERROR_VULKAN. */
cvk_result cvk_fail_vk(cvk_error* error, const char* call, VkResult vr);

/* cvk_fail_vk with "what: " in front, what formatted from `format`: the object the call was
   making ("positions (160000 bytes): vkCreateBuffer failed: ..."). */
cvk_result cvk_fail_vk_for(cvk_error* error, const char* call, VkResult vr, const char* format, ...)
    __attribute__((format(printf, 4, 5)));

/* CVK_ERROR_IO with "path: action: strerror(code)". */
cvk_result cvk_fail_errno(cvk_error* error, const char* path, const char* action, int code);

/* Puts "prefix: " in front of an existing message (for callers that add context). */
void cvk_error_prefix(cvk_error* error, const char* format, ...) __attribute__((format(printf, 2, 3)));

const char* cvk_vk_result_name(VkResult vr);

#endif
