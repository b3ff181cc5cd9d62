// A C++17 engine loop that embeds glyphcast through its installed C library
// (include/glyphcast.h, libglyphcast_c; see CMakeLists.txt).
//
// The engine owns everything Vulkan: its instance (with the validation layer and a
// messenger that counts its messages), device and queue, its own render pass (colour
// cleared to the background and stored, depth cleared to 1), three frames in flight (a
// command buffer, a fence, colour and depth images and a framebuffer each) and the
// memory glyphcast's buffers live in (GlyphcastAllocator callbacks: one
// vkAllocateMemory per block, counted). glyphcast is given the handles and the render
// pass once and records its glyphs into the engine's command buffer inside the pass each
// frame. Nine SH glyphs lie on a 3 x 3 grid in the plane z = 0, seen from above; every
// third frame they are replaced (a slice step). No window: the last frame is copied to a
// buffer and written as a PNG.
//
//   glyphcast-cpp-example OUT.png
//
// Exit status: 0, or 1 on any failure or validation message, or when glyphcast did not
// give back every block of memory.
#include <glyphcast.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

constexpr uint32_t kWidth = 192;
constexpr uint32_t kHeight = 144;
constexpr uint32_t kInFlight = 3;
constexpr int kFrames = 9;
constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_SRGB;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;
// The background, linear RGB: a dark grey (sRGB 0.2 is about 124 of 255).
constexpr VkClearColorValue kBackground = {{0.2f, 0.2f, 0.2f, 1.0f}};
// The camera: above the grid's centre, looking down; the grid's x to the right, y up.
constexpr double kEyeHeight = 7.0;
constexpr double kFovY = 35.0 * 3.14159265358979323846 / 180.0;

int validation_messages = 0;

VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                          VkDebugUtilsMessageTypeFlagsEXT,
                                          const VkDebugUtilsMessengerCallbackDataEXT *data,
                                          void *) {
    std::fprintf(stderr, "validation: %s\n", data->pMessage);
    ++validation_messages;
    return VK_FALSE;
}

void check(VkResult result, const char *call) {
    if (result != VK_SUCCESS)
        throw std::runtime_error(std::string(call) + " failed (" + std::to_string(result) + ")");
}
#define CHECK(call) check((call), #call)

void check_glyphcast(GlyphcastStatus status, const GlyphcastRenderer *renderer,
                     const char *call) {
    if (status != GLYPHCAST_STATUS_OK) {
        const char *message =
            renderer ? glyphcast_renderer_last_error(renderer) : glyphcast_last_error();
        throw std::runtime_error(std::string(call) + ": " + message);
    }
}
#define GLYPHCAST(renderer, call) check_glyphcast((call), (renderer), #call)

// Column-major 4 x 4 matrices, as Vulkan and glyphcast take them.
using Mat4 = std::array<double, 16>;

// The view from (0, 0, kEyeHeight) towards the origin, y up: a translation along z.
Mat4 view_from_above() {
    return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -kEyeHeight, 1};
}

// A Vulkan perspective (y down in clip space) with standard depth: 0 at near, 1 at far.
Mat4 perspective(double fov_y, double aspect, double near, double far) {
    const double h = 1.0 / std::tan(0.5 * fov_y);
    return {h / aspect, 0, 0, 0, 0, -h, 0, 0, 0, 0, far / (near - far), -1,
            0, 0, near * far / (near - far), 0};
}

struct Image {
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
};

struct Frame {
    Image color, depth;
    VkFramebuffer framebuffer = VK_NULL_HANDLE;
    VkCommandBuffer commands = VK_NULL_HANDLE;
    VkFence done = VK_NULL_HANDLE;
};

class Engine {
  public:
    Engine() {
        create_instance();
        choose_device();
        create_device();
    }
    Engine(const Engine &) = delete;
    Engine &operator=(const Engine &) = delete;
    ~Engine() {
        if (device_) vkDestroyDevice(device_, nullptr);
        if (messenger_) {
            auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
            destroy(instance_, messenger_, nullptr);
        }
        if (instance_) vkDestroyInstance(instance_, nullptr);
    }

    VkInstance instance() const { return instance_; }
    VkPhysicalDevice physical_device() const { return physical_device_; }
    VkDevice device() const { return device_; }
    VkQueue queue() const { return queue_; }
    uint32_t family() const { return family_; }

