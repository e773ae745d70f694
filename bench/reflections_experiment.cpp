// rtd_reflections_experiment: Voorhuis 2018's quality experiments on the renderer's scenes, run
// in process (render, denoise, score) so that nothing is written to disk:
//   quality        Fig. 8: Base vs NoSpecReproj vs Ours on a moving camera; RMSE (tone-mapped,
//                  no gamma) and SSIM (tone-mapped sRGB) of the last frames against references,
//                  over the whole image and over the reflective pixels (roughness < 0.4);
//   stability      Fig. 9: the same three on 60 frames of a still camera; temporal error
//                  mean_p |L_t - L_{t-1}| of tone-mapped luminance, whole image and reflective;
//   supersampling  Fig. 11: Ours at 1 spp with TAA, 1 spp without, and N spp with guide rays
//                  (Sec. 5) without TAA, against a jittered (anti-aliased) reference;
//   ablation       Fig. 8's scores for Ours with one part switched off at a time (and Base, the
//                  Sec. 6 robustness set alone): which part costs or gains on a scene;
//   motion         Figs. 12-13: the reflection motion vectors of a rendered sequence (--input)
//                  against the 200x200 brute-force search, with and without LDSP scaling, the
//                  reference on the far ray's half-line and on its line.
// Prints one JSON object per configuration and line; scripts/reflections-experiments.py makes
// the tables of docs/methods/reflections.md from them. Not a test: no thresholds here.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <memory>
#include <string>
#include <vector>

#include "rtd/eval/metrics.h"
#include "rtd/eval/reflections.h"
#include "rtd/guide_rays.h"
#include "rtd/render/render.h"
#include "rtd/rtd.h"

namespace {

using namespace rtd;

struct Options {
  std::string experiment = "quality", scene = "mirrorfloor", input;
  /// --config "label|variant|k=v,k=v" (repeatable): these configurations instead of the
  /// experiment's own (the settings after the variant preset; taa=false among them to switch it off).
  std::vector<std::string> configs;
  std::string dump;  ///< --dump DIR: the scored frames as .npy (outputs, reference, mask, SSIM maps)
  int width = 160, height = 90, frames = 24, evalFrames = 4, spp = 4, referenceSpp = 256, stillFrame = 24;
};

struct Config {
  std::string name;
  std::unique_ptr<Denoiser> d;
  bool supersample = false;
  double rmse = 0, ssim = 0, maskedRmse = 0, maskedSsim = 0, temporal = 0, maskedTemporal = 0;
  int scored = 0, temporalFrames = 0;
  Image previousLuma;
};

double maskedRmse(const Image& a, const Image& b, const Image& mask) {
  double sum = 0;
  size_t n = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      if (mask.at(x, y) <= 0.5f) continue;
      for (int c = 0; c < 3; ++c) sum += double(a.at(x, y, c) - b.at(x, y, c)) * (a.at(x, y, c) - b.at(x, y, c));
      n += 3;
    }
  return n ? std::sqrt(sum / double(n)) : NAN;
}

// mean_p |a - b| over all pixels, and over the masked ones.
std::pair<double, double> meanAbsDiff(const Image& a, const Image& b, const Image& mask) {
  double all = 0, masked = 0;
  size_t n = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    const double d = std::abs(double(a.pixels[i]) - b.pixels[i]);
    all += d;
    if (mask.pixels[i] > 0.5f) masked += d, ++n;
  }
  return {all / double(a.pixels.size()), n ? masked / double(n) : NAN};
}

// A float32 .npy file of an image (height x width x channels), for scripts that look at where
// a configuration loses (numpy.load).
void writeNpy(const std::string& path, const Image& im) {
  char header[128];
  int n = std::snprintf(header, sizeof header, "{'descr': '<f4', 'fortran_order': False, 'shape': (%d, %d, %d), }",
                        im.height, im.width, im.channels);
  std::string h(header, size_t(n));
  while ((10 + h.size() + 1) % 64) h += ' ';
  h += '\n';
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error("cannot write " + path);
  const uint16_t len = uint16_t(h.size());
  std::fwrite("\x93NUMPY\x01\x00", 1, 8, f);
  std::fwrite(&len, 2, 1, f);
  std::fwrite(h.data(), 1, h.size(), f);
  std::fwrite(im.pixels.data(), sizeof(float), im.pixels.size(), f);
  std::fclose(f);
}

std::string fileName(std::string s) {
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return s;
}

