// The RAE's weights and its oneDNN network (rae_model.h). Activations are NHWC float32 oneDNN
// memories, one set per level; a convolution over a concatenation cat(p_1, .., p_k) is run as
// k convolutions with the matching input-channel slices of the weights, the later ones adding
// into the first's output (oneDNN's "sum" post-op) and the last applying the leaky ReLU, so no
// concatenated tensor is ever built. The hidden states are double-buffered: frame t reads
// h^{t-1} from one buffer and writes h^t into the other (both argument sets are prepared).
#include "methods/rae/rae_model.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <oneapi/dnnl/dnnl.hpp>
#include <unordered_map>

#include "core/parallel.h"
#include "core/timer.h"
#include "io/small_file.h"
#include "methods/rae/rae_codec_kernels.h"
#include "methods/weights_header.h"
#include "rtd/error.h"

// The OpenMP runtime's API (libgomp, the runtime of Debian's oneDNN), declared here rather than
// through <omp.h>, which only GCC's -fopenmp include path has.
extern "C" {
int omp_get_max_threads(void);
void omp_set_num_threads(int);
}

namespace rtd::rae {

extern const char* const kBuiltinWeightsJson;  // rae_weights_embedded.cpp (generated)

namespace {

using nlohmann::json;

/// RFC 4648 base64 (the weights file's tensor encoding); false on a character outside it.
bool decodeBase64(const std::string& in, std::vector<unsigned char>& out) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  out.clear();
  out.reserve(in.size() / 4 * 3);
  uint32_t acc = 0;
  int bits = 0;
  for (char c : in) {
    if (c == '=') break;
    const int v = value(c);
    if (v < 0) return false;
    acc = (acc << 6) | uint32_t(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((acc >> bits) & 0xff));
    }
  }
  return true;
}

}  // namespace

size_t Weights::parameters() const {
  size_t n = 0;
  for (const auto* group : {&encIn, &encRec, &decA, &decB})
    for (const Conv& c : *group) n += c.weight.size() + c.bias.size();
  return n;
}

