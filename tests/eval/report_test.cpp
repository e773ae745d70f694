// The comparison report: every run and every metric appear; it renders in headless Chromium.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <unistd.h>
#include <fstream>
#include <nlohmann/json.hpp>

#include "rtd/eval/compare.h"
#include "rtd/rtd.h"
#include "synthetic/synthetic.h"

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

using namespace rtd;
using namespace rtd::eval;
namespace fs = std::filesystem;

namespace {
Comparison smallComparison() {
  synthetic::Scene scene;
  scene.width = 64;
  scene.height = 40;
  FrameSource src;
  src.description = "synthetic 64x40";
  src.frameCount = 5;
  src.load = [scene](int i, Image& ref) { return synthetic::makeFrame(scene, i, &ref); };
  CompareSettings cs;  // every CPU method
  cs.eval.warmupFrames = 2;
  return runComparison(src, cs);
}
}  // namespace

/// Occurrences of `needle` in `hay`.
size_t count(const std::string& hay, const std::string& needle) {
  size_t n = 0;
  for (size_t at = hay.find(needle); at != std::string::npos; at = hay.find(needle, at + needle.size())) ++n;
  return n;
}

TEST(Report, ContainsEveryMethodAndMetric) {
  const Comparison c = smallComparison();
  std::vector<std::string> expected = {"input"};
  for (const auto& m : listMethods())
    if (m.cpu) expected.push_back(m.name);
  ASSERT_EQ(c.runs.size(), expected.size());
  const std::string html = comparisonHtml(c);
  const auto json = nlohmann::json::parse(comparisonJson(c));
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(c.runs[i].label, expected[i]);
    EXPECT_NE(html.find("<td class='l'>" + expected[i] + "</td>"), std::string::npos) << expected[i];
    EXPECT_NE(html.find("alt='FLIP " + expected[i] + "'"), std::string::npos) << expected[i];  // its error map
    EXPECT_NE(html.find("{label:\"" + expected[i] + "\",img:["), std::string::npos) << expected[i];  // its frames
    EXPECT_EQ(json["runs"][i]["label"], expected[i]);
    EXPECT_EQ(json["runs"][i]["frames"].size(), 5u);
  }
  for (const auto& m : metricList()) {
    // A column header (ranked ones with their direction) and a per-frame plot per metric.
    const std::string arrow = !m.ranked ? "" : m.higherIsBetter ? " &uarr;" : " &darr;";
    EXPECT_NE(html.find(std::string(">").append(m.label).append(arrow).append("</th>")), std::string::npos) << m.key;
    EXPECT_NE(html.find(std::string("aria-label='").append(m.label).append(" per frame'")), std::string::npos) << m.key;
    EXPECT_TRUE(json["runs"][0]["steady"].contains(m.key)) << m.key;
  }
  // Self-contained: no external resources.
  EXPECT_EQ(html.find("http://"), html.find("http://www.w3.org/2000/svg"));
  EXPECT_EQ(html.find("https://"), std::string::npos);
  // The methods improve on the noisy input after warm-up.
  for (size_t i = 1; i < c.runs.size(); ++i)
    EXPECT_LT(c.runs[i].metrics.steady.mean.relMse, c.runs[0].metrics.steady.mean.relMse) << c.runs[i].label;
}

TEST(Report, OneImagePerFramePerConfiguration) {
  const Comparison c = smallComparison();
  const std::string html = comparisonHtml(c);
  // Every frame of every run and of the reference, plus a FLIP map per frame per run, each a
  // data URI of the encoding the build has (WebP or PNG).
  ASSERT_EQ(c.frameNumbers.size(), 5u);
  ASSERT_EQ(c.referenceImages.size(), 5u);
  for (const auto& r : c.runs) {
    EXPECT_EQ(r.frameImages.size(), 5u) << r.label;
    EXPECT_EQ(r.flipImages.size(), 5u) << r.label;
  }
  EXPECT_EQ(count(html, "\"data:" + c.imageMime + ";base64,"), 5 * (2 * c.runs.size() + 1));
  std::string frames = "frames:[";
  for (size_t i = 0; i < c.frameNumbers.size(); ++i) frames.append(i ? "," : "").append(std::to_string(c.frameNumbers[i]));
  EXPECT_NE(html.find(frames + "]"), std::string::npos);
}

