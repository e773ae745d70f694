#include "methods/asvgf/asvgf_passes.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "core/parallel.h"

namespace rtd::asvgf {

svgf::FilterParams filterParams(const AsvgfSettings& s) {
  svgf::FilterParams p;
  p.variance.shortHistoryFrames = s.shortHistoryFrames;
  p.variance.radius = s.spatialVarianceRadius;
  p.variance.sigmaDepth = s.sigmaDepth;
  svgf::setDepthEpsilon(p.variance, s.depthEpsilon, s.depthEpsilonRelative);
  p.variance.normalExponent = std::max(1, int(std::lround(s.sigmaNormal)));
  p.iterations = s.atrousIterations;
  p.feedbackLevel = s.feedbackLevel;
  p.sigmaLuminance = s.sigmaLuminance;
  p.luminanceEpsilon = s.luminanceEpsilon;
  return p;
}

std::vector<Buffer> requiredBuffers(const AsvgfSettings& s) {
  std::vector<Buffer> b{Buffer::Color, Buffer::Normal, Buffer::Depth};
  if (s.gradientSource == AsvgfGradientSource::samples)
    b.insert(b.end(), {Buffer::GradientSample, Buffer::GradientPrevious, Buffer::GradientCurrent});
  return b;
}

std::vector<Buffer> extraBuffers(const AsvgfSettings& s) {
  std::vector<Buffer> b{Buffer::DepthGradient};
  if (s.reflectedNormals) b.push_back(Buffer::ReflectedNormal);
  if (s.taa.taaOwnSurface) b.push_back(Buffer::ObjectId);  // the own-surface box's keys (passes/taa_keys.h)
  return b;
}

void GradientImage::resize(int w, int h, int pad) {
  width = strata(w);
  height = strata(h);
  guide.resize(width, height, pad);
  for (auto& l : level) l.resize(width, height, pad);
  for (auto& v : valid) v.resize(width, height, pad);
  noLuminanceWeight.resize(width, height, pad);
  result.resize(width, height);
}

namespace {

// Stratum (sx, sy) takes the guide features of full-resolution pixel (x, y); the depth gradient
// is per pixel there and per stratum (3 pixels) here.
void takeFeatures(const AtrousGuide& full, int x, int y, GradientImage& g, int sx, int sy) {
  g.guide.depth.at(sx, sy) = full.depth.at(x, y);
  for (int c = 0; c < 3; ++c) g.guide.normal[c].at(sx, sy) = full.normal[c].at(x, y);
  g.guide.gradX.at(sx, sy) = float(kStratum) * full.gradX.at(x, y);
  g.guide.gradY.at(sx, sy) = float(kStratum) * full.gradY.at(x, y);
}

// Level 0 of stratum (sx, sy): G in colour 0, everything else 0.
void setStratum(GradientImage& g, int sx, int sy, float gradient, bool valid) {
  AtrousImage& l = g.level[0];
  l.color[0].at(sx, sy) = valid ? gradient : 0.0f;
  l.color[1].at(sx, sy) = l.color[2].at(sx, sy) = l.lum.at(sx, sy) = l.var.at(sx, sy) = 0.0f;
  g.valid[0].at(sx, sy) = valid ? 1.0f : 0.0f;
}

}  // namespace

size_t gradientFromSamples(const Plane& sampleMask, const Plane& previous, const Plane& current,
                           const AtrousGuide& guide, float scale, GradientImage& out) {
  const int w = sampleMask.width, h = sampleMask.height;
  std::atomic<size_t> found{0};
  parallelRows(out.height, [&](int sy) {
    size_t n = 0;
    for (int sx = 0; sx < out.width; ++sx) {
      int px = -1, py = -1;
      for (int y = sy * kStratum; y < std::min(h, (sy + 1) * kStratum) && px < 0; ++y)
        for (int x = sx * kStratum; x < std::min(w, (sx + 1) * kStratum); ++x)
          if (sampleMask(x, y) > 0.5f) {
            px = x;
            py = y;
            break;
          }
      const bool valid = px >= 0;
      n += valid;
      if (!valid) {
        px = std::min(w - 1, sx * kStratum + 1);
        py = std::min(h - 1, sy * kStratum + 1);
      }
      takeFeatures(guide, px, py, out, sx, sy);
      setStratum(out, sx, sy, valid ? scale * temporalGradient(previous(px, py), current(px, py)) : 0.0f, valid);
    }
    found += n;
  });
  return found;
}

size_t historyLuminances(const Reprojection& rp, const Plane3& cur, const Plane& m1, const Plane& m2,
                         MomentLuminance luminance, const AtrousGuide& guide, GradientImage& out) {
  const int w = rp.width, h = rp.height;
  std::atomic<size_t> found{0};
  parallelRows(out.height, [&](int sy) {
    size_t valid = 0;
    for (int sx = 0; sx < out.width; ++sx) {
      float sc = 0, sh = 0, sv = 0;  // float sums, as the GPU twin
      int n = 0;
      for (int y = sy * kStratum; y < std::min(h, (sy + 1) * kStratum); ++y)
        for (int x = sx * kStratum; x < std::min(w, (sx + 1) * kStratum); ++x) {
          const size_t i = size_t(y) * w + x;
          if (rp.kind[i] == Reprojection::None) continue;
          const float lh = rp.gather(m1, i);
          sc += momentLuminance(luminance, cur[0].data[i], cur[1].data[i], cur[2].data[i]);
          sh += lh;
          sv += std::max(0.0f, rp.gather(m2, i) - lh * lh);
          ++n;
        }
      takeFeatures(guide, std::min(w - 1, sx * kStratum + 1), std::min(h - 1, sy * kStratum + 1), out, sx, sy);
      setStratum(out, sx, sy, n > 0 ? sc / float(n) : 0.0f, n > 0);
      if (n > 0) {
        // The mean of n one-sample luminances deviates from the history's by ~sqrt(V / n)
        // without any change of the lighting.
        out.level[0].color[1].at(sx, sy) = sh / float(n);
        out.level[0].var.at(sx, sy) = sv / float(n) / float(n);
        ++valid;
      }
    }
    found += valid;
  });
  return found;
}

void filterGradient(GradientImage& g, int iterations, const svgf::VarianceParams& v, bool propagateVariance) {
  int cur = 0;
  for (int i = 0; i < iterations; ++i) {
    AtrousLevel lv;
    lv.kernel = AtrousKernel::Binomial3x3;
    lv.step = 1 << i;
    lv.sigmaDepth = v.sigmaDepth;
    lv.depthEpsilon = v.depthEpsilon;
    lv.depthEpsilonRelative = v.depthEpsilonRelative;
    lv.normalExponent = v.normalExponent;
    lv.sigmaScale = &g.noLuminanceWeight;
    lv.prefilterVariance = false;
    lv.propagateVariance = propagateVariance;
    lv.validIn = &g.valid[cur];
    lv.validOut = &g.valid[cur ^ 1];
    atrousLevel(g.guide, lv, g.level[cur], g.level[cur ^ 1]);
    cur ^= 1;
  }
  g.last = cur;
  g.level[cur].color[0].copyTo(g.result);
}

void historyAntilagGradient(GradientImage& g, float noiseSigmas, float scale) {
  const AtrousImage& l = g.level[g.last];
  parallelRows(g.height, [&](int y) {
    for (int x = 0; x < g.width; ++x)
      g.result(x, y) = antilagGradient(l.color[0].at(x, y), l.color[1].at(x, y), l.var.at(x, y), noiseSigmas, scale);
  });
}

void guideNormals(const std::vector<Plane>& normal, const std::vector<Plane>* reflected, std::vector<Plane>& out) {
  const int w = normal[0].width;
  parallelRows(normal[0].height, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const std::vector<Plane>& src =
          reflected && ((*reflected)[0](x, y) != 0.0f || (*reflected)[1](x, y) != 0.0f || (*reflected)[2](x, y) != 0.0f)
              ? *reflected
              : normal;
      for (int c = 0; c < 3; ++c) out[c](x, y) = src[c](x, y);
    }
  });
}

}  // namespace rtd::asvgf
