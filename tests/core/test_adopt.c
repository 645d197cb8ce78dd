/* The library lives inside an application's Vulkan:
   - it adopts a VkInstance, VkPhysicalDevice, VkDevice and VkQueue the test made itself,
     and reports adopted == true;
   - cvk_sim_record into the test's own command buffer, submitted twice (3 frames each), gives
     bit for bit the positions of cvk_sim_step(sim, 6) on a library-made context on the same
     device, and the cloth did move;
   - cvk_sim_record refuses the host solver gs-cpu, and adoption with only some handles set is
     refused, each with its exact message;
   - cvk_context_destroy leaves the adopted device alive: the test still waits on it and
     submits to it before destroying it itself;
   - the test's own debug messenger (synchronisation validation on) sees no message; this also
     catches any object clothvk left on the adopted device, which vkDestroyDevice reports
     (VUID-vkDestroyDevice-device-00378). */
#include "harness.h"

/* The application's side: everything here is made and destroyed by the test. */
typedef struct app {
    VkInstance instance;
    VkDebugUtilsMessengerEXT messenger;
    VkPhysicalDevice physical_device;
    uint32_t queue_family;
    VkDevice device;
    VkQueue queue;
    VkCommandPool pool;
    VkFence fence;
    uint32_t messages; /* validation warnings and errors seen by the test's messenger */
} app;

static const char validation_layer[] = "VK_LAYER_KHRONOS_validation";

static void require_vk(VkResult vr, const char* call)
{
    if (vr != VK_SUCCESS) {
        fprintf(stderr, "FAILED: %s returned VkResult %d\n", call, (int)vr);
        exit(1);
    }
}

static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                 VkDebugUtilsMessageTypeFlagsEXT types,
                                                 const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                 void* user)
{
    (void)types;
    app* a = user;
    if (!(severity & (VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                      VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT)))
        return VK_FALSE;
    a->messages++;
    fprintf(stderr, "validation (application's messenger): %s\n",
            data->pMessage ? data->pMessage : "(no text)");
    return VK_FALSE;
}

static bool layer_installed(void)
{
    uint32_t count = 0;
    require_vk(vkEnumerateInstanceLayerProperties(&count, NULL), "vkEnumerateInstanceLayerProperties");
    VkLayerProperties* layers = calloc(count ? count : 1, sizeof *layers);
    if (!layers) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    require_vk(vkEnumerateInstanceLayerProperties(&count, layers), "vkEnumerateInstanceLayerProperties");
    bool found = false;
    for (uint32_t i = 0; i < count && !found; i++)
        found = strcmp(layers[i].layerName, validation_layer) == 0;
    free(layers);
    return found;
}

static VkDebugUtilsMessengerCreateInfoEXT messenger_info(app* a)
{
    return (VkDebugUtilsMessengerCreateInfoEXT){
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
        .pfnUserCallback = on_message,
        .pUserData = a,
    };
}

/* Vulkan 1.1 with the validation layer, synchronisation validation and a messenger, as an
   application that wants its own validation would make it. */
