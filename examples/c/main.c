/* A C engine that embeds glyphcast through its C API (include/glyphcast.h).
 *
 * The engine owns everything Vulkan: its instance (with the validation layer and a
 * messenger that counts messages), device, queue, command pool, two frames in flight
 * (a command buffer, a fence and colour and depth images each), and its own geometry: a
 * ground plane that cuts through the glyphs (SH glyphs, replaced halfway by tensor
 * glyphs of order 4, as a slice step would). glyphcast is handed the handles once and
 * records its glyphs into the engine's command buffer each frame, after the plane, in
 * the same rendering and depth buffer (standard depth: cleared to 1, tested LESS). No
 * window: the last frame is copied to a buffer and written as a PNG.
 *
 *   bash tools/c-example.sh OUT.png [--plain-memory] [--uniform-red]
 *       [--basis descoteaux07-legacy|descoteaux07|tournier07] [--no-plane]
 *       [--describe FILE.json]
 *
 * With --plain-memory glyphcast's buffers take their memory from the engine's own
 * allocation callbacks (GlyphcastAllocator: one vkAllocateMemory per block) instead of
 * the gpu-allocator allocator glyphcast makes by default. --no-plane leaves the engine's
 * plane out (the glyphs alone on the clear colour); --describe writes what the last
 * frame drew (image size, camera, settings, the SH glyphs and their basis) as JSON, for
 * drawing the same glyphs another way (python/tests/test_c_api_parity.py).
 *
 * Exit status: 0, or 1 on any failure or validation message. */
#include "glyphcast.h"

#include <math.h>
#include <shaderc/shaderc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define WIDTH 160
#define HEIGHT 120
#define FRAMES 6
#define IN_FLIGHT 2
#define COLOR_FORMAT VK_FORMAT_R8G8B8A8_SRGB
#define DEPTH_FORMAT VK_FORMAT_D32_SFLOAT
#define FOV_Y_DEG 35.0

static int validation_messages = 0;

static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(
    VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT type,
    const VkDebugUtilsMessengerCallbackDataEXT *data, void *user) {
    (void)severity, (void)type, (void)user;
    fprintf(stderr, "validation: %s\n", data->pMessage);
    validation_messages++;
    return VK_FALSE;
}

