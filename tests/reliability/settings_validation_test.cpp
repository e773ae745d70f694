// Issue 21: typed settings are validated exactly like settings given by name. For every method's
// settings struct, every numeric and enum field is set, one at a time, to each value its visit()
// declaration refuses (NaN, +-Inf, just outside its Range, an enum value past its choices); the
// typed setSettings() and createDenoiser(S{}) must throw rtd::Error naming the field, on both
// backends, leaving settings and history untouched. The cases of the issue (atrousIterations =
// 100 crashed the CPU SVGF, alpha = -0.5 or NaN wrote non-finite outputs, blockSize = 17 and
// maxHistoryLength = 0 were accepted) are checked by name as well.
#include <gtest/gtest.h>

#include <climits>
#include <cmath>
#include <cstdio>
#include <limits>

#include "rtd/rtd.h"
#include "support/backends.h"
#include "synthetic/synthetic.h"

namespace rtd::test {
namespace {

// Sets field number `target` (in visit() order) of a settings struct to its `variant`-th
// refused value; `applied` says whether that value exists.
struct BadValue {
  int target, variant;
  int index = 0;
  bool applied = false;
  std::string name, text;  // the field, and the value as text where it is finite

  bool mine(const char* n) {
    if (index++ != target) return false;
    name = n;
    return true;
  }
  void operator()(const char* n, float& v, const char*, Range r = {-INFINITY, INFINITY}) {
    if (!mine(n)) return;
    std::vector<float> bad = {std::numeric_limits<float>::quiet_NaN(), INFINITY, -INFINITY};
    if (std::isfinite(r.lo)) {
      float b = float(r.lo);
      while (double(b) >= r.lo) b = std::nextafter(b, -INFINITY);
      bad.push_back(b);
    }
    if (std::isfinite(r.hi)) {
      float b = float(r.hi);
      while (double(b) <= r.hi) b = std::nextafter(b, INFINITY);
      bad.push_back(b);
    }
    if (variant >= int(bad.size())) return;
    v = bad[size_t(variant)];
    applied = true;
    if (std::isfinite(v)) {
      char s[32];
      std::snprintf(s, sizeof s, "%.9g", double(v));
      text = s;
    }
  }
  void operator()(const char* n, int& v, const char*, Range r = {double(INT_MIN), double(INT_MAX)}) {
    if (!mine(n)) return;
    std::vector<int> bad;
    if (r.lo > INT_MIN) bad.push_back(int(r.lo) - 1);
    if (r.hi < INT_MAX) bad.push_back(int(r.hi) + 1);
    if (variant >= int(bad.size())) return;
    v = bad[size_t(variant)];
    applied = true;
    text = std::to_string(v);
  }
  void operator()(const char* n, bool&, const char*) { mine(n); }
  void operator()(const char* n, std::string&, const char*) { mine(n); }  // text: any value
  template <class E, class = std::enable_if_t<std::is_enum_v<E>>>
  void operator()(const char* n, E& v, const char*, Choices choices) {
    if (!mine(n)) return;
    const int bad[] = {int(choices.size()), -1, 17};
    if (variant >= 3) return;
    v = E(bad[variant]);
    applied = true;
  }
};

// Every refused value of every field of S, with the field's name and text.
template <class S> std::vector<std::pair<S, BadValue>> badSettings() {
  std::vector<std::pair<S, BadValue>> out;
  for (int field = 0;; ++field) {
    bool fieldExists = false;
    for (int variant = 0;; ++variant) {
      S s;
      BadValue b{field, variant};
      s.visit(b);
      fieldExists = b.index > field;
      if (!b.applied) break;
      out.emplace_back(s, b);
    }
    if (!fieldExists) break;
  }
  return out;
}

std::string listing(const Denoiser& d) {
  std::string s;
  for (const auto& i : d.settings()) s += i.name + "=" + i.value + ";";
  return s;
}

template <class S> class TypedSettingsValidation : public ::testing::Test {};
using AllSettings = ::testing::Types<AccumulateSettings, SvgfSettings, BmfrSettings, TnndSettings, AsvgfSettings>;
TYPED_TEST_SUITE(TypedSettingsValidation, AllSettings);

TYPED_TEST(TypedSettingsValidation, EveryRefusedValueOfEveryFieldIsRejectedOnBothBackends) {
  using S = TypeParam;
  const auto cases = badSettings<S>();
  ASSERT_GT(cases.size(), 10u);
  for (Backend backend : testBackends()) {
    Device* device = testDevice(backend);
    if (!device) continue;
    auto d = device->createDenoiser(S::kMethod);
    const std::string before = listing(*d);
    for (const auto& [settings, bad] : cases) {
      const std::string what = std::string(backendName(backend)) + " " + S::kMethod + "." + bad.name;
      try {
        d->setSettings(settings);
        ADD_FAILURE() << what << ": a refused value was accepted";
      } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("'" + bad.name + "'"), std::string::npos) << what << ": " << message;
        // The same value by name gives the same message: one validation path.
        if (!bad.text.empty()) {
          try {
            d->set(bad.name, bad.text);
            ADD_FAILURE() << what << " = " << bad.text << " accepted by name";
          } catch (const Error& byName) {
            EXPECT_EQ(std::string(byName.what()), message) << what;
          }
        }
      }
      EXPECT_EQ(listing(*d), before) << what << ": a refused value changed the settings";
      EXPECT_THROW(device->createDenoiser(settings), Error) << what;
    }
  }
}