static void app_create_instance(app* a)
{
    if (!layer_installed()) {
        fprintf(stderr, "FAILED: this test needs %s on the application's own instance and it is "
                        "not installed (Debian package vulkan-validationlayers)\n",
                validation_layer);
        exit(1);
    }
    VkApplicationInfo info = {
        .sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
        .pApplicationName = "test_adopt",
        .apiVersion = VK_API_VERSION_1_1,
    };
    VkValidationFeatureEnableEXT enables[] = {
        VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT,
    };
    VkValidationFeaturesEXT features = {
        .sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT,
        .enabledValidationFeatureCount = 1,
        .pEnabledValidationFeatures = enables,
    };
    /* Chained here too, so that messages about instance creation itself are counted. */
    VkDebugUtilsMessengerCreateInfoEXT during_create = messenger_info(a);
    during_create.pNext = &features;
    const char* layers[] = {validation_layer};
    const char* extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
    VkInstanceCreateInfo create = {
        .sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
        .pNext = &during_create,
        .pApplicationInfo = &info,
        .enabledLayerCount = 1,
        .ppEnabledLayerNames = layers,
        .enabledExtensionCount = 1,
        .ppEnabledExtensionNames = extensions,
    };
    require_vk(vkCreateInstance(&create, NULL, &a->instance), "vkCreateInstance");
    PFN_vkCreateDebugUtilsMessengerEXT create_messenger =
        (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(a->instance,
                                                                  "vkCreateDebugUtilsMessengerEXT");
    if (!create_messenger) {
        fprintf(stderr, "FAILED: vkCreateDebugUtilsMessengerEXT is missing\n");
        exit(1);
    }
    VkDebugUtilsMessengerCreateInfoEXT persistent = messenger_info(a);
    require_vk(create_messenger(a->instance, &persistent, NULL, &a->messenger),
               "vkCreateDebugUtilsMessengerEXT");
}

/* The first device and a compute queue family, graphics + compute where there is one. */
static void app_pick_device(app* a)
{
    uint32_t count = 1;
    VkResult vr = vkEnumeratePhysicalDevices(a->instance, &count, &a->physical_device);
    if ((vr != VK_SUCCESS && vr != VK_INCOMPLETE) || count == 0) {
        fprintf(stderr, "FAILED: no Vulkan device (vkEnumeratePhysicalDevices: %d)\n", (int)vr);
        exit(1);
    }
    uint32_t families = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(a->physical_device, &families, NULL);
    VkQueueFamilyProperties* props = calloc(families ? families : 1, sizeof *props);
    if (!props) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    vkGetPhysicalDeviceQueueFamilyProperties(a->physical_device, &families, props);
    int compute = -1, both = -1;
    for (uint32_t i = 0; i < families; i++) {
        VkQueueFlags f = props[i].queueFlags;
        if ((f & VK_QUEUE_COMPUTE_BIT) && compute < 0)
            compute = (int)i;
        if ((f & VK_QUEUE_COMPUTE_BIT) && (f & VK_QUEUE_GRAPHICS_BIT) && both < 0)
            both = (int)i;
    }
    free(props);
    if (compute < 0) {
        fprintf(stderr, "FAILED: the first device has no compute queue family\n");
        exit(1);
    }
    a->queue_family = (uint32_t)(both >= 0 ? both : compute);
}

static void app_create(app* a)
{
    memset(a, 0, sizeof *a);
    app_create_instance(a);
    app_pick_device(a);
    float priority = 1.0f;
    VkDeviceQueueCreateInfo queue = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
        .queueFamilyIndex = a->queue_family,
        .queueCount = 1,
        .pQueuePriorities = &priority,
    };
    VkDeviceCreateInfo device = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
        .queueCreateInfoCount = 1,
        .pQueueCreateInfos = &queue,
    };
    require_vk(vkCreateDevice(a->physical_device, &device, NULL, &a->device), "vkCreateDevice");
    vkGetDeviceQueue(a->device, a->queue_family, 0, &a->queue);
    VkCommandPoolCreateInfo pool = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
        .queueFamilyIndex = a->queue_family,
    };
    require_vk(vkCreateCommandPool(a->device, &pool, NULL, &a->pool), "vkCreateCommandPool");
    VkFenceCreateInfo fence = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    require_vk(vkCreateFence(a->device, &fence, NULL, &a->fence), "vkCreateFence");
}

static void app_destroy(app* a)
{
    vkDestroyFence(a->device, a->fence, NULL);
    vkDestroyCommandPool(a->device, a->pool, NULL);
    vkDestroyDevice(a->device, NULL);
    PFN_vkDestroyDebugUtilsMessengerEXT destroy_messenger =
        (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(a->instance,
                                                                   "vkDestroyDebugUtilsMessengerEXT");
    if (destroy_messenger)
        destroy_messenger(a->instance, a->messenger, NULL);
    vkDestroyInstance(a->instance, NULL);
}

static VkCommandBuffer app_command_buffer(app* a)
{
    VkCommandBufferAllocateInfo info = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
        .commandPool = a->pool,
        .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
        .commandBufferCount = 1,
    };
    VkCommandBuffer cmd;
    require_vk(vkAllocateCommandBuffers(a->device, &info, &cmd), "vkAllocateCommandBuffers");
    return cmd;
}

static void app_begin(VkCommandBuffer cmd)
{
    VkCommandBufferBeginInfo info = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    require_vk(vkBeginCommandBuffer(cmd, &info), "vkBeginCommandBuffer");
}