TEST(Report, StoresFramesAtTheDisplayWidth) {
  synthetic::Scene scene;
  scene.width = 100;
  scene.height = 30;
  FrameSource src;
  src.frameCount = 2;
  src.load = [scene](int i, Image& ref) { return synthetic::makeFrame(scene, i, &ref); };
  CompareSettings cs;
  cs.configs = {parseRunConfig("accumulate")};
  cs.eval.warmupFrames = 0;
  cs.reportMaxWidth = 40;  // an integer factor of 3: 34 x 10
  const Comparison c = runComparison(src, cs);
  EXPECT_EQ(c.displayWidth, 34);
  EXPECT_EQ(c.displayHeight, 10);
  ASSERT_EQ(c.runs.size(), 2u);
  ASSERT_EQ(c.runs[1].frameImages.size(), 2u);
  EXPECT_NE(comparisonHtml(c).find("stored at 34&times;10"), std::string::npos);
}

// The reference's own noise from two halves A = R + n, B = R - n (so R is their mean): the
// variance of R is (A - B)^2 / 4 = n^2 per value, relMSE_ref = mean(n^2 / (R^2 + 0.01)).
TEST(Report, ReferenceNoiseFromTwoHalves) {
  synthetic::Scene scene;
  scene.width = 16;
  scene.height = 8;
  FrameSource src;
  src.frameCount = 3;
  src.referenceSpp = 64;
  src.load = [scene](int i, Image& ref) {
    Frame f = synthetic::makeFrame(scene, i, &ref);
    for (float& v : ref.pixels) v = 0.5f;  // a constant reference: R^2 + eps = 0.26
    return f;
  };
  src.referenceHalves = [](int, Image& a, Image& b) {
    a = Image(16, 8, 3, 0.5f + 0.1f);
    b = Image(16, 8, 3, 0.5f - 0.1f);
  };
  CompareSettings cs;
  cs.configs = {parseRunConfig("accumulate")};
  cs.eval.warmupFrames = 1;
  cs.eval.computeFlip = false;
  const Comparison c = runComparison(src, cs);
  EXPECT_EQ(c.referenceQuality.spp, 64);
  ASSERT_TRUE(c.referenceQuality.estimated);
  EXPECT_NEAR(c.referenceQuality.relMse, 0.01 / 0.26, 1e-5);
  EXPECT_TRUE(std::isfinite(c.referenceQuality.psnr));
  const std::string html = comparisonHtml(c);
  EXPECT_NE(html.find("64 samples per pixel"), std::string::npos);
  EXPECT_NE(html.find("relMSE 0.0385"), std::string::npos);
  // Without halves, the report says the noise is unknown; an exact reference says so.
  src.referenceHalves = nullptr;
  EXPECT_NE(comparisonHtml(runComparison(src, cs)).find("remaining noise is not known"), std::string::npos);
  src.referenceExact = true;
  EXPECT_NE(comparisonHtml(runComparison(src, cs)).find("Exact"), std::string::npos);
}

TEST(Report, PngRoundTrips) {
  Image img(7, 5, 3);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 7; ++x) img.at(x, y, 0) = float(x) / 6.0f, img.at(x, y, 1) = float(y) / 4.0f;
  const std::string png = encodePng(img);
  int w = 0, h = 0, n = 0;
  unsigned char* px = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(png.data()), int(png.size()), &w, &h, &n, 3);
  ASSERT_NE(px, nullptr);
  EXPECT_EQ(w, 7);
  EXPECT_EQ(h, 5);
  EXPECT_EQ(px[(4 * 7 + 6) * 3 + 0], 255);
  EXPECT_EQ(px[(4 * 7 + 6) * 3 + 1], 255);
  EXPECT_EQ(px[(2 * 7 + 3) * 3 + 0], 128);
  stbi_image_free(px);
}

