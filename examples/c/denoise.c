/* The C API in one program (docs/integration.md): the scene of examples/common/scene.h denoised
 * through rtd/capi.h. Fails unless denoising removed most of the noise.
 *   example_denoise_c [method]      (default svgf) */
#include <rtd/capi.h>

#include <stdio.h>

#include "common/scene.h"

enum { W = kSceneWidth, H = kSceneHeight };

static void onError(void* user, RTDError code, const char* message) {
  (void)user;
  fprintf(stderr, "rtdenoise error %d: %s\n", (int)code, message);
}

int main(int argc, char** argv) {
  static float color[W * H * 3], clean[W * H * 3], albedo[W * H * 3], normal[W * H * 3], depth[W * H],
      motion[W * H * 2], output[W * H * 4];
  const char* method = argc > 1 ? argv[1] : "svgf";
  const char* names[6] = {"color", "albedo", "normal", "depth", "motion", "output"};
  const RTDImageView views[6] = {{color, W, H, RTD_FORMAT_FLOAT3, 0, 0},  {albedo, W, H, RTD_FORMAT_FLOAT3, 0, 0},
                                 {normal, W, H, RTD_FORMAT_FLOAT3, 0, 0}, {depth, W, H, RTD_FORMAT_FLOAT, 0, 0},
                                 {motion, W, H, RTD_FORMAT_FLOAT2, 0, 0}, {output, W, H, RTD_FORMAT_FLOAT4, 0, 0}};
  double input, result;
  int t, i;
  RTDDenoiser den;
  RTDDevice device = rtdNewDevice(RTD_BACKEND_CPU);
  rtdSetDeviceErrorFunction(device, onError, NULL); /* every error is also printed */
  if (rtdCommitDevice(device) != RTD_ERROR_NONE) return 1;
  den = rtdNewDenoiser(device, method);
  if (!den) return 1;

  /* The views are set once; the pixels they point to change every frame. */
  for (i = 0; i < 6; ++i)
    if (rtdSetDenoiserImage(den, names[i], &views[i]) != RTD_ERROR_NONE) return 1;
  for (t = 0; t < kSceneFrames; ++t) {
    sceneFrame(t, color, clean, albedo, normal, depth, motion);
    if (rtdDenoise(den) != RTD_ERROR_NONE) return 1; /* on a camera cut: rtdResetDenoiser(den) first */
  }
  input = sceneRmse(color, 3, clean);
  result = sceneRmse(output, 4, clean);
  printf("%s, %s: RMSE of frame %d: input %.4f, output %.4f\n", method, rtdGetDeviceName(device), kSceneFrames, input,
         result);
  for (i = 0; i < rtdGetPassCount(den); ++i) printf("  %-24s %8.3f ms\n", rtdGetPassName(den, i), rtdGetPassMilliseconds(den, i));
  rtdReleaseDenoiser(den);
  rtdReleaseDevice(device);
  return result < 0.5 * input ? 0 : 1;
}
