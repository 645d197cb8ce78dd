#include "core/context.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/cookie.h"
#include "core/error.h"

static const char validation_layer[] = "VK_LAYER_KHRONOS_validation";

static VKAPI_ATTR VkBool32 VKAPI_CALL on_validation_message(
    VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
    const VkDebugUtilsMessengerCallbackDataEXT* data, void* user)
{
    (void)types;
    cvk_context* context = user;
    if (!(severity & (VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                      VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT)))
        return VK_FALSE;
    atomic_fetch_add(&context->validation_messages, 1u);
    if (context->log)
        context->log(context->log_user, data->pMessage ? data->pMessage : "(no text)");
    return VK_FALSE;
}

static bool want_validation(const cvk_context_desc* desc)
{
    if (desc->validation != 0)
        return desc->validation > 0;
    const char* env = getenv("CLOTHVK_VALIDATION");
    return env && strcmp(env, "1") == 0;
}

static bool layer_available(const char* name)
{
    uint32_t count = 0;
    if (vkEnumerateInstanceLayerProperties(&count, NULL) != VK_SUCCESS || count == 0)
        return false;
    VkLayerProperties* layers = calloc(count, sizeof *layers);
    if (!layers)
        return false;
    bool found = false;
    if (vkEnumerateInstanceLayerProperties(&count, layers) == VK_SUCCESS)
        for (uint32_t i = 0; i < count && !found; i++)
            found = strcmp(layers[i].layerName, name) == 0;
    free(layers);
    return found;
}

static VkDebugUtilsMessengerCreateInfoEXT messenger_info(cvk_context* context)
{
    return (VkDebugUtilsMessengerCreateInfoEXT){
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
        .pfnUserCallback = on_validation_message,
        .pUserData = context,
    };
}

static cvk_result create_instance(cvk_context* context, cvk_error* error)
{
    if (context->validation && !layer_available(validation_layer))
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "validation was requested but %s is not installed "
                        "(Debian package vulkan-validationlayers)",
                        validation_layer);

    uint32_t loader_version = VK_API_VERSION_1_0;
    vkEnumerateInstanceVersion(&loader_version);
    if (loader_version < VK_API_VERSION_1_1)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "the Vulkan loader supports only Vulkan 1.0; clothvk needs 1.1");

    VkApplicationInfo app = {
        .sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
        .pApplicationName = "clothvk",
        .pEngineName = "clothvk",
        .engineVersion = VK_MAKE_API_VERSION(0, CLOTHVK_VERSION_MAJOR, CLOTHVK_VERSION_MINOR,
                                             CLOTHVK_VERSION_PATCH),
        .apiVersion = VK_API_VERSION_1_1,
    };
    /* Synchronisation validation catches a missing barrier, the error the layer's default
       checks cannot see. */
    VkValidationFeatureEnableEXT enables[] = {
        VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT,
    };
    VkValidationFeaturesEXT features = {
        .sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT,
        .enabledValidationFeatureCount = 1,
        .pEnabledValidationFeatures = enables,
    };
    VkDebugUtilsMessengerCreateInfoEXT messenger = messenger_info(context);
    messenger.pNext = &features;
    const char* extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
    const char* layers[] = {validation_layer};
    VkInstanceCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
        .pNext = context->validation ? &messenger : NULL,
        .pApplicationInfo = &app,
        .enabledLayerCount = context->validation ? 1 : 0,
        .ppEnabledLayerNames = layers,
        .enabledExtensionCount = context->validation ? 1 : 0,
        .ppEnabledExtensionNames = extensions,
    };
    VkResult vr = vkCreateInstance(&info, NULL, &context->instance);
    if (vr == VK_ERROR_INCOMPATIBLE_DRIVER)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "no Vulkan driver found (vkCreateInstance: VK_ERROR_INCOMPATIBLE_DRIVER); "
                        "on Debian install mesa-vulkan-drivers for the CPU device lavapipe");
    if (vr != VK_SUCCESS)
        return cvk_fail_vk(error, "vkCreateInstance", vr);

    if (!context->validation)
        return CVK_SUCCESS;
    PFN_vkCreateDebugUtilsMessengerEXT create_messenger =
        (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
            context->instance, "vkCreateDebugUtilsMessengerEXT");
    if (!create_messenger)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED, "vkCreateDebugUtilsMessengerEXT is missing");
    VkDebugUtilsMessengerCreateInfoEXT persistent = messenger_info(context);
    vr = create_messenger(context->instance, &persistent, NULL, &context->messenger);
    if (vr != VK_SUCCESS)
        return cvk_fail_vk(error, "vkCreateDebugUtilsMessengerEXT", vr);
    return CVK_SUCCESS;
}

