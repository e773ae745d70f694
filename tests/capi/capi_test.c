/* The C API (rtd/capi.h), compiled as C99: every entry point, every error path with its
 * documented code and message, the error callback and rtdGetDeviceError semantics, and that bad
 * input leaves a denoiser exactly where it was (its outputs stay those of a twin that never saw
 * the bad frames). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rtd/capi.h"

static int failures = 0;
#define CHECK(cond)                                                        \
  do {                                                                     \
    if (!(cond)) {                                                         \
      fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
      ++failures;                                                          \
    }                                                                      \
  } while (0)

/* The error callback records every call. */
typedef struct {
  int calls;
  RTDError last;
  char message[512];
} Reported;

static void onError(void* user, RTDError code, const char* message) {
  Reported* r = (Reported*)user;
  ++r->calls;
  r->last = code;
  strncpy(r->message, message, sizeof r->message - 1);
  r->message[sizeof r->message - 1] = '\0';
}

/* `call` returned `code`, the callback saw it once with a message containing `part`, and the
 * device keeps it as its (first, then cleared) error. */
static void expectError(RTDDevice device, Reported* r, RTDError got, RTDError code, const char* part, int line) {
  const char* message = NULL;
  const RTDError kept = rtdGetDeviceError(device, &message);
  if (got != code || r->calls != 1 || r->last != code || !strstr(r->message, part) || kept != code || !message ||
      !strstr(message, part) || rtdGetDeviceError(device, NULL) != RTD_ERROR_NONE) {
    fprintf(stderr, "capi_test.c:%d: expected error %d containing '%s'; returned %d, callback %d calls (%d: %s), kept %d\n",
            line, (int)code, part, (int)got, r->calls, (int)r->last, r->message, (int)kept);
    ++failures;
  }
  r->calls = 0;
  r->message[0] = '\0';
}
#define EXPECT_ERROR(device, r, call, code, part) expectError(device, r, (call), code, part, __LINE__)
/* For calls that return no RTDError (NULL or -1 instead): the device must have been told. */
#define EXPECT_REPORTED(device, r, code, part) expectError(device, r, code, code, part, __LINE__)

/* The thread's errors (calls with no device to report to). */
static void expectThreadError(RTDError code, const char* part, int line) {
  const char* message = NULL;
  const RTDError kept = rtdGetDeviceError(NULL, &message);
  if (kept != code || !message || !strstr(message, part) || rtdGetDeviceError(NULL, NULL) != RTD_ERROR_NONE) {
    fprintf(stderr, "capi_test.c:%d: expected thread error %d containing '%s', got %d (%s)\n", line, (int)code, part,
            (int)kept, message ? message : "no message");
    ++failures;
  }
}
#define EXPECT_THREAD_ERROR(code, part) expectThreadError(code, part, __LINE__)

enum { W = 24, H = 16 };

/* Frame i of a small moving scene: colour, albedo, normal, depth, motion (one pixel right). */
typedef struct {
  float color[W * H * 3], albedo[W * H * 3], normal[W * H * 3], depth[W * H], motion[W * H * 2];
} Frame;

static void makeFrame(Frame* f, int i) {
  int x, y, c;
  for (y = 0; y < H; ++y)
    for (x = 0; x < W; ++x) {
      const int p = y * W + x;
      const float checker = ((x + i) / 4 + y / 4) % 2 ? 0.8f : 0.2f;
      const float noise = (float)((p * 7919 + i * 104729) % 1000) / 1000.0f;
      for (c = 0; c < 3; ++c) {
        f->albedo[p * 3 + c] = checker;
        f->color[p * 3 + c] = checker * (0.5f + noise);
        f->normal[p * 3 + c] = c == 2 ? 1.0f : 0.0f;
      }
      f->depth[p] = 3.0f;
      f->motion[p * 2] = -1.0f; /* the content moves one pixel right per frame */
      f->motion[p * 2 + 1] = 0.0f;
    }
}