void print(const Options& o, const Config& c, int spp) {
  std::printf("{\"experiment\": \"%s\", \"scene\": \"%s\", \"config\": \"%s\", \"width\": %d, \"height\": %d, "
              "\"frames\": %d, \"spp\": %d, \"referenceSpp\": %d, \"scoredFrames\": %d",
              o.experiment.c_str(), o.scene.c_str(), c.name.c_str(), o.width, o.height, o.frames, spp, o.referenceSpp,
              o.experiment == "stability" ? c.temporalFrames : c.scored);
  if (o.experiment == "stability")
    std::printf(", \"temporalError\": %.6f, \"temporalErrorReflective\": %.6f}\n", c.temporal, c.maskedTemporal);
  else
    std::printf(", \"rmse\": %.5f, \"ssim\": %.4f, \"rmseReflective\": %.5f, \"ssimReflective\": %.4f}\n", c.rmse,
                c.ssim, c.maskedRmse, c.maskedSsim);
}

int motion(const Options& o) {
  const auto seq = SequenceReader::open(o.input);
  for (bool scaling : {true, false})
    for (bool onRay : {true, false}) {
      eval::ReflectionMotionSettings s;
      s.ldspScaling = scaling;
      s.referenceOnRay = onRay;
      const auto frames = eval::reflectionMotionError(*seq, s);
      double err = 0, within = 0, taps = 0, worst = 0, best = INFINITY;
      int n = 0;
      for (const auto& f : frames) {
        if (!f.pixels || !(f.meanError >= 0)) continue;
        err += f.meanError;
        within += f.withinOnePixel;
        taps += f.meanTaps;
        worst = std::max(worst, f.meanError);
        best = std::min(best, f.meanError);
        ++n;
      }
      std::printf("{\"experiment\": \"motion\", \"input\": \"%s\", \"ldspScaling\": %s, \"reference\": \"%s\", \"frames\": %d, "
                  "\"meanError\": %.4f, \"minFrameError\": %.4f, \"maxFrameError\": %.4f, \"withinOnePixel\": %.4f, "
                  "\"meanTaps\": %.2f}\n",
                  o.input.c_str(), scaling ? "true" : "false", onRay ? "ray" : "line", n, err / n, best, worst, within / n, taps / n);
    }
  return 0;
}

