// The compute shaders embedded in the library (SPIR-V compiled by glslc at build time).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rtd::vk {

struct EmbeddedShader {
  const char* name;  ///< file stem of the .comp source, e.g. "reproject"
  const uint32_t* code;
  size_t words;
};

const std::vector<EmbeddedShader>& embeddedShaders();

}  // namespace rtd::vk