static void setFrame(RTDDenoiser den, Frame* f, float* out) {
  RTDImageView color = {f->color, W, H, RTD_FORMAT_FLOAT3, 0, 0};
  RTDImageView albedo = {f->albedo, W, H, RTD_FORMAT_FLOAT3, 0, 0};
  RTDImageView normal = {f->normal, W, H, RTD_FORMAT_FLOAT3, 0, 0};
  RTDImageView depth = {f->depth, W, H, RTD_FORMAT_FLOAT, 0, 0};
  RTDImageView motion = {f->motion, W, H, RTD_FORMAT_FLOAT2, 0, 0};
  RTDImageView output = {out, W, H, RTD_FORMAT_FLOAT4, 0, 0};
  CHECK(rtdSetDenoiserImage(den, "color", &color) == RTD_ERROR_NONE);
  CHECK(rtdSetDenoiserImage(den, "albedo", &albedo) == RTD_ERROR_NONE);
  CHECK(rtdSetDenoiserImage(den, "normal", &normal) == RTD_ERROR_NONE);
  CHECK(rtdSetDenoiserImage(den, "depth", &depth) == RTD_ERROR_NONE);
  CHECK(rtdSetDenoiserImage(den, "motion", &motion) == RTD_ERROR_NONE);
  CHECK(rtdSetDenoiserImage(den, "output", &output) == RTD_ERROR_NONE);
}

static void testVersionAndLists(void) {
  int i, n, found = 0;
  CHECK(rtdGetVersion() == RTD_VERSION);
  CHECK(strcmp(rtdGetVersionString(), RTD_VERSION_STRING) == 0);
  n = rtdGetMethodCount();
  CHECK(n >= 3);
  for (i = 0; i < n; ++i) {
    CHECK(rtdGetMethodName(i) != NULL && rtdGetMethodSummary(i) != NULL && strlen(rtdGetMethodSummary(i)) > 0);
    if (strcmp(rtdGetMethodName(i), "svgf") == 0) ++found;
  }
  CHECK(found == 1);
  CHECK(rtdGetMethodName(n) == NULL);
  EXPECT_THREAD_ERROR(RTD_ERROR_INVALID_ARGUMENT, "out of range");
  CHECK(rtdGetMethodSummary(-1) == NULL);
  EXPECT_THREAD_ERROR(RTD_ERROR_INVALID_ARGUMENT, "out of range");

  n = rtdGetPhysicalDeviceCount();
  CHECK(n >= 1);
  CHECK(rtdGetPhysicalDeviceBackend(0) == RTD_BACKEND_CPU);
  CHECK(rtdGetPhysicalDeviceName(0) != NULL && strcmp(rtdGetPhysicalDeviceName(0), "CPU") == 0);
  CHECK(rtdGetPhysicalDeviceName(n) == NULL);
  EXPECT_THREAD_ERROR(RTD_ERROR_INVALID_ARGUMENT, "out of range");
  CHECK(rtdGetPhysicalDeviceBackend(n) == -1);
  EXPECT_THREAD_ERROR(RTD_ERROR_INVALID_ARGUMENT, "out of range");
}