#define CHECK(call)                                                              \
    do {                                                                         \
        VkResult r_ = (call);                                                    \
        if (r_ != VK_SUCCESS) {                                                  \
            fprintf(stderr, "%s:%d: %s failed (%d)\n", __FILE__, __LINE__, #call, r_); \
            exit(1);                                                             \
        }                                                                        \
    } while (0)

#define GLYPHCAST(renderer, call)                                                \
    do {                                                                         \
        if ((call) != GLYPHCAST_STATUS_OK) {                                     \
            fprintf(stderr, "%s: %s\n", #call, glyphcast_renderer_last_error(renderer)); \
            exit(1);                                                             \
        }                                                                        \
    } while (0)

typedef struct {
    VkImage image;
    VkImageView view;
    VkDeviceMemory memory;
} Image;

typedef struct {
    VkInstance instance;
    VkDebugUtilsMessengerEXT messenger;
    VkPhysicalDevice physical_device;
    VkDevice device;
    uint32_t family;
    VkQueue queue;
} Engine;

/* Column-major 4 x 4 matrices, as Vulkan and glyphcast take them. */
typedef struct {
    double m[16];
} Mat4;

static Mat4 multiply(Mat4 a, Mat4 b) {
    Mat4 c;
    for (int col = 0; col < 4; col++)
        for (int row = 0; row < 4; row++) {
            double s = 0.0;
            for (int k = 0; k < 4; k++) s += a.m[k * 4 + row] * b.m[col * 4 + k];
            c.m[col * 4 + row] = s;
        }
    return c;
}

/* A right-handed look-at view (the camera looks along -z, y up). */
static Mat4 look_at(const double eye[3], const double target[3], const double up[3]) {
    double f[3], s[3], u[3];
    for (int i = 0; i < 3; i++) f[i] = target[i] - eye[i];
    double fl = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (int i = 0; i < 3; i++) f[i] /= fl;
    s[0] = f[1] * up[2] - f[2] * up[1];
    s[1] = f[2] * up[0] - f[0] * up[2];
    s[2] = f[0] * up[1] - f[1] * up[0];
    double sl = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    for (int i = 0; i < 3; i++) s[i] /= sl;
    u[0] = s[1] * f[2] - s[2] * f[1];
    u[1] = s[2] * f[0] - s[0] * f[2];
    u[2] = s[0] * f[1] - s[1] * f[0];
    Mat4 v = {{s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0,
               -(s[0] * eye[0] + s[1] * eye[1] + s[2] * eye[2]),
               -(u[0] * eye[0] + u[1] * eye[1] + u[2] * eye[2]),
               f[0] * eye[0] + f[1] * eye[1] + f[2] * eye[2], 1}};
    return v;
}

/* A Vulkan perspective (y down) with standard depth: 0 at near, 1 at far. */
static Mat4 perspective(double fov_y, double aspect, double near, double far) {
    double h = 1.0 / tan(0.5 * fov_y);
    Mat4 p = {{h / aspect, 0, 0, 0, 0, -h, 0, 0, 0, 0, far / (near - far), -1, 0, 0,
               near * far / (near - far), 0}};
    return p;
}

/* Whether the engine's device enables fragmentStoresAndAtomics (`--no-fragment-stores`:
 * a host that enables only what glyphcast asks of it, which draws the same glyphs). */
static int fragment_stores = 1;

static void create_engine(Engine *e) {
    VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
                             .pApplicationName = "glyphcast C example",
                             .apiVersion = VK_API_VERSION_1_3};
    const char *layers[] = {"VK_LAYER_KHRONOS_validation"};
    const char *extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
    VkInstanceCreateInfo info = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
                                 .pApplicationInfo = &app,
                                 .enabledLayerCount = 1,
                                 .ppEnabledLayerNames = layers,
                                 .enabledExtensionCount = 1,
                                 .ppEnabledExtensionNames = extensions};
    CHECK(vkCreateInstance(&info, NULL, &e->instance));
    VkDebugUtilsMessengerCreateInfoEXT messenger = {
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT,
        .pfnUserCallback = on_message};
    PFN_vkCreateDebugUtilsMessengerEXT create_messenger =
        (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
            e->instance, "vkCreateDebugUtilsMessengerEXT");
    CHECK(create_messenger(e->instance, &messenger, NULL, &e->messenger));

    uint32_t count = 0;
    CHECK(vkEnumeratePhysicalDevices(e->instance, &count, NULL));
    VkPhysicalDevice devices[16];
    if (count > 16) count = 16;
    CHECK(vkEnumeratePhysicalDevices(e->instance, &count, devices));
    e->physical_device = VK_NULL_HANDLE;
    for (uint32_t i = 0; i < count && !e->physical_device; i++) {
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(devices[i], &props);
        uint32_t nf = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(devices[i], &nf, NULL);
        VkQueueFamilyProperties families[16];
        if (nf > 16) nf = 16;
        vkGetPhysicalDeviceQueueFamilyProperties(devices[i], &nf, families);
        for (uint32_t f = 0; f < nf; f++)
            if (props.apiVersion >= VK_API_VERSION_1_3 &&
                (families[f].queueFlags & VK_QUEUE_GRAPHICS_BIT)) {
                e->physical_device = devices[i];
                e->family = f;
                break;
            }
    }
    if (!e->physical_device) {
        fprintf(stderr, "no Vulkan 1.3 device with a graphics queue\n");
        exit(1);
    }
    float priority = 1.0f;
    VkDeviceQueueCreateInfo queue = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
                                     .queueFamilyIndex = e->family,
                                     .queueCount = 1,
                                     .pQueuePriorities = &priority};
    /* What glyphcast needs: dynamic rendering (and sampleRateShading for MSAA). Storage
       writes in fragment shaders are the engine's own choice; glyphcast writes no buffer
       from a fragment shader of a host's device. */
    VkPhysicalDeviceVulkan13Features v13 = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES,
        .dynamicRendering = VK_TRUE,
        .synchronization2 = VK_TRUE};
    VkPhysicalDeviceFeatures core = {.fragmentStoresAndAtomics = fragment_stores ? VK_TRUE
                                                                                : VK_FALSE};
    VkDeviceCreateInfo device = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
                                 .pNext = &v13,
                                 .pEnabledFeatures = &core,
                                 .queueCreateInfoCount = 1,
                                 .pQueueCreateInfos = &queue};
    CHECK(vkCreateDevice(e->physical_device, &device, NULL, &e->device));
    vkGetDeviceQueue(e->device, e->family, 0, &e->queue);
}

static uint32_t memory_type(Engine *e, uint32_t bits, VkMemoryPropertyFlags flags) {
    VkPhysicalDeviceMemoryProperties props;
    vkGetPhysicalDeviceMemoryProperties(e->physical_device, &props);
    for (uint32_t i = 0; i < props.memoryTypeCount; i++)
        if ((bits & (1u << i)) && (props.memoryTypes[i].propertyFlags & flags) == flags) return i;
    fprintf(stderr, "no memory type\n");
    exit(1);
}

/* The engine's allocation callbacks: one vkAllocateMemory per block, host-visible blocks
 * mapped whole. `allocated` and `live` count the blocks, for the test. */
typedef struct {
    Engine *engine;
    int allocated, live;
} PlainMemory;

