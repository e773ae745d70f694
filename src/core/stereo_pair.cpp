#include "core/stereo_pair.h"

#include <algorithm>

#include "core/validate.h"

namespace rtd {

FrameStats combineEyeStats(const FrameStats& l, const FrameStats& r) {
  FrameStats out;
  out.passes = l.passes;
  for (const auto& p : r.passes) {
    auto it = std::find_if(out.passes.begin(), out.passes.end(), [&](const PassTiming& q) { return q.name == p.name; });
    if (it != out.passes.end()) it->milliseconds += p.milliseconds;
    else out.passes.push_back(p);
  }
  out.totalMilliseconds = l.totalMilliseconds + r.totalMilliseconds;
  out.sanitizedValues = l.sanitizedValues + r.sanitizedValues;
  for (int b = 0; b < kBufferCount; ++b) {
    out.sanitized[b].nonFinite = l.sanitized[b].nonFinite + r.sanitized[b].nonFinite;
    out.sanitized[b].outOfRange = l.sanitized[b].outOfRange + r.sanitized[b].outOfRange;
    out.sanitized[b].renormalized = l.sanitized[b].renormalized + r.sanitized[b].renormalized;
  }
  out.notes = l.notes;  // the eyes' distinct notes
  for (const auto& n : r.notes)
    if (std::find(out.notes.begin(), out.notes.end(), n) == out.notes.end()) out.notes.push_back(n);
  out.pixels = l.pixels + r.pixels;
  out.memory = l.memory;
  for (const auto& m : r.memory) {
    auto it = std::find_if(out.memory.begin(), out.memory.end(), [&](const MemoryUse& q) { return q.category == m.category; });
    if (it != out.memory.end()) it->bytes += m.bytes;
    else out.memory.push_back(m);
  }
  return out;
}

StereoPair::StereoPair(std::unique_ptr<Denoiser> left, std::unique_ptr<Denoiser> right) {
  eyes_[0] = std::move(left);
  eyes_[1] = std::move(right);
}

void StereoPair::set(std::string_view name, std::string_view value) {
  eyes_[0]->set(name, value);  // a rejected value throws here, before the right eye changes
  eyes_[1]->set(name, value);
}

void StereoPair::validate(const StereoFrameInputs& in, const ImageView& left, const ImageView& right) const {
  const char* names[2] = {"left", "right"};
  const ImageView* outs[2] = {&left, &right};
  for (int e = 0; e < 2; ++e) {
    // The single-view checks (core/validate.h), the eye named in the message.
    try {
      checkInputViews(in.eye[e], requiredBuffers());
      checkOutputView(*outs[e], in.eye[e][Buffer::Color].width, in.eye[e][Buffer::Color].height);
    } catch (const Error& err) {
      throw Error(std::string(names[e]) + " eye: " + err.what());
    }
  }
  const ImageView &a = in.eye[0][Buffer::Color], &b = in.eye[1][Buffer::Color];
  if (a.width != b.width || a.height != b.height)
    throw Error("stereo: the left eye is " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                ", the right eye " + std::to_string(b.width) + "x" + std::to_string(b.height));
}

void StereoPair::denoise(const StereoFrameInputs& in, const ImageView& left, const ImageView& right) {
  validate(in, left, right);
  if (in.eye[0].cameraCut || in.eye[1].cameraCut) reset();
  eyes_[0]->denoise(in.eye[0], left);
  eyes_[1]->denoise(in.eye[1], right);
  for (int e = 0; e < 2; ++e) eyeStats_[e] = eyes_[e]->stats();
  stats_ = combineEyeStats(eyeStats_[0], eyeStats_[1]);
}

void StereoPair::reset() {
  for (auto& e : eyes_) e->reset();
}

}  // namespace rtd