static void testDevices(void) {
  Reported r;
  RTDDevice device, vk;
  memset(&r, 0, sizeof r);
  CHECK(rtdNewDevice((RTDBackend)7) == NULL);
  EXPECT_THREAD_ERROR(RTD_ERROR_INVALID_ARGUMENT, "unknown backend");
  CHECK(rtdGetDeviceError(NULL, NULL) == RTD_ERROR_NONE);

  device = rtdNewDevice(RTD_BACKEND_CPU);
  CHECK(device != NULL);
  rtdSetDeviceErrorFunction(device, onError, &r);
  EXPECT_ERROR(device, &r, rtdSetDeviceInt(device, "thread", 2), RTD_ERROR_INVALID_ARGUMENT, "unknown device parameter 'thread'");
  EXPECT_ERROR(device, &r, rtdSetDeviceInt(device, "threads", -1), RTD_ERROR_INVALID_ARGUMENT, "threads");
  EXPECT_ERROR(device, &r, rtdSetDeviceString(device, "vulkanDevice", NULL), RTD_ERROR_INVALID_ARGUMENT, "NULL");
  EXPECT_ERROR(device, &r, rtdSetDeviceInt(device, NULL, 1), RTD_ERROR_INVALID_ARGUMENT, "NULL");
  CHECK(rtdSetDeviceInt(device, "threads", 2) == RTD_ERROR_NONE);
  CHECK(rtdGetDeviceName(device) == NULL);
  EXPECT_REPORTED(device, &r, RTD_ERROR_INVALID_OPERATION, "not committed");
  CHECK(rtdNewDenoiser(device, "accumulate") == NULL);
  EXPECT_REPORTED(device, &r, RTD_ERROR_INVALID_OPERATION, "rtdCommitDevice");
  CHECK(rtdCommitDevice(device) == RTD_ERROR_NONE);
  CHECK(rtdGetDeviceName(device) != NULL && strstr(rtdGetDeviceName(device), "2 threads") != NULL);
  EXPECT_ERROR(device, &r, rtdCommitDevice(device), RTD_ERROR_INVALID_OPERATION, "after rtdCommitDevice");
  EXPECT_ERROR(device, &r, rtdSetDeviceInt(device, "threads", 1), RTD_ERROR_INVALID_OPERATION, "after rtdCommitDevice");

  /* Only the first unqueried error is kept; the callback sees each. */
  rtdSetDeviceInt(device, "threads", 1);
  rtdSetDeviceInt(device, "bogus", 1);
  CHECK(r.calls == 2 && r.last == RTD_ERROR_INVALID_OPERATION);
  {
    const char* m = NULL;
    CHECK(rtdGetDeviceError(device, &m) == RTD_ERROR_INVALID_OPERATION && strstr(m, "after rtdCommitDevice"));
    CHECK(rtdGetDeviceError(device, &m) == RTD_ERROR_NONE && m == NULL);
  }
  r.calls = 0;

  /* A Vulkan device that does not exist: unsupported, with the reason. */
  vk = rtdNewDevice(RTD_BACKEND_VULKAN);
  CHECK(rtdSetDeviceString(vk, "vulkanDevice", "no such device anywhere") == RTD_ERROR_NONE);
  CHECK(rtdCommitDevice(vk) == RTD_ERROR_UNSUPPORTED);
  CHECK(rtdGetDeviceError(vk, NULL) == RTD_ERROR_UNSUPPORTED);
  rtdReleaseDevice(vk);

  /* NULL handles: the thread's error. */
  CHECK(rtdCommitDevice(NULL) == RTD_ERROR_INVALID_ARGUMENT);
  EXPECT_THREAD_ERROR(RTD_ERROR_INVALID_ARGUMENT, "device is NULL");
  CHECK(rtdNewDenoiser(NULL, "svgf") == NULL);
  EXPECT_THREAD_ERROR(RTD_ERROR_INVALID_ARGUMENT, "device is NULL");
  rtdSetDeviceErrorFunction(NULL, onError, &r);
  EXPECT_THREAD_ERROR(RTD_ERROR_INVALID_ARGUMENT, "device is NULL");
  rtdRetainDevice(NULL);
  rtdReleaseDevice(NULL);
  rtdReleaseDevice(device);
}

