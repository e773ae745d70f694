// The shared TAA pass alone on noise-free frames (docs/methods/taa.md): a rendered sequence's
// references, moved by the sequence's own motion vectors, through Taa::run with each history
// filter and domain. The input is exact, so every departure of the output from it is the TAA's
// own (resampling blur, lag, clamp): PSNR and SSIM of the ACES-tone-mapped sRGB output against
// the frame it was given, mean over the frames after the warm-up.
//
//   rtd_taa_experiment SEQUENCE [REFERENCE = SEQUENCE/reference] [--warmup 4]
//
// Prints one JSON line per configuration.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "core/frame_data.h"
#include "passes/reprojection.h"
#include "passes/taa.h"
#include "rtd/eval/metrics.h"
#include "rtd/rtd.h"
#include "rtd/sequence.h"

namespace {

rtd::Image toImage(const rtd::Plane3& p) {
  rtd::Image img(p[0].width, p[0].height, 3);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = p[c](x, y);
  return img;
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc < 2) {
    std::fprintf(stderr, "usage: rtd_taa_experiment SEQUENCE [REFERENCE] [--warmup N]\n");
    return 2;
  }
  std::string input = argv[1], reference = input + "/reference";
  int warmup = 4;
  std::string dump;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--warmup" && i + 1 < argc) warmup = std::atoi(argv[++i]);
    else if (a == "--dump" && i + 1 < argc) dump = argv[++i];
    else reference = a;
  }
  const auto seq = rtd::SequenceReader::open(input);
  const auto ref = rtd::SequenceReader::open(reference);
  struct Config {
    const char* name;
    rtd::TaaSettings s;
    rtd::Taa taa;
    double psnr = 0, ssim = 0;
    int n = 0;
  };
  std::vector<Config> configs;
  for (auto d : {rtd::TaaDomain::display, rtd::TaaDomain::linear})
    for (auto f : {rtd::TaaHistoryFilter::bilinear, rtd::TaaHistoryFilter::catmullRom}) {
      Config c;
      c.s.taaDomain = d;
      c.s.taaHistoryFilter = f;
      c.name = d == rtd::TaaDomain::display ? (f == rtd::TaaHistoryFilter::bilinear ? "display bilinear" : "display catmullRom")
                                            : (f == rtd::TaaHistoryFilter::bilinear ? "linear bilinear" : "linear catmullRom");
      configs.push_back(std::move(c));
    }
  rtd::FrameData prev, cur;
  const rtd::eval::ToneMapSettings tm;
  for (int i = 0; i < seq->frameCount(); ++i) {
    rtd::Frame f = seq->read(i);
    f[rtd::Buffer::Color] = ref->read(i)[rtd::Buffer::Color];
    f[rtd::Buffer::Emission] = rtd::Image();  // the reference as it is: no emission to separate
    rtd::importFrame(f.inputs(), {rtd::Buffer::Color, rtd::Buffer::Motion}, cur);
    rtd::Reprojection rp;
    rtd::reproject(cur, i ? &prev : nullptr, {}, rp);
    const rtd::Plane3 color{cur.plane(rtd::Buffer::Color, 0), cur.plane(rtd::Buffer::Color, 1), cur.plane(rtd::Buffer::Color, 2)};
    const rtd::Image truth = rtd::eval::toneMap(toImage(color), tm);
    for (Config& c : configs) {
      const rtd::Image out = rtd::eval::toneMap(toImage(c.taa.run(rp, color, c.s)), tm);
      if (!dump.empty() && i + 1 == seq->frameCount()) {  // the last frame, tone-mapped, raw float RGB
        for (const auto& [img, what] : {std::pair{&out, std::string(c.name)}, std::pair{&truth, std::string("truth")}}) {
          FILE* fp = std::fopen((dump + "/" + what + ".rgb").c_str(), "wb");
          std::fwrite(img->pixels.data(), sizeof(float), img->pixels.size(), fp);
          std::fclose(fp);
        }
      }
      if (i < warmup) continue;
      c.psnr += rtd::eval::psnr(out, truth);
      c.ssim += rtd::eval::ssim(out, truth);
      ++c.n;
    }
    std::swap(prev, cur);
  }
  for (const Config& c : configs)
    std::printf("{\"sequence\": \"%s\", \"config\": \"%s\", \"frames\": %d, \"psnr\": %.2f, \"ssim\": %.4f}\n", input.c_str(),
                c.name, c.n, c.psnr / c.n, c.ssim / c.n);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "rtd_taa_experiment: %s\n", e.what());
  return 1;
}
