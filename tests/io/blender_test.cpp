// The Blender Cycles fixture (tests/fixtures/blender, made by tools/blender/make_fixture.py)
// imports with the conventions of include/rtd/frame.h.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "passes/reprojection.h"
#include "support/test_frames.h"

namespace rtd {
namespace {

const std::filesystem::path kFixture = std::filesystem::path(RTD_SOURCE_DIR) / "tests/fixtures/blender";

TEST(BlenderImport, DetectsTheSequenceAndItsPasses) {
  auto seq = SequenceReader::open(kFixture);
  EXPECT_EQ(seq->kind(), SequenceKind::Blender);
  ASSERT_EQ(seq->frameCount(), 5);
  EXPECT_EQ(seq->frameNumber(0), 1);
  EXPECT_EQ(seq->frameNumber(4), 5);
  EXPECT_EQ(seq->width(), 64);
  EXPECT_EQ(seq->height(), 36);
  const auto buffers = seq->buffers();
  for (Buffer b : {Buffer::Color, Buffer::Albedo, Buffer::Normal, Buffer::Depth, Buffer::Position, Buffer::Motion,
                   Buffer::ObjectId})
    EXPECT_NE(std::find(buffers.begin(), buffers.end(), b), buffers.end()) << bufferName(b);
  const Frame f = seq->read(2);
  EXPECT_EQ(f.number, 3);
  EXPECT_TRUE(f.camera.valid);
  // Normals are unit length where a surface was hit (object id > 0).
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      if (f[Buffer::ObjectId].at(x, y) == 0) continue;
      const float* n = f[Buffer::Normal].pixel(x, y);
      EXPECT_NEAR(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), 1.0f, 1e-3);
    }
}

// Projecting each static surface point with the previous frame's camera lands on
// (x + 0.5 + motion.X, y + 0.5 + motion.Y): checks the y flip and the sign of the motion.
TEST(BlenderImport, MotionAgreesWithThePreviousCameraProjection) {
  auto seq = SequenceReader::open(kFixture);
  for (int t = 1; t < seq->frameCount(); ++t) {
    const Frame prev = seq->read(t - 1), cur = seq->read(t);
    const auto& V = prev.camera.worldToCamera;
    const auto& P = prev.camera.projection;
    double maxErr = 0;
    int n = 0;
    for (int y = 0; y < cur.height; ++y)
      for (int x = 0; x < cur.width; ++x) {
        const float id = cur[Buffer::ObjectId].at(x, y);
        if (id == 0 || id == 2) continue;  // sky, and the moving sphere (object motion)
        const float* p = cur[Buffer::Position].pixel(x, y);
        float v[4], c[4];
        for (int r = 0; r < 4; ++r) v[r] = V[r * 4] * p[0] + V[r * 4 + 1] * p[1] + V[r * 4 + 2] * p[2] + V[r * 4 + 3];
        for (int r = 0; r < 4; ++r) c[r] = P[r * 4] * v[0] + P[r * 4 + 1] * v[1] + P[r * 4 + 2] * v[2] + P[r * 4 + 3] * v[3];
        const double px = (c[0] / c[3] * 0.5 + 0.5) * cur.width, py = (0.5 - c[1] / c[3] * 0.5) * cur.height;
        const float* m = cur[Buffer::Motion].pixel(x, y);
        maxErr = std::max({maxErr, std::abs(px - (x + 0.5 + m[0])), std::abs(py - (y + 0.5 + m[1]))});
        // Depth is the linear view depth: -z in this frame's camera space.
        const auto& C = cur.camera.worldToCamera;
        const float zc = C[8] * p[0] + C[9] * p[1] + C[10] * p[2] + C[11];
        EXPECT_NEAR(cur[Buffer::Depth].at(x, y), -zc, 1e-4 * -zc);
        ++n;
      }
    EXPECT_GT(n, 500);
    EXPECT_LT(maxErr, 0.01) << "frame " << cur.number;
  }
}