static void app_submit_and_wait(app* a, VkCommandBuffer cmd)
{
    VkSubmitInfo submit = {
        .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
        .commandBufferCount = 1,
        .pCommandBuffers = &cmd,
    };
    require_vk(vkQueueSubmit(a->queue, 1, &submit, a->fence), "vkQueueSubmit");
    require_vk(vkWaitForFences(a->device, 1, &a->fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
    require_vk(vkResetFences(a->device, 1, &a->fence), "vkResetFences");
}

/* ---- the scene: a 24 x 16 cloth, horizontal at y = 1, pinned at the two corners of v = 0 ---- */

enum { GRID_U = 24, GRID_V = 16 };
static const uint32_t corner_pins[2][2] = {{0, 0}, {GRID_U - 1, 0}};

static void make_scene(cvk_cloth_desc* cloth, cvk_scene_desc* scene, cvk_linear_solver linear)
{
    *cloth = cvk_default_cloth_desc();
    cloth->grid[0] = GRID_U;
    cloth->grid[1] = GRID_V;
    cloth->stiffness.shear = 1e5f;
    cloth->pins = corner_pins;
    cloth->pin_count = 2;
    *scene = cvk_default_scene_desc();
    scene->cloths = cloth;
    scene->cloth_count = 1;
    scene->solver.linear = linear;
}

static cvk_sim* make_sim(cvk_context* ctx, cvk_linear_solver linear)
{
    cvk_cloth_desc cloth;
    cvk_scene_desc scene;
    make_scene(&cloth, &scene, linear);
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    return sim;
}

/* ---- the facts ------------------------------------------------------------------------------ */

static const char partial_message[] =
    "to adopt a device, set all of instance, physical_device, device, queue_family and queue";

static void adoption_needs_every_handle(app* a)
{
    struct {
        const char* what;
        cvk_context_desc desc;
    } partial[3] = {
        {"instance and physical_device only", cvk_default_context_desc()},
        {"all but the queue", cvk_default_context_desc()},
        {"device and queue only", cvk_default_context_desc()},
    };
    partial[0].desc.instance = a->instance;
    partial[0].desc.physical_device = a->physical_device;
    partial[1].desc.instance = a->instance;
    partial[1].desc.physical_device = a->physical_device;
    partial[1].desc.device = a->device;
    partial[1].desc.queue_family = a->queue_family;
    partial[2].desc.device = a->device;
    partial[2].desc.queue = a->queue;
    for (size_t i = 0; i < sizeof partial / sizeof partial[0]; i++) {
        cvk_error err = {0};
        cvk_context* ctx = NULL;
        cvk_result r = cvk_context_create(&partial[i].desc, &ctx, &err);
        CHECK(r == CVK_ERROR_INVALID_ARGUMENT, "%s: cvk_context_create returned %s, not "
              "CVK_ERROR_INVALID_ARGUMENT", partial[i].what, cvk_result_name(r));
        CHECK(err.result == r, "%s: the error says %s, the call returned %s", partial[i].what,
              cvk_result_name(err.result), cvk_result_name(r));
        CHECK(strcmp(err.message, partial_message) == 0, "%s: message \"%s\"", partial[i].what,
              err.message);
        CHECK(ctx == NULL, "%s: a context came back from a failed adoption", partial[i].what);
        if (r == CVK_SUCCESS)
            cvk_context_destroy(ctx);
    }
}

static cvk_context* adopt(app* a)
{
    cvk_context_desc desc = cvk_default_context_desc();
    desc.log = harness_log;
    desc.instance = a->instance;
    desc.physical_device = a->physical_device;
    desc.device = a->device;
    desc.queue_family = a->queue_family;
    desc.queue = a->queue;
    cvk_error err;
    cvk_context* ctx;
    REQUIRE_OK(cvk_context_create(&desc, &ctx, &err), err);
    cvk_context_info info = cvk_context_get_info(ctx);
    CHECK(info.adopted, "cvk_context_get_info says adopted == false for the test's own device");
    printf("adopted %s, queue family %u\n", info.device_name, a->queue_family);
    return ctx;
}

/* Six frames: the test's own command buffer, recorded once with 3 frames, submitted twice. */
static float* six_recorded_frames(app* a, cvk_context* ctx, float** out_start)
{
    cvk_sim* sim = make_sim(ctx, CVK_LINEAR_RBGS);
    *out_start = harness_read_all(sim);
    VkCommandBuffer cmd = app_command_buffer(a);
    app_begin(cmd);
    cvk_error err;
    REQUIRE_OK(cvk_sim_record(sim, cmd, 3, &err), err);
    require_vk(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    app_submit_and_wait(a, cmd);
    app_submit_and_wait(a, cmd);
    float* end = harness_read_all(sim);
    vkFreeCommandBuffers(a->device, a->pool, 1, &cmd);
    cvk_sim_destroy(sim);
    return end;
}

/* Six frames of cvk_sim_step on a library-made context on the same device (index 0, as the
   test picked it, whatever $CLOTHVK_DEVICE says). */
static float* six_stepped_frames(void)
{
    cvk_context_desc desc = cvk_default_context_desc();
    desc.validation = 1;
    desc.device_name = "0";
    desc.log = harness_log;
    cvk_error err;
    cvk_context* ctx;
    REQUIRE_OK(cvk_context_create(&desc, &ctx, &err), err);
    cvk_sim* sim = make_sim(ctx, CVK_LINEAR_RBGS);
    REQUIRE_OK(cvk_sim_step(sim, 6, &err), err);
    float* end = harness_read_all(sim);
    cvk_sim_destroy(sim);
    uint32_t messages = cvk_context_validation_message_count(ctx);
    CHECK(messages == 0, "the library-made context saw %u validation messages", messages);
    cvk_context_destroy(ctx);
    return end;
}

static void recording_matches_stepping(app* a, cvk_context* ctx)
{
    float* start;
    float* recorded = six_recorded_frames(a, ctx, &start);
    float* stepped = six_stepped_frames();
    const uint64_t n = (uint64_t)GRID_U * GRID_V;

    /* A free corner far from the pins: 6 frames (0.096 s) of near free fall drop it ~4.5 cm. */
    size_t corner = (size_t)(GRID_V - 1) * GRID_U + GRID_U / 2;
    double fell = (double)start[3 * corner + 1] - recorded[3 * corner + 1];
    CHECK(fell > 0.01, "the recorded frames moved particle [%d, %d] down by %g m only",
          GRID_U / 2, GRID_V - 1, fell);

    bool same = memcmp(recorded, stepped, 3 * n * sizeof(float)) == 0;
    uint64_t differing = 0;
    for (uint64_t i = 0; i < 3 * n; i++)
        differing += memcmp(&recorded[i], &stepped[i], sizeof(float)) != 0;
    CHECK(same, "recorded and stepped positions differ in %llu of %llu coordinates, by up to %g m",
          (unsigned long long)differing, (unsigned long long)(3 * n),
          harness_max_diff(recorded, stepped, 3 * n));
    printf("record 3 frames x 2 submissions vs step 6: %s; particle [%d, %d] fell %.4f m\n",
           same ? "bit-identical" : "DIFFERENT", GRID_U / 2, GRID_V - 1, fell);
    free(start);
    free(recorded);
    free(stepped);
}

static const char gs_cpu_message[] =
    "the gs-cpu solver runs on the host and cannot be recorded into a command buffer; use "
    "cvk_sim_step";

static void record_refuses_host_solver(app* a, cvk_context* ctx)
{
    cvk_sim* sim = make_sim(ctx, CVK_LINEAR_GS_CPU);
    VkCommandBuffer cmd = app_command_buffer(a);
    app_begin(cmd);
    cvk_error err = {0};
    cvk_result r = cvk_sim_record(sim, cmd, 1, &err);
    CHECK(r == CVK_ERROR_UNSUPPORTED, "cvk_sim_record on gs-cpu returned %s, not "
          "CVK_ERROR_UNSUPPORTED", cvk_result_name(r));
    CHECK(err.result == r, "the error says %s, the call returned %s", cvk_result_name(err.result),
          cvk_result_name(r));
    CHECK(strcmp(err.message, gs_cpu_message) == 0, "message \"%s\"", err.message);
    require_vk(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    vkFreeCommandBuffers(a->device, a->pool, 1, &cmd);
    cvk_sim_destroy(sim);
}

/* After cvk_context_destroy the device is still the application's to use. */
static void device_outlives_context(app* a)
{
    VkResult vr = vkDeviceWaitIdle(a->device);
    CHECK(vr == VK_SUCCESS, "vkDeviceWaitIdle after cvk_context_destroy returned %d", (int)vr);
    VkCommandBuffer cmd = app_command_buffer(a);
    app_begin(cmd);
    require_vk(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    VkSubmitInfo submit = {
        .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
        .commandBufferCount = 1,
        .pCommandBuffers = &cmd,
    };
    vr = vkQueueSubmit(a->queue, 1, &submit, a->fence);
    CHECK(vr == VK_SUCCESS, "vkQueueSubmit after cvk_context_destroy returned %d", (int)vr);
    if (vr == VK_SUCCESS) {
        vr = vkWaitForFences(a->device, 1, &a->fence, VK_TRUE, UINT64_MAX);
        CHECK(vr == VK_SUCCESS, "vkWaitForFences after cvk_context_destroy returned %d", (int)vr);
    }
    vkFreeCommandBuffers(a->device, a->pool, 1, &cmd);
}

int main(void)
{
    app a;
    app_create(&a);
    adoption_needs_every_handle(&a);
    cvk_context* ctx = adopt(&a);
    recording_matches_stepping(&a, ctx);
    record_refuses_host_solver(&a, ctx);
    cvk_context_destroy(ctx);
    device_outlives_context(&a);
    app_destroy(&a);
    CHECK(a.messages == 0, "the application's messenger saw %u validation messages", a.messages);
    printf("%d checks, %d failed\n", harness_checks, harness_failures);
    return harness_failures ? 1 : 0;
}
