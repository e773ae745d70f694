/* rtdenoise — the C API (C99): the library from C or any language with a C FFI, as a thin layer
 * over the C++ API (rtd/rtd.h), in the manner of Intel Open Image Denoise: opaque, reference-
 * counted handles; settings by name; image views with explicit formats and strides; every call
 * returns an error code, and every error is also kept by the device (rtdGetDeviceError) and
 * reported to its error callback. No C++ exception crosses this boundary.
 *
 *   RTDDevice device = rtdNewDevice(RTD_BACKEND_CPU);
 *   rtdCommitDevice(device);
 *   RTDDenoiser den = rtdNewDenoiser(device, "svgf");
 *   rtdSetDenoiserSetting(den, "atrousIterations", "5");
 *   RTDImageView color = {colorPixels, width, height, RTD_FORMAT_FLOAT3, 0, 0};
 *   rtdSetDenoiserImage(den, "color", &color);      // and "albedo", "normal", ..., "output"
 *   per frame: update the pixels (or the views), rtdSetDenoiserCamera(...), rtdDenoise(den);
 *   on a camera cut: rtdResetDenoiser(den);
 *   rtdReleaseDenoiser(den); rtdReleaseDevice(device);
 *
 * Threading: a denoiser is used from one thread at a time. CPU denoisers of one device may run
 * on different threads at once; on a Vulkan device, denoise calls must not overlap (they share
 * the device's queue, which Vulkan requires to be externally synchronized).
 * Strings returned by the library stay valid until the next call on the same handle (for the
 * device's error message: until the next rtdGetDeviceError on it) unless stated otherwise. */
#ifndef RTD_CAPI_H
#define RTD_CAPI_H

#include <stddef.h>
#include <stdint.h>

#include "rtd/config.h"
#include "rtd/version.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Errors ---------------------------------------------------------------------------- */

typedef enum RTDError {
  RTD_ERROR_NONE = 0,
  /** An unexpected failure inside the library (a bug: please report the message). */
  RTD_ERROR_UNKNOWN = 1,
  /** A null handle or pointer, an unknown name, a value out of range, or input the denoiser
   *  rejects (a missing buffer, mismatched sizes): the message names the setting or buffer.
   *  The denoiser is left as it was: its history and settings do not change. */
  RTD_ERROR_INVALID_ARGUMENT = 2,
  /** A call out of order: a device used before rtdCommitDevice or changed after it, or
   *  rtdDenoise without an output image. */
  RTD_ERROR_INVALID_OPERATION = 3,
  RTD_ERROR_OUT_OF_MEMORY = 4,
  /** Not available in this build or on this machine: no Vulkan device (or none matching the
   *  "vulkanDevice" parameter), a method without an implementation on the device's backend. */
  RTD_ERROR_UNSUPPORTED = 5,
  /** Not a value. The *_MAX_ENUM entries make each enum 32 bits wide in C and C++ alike, so any
   *  int a C caller passes is a valid object of the type and is refused by a range check (a
   *  value outside a narrower enum's range would be undefined behaviour in C++). */
  RTD_ERROR_MAX_ENUM = 0x7fffffff
} RTDError;

/** Called for every error of a device (and of its denoisers), on the thread of the failing call,
 *  before that call returns. `message` is valid only during the call. */
typedef void (*RTDErrorFunction)(void* userPtr, RTDError code, const char* message);

/* ---- Version and what this build offers ---------------------------------------------- */

/** RTD_VERSION (10000 * major + 100 * minor + patch) of the loaded library. */
int rtdGetVersion(void);
/** "major.minor.patch" of the loaded library. */
const char* rtdGetVersionString(void);

/** Registered methods ("accumulate", "svgf", "bmfr", ...); names and summaries are static. */
int rtdGetMethodCount(void);
/** NULL (and RTD_ERROR_INVALID_ARGUMENT on the thread, see rtdGetDeviceError) out of range. */
const char* rtdGetMethodName(int index);
const char* rtdGetMethodSummary(int index);

typedef enum RTDBackend { RTD_BACKEND_CPU = 0, RTD_BACKEND_VULKAN = 1, RTD_BACKEND_MAX_ENUM = 0x7fffffff } RTDBackend;

/** Devices this machine can run on: the CPU first, then each Vulkan device. The strings stay
 *  valid until the next rtdGetPhysicalDeviceCount call. */