Weights parseWeights(const std::string& text, const std::string& source) {
  auto fail = [&](const std::string& what) -> void { throw Error("RAE weights '" + source + "': " + what); };
  json j = parseWeightsHeader(text, source, "RAE", kWeightsFormat, kWeightsVersion,
                                    {{"colorTransform", "log1p"}, {"normalSpace", "view"}, {"upsampling", "bilinear"}});
  Weights w;
  w.source = source;
  const json inputs = j.value("inputs", json());
  if (inputs == json::array({"color"})) {
    w.albedo = w.normal = false;
  } else if (inputs == json::array({"color", "albedo"})) {
    w.normal = false;
  } else if (inputs != json::array({"color", "albedo", "normal"})) {
    fail("field 'inputs' must be [\"color\"], [\"color\", \"albedo\"] or [\"color\", \"albedo\", \"normal\"]");
  }
  const json channels = j.value("channels", json());
  if (!channels.is_array() || channels.size() < 2 || channels.size() > 8)
    fail("field 'channels' must list 2 to 8 channel counts");
  for (const json& c : channels) {
    if (!c.is_number_integer() || c.get<int>() < 1 || c.get<int>() > 1024)
      fail("field 'channels' must hold integers in [1, 1024]");
    w.channels.push_back(c.get<int>());
  }
  for (auto [key, dst] : {std::pair{"slope", &w.slope}, std::pair{"epsilon", &w.epsilon}}) {
    if (!j.contains(key) || !j[key].is_number() || !std::isfinite(j[key].get<double>()))
      fail(std::string("field '") + key + "' must be a finite number");
    *dst = j[key].get<float>();
  }
  if (w.epsilon <= 0) fail("field 'epsilon' must be positive");

  std::unordered_map<std::string, const json*> tensors;
  if (!j.contains("tensors") || !j["tensors"].is_array()) fail("field 'tensors' must be an array");
  for (const json& t : j["tensors"])
    if (t.is_object() && t.contains("name") && t["name"].is_string()) tensors[t["name"].get<std::string>()] = &t;
  auto tensor = [&](const std::string& name, const std::vector<int>& shape) {
    auto it = tensors.find(name);
    if (it == tensors.end()) fail("tensor '" + name + "' is missing");
    const json& t = *it->second;
    std::string shapeText;
    for (int s : shape) shapeText += (shapeText.empty() ? "" : ", ") + std::to_string(s);
    if (t.value("shape", json()) != json(shape)) fail("tensor '" + name + "' must have shape [" + shapeText + "]");
    std::vector<unsigned char> bytes;
    size_t count = 1;
    for (int s : shape) count *= size_t(s);
    if (!t.contains("data") || !t["data"].is_string() || !decodeBase64(t["data"].get<std::string>(), bytes) ||
        bytes.size() != count * 4)
      fail("tensor '" + name + "': field 'data' must be the base64 of " + std::to_string(count) + " float32 values");
    std::vector<float> v(count);
    for (size_t i = 0; i < count; ++i) {  // little-endian float32
      const uint32_t u = uint32_t(bytes[4 * i]) | uint32_t(bytes[4 * i + 1]) << 8 | uint32_t(bytes[4 * i + 2]) << 16 |
                         uint32_t(bytes[4 * i + 3]) << 24;
      std::memcpy(&v[i], &u, 4);
      if (!std::isfinite(v[i])) fail("tensor '" + name + "' holds a non-finite value at " + std::to_string(i));
    }
    return v;
  };
  auto conv = [&](const std::string& name, int out, int in) {
    Conv c;
    c.out = out;
    c.in = in;
    c.weight = tensor(name + ".weight", {out, in, 3, 3});
    c.bias = tensor(name + ".bias", {out});
    return c;
  };
  const int levels = w.levels(), nf = w.featureChannels();
  const auto& C = w.channels;
  for (int l = 0; l < levels; ++l) {
    w.encIn.push_back(conv("encIn." + std::to_string(l), C[l], l == 0 ? 3 + nf : C[l - 1]));
    w.encRec.push_back(conv("encRec." + std::to_string(l), C[l], 2 * C[l]));
  }
  for (int l = 0; l + 1 < levels; ++l) {
    w.decA.push_back(conv("decA." + std::to_string(l), C[l], C[l + 1] + C[l] + nf));
    w.decB.push_back(conv("decB." + std::to_string(l), l ? C[l] : 3, C[l]));
  }
  return w;
}

const std::string& builtinWeightsJson() {
  static const std::string text(kBuiltinWeightsJson);
  return text;
}

Weights loadWeights(const std::string& path) {
  if (path.empty()) return parseWeights(builtinWeightsJson(), "built-in");
  // An untrusted path (a setting): a regular file of at most 64 MiB (io/small_file.h).
  return parseWeights(readSmallFile(path, std::uintmax_t(64) << 20, "RAE weights '" + path + "'"), path);
}

std::vector<Buffer> requiredBuffers(const Weights& w) {
  std::vector<Buffer> b{Buffer::Color};
  if (w.albedo) b.push_back(Buffer::Albedo);
  if (w.normal) b.push_back(Buffer::Normal);
  return b;
}

bool reloadWeights(std::string& requested, std::string& loaded, Weights& w) {
  if (requested == loaded) return false;
  try {
    w = loadWeights(requested);
    loaded = requested;
  } catch (...) {
    requested = loaded;
    throw;
  }
  return true;
}

// ---------------------------------------------------------------------------------------------

using dnnl::memory;
using Tag = memory::format_tag;
using Type = memory::data_type;

struct Network::Impl {
  dnnl::engine engine{dnnl::engine::kind::cpu, 0};
  dnnl::stream stream{engine};
  Weights weights;
  int threads = 0;            // setThreads()
  int width = 0, height = 0;  // the frame's
  int pw = 0, ph = 0;         // padded to weights.multiple()

  struct Op {
    dnnl::primitive primitive;
    std::unordered_map<int, memory> args;
  };
  struct Level {
    int w = 0, h = 0;
    memory u, a, hidden[2], f, up, t, d;  // u: pooled input (l > 0); up, t, d: decoder (l < L-1)
  };
  memory x;  // the network input at level 0
  std::vector<Level> level;
  // Per level, for each parity p (frame reads hidden[p], writes hidden[1 - p]).
  std::vector<std::vector<Op>> encoder[2], decoder[2];
  std::vector<Op> features;  // avg-pooling of f_l
  int parity = 0;

