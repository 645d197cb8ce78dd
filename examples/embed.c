/* Embedding clothvk in a Vulkan application — a template to copy.

   The application owns everything Vulkan: the instance, the device, the queue, the command
   buffers, a render pass, a pipeline with its own shaders and the image it draws into. clothvk
   adopts the device and records its work into the application's command buffer:

       every frame, one command buffer:
           cvk_sim_record   the simulation step (compute)
           cvk_mesh_record  triangles and normals from the particles (compute)
           a barrier        compute-shader writes -> vertex input (the contract in clothvk.h)
           the application's render pass and draw from clothvk's vertex and index buffers

   No data goes through the host. At the end the image is copied to host memory and written as
   a PNG.

       embed OUT.png [FRAMES]

   With CLOTHVK_VALIDATION=1 the instance has the Khronos validation layer with synchronisation
   validation, and any message makes the program exit with status 1. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothvk.h>

#include "embed_frag.h"
#include "embed_vert.h"

enum { WIDTH = 640, HEIGHT = 480 };
#define COLOR_FORMAT VK_FORMAT_R8G8B8A8_SRGB
#define DEPTH_FORMAT VK_FORMAT_D32_SFLOAT

typedef struct app {
    VkInstance instance;
    VkDebugUtilsMessengerEXT messenger;
    uint32_t messages;
    VkPhysicalDevice physical_device;
    uint32_t queue_family;
    VkDevice device;
    VkQueue queue;
    VkCommandPool pool;
    VkCommandBuffer cmd;
    VkFence fence;

    VkImage images[2];            /* colour, depth */
    VkDeviceMemory memories[3];   /* colour, depth, readback */
    VkImageView views[2];
    VkBuffer readback;
    void* pixels;
    VkRenderPass pass;
    VkFramebuffer framebuffer;
    VkPipelineLayout layout;
    VkPipeline pipeline;
} app;

/* What the shaders' push constants hold. */
typedef struct camera {
    float view_proj[16];
    float eye[4];
    float color[4];
} camera;

static void check(VkResult vr, const char* call)
{
    if (vr != VK_SUCCESS) {
        fprintf(stderr, "embed: %s failed: VkResult %d\n", call, (int)vr);
        exit(1);
    }
}

static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                 VkDebugUtilsMessageTypeFlagsEXT types,
                                                 const VkDebugUtilsMessengerCallbackDataEXT* data, void* user)
{
    (void)types;
    if (severity & (VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT)) {
        ((app*)user)->messages++;
        fprintf(stderr, "embed: validation: %s\n", data->pMessage);
    }
    return VK_FALSE;
}

/* ---- the application's Vulkan: instance, device, queue ---------------------------------- */