static GlyphcastStatus plain_allocate(void *user, const GlyphcastMemoryRequest *request,
                                      GlyphcastMemoryBlock *block) {
    PlainMemory *plain = user;
    VkPhysicalDeviceMemoryProperties props;
    vkGetPhysicalDeviceMemoryProperties(plain->engine->physical_device, &props);
    uint32_t type = UINT32_MAX;
    VkMemoryPropertyFlags wanted[2] = {request->required_flags | request->preferred_flags,
                                       request->required_flags};
    for (int pass = 0; pass < 2 && type == UINT32_MAX; pass++)
        for (uint32_t i = 0; i < props.memoryTypeCount; i++)
            if ((request->memory_type_bits & (1u << i)) &&
                (props.memoryTypes[i].propertyFlags & wanted[pass]) == wanted[pass]) {
                type = i;
                break;
            }
    if (type == UINT32_MAX) return GLYPHCAST_STATUS_VULKAN;
    VkMemoryAllocateInfo info = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                                 .allocationSize = request->size,
                                 .memoryTypeIndex = type};
    VkDeviceMemory memory;
    if (vkAllocateMemory(plain->engine->device, &info, NULL, &memory) != VK_SUCCESS)
        return GLYPHCAST_STATUS_VULKAN;
    void *mapped = NULL;
    if (request->usage != GLYPHCAST_MEMORY_USE_DEVICE_LOCAL &&
        vkMapMemory(plain->engine->device, memory, 0, VK_WHOLE_SIZE, 0, &mapped) != VK_SUCCESS) {
        vkFreeMemory(plain->engine->device, memory, NULL);
        return GLYPHCAST_STATUS_VULKAN;
    }
    *block = (GlyphcastMemoryBlock){.memory = memory, .offset = 0, .size = request->size,
                                    .mapped = mapped, .token = 0};
    plain->allocated++, plain->live++;
    return GLYPHCAST_STATUS_OK;
}

static void plain_free(void *user, const GlyphcastMemoryBlock *block) {
    PlainMemory *plain = user;
    vkFreeMemory(plain->engine->device, block->memory, NULL); /* unmaps it too */
    plain->live--;
}

static Image create_image(Engine *e, VkFormat format, VkImageUsageFlags usage,
                          VkImageAspectFlags aspect) {
    Image img;
    VkImageCreateInfo info = {.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO,
                              .imageType = VK_IMAGE_TYPE_2D,
                              .format = format,
                              .extent = {WIDTH, HEIGHT, 1},
                              .mipLevels = 1,
                              .arrayLayers = 1,
                              .samples = VK_SAMPLE_COUNT_1_BIT,
                              .tiling = VK_IMAGE_TILING_OPTIMAL,
                              .usage = usage,
                              .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED};
    CHECK(vkCreateImage(e->device, &info, NULL, &img.image));
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(e->device, img.image, &req);
    VkMemoryAllocateInfo alloc = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
        .allocationSize = req.size,
        .memoryTypeIndex = memory_type(e, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT)};
    CHECK(vkAllocateMemory(e->device, &alloc, NULL, &img.memory));
    CHECK(vkBindImageMemory(e->device, img.image, img.memory, 0));
    VkImageViewCreateInfo view = {.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
                                  .image = img.image,
                                  .viewType = VK_IMAGE_VIEW_TYPE_2D,
                                  .format = format,
                                  .subresourceRange = {aspect, 0, 1, 0, 1}};
    CHECK(vkCreateImageView(e->device, &view, NULL, &img.view));
    return img;
}

static void destroy_image(Engine *e, Image *img) {
    vkDestroyImageView(e->device, img->view, NULL);
    vkDestroyImage(e->device, img->image, NULL);
    vkFreeMemory(e->device, img->memory, NULL);
}

/* The engine's own shaders (examples/shaders/plane.*, in PLANE_SHADER_DIR), compiled
 * here with shaderc's C API: glyphcast carries no shaders of an engine's own. */
static VkShaderModule plane_module(Engine *e, uint32_t fragment) {
    const char *name = fragment ? PLANE_SHADER_DIR "/plane.frag" : PLANE_SHADER_DIR "/plane.vert";
    FILE *file = fopen(name, "rb");
    if (!file) {
        fprintf(stderr, "cannot open %s\n", name);
        exit(1);
    }
    char source[8192];
    size_t length = fread(source, 1, sizeof source, file);
    fclose(file);
    shaderc_compiler_t compiler = shaderc_compiler_initialize();
    shaderc_compilation_result_t result = shaderc_compile_into_spv(
        compiler, source, length,
        fragment ? shaderc_glsl_fragment_shader : shaderc_glsl_vertex_shader, name, "main",
        NULL);
    if (shaderc_result_get_compilation_status(result) != shaderc_compilation_status_success) {
        fprintf(stderr, "%s: %s\n", name, shaderc_result_get_error_message(result));
        exit(1);
    }
    VkShaderModuleCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
        .codeSize = shaderc_result_get_length(result),
        .pCode = (const uint32_t *)shaderc_result_get_bytes(result)};
    VkShaderModule module;
    CHECK(vkCreateShaderModule(e->device, &info, NULL, &module));
    shaderc_result_release(result);
    shaderc_compiler_release(compiler);
    return module;
}