static void testSettings(RTDDevice device, Reported* r) {
  RTDDenoiser den;
  int i, n, found = 0;
  CHECK(rtdNewDenoiser(device, "nosuchmethod") == NULL);
  EXPECT_REPORTED(device, r, RTD_ERROR_INVALID_ARGUMENT, "unknown method 'nosuchmethod'");
  CHECK(rtdNewDenoiser(device, NULL) == NULL);
  EXPECT_REPORTED(device, r, RTD_ERROR_INVALID_ARGUMENT, "NULL");

  den = rtdNewDenoiser(device, "accumulate");
  CHECK(den != NULL);
  CHECK(strcmp(rtdGetDenoiserRequiredBuffers(den), "color") == 0);
  CHECK(rtdSetDenoiserSetting(den, "alpha", "0.1") == RTD_ERROR_NONE);
  CHECK(strcmp(rtdGetDenoiserSetting(den, "alpha"), "0.1") == 0);
  CHECK(rtdSetDenoiserSettingFloat(den, "alpha", 0.25f) == RTD_ERROR_NONE);
  CHECK(strcmp(rtdGetDenoiserSetting(den, "alpha"), "0.25") == 0);
  CHECK(rtdSetDenoiserSettingInt(den, "maxHistoryLength", 32) == RTD_ERROR_NONE);
  CHECK(strcmp(rtdGetDenoiserSetting(den, "maxHistoryLength"), "32") == 0);
  CHECK(rtdSetDenoiserSettingBool(den, "demodulate", 0) == RTD_ERROR_NONE);
  CHECK(strcmp(rtdGetDenoiserSetting(den, "demodulate"), "false") == 0);

  EXPECT_ERROR(device, r, rtdSetDenoiserSetting(den, "alpah", "0.1"), RTD_ERROR_INVALID_ARGUMENT, "no setting 'alpah'");
  EXPECT_ERROR(device, r, rtdSetDenoiserSetting(den, "alpha", "abc"), RTD_ERROR_INVALID_ARGUMENT, "'abc'");
  EXPECT_ERROR(device, r, rtdSetDenoiserSetting(den, "alpha", "7"), RTD_ERROR_INVALID_ARGUMENT, "outside");
  EXPECT_ERROR(device, r, rtdSetDenoiserSettingFloat(den, "alpha", (float)NAN), RTD_ERROR_INVALID_ARGUMENT, "finite");
  EXPECT_ERROR(device, r, rtdSetDenoiserSettingInt(den, "demodulate", 3), RTD_ERROR_INVALID_ARGUMENT, "true or false");
  EXPECT_ERROR(device, r, rtdSetDenoiserSetting(den, "alpha", NULL), RTD_ERROR_INVALID_ARGUMENT, "NULL");
  CHECK(strcmp(rtdGetDenoiserSetting(den, "alpha"), "0.25") == 0); /* rejected values change nothing */
  CHECK(rtdGetDenoiserSetting(den, "nope") == NULL);
  EXPECT_REPORTED(device, r, RTD_ERROR_INVALID_ARGUMENT, "no setting 'nope'");

  n = rtdGetDenoiserSettingCount(den);
  CHECK(n > 5);
  for (i = 0; i < n; ++i)
    if (strcmp(rtdGetDenoiserSettingName(den, i), "normalTolerance") == 0) ++found;
  CHECK(found == 1);
  CHECK(rtdGetDenoiserSettingName(den, n) == NULL);
  EXPECT_REPORTED(device, r, RTD_ERROR_INVALID_ARGUMENT, "out of range");

  CHECK(rtdSetDenoiserSetting(NULL, "alpha", "0.1") == RTD_ERROR_INVALID_ARGUMENT);
  EXPECT_THREAD_ERROR(RTD_ERROR_INVALID_ARGUMENT, "denoiser is NULL");
  CHECK(rtdGetDenoiserSettingCount(NULL) == 0);
  EXPECT_THREAD_ERROR(RTD_ERROR_INVALID_ARGUMENT, "denoiser is NULL");
  rtdReleaseDenoiser(den);
}