TEST(Report, RendersInHeadlessChromium) {
  const char* chromium = "/usr/bin/chromium";
  if (!fs::exists(chromium))
    GTEST_SKIP() << "headless Chromium check skipped: /usr/bin/chromium not installed (apt-get install chromium; "
                    "or run tools/check_report.sh)";
  const fs::path dir = fs::temp_directory_path() / ("rtd_report_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "profile");
  const fs::path html = dir / "report.html", shot = dir / "shot.png";
  writeHtmlReport(smallComparison(), html);
  const std::string cmd = std::string("timeout 120 ") + chromium +
                          " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
                          " --disable-background-networking --disable-component-update --disable-sync"
                          " --user-data-dir=" + (dir / "profile").string() + " --screenshot=" + shot.string() +
                          " --window-size=1400,1000 file://" + html.string() + " > " + (dir / "log.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << "chromium failed; see " << (dir / "log.txt");
  int w = 0, h = 0, n = 0;
  unsigned char* px = stbi_load(shot.string().c_str(), &w, &h, &n, 3);
  ASSERT_NE(px, nullptr) << "no screenshot at " << shot;
  EXPECT_EQ(w, 1400);
  EXPECT_EQ(h, 1000);
  // Rendered content: white page with dark text, table borders and images, i.e. many distinct
  // colours and a good share of non-white pixels.
  size_t nonWhite = 0;
  std::vector<bool> seen(1 << 15);
  size_t distinct = 0;
  for (int i = 0; i < w * h; ++i) {
    const unsigned char* p = px + 3 * i;
    if (p[0] < 235 || p[1] < 235 || p[2] < 235) ++nonWhite;
    const int key = (p[0] >> 3) << 10 | (p[1] >> 3) << 5 | (p[2] >> 3);
    if (!seen[key]) seen[key] = true, ++distinct;
  }
  stbi_image_free(px);
  EXPECT_GT(nonWhite, size_t(w) * h / 50);
  EXPECT_GT(distinct, 100u);

  // The page fits 1400 px: no horizontal scroll of the page, nor of any table's own box. A
  // probe appended to a copy of the report writes the widths into the title, which
  // --dump-dom prints after the scripts have run.
  const fs::path probe = dir / "probe.html";
  {
    std::ifstream in(html, std::ios::binary);
    std::ofstream out(probe, std::ios::binary);
    out << in.rdbuf()
        << "<script>window.addEventListener('load',function(){var over=0;"
           "document.querySelectorAll('.wrap,table,.cmp,.rows,.plots,svg').forEach(function(e){"
           "if(e.getClientRects().length)over=Math.max(over,e.getBoundingClientRect().right-"
           "document.documentElement.clientWidth,e.scrollWidth-e.clientWidth);});"
           "document.title='probe page='+document.documentElement.scrollWidth+' over='+Math.ceil(over)+';';});</script>";
  }
  const std::string dump = std::string("timeout 120 ") + chromium +
                           " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
                           " --disable-background-networking --disable-component-update --disable-sync"
                           " --user-data-dir=" + (dir / "profile").string() + " --virtual-time-budget=3000"
                           " --window-size=1400,1000 --dump-dom file://" + probe.string() + " > " +
                           (dir / "dom.html").string() + " 2>> " + (dir / "log.txt").string();
  ASSERT_EQ(std::system(dump.c_str()), 0) << "chromium --dump-dom failed; see " << (dir / "log.txt");
  std::ifstream domFile(dir / "dom.html");
  const std::string dom((std::istreambuf_iterator<char>(domFile)), std::istreambuf_iterator<char>());
  const size_t at = dom.find("probe page=");
  ASSERT_NE(at, std::string::npos) << "the probe did not run; see " << (dir / "dom.html");
  int pageWidth = 0, over = 0;
  ASSERT_EQ(std::sscanf(dom.c_str() + at, "probe page=%d over=%d;", &pageWidth, &over), 2);
  EXPECT_LE(pageWidth, 1400);
  EXPECT_LE(over, 0) << "an element sticks out of the page or scrolls sideways";
  fs::remove_all(dir);
}