/* The engine's plane: its own pipeline, depth tested LESS and written. */
static VkPipeline plane_pipeline(Engine *e, VkPipelineLayout layout) {
    VkShaderModule vert = plane_module(e, 0), frag = plane_module(e, 1);
    VkPipelineShaderStageCreateInfo stages[2] = {
        {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
         .stage = VK_SHADER_STAGE_VERTEX_BIT, .module = vert, .pName = "main"},
        {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
         .stage = VK_SHADER_STAGE_FRAGMENT_BIT, .module = frag, .pName = "main"}};
    VkPipelineVertexInputStateCreateInfo input = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkPipelineInputAssemblyStateCreateInfo assembly = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO,
        .topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST};
    VkPipelineViewportStateCreateInfo viewport = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO,
        .viewportCount = 1, .scissorCount = 1};
    VkPipelineRasterizationStateCreateInfo raster = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO,
        .polygonMode = VK_POLYGON_MODE_FILL, .cullMode = VK_CULL_MODE_NONE, .lineWidth = 1.0f};
    VkPipelineMultisampleStateCreateInfo multisample = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO,
        .rasterizationSamples = VK_SAMPLE_COUNT_1_BIT};
    VkPipelineDepthStencilStateCreateInfo depth = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO,
        .depthTestEnable = VK_TRUE, .depthWriteEnable = VK_TRUE,
        .depthCompareOp = VK_COMPARE_OP_LESS};
    VkPipelineColorBlendAttachmentState blend_attachment = {.colorWriteMask = 0xf};
    VkPipelineColorBlendStateCreateInfo blend = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO,
        .attachmentCount = 1, .pAttachments = &blend_attachment};
    VkDynamicState states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO,
        .dynamicStateCount = 2, .pDynamicStates = states};
    VkFormat color = COLOR_FORMAT;
    VkPipelineRenderingCreateInfo rendering = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO,
        .colorAttachmentCount = 1, .pColorAttachmentFormats = &color,
        .depthAttachmentFormat = DEPTH_FORMAT};
    VkGraphicsPipelineCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO, .pNext = &rendering,
        .stageCount = 2, .pStages = stages, .pVertexInputState = &input,
        .pInputAssemblyState = &assembly, .pViewportState = &viewport,
        .pRasterizationState = &raster, .pMultisampleState = &multisample,
        .pDepthStencilState = &depth, .pColorBlendState = &blend,
        .pDynamicState = &dynamic, .layout = layout};
    VkPipeline pipeline;
    CHECK(vkCreateGraphicsPipelines(e->device, VK_NULL_HANDLE, 1, &info, NULL, &pipeline));
    vkDestroyShaderModule(e->device, vert, NULL);
    vkDestroyShaderModule(e->device, frag, NULL);
    return pipeline;
}

static VkImageMemoryBarrier2 barrier(VkImage image, VkImageAspectFlags aspect,
                                     VkImageLayout from, VkImageLayout to,
                                     VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                                     VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access) {
    VkImageMemoryBarrier2 b = {.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2,
                               .srcStageMask = src_stage, .srcAccessMask = src_access,
                               .dstStageMask = dst_stage, .dstAccessMask = dst_access,
                               .oldLayout = from, .newLayout = to, .image = image,
                               .subresourceRange = {aspect, 0, 1, 0, 1}};
    return b;
}

/* How the example's SH coefficients are read (--basis): DIPY's default, descoteaux07
 * legacy, unless the command line names another. */
static GlyphcastShBasis sh_basis = GLYPHCAST_SH_BASIS_DESCOTEAUX07;
static uint32_t sh_legacy = 1;
/* With --basis the slice step brings SH glyphs again, so the last frame shows them. */
static int sh_slice_step = 0;

/* --no-plane: the glyphs alone on the clear colour. */
static int draw_plane = 1;

/* The SH glyphs last handed to glyphcast, for --describe. */
enum { SH_COUNT = 9, SH_PER = 15 };
static double sh_centers[3 * SH_COUNT], sh_scales[SH_COUNT], sh_coefficients[SH_PER * SH_COUNT];

/* Nine glyphs of SH bands 0 to 4 on a 3 x 3 grid at z = 0: a sphere stretched along a
 * direction that turns across the grid. */
static void glyphs(GlyphcastRenderer *renderer, double turn) {
    enum { N = SH_COUNT, PER = SH_PER };
    double *centers = sh_centers, *scales = sh_scales, *coefficients = sh_coefficients;
    memset(sh_coefficients, 0, sizeof sh_coefficients);
    for (int k = 0; k < N; k++) {
        centers[3 * k] = 1.1 * (k % 3 - 1);
        centers[3 * k + 1] = 1.1 * (k / 3 - 1);
        centers[3 * k + 2] = 0.0;
        scales[k] = 0.45;
        double *c = coefficients + PER * k;
        c[0] = 2.5; /* band 0 */
        /* band 2, orders -2..2 at indices 1..5; band 4 at 6..14 */
        c[1 + 2 + (k % 2 ? 2 : -2)] = 1.0 * cos(turn + k);
        c[3] = 1.2; /* order 0 of band 2: along z */
        c[3 + 1] = 0.6; /* order 1 of band 2: odd orders tell the legacy basis apart */
        c[6 + 4] = 0.5 * sin(turn + 0.5 * k);
        c[6 + 4 - 1] = 0.4; /* order -1 of band 4 */
    }
    GLYPHCAST(renderer, glyphcast_renderer_set_sh_glyphs(renderer, 4, sh_basis, sh_legacy, N,
                                                         centers, scales, coefficients));
}

