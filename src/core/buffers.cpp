// Names and channel layouts of the frame buffers (rtd/frame.h).
#include <string_view>

#include "rtd/denoiser.h"
#include "rtd/frame.h"

namespace rtd {

namespace {
struct BufferDesc {
  std::string_view name;
  std::string_view channels;  // one letter per channel; "I" = an id channel named "id"
};
constexpr BufferDesc kBuffers[kBufferCount] = {
    {"color", "RGB"},         {"albedo", "RGB"},          {"normal", "XYZ"},
    {"depth", "Z"},           {"position", "XYZ"},        {"motion", "XY"},
    {"objectId", "I"},        {"materialId", "I"},        {"roughness", "V"},
    {"metalness", "V"},       {"depthGradient", "XY"},    {"direct", "RGB"},
    {"indirect", "RGB"},      {"diffuse", "RGB"},         {"specular", "RGB"},
    {"reflectedPosition", "XYZ"}, {"reflectedNormal", "XYZ"}, {"reflectedAlbedo", "RGB"},
    {"secondaryDistance", "Z"}, {"mirrorDirection", "XYZ"}, {"seed", "I"},
    {"sampleMask", "V"},      {"emission", "RGB"},        {"gradientSample", "V"},
    {"gradientPrevious", "V"}, {"gradientCurrent", "V"},  {"reflectedFootprint", "V"},
    {"diffuseAlbedo", "RGB"}, {"specularAlbedo", "RGB"}, {"indirectDiffuse", "RGB"},
    {"hiddenArea", "V"},
};
}  // namespace

std::string_view bufferName(Buffer b) { return kBuffers[int(b)].name; }
std::string_view bufferChannels(Buffer b) { return kBuffers[int(b)].channels; }
int bufferChannelCount(Buffer b) { return int(kBuffers[int(b)].channels.size()); }
std::optional<Buffer> bufferFromName(std::string_view name) {
  for (int i = 0; i < kBufferCount; ++i)
    if (kBuffers[i].name == name) return Buffer(i);
  return std::nullopt;
}

std::string_view backendName(Backend b) { return b == Backend::Cpu ? "cpu" : "vulkan"; }

}  // namespace rtd