static void create_instance(app* a)
{
    const char* env = getenv("CLOTHVK_VALIDATION");
    bool validation = env && strcmp(env, "1") == 0;
    VkApplicationInfo info = {
        .sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
        .pApplicationName = "clothvk embedding example",
        .apiVersion = VK_API_VERSION_1_1,
    };
    VkValidationFeatureEnableEXT sync = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
    VkValidationFeaturesEXT features = {
        .sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT,
        .enabledValidationFeatureCount = 1,
        .pEnabledValidationFeatures = &sync,
    };
    VkDebugUtilsMessengerCreateInfoEXT messenger = {
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .pNext = &features,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
        .pfnUserCallback = on_message,
        .pUserData = a,
    };
    const char* layers[] = {"VK_LAYER_KHRONOS_validation"};
    const char* extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
    VkInstanceCreateInfo create = {
        .sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
        .pNext = validation ? &messenger : NULL,
        .pApplicationInfo = &info,
        .enabledLayerCount = validation ? 1 : 0,
        .ppEnabledLayerNames = layers,
        .enabledExtensionCount = validation ? 1 : 0,
        .ppEnabledExtensionNames = extensions,
    };
    check(vkCreateInstance(&create, NULL, &a->instance), "vkCreateInstance");
    if (!validation)
        return;
    PFN_vkCreateDebugUtilsMessengerEXT create_messenger =
        (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(a->instance, "vkCreateDebugUtilsMessengerEXT");
    messenger.pNext = NULL;
    check(create_messenger(a->instance, &messenger, NULL, &a->messenger), "vkCreateDebugUtilsMessengerEXT");
}

/* The first device, and a queue family that both computes (clothvk) and draws (the app). */
static void create_device(app* a)
{
    uint32_t count = 1;
    VkResult vr = vkEnumeratePhysicalDevices(a->instance, &count, &a->physical_device);
    if ((vr != VK_SUCCESS && vr != VK_INCOMPLETE) || count == 0)
        check(VK_ERROR_INITIALIZATION_FAILED, "vkEnumeratePhysicalDevices (no device)");
    VkQueueFamilyProperties families[16];
    uint32_t family_count = 16;
    vkGetPhysicalDeviceQueueFamilyProperties(a->physical_device, &family_count, families);
    a->queue_family = UINT32_MAX;
    for (uint32_t i = 0; i < family_count && a->queue_family == UINT32_MAX; i++)
        if ((families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) && (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT))
            a->queue_family = i;
    if (a->queue_family == UINT32_MAX)
        check(VK_ERROR_FEATURE_NOT_PRESENT, "finding a graphics + compute queue family");
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
    check(vkCreateDevice(a->physical_device, &device, NULL, &a->device), "vkCreateDevice");
    vkGetDeviceQueue(a->device, a->queue_family, 0, &a->queue);
    VkCommandPoolCreateInfo pool = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
        .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
        .queueFamilyIndex = a->queue_family,
    };
    check(vkCreateCommandPool(a->device, &pool, NULL, &a->pool), "vkCreateCommandPool");
    VkCommandBufferAllocateInfo alloc = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
        .commandPool = a->pool,
        .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
        .commandBufferCount = 1,
    };
    check(vkAllocateCommandBuffers(a->device, &alloc, &a->cmd), "vkAllocateCommandBuffers");
    VkFenceCreateInfo fence = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    check(vkCreateFence(a->device, &fence, NULL, &a->fence), "vkCreateFence");
}

/* ---- the application's render target and pipeline --------------------------------------- */

static uint32_t memory_type(const app* a, uint32_t allowed, VkMemoryPropertyFlags want)
{
    VkPhysicalDeviceMemoryProperties m;
    vkGetPhysicalDeviceMemoryProperties(a->physical_device, &m);
    for (uint32_t i = 0; i < m.memoryTypeCount; i++)
        if ((allowed & (1u << i)) && (m.memoryTypes[i].propertyFlags & want) == want)
            return i;
    check(VK_ERROR_FEATURE_NOT_PRESENT, "finding a memory type");
    return 0;
}

static void create_target(app* a)
{
    VkFormat formats[2] = {COLOR_FORMAT, DEPTH_FORMAT};
    VkImageUsageFlags usages[2] = {VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                   VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT};
    VkImageAspectFlags aspects[2] = {VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_ASPECT_DEPTH_BIT};
    for (int i = 0; i < 2; i++) {
        VkImageCreateInfo image = {
            .sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO,
            .imageType = VK_IMAGE_TYPE_2D,
            .format = formats[i],
            .extent = {WIDTH, HEIGHT, 1},
            .mipLevels = 1,
            .arrayLayers = 1,
            .samples = VK_SAMPLE_COUNT_1_BIT,
            .tiling = VK_IMAGE_TILING_OPTIMAL,
            .usage = usages[i],
        };
        check(vkCreateImage(a->device, &image, NULL, &a->images[i]), "vkCreateImage");
        VkMemoryRequirements req;
        vkGetImageMemoryRequirements(a->device, a->images[i], &req);
        VkMemoryAllocateInfo alloc = {
            .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
            .allocationSize = req.size,
            .memoryTypeIndex = memory_type(a, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT),
        };
        check(vkAllocateMemory(a->device, &alloc, NULL, &a->memories[i]), "vkAllocateMemory");
        check(vkBindImageMemory(a->device, a->images[i], a->memories[i], 0), "vkBindImageMemory");
        VkImageViewCreateInfo view = {
            .sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
            .image = a->images[i],
            .viewType = VK_IMAGE_VIEW_TYPE_2D,
            .format = formats[i],
            .subresourceRange = {aspects[i], 0, 1, 0, 1},
        };
        check(vkCreateImageView(a->device, &view, NULL, &a->views[i]), "vkCreateImageView");
    }
    VkBufferCreateInfo buffer = {
        .sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
        .size = (VkDeviceSize)WIDTH * HEIGHT * 4,
        .usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT,
    };
    check(vkCreateBuffer(a->device, &buffer, NULL, &a->readback), "vkCreateBuffer");
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(a->device, a->readback, &req);
    VkMemoryAllocateInfo alloc = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
        .allocationSize = req.size,
        .memoryTypeIndex = memory_type(a, req.memoryTypeBits,
                                       VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT),
    };
    check(vkAllocateMemory(a->device, &alloc, NULL, &a->memories[2]), "vkAllocateMemory");
    check(vkBindBufferMemory(a->device, a->readback, a->memories[2], 0), "vkBindBufferMemory");
    check(vkMapMemory(a->device, a->memories[2], 0, VK_WHOLE_SIZE, 0, &a->pixels), "vkMapMemory");
}