static bool contains_ignoring_case(const char* text, const char* part)
{
    size_t n = strlen(part);
    for (; *text; text++) {
        size_t i = 0;
        while (i < n && text[i] && tolower((unsigned char)text[i]) == tolower((unsigned char)part[i]))
            i++;
        if (i == n)
            return true;
    }
    return n == 0;
}

static bool is_index(const char* text)
{
    if (!*text)
        return false;
    for (; *text; text++)
        if (!isdigit((unsigned char)*text))
            return false;
    return true;
}

static cvk_result pick_physical_device(cvk_context* context, const char* wanted, cvk_error* error)
{
    uint32_t count = 0;
    VkResult vr = vkEnumeratePhysicalDevices(context->instance, &count, NULL);
    if (vr != VK_SUCCESS)
        return cvk_fail_vk(error, "vkEnumeratePhysicalDevices", vr);
    if (count == 0)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "no Vulkan device found; on Debian install mesa-vulkan-drivers for the "
                        "CPU device lavapipe");
    VkPhysicalDevice* devices = calloc(count, sizeof *devices);
    if (!devices)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory listing devices");
    vr = vkEnumeratePhysicalDevices(context->instance, &count, devices);
    if (vr != VK_SUCCESS && vr != VK_INCOMPLETE) {
        free(devices);
        return cvk_fail_vk(error, "vkEnumeratePhysicalDevices", vr);
    }

    int chosen = -1;
    if (!wanted || !*wanted) {
        chosen = 0;
    } else if (is_index(wanted)) {
        long index = strtol(wanted, NULL, 10);
        if (index < (long)count)
            chosen = (int)index;
    } else {
        for (uint32_t i = 0; i < count && chosen < 0; i++) {
            VkPhysicalDeviceProperties p;
            vkGetPhysicalDeviceProperties(devices[i], &p);
            if (contains_ignoring_case(p.deviceName, wanted))
                chosen = (int)i;
        }
    }
    if (chosen < 0) {
        char names[384] = "";
        for (uint32_t i = 0; i < count; i++) {
            VkPhysicalDeviceProperties p;
            vkGetPhysicalDeviceProperties(devices[i], &p);
            size_t used = strlen(names);
            snprintf(names + used, sizeof names - used, "%s%u: %s", i ? ", " : "", i, p.deviceName);
        }
        free(devices);
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "no Vulkan device matches \"%s\" (devices: %s)", wanted, names);
    }
    context->physical_device = devices[chosen];
    free(devices);
    return CVK_SUCCESS;
}

/* Prefers a family with graphics and compute (the renderer draws on the same queue). */
static cvk_result pick_queue_family(cvk_context* context, cvk_error* error)
{
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(context->physical_device, &count, NULL);
    VkQueueFamilyProperties* families = calloc(count ? count : 1, sizeof *families);
    if (!families)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory listing queues");
    vkGetPhysicalDeviceQueueFamilyProperties(context->physical_device, &count, families);
    int compute = -1, both = -1;
    for (uint32_t i = 0; i < count; i++) {
        VkQueueFlags f = families[i].queueFlags;
        if ((f & VK_QUEUE_COMPUTE_BIT) && compute < 0)
            compute = (int)i;
        if ((f & VK_QUEUE_COMPUTE_BIT) && (f & VK_QUEUE_GRAPHICS_BIT) && both < 0)
            both = (int)i;
    }
    free(families);
    int chosen = both >= 0 ? both : compute;
    if (chosen < 0)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED, "the device has no compute queue");
    context->queue_family = (uint32_t)chosen;
    return CVK_SUCCESS;
}