int rtdGetPhysicalDeviceCount(void);
const char* rtdGetPhysicalDeviceName(int index);
/** The backend of physical device `index`, or -1 out of range. */
int rtdGetPhysicalDeviceBackend(int index);

/* ---- Devices -------------------------------------------------------------------------- */

typedef struct RTDDeviceImpl* RTDDevice;

/** A new, uncommitted device of `backend` (reference count 1); NULL for an unknown backend
 *  (the error is then the thread's: rtdGetDeviceError(NULL, ...)). */
RTDDevice rtdNewDevice(RTDBackend backend);
/** Parameters, before rtdCommitDevice: "threads" (CPU worker threads, 0 = all cores),
 *  "vulkanValidation" (0/1: Vulkan validation layers if installed). */
RTDError rtdSetDeviceInt(RTDDevice device, const char* name, int value);
/** "vulkanDevice": Vulkan device index or part of its name (empty = the best one). */
RTDError rtdSetDeviceString(RTDDevice device, const char* name, const char* value);
/** Creates the device: RTD_ERROR_UNSUPPORTED when the backend is not available. */
RTDError rtdCommitDevice(RTDDevice device);
/** The committed device's description ("CPU (8 threads, oneTBB)"); NULL before the commit. */
const char* rtdGetDeviceName(RTDDevice device);

/** Every later error of the device and its denoisers is also reported to `func` (NULL: none). */
void rtdSetDeviceErrorFunction(RTDDevice device, RTDErrorFunction func, void* userPtr);
/** The first error since the last call (then cleared), RTD_ERROR_NONE if none; `message`, if
 *  not NULL, receives its text (valid until the next rtdGetDeviceError on this device). With
 *  device NULL: the first error of this thread's calls that had no device to report to. */
RTDError rtdGetDeviceError(RTDDevice device, const char** message);

void rtdRetainDevice(RTDDevice device);
/** Drops a reference; the device goes when the last one and its denoisers are gone. */
void rtdReleaseDevice(RTDDevice device);

/* ---- Denoisers ------------------------------------------------------------------------ */

typedef struct RTDDenoiserImpl* RTDDenoiser;

/** A denoiser of `method` with default settings on a committed device; NULL on error. It owns the
 *  history of one image stream (the previous frames it reprojects). */
RTDDenoiser rtdNewDenoiser(RTDDevice device, const char* method);
void rtdRetainDenoiser(RTDDenoiser denoiser);
void rtdReleaseDenoiser(RTDDenoiser denoiser);

/** Settings by name, as `rtdenoise methods` lists them; values as text ("0.2", "true",
 *  an enum's name). A rejected value leaves the settings unchanged. */
RTDError rtdSetDenoiserSetting(RTDDenoiser denoiser, const char* name, const char* value);
RTDError rtdSetDenoiserSettingFloat(RTDDenoiser denoiser, const char* name, float value);
RTDError rtdSetDenoiserSettingInt(RTDDenoiser denoiser, const char* name, int value);
RTDError rtdSetDenoiserSettingBool(RTDDenoiser denoiser, const char* name, int value);
/** The current value as text; NULL for an unknown name. */
const char* rtdGetDenoiserSetting(RTDDenoiser denoiser, const char* name);
int rtdGetDenoiserSettingCount(RTDDenoiser denoiser);
const char* rtdGetDenoiserSettingName(RTDDenoiser denoiser, int index);
/** The buffers this method needs in every frame, comma-separated ("color,normal,depth"). */
const char* rtdGetDenoiserRequiredBuffers(RTDDenoiser denoiser);

/* ---- Frames --------------------------------------------------------------------------- */

/** Pixel formats, as rtd::Format: 32-bit floats, int32 (ids), 16-bit half floats. */
typedef enum RTDFormat {
  RTD_FORMAT_UNDEFINED = 0,
  RTD_FORMAT_FLOAT = 1,
  RTD_FORMAT_FLOAT2 = 2,
  RTD_FORMAT_FLOAT3 = 3,
  RTD_FORMAT_FLOAT4 = 4,
  RTD_FORMAT_INT32 = 5,
  RTD_FORMAT_HALF = 6,
  RTD_FORMAT_HALF2 = 7,
  RTD_FORMAT_HALF3 = 8,
  RTD_FORMAT_HALF4 = 9,
  RTD_FORMAT_MAX_ENUM = 0x7fffffff /* not a value (see RTD_ERROR_MAX_ENUM) */
} RTDFormat;