  memory make(int c, int w, int h) { return memory({{1, c, h, w}, Type::f32, Tag::nhwc}, engine); }

  /// The convolution of the input-channel slice [begin, begin + src channels) of `c` from
  /// `src` into `dst`: with c's bias when `first`, else adding into dst; leaky ReLU when `act`.
  Op convolution(const Conv& c, int begin, const memory& src, const memory& dst, bool first, bool act) {
    const int in = int(src.get_desc().dims()[1]);
    const memory::desc wAny({c.out, in, 3, 3}, Type::f32, Tag::any);
    const memory::desc bias({c.out}, Type::f32, Tag::x);
    const memory::dims one{1, 1};
    auto desc = first ? dnnl::convolution_forward::desc(dnnl::prop_kind::forward_inference,
                                                        dnnl::algorithm::convolution_direct, src.get_desc(), wAny,
                                                        bias, dst.get_desc(), one, one, one)
                      : dnnl::convolution_forward::desc(dnnl::prop_kind::forward_inference,
                                                        dnnl::algorithm::convolution_direct, src.get_desc(), wAny,
                                                        dst.get_desc(), one, one, one);
    dnnl::post_ops po;
    if (!first) po.append_sum(1.0f);
    if (act) po.append_eltwise(1.0f, dnnl::algorithm::eltwise_relu, weights.slope, 0.0f);
    dnnl::primitive_attr attr;
    attr.set_post_ops(po);
    const dnnl::convolution_forward::primitive_desc pd(desc, attr, engine);
    memory user({{c.out, in, 3, 3}, Type::f32, Tag::oihw}, engine);
    float* wp = static_cast<float*>(user.get_data_handle());
    for (int o = 0; o < c.out; ++o)
      std::copy_n(c.weight.data() + (size_t(o) * c.in + begin) * 9, size_t(in) * 9, wp + size_t(o) * in * 9);
    memory wm = user;
    if (pd.weights_desc() != user.get_desc()) {
      wm = memory(pd.weights_desc(), engine);
      dnnl::reorder(user, wm).execute(stream, user, wm);
    }
    Op op{dnnl::convolution_forward(pd), {{DNNL_ARG_SRC, src}, {DNNL_ARG_WEIGHTS, wm}, {DNNL_ARG_DST, dst}}};
    if (first) {
      memory b(bias, engine);
      std::copy(c.bias.begin(), c.bias.end(), static_cast<float*>(b.get_data_handle()));
      op.args[DNNL_ARG_BIAS] = b;
    }
    return op;
  }

  /// cat(parts) -> conv c -> dst, as one convolution per part (the header comment).
  void concatConvolution(std::vector<Op>& ops, const Conv& c, const std::vector<memory>& parts, const memory& dst,
                         bool act) {
    int begin = 0;
    for (size_t i = 0; i < parts.size(); ++i) {
      ops.push_back(convolution(c, begin, parts[i], dst, i == 0, act && i + 1 == parts.size()));
      begin += int(parts[i].get_desc().dims()[1]);
    }
  }

  // (A variadic list rather than an initializer list of memories: GCC 12 warns, wrongly, on
  // destroying the latter's backing array.)
  template <class... M> static std::vector<memory> parts(const M&... m) {
    std::vector<memory> v;
    (v.push_back(m), ...);
    return v;
  }

  Op pooling(dnnl::algorithm alg, const memory& src, const memory& dst) {
    const memory::dims two{2, 2}, zero{0, 0};
    const dnnl::pooling_forward::desc d(dnnl::prop_kind::forward_inference, alg, src.get_desc(), dst.get_desc(), two,
                                        two, zero, zero);
    return {dnnl::pooling_forward({d, engine}), {{DNNL_ARG_SRC, src}, {DNNL_ARG_DST, dst}}};
  }

  Op upsampling(const memory& src, const memory& dst) {
    const dnnl::resampling_forward::desc d(dnnl::prop_kind::forward_inference, dnnl::algorithm::resampling_linear,
                                           src.get_desc(), dst.get_desc());
    return {dnnl::resampling_forward({d, engine}), {{DNNL_ARG_SRC, src}, {DNNL_ARG_DST, dst}}};
  }