static cvk_result create_device(cvk_context* context, cvk_error* error)
{
    float priority = 1.0f;
    VkDeviceQueueCreateInfo queue = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
        .queueFamilyIndex = context->queue_family,
        .queueCount = 1,
        .pQueuePriorities = &priority,
    };
    /* Triangles drawn as lines, and lines wider than a pixel, for the renderer's wireframe,
       anisotropic filtering for its textures and tessellation for its curved triangles, where
       the device has them. */
    VkPhysicalDeviceFeatures supported, enabled = {0};
    vkGetPhysicalDeviceFeatures(context->physical_device, &supported);
    enabled.fillModeNonSolid = supported.fillModeNonSolid;
    enabled.wideLines = supported.wideLines;
    enabled.samplerAnisotropy = supported.samplerAnisotropy;
    enabled.tessellationShader = supported.tessellationShader;
    context->tessellation = supported.tessellationShader == VK_TRUE;
    context->sampler_anisotropy = supported.samplerAnisotropy == VK_TRUE;
    context->fill_mode_non_solid = supported.fillModeNonSolid == VK_TRUE;
    context->wide_lines = supported.wideLines == VK_TRUE;
    VkDeviceCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
        .queueCreateInfoCount = 1,
        .pQueueCreateInfos = &queue,
        .pEnabledFeatures = &enabled,
    };
    VkResult vr = vkCreateDevice(context->physical_device, &info, NULL, &context->device);
    if (vr != VK_SUCCESS)
        return cvk_fail_vk(error, "vkCreateDevice", vr);
    vkGetDeviceQueue(context->device, context->queue_family, 0, &context->queue);
    return CVK_SUCCESS;
}

static cvk_result read_device_facts(cvk_context* context, cvk_error* error)
{
    vkGetPhysicalDeviceProperties(context->physical_device, &context->properties);
    vkGetPhysicalDeviceMemoryProperties(context->physical_device, &context->memory);
    if (context->properties.apiVersion < VK_API_VERSION_1_1)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "%s supports only Vulkan 1.0; clothvk needs 1.1",
                        context->properties.deviceName);

    VkPhysicalDeviceSubgroupProperties subgroup = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES,
    };
    VkPhysicalDeviceProperties2 p2 = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2,
        .pNext = &subgroup,
    };
    vkGetPhysicalDeviceProperties2(context->physical_device, &p2);
    context->subgroup_size = subgroup.subgroupSize;

    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(context->physical_device, &count, NULL);
    if (context->queue_family >= count)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "queue family %u does not exist (the device has %u)",
                        context->queue_family, count);
    VkQueueFamilyProperties* families = calloc(count, sizeof *families);
    if (!families)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory listing queues");
    vkGetPhysicalDeviceQueueFamilyProperties(context->physical_device, &count, families);
    VkQueueFamilyProperties family = families[context->queue_family];
    free(families);
    if (!(family.queueFlags & VK_QUEUE_COMPUTE_BIT))
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "queue family %u does not support compute", context->queue_family);
    context->timestamp_valid_bits =
        context->properties.limits.timestampComputeAndGraphics ? family.timestampValidBits : 0;
    context->graphics = (family.queueFlags & VK_QUEUE_GRAPHICS_BIT) != 0;
    return CVK_SUCCESS;
}

static bool adopting(const cvk_context_desc* desc)
{
    return desc->instance || desc->physical_device || desc->device || desc->queue;
}

cvk_context_desc cvk_default_context_desc(void)
{
    return (cvk_context_desc){
        .validation = 0,         /* as $CLOTHVK_VALIDATION says */
        .device_name = NULL,     /* $CLOTHVK_DEVICE, else the first device */
        .log = NULL,
        .log_user = NULL,
        .instance = VK_NULL_HANDLE, /* no adoption: the library makes its own */
        .physical_device = VK_NULL_HANDLE,
        .device = VK_NULL_HANDLE,
        .queue_family = 0,
        .queue = VK_NULL_HANDLE,
        .cookie_ = CVK_COOKIE_CONTEXT,
    };
}

