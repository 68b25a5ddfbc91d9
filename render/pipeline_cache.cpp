#include "pipeline_cache.h"

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "mesh/file_io.h"
#include "vk_check.h"

namespace qp {

namespace {

constexpr char kMagic[8] = {'Q', 'P', 'P', 'C', 'A', 'C', 'H', 'E'};
constexpr uint32_t kFormatVersion = 1;

struct FileHeader {
    char magic[8];
    uint32_t version;
    uint32_t dataSize;
    uint64_t dataHash;
};
static_assert(sizeof(FileHeader) == 24);

uint64_t fnv1a(const char* data, size_t size) {
    uint64_t hash = 0xcbf29ce484222325ull;
    for (size_t i = 0; i < size; ++i) hash = (hash ^ uint8_t(data[i])) * 0x100000001b3ull;
    return hash;
}

// Empty when `file` holds driver data this device accepts, else why not.
std::string checkFile(const VulkanContext& ctx, const std::string& file) {
    FileHeader header;
    if (file.size() < sizeof header) return "it is too short to be a pipeline cache";
    std::memcpy(&header, file.data(), sizeof header);
    if (std::memcmp(header.magic, kMagic, sizeof kMagic) != 0) return "it is not a Quadplan pipeline cache";
    if (header.version != kFormatVersion) return "it has format version " + std::to_string(header.version);
    const char* data = file.data() + sizeof header;
    if (header.dataSize != file.size() - sizeof header) return "it is truncated or has trailing bytes";
    if (fnv1a(data, header.dataSize) != header.dataHash) return "its contents are damaged (hash mismatch)";

    VkPipelineCacheHeaderVersionOne vk;
    if (header.dataSize < sizeof vk) return "its driver data is too short";
    std::memcpy(&vk, data, sizeof vk);
    if (vk.headerVersion != VK_PIPELINE_CACHE_HEADER_VERSION_ONE || vk.headerSize < sizeof vk)
        return "its driver data has an unknown header";
    if (vk.vendorID != ctx.properties.vendorID || vk.deviceID != ctx.properties.deviceID ||
        std::memcmp(vk.pipelineCacheUUID, ctx.properties.pipelineCacheUUID, VK_UUID_SIZE) != 0)
        return "it was made by another device or driver version";
    return {};
}

}  // namespace

std::string defaultPipelineCachePath() {
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    if (xdg && xdg[0] == '/') return std::string(xdg) + "/quadplan/pipelines.bin";
    const char* home = std::getenv("HOME");
    if (home && home[0]) return std::string(home) + "/.cache/quadplan/pipelines.bin";
    return {};
}

Result<PipelineCache> loadPipelineCache(const VulkanContext& ctx, const std::string& path,
                                        std::vector<std::string>* warnings) {
    PipelineCache cache;
    cache.path = path;
    std::string file;
    std::error_code ec;
    if (!path.empty() && std::filesystem::exists(path, ec)) {
        Result<std::string> read = readFile(path);
        std::string why = read ? checkFile(ctx, *read) : read.error().message;
        if (why.empty()) {
            file = std::move(*read);
            cache.loadedFromFile = true;
        } else if (warnings) {
            warnings->push_back("ignoring the pipeline cache '" + path + "': " + why);
        }
    }

    VkPipelineCacheCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
    if (cache.loadedFromFile) {
        info.initialDataSize = file.size() - sizeof(FileHeader);
        info.pInitialData = file.data() + sizeof(FileHeader);
    }
    VK_CHECK(vkCreatePipelineCache(ctx.device, &info, nullptr, &cache.cache));
    return cache;
}

Status savePipelineCache(const VulkanContext& ctx, const PipelineCache& cache) {
    if (cache.path.empty()) return success();
    size_t size = 0;
    VK_CHECK(vkGetPipelineCacheData(ctx.device, cache.cache, &size, nullptr));
    std::string file(sizeof(FileHeader) + size, '\0');
    VK_CHECK(vkGetPipelineCacheData(ctx.device, cache.cache, &size, file.data() + sizeof(FileHeader)));
    file.resize(sizeof(FileHeader) + size);

    FileHeader header;
    std::memcpy(header.magic, kMagic, sizeof kMagic);
    header.version = kFormatVersion;
    header.dataSize = uint32_t(size);
    header.dataHash = fnv1a(file.data() + sizeof header, size);
    std::memcpy(file.data(), &header, sizeof header);

    const std::filesystem::path dir = std::filesystem::path(cache.path).parent_path();
    std::error_code ec;
    if (!dir.empty()) std::filesystem::create_directories(dir, ec);
    if (ec) return Error{"cannot create the directory '" + dir.string() + "': " + ec.message()};
    return writeFileAtomically(cache.path, file);
}

void destroyPipelineCache(const VulkanContext& ctx, PipelineCache& cache) {
    if (cache.cache) vkDestroyPipelineCache(ctx.device, cache.cache, nullptr);
    cache = PipelineCache{};
}

}  // namespace qp
