// One line per method. Each method's folder (src/methods/<name>/) defines its factories.
#include "core/registry.h"

#include "core/settings_reflect.h"
#include "rtd/methods/accumulate.h"
#include "rtd/methods/asvgf.h"
#include "rtd/methods/svgf.h"
#include "rtd/methods/bmfr.h"
#include "rtd/methods/rae.h"
#include "rtd/methods/tnnd.h"

namespace rtd {

std::unique_ptr<Denoiser> createAccumulateCpu(tbb::task_arena&);
std::unique_ptr<Denoiser> createSvgfCpu(tbb::task_arena&);
std::unique_ptr<Denoiser> createBmfrCpu(tbb::task_arena&);
std::unique_ptr<Denoiser> createTnndCpu(tbb::task_arena&);
std::unique_ptr<Denoiser> createAsvgfCpu(tbb::task_arena&);
std::unique_ptr<Denoiser> createRaeCpu(tbb::task_arena&);
std::unique_ptr<StereoDenoiser> createSvgfStereoCpu(tbb::task_arena&);

// Vulkan factories (src/methods/<name>/<name>_vulkan.cpp); null where the build has no Vulkan.
#ifdef RTD_HAS_VULKAN
#define RTD_VULKAN_FACTORY(f) &f
std::unique_ptr<Denoiser> createAccumulateVulkan(vk::Context&);
std::unique_ptr<Denoiser> createSvgfVulkan(vk::Context&);
std::unique_ptr<Denoiser> createBmfrVulkan(vk::Context&);
std::unique_ptr<Denoiser> createTnndVulkan(vk::Context&);
std::unique_ptr<Denoiser> createAsvgfVulkan(vk::Context&);
std::unique_ptr<Denoiser> createRaeVulkan(vk::Context&);
std::unique_ptr<StereoDenoiser> createSvgfStereoVulkan(vk::Context&);
#else
#define RTD_VULKAN_FACTORY(f) nullptr
#endif

template <class S> static std::vector<SettingInfo> defaultsOf() { return detail::listSettings(S{}); }

const std::vector<MethodEntry>& methodRegistry() {
  static const std::vector<MethodEntry> entries = {
      {"accumulate", "temporal accumulation with robust reprojection (baseline of SVGF/BMFR)",
       &defaultsOf<AccumulateSettings>, &createAccumulateCpu, RTD_VULKAN_FACTORY(createAccumulateVulkan)},
      {"svgf", "spatiotemporal variance-guided filtering (Schied 2017; Dundr, Gersthofer, Voorhuis variants)",
       &defaultsOf<SvgfSettings>, &createSvgfCpu, RTD_VULKAN_FACTORY(createSvgfVulkan), &createSvgfStereoCpu,
       RTD_VULKAN_FACTORY(createSvgfStereoVulkan)},
      {"bmfr", "blockwise multi-order feature regression (Koskela et al. 2019)", &defaultsOf<BmfrSettings>,
       &createBmfrCpu, RTD_VULKAN_FACTORY(createBmfrVulkan)},
      {"tnnd", "tiny neural network denoiser, a 360-parameter neural cellular automaton (Higginson 2023)",
       &defaultsOf<TnndSettings>, &createTnndCpu, RTD_VULKAN_FACTORY(createTnndVulkan)},
      {"asvgf", "adaptive SVGF: history dropped where re-shaded gradient samples changed (Schied 2018; Higginson)",
       &defaultsOf<AsvgfSettings>, &createAsvgfCpu, RTD_VULKAN_FACTORY(createAsvgfVulkan)},
      {"rae", "recurrent denoising autoencoder, a U-Net with a recurrent block per encoder level (Chaitanya 2017)",
       &defaultsOf<RaeSettings>, &createRaeCpu, RTD_VULKAN_FACTORY(createRaeVulkan)},
  };
  return entries;
}

const MethodEntry* findMethod(std::string_view name) {
  for (const auto& e : methodRegistry())
    if (name == e.name) return &e;
  return nullptr;
}

std::vector<MethodInfo> listMethods() {
  std::vector<MethodInfo> out;
  for (const auto& e : methodRegistry())
    out.push_back({e.name, e.summary, e.defaults(), e.createCpu != nullptr, e.createVulkan != nullptr});
  return out;
}

}  // namespace rtd