static void create_pass(app* a)
{
    VkAttachmentDescription attachments[2] = {
        {.format = COLOR_FORMAT, .samples = VK_SAMPLE_COUNT_1_BIT, .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
         .storeOp = VK_ATTACHMENT_STORE_OP_STORE, .stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE,
         .stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE, .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED,
         .finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL},
        {.format = DEPTH_FORMAT, .samples = VK_SAMPLE_COUNT_1_BIT, .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
         .storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE, .stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE,
         .stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE, .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED,
         .finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL},
    };
    VkAttachmentReference color = {0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkAttachmentReference depth = {1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass = {
        .pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS,
        .colorAttachmentCount = 1,
        .pColorAttachments = &color,
        .pDepthStencilAttachment = &depth,
    };
    VkPipelineStageFlags output = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                  VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    VkAccessFlags writes = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    VkSubpassDependency dependencies[2] = {
        /* Last frame's drawing and its copy out of the image come before this frame's clears. */
        {VK_SUBPASS_EXTERNAL, 0, output | VK_PIPELINE_STAGE_TRANSFER_BIT, output, writes, writes, 0},
        {0, VK_SUBPASS_EXTERNAL, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
         VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT, 0},
    };
    VkRenderPassCreateInfo pass = {
        .sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO,
        .attachmentCount = 2,
        .pAttachments = attachments,
        .subpassCount = 1,
        .pSubpasses = &subpass,
        .dependencyCount = 2,
        .pDependencies = dependencies,
    };
    check(vkCreateRenderPass(a->device, &pass, NULL, &a->pass), "vkCreateRenderPass");
    VkFramebufferCreateInfo framebuffer = {
        .sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO,
        .renderPass = a->pass,
        .attachmentCount = 2,
        .pAttachments = a->views,
        .width = WIDTH,
        .height = HEIGHT,
        .layers = 1,
    };
    check(vkCreateFramebuffer(a->device, &framebuffer, NULL, &a->framebuffer), "vkCreateFramebuffer");
}

static VkShaderModule shader(const app* a, const uint32_t* code, size_t bytes)
{
    VkShaderModuleCreateInfo info = {.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO, .codeSize = bytes,
                                     .pCode = code};
    VkShaderModule module;
    check(vkCreateShaderModule(a->device, &info, NULL, &module), "vkCreateShaderModule");
    return module;
}

/* The pipeline's layout: the camera as push constants, no descriptor set. */
static void create_layout(app* a)
{
    VkPushConstantRange push = {VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(camera)};
    VkPipelineLayoutCreateInfo layout = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .pushConstantRangeCount = 1,
        .pPushConstantRanges = &push,
    };
    check(vkCreatePipelineLayout(a->device, &layout, NULL, &a->layout), "vkCreatePipelineLayout");
}

/* The vertex layout is clothvk's, read from cvk_mesh_get_buffers: nothing is hard-coded. */
static void create_pipeline(app* a, const cvk_mesh_buffers* mesh)
{
    create_layout(a);
    VkShaderModule vert = shader(a, spv_embed_vert, sizeof spv_embed_vert);
    VkShaderModule frag = shader(a, spv_embed_frag, sizeof spv_embed_frag);
    VkPipelineShaderStageCreateInfo stages[2] = {
        {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, .stage = VK_SHADER_STAGE_VERTEX_BIT,
         .module = vert, .pName = "main"},
        {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, .stage = VK_SHADER_STAGE_FRAGMENT_BIT,
         .module = frag, .pName = "main"},
    };
    VkVertexInputBindingDescription binding = {0, mesh->vertex_stride, VK_VERTEX_INPUT_RATE_VERTEX};
    VkVertexInputAttributeDescription attributes[2] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, mesh->position_offset},
        {1, 0, VK_FORMAT_R32G32B32_SFLOAT, mesh->normal_offset},
    };
    VkPipelineVertexInputStateCreateInfo input = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO,
        .vertexBindingDescriptionCount = 1,
        .pVertexBindingDescriptions = &binding,
        .vertexAttributeDescriptionCount = 2,
        .pVertexAttributeDescriptions = attributes,
    };
    VkPipelineInputAssemblyStateCreateInfo assembly = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO,
        .topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST,
    };
    VkViewport viewport = {0, 0, WIDTH, HEIGHT, 0, 1};
    VkRect2D scissor = {{0, 0}, {WIDTH, HEIGHT}};
    VkPipelineViewportStateCreateInfo viewport_state = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO,
        .viewportCount = 1,
        .pViewports = &viewport,
        .scissorCount = 1,
        .pScissors = &scissor,
    };
    VkPipelineRasterizationStateCreateInfo raster = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO,
        .polygonMode = VK_POLYGON_MODE_FILL,
        .cullMode = VK_CULL_MODE_NONE,
        .lineWidth = 1.0f,
    };
    VkPipelineMultisampleStateCreateInfo multisample = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO,
        .rasterizationSamples = VK_SAMPLE_COUNT_1_BIT,
    };
    VkPipelineDepthStencilStateCreateInfo depth = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO,
        .depthTestEnable = VK_TRUE,
        .depthWriteEnable = VK_TRUE,
        .depthCompareOp = VK_COMPARE_OP_LESS,
    };
    VkPipelineColorBlendAttachmentState blend_attachment = {.colorWriteMask = 0xf};
    VkPipelineColorBlendStateCreateInfo blend = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO,
        .attachmentCount = 1,
        .pAttachments = &blend_attachment,
    };
    VkGraphicsPipelineCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO,
        .stageCount = 2,
        .pStages = stages,
        .pVertexInputState = &input,
        .pInputAssemblyState = &assembly,
        .pViewportState = &viewport_state,
        .pRasterizationState = &raster,
        .pMultisampleState = &multisample,
        .pDepthStencilState = &depth,
        .pColorBlendState = &blend,
        .layout = a->layout,
        .renderPass = a->pass,
    };
    check(vkCreateGraphicsPipelines(a->device, VK_NULL_HANDLE, 1, &info, NULL, &a->pipeline),
          "vkCreateGraphicsPipelines");
    vkDestroyShaderModule(a->device, vert, NULL);
    vkDestroyShaderModule(a->device, frag, NULL);
}

