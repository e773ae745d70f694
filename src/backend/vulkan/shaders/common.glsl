// Shared by every compute shader of the Vulkan backend. Images are planes of width*height
// 32-bit values (plane c of a buffer starts at c * width * height), as on the CPU, so loads and
// stores of neighbouring invocations are consecutive addresses (coalesced).
#extension GL_EXT_scalar_block_layout : enable

// 16x16 workgroups: 256 invocations, a multiple of every vendor's wave/subgroup size.
#define RTD_LOCAL_SIZE layout(local_size_x = 16, local_size_y = 16, local_size_z = 1) in;

// Rec. 709 luminance, evaluated without fused multiply-add like the CPU backend (GCC does not
// contract in ISO C++ mode), so both backends take the same decisions on the same inputs.
float luminance(vec3 c) {
  precise float l = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
  return l;
}

// CIE 1976 lightness L* of relative luminance y (white = 1), as cieLightness() on the CPU.
float cieLightness(float y) {
  const float kDelta3 = 216.0 / 24389.0;
  const float f = y > kDelta3 ? pow(y, 1.0 / 3.0) : y * (841.0 / 108.0) + 4.0 / 29.0;
  return 116.0 * f - 16.0;
}

// The luminance of moments, variance and w_l (MomentLuminance: 0 Rec709, 1 Rec601, 2 CIE L*).
float momentLuminance(uint mode, vec3 c) {
  if (mode == 1u) {
    precise float l = 0.299 * c.r + 0.587 * c.g + 0.114 * c.b;
    return l;
  }
  if (mode == 2u) return cieLightness(max(0.0, luminance(c)));
  return luminance(c);
}

bool outside(uvec2 p, uint width, uint height) { return p.x >= width || p.y >= height; }

// FXAA's luma of linear HDR radiance, sqrt(Y / (1 + Y)) (fxaaLuma in src/passes/fxaa.h).
float fxaaLuma(vec3 c) {
  const float y = max(0.0, luminance(c));
  return sqrt(y / (1.0 + y));
}

// log(1 + x) for x >= 0 and e^x - 1 for x >= 0 (the learned methods' colour transform, std::log1p and
// std::expm1 on the CPU): below 0.01 by their series, where log(1.0 + x) and exp(x) - 1.0 would lose digits.
float log1pNonNegative(float x) { return x < 0.01 ? x * (1.0 - x * (0.5 - x * (1.0 / 3.0))) : log(1.0 + x); }
float expm1NonNegative(float x) { return x < 0.01 ? x * (1.0 + x * (0.5 + x * (1.0 / 6.0))) : exp(x) - 1.0; }
