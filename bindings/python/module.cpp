// rtdenoise._core: Python bindings (pybind11) of the C++ API, a client of include/rtd/ only.
// Arrays are numpy arrays, rows from the top, channels last (H x W x C; one-channel buffers
// H x W); float32 or float16 arrays whose channels are contiguous are read in place (any row
// and pixel strides: a slice of a larger array works), others are converted once. Buffer
// names are rtd::Buffer's ("color", "albedo", "normal", "depth", "motion", "objectId", ...).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cstring>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "rtd/config.h"
#include "rtd/eval/metrics.h"
#include "rtd/rtd.h"

namespace py = pybind11;

namespace {

// A setting's value as text, from the Python value given (bool before int: bool is an int).
std::string settingText(const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(value)) return std::to_string(value.cast<long long>());
  if (py::isinstance<py::float_>(value)) {
    std::ostringstream s;
    s.precision(9);
    s << value.cast<double>();
    return s.str();
  }
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  throw py::type_error("setting values are bool, int, float or str, not " +
                       std::string(py::str(value.get_type().attr("__name__"))));
}

// A setting's text as the Python value of its type.
py::object settingValue(const rtd::SettingInfo& s) {
  if (s.type == "bool") return py::bool_(s.value == "true");
  if (s.type == "int") return py::int_(std::stoll(s.value));
  if (s.type == "float") return py::float_(std::stod(s.value));
  return py::str(s.value);
}

py::dict settingInfo(const rtd::SettingInfo& s) {
  py::dict d;
  d["name"] = s.name;
  d["type"] = s.type;
  d["value"] = settingValue(s);
  d["doc"] = s.doc;
  d["choices"] = s.choices;
  return d;
}

// ---- Arrays <-> views and images.

std::string shapeText(const py::array& a) {
  std::string s;
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? " x " : "") + std::to_string(a.shape(i));
  return s;
}

/// The numpy array of one buffer, checked (shape, dtype) and kept alive while its view is used.
struct ArrayView {
  py::array array;  // the array read (the caller's, or a converted copy)
  rtd::ImageView view;
};

// A view of `value` for buffer `what` with `need` channels (0: 3 or 4, an output), or a
// ValueError naming the buffer. Float32/float16 (and int32 for ids) arrays with contiguous
// channels are used in place; others are converted to float32 (writable outputs never are).
ArrayView viewOf(const std::string& what, const py::handle& value, int need, bool ids, bool output) {
  py::array a = py::array::ensure(value);
  if (!a) throw py::type_error(what + ": expected a numpy array, not " + std::string(py::str(value.get_type().attr("__name__"))));
  if (a.ndim() != 2 && a.ndim() != 3)
    throw py::value_error(what + ": expected an H x W or H x W x C array, got " + std::to_string(a.ndim()) + " dimensions");
  const int h = int(a.shape(0)), w = int(a.shape(1)), c = a.ndim() == 3 ? int(a.shape(2)) : 1;
  if (h <= 0 || w <= 0) throw py::value_error(what + ": the array is empty");
  if (c < 1 || c > 4) throw py::value_error(what + ": " + std::to_string(c) + " channels (1 to 4 are accepted)");
  if (need > 0 && c < need)
    throw py::value_error(what + ": needs " + std::to_string(need) + " channels, the array is " + shapeText(a));
  if (need == 0 && c < 3) throw py::value_error(what + ": needs 3 or 4 channels (H x W x 3 or H x W x 4)");

  const py::dtype f32 = py::dtype::of<float>(), f16 = py::dtype("float16"), i32 = py::dtype::of<int32_t>();
  const bool half = a.dtype().equal(f16);
  const bool int32 = ids && a.dtype().equal(i32);
  const bool float32 = a.dtype().equal(f32);
  const py::ssize_t item = a.itemsize();
  const bool channelsContiguous = a.ndim() == 2 || c == 1 || a.strides(2) == item;
  const bool stridesOk = a.strides(0) > 0 && a.strides(1) > 0 && a.strides(0) % item == 0 && a.strides(1) % item == 0 &&
                         reinterpret_cast<uintptr_t>(a.data()) % size_t(item) == 0;
  if (output) {
    if (!(float32 || half)) throw py::value_error(what + ": must be a float32 or float16 array");
    if (!a.writeable()) throw py::value_error(what + ": the array is read-only");
    if (!channelsContiguous || !stridesOk) throw py::value_error(what + ": the array's channels must be contiguous");
  } else if (!((float32 || half || int32) && channelsContiguous && stridesOk)) {
    // One conversion to a packed float32 array (float64 input, reversed or odd strides, ...).
    a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!a) throw py::type_error(what + ": cannot convert the array to float32");
    return viewOf(what, a, need, ids, output);
  }
  static const rtd::Format floats[] = {rtd::Format::Undefined, rtd::Format::Float, rtd::Format::Float2,
                                       rtd::Format::Float3, rtd::Format::Float4};
  static const rtd::Format halves[] = {rtd::Format::Undefined, rtd::Format::Half, rtd::Format::Half2,
                                       rtd::Format::Half3, rtd::Format::Half4};
  const rtd::Format format = int32 ? rtd::Format::Int32 : half ? halves[c] : floats[c];
  if (int32 && c != 1) throw py::value_error(what + ": int32 arrays hold ids, one channel");
  ArrayView out{a, {const_cast<void*>(a.data()), w, h, format, size_t(a.strides(1)), size_t(a.strides(0))}};
  return out;
}