static void write_doubles(FILE *file, const double *values, int count) {
    fputc('[', file);
    for (int i = 0; i < count; i++) fprintf(file, "%s%.17g", i ? ", " : "", values[i]);
    fputc(']', file);
}

/* --describe: the last frame as JSON (the camera as a look-at and a vertical field of
 * view; the SH glyphs' centres, scales and coefficients as handed to glyphcast). */
static int describe(const char *name, const GlyphcastSettings *settings, const double eye[3],
                    const double target[3], const double up[3], double fov_y_deg) {
    FILE *file = fopen(name, "w");
    if (!file) {
        fprintf(stderr, "--describe %s: cannot be written\n", name);
        return 1;
    }
    fprintf(file, "{\"width\": %d, \"height\": %d,\n", WIDTH, HEIGHT);
    fprintf(file, " \"camera\": {\"projection\": \"perspective\", \"fov_y_deg\": %.17g, \"eye\": ",
            fov_y_deg);
    write_doubles(file, eye, 3);
    fprintf(file, ", \"target\": ");
    write_doubles(file, target, 3);
    fprintf(file, ", \"up\": ");
    write_doubles(file, up, 3);
    double light[3] = {settings->light[0], settings->light[1], settings->light[2]};
    fprintf(file, "},\n \"method\": \"exact\", \"ambient\": %.9g, \"light\": ",
            (double)settings->ambient);
    write_doubles(file, light, 3);
    fprintf(file, ",\n \"clear_color\": [0.55, 0.65, 0.8], \"plane\": %s,\n",
            draw_plane ? "true" : "false");
    fprintf(file, " \"sh\": {\"band\": 4, \"basis\": \"%s\", \"legacy\": %s, \"centers\": ",
            sh_basis == GLYPHCAST_SH_BASIS_TOURNIER07 ? "tournier07" : "descoteaux07",
            sh_legacy ? "true" : "false");
    write_doubles(file, sh_centers, 3 * SH_COUNT);
    fprintf(file, ",\n  \"scales\": ");
    write_doubles(file, sh_scales, SH_COUNT);
    fprintf(file, ",\n  \"coefficients\": ");
    write_doubles(file, sh_coefficients, SH_PER * SH_COUNT);
    fprintf(file, "}}\n");
    if (fclose(file) != 0) {
        fprintf(stderr, "--describe %s: cannot be written\n", name);
        return 1;
    }
    return 0;
}

/* The slice step's glyphs: nine symmetric tensors of order 4 (the scene format's unique
 * entries, sorted index tuples in lexicographic order), each two crossing fibres d1 and
 * d2: entry (i, j, k, l) = d1_i d1_j d1_k d1_l + 0.6 d2_i d2_j d2_k d2_l. */
static void tensor_glyphs(GlyphcastRenderer *renderer, double turn) {
    enum { N = 9, PER = 15 };
    double centers[3 * N], scales[N], coefficients[PER * N];
    for (int k = 0; k < N; k++) {
        centers[3 * k] = 1.1 * (k % 3 - 1);
        centers[3 * k + 1] = 1.1 * (k / 3 - 1);
        centers[3 * k + 2] = 0.0;
        scales[k] = 0.5;
        double a = turn + 0.7 * k;
        double d1[3] = {cos(a), sin(a), 0.3}, d2[3] = {-sin(a), cos(a), 0.8};
        for (int v = 0; v < 3; v++) d1[v] /= sqrt(1.09), d2[v] /= sqrt(1.64);
        int e = 0;
        for (int i = 0; i < 3; i++)
            for (int j = i; j < 3; j++)
                for (int m = j; m < 3; m++)
                    for (int l = m; l < 3; l++, e++)
                        coefficients[PER * k + e] = d1[i] * d1[j] * d1[m] * d1[l] +
                                                    0.6 * d2[i] * d2[j] * d2[m] * d2[l];
    }
    GLYPHCAST(renderer, glyphcast_renderer_set_tensor_glyphs(renderer, 4, 1, N, centers, scales,
                                                             coefficients));
}