/* Bad frames, each rejected with its code, while `den` keeps denoising exactly like `twin`. */
static void testFrames(RTDDevice device, Reported* r) {
  static Frame f;
  static float out[W * H * 4], twinOut[W * H * 4];
  static float small[8 * 8 * 3];
  float wrongFormatOut[W * H * 2];
  const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  RTDDenoiser den = rtdNewDenoiser(device, "svgf"), twin = rtdNewDenoiser(device, "svgf");
  int i, k;
  CHECK(den && twin);
  CHECK(strcmp(rtdGetDenoiserRequiredBuffers(den), "color,normal,depth") == 0);

  /* Before any image: no output. */
  EXPECT_ERROR(device, r, rtdDenoise(den), RTD_ERROR_INVALID_OPERATION, "no output image");

  for (i = 0; i < 4; ++i) {
    RTDImageView view;
    makeFrame(&f, i);
    setFrame(twin, &f, twinOut);
    CHECK(rtdDenoise(twin) == RTD_ERROR_NONE);

    /* Bad views are refused when set... */
    view.data = f.color, view.width = W, view.height = H, view.format = (RTDFormat)42, view.pixelStride = 0, view.rowStride = 0;
    EXPECT_ERROR(device, r, rtdSetDenoiserImage(den, "color", &view), RTD_ERROR_INVALID_ARGUMENT, "not an RTDFormat");
    view.format = RTD_FORMAT_FLOAT3, view.width = -W;
    EXPECT_ERROR(device, r, rtdSetDenoiserImage(den, "color", &view), RTD_ERROR_INVALID_ARGUMENT, "not positive");
    view.width = W;
    EXPECT_ERROR(device, r, rtdSetDenoiserImage(den, "colour", &view), RTD_ERROR_INVALID_ARGUMENT, "unknown buffer 'colour'");
    EXPECT_ERROR(device, r, rtdSetDenoiserImage(den, NULL, &view), RTD_ERROR_INVALID_ARGUMENT, "NULL");

    /* ...and bad frames when denoised, leaving the history alone. */
    setFrame(den, &f, out);
    CHECK(rtdSetDenoiserImage(den, "depth", NULL) == RTD_ERROR_NONE);
    EXPECT_ERROR(device, r, rtdDenoise(den), RTD_ERROR_INVALID_ARGUMENT, "missing required buffer 'depth'");
    setFrame(den, &f, out);
    view.data = small, view.width = 8, view.height = 8;
    CHECK(rtdSetDenoiserImage(den, "albedo", &view) == RTD_ERROR_NONE);
    EXPECT_ERROR(device, r, rtdDenoise(den), RTD_ERROR_INVALID_ARGUMENT, "buffer 'albedo' is 8x8");
    setFrame(den, &f, out);
    view.data = wrongFormatOut, view.width = W, view.height = H, view.format = RTD_FORMAT_FLOAT2;
    CHECK(rtdSetDenoiserImage(den, "output", &view) == RTD_ERROR_NONE);
    EXPECT_ERROR(device, r, rtdDenoise(den), RTD_ERROR_INVALID_ARGUMENT, "output view must be");
    setFrame(den, &f, out);
    view.data = f.normal, view.format = RTD_FORMAT_FLOAT2;
    CHECK(rtdSetDenoiserImage(den, "normal", &view) == RTD_ERROR_NONE);
    EXPECT_ERROR(device, r, rtdDenoise(den), RTD_ERROR_INVALID_ARGUMENT, "buffer 'normal' needs 3 channels");
    setFrame(den, &f, out);
    CHECK(rtdSetDenoiserConvention(den, "normalSpace", "view") == RTD_ERROR_NONE);
    EXPECT_ERROR(device, r, rtdDenoise(den), RTD_ERROR_INVALID_ARGUMENT, "view-space normals need the frame's camera");
    CHECK(rtdSetDenoiserConvention(den, "normalSpace", "world") == RTD_ERROR_NONE);

    CHECK(rtdDenoise(den) == RTD_ERROR_NONE);
    CHECK(r->calls == 0);
    CHECK(memcmp(out, twinOut, sizeof out) == 0);
  }

  /* Conventions and cameras. */
  EXPECT_ERROR(device, r, rtdSetDenoiserConvention(den, "motionUnit", "uv"), RTD_ERROR_INVALID_ARGUMENT, "no field 'motionUnit'");
  EXPECT_ERROR(device, r, rtdSetDenoiserConvention(den, "motionUnits", "furlongs"), RTD_ERROR_INVALID_ARGUMENT, "furlongs");
  EXPECT_ERROR(device, r, rtdSetDenoiserConvention(den, "jitterX", NULL), RTD_ERROR_INVALID_ARGUMENT, "NULL");
  EXPECT_ERROR(device, r, rtdSetDenoiserDepthProjection(den, NULL), RTD_ERROR_INVALID_ARGUMENT, "NULL");
  CHECK(rtdSetDenoiserDepthProjection(den, identity) == RTD_ERROR_NONE);
  EXPECT_ERROR(device, r, rtdSetDenoiserCamera(den, identity, NULL), RTD_ERROR_INVALID_ARGUMENT, "both matrices");
  {
    float bad[16];
    memcpy(bad, identity, sizeof bad);
    bad[3] = (float)INFINITY;
    EXPECT_ERROR(device, r, rtdSetDenoiserCamera(den, bad, identity), RTD_ERROR_INVALID_ARGUMENT, "finite");
  }
  CHECK(rtdSetDenoiserCamera(den, identity, identity) == RTD_ERROR_NONE);
  CHECK(rtdSetDenoiserCamera(den, NULL, NULL) == RTD_ERROR_NONE);
  /* Motion in UV: the same frame as pixels gives the same output as the twin. */
  makeFrame(&f, 4);
  setFrame(twin, &f, twinOut);
  CHECK(rtdDenoise(twin) == RTD_ERROR_NONE);
  for (k = 0; k < W * H; ++k) f.motion[k * 2] /= (float)W;
  setFrame(den, &f, out);
  CHECK(rtdSetDenoiserConvention(den, "motionUnits", "uv") == RTD_ERROR_NONE);
  CHECK(rtdDenoise(den) == RTD_ERROR_NONE);
  for (k = 0; k < W * H * 4; ++k) CHECK(fabsf(out[k] - twinOut[k]) <= 1e-5f * (1.0f + fabsf(twinOut[k])));
  CHECK(rtdSetDenoiserConvention(den, "motionUnits", "pixels") == RTD_ERROR_NONE);

  /* Timings of the last frame. */
  {
    const int n = rtdGetPassCount(den);
    CHECK(n >= 4);
    CHECK(strcmp(rtdGetPassName(den, 0), "import") == 0);
    {
      /* The output is written last: by its own pass, or by the last one fused with it ("taa+export"). */
      const char* last = rtdGetPassName(den, n - 1);
      CHECK(last && strlen(last) >= 6 && strcmp(last + strlen(last) - 6, "export") == 0);
    }
    for (k = 0; k < n; ++k) CHECK(rtdGetPassMilliseconds(den, k) >= 0);
    CHECK(rtdGetDenoiseMilliseconds(den) > 0);
    CHECK(rtdGetSanitizedValueCount(den) == 0);
    CHECK(rtdGetPassName(den, n) == NULL);
    EXPECT_REPORTED(device, r, RTD_ERROR_INVALID_ARGUMENT, "pass index");
    CHECK(rtdGetPassMilliseconds(den, -1) == -1);
    EXPECT_REPORTED(device, r, RTD_ERROR_INVALID_ARGUMENT, "pass index");
  }

  /* Memory held: this frame's and the previous frame's colour, albedo, normal, depth and motion
     (12 float channels each), and the rest. */
  {
    const int n = rtdGetMemoryCount(den);
    uint64_t frames = 0, planes = 0;
    CHECK(n == 2);
    for (k = 0; k < n; ++k) {
      if (strcmp(rtdGetMemoryCategory(den, k), "frames") == 0) frames = rtdGetMemoryBytes(den, k);
      if (strcmp(rtdGetMemoryCategory(den, k), "planes") == 0) planes = rtdGetMemoryBytes(den, k);
    }
    CHECK(frames == 2u * 12u * W * H * 4u);
    CHECK(planes > 0);
    CHECK(rtdGetMemoryCategory(den, n) == NULL);
    EXPECT_REPORTED(device, r, RTD_ERROR_INVALID_ARGUMENT, "memory category index");
    CHECK(rtdGetMemoryBytes(den, -1) == 0);
    EXPECT_REPORTED(device, r, RTD_ERROR_INVALID_ARGUMENT, "memory category index");
  }

  /* A NaN in the colour is counted and does not reach the output. */
  makeFrame(&f, 5);
  f.color[7] = (float)NAN;
  setFrame(den, &f, out);
  CHECK(rtdDenoise(den) == RTD_ERROR_NONE);
  CHECK(rtdGetSanitizedValueCount(den) == 1);
  for (k = 0; k < W * H * 4; ++k) CHECK(isfinite(out[k]));

  /* Reset: the next frame is what a new denoiser makes of it. */
  {
    RTDDenoiser fresh = rtdNewDenoiser(device, "svgf");
    makeFrame(&f, 6);
    setFrame(fresh, &f, twinOut);
    CHECK(rtdDenoise(fresh) == RTD_ERROR_NONE);
    CHECK(rtdResetDenoiser(den) == RTD_ERROR_NONE);
    setFrame(den, &f, out);
    CHECK(rtdDenoise(den) == RTD_ERROR_NONE);
    CHECK(memcmp(out, twinOut, sizeof out) == 0);
    rtdReleaseDenoiser(fresh);
  }
  CHECK(rtdResetDenoiser(NULL) == RTD_ERROR_INVALID_ARGUMENT);
  EXPECT_THREAD_ERROR(RTD_ERROR_INVALID_ARGUMENT, "denoiser is NULL");
  CHECK(rtdDenoise(NULL) == RTD_ERROR_INVALID_ARGUMENT);
  EXPECT_THREAD_ERROR(RTD_ERROR_INVALID_ARGUMENT, "denoiser is NULL");

  /* References: the denoiser keeps its device alive. */
  rtdRetainDenoiser(den);
  rtdReleaseDenoiser(den);
  rtdReleaseDenoiser(twin);
  rtdReleaseDenoiser(den);
  rtdReleaseDenoiser(NULL);
}

