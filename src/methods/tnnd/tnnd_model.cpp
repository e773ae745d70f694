// TNND's weights and CPU passes (tnnd_model.h). The automaton step is written for the
// compiler's auto-vectorizer: a row is processed in chunks of 64 pixels, first the separable
// 3x3 filters of every channel into a 39 x 64 perception block, then the 39x9 rule as 351
// multiply-adds over the chunk, then the sigmoid (a vectorizable exp) and the residual update.
#include "methods/tnnd/tnnd_model.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/conventions.h"
#include "core/parallel.h"
#include "io/small_file.h"
#include "methods/weights_header.h"
#include "rtd/error.h"

namespace rtd::tnnd {

extern const char* const kBuiltinWeightsJson;  // tnnd_weights_embedded.cpp (generated)

namespace {

using nlohmann::json;

/// e^x for |x| < 87: 2^u with u = x log2(e) = n + f, n = round(u), 2^f by its degree-5 Taylor
/// polynomial (relative error < 3e-6). Branch-free, so loops over it vectorize.
inline float expApprox(float x) {
  const float u = std::min(std::max(x * 1.44269504088896341f, -126.0f), 126.0f);
  const float n = std::floor(u + 0.5f);
  const float f = u - n;
  constexpr float l1 = 0.693147180559945f, l2 = l1 * l1 / 2, l3 = l2 * l1 / 3, l4 = l3 * l1 / 4, l5 = l4 * l1 / 5;
  const float p = 1.0f + f * (l1 + f * (l2 + f * (l3 + f * (l4 + f * l5))));
  return p * std::bit_cast<float>((int32_t(n) + 127) << 23);
}

inline float sigmoid(float z) { return 1.0f / (1.0f + expApprox(-z)); }

}  // namespace

Weights parseWeights(const std::string& text, const std::string& source) {
  auto fail = [&](const std::string& what) -> void { throw Error("TNND weights '" + source + "': " + what); };
  json j = parseWeightsHeader(text, source, "TNND", kWeightsFormat, kWeightsVersion,
                                    {{"colorTransform", "log1p"}, {"normalSpace", "view"}});
  Weights w;
  w.source = source;
  const json& rows = j.contains("W") ? j["W"] : json();
  if (!rows.is_array() || rows.size() != size_t(kPerception)) fail("field 'W' must be an array of 39 rows of 9 numbers");
  for (int k = 0; k < kPerception; ++k) {
    if (!rows[k].is_array() || rows[k].size() != size_t(kState)) fail("field 'W[" + std::to_string(k) + "]' must hold 9 numbers");
    for (int c = 0; c < kState; ++c) {
      if (!rows[k][c].is_number() || !std::isfinite(rows[k][c].get<double>()))
        fail("field 'W[" + std::to_string(k) + "][" + std::to_string(c) + "]' must be a finite number");
      w.w[size_t(k) * kState + c] = rows[k][c].get<float>();
    }
  }
  const json& b = j.contains("b") ? j["b"] : json();
  if (!b.is_array() || b.size() != size_t(kState)) fail("field 'b' must be an array of 9 numbers");
  for (int c = 0; c < kState; ++c) {
    if (!b[c].is_number() || !std::isfinite(b[c].get<double>())) fail("field 'b[" + std::to_string(c) + "]' must be a finite number");
    w.b[c] = b[c].get<float>();
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
  return parseWeights(readSmallFile(path, std::uintmax_t(64) << 20, "TNND weights '" + path + "'"), path);
}

void resize(State& s, int w, int h) {
  for (auto& p : s) p.resize(w, h);
}

void encode(const Plane* color, const std::vector<Plane>& normal, const std::vector<Plane>& albedo, const Camera& camera,
            State& s) {
  const int w = color[0].width, h = color[0].height;
  const std::array<float, 9> r = worldToViewRotation(camera);  // n_view = R n_world
  parallelRows(h, [&](int y) {
    for (int c = 0; c < 3; ++c) {
      const float* in = color[c].row(y);
      float* out = s[c].row(y);
      for (int x = 0; x < w; ++x) out[x] = std::log1p(std::max(in[x], 0.0f));
      std::copy_n(albedo[c].row(y), w, s[6 + c].row(y));
    }
    const float *nx = normal[0].row(y), *ny = normal[1].row(y), *nz = normal[2].row(y);
    for (int c = 0; c < 3; ++c) {
      float* out = s[3 + c].row(y);
      const float a = r[c * 3], b = r[c * 3 + 1], d = r[c * 3 + 2];
      for (int x = 0; x < w; ++x) out[x] = a * nx[x] + b * ny[x] + d * nz[x];
    }
  });
}

void decode(const State& s, Plane3& out) {
  const int w = s[0].width, h = s[0].height;
  parallelRows(h, [&](int y) {
    for (int c = 0; c < 3; ++c) {
      const float* in = s[c].row(y);
      float* o = out[c].row(y);
      for (int x = 0; x < w; ++x) o[x] = std::expm1(std::max(in[x], 0.0f));
    }
  });
}

std::array<float, kPerception> perceive(const State& s, int x, int y) {
  const int w = s[0].width, h = s[0].height;
  auto at = [&](int c, int dx, int dy) { return s[c](std::clamp(x + dx, 0, w - 1), std::clamp(y + dy, 0, h - 1)); };
  std::array<float, kPerception> p{};
  for (int c = 0; c < kState; ++c) {
    float g = 0, sx = 0, sy = 0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const float v = at(c, dx, dy);
        const float smooth = float((2 - std::abs(dx)) * (2 - std::abs(dy)));  // [1 2 1] x [1 2 1]
        g += smooth * v;
        sx += float(dx * (2 - std::abs(dy))) * v;
        sy += float(dy * (2 - std::abs(dx))) * v;
      }
    p[c] = at(c, 0, 0);
    if (c < 3) p[9 + c] = g / 16;
    p[12 + c] = g / 16 - at(c, 0, 0);  // Laplace = Gaussian - identity
    p[21 + c] = sx / 8;
    p[30 + c] = sy / 8;
  }
  return p;
}

void step(const Weights& weights, const State& s, State& next) {
  const int w = s[0].width, h = s[0].height;
  constexpr int kChunk = 64;
  parallelRows(h, [&](int y) {
    const int ym = std::max(y - 1, 0), yp = std::min(y + 1, h - 1);
    // Vertical passes with a one-pixel halo: v = [1 2 1] down the column, d = [-1 0 1].
    alignas(64) float v[kState][kChunk + 2], d[kState][kChunk + 2];
    alignas(64) float p[kPerception][kChunk];
    alignas(64) float z[kState][kChunk];
    for (int x0 = 0; x0 < w; x0 += kChunk) {
      const int n = std::min(kChunk, w - x0);
      for (int c = 0; c < kState; ++c) {
        const float *a = s[c].row(ym), *b = s[c].row(y), *e = s[c].row(yp);
        for (int i = 1; i <= n; ++i) {
          const int x = x0 + i - 1;
          v[c][i] = a[x] + 2.0f * b[x] + e[x];
          d[c][i] = e[x] - a[x];
        }
        for (int i : {0, n + 1}) {  // the halo columns, borders replicated
          const int x = std::clamp(x0 + i - 1, 0, w - 1);
          v[c][i] = a[x] + 2.0f * b[x] + e[x];
          d[c][i] = e[x] - a[x];
        }
        // Horizontal passes: Gaussian [1 2 1]/16, Sobel x [-1 0 1]/8 of v, Sobel y [1 2 1]/8 of d.
        float* ps = p[c];
        float* pl = p[12 + c];
        float* px = p[21 + c];
        float* py = p[30 + c];
        float* pg = c < 3 ? p[9 + c] : nullptr;
        const float* centre = b + x0;
        for (int i = 0; i < n; ++i) {
          const float g = (v[c][i] + 2.0f * v[c][i + 1] + v[c][i + 2]) * (1.0f / 16.0f);
          ps[i] = centre[i];
          pl[i] = g - centre[i];
          px[i] = (v[c][i + 2] - v[c][i]) * (1.0f / 8.0f);
          py[i] = (d[c][i] + 2.0f * d[c][i + 1] + d[c][i + 2]) * (1.0f / 8.0f);
        }
        if (pg)
          for (int i = 0; i < n; ++i) pg[i] = (v[c][i] + 2.0f * v[c][i + 1] + v[c][i + 2]) * (1.0f / 16.0f);
      }
      // The rule: z = p W (Eq. 2.16), then s + sigmoid(z) + b (Eq. 2.17).
      for (int j = 0; j < kState; ++j) std::fill_n(z[j], n, 0.0f);
      for (int k = 0; k < kPerception; ++k) {
        const float* pk = p[k];
        for (int j = 0; j < kState; ++j) {
          const float wkj = weights.w[size_t(k) * kState + j];
          float* zj = z[j];
          for (int i = 0; i < n; ++i) zj[i] += pk[i] * wkj;
        }
      }
      for (int j = 0; j < kState; ++j) {
        const float* in = s[j].row(y) + x0;
        float* out = next[j].row(y) + x0;
        const float bj = weights.b[j];
        for (int i = 0; i < n; ++i) out[i] = in[i] + sigmoid(z[j][i]) + bj;
      }
    }
  });
}

}  // namespace rtd::tnnd