/* A right-handed camera for Vulkan's clip space (y down, depth 0 to 1), column-major. */
static void look_at(const float eye[3], const float target[3], float out[16])
{
    float f[3] = {target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]};
    float fl = sqrtf(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (int k = 0; k < 3; k++)
        f[k] /= fl;
    float r[3] = {-f[2], 0.0f, f[0]}; /* f × (0, 1, 0) */
    float rl = sqrtf(r[0] * r[0] + r[2] * r[2]);
    r[0] /= rl;
    r[2] /= rl;
    float u[3] = {r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]};
    float t = 1.0f / tanf(0.35f), aspect = (float)WIDTH / HEIGHT, n = 0.05f, fa = 20.0f;
    float rows[4][4] = {
        {t / aspect * r[0], t / aspect * r[1], t / aspect * r[2],
         -t / aspect * (r[0] * eye[0] + r[1] * eye[1] + r[2] * eye[2])},
        {-t * u[0], -t * u[1], -t * u[2], t * (u[0] * eye[0] + u[1] * eye[1] + u[2] * eye[2])},
        {fa / (fa - n) * f[0], fa / (fa - n) * f[1], fa / (fa - n) * f[2],
         -fa / (fa - n) * (f[0] * eye[0] + f[1] * eye[1] + f[2] * eye[2]) - fa * n / (fa - n)},
        {f[0], f[1], f[2], -(f[0] * eye[0] + f[1] * eye[1] + f[2] * eye[2])},
    };
    for (int row = 0; row < 4; row++)
        for (int col = 0; col < 4; col++)
            out[col * 4 + row] = rows[row][col];
}