py::array_t<float> toArray(const rtd::Image& img, bool squeeze = true) {
  std::vector<py::ssize_t> shape = {img.height, img.width};
  if (!(squeeze && img.channels == 1)) shape.push_back(img.channels);
  py::array_t<float> a(shape);
  std::memcpy(a.mutable_data(), img.pixels.data(), img.pixels.size() * sizeof(float));
  return a;
}

rtd::Image toImage(const std::string& what, const py::handle& value, int channels = 0) {
  auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!a) throw py::type_error(what + ": expected a numpy array");
  if (a.ndim() != 2 && a.ndim() != 3) throw py::value_error(what + ": expected an H x W or H x W x C array");
  const int c = a.ndim() == 3 ? int(a.shape(2)) : 1;
  if (channels && c != channels)
    throw py::value_error(what + ": needs " + std::to_string(channels) + " channels, the array has " + std::to_string(c));
  rtd::Image img(int(a.shape(1)), int(a.shape(0)), c);
  std::memcpy(img.pixels.data(), a.data(), img.pixels.size() * sizeof(float));
  return img;
}

// ---- Cameras and conventions.

py::array_t<float> matrix(const std::array<float, 16>& m) {
  py::array_t<float> a({4, 4});
  std::memcpy(a.mutable_data(), m.data(), sizeof(float) * 16);
  return a;
}

std::array<float, 16> toMatrix(const std::string& what, const py::handle& value) {
  auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!a || a.size() != 16 || !(a.ndim() == 2 || a.ndim() == 1))
    throw py::value_error(what + ": expected a 4 x 4 matrix (row-major, acting on column vectors)");
  std::array<float, 16> m;
  std::memcpy(m.data(), a.data(), sizeof m);
  return m;
}

rtd::FrameConventions toConventions(const py::dict& d) {
  rtd::FrameConventions c;
  for (const auto& [key, value] : d) {
    const std::string name = py::str(key);
    if (name == "depthProjection") c.depthProjection = toMatrix("conventions['depthProjection']", value);
    else rtd::setConvention(c, name, settingText(value));
  }
  return c;
}

// ---- Denoising.

class PyDenoiser {
 public:
  explicit PyDenoiser(std::unique_ptr<rtd::Denoiser> d) : d_(std::move(d)) {}
  rtd::Denoiser& get() { return *d_; }