/** Pixels owned by the application: pixel (x, y), channel c, at
 *  (char*)data + y * rowStride + x * pixelStride + c * (4, or 2 for halves); rows from the top.
 *  Strides in bytes; 0 means tightly packed. The memory must stay valid until rtdDenoise returns. */
typedef struct RTDImageView {
  void* data;
  int width;
  int height;
  RTDFormat format;
  size_t pixelStride;
  size_t rowStride;
} RTDImageView;

/** Sets the view of a buffer for the following rtdDenoise calls: `buffer` is a buffer name of
 *  rtd::Buffer ("color", "albedo", "normal", "depth", "motion", "position", "objectId", ...;
 *  docs/integration.md says what each must hold) or "output" (FLOAT3/FLOAT4/HALF3/HALF4, the
 *  size of "color"). The view is copied, not its pixels. `view` NULL (or its data NULL) removes
 *  the buffer. */
RTDError rtdSetDenoiserImage(RTDDenoiser denoiser, const char* buffer, const RTDImageView* view);
/** The camera of the following frames: row-major 4x4 matrices acting on column vectors, as
 *  rtd::Camera (world to a right-handed camera space looking down -z; OpenGL-style projection).
 *  Both NULL: no camera. */
RTDError rtdSetDenoiserCamera(RTDDenoiser denoiser, const float worldToCamera[16], const float projection[16]);
/** An engine convention of the following frames by name (rtd::FrameConventions:
 *  "motionUnits" = "pixels" | "uv" | "ndc", "motionYUp", "motionToCurrent",
 *  "motionIncludesJitter", "jitterX", "jitterY", "previousJitterX", "previousJitterY",
 *  "normalSpace" = "world" | "view", "depth" = "linear" | "hardware",
 *  "depthRange" = "zeroToOne" | "minusOneToOne"). */
RTDError rtdSetDenoiserConvention(RTDDenoiser denoiser, const char* name, const char* value);
/** The projection that wrote a hardware depth buffer (row-major; "depth" = "hardware"). */
RTDError rtdSetDenoiserDepthProjection(RTDDenoiser denoiser, const float projection[16]);

/** Denoises the frame the images describe into "output". On RTD_ERROR_INVALID_ARGUMENT (bad
 *  input) nothing was written and the history is unchanged: the next good frame continues the
 *  stream. */
RTDError rtdDenoise(RTDDenoiser denoiser);
/** Forgets the history (camera cut, scene change); the next frame starts anew. */
RTDError rtdResetDenoiser(RTDDenoiser denoiser);

/* ---- Timings of the last rtdDenoise --------------------------------------------------- */

/** Passes of the last frame, in order ("import", ..., "export", or "taa+export" where the TAA writes the output; GPU times on Vulkan). */
int rtdGetPassCount(RTDDenoiser denoiser);
const char* rtdGetPassName(RTDDenoiser denoiser, int index);
/** Milliseconds of pass `index`; -1 (and RTD_ERROR_INVALID_ARGUMENT) out of range. */
double rtdGetPassMilliseconds(RTDDenoiser denoiser, int index);
/** Wall time of the whole last rtdDenoise call, milliseconds. */
double rtdGetDenoiseMilliseconds(RTDDenoiser denoiser);
/** NaN, infinite or negative radiance values the last frame had (replaced by 0). */
uint64_t rtdGetSanitizedValueCount(RTDDenoiser denoiser);

/* ---- Memory held after the last rtdDenoise ---------------------------------------------- */

/** Categories of the memory the denoiser holds ("frames": the current and previous frame's
 *  imported buffers; "planes": the rest; "staging" on Vulkan: host-visible buffers;
 *  Gersthofer's "history" and "intermediate"). They add up to all it holds (rtd::MemoryUse). */
int rtdGetMemoryCount(RTDDenoiser denoiser);
/** Name of category `index`; NULL (and RTD_ERROR_INVALID_ARGUMENT) out of range. */
const char* rtdGetMemoryCategory(RTDDenoiser denoiser, int index);
/** Bytes of category `index`; 0 (and RTD_ERROR_INVALID_ARGUMENT) out of range. */
uint64_t rtdGetMemoryBytes(RTDDenoiser denoiser, int index);

#ifdef __cplusplus
}
#endif

#endif /* RTD_CAPI_H */