cvk_result cvk_context_create(const cvk_context_desc* desc, cvk_context** out_context,
                              cvk_error* error)
{
    if (out_context)
        *out_context = NULL;
    if (!desc || !out_context)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_context_create needs a description and an output pointer");
    if (desc->cookie_ != CVK_COOKIE_CONTEXT)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "cvk_context_create: the description "
                        "did not come from cvk_default_context_desc()");
    if (adopting(desc) && !(desc->instance && desc->physical_device && desc->device && desc->queue))
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "to adopt a device, set all of instance, physical_device, device, "
                        "queue_family and queue");

    cvk_context* context = calloc(1, sizeof *context);
    if (!context)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the context");
    context->log = desc->log;
    context->log_user = desc->log_user;
    atomic_init(&context->validation_messages, 0u);

    cvk_result r = CVK_SUCCESS;
    if (adopting(desc)) {
        context->adopted = true;
        context->instance = desc->instance;
        context->physical_device = desc->physical_device;
        context->device = desc->device;
        context->queue_family = desc->queue_family;
        context->queue = desc->queue;
    } else {
        context->validation = want_validation(desc);
        const char* wanted = desc->device_name ? desc->device_name : getenv("CLOTHVK_DEVICE");
        r = create_instance(context, error);
        if (r == CVK_SUCCESS)
            r = pick_physical_device(context, wanted, error);
        if (r == CVK_SUCCESS)
            r = pick_queue_family(context, error);
    }
    if (r == CVK_SUCCESS)
        r = read_device_facts(context, error);
    if (r == CVK_SUCCESS && !context->adopted)
        r = create_device(context, error);
    if (r != CVK_SUCCESS) {
        cvk_context_destroy(context);
        return r;
    }
    *out_context = context;
    return CVK_SUCCESS;
}

void cvk_context_destroy(cvk_context* context)
{
    if (!context)
        return;
    /* The shared objects were made on the device, adopted or not: gone before it is. */
    cvk_gpu_cache_destroy(context->device, &context->cache);
    if (!context->adopted) {
        if (context->device)
            vkDestroyDevice(context->device, NULL);
        if (context->messenger) {
            PFN_vkDestroyDebugUtilsMessengerEXT destroy_messenger =
                (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
                    context->instance, "vkDestroyDebugUtilsMessengerEXT");
            if (destroy_messenger)
                destroy_messenger(context->instance, context->messenger, NULL);
        }
        if (context->instance)
            vkDestroyInstance(context->instance, NULL);
    }
    free(context);
}

uint64_t cvk_context_max_particles(const cvk_context* context)
{
    /* The largest per-particle array holds one vec4 (16 bytes) per particle. */
    uint64_t by_range = context->properties.limits.maxStorageBufferRange / 16u;
    uint64_t by_index = UINT32_MAX / 2u;
    return by_range < by_index ? by_range : by_index;
}

cvk_context_info cvk_context_get_info(const cvk_context* context)
{
    return (cvk_context_info){
        .device_name = context->properties.deviceName,
        .api_version = context->properties.apiVersion,
        .adopted = context->adopted,
        .validation = context->validation,
        .timestamps = context->timestamp_valid_bits != 0,
        .subgroup_size = context->subgroup_size,
        .max_particles = cvk_context_max_particles(context),
        .graphics = context->graphics,
        .max_image_size = cvk_context_max_image_size(context),
        .device_bytes = atomic_load(&context->device_bytes),
        .device_peak_bytes = atomic_load(&context->device_peak_bytes),
    };
}

uint32_t cvk_context_validation_message_count(const cvk_context* context)
{
    return atomic_load(&context->validation_messages);
}

uint32_t cvk_context_max_image_size(const cvk_context* context)
{
    const VkPhysicalDeviceLimits* limits = &context->properties.limits;
    uint32_t size = limits->maxImageDimension2D;
    if (limits->maxFramebufferWidth < size)
        size = limits->maxFramebufferWidth;
    if (limits->maxFramebufferHeight < size)
        size = limits->maxFramebufferHeight;
    return size;
}