/* Half inputs and a half output through the C API. */
static void testHalf(RTDDevice device) {
  /* 2x1 pixels: 1.0, 0.5, 2.0 and 0.25, 4.0, 1.5 as IEEE halves. */
  unsigned short color[6] = {0x3c00, 0x3800, 0x4000, 0x3400, 0x4400, 0x3e00}, out[8];
  RTDDenoiser den = rtdNewDenoiser(device, "accumulate");
  RTDImageView c = {color, 2, 1, RTD_FORMAT_HALF3, 0, 0}, o = {out, 2, 1, RTD_FORMAT_HALF4, 0, 0};
  CHECK(rtdSetDenoiserImage(den, "color", &c) == RTD_ERROR_NONE);
  CHECK(rtdSetDenoiserImage(den, "output", &o) == RTD_ERROR_NONE);
  CHECK(rtdDenoise(den) == RTD_ERROR_NONE);
  CHECK(out[0] == 0x3c00 && out[1] == 0x3800 && out[2] == 0x4000 && out[3] == 0x3c00);
  CHECK(out[4] == 0x3400 && out[5] == 0x4400 && out[6] == 0x3e00 && out[7] == 0x3c00);
  rtdReleaseDenoiser(den);
}

int main(void) {
  Reported r;
  RTDDevice device;
  memset(&r, 0, sizeof r);
  testVersionAndLists();
  testDevices();

  device = rtdNewDevice(RTD_BACKEND_CPU);
  rtdSetDeviceInt(device, "threads", 2);
  CHECK(rtdCommitDevice(device) == RTD_ERROR_NONE);
  rtdSetDeviceErrorFunction(device, onError, &r);
  testSettings(device, &r);
  testFrames(device, &r);
  testHalf(device);
  rtdReleaseDevice(device);

  if (failures) {
    fprintf(stderr, "%d checks failed\n", failures);
    return 1;
  }
  printf("C API: all checks passed\n");
  return 0;
}
