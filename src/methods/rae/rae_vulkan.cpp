// Method "rae" on the Vulkan backend: the network of rae_model.h as compute shaders
// (shaders/rae_*.comp): "encode" (input, padding, view normals), per encoder level a 2x2 max
// pooling and the recurrent block's two 3x3 convolutions, per decoder level a bilinear x2
// upsampling and two convolutions, then "decode" (output, crop). A convolution over a
// concatenation reads its parts in place (rae_conv.comp), so no concatenated tensor is built.
// Activations and hidden states are float32 planes on the GPU (fp16 storage: docs/methods/rae.md);
// the hidden states are double-buffered (frame t reads h^(t-1) from one set and writes h^t into
// the other) and cleared by reset(), a camera cut, a resize and new weights. Every weight and
// bias lives in one device-local storage buffer, uploaded when the network is built for a
// frame size (the first frame, a resize, new weights).
#if defined(RTD_HAS_VULKAN)
#include <algorithm>

#include "backend/vulkan/vulkan_denoiser.h"
#include "core/conventions.h"
#include "methods/rae/rae_model.h"
#include "rtd/methods/rae.h"

namespace rtd {

namespace {

class RaeVulkan final : public vk::VulkanDenoiser<RaeSettings> {
 public:
  explicit RaeVulkan(vk::Context& ctx) : VulkanDenoiser(ctx), weights_(rae::loadWeights("")) {}
  std::vector<Buffer> requiredBuffers() const override { return rae::requiredBuffers(weights_); }

 protected:
  void settingsChanged() override {
    if (!rae::reloadWeights(settings_.weights, loaded_, weights_)) return;
    // New weights, new network: the next frame reallocates (after the GPU is idle, with the
    // descriptor sets of the old buffers dropped) and starts from a cleared state.
    width_ = height_ = 0;
  }

  void resizeHistory(int w, int h) override {
    const rae::Weights& wt = weights_;
    const int L = wt.levels(), nf = wt.featureChannels(), k = wt.multiple();
    const auto& C = wt.channels;
    pw_ = (w + k - 1) / k * k;
    ph_ = (h + k - 1) / k * k;
    x_.allocate(ctx_, pw_, ph_, 3 + nf);
    level_.clear();
    level_.resize(size_t(L));
    for (int l = 0; l < L; ++l) {
      Level& v = level_[size_t(l)];
      v.w = pw_ >> l;
      v.h = ph_ >> l;
      if (l) v.u.allocate(ctx_, v.w, v.h, C[size_t(l) - 1]);
      v.a.allocate(ctx_, v.w, v.h, C[size_t(l)]);
      for (auto& hidden : v.hidden) hidden.allocate(ctx_, v.w, v.h, C[size_t(l)]);
      if (l + 1 < L) {
        if (nf && l) v.f.allocate(ctx_, v.w, v.h, nf);
        v.up.allocate(ctx_, v.w, v.h, C[size_t(l) + 1]);
        v.t.allocate(ctx_, v.w, v.h, C[size_t(l)]);
        v.d.allocate(ctx_, v.w, v.h, l ? C[size_t(l)] : 3);
      }
    }
    output_.allocate(ctx_, w, h, 3);

    // Every convolution's weight [out][in][3][3] then bias [out], one after the other.
    std::vector<float> all;
    auto add = [&](const std::vector<rae::Conv>& group, std::vector<ConvAt>& at) {
      at.clear();
      for (const rae::Conv& c : group) {
        at.push_back({uint32_t(all.size()), uint32_t(all.size() + c.weight.size()), uint32_t(c.out)});
        all.insert(all.end(), c.weight.begin(), c.weight.end());
        all.insert(all.end(), c.bias.begin(), c.bias.end());
      }
    };
    add(wt.encIn, encIn_);
    add(wt.encRec, encRec_);
    add(wt.decA, decA_);
    add(wt.decB, decB_);
    weightsBuffer_ = vk::DeviceBuffer(ctx_, all.size() * sizeof(float), false);
    ctx_.upload(weightsBuffer_, all.data(), all.size() * sizeof(float));
  }
  void resetHistory() override { clearState_ = true; }

