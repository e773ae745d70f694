#include "rtd/eval/reflections.h"

#include <atomic>
#include <cmath>

#include "core/frame_data.h"
#include "core/parallel.h"
#include "passes/reflection_reprojection.h"
#include "rtd/eval/metrics.h"

namespace rtd::eval {

std::vector<ReflectionMotionFrame> reflectionMotionError(const SequenceReader& seq, const ReflectionMotionSettings& s,
                                                         const std::function<void(int, int)>& progress) {
  const auto have = seq.buffers();
  for (Buffer b : {Buffer::Normal, Buffer::Depth, Buffer::Roughness, Buffer::ReflectedPosition, Buffer::Position,
                   Buffer::MirrorDirection, Buffer::SecondaryDistance})
    if (std::find(have.begin(), have.end(), b) == have.end())
      throw Error("reflection motion: the sequence has no '" + std::string(bufferName(b)) + "' buffer (first frame: '" +
                  seq.framePath(0).string() + "'); render it with the reflection buffers (not --minimal)");
  const SurfaceClassThresholds t{s.pureSpecularRoughness, s.reflectionRoughness, s.diffuseRoughness};
  DiamondSearchOptions opt;
  opt.scaleLdsp = s.ldspScaling;
  opt.maxIterations = s.searchIterations;
  opt.subpixel = s.subpixel;
  opt.fit = s.subpixelFit == SvgfSubpixelFit::quadratic ? SubpixelFit::quadratic : SubpixelFit::inverseDistance;
  std::vector<ReflectionMotionFrame> out;
  FrameData prev, cur;
  PixelVector<uint8_t> prevCls, cls;
  ReflectionSearchFeatures prevFeatures;
  Reprojection primary;
  const int n = seq.frameCount();
  for (int i = 0; i < n; ++i) {
    importFrame(seq.read(i).inputs(), {Buffer::Color}, cur);
    classifySurfaces(cur, t, false, cls);
    if (i > 0) {
      reproject(cur, &prev, ReprojectionSettings{}, primary);
      prevFeatures.build(prev, prevCls);
      std::atomic<uint64_t> count{0}, missed{0}, within{0}, taps{0};
      std::vector<double> rowError(size_t(cur.height), 0.0);  // summed in row order: deterministic
      const int w = cur.width;
      parallelRows(cur.height, [&](int y) {
        uint64_t c = 0, m = 0, k = 0, tp = 0;
        double e = 0;
        for (int x = 0; x < w; ++x) {
          const SurfaceClass sc = SurfaceClass(cls[size_t(y) * w + x]);
          if (!((sc == SurfaceClass::Mirror && s.mirrors) || (sc == SurfaceClass::GlossyReflection && s.glossy))) continue;
          const SearchResult bf = searchReflection(cur, prevFeatures, cls, prevCls, primary, x, y, opt, s.bruteForceRadius,
                                                   s.referenceOnRay);
          if (!bf.found()) continue;
          const SearchResult ds = searchReflection(cur, prevFeatures, cls, prevCls, primary, x, y, opt);
          ++c;
          tp += uint64_t(ds.taps);
          if (!ds.found()) {
            ++m;
            continue;
          }
          const double err = std::hypot(ds.matchX - bf.matchX, ds.matchY - bf.matchY);
          e += err;
          k += err <= 1.0;
        }
        count += c;
        missed += m;
        within += k;
        taps += tp;
        rowError[size_t(y)] = e;
      }, 1);
      double sum = 0;
      for (double e : rowError) sum += e;
      ReflectionMotionFrame f;
      f.number = seq.frameNumber(i);
      f.pixels = count;
      f.missed = missed;
      f.meanError = count > missed ? sum / double(count - missed) : std::nan("");
      f.withinOnePixel = count ? double(within) / double(count) : std::nan("");
      f.meanTaps = count ? double(taps) / double(count) : std::nan("");
      out.push_back(f);
    }
    std::swap(prev, cur);
    std::swap(prevCls, cls);
    if (progress) progress(i + 1, n);
  }
  return out;
}

Image reflectiveMask(const Frame& f, float roughness) {
  if (!f.has(Buffer::Roughness)) throw Error("reflective mask: frame " + std::to_string(f.number) + " has no 'roughness' buffer");
  Image m(f.width, f.height, 1);
  const Image& r = f[Buffer::Roughness];
  for (size_t i = 0; i < m.pixels.size(); ++i) m.pixels[i] = r.pixels[i] < roughness ? 1.0f : 0.0f;
  return m;
}

namespace {
void checkMask(const Image& test, const Image& mask) {
  if (mask.width != test.width || mask.height != test.height)
    throw Error("reflective mask is " + std::to_string(mask.width) + "x" + std::to_string(mask.height) + " but the image is " +
                std::to_string(test.width) + "x" + std::to_string(test.height));
}
}  // namespace

double maskedPsnr(const Image& test, const Image& ref, const Image& mask) {
  checkMask(test, mask);
  double s = 0;
  uint64_t n = 0;
  for (size_t i = 0; i < mask.pixels.size(); ++i) {
    if (!(mask.pixels[i] > 0.5f)) continue;
    for (int c = 0; c < 3; ++c) {
      const double d = double(test.pixels[i * test.channels + c]) - ref.pixels[i * ref.channels + c];
      s += d * d;
    }
    n += 3;
  }
  if (!n) return std::nan("");
  return s > 0 ? 10.0 * std::log10(double(n) / s) : INFINITY;
}

double maskedSsim(const Image& test, const Image& ref, const Image& mask) {
  checkMask(test, mask);
  Image map;
  ssim(test, ref, 1.0, &map);
  double s = 0;
  uint64_t n = 0;
  for (size_t i = 0; i < mask.pixels.size(); ++i)
    if (mask.pixels[i] > 0.5f) {
      s += map.pixels[i];
      ++n;
    }
  return n ? s / double(n) : std::nan("");
}

}  // namespace rtd::eval