// Reprojecting frame t-1 with the imported motion reproduces frame t wherever history is
// valid: world positions of static objects, and of the moving sphere once its own
// translation (exported by the fixture script) is applied.
TEST(BlenderImport, ReprojectingThePreviousFrameMatchesTheCurrentOne) {
  auto seq = SequenceReader::open(kFixture);
  std::ifstream in(kFixture / "cameras.json");
  const nlohmann::json cameras = nlohmann::json::parse(in);
  for (int t = 1; t < seq->frameCount(); ++t) {
    const Frame prevF = seq->read(t - 1), curF = seq->read(t);
    const FrameData prev = test::toFrameData(prevF), cur = test::toFrameData(curF);
    Reprojection rp;
    reproject(cur, &prev, ReprojectionSettings{}, rp);
    // The same with zero motion, to show the motion matters.
    Frame still = curF;
    for (float& v : still[Buffer::Motion].pixels) v = 0.0f;
    const FrameData curStill = test::toFrameData(still);
    Reprojection rp0;
    reproject(curStill, &prev, ReprojectionSettings{.depthTolerance = 1e9f, .normalTolerance = -2.0f, .testObjectId = false}, rp0);

    double posErr = 0, posErr0 = 0, sphereErr = 0, sphereErr0 = 0;
    int nPos = 0, nSphere = 0;
    // The sphere (pass index 2) only translates: T_t - T_{t-1} from the exported matrices.
    const auto& cams = cameras["cameras"];
    float shift[3];
    for (int r = 0; r < 3; ++r)
      shift[r] = cams[std::to_string(curF.number)]["objects"]["Sphere"][r][3].get<float>() -
                 cams[std::to_string(prevF.number)]["objects"]["Sphere"][r][3].get<float>();
    for (size_t i = 0; i < rp.kind.size(); ++i) {
      // Full bilinear footprints only (all four taps valid): no disocclusion near the pixel.
      if (rp.kind[i] != Reprojection::Bilinear) continue;
      bool full = true;
      const auto& w = rp.weights[i];
      const float fx = rp.prevX.data[i] - 0.5f - std::floor(rp.prevX.data[i] - 0.5f);
      const float fy = rp.prevY.data[i] - 0.5f - std::floor(rp.prevY.data[i] - 0.5f);
      const float bw[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
      for (int k = 0; k < 4; ++k) full &= std::abs(w[k] - bw[k]) < 1e-4f;
      if (!full) continue;
      const float id = cur.plane(Buffer::ObjectId).data[i];
      if (id == 2) {
        for (int c = 0; c < 3; ++c) {
          const float p = cur.plane(Buffer::Position, c).data[i];
          sphereErr += std::abs(rp.gather(prev.plane(Buffer::Position, c), i) + shift[c] - p);
          sphereErr0 += std::abs(rp0.gather(prev.plane(Buffer::Position, c), i) + shift[c] - p);
        }
        ++nSphere;
        continue;
      }
      for (int c = 0; c < 3; ++c) {
        posErr += std::abs(rp.gather(prev.plane(Buffer::Position, c), i) - cur.plane(Buffer::Position, c).data[i]);
        posErr0 += std::abs(rp0.gather(prev.plane(Buffer::Position, c), i) - cur.plane(Buffer::Position, c).data[i]);
        ++nPos;
      }
    }
    ASSERT_GT(nPos, 300);
    posErr /= nPos;
    posErr0 /= nPos;
    sphereErr /= std::max(nSphere, 1);
    sphereErr0 /= std::max(nSphere, 1);
    // Interpolating world positions bilinearly on planar surfaces is nearly exact.
    EXPECT_LT(posErr, 0.01) << "frame " << curF.number;
    EXPECT_GT(posErr0, 5 * posErr) << "frame " << curF.number;
    // Object motion: the moving sphere's surface points, moved by the sphere's translation.
    EXPECT_GT(nSphere, 20);
    EXPECT_LT(sphereErr, 0.02) << "frame " << curF.number;
    EXPECT_GT(sphereErr0, 3 * sphereErr) << "frame " << curF.number;
  }
}

}  // namespace
}  // namespace rtd