  const vk::Planes& process(vk::Recorder& rec, const vk::GpuFrame& frame, const vk::GpuFrame*) override {
    const rae::Weights& wt = weights_;
    const int L = wt.levels(), nf = wt.featureChannels();
    const auto& C = wt.channels;
    const int p = parity_, q = 1 - p;  // this frame reads hidden[p] (h^(t-1)), writes hidden[q] (h^t)
    if (clearState_ || !settings_.recurrent) {
      rec.pass("clear state");
      for (Level& v : level_) rec.fill(v.hidden[p].buffer, 0);
      clearState_ = false;
    }
    const vk::Binding albedo = frame.bindingOf(Buffer::Albedo, ctx_);
    const uint32_t w = uint32_t(frame.width), h = uint32_t(frame.height);

    rec.pass("encode");
    struct EncodePC {
      uint32_t width, height, paddedWidth, paddedHeight, useAlbedo, useNormal;
      float epsilon;
      float r[9];
    } epc{w, h, uint32_t(pw_), uint32_t(ph_), wt.albedo, wt.normal, wt.epsilon, {}};
    const std::array<float, 9> r = worldToViewRotation(frame.cameraValue);
    std::copy(r.begin(), r.end(), epc.r);
    rec.dispatch("rae_encode", {frame[Buffer::Color], albedo, frame.bindingOf(Buffer::Normal, ctx_), x_}, epc, pw_, ph_);

    if (nf && L > 2) {
      rec.pass("features");  // f_l = avgpool2(f_(l-1)), f_0 = x's planes 3..
      for (int l = 1; l + 1 < L; ++l)
        pool("rae_pool_average", rec, l == 1 ? x_ : level_[size_t(l) - 1].f, l == 1 ? 3 : 0, nf, level_[size_t(l)].f);
    }
    for (int l = 0; l < L; ++l) {
      rec.pass("encoder" + std::to_string(l));
      Level& v = level_[size_t(l)];
      if (l) pool("rae_pool", rec, level_[size_t(l) - 1].hidden[q], 0, C[size_t(l) - 1], v.u);
      convolution(rec, encIn_[size_t(l)], {l ? Part{&v.u, 0, C[size_t(l) - 1]} : Part{&x_, 0, 3 + nf}}, v.a, true);
      convolution(rec, encRec_[size_t(l)], {Part{&v.a, 0, C[size_t(l)]}, Part{&v.hidden[p], 0, C[size_t(l)]}},
                  v.hidden[q], true);
    }
    for (int l = L - 2; l >= 0; --l) {
      rec.pass("decoder" + std::to_string(l));
      Level& v = level_[size_t(l)];
      const vk::Planes& below = l + 2 == L ? level_[size_t(l) + 1].hidden[q] : level_[size_t(l) + 1].d;
      struct ResamplePC {
        uint32_t width, height, channels;
      } upc{uint32_t(v.w), uint32_t(v.h), uint32_t(C[size_t(l) + 1])};
      rec.dispatch("rae_upsample", {below, v.up}, upc, v.w, v.h);
      std::vector<Part> parts{{&v.up, 0, C[size_t(l) + 1]}, {&v.hidden[q], 0, C[size_t(l)]}};
      if (nf) parts.push_back(l ? Part{&v.f, 0, nf} : Part{&x_, 3, nf});
      convolution(rec, decA_[size_t(l)], parts, v.t, true);
      convolution(rec, decB_[size_t(l)], {Part{&v.t, 0, C[size_t(l)]}}, v.d, l > 0);
    }
    parity_ = q;

    rec.pass("decode");
    struct DecodePC {
      uint32_t width, height, paddedWidth, paddedHeight, useAlbedo;
      float epsilon, maxOutput;
    } dpc{w, h, uint32_t(pw_), uint32_t(ph_), wt.albedo, wt.epsilon, rae::kMaxOutput};
    rec.dispatch("rae_decode", {level_[0].d, albedo, output_}, dpc, frame.width, frame.height);
    return output_;
  }

