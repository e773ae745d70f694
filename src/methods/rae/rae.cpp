// Method "rae" on the CPU: view-space normals -> the oneDNN network (rae_model.h), whose hidden
// states are the denoiser's history: cleared by reset() (a camera cut, a resize) and, with
// recurrent = false, before every frame. The weights are read when the denoiser is created and
// whenever the setting "weights" changes (a bad file is reported by set() and the old weights
// stay).
#include "backend/cpu/cpu_denoiser.h"
#include "core/conventions.h"
#include "core/parallel.h"
#include "methods/rae/rae_model.h"
#include "rtd/methods/rae.h"

namespace rtd {

namespace {

class RaeCpu final : public CpuDenoiser<RaeSettings> {
 public:
  explicit RaeCpu(tbb::task_arena& arena) : CpuDenoiser(arena), weights_(rae::loadWeights("")) {
    network_.setThreads(arena.max_concurrency());  // --threads bounds oneDNN's OpenMP threads too
  }
  std::vector<Buffer> requiredBuffers() const override { return rae::requiredBuffers(weights_); }

 protected:
  void settingsChanged() override {
    if (!rae::reloadWeights(settings_.weights, loaded_, weights_)) return;
    if (width_ > 0) network_.configure(weights_, width_, height_);  // new weights: new network, no state
  }
  void resizeHistory(int w, int h) override {
    network_.configure(weights_, w, h);
    for (auto& p : viewNormal_) p.resize(w, h);
  }
  void resetHistory() override { network_.reset(); }
  void visitMethodPlanes(const PlaneVisitor& visit) const override {
    network_.forEachState([&](const float* data, size_t count) { visit("hidden state", data, count); });
    visitPlanes(visit, "view-space normal", viewNormal_);
  }

  const Plane3& process(const FrameData& frame, const FrameData*, Plane3& out, FrameStats& stats) override {
    if (!settings_.recurrent) network_.reset();
    const Plane* normal = nullptr;
    if (weights_.normal) {
      PassTimer t(stats, "view normals");
      const std::array<float, 9> r = worldToViewRotation(frame.camera);  // n_view = R n_world
      const auto& n = frame.planes(Buffer::Normal);
      parallelRows(frame.height, [&](int y) {
        const float *nx = n[0].row(y), *ny = n[1].row(y), *nz = n[2].row(y);
        for (int c = 0; c < 3; ++c) {
          float* o = viewNormal_[c].row(y);
          for (int x = 0; x < frame.width; ++x) o[x] = r[c * 3] * nx[x] + r[c * 3 + 1] * ny[x] + r[c * 3 + 2] * nz[x];
        }
      });
      normal = viewNormal_.data();
    }
    network_.run(frame.planes(Buffer::Color).data(), weights_.albedo ? frame.planes(Buffer::Albedo).data() : nullptr,
                 normal, out, stats);
    return out;
  }

 private:
  rae::Weights weights_;
  std::string loaded_;  // the "weights" setting weights_ came from ("" = built-in)
  rae::Network network_;
  Plane3 viewNormal_;
};

}  // namespace

std::unique_ptr<Denoiser> createRaeCpu(tbb::task_arena& arena) { return std::make_unique<RaeCpu>(arena); }

}  // namespace rtd