  py::array denoise(const py::kwargs& kwargs) {
    // Every argument is checked before anything runs: a bad array changes no history.
    rtd::FrameInputs frame;
    std::vector<ArrayView> keep;
    std::optional<ArrayView> out;
    for (const auto& [key, value] : kwargs) {
      const std::string name = py::str(key);
      if (value.is_none()) continue;
      if (name == "output") {
        out = viewOf("output", value, 0, false, true);
      } else if (name == "camera") {
        frame.camera = value.cast<rtd::Camera>();
      } else if (name == "camera_cut") {
        frame.cameraCut = value.cast<bool>();
      } else if (name == "conventions") {
        frame.conventions = toConventions(value.cast<py::dict>());
      } else if (auto b = rtd::bufferFromName(name)) {
        const bool ids = rtd::bufferChannels(*b) == "I";
        keep.push_back(viewOf(name, value, rtd::bufferChannelCount(*b), ids, false));
        frame[*b] = keep.back().view;
      } else {
        throw py::type_error("denoise(): unknown argument '" + name + "' (buffers: " + bufferList() +
                             "; and output, camera, camera_cut, conventions)");
      }
    }
    if (!frame.has(rtd::Buffer::Color)) throw py::value_error("denoise(): the color buffer is required");
    const rtd::ImageView& color = frame[rtd::Buffer::Color];
    for (int i = 0; i < rtd::kBufferCount; ++i) {
      const rtd::ImageView& v = frame.buffers[size_t(i)];
      if (!v.empty() && (v.width != color.width || v.height != color.height))
        throw py::value_error(std::string(rtd::bufferName(rtd::Buffer(i))) + ": the array is " +
                              std::to_string(v.height) + " x " + std::to_string(v.width) + ", color is " +
                              std::to_string(color.height) + " x " + std::to_string(color.width));
    }
    for (rtd::Buffer b : d_->requiredBuffers())
      if (!frame.has(b)) throw py::value_error("denoise(): method '" + std::string(d_->method()) + "' needs buffer '" +
                                               std::string(rtd::bufferName(b)) + "'");
    py::array result;
    if (out) {
      if (out->view.width != color.width || out->view.height != color.height)
        throw py::value_error("output: the array is " + std::to_string(out->view.height) + " x " +
                              std::to_string(out->view.width) + ", color is " + std::to_string(color.height) + " x " +
                              std::to_string(color.width));
      result = out->array;
    } else {
      result = py::array_t<float>({py::ssize_t(color.height), py::ssize_t(color.width), py::ssize_t(3)});
      out = viewOf("output", result, 0, false, true);
    }
    {
      py::gil_scoped_release release;
      d_->denoise(frame, out->view);
    }
    return result;
  }

  static std::string bufferList() {
    std::string s;
    for (int i = 0; i < rtd::kBufferCount; ++i) s += (i ? ", " : "") + std::string(rtd::bufferName(rtd::Buffer(i)));
    return s;
  }

 private:
  std::unique_ptr<rtd::Denoiser> d_;
};

std::string backendOf(rtd::Backend b) { return std::string(rtd::backendName(b)); }

rtd::Backend parseBackend(const std::string& s) {
  if (s == "cpu") return rtd::Backend::Cpu;
  if (s == "vulkan") return rtd::Backend::Vulkan;
  throw py::value_error("backend must be 'cpu' or 'vulkan', not '" + s + "'");
}

py::dict statsOf(const rtd::FrameStats& s) {
  py::dict d, passes;
  for (const auto& p : s.passes) passes[py::str(p.name)] = p.milliseconds;
  d["passes"] = passes;
  d["total_ms"] = s.totalMilliseconds;
  d["sanitized_values"] = s.sanitizedValues;
  d["pixels"] = s.pixels;
  py::dict memory;
  for (const auto& m : s.memory) memory[py::str(m.category)] = m.bytes;
  d["memory"] = memory;
  py::list notes;
  for (const auto& n : s.notes) notes.append(n);
  d["notes"] = notes;
  return d;
}