    // The first memory type in `bits` with `flags` (all of them), or UINT32_MAX.
    uint32_t memory_type(uint32_t bits, VkMemoryPropertyFlags flags) const {
        VkPhysicalDeviceMemoryProperties props;
        vkGetPhysicalDeviceMemoryProperties(physical_device_, &props);
        for (uint32_t i = 0; i < props.memoryTypeCount; ++i)
            if ((bits & (1u << i)) && (props.memoryTypes[i].propertyFlags & flags) == flags)
                return i;
        return UINT32_MAX;
    }

  private:
    void create_instance() {
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.pApplicationName = "glyphcast C++ example";
        app.apiVersion = VK_API_VERSION_1_3;
        const char *layers[] = {"VK_LAYER_KHRONOS_validation"};
        const char *extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
        VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        info.pApplicationInfo = &app;
        info.enabledLayerCount = 1;
        info.ppEnabledLayerNames = layers;
        info.enabledExtensionCount = 1;
        info.ppEnabledExtensionNames = extensions;
        CHECK(vkCreateInstance(&info, nullptr, &instance_));
        VkDebugUtilsMessengerCreateInfoEXT messenger{
            VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                    VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
        messenger.pfnUserCallback = on_message;
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
        if (!create) throw std::runtime_error("no vkCreateDebugUtilsMessengerEXT");
        CHECK(create(instance_, &messenger, nullptr, &messenger_));
    }

    // The first Vulkan 1.3 device with a graphics queue.
    void choose_device() {
        uint32_t count = 0;
        CHECK(vkEnumeratePhysicalDevices(instance_, &count, nullptr));
        std::vector<VkPhysicalDevice> devices(count);
        CHECK(vkEnumeratePhysicalDevices(instance_, &count, devices.data()));
        for (VkPhysicalDevice candidate : devices) {
            VkPhysicalDeviceProperties props;
            vkGetPhysicalDeviceProperties(candidate, &props);
            if (props.apiVersion < VK_API_VERSION_1_3) continue;
            uint32_t n = 0;
            vkGetPhysicalDeviceQueueFamilyProperties(candidate, &n, nullptr);
            std::vector<VkQueueFamilyProperties> families(n);
            vkGetPhysicalDeviceQueueFamilyProperties(candidate, &n, families.data());
            for (uint32_t f = 0; f < n; ++f)
                if (families[f].queueFlags & VK_QUEUE_GRAPHICS_BIT) {
                    physical_device_ = candidate;
                    family_ = f;
                    VkPhysicalDeviceDriverProperties driver{
                        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
                    VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
                    props2.pNext = &driver;
                    vkGetPhysicalDeviceProperties2(candidate, &props2);
                    std::printf("device: %s, driver: %s\n", props.deviceName, driver.driverInfo);
                    return;
                }
        }
        throw std::runtime_error("no Vulkan 1.3 device with a graphics queue");
    }

    void create_device() {
        const float priority = 1.0f;
        VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        queue.queueFamilyIndex = family_;
        queue.queueCount = 1;
        queue.pQueuePriorities = &priority;
        // What glyphcast asks of the device: Vulkan 1.3 with dynamic rendering (even
        // when, as here, it draws in the host's render pass), and storage writes in
        // fragment shaders.
        VkPhysicalDeviceVulkan13Features v13{
            VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
        v13.dynamicRendering = VK_TRUE;
        v13.synchronization2 = VK_TRUE;
        VkPhysicalDeviceFeatures core{};
        core.fragmentStoresAndAtomics = VK_TRUE;
        VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
        info.pNext = &v13;
        info.pEnabledFeatures = &core;
        info.queueCreateInfoCount = 1;
        info.pQueueCreateInfos = &queue;
        CHECK(vkCreateDevice(physical_device_, &info, nullptr, &device_));
        vkGetDeviceQueue(device_, family_, 0, &queue_);
    }

    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_device_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    uint32_t family_ = 0;
};

// The engine's memory for glyphcast (GlyphcastAllocator): one vkAllocateMemory per
// block, host-visible blocks mapped whole; counts the blocks so that the engine can tell
// whether glyphcast gave every one back.
struct HostMemory {
    const Engine *engine;
    int allocated = 0;
    int live = 0;

    static GlyphcastStatus allocate(void *user, const GlyphcastMemoryRequest *request,
                                    GlyphcastMemoryBlock *block) {
        auto *self = static_cast<HostMemory *>(user);
        const Engine &e = *self->engine;
        uint32_t type = e.memory_type(request->memory_type_bits,
                                      request->required_flags | request->preferred_flags);
        if (type == UINT32_MAX) type = e.memory_type(request->memory_type_bits, request->required_flags);
        if (type == UINT32_MAX) return GLYPHCAST_STATUS_VULKAN;
        VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        info.allocationSize = request->size;
        info.memoryTypeIndex = type;
        VkDeviceMemory memory;
        if (vkAllocateMemory(e.device(), &info, nullptr, &memory) != VK_SUCCESS)
            return GLYPHCAST_STATUS_VULKAN;
        void *mapped = nullptr;
        if (request->usage != GLYPHCAST_MEMORY_USE_DEVICE_LOCAL &&
            vkMapMemory(e.device(), memory, 0, VK_WHOLE_SIZE, 0, &mapped) != VK_SUCCESS) {
            vkFreeMemory(e.device(), memory, nullptr);
            return GLYPHCAST_STATUS_VULKAN;
        }
        *block = GlyphcastMemoryBlock{memory, 0, request->size, mapped, 0};
        ++self->allocated;
        ++self->live;
        return GLYPHCAST_STATUS_OK;
    }

    static void free(void *user, const GlyphcastMemoryBlock *block) {
        auto *self = static_cast<HostMemory *>(user);
        vkFreeMemory(self->engine->device(), block->memory, nullptr);  // unmaps it too
        --self->live;
    }
};

Image create_image(const Engine &e, VkFormat format, VkImageUsageFlags usage,
                   VkImageAspectFlags aspect) {
    Image img;
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {kWidth, kHeight, 1};
    info.mipLevels = 1;
    info.arrayLayers = 1;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    CHECK(vkCreateImage(e.device(), &info, nullptr, &img.image));
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(e.device(), img.image, &req);
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = e.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    CHECK(vkAllocateMemory(e.device(), &alloc, nullptr, &img.memory));
    CHECK(vkBindImageMemory(e.device(), img.image, img.memory, 0));
    VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    view.image = img.image;
    view.viewType = VK_IMAGE_VIEW_TYPE_2D;
    view.format = format;
    view.subresourceRange = {aspect, 0, 1, 0, 1};
    CHECK(vkCreateImageView(e.device(), &view, nullptr, &img.view));
    return img;
}

void destroy_image(const Engine &e, Image &img) {
    vkDestroyImageView(e.device(), img.view, nullptr);
    vkDestroyImage(e.device(), img.image, nullptr);
    vkFreeMemory(e.device(), img.memory, nullptr);
}

// The engine's render pass: one subpass with a colour attachment (cleared, stored, left
// ready to be copied out) and a depth attachment (cleared to 1, standard depth).
VkRenderPass create_render_pass(const Engine &e) {
    VkAttachmentDescription attachments[2] = {};
    attachments[0].format = kColorFormat;
    attachments[0].samples = VK_SAMPLE_COUNT_1_BIT;
    attachments[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    attachments[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    attachments[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    attachments[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    attachments[0].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    attachments[0].finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    attachments[1] = attachments[0];
    attachments[1].format = kDepthFormat;
    attachments[1].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    attachments[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    VkAttachmentReference color{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkAttachmentReference depth{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &color;
    subpass.pDepthStencilAttachment = &depth;
    // In: the previous use of the frame's images (the copy out of the colour, the depth
    // tests) is done before this frame clears them. Out: the copy waits for the colour.
    VkSubpassDependency dependencies[2] = {};
    dependencies[0].srcSubpass = VK_SUBPASS_EXTERNAL;
    dependencies[0].dstSubpass = 0;
    dependencies[0].srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT |
                                   VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    dependencies[0].srcAccessMask = VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    dependencies[0].dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                   VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                                   VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    dependencies[0].dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                                    VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                                    VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    dependencies[1].srcSubpass = 0;
    dependencies[1].dstSubpass = VK_SUBPASS_EXTERNAL;
    dependencies[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dependencies[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    dependencies[1].dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
    dependencies[1].dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    info.attachmentCount = 2;
    info.pAttachments = attachments;
    info.subpassCount = 1;
    info.pSubpasses = &subpass;
    info.dependencyCount = 2;
    info.pDependencies = dependencies;
    VkRenderPass pass;
    CHECK(vkCreateRenderPass(e.device(), &info, nullptr, &pass));
    return pass;
}

// Nine glyphs of SH bands 0 to 4 (DIPY's default basis, descoteaux07 legacy) on a 3 x 3
// grid 1.1 apart at z = 0: a sphere stretched along a direction that turns with `turn`
// and from glyph to glyph. Band 0 dominates, so every glyph covers its centre.
void set_glyphs(GlyphcastRenderer *renderer, double turn) {
    constexpr uint32_t kCount = 9, kPer = 15;
    std::vector<double> centers(3 * kCount), scales(kCount, 0.45), coefficients(kPer * kCount, 0.0);
    for (uint32_t k = 0; k < kCount; ++k) {
        centers[3 * k] = 1.1 * (static_cast<int>(k % 3) - 1);
        centers[3 * k + 1] = 1.1 * (static_cast<int>(k / 3) - 1);
        double *c = &coefficients[kPer * k];
        c[0] = 2.5;                                        // band 0
        c[1 + (k % 2 ? 4 : 0)] = 1.0 * std::cos(turn + k);  // band 2, order -2 or 2
        c[3] = 1.2;                                        // band 2, order 0: along z
        c[10] = 0.5 * std::sin(turn + 0.5 * k);            // band 4, order 0
    }
    GLYPHCAST(renderer, glyphcast_renderer_set_sh_glyphs(renderer, 4, GLYPHCAST_SH_BASIS_DESCOTEAUX07,
                                                         1, kCount, centers.data(), scales.data(),
                                                         coefficients.data()));
}

int run(const char *output) {
    Engine e;
    HostMemory memory{&e};
    const GlyphcastAllocator callbacks{&memory, &HostMemory::allocate, &HostMemory::free};
    const VkRenderPass pass = create_render_pass(e);

    GlyphcastSettings settings;
    glyphcast_settings_default(&settings);  // exact, colour by direction
    settings.ambient = 0.3f;

    GlyphcastRendererDesc desc{};
    desc.get_instance_proc_addr = vkGetInstanceProcAddr;
    desc.instance = e.instance();
    desc.physical_device = e.physical_device();
    desc.device = e.device();
    desc.color_format = kColorFormat;
    desc.depth_format = kDepthFormat;
    desc.samples = 1;
    desc.depth = GLYPHCAST_DEPTH_STANDARD;
    desc.pipeline_cache = VK_NULL_HANDLE;
    desc.frames_in_flight = kInFlight;
    desc.render_pass = pass;  // the engine's render pass, subpass 0
    desc.subpass = 0;
    desc.allocator = &callbacks;
    desc.settings = &settings;
    GlyphcastRenderer *renderer = nullptr;
    GLYPHCAST(nullptr, glyphcast_renderer_create(&desc, &renderer));

    VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool_info.queueFamilyIndex = e.family();
    VkCommandPool pool;
    CHECK(vkCreateCommandPool(e.device(), &pool_info, nullptr, &pool));
    std::array<Frame, kInFlight> frames;
    for (Frame &f : frames) {
        VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        alloc.commandPool = pool;
        alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        alloc.commandBufferCount = 1;
        CHECK(vkAllocateCommandBuffers(e.device(), &alloc, &f.commands));
        VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        fence.flags = VK_FENCE_CREATE_SIGNALED_BIT;
        CHECK(vkCreateFence(e.device(), &fence, nullptr, &f.done));
        f.color = create_image(e, kColorFormat,
                               VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                               VK_IMAGE_ASPECT_COLOR_BIT);
        f.depth = create_image(e, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                               VK_IMAGE_ASPECT_DEPTH_BIT);
        VkImageView views[2] = {f.color.view, f.depth.view};
        VkFramebufferCreateInfo fb{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
        fb.renderPass = pass;
        fb.attachmentCount = 2;
        fb.pAttachments = views;
        fb.width = kWidth;
        fb.height = kHeight;
        fb.layers = 1;
        CHECK(vkCreateFramebuffer(e.device(), &fb, nullptr, &f.framebuffer));
    }
    // The read-back of the last frame.
    VkBufferCreateInfo buffer_info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    buffer_info.size = 4 * kWidth * kHeight;
    buffer_info.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    VkBuffer readback;
    CHECK(vkCreateBuffer(e.device(), &buffer_info, nullptr, &readback));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(e.device(), readback, &req);
    VkMemoryAllocateInfo readback_alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    readback_alloc.allocationSize = req.size;
    readback_alloc.memoryTypeIndex = e.memory_type(
        req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    VkDeviceMemory readback_memory;
    CHECK(vkAllocateMemory(e.device(), &readback_alloc, nullptr, &readback_memory));
    CHECK(vkBindBufferMemory(e.device(), readback, readback_memory, 0));

    const Mat4 view = view_from_above();
    const Mat4 projection = perspective(kFovY, double(kWidth) / kHeight, 0.5, 40.0);
    const GlyphcastViewport viewport{0, 0, kWidth, kHeight};
    for (int frame = 0; frame < kFrames; ++frame) {
        Frame &f = frames[frame % kInFlight];
        const uint32_t k = frame % kInFlight;
        // Frame k's previous submission is done: its command buffer, images and
        // glyphcast's frame-k state may be reused.
        CHECK(vkWaitForFences(e.device(), 1, &f.done, VK_TRUE, UINT64_MAX));
        CHECK(vkResetFences(e.device(), 1, &f.done));
        if (frame % 3 == 0) set_glyphs(renderer, 0.4 * frame);  // a slice step, no wait
        GLYPHCAST(renderer, glyphcast_renderer_set_view(renderer, k, view.data(),
                                                        projection.data(), &viewport));
        CHECK(vkResetCommandBuffer(f.commands, 0));
        VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        CHECK(vkBeginCommandBuffer(f.commands, &begin));
        VkClearValue clears[2];
        clears[0].color = kBackground;
        clears[1].depthStencil = {1.0f, 0};
        VkRenderPassBeginInfo pass_begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
        pass_begin.renderPass = pass;
        pass_begin.framebuffer = f.framebuffer;
        pass_begin.renderArea = {{0, 0}, {kWidth, kHeight}};
        pass_begin.clearValueCount = 2;
        pass_begin.pClearValues = clears;
        vkCmdBeginRenderPass(f.commands, &pass_begin, VK_SUBPASS_CONTENTS_INLINE);
        // The engine's own geometry would go here; glyphcast's glyphs share its depth.
        GLYPHCAST(renderer, glyphcast_renderer_record(renderer, f.commands, k));
        vkCmdEndRenderPass(f.commands);
        if (frame == kFrames - 1) {
            // The render pass left the colour in TRANSFER_SRC_OPTIMAL, after the colour
            // writes (its outgoing dependency).
            VkBufferImageCopy copy{};
            copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            copy.imageExtent = {kWidth, kHeight, 1};
            vkCmdCopyImageToBuffer(f.commands, f.color.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                   readback, 1, &copy);
            VkMemoryBarrier host{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
            host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
            vkCmdPipelineBarrier(f.commands, VK_PIPELINE_STAGE_TRANSFER_BIT,
                                 VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &host, 0, nullptr, 0, nullptr);
        }
        CHECK(vkEndCommandBuffer(f.commands));
        VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        submit.commandBufferCount = 1;
        submit.pCommandBuffers = &f.commands;
        CHECK(vkQueueSubmit(e.queue(), 1, &submit, f.done));
    }
    CHECK(vkDeviceWaitIdle(e.device()));

    void *pixels = nullptr;
    CHECK(vkMapMemory(e.device(), readback_memory, 0, VK_WHOLE_SIZE, 0, &pixels));
    const GlyphcastStatus written =
        glyphcast_write_png(output, kWidth, kHeight, static_cast<const uint8_t *>(pixels));
    vkUnmapMemory(e.device(), readback_memory);
    GLYPHCAST(nullptr, written);

    glyphcast_renderer_destroy(renderer);
    std::printf("wrote %s; %d blocks of memory for glyphcast, %d not given back; "
                "%d validation message(s)\n",
                output, memory.allocated, memory.live, validation_messages);
    vkDestroyBuffer(e.device(), readback, nullptr);
    vkFreeMemory(e.device(), readback_memory, nullptr);
    for (Frame &f : frames) {
        vkDestroyFramebuffer(e.device(), f.framebuffer, nullptr);
        vkDestroyFence(e.device(), f.done, nullptr);
        destroy_image(e, f.color);
        destroy_image(e, f.depth);
    }
    vkDestroyCommandPool(e.device(), pool, nullptr);
    vkDestroyRenderPass(e.device(), pass, nullptr);
    return memory.live == 0 && memory.allocated > 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char **argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: glyphcast-cpp-example OUT.png\n");
        return 2;
    }
    int status = 1;
    try {
        status = run(argv[1]);
    } catch (const std::exception &error) {
        std::fprintf(stderr, "error: %s\n", error.what());
        status = 1;
    }
    // The messages of the device's and instance's destruction (in ~Engine) count too.
    if (validation_messages > 0) {
        std::fprintf(stderr, "%d validation message(s)\n", validation_messages);
        return 1;
    }
    return status;
}
