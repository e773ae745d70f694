/* The C API in one program (docs/integration.md): the scene of examples/cpp/denoise.cpp,
 * denoised through rtd/capi.h. Fails unless denoising removed most of the noise.
 *   denoise_c [method]      (default svgf) */
#include <rtd/capi.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

enum { W = 64, H = 48, FRAMES = 8 };

static float albedoAt(int x, int y, int t) { return ((x - t + 64) / 8 + y / 8) % 2 ? 0.8f : 0.2f; }
static float lightAt(int x, int y, int t) { return 1.0f + 0.5f * sinf(0.1f * (float)(x - t)) * cosf(0.13f * (float)y); }
static float noiseAt(int x, int y, int t) {
  unsigned h = (unsigned)x * 73856093u ^ (unsigned)y * 19349663u ^ (unsigned)t * 83492791u;
  h = (h ^ (h >> 13)) * 1274126177u;
  return -logf(((float)((h >> 8) & 0xffffff) + 0.5f) / 16777216.0f);
}

static void onError(void* user, RTDError code, const char* message) {
  (void)user;
  fprintf(stderr, "rtdenoise error %d: %s\n", (int)code, message);
}

int main(int argc, char** argv) {
  static float color[W * H * 3], albedo[W * H * 3], normal[W * H * 3], depth[W * H], motion[W * H * 2];
  static float clean[W * H * 3], output[W * H * 4];
  const char* method = argc > 1 ? argv[1] : "svgf";
  double inputError = 0, outputError = 0;
  int t, x, y, c, p, i;
  RTDDenoiser den;
  RTDDevice device = rtdNewDevice(RTD_BACKEND_CPU);
  rtdSetDeviceErrorFunction(device, onError, NULL);
  if (rtdCommitDevice(device) != RTD_ERROR_NONE) return 1;
  den = rtdNewDenoiser(device, method);
  if (!den) return 1;

  {
    /* The views are set once; the pixels they point to change every frame. */
    const RTDImageView views[6] = {{color, W, H, RTD_FORMAT_FLOAT3, 0, 0},  {albedo, W, H, RTD_FORMAT_FLOAT3, 0, 0},
                                   {normal, W, H, RTD_FORMAT_FLOAT3, 0, 0}, {depth, W, H, RTD_FORMAT_FLOAT, 0, 0},
                                   {motion, W, H, RTD_FORMAT_FLOAT2, 0, 0}, {output, W, H, RTD_FORMAT_FLOAT4, 0, 0}};
    const char* names[6] = {"color", "albedo", "normal", "depth", "motion", "output"};
    for (i = 0; i < 6; ++i)
      if (rtdSetDenoiserImage(den, names[i], &views[i]) != RTD_ERROR_NONE) return 1;
  }

  for (t = 0; t < FRAMES; ++t) {
    for (y = 0; y < H; ++y)
      for (x = 0; x < W; ++x) {
        p = y * W + x;
        for (c = 0; c < 3; ++c) {
          albedo[p * 3 + c] = albedoAt(x, y, t);
          clean[p * 3 + c] = albedoAt(x, y, t) * lightAt(x, y, t);
          color[p * 3 + c] = clean[p * 3 + c] * noiseAt(x, y, t);
          normal[p * 3 + c] = c == 2 ? 1.0f : 0.0f;
        }
        depth[p] = 5.0f;
        motion[p * 2] = -1.0f;
        motion[p * 2 + 1] = 0.0f;
      }
    if (rtdDenoise(den) != RTD_ERROR_NONE) return 1;
    inputError = outputError = 0;
    for (p = 0; p < W * H; ++p)
      for (c = 0; c < 3; ++c) {
        inputError += pow(color[p * 3 + c] - clean[p * 3 + c], 2);
        outputError += pow(output[p * 4 + c] - clean[p * 3 + c], 2);
      }
  }
  inputError = sqrt(inputError / (W * H * 3));
  outputError = sqrt(outputError / (W * H * 3));
  printf("%s, %s: RMSE of frame %d: input %.4f, output %.4f\n", method, rtdGetDeviceName(device), FRAMES, inputError,
         outputError);
  for (i = 0; i < rtdGetPassCount(den); ++i) printf("  %-24s %8.3f ms\n", rtdGetPassName(den, i), rtdGetPassMilliseconds(den, i));
  rtdReleaseDenoiser(den);
  rtdReleaseDevice(device);
  return outputError < 0.5 * inputError ? 0 : 1;
}