int main(int argc, char **argv) {
    const char *output = argc > 1 ? argv[1] : "c-example.png";
    const char *description = NULL;
    int plain_memory = 0;
    /* The render settings: glyphcast's defaults, then the host's choices. */
    GlyphcastSettings settings;
    glyphcast_settings_default(&settings);
    settings.method = GLYPHCAST_METHOD_EXACT;
    settings.ambient = 0.25f;
    settings.light[0] = 0.5f, settings.light[1] = 0.6f, settings.light[2] = 1.0f;
    for (int i = 2; i < argc; i++) {
        if (strcmp(argv[i], "--plain-memory") == 0) {
            plain_memory = 1;
        } else if (strcmp(argv[i], "--uniform-red") == 0) {
            settings.color = GLYPHCAST_COLOR_UNIFORM;
            settings.uniform_color[0] = 0.85f;
            settings.uniform_color[1] = 0.05f;
            settings.uniform_color[2] = 0.05f;
            settings.specular = 0.0f;
        } else if (strcmp(argv[i], "--no-fragment-stores") == 0) {
            fragment_stores = 0;
        } else if (strcmp(argv[i], "--no-plane") == 0) {
            draw_plane = 0;
        } else if (strcmp(argv[i], "--describe") == 0 && i + 1 < argc) {
            description = argv[++i];
        } else if (strcmp(argv[i], "--side-light") == 0) {
            settings.light[0] = -1.0f, settings.light[1] = 0.1f, settings.light[2] = 0.1f;
        } else if (strcmp(argv[i], "--compute") == 0) {
            /* glyphcast's compute ray caster: dispatched before the rendering, composed
               into the engine's attachments inside it. */
            settings.path = GLYPHCAST_PATH_COMPUTE;
        } else if (strcmp(argv[i], "--shadows") == 0) {
            settings.shadows = GLYPHCAST_SHADOWS_HARD;
        } else if (strcmp(argv[i], "--soft-shadows") == 0 && i + 1 < argc) {
            settings.shadows = GLYPHCAST_SHADOWS_SOFT;
            settings.shadow_radius = (float)atof(argv[++i]);
        } else if (strcmp(argv[i], "--ambient-occlusion") == 0 && i + 1 < argc) {
            settings.ambient_occlusion = (float)atof(argv[++i]);
            settings.ambient = 0.6f;
        } else if (strcmp(argv[i], "--basis") == 0 && i + 1 < argc) {
            const char *name = argv[++i];
            sh_slice_step = 1;
            if (strcmp(name, "descoteaux07-legacy") == 0) {
                sh_basis = GLYPHCAST_SH_BASIS_DESCOTEAUX07, sh_legacy = 1;
            } else if (strcmp(name, "descoteaux07") == 0) {
                sh_basis = GLYPHCAST_SH_BASIS_DESCOTEAUX07, sh_legacy = 0;
            } else if (strcmp(name, "tournier07") == 0) {
                sh_basis = GLYPHCAST_SH_BASIS_TOURNIER07, sh_legacy = 0;
            } else {
                fprintf(stderr, "--basis: '%s' is not descoteaux07-legacy, descoteaux07 or "
                                "tournier07\n", name);
                return 2;
            }
        } else {
            fprintf(stderr, "usage: c-example OUT.png [--plain-memory] [--uniform-red] "
                            "[--side-light] [--compute] [--shadows] [--soft-shadows DEGREES] "
                            "[--ambient-occlusion REACH] "
                            "[--basis descoteaux07-legacy|descoteaux07|"
                            "tournier07] [--no-plane] [--no-fragment-stores] "
                            "[--describe FILE.json]\n");
            return 2;
        }
    }
    if (description && !sh_slice_step) {
        fprintf(stderr, "--describe: give --basis too, so that the last frame shows SH glyphs\n");
        return 2;
    }
    Engine e;
    create_engine(&e);
    PlainMemory plain = {.engine = &e};
    GlyphcastAllocator callbacks = {.user = &plain, .allocate = plain_allocate, .free = plain_free};

    GlyphcastRendererDesc desc = {.get_instance_proc_addr = vkGetInstanceProcAddr,
                                  .instance = e.instance,
                                  .physical_device = e.physical_device,
                                  .device = e.device,
                                  .color_format = COLOR_FORMAT,
                                  .depth_format = DEPTH_FORMAT,
                                  .samples = 1,
                                  .depth = GLYPHCAST_DEPTH_STANDARD,
                                  .pipeline_cache = VK_NULL_HANDLE,
                                  .frames_in_flight = IN_FLIGHT,
                                  .render_pass = VK_NULL_HANDLE /* dynamic rendering */,
                                  .allocator = plain_memory ? &callbacks : NULL,
                                  .settings = &settings};
    GlyphcastRenderer *renderer = NULL;
    if (glyphcast_renderer_create(&desc, &renderer) != GLYPHCAST_STATUS_OK) {
        fprintf(stderr, "glyphcast_renderer_create: %s\n", glyphcast_last_error());
        return 1;
    }
    glyphs(renderer, 0.0);

    VkCommandPoolCreateInfo pool_info = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                         .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                         .queueFamilyIndex = e.family};
    VkCommandPool pool;
    CHECK(vkCreateCommandPool(e.device, &pool_info, NULL, &pool));
    VkCommandBuffer cmds[IN_FLIGHT];
    VkCommandBufferAllocateInfo alloc = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                         .commandPool = pool,
                                         .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                         .commandBufferCount = IN_FLIGHT};
    CHECK(vkAllocateCommandBuffers(e.device, &alloc, cmds));
    VkFence fences[IN_FLIGHT];
    Image colors[IN_FLIGHT], depths[IN_FLIGHT];
    for (int i = 0; i < IN_FLIGHT; i++) {
        VkFenceCreateInfo fence = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO,
                                   .flags = VK_FENCE_CREATE_SIGNALED_BIT};
        CHECK(vkCreateFence(e.device, &fence, NULL, &fences[i]));
        colors[i] = create_image(&e, COLOR_FORMAT,
                                 VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                 VK_IMAGE_ASPECT_COLOR_BIT);
        depths[i] = create_image(&e, DEPTH_FORMAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                                 VK_IMAGE_ASPECT_DEPTH_BIT);
    }
    VkBufferCreateInfo buffer_info = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
                                      .size = 4 * WIDTH * HEIGHT,
                                      .usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT};
    VkBuffer readback;
    CHECK(vkCreateBuffer(e.device, &buffer_info, NULL, &readback));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(e.device, readback, &req);
    VkMemoryAllocateInfo readback_alloc = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
        .allocationSize = req.size,
        .memoryTypeIndex = memory_type(&e, req.memoryTypeBits,
                                       VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                           VK_MEMORY_PROPERTY_HOST_COHERENT_BIT)};
    VkDeviceMemory readback_memory;
    CHECK(vkAllocateMemory(e.device, &readback_alloc, NULL, &readback_memory));
    CHECK(vkBindBufferMemory(e.device, readback, readback_memory, 0));

    VkPushConstantRange push = {VK_SHADER_STAGE_VERTEX_BIT, 0, 80};
    VkPipelineLayoutCreateInfo layout_info = {.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
                                              .pushConstantRangeCount = 1,
                                              .pPushConstantRanges = &push};
    VkPipelineLayout plane_layout;
    CHECK(vkCreatePipelineLayout(e.device, &layout_info, NULL, &plane_layout));
    VkPipeline plane = plane_pipeline(&e, plane_layout);

    double eye[3], target[3] = {0, 0, 0}, up[3] = {0, 0, 1};
    for (int frame = 0; frame < FRAMES; frame++) {
        int k = frame % IN_FLIGHT;
        CHECK(vkWaitForFences(e.device, 1, &fences[k], VK_TRUE, UINT64_MAX));
        CHECK(vkResetFences(e.device, 1, &fences[k]));
        if (frame == FRAMES / 2) { /* new glyphs, no wait */
            if (sh_slice_step) {
                glyphs(renderer, 1.0);
            } else {
                tensor_glyphs(renderer, 1.0);
            }
        }
        double angle = -1.3 + 0.05 * frame;
        eye[0] = 4.4 * cos(angle), eye[1] = 4.4 * sin(angle), eye[2] = 3.0;
        Mat4 view = look_at(eye, target, up);
        Mat4 projection = perspective(FOV_Y_DEG * 3.14159265358979323846 / 180.0,
                                      (double)WIDTH / HEIGHT, 0.5, 40.0);
        GlyphcastViewport viewport = {0, 0, WIDTH, HEIGHT};
        GLYPHCAST(renderer, glyphcast_renderer_set_view(renderer, k, view.m, projection.m, &viewport));

        VkCommandBuffer cmd = cmds[k];
        CHECK(vkResetCommandBuffer(cmd, 0));
        VkCommandBufferBeginInfo begin = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                          .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
        CHECK(vkBeginCommandBuffer(cmd, &begin));
        VkImageMemoryBarrier2 to_attachment[2] = {
            barrier(colors[k].image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_COPY_BIT,
                    VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_READ_BIT,
                    VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                    VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT),
            barrier(depths[k].image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                    VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT |
                        VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                        VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT)};
        VkDependencyInfo dependency = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                       .imageMemoryBarrierCount = 2,
                                       .pImageMemoryBarriers = to_attachment};
        vkCmdPipelineBarrier2(cmd, &dependency);
        /* The compute ray caster's dispatches, outside the rendering: they write
           glyphcast's own buffers only (nothing on the fragment path; with the default
           GLYPHCAST_PATH_AUTO on a GPU, this is what lets it take the compute path). */
        GLYPHCAST(renderer, glyphcast_renderer_record_compute(renderer, cmd, k));
        VkRenderingAttachmentInfo color = {
            .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
            .imageView = colors[k].view, .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
            .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR, .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
            .clearValue = {.color = {{0.55f, 0.65f, 0.8f, 1.0f}}}};
        VkRenderingAttachmentInfo depth = {
            .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
            .imageView = depths[k].view, .imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
            .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR, .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
            .clearValue = {.depthStencil = {1.0f, 0}}};
        VkRenderingInfo rendering = {.sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
                                     .renderArea = {{0, 0}, {WIDTH, HEIGHT}},
                                     .layerCount = 1,
                                     .colorAttachmentCount = 1,
                                     .pColorAttachments = &color,
                                     .pDepthAttachment = &depth};
        vkCmdBeginRendering(cmd, &rendering);
        /* The engine's plane first, with its own view-projection ... */
        Mat4 view_proj = multiply(projection, view);
        float push_data[20];
        for (int i = 0; i < 16; i++) push_data[i] = (float)view_proj.m[i];
        push_data[16] = 0.0f, push_data[17] = 0.0f, push_data[18] = 0.08f, push_data[19] = 2.2f;
        VkViewport vp = {0, 0, WIDTH, HEIGHT, 0, 1};
        VkRect2D scissor = {{0, 0}, {WIDTH, HEIGHT}};
        if (draw_plane) {
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, plane);
            vkCmdSetViewport(cmd, 0, 1, &vp);
            vkCmdSetScissor(cmd, 0, 1, &scissor);
            vkCmdPushConstants(cmd, plane_layout, VK_SHADER_STAGE_VERTEX_BIT, 0,
                               sizeof push_data, push_data);
            vkCmdDraw(cmd, 6, 1, 0, 0);
        }
        /* ... then glyphcast's glyphs into the same attachments. */
        GLYPHCAST(renderer, glyphcast_renderer_record(renderer, cmd, k));
        vkCmdEndRendering(cmd);
        if (frame == FRAMES - 1) {
            VkImageMemoryBarrier2 to_transfer = barrier(
                colors[k].image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                VK_ACCESS_2_TRANSFER_READ_BIT);
            VkDependencyInfo d = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                  .imageMemoryBarrierCount = 1,
                                  .pImageMemoryBarriers = &to_transfer};
            vkCmdPipelineBarrier2(cmd, &d);
            VkBufferImageCopy copy = {.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
                                      .imageExtent = {WIDTH, HEIGHT, 1}};
            vkCmdCopyImageToBuffer(cmd, colors[k].image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                   readback, 1, &copy);
            VkMemoryBarrier2 host = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
                                     .srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT,
                                     .srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT,
                                     .dstStageMask = VK_PIPELINE_STAGE_2_HOST_BIT,
                                     .dstAccessMask = VK_ACCESS_2_HOST_READ_BIT};
            VkDependencyInfo h = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                  .memoryBarrierCount = 1,
                                  .pMemoryBarriers = &host};
            vkCmdPipelineBarrier2(cmd, &h);
        }
        CHECK(vkEndCommandBuffer(cmd));
        VkSubmitInfo submit = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
                               .commandBufferCount = 1,
                               .pCommandBuffers = &cmd};
        CHECK(vkQueueSubmit(e.queue, 1, &submit, fences[k]));
    }
    CHECK(vkDeviceWaitIdle(e.device));

    void *pixels;
    CHECK(vkMapMemory(e.device, readback_memory, 0, VK_WHOLE_SIZE, 0, &pixels));
    int glyph_pixels = 0;
    const uint8_t *p = pixels;
    for (int i = 0; i < WIDTH * HEIGHT; i++) /* saturated glyph colours, not grey or sky */
        if (abs(p[4 * i] - p[4 * i + 1]) > 40 || abs(p[4 * i + 1] - p[4 * i + 2]) > 40) glyph_pixels++;
    GlyphcastStatus written = glyphcast_write_png(output, WIDTH, HEIGHT, pixels);
    vkUnmapMemory(e.device, readback_memory);
    if (written != GLYPHCAST_STATUS_OK) {
        fprintf(stderr, "glyphcast_write_png: %s\n", glyphcast_last_error());
        return 1;
    }
    printf("wrote %s: %d glyph pixels, %d validation message(s)\n", output, glyph_pixels,
           validation_messages);
    if (description && describe(description, &settings, eye, target, up, FOV_Y_DEG) != 0)
        return 1;

    glyphcast_renderer_destroy(renderer);
    if (plain_memory)
        printf("plain memory: %d blocks for glyphcast, %d not given back\n", plain.allocated,
               plain.live);
    vkDestroyPipeline(e.device, plane, NULL);
    vkDestroyPipelineLayout(e.device, plane_layout, NULL);
    vkDestroyBuffer(e.device, readback, NULL);
    vkFreeMemory(e.device, readback_memory, NULL);
    for (int i = 0; i < IN_FLIGHT; i++) {
        vkDestroyFence(e.device, fences[i], NULL);
        destroy_image(&e, &colors[i]);
        destroy_image(&e, &depths[i]);
    }
    vkDestroyCommandPool(e.device, pool, NULL);
    vkDestroyDevice(e.device, NULL);
    PFN_vkDestroyDebugUtilsMessengerEXT destroy_messenger =
        (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
            e.instance, "vkDestroyDebugUtilsMessengerEXT");
    destroy_messenger(e.instance, e.messenger, NULL);
    vkDestroyInstance(e.instance, NULL);
    return validation_messages == 0 && glyph_pixels > 200 && plain.live == 0 ? 0 : 1;
}