int run(const Options& o) {
  if (o.experiment == "motion") return motion(o);
  auto scene = render::Scene::load(o.scene);
  render::RenderSettings rs = scene->suggestedSettings();
  rs.width = o.width;
  rs.height = o.height;
  rs.gradientSamples = false;
  const bool supersampling = o.experiment == "supersampling";
  if (supersampling) {
    rs.spp = o.spp;
    rs.guideRays = true;
  }
  render::RenderSettings refSettings = rs;
  refSettings.spp = 1;
  refSettings.guideRays = false;
  refSettings.pixelJitter = supersampling;  // Fig. 11 compares against anti-aliased images
  render::Renderer refRenderer(scene, refSettings);
  const render::ReferenceCache cache{render::ReferenceCache::defaultDir()};

  auto device = Device::create();
  std::vector<Config> configs;
  auto add = [&](const std::string& name, const char* variant, bool taa, bool ss,
                 const std::vector<std::pair<const char*, const char*>>& set = {}) {
    Config c;
    c.name = name;
    c.d = device->createDenoiser("svgf");
    c.d->set("variant", variant);
    c.d->set("taa", taa ? "true" : "false");
    for (const auto& kv : set) c.d->set(kv.first, kv.second);
    c.supersample = ss;
    configs.push_back(std::move(c));
  };
  if (!o.configs.empty()) {
    for (const std::string& spec : o.configs) {
      const size_t a = spec.find('|'), b = a == std::string::npos ? a : spec.find('|', a + 1);
      if (a == std::string::npos) throw Error("--config '" + spec + "': label|variant[|k=v,...]");
      Config c;
      c.name = spec.substr(0, a);
      c.d = device->createDenoiser("svgf");
      c.d->set("variant", spec.substr(a + 1, b == std::string::npos ? std::string::npos : b - a - 1));
      std::string rest = b == std::string::npos ? std::string() : spec.substr(b + 1);
      while (!rest.empty()) {
        const size_t comma = rest.find(',');
        const std::string kv = rest.substr(0, comma);
        const size_t eq = kv.find('=');
        if (eq == std::string::npos) throw Error("--config '" + spec + "': setting '" + kv + "' is not k=v");
        c.d->set(kv.substr(0, eq), kv.substr(eq + 1));
        rest = comma == std::string::npos ? std::string() : rest.substr(comma + 1);
      }
      c.supersample = false;
      configs.push_back(std::move(c));
    }
  } else if (o.experiment == "ablation") {
    add("Base", "voorhuisBase", true, false);
    add("Robustness (Sec. 6) only", "voorhuisRobustness", true, false);
    add("Ours", "voorhuis", true, false);
    add("Ours, no lobe split", "voorhuis", true, false, {{"preferLobes", "false"}});
    add("Ours, primary motion", "voorhuis", true, false, {{"specularMotion", "primary"}});
    add("Ours, no reflected features", "voorhuis", true, false, {{"reflectedFeatures", "off"}});
    add("Ours, no Eq. 6", "voorhuis", true, false, {{"glossyBandwidth", "off"}});
    add("Ours, Eq. 6 in world units (the paper's omega)", "voorhuis", true, false, {{"bandwidthPerLobe", "false"}});
    add("Ours, no clipping", "voorhuis", true, false, {{"neighbourhoodClipping", "off"}});
    add("Ours, clipping over the whole window", "voorhuis", true, false, {{"clipOwnSurface", "false"}});
    add("Ours, no per-class blend", "voorhuis", true, false, {{"materialAlpha", "off"}});
    add("Ours, TAA on glossy reflection motion", "voorhuis", true, false, {{"taaGlossyReflectionMotion", "true"}});
    add("Ours, no TAA", "voorhuis", false, false);
    add("Ours, plain TAA box", "voorhuis", true, false, {{"taaOwnSurface", "false"}, {"taaHistoryRejection", "false"}});
    add("Base, no TAA", "voorhuisBase", false, false);
    add("Base, plain TAA box", "voorhuisBase", true, false, {{"taaOwnSurface", "false"}, {"taaHistoryRejection", "false"}});
    add("NoSpecReproj", "voorhuisNoSpecReproj", true, false);
    add("Ours, primary motion, no TAA", "voorhuis", false, false, {{"specularMotion", "primary"}});
  } else if (supersampling) {
    add("1 spp + TAA", "voorhuis", true, false);
    add("1 spp, no TAA", "voorhuis", false, false);
    add(std::to_string(o.spp) + " spp guide rays, no TAA", "voorhuis", false, true);
  } else {
    add("Base", "voorhuisBase", true, false);
    add("NoSpecReproj", "voorhuisNoSpecReproj", true, false);
    add("Ours", "voorhuis", true, false);
    if (o.experiment == "quality" || o.experiment == "stability") {
      // TAA as before 2026-12-03: the plain 3x3 box, no history rejection (the defaults now
      // take the own-surface box and reject disoccluded history; docs/methods/taa.md).
      add("Base, plain TAA box", "voorhuisBase", true, false, {{"taaOwnSurface", "false"}, {"taaHistoryRejection", "false"}});
      add("NoSpecReproj, plain TAA box", "voorhuisNoSpecReproj", true, false, {{"taaOwnSurface", "false"}, {"taaHistoryRejection", "false"}});
      add("Ours, plain TAA box", "voorhuis", true, false, {{"taaOwnSurface", "false"}, {"taaHistoryRejection", "false"}});
    }
  }

  const bool still = o.experiment == "stability";
  const eval::ToneMapSettings tm;
  Image out(o.width, o.height, 3);
  std::unique_ptr<render::Renderer> renderer;
  for (int f = 0; f < o.frames; ++f) {
    GuideRaySamples samples;
    Frame frame;
    if (still) {
      // A still camera: the same view with fresh noise each frame (a new seed), no motion.
      render::RenderSettings s = rs;
      s.seed = rs.seed + uint32_t(f);
      render::Renderer r(scene, s);
      frame = r.render(o.stillFrame);
      frame[Buffer::Motion] = Image(o.width, o.height, 2);
    } else {
      if (!renderer) renderer = std::make_unique<render::Renderer>(scene, rs);
      frame = supersampling ? renderer->render(f, render::Eye::Center, samples) : renderer->render(f);
    }
    const Image mask = eval::reflectiveMask(frame, 0.4f);
    const bool scored = !still && f >= o.frames - o.evalFrames;
    Image ref;
    if (scored) ref = eval::toneMap(cache.fetchOrRender(refRenderer, *scene, f, o.referenceSpp, 0, render::Eye::Center), tm);
    const std::string dumpAt = o.dump.empty() ? std::string() : o.dump + "/" + fileName(o.scene) + "_f" + std::to_string(f);
    if (scored && !dumpAt.empty()) {
      writeNpy(dumpAt + "_reference.npy", ref);
      writeNpy(dumpAt + "_mask.npy", mask);
      writeNpy(dumpAt + "_input.npy", eval::toneMap(frame[Buffer::Color], tm));
      if (frame.has(Buffer::Roughness)) {
        const Image& r = frame[Buffer::Roughness];
        writeNpy(dumpAt + "_roughness.npy", r);
      }
    }
    for (Config& c : configs) {
      Image result;
      if (c.supersample) {
        result = GuideRays().denoise(*c.d, frame, samples);
      } else {
        c.d->denoise(frame.inputs(), out.view());
        result = out;
      }
      const Image shown = eval::toneMap(result, tm);
      if (still) {
        const Image luma = eval::luminance(shown);
        // The second half of the 60 frames: the history has converged (Fig. 9's plateau).
        if (!c.previousLuma.empty() && f >= o.frames / 2) {
          const auto [all, refl] = meanAbsDiff(luma, c.previousLuma, mask);
          c.temporal += all;
          c.maskedTemporal += refl;
          ++c.temporalFrames;
        }
        c.previousLuma = luma;
      }
      if (!scored) continue;
      if (!dumpAt.empty()) {
        Image map;
        eval::ssim(shown, ref, 1.0, &map);
        writeNpy(dumpAt + "_" + fileName(c.name) + ".npy", shown);
        writeNpy(dumpAt + "_" + fileName(c.name) + "_ssim.npy", map);
      }
      c.rmse += eval::rmse(shown, ref);
      c.ssim += eval::ssim(shown, ref);
      c.maskedRmse += maskedRmse(shown, ref, mask);
      c.maskedSsim += eval::maskedSsim(shown, ref, mask);
      ++c.scored;
    }
    std::fprintf(stderr, "%s %s: frame %d/%d\r", o.experiment.c_str(), o.scene.c_str(), f + 1, o.frames);
  }
  std::fprintf(stderr, "\n");
  for (Config& c : configs) {
    if (c.scored) c.rmse /= c.scored, c.ssim /= c.scored, c.maskedRmse /= c.scored, c.maskedSsim /= c.scored;
    if (c.temporalFrames) c.temporal /= c.temporalFrames, c.maskedTemporal /= c.temporalFrames;
    print(o, c, c.supersample ? o.spp : 1);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; i += 2) {
    const std::string a = argv[i];
    if (i + 1 >= argc) {
      std::fprintf(stderr, "rtd_reflections_experiment: %s needs a value\n", a.c_str());
      return 2;
    }
    const std::string v = argv[i + 1];
    const int n = std::atoi(v.c_str());
    if (a == "--experiment") o.experiment = v;
    else if (a == "--scene") o.scene = v;
    else if (a == "--input") o.input = v;
    else if (a == "--width") o.width = n;
    else if (a == "--height") o.height = n;
    else if (a == "--frames") o.frames = n;
    else if (a == "--eval-frames") o.evalFrames = n;
    else if (a == "--spp") o.spp = n;
    else if (a == "--reference-spp") o.referenceSpp = n;
    else if (a == "--still-frame") o.stillFrame = n;
    else if (a == "--dump") o.dump = v;
    else if (a == "--config") o.configs.push_back(v);
    else {
      std::fprintf(stderr,
                   "usage: rtd_reflections_experiment --experiment quality|stability|supersampling|ablation|motion [--scene S] [--input DIR] "
                   "[--width W] [--height H] [--frames N] [--eval-frames N] [--spp N] [--reference-spp N] "
                   "[--still-frame N] [--dump DIR] [--config 'label|variant|k=v,...']...\n");
      return 2;
    }
  }
  if (o.experiment != "quality" && o.experiment != "stability" && o.experiment != "supersampling" &&
      o.experiment != "motion" && o.experiment != "ablation") {
    std::fprintf(stderr, "rtd_reflections_experiment: unknown experiment '%s'\n", o.experiment.c_str());
    return 2;
  }
  try {
    return run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rtd_reflections_experiment: %s\n", e.what());
    return 1;
  }
}