 private:
  /// Where one convolution's weights and bias start in weightsBuffer_ (floats).
  struct ConvAt {
    uint32_t weight, bias, out;
  };
  /// One part of a concatenation: `channels` planes of `planes` from plane `first`.
  struct Part {
    const vk::Planes* planes;
    int first, channels;
  };
  struct Level {
    int w = 0, h = 0;
    // u: pooled input (l > 0); a: the block's first activation; hidden: h_l (two frames);
    // f: the features pooled to l (0 < l < L-1); up, t, d: the decoder block (l < L-1).
    vk::Planes u, a, hidden[2], f, up, t, d;
  };

  /// 2x2 pooling of `channels` planes of `in` from plane `first` into `out` (its size).
  void pool(const char* shader, vk::Recorder& rec, const vk::Planes& in, int first, int channels, vk::Planes& out) {
    struct PoolPC {
      uint32_t width, height, channels, first;
    } pc{uint32_t(out.width), uint32_t(out.height), uint32_t(channels), uint32_t(first)};
    rec.dispatch(shader, {in, out}, pc, out.width, out.height);
  }

  /// out = conv(cat(parts)) (+ leaky ReLU), the parts read in place (rae_conv.comp).
  void convolution(vk::Recorder& rec, const ConvAt& c, const std::vector<Part>& parts, vk::Planes& out, bool act) {
    // rae_conv.comp's output channels per workgroup (16, or 4 in rae_conv_narrow: layers of
    // at most 4 outputs), and its tile size.
    const bool narrow = c.out <= 4;
    const int outGroup = narrow ? 4 : 16;
    constexpr int kTile = 16;
    struct ConvPC {
      uint32_t width, height, tilesY, channels[3], first[3], outChannels, weightOffset, biasOffset, activation;
      float slope;
    } pc{};
    pc.width = uint32_t(out.width);
    pc.height = uint32_t(out.height);
    pc.tilesY = uint32_t((out.height + kTile - 1) / kTile);
    pc.outChannels = c.out;
    pc.weightOffset = c.weight;
    pc.biasOffset = c.bias;
    pc.activation = act;
    pc.slope = weights_.slope;
    std::vector<vk::Binding> bindings;
    for (size_t i = 0; i < 3; ++i) {
      bindings.push_back(i < parts.size() ? vk::Binding(*parts[i].planes) : vk::Binding(ctx_.dummy()));
      pc.channels[i] = i < parts.size() ? uint32_t(parts[i].channels) : 0;
      pc.first[i] = i < parts.size() ? uint32_t(parts[i].first) : 0;
    }
    bindings.push_back(weightsBuffer_);
    bindings.push_back(out);
    const int groups = (int(c.out) + outGroup - 1) / outGroup;
    rec.dispatch(narrow ? "rae_conv_narrow" : "rae_conv", bindings, pc, out.width, int(pc.tilesY) * kTile * groups);
  }

  rae::Weights weights_;
  std::string loaded_;  // the "weights" setting weights_ came from ("" = built-in)
  int pw_ = 0, ph_ = 0;  // the frame padded to weights_.multiple()
  vk::Planes x_, output_;
  std::vector<Level> level_;
  std::vector<ConvAt> encIn_, encRec_, decA_, decB_;
  vk::DeviceBuffer weightsBuffer_;
  int parity_ = 0;
  bool clearState_ = true;
};

}  // namespace

std::unique_ptr<Denoiser> createRaeVulkan(vk::Context& ctx) { return std::make_unique<RaeVulkan>(ctx); }

}  // namespace rtd
#endif