  void build() {
    const int L = weights.levels(), nf = weights.featureChannels();
    const auto& C = weights.channels;
    level.assign(size_t(L), Level{});
    x = make(3 + nf, pw, ph);
    for (int l = 0; l < L; ++l) {
      Level& v = level[size_t(l)];
      v.w = pw >> l;
      v.h = ph >> l;
      if (l) v.u = make(C[size_t(l) - 1], v.w, v.h);
      v.a = make(C[size_t(l)], v.w, v.h);
      for (auto& h : v.hidden) h = make(C[size_t(l)], v.w, v.h);
      if (nf && l + 1 < L) v.f = make(nf, v.w, v.h);
      if (l + 1 < L) {
        v.up = make(C[size_t(l) + 1], v.w, v.h);
        v.t = make(C[size_t(l)], v.w, v.h);
        v.d = make(l ? C[size_t(l)] : 3, v.w, v.h);
      }
    }
    features.clear();
    if (nf)
      for (int l = 1; l + 1 < L; ++l)
        features.push_back(pooling(dnnl::algorithm::pooling_avg_exclude_padding, level[size_t(l) - 1].f, level[size_t(l)].f));
    for (int p = 0; p < 2; ++p) {
      // Frame parity p reads h^(t-1) from hidden[p] and writes h^t into hidden[q].
      const int q = 1 - p;
      encoder[p].assign(size_t(L), {});
      decoder[p].assign(size_t(L), {});
      for (int l = 0; l < L; ++l) {
        Level& v = level[size_t(l)];
        auto& ops = encoder[p][size_t(l)];
        if (l) ops.push_back(pooling(dnnl::algorithm::pooling_max, level[size_t(l) - 1].hidden[q], v.u));
        ops.push_back(convolution(weights.encIn[size_t(l)], 0, l ? v.u : x, v.a, true, true));
        concatConvolution(ops, weights.encRec[size_t(l)], parts(v.a, v.hidden[p]), v.hidden[q], true);
      }
      for (int l = L - 2; l >= 0; --l) {
        Level& v = level[size_t(l)];
        auto& ops = decoder[p][size_t(l)];
        const memory& below = l + 2 == L ? level[size_t(l) + 1].hidden[q] : level[size_t(l) + 1].d;
        ops.push_back(upsampling(below, v.up));
        concatConvolution(ops, weights.decA[size_t(l)], nf ? parts(v.up, v.hidden[q], v.f) : parts(v.up, v.hidden[q]),
                          v.t, true);
        ops.push_back(convolution(weights.decB[size_t(l)], 0, v.t, v.d, true, l > 0));
      }
    }
    stream.wait();
  }

  void zeroHidden() {
    for (Level& v : level)
      for (memory& h : v.hidden) std::memset(h.get_data_handle(), 0, h.get_desc().get_size());
    parity = 0;
  }

  void execute(std::vector<Op>& ops) {
    for (Op& op : ops) op.primitive.execute(stream, op.args);
    stream.wait();
  }
};

namespace {

/// Bounds the OpenMP threads of the primitives this thread runs by n (and by the bound it had:
/// OMP_NUM_THREADS still lowers it; OpenMP's nthreads-var is the calling thread's), restoring
/// the previous bound when it goes out of scope.
class OpenMpThreads {
 public:
  explicit OpenMpThreads(int n) : saved_(omp_get_max_threads()) {
    if (n > 0) omp_set_num_threads(std::min(n, saved_));
  }
  ~OpenMpThreads() { omp_set_num_threads(saved_); }
  OpenMpThreads(const OpenMpThreads&) = delete;
  OpenMpThreads& operator=(const OpenMpThreads&) = delete;

 private:
  int saved_;
};

}  // namespace

Network::Network() : impl_(std::make_unique<Impl>()) {}
Network::~Network() = default;

void Network::setThreads(int threads) { impl_->threads = threads; }

void Network::configure(const Weights& weights, int width, int height) {
  Impl& m = *impl_;
  const OpenMpThreads bound(m.threads);  // the weights' reorders run OpenMP regions too
  m.weights = weights;
  m.width = width;
  m.height = height;
  const int k = weights.multiple();
  m.pw = (width + k - 1) / k * k;
  m.ph = (height + k - 1) / k * k;
  m.build();
  m.zeroHidden();
}

