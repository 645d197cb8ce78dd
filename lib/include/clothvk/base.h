/* clothvk/base.h — what every other header needs: the export macro, the result codes and the
 * error sentence every fallible call leaves.
 *
 * Every fallible call returns a cvk_result; on failure the optional cvk_error receives the
 * same code and one sentence naming the cause (the JSON key path, the Vulkan call and its
 * VkResult, the device limit). The library never prints, exits or aborts.
 *
 * Descriptions. Every struct you fill for the library (cvk_context_desc, cvk_scene_desc,
 * cvk_cloth_desc, cvk_collider_desc, cvk_attachment_desc, cvk_render_desc, cvk_sim_desc,
 * cvk_mesh_desc) starts from its defaults function, and you change only what you need:
 *
 *     cvk_sim_desc desc = cvk_default_sim_desc();
 *     desc.scene = &scene;
 *
 * The structs inside them (the solver, collision, wind, a cloth's aero) get their defaults
 * from the outer one (for cvk_sim_set_solver, start from cvk_sim_get_solver). Each description carries a cookie_ that its defaults function sets; a
 * description that skipped it (a zero-initialised struct, a compound literal) would have
 * zeros where the defaults belong, so the call that reads it refuses it with
 * CVK_ERROR_INVALID_ARGUMENT and a sentence that names the defaults function.
 */
#ifndef CLOTHVK_BASE_H
#define CLOTHVK_BASE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#if defined(_WIN32) && defined(CLOTHVK_BUILD_SHARED)
#define CVK_API __declspec(dllexport)
#elif defined(__GNUC__)
#define CVK_API __attribute__((visibility("default")))
#else
#define CVK_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ----------------------------------------------------------------------------------------
 * Results and errors
 * ------------------------------------------------------------------------------------- */

typedef enum cvk_result {
    CVK_SUCCESS = 0,
    CVK_ERROR_INVALID_ARGUMENT, /* a description or argument is wrong; the message names it */
    CVK_ERROR_IO,               /* a file could not be read or written */
    CVK_ERROR_PARSE,            /* scene text is not well-formed JSON (line and column given) */
    CVK_ERROR_UNSUPPORTED,      /* the device or this configuration lacks what is needed */
    CVK_ERROR_DEVICE_LIMIT,     /* the scene exceeds a limit of the device */
    CVK_ERROR_OUT_OF_MEMORY,    /* host or device memory ran out */
    CVK_ERROR_VULKAN,           /* a Vulkan call failed; the message names it and its VkResult */
    CVK_ERROR_DIVERGED,         /* the simulation blew up; the message names the frame and cloth */
    CVK_ERROR_DEVICE_LOST,      /* the device was lost (VK_ERROR_DEVICE_LOST): objects made on its
                                   context can only be destroyed; nothing more is submitted */
} cvk_result;

/* One sentence that says why a call failed, on one line (a control character in what it
   quotes is written as \xNN). Pass NULL where you do not want it. */
typedef struct cvk_error {
    cvk_result result;
    char message[512];
} cvk_error;

/* "CVK_ERROR_PARSE" and so on. */
CVK_API const char* cvk_result_name(cvk_result result);

#ifdef __cplusplus
}
#endif
#endif /* CLOTHVK_BASE_H */
