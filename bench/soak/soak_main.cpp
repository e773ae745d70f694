// rtd_soak: the soak of bench/soak/soak.h at length (scripts/soak.sh). Exit status 0 when
// every method on every backend kept its outputs finite and stable and its memory flat.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "soak/soak.h"

int main(int argc, char** argv) {
  rtd::soak::Config c;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "rtd_soak: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--frames") c.frames = std::atoi(next().c_str());
    else if (a == "--method") c.methods.push_back(next());
    else if (a == "--backend") c.backends = {next() == "vulkan" ? rtd::Backend::Vulkan : rtd::Backend::Cpu};
    else if (a == "--rss-bound-mib") c.rssBoundMiB = std::atof(next().c_str());
    else {
      std::fprintf(stderr,
                   "usage: rtd_soak [--frames N] [--method M]... [--backend cpu|vulkan] [--rss-bound-mib B]\n");
      return 2;
    }
  }
  c.log = [](const std::string& line) { std::printf("%s\n", line.c_str()), std::fflush(stdout); };
  std::printf("soak: %d frames per method and backend: shots of %d frames (each a camera cut), sizes 64x48 and "
              "48x32 alternating every %d shots, bad pixels in frame %d of each shot, output mean checked from "
              "frame %d; RSS may grow at most %.0f MiB after %d frames\n",
              c.frames, c.shotLength, c.shotsPerSize, c.badAt, c.checkFrom, c.rssBoundMiB, c.warmupFrames);
  bool ok = true;
  for (const auto& r : rtd::soak::run(c)) ok = ok && r.ok(c.rssBoundMiB);
  std::printf("soak: %s\n", ok ? "passed" : "FAILED");
  return ok ? 0 : 1;
}