void Network::reset() { impl_->zeroHidden(); }

void Network::forEachState(const std::function<void(const float*, size_t)>& visit) const {
  for (const auto& v : impl_->level)
    for (const memory& h : v.hidden)
      visit(static_cast<const float*>(h.get_data_handle()), h.get_desc().get_size() / sizeof(float));
}

void Network::run(const Plane* color, const Plane* albedo, const Plane* normal, Plane3& out, FrameStats& stats) {
  Impl& m = *impl_;
  const OpenMpThreads bound(m.threads);
  const Weights& wt = m.weights;
  const int w = m.width, h = m.height, pw = m.pw, L = wt.levels();
  const int nf = wt.featureChannels(), cin = 3 + nf;
  const float eps = wt.epsilon;
  {
    // x = [log1p(max(c, 0) / k), features], k = clamp(a, 0, 1) + eps (or 1), f_0 = features
    // (albedo clamped to [0, 1], the trained domain), both padded by replicating the last row
    // and column.
    PassTimer t(stats, "encode");
    float* x = static_cast<float*>(m.x.get_data_handle());
    float* f = nf ? static_cast<float*>(m.level[0].f.get_data_handle()) : nullptr;
    parallelRows(m.ph, [&](int py) {
      const int y = std::min(py, h - 1);
      // Per channel: k and log1p(max(c, 0) / k) of the frame's row y (vectorized), then
      // interleaved into x and f with the padding columns repeating the last pixel.
      thread_local std::vector<float> scratch;
      scratch.resize(size_t(6) * w);
      float* k = scratch.data();
      float* logc = k + size_t(3) * w;
      for (int c = 0; c < 3; ++c) {
        float* kc = k + size_t(c) * w;
        if (wt.albedo) {
          const float* a = albedo[c].row(y);
          for (int xx = 0; xx < w; ++xx) kc[xx] = std::clamp(a[xx], 0.0f, 1.0f) + eps;
        }
        RTD_SIMD(raeLog1pRatio)(color[c].row(y), wt.albedo ? kc : nullptr, logc + size_t(c) * w, w);
      }
      for (int px = 0; px < pw; ++px) {
        const int xx = std::min(px, w - 1);
        float* xp = x + (size_t(py) * pw + px) * cin;
        float feat[6];
        int n = 0;
        if (wt.albedo)
          for (int c = 0; c < 3; ++c) feat[n++] = std::clamp(albedo[c](xx, y), 0.0f, 1.0f);
        if (wt.normal)
          for (int c = 0; c < 3; ++c) feat[n++] = normal[c](xx, y);
        for (int c = 0; c < 3; ++c) xp[c] = logc[size_t(c) * w + xx];
        std::copy_n(feat, n, xp + 3);
        if (f) std::copy_n(feat, n, f + (size_t(py) * pw + px) * nf);
      }
    });
  }
  {
    PassTimer t(stats, "features");
    m.execute(m.features);
  }
  for (int l = 0; l < L; ++l) {
    PassTimer t(stats, "encoder" + std::to_string(l));
    m.execute(m.encoder[m.parity][size_t(l)]);
  }
  for (int l = L - 2; l >= 0; --l) {
    PassTimer t(stats, "decoder" + std::to_string(l));
    m.execute(m.decoder[m.parity][size_t(l)]);
  }
  m.parity ^= 1;
  PassTimer t(stats, "decode");
  const float* y = static_cast<const float*>(m.level[0].d.get_data_handle());
  parallelRows(h, [&](int py) {
    thread_local std::vector<float> scratch;
    scratch.resize(size_t(2) * w);
    float* yc = scratch.data();
    float* k = yc + w;
    for (int c = 0; c < 3; ++c) {
      for (int px = 0; px < w; ++px) yc[px] = y[(size_t(py) * pw + px) * 3 + c];
      if (wt.albedo) {
        const float* a = albedo[c].row(py);
        for (int px = 0; px < w; ++px) k[px] = std::clamp(a[px], 0.0f, 1.0f) + eps;
      }
      RTD_SIMD(raeExpm1Scaled)(yc, wt.albedo ? k : nullptr, out[c].row(py), w, kMaxOutput);
    }
  });
}

}  // namespace rtd::rae