TYPED_TEST(TypedSettingsValidation, DefaultsAreAccepted) {
  for (Backend backend : testBackends()) {
    Device* device = testDevice(backend);
    if (!device) continue;
    EXPECT_NO_THROW(device->createDenoiser(TypeParam{})) << backendName(backend);
  }
}

// The cases, by name.
TEST(TypedSettingsValidation, TheReportedCasesAreRefused) {
  for (Backend backend : testBackends()) {
    Device* device = testDevice(backend);
    if (!device) continue;
    auto expectRefused = [&](auto settings, const char* field) {
      try {
        device->createDenoiser(settings);
        ADD_FAILURE() << backendName(backend) << ": " << field << " accepted";
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
      }
    };
    SvgfSettings svgf;
    svgf.atrousIterations = 100;
    expectRefused(svgf, "atrousIterations");
    svgf = {};
    svgf.maxHistoryLength = 0;
    expectRefused(svgf, "maxHistoryLength");
    AccumulateSettings acc;
    acc.alpha = -0.5f;
    expectRefused(acc, "alpha");
    acc.alpha = std::numeric_limits<float>::quiet_NaN();
    expectRefused(acc, "alpha");
    acc = {};
    acc.maxHistoryLength = 0;
    expectRefused(acc, "maxHistoryLength");
    BmfrSettings bmfr;
    bmfr.blockSize = BmfrBlockSize(17);
    expectRefused(bmfr, "blockSize");
    bmfr = {};
    bmfr.maxHistoryLength = 0;
    expectRefused(bmfr, "maxHistoryLength");
  }
}

// A refused setSettings() between frames leaves history alone: the next output is exactly that
// of a denoiser that never saw the attempt.
TEST(TypedSettingsValidation, ARefusedChangeLeavesHistoryUntouched) {
  synthetic::Scene scene;
  scene.width = 48;
  scene.height = 32;
  std::vector<Frame> frames;
  for (int i = 0; i < 4; ++i) frames.push_back(synthetic::makeFrame(scene, i));
  for (Backend backend : testBackends()) {
    Device* device = testDevice(backend);
    if (!device) continue;
    for (const char* method : {"accumulate", "svgf", "bmfr"}) {
      auto a = device->createDenoiser(method), b = device->createDenoiser(method);
      Image outA(scene.width, scene.height, 3), outB(scene.width, scene.height, 3);
      for (size_t i = 0; i < frames.size(); ++i) {
        if (i == 2) {
          if (std::string(method) == "accumulate") {
            AccumulateSettings s;
            s.alpha = -0.5f;
            EXPECT_THROW(a->setSettings(s), Error);
          } else if (std::string(method) == "svgf") {
            SvgfSettings s;
            s.atrousIterations = 100;
            EXPECT_THROW(a->setSettings(s), Error);
          } else {
            BmfrSettings s;
            s.blockSize = BmfrBlockSize(17);
            EXPECT_THROW(a->setSettings(s), Error);
          }
        }
        a->denoise(frames[i].inputs(), outA.view());
        b->denoise(frames[i].inputs(), outB.view());
        ASSERT_EQ(outA.pixels, outB.pixels) << backendName(backend) << " " << method << " frame " << i;
      }
    }
  }
}

}  // namespace
}  // namespace rtd::test