/* ---- one frame: clothvk's work and the application's draw in one command buffer ---------- */

static void record_frame(app* a, cvk_sim* sim, cvk_mesh* mesh, const cvk_mesh_buffers* buffers, bool read_back)
{
    cvk_error err;
    VkCommandBufferBeginInfo begin = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                      .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    check(vkBeginCommandBuffer(a->cmd, &begin), "vkBeginCommandBuffer");
    if (cvk_sim_record(sim, a->cmd, 1, &err) != CVK_SUCCESS || cvk_mesh_record(mesh, a->cmd, &err) != CVK_SUCCESS) {
        fprintf(stderr, "embed: %s\n", err.message);
        exit(1);
    }
    /* The one barrier the contract leaves to the application: clothvk's compute writes before
       the vertex input reads them. */
    VkMemoryBarrier barrier = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
        .dstAccessMask = VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_INDEX_READ_BIT,
    };
    vkCmdPipelineBarrier(a->cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_VERTEX_INPUT_BIT, 0, 1,
                         &barrier, 0, NULL, 0, NULL);

    VkClearValue clears[2] = {{.color = {{0.9f, 0.9f, 0.92f, 1.0f}}}, {.depthStencil = {1.0f, 0}}};
    VkRenderPassBeginInfo pass = {
        .sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO,
        .renderPass = a->pass,
        .framebuffer = a->framebuffer,
        .renderArea = {{0, 0}, {WIDTH, HEIGHT}},
        .clearValueCount = 2,
        .pClearValues = clears,
    };
    vkCmdBeginRenderPass(a->cmd, &pass, VK_SUBPASS_CONTENTS_INLINE);
    vkCmdBindPipeline(a->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, a->pipeline);
    VkDeviceSize offset = 0;
    vkCmdBindVertexBuffers(a->cmd, 0, 1, &buffers->vertex_buffer, &offset);
    vkCmdBindIndexBuffer(a->cmd, buffers->index_buffer, 0, buffers->index_type);
    camera cam = {.eye = {1.6f, 1.4f, 2.2f, 1.0f}, .color = {0.2f, 0.45f, 0.8f, 1.0f}};
    look_at(cam.eye, (const float[3]){0.0f, 0.4f, -0.3f}, cam.view_proj);
    vkCmdPushConstants(a->cmd, a->layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof cam,
                       &cam);
    for (uint32_t c = 0; c < buffers->cloth_count; c++)
        vkCmdDrawIndexed(a->cmd, buffers->cloths[c].index_count, 1, buffers->cloths[c].first_index, 0, 0);
    vkCmdEndRenderPass(a->cmd);

    if (read_back) {
        VkBufferImageCopy region = {.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
                                    .imageExtent = {WIDTH, HEIGHT, 1}};
        vkCmdCopyImageToBuffer(a->cmd, a->images[0], VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, a->readback, 1, &region);
        VkMemoryBarrier to_host = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                                   .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                                   .dstAccessMask = VK_ACCESS_HOST_READ_BIT};
        vkCmdPipelineBarrier(a->cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &to_host, 0,
                             NULL, 0, NULL);
    }
    check(vkEndCommandBuffer(a->cmd), "vkEndCommandBuffer");
    VkSubmitInfo submit = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO, .commandBufferCount = 1, .pCommandBuffers = &a->cmd};
    check(vkQueueSubmit(a->queue, 1, &submit, a->fence), "vkQueueSubmit");
    check(vkWaitForFences(a->device, 1, &a->fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
    check(vkResetFences(a->device, 1, &a->fence), "vkResetFences");
}

static void destroy(app* a)
{
    vkDeviceWaitIdle(a->device);
    vkDestroyPipeline(a->device, a->pipeline, NULL);
    vkDestroyPipelineLayout(a->device, a->layout, NULL);
    vkDestroyFramebuffer(a->device, a->framebuffer, NULL);
    vkDestroyRenderPass(a->device, a->pass, NULL);
    vkDestroyBuffer(a->device, a->readback, NULL);
    for (int i = 0; i < 2; i++) {
        vkDestroyImageView(a->device, a->views[i], NULL);
        vkDestroyImage(a->device, a->images[i], NULL);
    }
    for (int i = 0; i < 3; i++)
        vkFreeMemory(a->device, a->memories[i], NULL);
    vkDestroyFence(a->device, a->fence, NULL);
    vkDestroyCommandPool(a->device, a->pool, NULL);
    vkDestroyDevice(a->device, NULL);
    if (a->messenger) {
        PFN_vkDestroyDebugUtilsMessengerEXT destroy_messenger =
            (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(a->instance, "vkDestroyDebugUtilsMessengerEXT");
        destroy_messenger(a->instance, a->messenger, NULL);
    }
    vkDestroyInstance(a->instance, NULL);
}

int main(int argc, char** argv)
{
    if (argc < 2 || argc > 3) {
        fprintf(stderr, "usage: embed OUT.png [FRAMES]\n");
        return 2;
    }
    int frames = argc == 3 ? atoi(argv[2]) : 35;
    if (frames < 1) {
        fprintf(stderr, "embed: FRAMES must be a whole number of at least 1, got %s\n", argv[2]);
        return 2;
    }
    app a = {0};
    create_instance(&a);
    create_device(&a);

    /* clothvk adopts the application's device and queue; it creates no Vulkan instance or
       device of its own and never destroys these. */
    cvk_error err;
    cvk_context* ctx;
    cvk_context_desc adopt = cvk_default_context_desc();
    adopt.instance = a.instance;
    adopt.physical_device = a.physical_device;
    adopt.device = a.device;
    adopt.queue_family = a.queue_family;
    adopt.queue = a.queue;
    if (cvk_context_create(&adopt, &ctx, &err) != CVK_SUCCESS) {
        fprintf(stderr, "embed: %s\n", err.message);
        return 1;
    }
    /* A 48 x 48 cloth pinned at two corners, described in code. */
    static const uint32_t pins[2][2] = {{0, 0}, {47, 0}};
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = cloth.grid[1] = 48;
    cloth.origin[2] = -0.5f;
    cloth.stiffness.shear = 1e5f;
    cloth.pins = pins;
    cloth.pin_count = 2;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    cvk_sim* sim = NULL;
    cvk_mesh* mesh = NULL;
    cvk_sim_desc sim_desc = cvk_default_sim_desc();
    sim_desc.scene = &scene;
    if (cvk_sim_create(ctx, &sim_desc, &sim, &err) != CVK_SUCCESS ||
        cvk_mesh_create(sim, NULL, &mesh, &err) != CVK_SUCCESS) {
        fprintf(stderr, "embed: %s\n", err.message);
        return 1;
    }
    cvk_mesh_buffers buffers = cvk_mesh_get_buffers(mesh);

    create_target(&a);
    create_pass(&a);
    create_pipeline(&a, &buffers);
    for (int f = 0; f < frames; f++)
        record_frame(&a, sim, mesh, &buffers, f + 1 == frames);

    cvk_image image = {a.pixels, WIDTH, HEIGHT, 4 * WIDTH};
    int status = 0;
    if (cvk_image_write_png(&image, argv[1], &err) != CVK_SUCCESS) {
        fprintf(stderr, "embed: %s\n", err.message);
        status = 1;
    }
    cvk_mesh_destroy(mesh);
    cvk_sim_destroy(sim);
    cvk_context_destroy(ctx);
    destroy(&a);
    if (a.messages) {
        fprintf(stderr, "embed: %u validation messages\n", a.messages);
        status = 1;
    }
    if (status == 0)
        printf("embed: %d frames of a %u-particle cloth drawn by the application, written to %s\n", frames,
               buffers.vertex_count, argv[1]);
    return status;
}