// ---- Frames of a sequence.

py::array bufferArray(py::object self, rtd::Frame& f, rtd::Buffer b) {
  rtd::Image& img = f[b];
  if (img.empty()) throw py::key_error("the frame has no buffer '" + std::string(rtd::bufferName(b)) + "'");
  std::vector<py::ssize_t> shape = {img.height, img.width};
  if (img.channels > 1) shape.push_back(img.channels);
  return py::array_t<float>(shape, img.pixels.data(), self);  // a view into the frame, keeping it alive
}

rtd::Buffer bufferNamed(const std::string& name) {
  if (auto b = rtd::bufferFromName(name)) return *b;
  throw py::key_error("unknown buffer '" + name + "' (buffers: " + PyDenoiser::bufferList() + ")");
}

void setBuffer(rtd::Frame& f, const std::string& name, const py::handle& value) {
  const rtd::Buffer b = bufferNamed(name);
  rtd::Image img = toImage(name, value, rtd::bufferChannelCount(b));
  if (f.width == 0 && f.height == 0) f.width = img.width, f.height = img.height;
  if (img.width != f.width || img.height != f.height)
    throw py::value_error(name + ": the array is " + std::to_string(img.height) + " x " + std::to_string(img.width) +
                          ", the frame is " + std::to_string(f.height) + " x " + std::to_string(f.width));
  f[b] = std::move(img);
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "rtdenoise: real-time denoising of path-traced frames (Python bindings of the C++ API)";
  py::register_exception<rtd::Error>(m, "Error", PyExc_ValueError);
  m.attr("__version__") = rtd::versionString();
  m.attr("version_info") = py::make_tuple(rtd::version() / 10000, rtd::version() / 100 % 100, rtd::version() % 100);
  m.attr("has_vulkan") = bool(RTD_WITH_VULKAN);

  m.def("buffer_names", [] {
    std::vector<std::string> names;
    for (int i = 0; i < rtd::kBufferCount; ++i) names.emplace_back(rtd::bufferName(rtd::Buffer(i)));
    return names;
  }, "Names of the buffers a frame may carry (rtd::Buffer), in order.");
  m.def("buffer_channels", [](const std::string& name) { return rtd::bufferChannelCount(bufferNamed(name)); },
        "Number of channels of a buffer.");
  m.def("list_methods", [] {
    py::list out;
    for (const auto& info : rtd::listMethods()) {
      py::dict d;
      d["name"] = info.name;
      d["summary"] = info.summary;
      d["cpu"] = info.cpu;
      d["vulkan"] = info.vulkan;
      py::list settings;
      for (const auto& s : info.settings) settings.append(settingInfo(s));
      d["settings"] = settings;
      out.append(d);
    }
    return out;
  }, "Every method with its settings' defaults (dicts: name, summary, cpu, vulkan, settings).");
  m.def("list_devices", [] {
    std::string vulkanError;
    py::list out;
    for (const auto& info : rtd::listDevices(&vulkanError)) {
      py::dict d;
      d["backend"] = backendOf(info.backend);
      d["index"] = info.index;
      d["name"] = info.name;
      d["description"] = info.description;
      out.append(d);
    }
    return out;
  }, "Every device this build can run on: the CPU, then each Vulkan device.");
  m.def("convention_settings", [] {
    py::list out;
    for (const auto& s : rtd::conventionSettings()) out.append(settingInfo(s));
    return out;
  }, "The engine conventions a frame may declare (denoise(conventions={...})), with their defaults.");

  py::class_<rtd::Camera>(m, "Camera", "The camera of a frame: row-major 4x4 matrices acting on column vectors.")
      .def(py::init([](py::object worldToCamera, py::object projection) {
             rtd::Camera c;
             if (!worldToCamera.is_none()) c.worldToCamera = toMatrix("world_to_camera", worldToCamera);
             if (!projection.is_none()) c.projection = toMatrix("projection", projection);
             c.valid = !worldToCamera.is_none() || !projection.is_none();
             return c;
           }),
           py::arg("world_to_camera") = py::none(), py::arg("projection") = py::none())
      .def_property("world_to_camera", [](const rtd::Camera& c) { return matrix(c.worldToCamera); },
                    [](rtd::Camera& c, py::object m) { c.worldToCamera = toMatrix("world_to_camera", m); },
                    "World to a right-handed camera space looking down -z.")
      .def_property("projection", [](const rtd::Camera& c) { return matrix(c.projection); },
                    [](rtd::Camera& c, py::object m) { c.projection = toMatrix("projection", m); },
                    "Camera space to OpenGL clip space (unjittered).")
      .def_readwrite("valid", &rtd::Camera::valid, "False when the source gave no camera.");

  py::class_<PyDenoiser>(m, "Denoiser", "A denoiser owns the history of one image stream (one per stream; not thread-safe).")
      .def_property_readonly("method", [](PyDenoiser& d) { return std::string(d.get().method()); })
      .def_property_readonly("backend", [](PyDenoiser& d) { return backendOf(d.get().backend()); })
      .def_property_readonly("required_buffers", [](PyDenoiser& d) {
        std::vector<std::string> out;
        for (rtd::Buffer b : d.get().requiredBuffers()) out.emplace_back(rtd::bufferName(b));
        return out;
      })
      .def_property_readonly("settings", [](PyDenoiser& d) {
        py::dict out;
        for (const auto& s : d.get().settings()) out[py::str(s.name)] = settingValue(s);
        return out;
      }, "Current settings, name -> value.")
      .def("settings_info", [](PyDenoiser& d) {
        py::list out;
        for (const auto& s : d.get().settings()) out.append(settingInfo(s));
        return out;
      }, "Current settings with type, documentation and choices.")
      .def("set", [](PyDenoiser& d, const std::string& name, py::object value) { d.get().set(name, settingText(value)); },
           py::arg("name"), py::arg("value"), "Sets a setting by name; raises rtdenoise.Error for a bad name or value.")
      .def("get", [](PyDenoiser& d, const std::string& name) -> py::object {
        for (const auto& s : d.get().settings())
          if (s.name == name) return settingValue(s);
        throw rtd::Error("method '" + std::string(d.get().method()) + "' has no setting '" + name + "'");
      }, py::arg("name"))
      .def("denoise", &PyDenoiser::denoise,
           "denoise(color=..., albedo=..., normal=..., depth=..., motion=..., ..., output=None, camera=None,\n"
           "        camera_cut=False, conventions=None) -> H x W x 3 float32 array (or `output`, filled in place)")
      .def("reset", [](PyDenoiser& d) { d.get().reset(); }, "Forgets the history (a camera cut).")
      .def_property_readonly("stats", [](PyDenoiser& d) { return statsOf(d.get().stats()); },
                             "The last frame: passes (name -> ms), total_ms, sanitized_values, pixels, memory (category\n"
                             "-> bytes held after it: frames, planes, staging on Vulkan; rtd::MemoryUse), notes (parts\n"
                             "asked for that did not run, and why).")
      .def_property_readonly("timings", [](PyDenoiser& d) {
        py::dict passes;
        for (const auto& p : d.get().stats().passes) passes[py::str(p.name)] = p.milliseconds;
        return passes;
      }, "Milliseconds of each pass of the last frame, in order.");

  py::class_<rtd::Device>(m, "Device", "A compute device (CPU thread pool or Vulkan device).")
      .def(py::init([](const std::string& backend, int threads, const std::string& vulkanDevice, bool validation) {
             return rtd::Device::create({parseBackend(backend), threads, vulkanDevice, validation});
           }),
           py::arg("backend") = "cpu", py::arg("threads") = 0, py::arg("vulkan_device") = "",
           py::arg("validation") = false)
      .def_property_readonly("backend", [](rtd::Device& d) { return backendOf(d.backend()); })
      .def_property_readonly("name", &rtd::Device::name)
      .def("create_denoiser", [](rtd::Device& d, const std::string& method, const py::kwargs& settings) {
             auto den = d.createDenoiser(method);
             for (const auto& [k, v] : settings) den->set(std::string(py::str(k)), settingText(v));
             return PyDenoiser(std::move(den));
           }, py::arg("method"), "create_denoiser(method, **settings): a denoiser with these settings (by name).");

  // ---- Sequences.
  py::class_<rtd::Frame>(m, "Frame", "One frame in memory: arrays by buffer name, its number and camera.")
      .def(py::init([](int number, std::optional<rtd::Camera> camera, const py::kwargs& buffers) {
             rtd::Frame f;
             f.number = number;
             if (camera) f.camera = *camera;
             for (const auto& [k, v] : buffers) setBuffer(f, std::string(py::str(k)), v);
             return f;
           }),
           py::arg("number") = 0, py::arg("camera") = py::none(), "Frame(number=0, camera=None, **buffers)")
      .def_readwrite("number", &rtd::Frame::number)
      .def_readonly("width", &rtd::Frame::width)
      .def_readonly("height", &rtd::Frame::height)
      .def_readwrite("camera", &rtd::Frame::camera)
      .def("__getitem__", [](py::object self, const std::string& name) {
        return bufferArray(self, self.cast<rtd::Frame&>(), bufferNamed(name));
      }, "The buffer as an array (a view into the frame).")
      .def("__setitem__", [](rtd::Frame& f, const std::string& name, py::object value) { setBuffer(f, name, value); })
      .def("__contains__", [](rtd::Frame& f, const std::string& name) {
        auto b = rtd::bufferFromName(name);
        return b && f.has(*b);
      })
      .def_property_readonly("buffers", [](py::object self) {
        rtd::Frame& f = self.cast<rtd::Frame&>();
        py::dict d;
        for (int i = 0; i < rtd::kBufferCount; ++i)
          if (f.has(rtd::Buffer(i))) d[py::str(std::string(rtd::bufferName(rtd::Buffer(i))))] = bufferArray(self, f, rtd::Buffer(i));
        return d;
      }, "Every buffer present, name -> array (views): den.denoise(**frame.buffers, camera=frame.camera).");

  py::class_<rtd::SequenceReader>(m, "SequenceReader",
                                  "Reads a sequence directory (native, or Blender Cycles multilayer EXR) frame by frame.")
      .def(py::init([](const std::filesystem::path& dir) { return rtd::SequenceReader::open(dir); }), py::arg("path"))
      .def_property_readonly("kind", [](rtd::SequenceReader& r) { return std::string(rtd::sequenceKindName(r.kind())); })
      .def_property_readonly("width", &rtd::SequenceReader::width)
      .def_property_readonly("height", &rtd::SequenceReader::height)
      .def_property_readonly("buffers", [](rtd::SequenceReader& r) {
        std::vector<std::string> out;
        for (rtd::Buffer b : r.buffers()) out.emplace_back(rtd::bufferName(b));
        return out;
      })
      .def("__len__", &rtd::SequenceReader::frameCount)
      .def("frame_number", &rtd::SequenceReader::frameNumber, py::arg("index"))
      .def("frame_path", &rtd::SequenceReader::framePath, py::arg("index"))
      .def("read", [](rtd::SequenceReader& r, int index) {
        if (index < 0) index += r.frameCount();
        if (index < 0 || index >= r.frameCount()) throw py::index_error("frame index out of range");
        return r.read(index);
      }, py::arg("index"))
      .def("__getitem__", [](rtd::SequenceReader& r, int index) {
        if (index < 0) index += r.frameCount();
        if (index < 0 || index >= r.frameCount()) throw py::index_error("frame index out of range");
        return r.read(index);
      });

  py::class_<rtd::SequenceWriter>(m, "SequenceWriter", "Writes a native sequence: frame EXRs and sequence.json.")
      .def(py::init<std::filesystem::path>(), py::arg("path"))
      .def("write", [](rtd::SequenceWriter& w, const rtd::Frame& f) { w.write(f); }, py::arg("frame"),
           "Writes frame_NNNN.exr with every buffer the frame has.")
      .def("finish", &rtd::SequenceWriter::finish, "Writes sequence.json for the frames written so far.")
      .def_property_readonly("path", &rtd::SequenceWriter::dir);

  m.def("read_exr", [](const std::filesystem::path& p) { return toArray(rtd::readRgbExr(p), false); }, py::arg("path"),
        "The R, G, B channels of an EXR file as an H x W x 3 float32 array.");
  m.def("write_exr", [](const std::filesystem::path& p, py::object rgb) { rtd::writeRgbExr(p, toImage("rgb", rgb, 3)); },
        py::arg("path"), py::arg("rgb"), "Writes an H x W x 3 array as a float EXR (atomically).");

  // ---- Evaluation metrics (the eval library).
  py::module_ ev = m.def_submodule("eval", "Image metrics of the evaluation library (docs/evaluation.md).");
  auto rgb = [](const char* what, const py::handle& a) { return toImage(what, a, 3); };
  ev.def("tone_map", [rgb](py::object linear, const std::string& op, float exposure) {
    rtd::eval::ToneMapSettings tm{rtd::eval::parseOperator(op), exposure};
    return toArray(rtd::eval::toneMap(rgb("linear", linear), tm));
  }, py::arg("linear"), py::arg("op") = "aces", py::arg("exposure") = 0.0f,
     "Linear HDR RGB -> tone-mapped sRGB in [0, 1] (op: clamp, reinhard, aces).");
  ev.def("mse", [](py::object a, py::object b) { return rtd::eval::mse(toImage("a", a), toImage("b", b)); });
  ev.def("rmse", [rgb](py::object t, py::object r) { return rtd::eval::rmse(rgb("test", t), rgb("reference", r)); },
         py::arg("test"), py::arg("reference"), "RMSE on linear HDR radiance.");
  ev.def("rel_mse", [rgb](py::object t, py::object r, double eps) { return rtd::eval::relMse(rgb("test", t), rgb("reference", r), eps); },
         py::arg("test"), py::arg("reference"), py::arg("epsilon") = 0.01, "Relative MSE on linear HDR radiance.");
  ev.def("psnr", [rgb](py::object t, py::object r, double peak) { return rtd::eval::psnr(rgb("test", t), rgb("reference", r), peak); },
         py::arg("test"), py::arg("reference"), py::arg("peak") = 1.0, "PSNR in dB of tone-mapped sRGB images.");
  ev.def("ssim", [rgb](py::object t, py::object r, double range) { return rtd::eval::ssim(rgb("test", t), rgb("reference", r), range); },
         py::arg("test"), py::arg("reference"), py::arg("data_range") = 1.0, "SSIM of tone-mapped sRGB images.");
  ev.def("flip", [rgb](py::object t, py::object r, bool errorMap) -> py::object {
    rtd::Image map;
    const double mean = rtd::eval::flip(rgb("test", t), rgb("reference", r), {}, errorMap ? &map : nullptr);
    if (errorMap) return py::make_tuple(mean, toArray(map));
    return py::float_(mean);
  }, py::arg("test"), py::arg("reference"), py::arg("error_map") = false,
     "LDR-FLIP mean of tone-mapped sRGB images (and the per-pixel map with error_map=True).");
}
